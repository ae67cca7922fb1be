"""Randomised scenes for trackers of groups and raw points: the seed draws everything.

``random-groups``: parties of 1-4 people in a cluttered room who walk in formation, stand
in a circle, split, meet other parties and pass them. Per seed:

- a room 9-16 m by 7-12 m with clutter of the ``randomised`` family (chairs, tables, bins,
  plants, railings, pillars, poles);
- a scanner of its own (0.25-1 deg resolution, 180-360 deg field of view, range, noise,
  dropout and rate drawn as in the ``randomised`` family) at feet height (0.15-0.3 m) or,
  in :attr:`RandomGroupsParams.torso_probability` of the scenes, at torso height
  (1.0-1.3 m: one blob per person, no legs); still, or on a robot driving between
  waypoints with drifting odometry (scans carry the odometry poses, the truth is in the
  same frame);
- 2-4 parties of 1-4 people (leg radius 0.05-0.09 m, hip width, speed and cadence drawn
  per person). Each party, in turn, does one of: walk in formation to a free spot; stand
  in a circle (or alone) for 2-6 s; split into two parties that walk to different spots;
  meet another party (both walk up, stand in one circle as one group for 3-8 s, then go
  on together as one party, or part again with the members *permuted*: who leaves with
  whom is drawn anew); or cross another party (both walk past each other through the
  same spot at the same time, 0.6 m between their nearest members).
People of different groups step aside for each other
(:attr:`RandomGroupsParams.pass_distance`, :func:`~laserpeople.sim.avoidance.keep_apart`).

Ground truth as the ``entrance-hall`` scenes give it: every person's group over time
(``PersonSpec.groups``; -1 walking alone), in the truth frames (``group_ids``) and the
per-beam labels. A merged group exists from when the last member arrives in the circle;
parties that part get their new groups 0.3 s after they start to leave (as
``entrance-hall``). A person is in the truth of a scan when the scanner hit them within
:attr:`RandomGroupsParams.truth_seen_within` of it (as ``randomised``).

**Seeds:** tune on :data:`TUNING_SEEDS` (0-9); :data:`HELD_BACK_SEEDS` (100-119) are the
test set and must never be used for tuning.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from laserpeople.config import param
from laserpeople.scan import Pose2D
from laserpeople.sim.avoidance import keep_apart
from laserpeople.sim.groups import (
    DEFAULT_SPACING,
    PERSONAL_SPACE,
    circle_slots,
    gather_in_circle,
    line_offsets,
    sync,
    walk_in_formation,
)
from laserpeople.sim.motion import Route
from laserpeople.sim.people import BodyParams, PersonSpec, random_person, with_feet_apart
from laserpeople.sim.scenarios import register
from laserpeople.sim.scenarios.randomised import (
    RandomisedParams,
    _Layout,
    clutter,
    drawn_gait,
    drawn_robot,
    one_laser_scene,
    random_laser,
    scanner_notes,
)
from laserpeople.sim.simulator import Scene
from laserpeople.sim.world import StaticObject, room

TUNING_SEEDS = range(0, 10)
"""Seeds of the random-groups family that may be looked at while tuning."""
HELD_BACK_SEEDS = range(100, 120)
"""Seeds reserved for testing; never tune on them."""

EVENTS = ("walk", "stand", "split", "meet", "merge", "part", "cross")
"""What parties do (``meet`` counts meetings; each ends in ``merge`` or ``part``)."""


@dataclass(frozen=True)
class RandomGroupsParams:
    """Ranges the random-groups scenes are drawn from (uniformly unless stated)."""

    config_section = "sim_random_groups"

    leg_radius_min: float = param(
        0.05, "assumption: legs 0.10-0.18 m wide (docs/groups.md)", "smallest leg radius", "m"
    )
    leg_radius_max: float = param(0.09, "assumption (docs/groups.md)", "largest leg radius", "m")
    resolution_min_deg: float = param(
        0.25, "assumption (docs/groups.md)", "finest scanner resolution", "deg"
    )
    resolution_max_deg: float = param(
        1.0, "assumption (docs/groups.md)", "coarsest scanner resolution", "deg"
    )
    feet_height: tuple[float, float] = param(
        (0.15, 0.3), "assumption: lasers at feet height", "range of a feet-height mounting", "m"
    )
    torso_height: tuple[float, float] = param(
        (1.0, 1.3), "assumption: lasers at torso height", "range of a torso-height mounting", "m"
    )
    torso_probability: float = param(
        0.25, "assumed", "share of scenes whose scanner is at torso height", ""
    )
    moving_sensor_probability: float = param(
        0.4, "assumed", "share of scenes whose scanner rides on a moving robot", ""
    )
    parties: tuple[int, int] = param((2, 4), "assumed", "fewest and most parties in a scene")
    party_size_max: int = param(
        4, "assumed (000 Sec. 4.6: small groups)", "most people in a party or merged group"
    )
    speed_min: float = param(0.6, "assumed (strolling group)", "slowest walking speed", "m/s")
    speed_max: float = param(1.4, "assumed", "fastest walking speed", "m/s")
    robot_speed_max: float = param(0.5, "assumed (indoor robot)", "fastest robot speed", "m/s")
    pass_distance: float = param(
        0.6,
        "assumed: strangers keep out of each other's intimate space (Hall, 000 Sec. 4.2)",
        "people of different groups step aside to keep their centres this far apart; 0: "
        "nobody steps aside and people may walk through each other",
        "m",
    )
    truth_seen_within: float = param(
        2.0,
        "as the randomised family",
        "a person is scored in a frame when the scanner hit them within this time of it",
        "s",
    )


def _u(rng: np.random.Generator, lo: float, hi: float) -> float:
    return float(rng.uniform(lo, hi))


@dataclass
class _Party:
    """People moving together: indices into the scene's routes, walking speed [m/s]."""

    members: list[int]
    speed: float


@dataclass
class _Plan:
    """The scene's people while their routes are drawn: routes, group history, events."""

    routes: list[Route]
    groups: list[list[tuple[float, int]]]
    events: dict[str, int] = field(default_factory=lambda: dict.fromkeys(EVENTS, 0))
    next_group: int = 0

    def rs(self, party: _Party) -> list[Route]:
        return [self.routes[i] for i in party.members]

    def join(self, members: list[int], t: float) -> None:
        """From time ``t`` [s] the ``members`` are one group (alone: -1); a person's first
        group holds from the start."""
        gid = -1
        if len(members) > 1:
            gid = self.next_group
            self.next_group += 1
        for i in members:
            hist = self.groups[i]
            hist.append((max(t, hist[-1][0] + 1e-3) if hist else -math.inf, gid))


def _centre(routes: list[Route]) -> tuple[float, float]:
    c = np.mean([r.end for r in routes], axis=0)
    return float(c[0]), float(c[1])


def _walk(plan: _Plan, party: _Party, to: tuple[float, float]) -> None:
    routes = plan.rs(party)
    walk_in_formation(routes, np.array([_centre(routes), to]), party.speed)


def _cut(rng: np.random.Generator, members: list[int]) -> tuple[list[int], list[int]]:
    """Two non-empty parts of ``members`` (n >= 2), who goes where drawn anew."""
    order = [members[k] for k in rng.permutation(len(members))]
    k = int(rng.integers(1, len(members)))
    return order[:k], order[k:]


def _leave_apart(
    rng: np.random.Generator, plan: _Plan, layout: _Layout, parts: list[_Party]
) -> None:
    """Parties that stood together leave to different spots; new groups 0.3 s later."""
    t_leave = sync([r for p in parts for r in plan.rs(p)])
    for p in parts:
        plan.join(p.members, t_leave + 0.3)
        spot = layout.free_point(rng, 1.0, margin=1.2)
        if spot is not None:
            _walk(plan, p, spot)


def _meet(
    rng: np.random.Generator, plan: _Plan, layout: _Layout, a: _Party, b: _Party
) -> list[_Party]:
    """``a`` and ``b`` stand in one circle, then go on together or part permuted."""
    spot = layout.free_point(rng, 1.5, margin=1.5)
    if spot is None:
        return [a, b]
    for p in (a, b):  # each walks up to 1.6 m from the spot on its side
        c = np.asarray(_centre(plan.rs(p)))
        away = c - np.asarray(spot)
        d = float(np.hypot(*away))
        if d > 1.7:
            _walk(plan, p, tuple(np.asarray(spot) + 1.6 * away / d))
    members = a.members + b.members
    routes = [plan.routes[i] for i in members]
    sync(routes)
    slots = circle_slots(spot, len(members), start=_u(rng, -math.pi, math.pi))
    t_merge = gather_in_circle(routes, slots, 0.8)
    plan.join(members, t_merge)
    for r in routes:
        r.wait(_u(rng, 3.0, 8.0))
    plan.events["meet"] += 1
    speed = min(a.speed, b.speed)
    if rng.random() < 0.5:
        plan.events["merge"] += 1
        merged = _Party(members, speed)
        sync(routes)
        spot2 = layout.free_point(rng, 1.0, margin=1.2)
        if spot2 is not None:
            _walk(plan, merged, spot2)
        return [merged]
    plan.events["part"] += 1
    one, two = _cut(rng, members)
    parts = [_Party(one, a.speed), _Party(two, b.speed)]
    _leave_apart(rng, plan, layout, parts)
    return parts


def _width(party: _Party) -> float:
    return (min(len(party.members), 3) - 1) * DEFAULT_SPACING


def _cross(rng: np.random.Generator, plan: _Plan, layout: _Layout, a: _Party, b: _Party) -> None:
    """``a`` and ``b`` walk past each other through one spot at the same time."""
    spot = layout.free_point(rng, 1.5, margin=2.0)
    if spot is None:
        return
    ang = _u(rng, -math.pi, math.pi)
    d = np.array([math.cos(ang), math.sin(ang)])
    n = np.array([-d[1], d[0]])
    half = _u(rng, 2.0, 3.5)
    gap = 0.5 * (_width(a) + _width(b)) + 0.6  # 0.6 m between the nearest members
    lo, hi = np.array([0.8, 0.8]), np.array([layout.w - 0.8, layout.h - 0.8])
    c = np.asarray(spot)
    ends = {
        id(a): (c - half * d + 0.5 * gap * n, c + half * d + 0.5 * gap * n),
        id(b): (c + half * d - 0.5 * gap * n, c - half * d - 0.5 * gap * n),
    }
    speed = min(a.speed, b.speed)
    for p in (a, b):
        _walk(plan, p, tuple(np.clip(ends[id(p)][0], lo, hi)))
    sync(plan.rs(a) + plan.rs(b))
    for p in (a, b):
        routes = plan.rs(p)
        path = np.array([_centre(routes), np.clip(ends[id(p)][1], lo, hi)])
        walk_in_formation(routes, path, speed)
    plan.events["cross"] += 1


def _stand(rng: np.random.Generator, plan: _Plan, party: _Party) -> None:
    routes = plan.rs(party)
    if len(routes) > 1:
        slots = circle_slots(_centre(routes), len(routes), start=_u(rng, -math.pi, math.pi))
        gather_in_circle(routes, slots, 0.6)
    else:
        routes[0].turn_by(_u(rng, -math.pi, math.pi), 1.0)
    stay = _u(rng, 2.0, 6.0)
    for r in routes:
        r.wait(stay)
    plan.events["stand"] += 1


def random_parties(
    rng: np.random.Generator, layout: _Layout, duration: float, p: RandomGroupsParams
) -> tuple[list[PersonSpec], dict[str, int], int]:
    """The people of a scene (module docstring): their specs with group histories, the
    event counts and the number of parties at the start."""
    plan = _Plan([], [])
    parties: list[_Party] = []
    n_parties = int(rng.integers(p.parties[0], p.parties[1] + 1))
    for k in range(n_parties):
        size = int(rng.choice([1, 2, 2, 3, 3, 4]))
        size = min(size, p.party_size_max)
        spot = layout.free_point(rng, 1.5, margin=1.5) or (layout.w / 2, layout.h / 2)
        heading = _u(rng, -math.pi, math.pi)
        start = 0.0 if k < 2 else _u(rng, 0.0, 0.3 * duration)
        c, s = math.cos(heading), math.sin(heading)
        members = []
        for ahead, left in line_offsets(size):
            x, y = spot[0] + ahead * c - left * s, spot[1] + ahead * s + left * c
            plan.routes.append(Route(x, y, heading, start=start))
            plan.groups.append([])
            members.append(len(plan.routes) - 1)
        plan.join(members, 0.0)
        parties.append(_Party(members, _u(rng, p.speed_min, p.speed_max)))
    for _ in range(400):
        busy = [q for q in parties if max(plan.routes[i].end_time for i in q.members) < duration]
        if not busy:
            break
        a = min(busy, key=lambda q: max(plan.routes[i].end_time for i in q.members))
        others = [q for q in parties if q is not a]
        can_meet = [q for q in others if len(q.members) + len(a.members) <= p.party_size_max]
        u = rng.random()
        if u < 0.3 or (u >= 0.6 and not others):
            spot = layout.free_point(rng, 1.0, margin=1.2)
            if spot is not None:
                _walk(plan, a, spot)
            plan.events["walk"] += 1
        elif u < 0.45:
            _stand(rng, plan, a)
        elif u < 0.6:
            if len(a.members) < 2:
                _stand(rng, plan, a)
                continue
            one, two = _cut(rng, a.members)
            parts = [_Party(one, a.speed), _Party(two, _u(rng, p.speed_min, p.speed_max))]
            _leave_apart(rng, plan, layout, parts)
            parties.remove(a)
            parties += parts
            plan.events["split"] += 1
        elif u < 0.8 and can_meet:
            b = can_meet[int(rng.integers(len(can_meet)))]
            parties.remove(a)
            parties.remove(b)
            parties += _meet(rng, plan, layout, a, b)
        else:
            b = others[int(rng.integers(len(others)))]
            _cross(rng, plan, layout, a, b)
    body = BodyParams(
        leg_radius_min=p.leg_radius_min,
        leg_radius_max=p.leg_radius_max,
        hip_half_width_min=0.08,
        hip_half_width_max=0.13,
    )
    people = []
    for k, route in enumerate(plan.routes):
        gait = drawn_gait(rng, 0.8, 1.25)
        groups = tuple(plan.groups[k])
        person = random_person(rng, k, route, params=body, gait_params=gait, groups=groups)
        people.append(with_feet_apart(person))
    if p.pass_distance > 0:
        people = keep_apart(
            people,
            duration,
            distance=p.pass_distance,
            group_distance=PERSONAL_SPACE[0],
            bounds=(0.3, 0.3, layout.w - 0.3, layout.h - 0.3),
        )
    return people, plan.events, n_parties


def random_groups_scene(
    rng: np.random.Generator, duration: float, params: RandomGroupsParams | None = None
) -> Scene:
    """One scene of the family (module docstring)."""
    p = params or RandomGroupsParams()
    w, h = _u(rng, 9.0, 16.0), _u(rng, 7.0, 12.0)
    objs: list[StaticObject] = [*room(0.0, 0.0, w, h, doors=(("north", w / 2, 1.2),))]
    laser = random_laser(
        rng,
        replace(
            RandomisedParams(),
            resolution_min_deg=p.resolution_min_deg,
            resolution_max_deg=p.resolution_max_deg,
        ),
    )
    torso = bool(rng.random() < p.torso_probability)
    height = _u(rng, *(p.torso_height if torso else p.feet_height))
    moving = bool(rng.random() < p.moving_sensor_probability)
    layout = _Layout(w, h, [])
    if laser.fov_deg >= 300.0:
        sx, sy, sth = _u(rng, 1.0, w - 1.0), _u(rng, 1.0, h - 1.0), _u(rng, -math.pi, math.pi)
    else:
        sx, sy, sth = _u(rng, 1.0, w - 1.0), 0.3, math.pi / 2
    layout.taken.append((sx, sy, 0.8))
    stuff, counts = clutter(rng, layout)
    objs += stuff
    people, events, n_parties = random_parties(rng, layout, duration, p)
    robot = None
    if moving:
        speed = _u(rng, 0.15, p.robot_speed_max)
        route = Route(sx, max(sy, 0.8), sth)
        while route.end_time < duration:
            spot = layout.free_point(rng, 0.5, margin=0.8)
            if spot is not None:
                route.walk_to(spot[0], spot[1], speed)
            route.wait(_u(rng, 0.5, 4.0))
        robot = drawn_robot(rng, route, duration, 2.0)
    mount = Pose2D(0.2, 0.0, 0.0) if moving else Pose2D(sx, sy, sth)
    notes = {
        "family": "random-groups",
        "room_m": [round(w, 2), round(h, 2)],
        "scanner": {**scanner_notes(laser, height), "level": "torso" if torso else "feet"},
        "moving_robot": moving,
        "clutter": counts,
        "people": len(people),
        "parties": n_parties,
        "events": events,
    }
    return one_laser_scene(objs, people, laser, height, mount, robot, notes, p.truth_seen_within)


@register(
    "random-groups",
    "randomised room, clutter, scanner (feet or torso height, still or moving) and 2-4 "
    "parties of 1-4 people who walk, stand, split, meet, part permuted and cross (the seed "
    "draws all; tune on seeds 0-9, seeds 100-119 are held back)",
    "docs/groups.md",
    40.0,
)
def _random_groups(rng: np.random.Generator, duration: float) -> Scene:
    return random_groups_scene(rng, duration)
