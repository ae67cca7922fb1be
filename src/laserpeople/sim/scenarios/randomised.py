"""Randomised scenes that a tracker cannot be tuned to: the seed draws everything.

``randomised`` (people among clutter) and ``randomised-furniture`` (the same rooms and
clutter, nobody in them: every person track there sits on a static object). Per seed:

- a room 7-16 m by 5-12 m with 1-3 door gaps, sometimes a partition wall with gaps;
- clutter families: 4-post chairs and tables (post radius and spacing drawn), round bins,
  plants (a pot and thin stems), railings (rows of thin posts), pillars, thin poles;
- a scanner model of its own: 0.25-1 deg resolution, 180-360 deg field of view, range,
  noise and dropout drawn, mounted 0.1-0.35 m above the floor;
- a static scanner, or one on a robot driving between waypoints with drifting odometry
  (the scans then carry odometry poses, as on a real robot, and the truth is expressed in
  the same odometry frame: see :class:`~laserpeople.sim.simulator.Scene`);
- 1-6 people with leg radius 0.05-0.09 m, leg spacing (hip half-width), speed and
  cadence drawn per person, who walk between waypoints, stop, turn on the spot, and meet
  in pairs to stand together for a while.

A person is in the ground truth of a scan when the scanner hit them within 2 s of it
(:attr:`RandomisedParams.truth_seen_within`): a robot's 180 deg scanner does not see who is
behind it, and nobody should be scored as missed for that; short occlusions still count.

**Seeds:** tune on :data:`TUNING_SEEDS` (0-49); :data:`HELD_BACK_SEEDS` (100-119) are the
test set of ``benchmarks/people_suite.py`` and must never be used for tuning.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from laserpeople.config import param
from laserpeople.scan import Pose2D
from laserpeople.sim.gait import GaitParams
from laserpeople.sim.motion import Route, sample_route
from laserpeople.sim.people import BodyParams, PersonSpec, random_person, with_feet_apart
from laserpeople.sim.robot import OdometryParams, RobotSpec
from laserpeople.sim.scenarios import register_scene
from laserpeople.sim.sensors import LaserModel, SensorSpec
from laserpeople.sim.simulator import Scene
from laserpeople.sim.world import (
    WALL_HEIGHT,
    StaticObject,
    World,
    pillar,
    pole,
    rectangle_corners,
    room,
    round_bin,
    table,
)

TUNING_SEEDS = range(0, 50)
"""Seeds of the randomised family that may be looked at while tuning."""
HELD_BACK_SEEDS = range(100, 120)
"""Seeds reserved for testing (benchmarks/people_suite.py); never tune on them."""


@dataclass(frozen=True)
class RandomisedParams:
    """Ranges the randomised scenes are drawn from (uniformly unless stated)."""

    config_section = "sim_randomised"

    leg_radius_min: float = param(
        0.05,
        "assumption: legs 0.10-0.18 m wide (docs/people-benchmarks.md)",
        "smallest leg radius",
        "m",
    )
    leg_radius_max: float = param(
        0.09, "assumption (docs/people-benchmarks.md)", "largest leg radius", "m"
    )
    hip_half_width_min: float = param(
        0.08,
        "assumed (feet close together); never less than the leg radius + 1.5 cm",
        "smallest foot offset from the body centre",
        "m",
    )
    hip_half_width_max: float = param(
        0.15, "assumed (wide stance)", "largest foot offset from the body centre", "m"
    )
    speed_min: float = param(0.4, "assumed (strolling)", "slowest walking speed", "m/s")
    speed_max: float = param(1.7, "assumed (brisk walk)", "fastest walking speed", "m/s")
    cadence_scale_min: float = param(
        0.8, "assumed", "smallest factor on the default cadence law", ""
    )
    cadence_scale_max: float = param(
        1.25, "assumed", "largest factor on the default cadence law", ""
    )
    people_max: int = param(6, "assumed", "most people in a scene (at least 1)")
    resolution_min_deg: float = param(
        0.25, "assumption (docs/people-benchmarks.md)", "finest scanner resolution", "deg"
    )
    resolution_max_deg: float = param(
        1.0, "assumption (docs/people-benchmarks.md)", "coarsest scanner resolution", "deg"
    )
    fov_min_deg: float = param(
        180.0, "assumption (docs/people-benchmarks.md)", "narrowest field of view", "deg"
    )
    fov_max_deg: float = param(
        360.0, "assumption (docs/people-benchmarks.md)", "widest field of view", "deg"
    )
    height_min: float = param(0.1, "assumed (leg height)", "lowest scanner mounting", "m")
    height_max: float = param(0.35, "assumed (leg height)", "highest scanner mounting", "m")
    rate_hz: tuple[float, ...] = param(
        (10.0, 12.5, 15.0, 20.0), "common scanner rates", "scan rates drawn from", "Hz"
    )
    moving_robot_probability: float = param(
        0.5, "assumed", "share of scenes whose scanner rides on a moving robot", ""
    )
    robot_speed_max: float = param(0.6, "assumed (indoor robot)", "fastest robot speed", "m/s")
    odometry_scale_max: float = param(
        2.0, "assumed", "largest factor on the default odometry errors", ""
    )
    truth_seen_within: float = param(
        2.0,
        "assumed: occlusions up to ~4 s are the tracker's to bridge",
        "a person is scored in a frame when the scanner hit them within this time of it",
        "s",
    )


def _uniform(rng: np.random.Generator, lo: float, hi: float) -> float:
    return float(rng.uniform(lo, hi))


def random_laser(rng: np.random.Generator, p: RandomisedParams) -> LaserModel:
    """A scanner model with drawn resolution, field of view, range, noise and dropout."""
    res = _uniform(rng, p.resolution_min_deg, p.resolution_max_deg)
    fov = _uniform(rng, p.fov_min_deg, p.fov_max_deg)
    if fov > 360.0 - res:  # a full circle: the last beam must not repeat the first
        fov = 360.0 - res
    fov = res * round(fov / res)
    return drawn_laser(
        rng,
        f"random-{res:.3f}deg-{fov:.0f}deg",
        fov,
        res,
        p.rate_hz,
        (5.6, 30.0),
        0.01,
        "randomised (laserpeople.sim.scenarios.randomised)",
    )


def drawn_laser(
    rng: np.random.Generator,
    name: str,
    fov_deg: float,
    resolution_deg: float,
    rates_hz: Sequence[float],
    range_max_m: tuple[float, float],
    dropout_max: float,
    source: str,
) -> LaserModel:
    """A scanner of field of view ``fov_deg`` [deg] and beam spacing ``resolution_deg``
    [deg] with the rest drawn, in this order: the scan rate [Hz] from ``rates_hz``, the
    largest range [m] uniformly in ``range_max_m`` (low, high), the range noise sigma [m]
    in [0.005, 0.02], the relative range noise [1] in [0, 0.002] and the share of dropped
    beams [1] in [0, ``dropout_max``]. The smallest range is 0.02 m."""
    return LaserModel(
        name=name,
        fov_deg=fov_deg,
        resolution_deg=resolution_deg,
        rate_hz=float(rng.choice(rates_hz)),
        range_min=0.02,
        range_max=_uniform(rng, *range_max_m),
        sigma=_uniform(rng, 0.005, 0.02),
        sigma_relative=_uniform(rng, 0.0, 0.002),
        dropout=_uniform(rng, 0.0, dropout_max),
        source=source,
    )


def drawn_odometry(rng: np.random.Generator, scale_max: float) -> OdometryParams:
    """Odometry errors: the defaults times a factor drawn in [0.5, ``scale_max``], the
    scale error and heading bias with a drawn sign."""
    odo_scale = _uniform(rng, 0.5, scale_max)
    base = OdometryParams()
    return OdometryParams(
        scale_error=base.scale_error * odo_scale * float(rng.choice([-1.0, 1.0])),
        heading_bias=base.heading_bias * odo_scale * float(rng.choice([-1.0, 1.0])),
        heading_scale_error=base.heading_scale_error * odo_scale,
        translation_noise=base.translation_noise * odo_scale,
        heading_noise=base.heading_noise * odo_scale,
    )


def drawn_gait(rng: np.random.Generator, scale_min: float, scale_max: float) -> GaitParams:
    """A gait with the default cadence law scaled by a factor drawn in [``scale_min``,
    ``scale_max``] and a swing fraction drawn in [0.7, 0.9]."""
    scale = _uniform(rng, scale_min, scale_max)
    base = GaitParams()
    return GaitParams(
        cadence_at_rest=base.cadence_at_rest * scale,
        cadence_per_speed=base.cadence_per_speed * scale,
        swing_fraction=_uniform(rng, 0.7, 0.9),
    )


def drawn_robot(
    rng: np.random.Generator, route: Route, duration: float, odometry_scale_max: float
) -> RobotSpec:
    """A robot that follows ``route`` (sampled until ``duration`` [s], its positions
    smoothed with a 0.5 s Gaussian) with odometry errors drawn by :func:`drawn_odometry`
    (factor in [0.5, ``odometry_scale_max``])."""
    odometry = drawn_odometry(rng, odometry_scale_max)
    return RobotSpec(sample_route(route, duration, smoothing=0.5), odometry)


def one_laser_scene(
    objs: list[StaticObject],
    people: list[PersonSpec],
    laser: LaserModel,
    height: float,
    mount: Pose2D,
    robot: RobotSpec | None,
    notes: dict[str, Any],
    truth_seen_within: float,
    truth_in_view: bool = False,
) -> Scene:
    """A scene seen by one scanner called ``laser`` with the model ``laser``, mounted
    ``height`` [m] above the floor at ``mount`` (on the robot when there is one, the scans
    then carrying odometry poses; in the world [m, rad] otherwise). A person is scored in
    a scan when the scanner hit them within ``truth_seen_within`` [s] of it, or, with
    ``truth_in_view``, only while that scan can see them (:attr:`Scene.truth_in_view`)."""
    sensor = SensorSpec(
        "laser",
        laser.name,
        height,
        mount,
        on_robot=robot is not None,
        rate_hz=laser.rate_hz,
        laser_model=laser,
    )
    return Scene(
        World(objs),
        people,
        [sensor],
        robot,
        notes,
        poses_from_odometry=robot is not None,
        truth_seen_within=None if truth_in_view else truth_seen_within,
        truth_in_view=truth_in_view,
    )


# -- clutter ---------------------------------------------------------------------------------


def four_posts(
    kind: str, cx: float, cy: float, length: float, width: float, angle: float, radius: float
) -> list[StaticObject]:
    """Four thin posts at the corners of a rectangle (chair or table legs)."""
    corners = rectangle_corners(cx, cy, length, width, angle)
    z_max = 0.45 if kind == "chair-leg" else 0.72
    return [StaticObject(kind, circles=np.array([[x, y, radius]]), z_max=z_max) for x, y in corners]


def plant(rng: np.random.Generator, cx: float, cy: float) -> StaticObject:
    """A pot with a few thin stems and leaves around it at foot height."""
    pot = _uniform(rng, 0.08, 0.2)
    n = int(rng.integers(0, 5))
    ang = rng.uniform(-math.pi, math.pi, n)
    dist = pot + rng.uniform(0.03, 0.2, n)
    stems = np.column_stack(
        [cx + dist * np.cos(ang), cy + dist * np.sin(ang), rng.uniform(0.01, 0.03, n)]
    )
    return StaticObject("plant", circles=np.vstack([[cx, cy, pot], stems]), z_max=1.2)


def railing(rng: np.random.Generator, x0: float, y0: float, angle: float) -> StaticObject:
    """A row of thin posts 2-5 m long, 0.1-1.2 m apart (balustrade, barrier)."""
    length = _uniform(rng, 2.0, 5.0)
    gap = _uniform(rng, 0.1, 1.2)
    s = np.arange(0.0, length + 1e-9, gap)
    r = _uniform(rng, 0.01, 0.03)
    xy = np.column_stack([x0 + s * math.cos(angle), y0 + s * math.sin(angle)])
    return StaticObject("railing", circles=np.column_stack([xy, np.full(s.size, r)]), z_max=1.0)


def partition(rng: np.random.Generator, w: float, h: float) -> list[StaticObject]:
    """A wall across the room with one or two gaps."""
    along_x = bool(rng.random() < 0.5)
    span = h if along_x else w
    at = _uniform(rng, 0.35, 0.65) * (w if along_x else h)
    cuts = sorted(rng.uniform(0.15 * span, 0.85 * span, int(rng.integers(1, 3))).tolist())
    pieces, cur = [], 0.0
    for c in cuts:
        half = _uniform(rng, 0.45, 0.9)
        if c - half > cur:
            pieces.append((cur, c - half))
        cur = max(cur, c + half)
    if cur < span:
        pieces.append((cur, span))
    segs = [[at, a, at, b] if along_x else [a, at, b, at] for a, b in pieces]
    return [StaticObject("wall", segments=np.array(segs, float).reshape(-1, 4))]


@dataclass
class _Layout:
    """Free-space bookkeeping while placing things in the room."""

    w: float
    h: float
    taken: list[tuple[float, float, float]]  # x, y, radius kept clear

    def free_point(self, rng: np.random.Generator, clear: float, margin: float = 0.5) -> Any:
        xs, ys = (margin, self.w - margin), (margin, self.h - margin)
        return free_spot(rng, xs, ys, self.taken, clear)


def free_spot(
    rng: np.random.Generator,
    xs: tuple[float, float],
    ys: tuple[float, float],
    taken: list[tuple[float, float, float]],
    clear: float,
    allowed: Callable[[float, float], bool] | None = None,
) -> tuple[float, float] | None:
    """A point drawn uniformly in ``xs`` x ``ys`` (low, high) [m] that lies more than
    ``clear`` [m] beyond the kept-clear radius of every ``taken`` (x, y, radius) [m] and
    that ``allowed(x, y)`` accepts; 60 draws (x then y) at most, None when all fail."""
    for _ in range(60):
        x, y = _uniform(rng, *xs), _uniform(rng, *ys)
        if allowed is not None and not allowed(x, y):
            continue
        if all(math.hypot(x - a, y - b) > clear + r for a, b, r in taken):
            return x, y
    return None


def clutter(rng: np.random.Generator, layout: _Layout) -> tuple[list[StaticObject], dict[str, int]]:
    """Drawn clutter of every family, placed apart from each other and the scanner."""
    objs: list[StaticObject] = []
    counts = {
        "chairs": int(rng.integers(0, 7)),
        "tables": int(rng.integers(0, 3)),
        "bins": int(rng.integers(0, 4)),
        "plants": int(rng.integers(0, 4)),
        "railings": int(rng.integers(0, 2)),
        "pillars": int(rng.integers(0, 3)),
        "poles": int(rng.integers(0, 3)),
    }
    for family, n in counts.items():
        for _ in range(n):
            size = {"tables": 0.9, "railings": 0.3, "chairs": 0.4}.get(family, 0.35)
            spot = layout.free_point(rng, size + 0.5)
            if spot is None:
                continue
            x, y = spot
            a = _uniform(rng, -math.pi, math.pi)
            if family == "chairs":
                side = _uniform(rng, 0.35, 0.5)
                objs += four_posts("chair-leg", x, y, side, side, a, _uniform(rng, 0.01, 0.025))
            elif family == "tables":
                objs += table(x, y, _uniform(rng, 0.8, 1.8), _uniform(rng, 0.6, 1.0), a)
            elif family == "bins":
                objs.append(round_bin(x, y, _uniform(rng, 0.1, 0.2)))
            elif family == "plants":
                objs.append(plant(rng, x, y))
            elif family == "railings":
                objs.append(railing(rng, x, y, a))
            elif family == "pillars":
                objs.append(pillar(x, y, _uniform(rng, 0.12, 0.35)))
            else:
                objs.append(pole(x, y, _uniform(rng, 0.02, 0.05)))
            layout.taken.append((x, y, size))
    return objs, counts


# -- people ----------------------------------------------------------------------------------


def _person_route(
    rng: np.random.Generator, layout: _Layout, start: float, duration: float, speed: float
) -> Route:
    first = layout.free_point(rng, 0.4) or (layout.w / 2, layout.h / 2)
    route = Route(first[0], first[1], _uniform(rng, -math.pi, math.pi), start=start)
    _wander(rng, layout, route, duration, speed)
    return route


def _wander(
    rng: np.random.Generator, layout: _Layout, route: Route, until: float, speed: float
) -> None:
    """Walk between free waypoints until ``until``, stopping and turning on the spot."""
    while route.end_time < until:
        spot = layout.free_point(rng, 0.4)
        if spot is not None:
            route.walk_to(spot[0], spot[1], speed)
        u = rng.random()
        if u < 0.3:
            route.wait(_uniform(rng, 1.0, 5.0))
        elif u < 0.5:
            route.turn_by(_uniform(rng, -math.pi, math.pi), _uniform(rng, 0.8, 2.0))
        elif spot is None:
            route.wait(1.0)


def _meet(
    rng: np.random.Generator, layout: _Layout, a: Route, b: Route, speeds: tuple[float, float]
) -> None:
    """Both walk to a spot, stand there facing each other 0.6-1.1 m apart, then move on."""
    spot = layout.free_point(rng, 0.8, margin=1.0)
    if spot is None:
        return
    gap = 0.5 * _uniform(rng, 0.6, 1.1)
    facing = _uniform(rng, -math.pi, math.pi)
    dx, dy = gap * math.cos(facing), gap * math.sin(facing)
    a.walk_to(spot[0] - dx, spot[1] - dy, speeds[0])
    b.walk_to(spot[0] + dx, spot[1] + dy, speeds[1])
    meet = max(a.end_time, b.end_time)
    a.wait_until(meet)
    b.wait_until(meet)
    a.turn_by(0.0, 0.5)
    b.turn_by(0.0, 0.5)
    stay = _uniform(rng, 3.0, 8.0)
    a.wait(stay)
    b.wait(stay)


def random_people(
    rng: np.random.Generator, layout: _Layout, duration: float, p: RandomisedParams
) -> tuple[list[PersonSpec], int]:
    """1..people_max people wandering; some pairs meet and stand together. Returns the
    people and the number of meetings."""
    n = int(rng.integers(1, p.people_max + 1))
    body = BodyParams(
        leg_radius_min=p.leg_radius_min,
        leg_radius_max=p.leg_radius_max,
        hip_half_width_min=p.hip_half_width_min,
        hip_half_width_max=p.hip_half_width_max,
    )
    speeds = [_uniform(rng, p.speed_min, p.speed_max) for _ in range(n)]
    starts = [0.0 if k == 0 else _uniform(rng, 0.0, 0.4 * duration) for k in range(n)]
    routes = [_person_route(rng, layout, starts[k], 0.0, speeds[k]) for k in range(n)]
    meetings = 0
    order = rng.permutation(n)
    for i in range(0, n - 1, 2):
        a, b = int(order[i]), int(order[i + 1])
        if rng.random() < 0.5:
            _wander(rng, layout, routes[a], routes[a].end_time + 4.0, speeds[a])
            _meet(rng, layout, routes[a], routes[b], (speeds[a], speeds[b]))
            meetings += 1
    people = []
    for k in range(n):
        _wander(rng, layout, routes[k], duration, speeds[k])
        gait = drawn_gait(rng, p.cadence_scale_min, p.cadence_scale_max)
        person = random_person(rng, k, routes[k], params=body, gait_params=gait)
        people.append(with_feet_apart(person))
    return people, meetings


# -- the scene -------------------------------------------------------------------------------


def scanner_notes(laser: LaserModel, height: float) -> dict[str, float]:
    """The drawn scanner for a scene's notes (rounded)."""
    return {
        "resolution_deg": round(laser.resolution_deg, 4),
        "fov_deg": round(laser.fov_deg, 2),
        "range_max_m": round(laser.range_max, 2),
        "rate_hz": laser.rate_hz,
        "height_m": round(height, 3),
    }


def randomised_scene(
    rng: np.random.Generator,
    duration: float,
    *,
    with_people: bool = True,
    params: RandomisedParams | None = None,
) -> Scene:
    """One randomised scene (see the module docstring); ``with_people=False`` gives the
    furniture-only variant."""
    p = params or RandomisedParams()
    w, h = _uniform(rng, 7.0, 16.0), _uniform(rng, 5.0, 12.0)
    doors = []
    for _ in range(int(rng.integers(1, 4))):
        side = str(rng.choice(["south", "north", "west", "east"]))
        length = w if side in ("south", "north") else h  # doors sit along the wall
        doors.append((side, _uniform(rng, 1.0, length - 1.0), _uniform(rng, 0.9, 1.8)))
    objs: list[StaticObject] = [*room(0.0, 0.0, w, h, doors=tuple(doors))]
    if rng.random() < 0.4:
        objs += partition(rng, w, h)
    laser = random_laser(rng, p)
    height = _uniform(rng, p.height_min, p.height_max)
    moving = bool(rng.random() < p.moving_robot_probability)
    layout = _Layout(w, h, [])
    # the scanner: against the south wall looking in (or anywhere for a wide view)
    if laser.fov_deg >= 300.0:
        sx, sy, sth = _uniform(rng, 1.0, w - 1.0), _uniform(rng, 1.0, h - 1.0), 0.0
        sth = _uniform(rng, -math.pi, math.pi)
    else:
        sx, sy, sth = _uniform(rng, 1.0, w - 1.0), 0.3, math.pi / 2
    layout.taken.append((sx, sy, 0.8))
    stuff, counts = clutter(rng, layout)
    objs += stuff
    people: list[PersonSpec] = []
    meetings = 0
    if with_people:
        people, meetings = random_people(rng, layout, duration, p)
    robot = None
    if moving:
        speed = _uniform(rng, 0.15, p.robot_speed_max)
        route = Route(sx, max(sy, 0.8), sth)
        while route.end_time < duration:
            spot = layout.free_point(rng, 0.5, margin=0.8)
            if spot is not None:
                route.walk_to(spot[0], spot[1], speed)
            if spot is None or rng.random() < 0.4:
                route.wait(_uniform(rng, 1.0, 4.0))
        robot = drawn_robot(rng, route, duration, p.odometry_scale_max)
        mount = Pose2D(0.2, 0.0, 0.0)
    else:
        mount = Pose2D(sx, sy, sth)
    notes = {
        "family": "randomised" if with_people else "randomised-furniture",
        "room_m": [round(w, 2), round(h, 2)],
        "scanner": scanner_notes(laser, height),
        "moving_robot": moving,
        "clutter": counts,
        "people": len(people),
        "meetings": meetings,
        "wall_height_m": WALL_HEIGHT,
    }
    return one_laser_scene(objs, people, laser, height, mount, robot, notes, p.truth_seen_within)


register_scene(
    "randomised",
    "randomised room, clutter, scanner model, robot and 1-6 people (the seed draws all; "
    "tune on seeds 0-49, seeds 100-119 are held back)",
    "docs/people-benchmarks.md",
    30.0,
    randomised_scene,
    with_people=True,
)
register_scene(
    "randomised-furniture",
    "the randomised rooms and clutter with nobody in them (person tracks there are false)",
    "docs/people-benchmarks.md",
    30.0,
    randomised_scene,
    with_people=False,
)
