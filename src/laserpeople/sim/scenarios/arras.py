"""000's experiments (Arras et al.): detection scenes (Sec. 2.3), leg tracking (Sec. 3.4),
group tracking (Sec. 4.6).

Sensors follow the paper: a SICK LMS (180 deg, 0.5 deg) 30 cm above the floor for
detection and group tracking (Sec. 2.3, 4.6; 10 scans/s in 4.6) and 11 cm above the
floor for leg tracking (Sec. 3.4). Room sizes other than the 2.5 m corridor of Sec.
3.4.1 are not in the paper and are chosen here.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import gaussian_filter1d

from laserpeople.scan import Pose2D
from laserpeople.sim.gait import pivot_walk
from laserpeople.sim.groups import (
    circle_slots,
    gather_in_circle,
    line_offsets,
    sync,
    walk_in_formation,
)
from laserpeople.sim.motion import BodyTrack, Route, sample_route
from laserpeople.sim.people import PersonSpec, random_person
from laserpeople.sim.robot import RobotSpec
from laserpeople.sim.scenarios import register, register_scene
from laserpeople.sim.sensors import SensorSpec
from laserpeople.sim.simulator import Scene
from laserpeople.sim.world import (
    StaticObject,
    World,
    box,
    chair,
    pillar,
    pole,
    room,
    round_bin,
    table,
    wall,
)

DETECTION_HEIGHT = 0.30  # 000 Sec. 2.3
TRACKING_HEIGHT = 0.11  # 000 Sec. 3.4
GROUP_RATE = 10.0  # 000 Sec. 4.6


def _lms(name: str, height: float, pose: Pose2D, **kw: object) -> SensorSpec:
    return SensorSpec(name, "sick-lms200", height, pose, **kw)  # type: ignore[arg-type]


def corridor_world(length: float = 20.0, width: float = 2.5) -> list[StaticObject]:
    """A corridor along x from 0 to ``length``, ``width`` wide, with two door recesses."""
    return [
        *room(0.0, 0.0, length, width, doors=(("north", 6.0, 1.0), ("south", 12.0, 1.0))),
        wall(5.5, width, 5.5, width + 0.4),
        wall(6.5, width, 6.5, width + 0.4),
        wall(11.5, 0.0, 11.5, -0.4),
        wall(12.5, 0.0, 12.5, -0.4),
    ]


@register("corridor", "a person walking and standing in a corridor", "000 Sec. 2.3.1", 30.0)
def _corridor(rng: np.random.Generator, duration: float) -> Scene:
    world = World([*corridor_world(), round_bin(8.0, 0.25)])
    v = float(rng.uniform(1.0, 1.3))
    route = Route(14.0, 1.25, math.pi).walk_to(4.0, 1.6, v).wait(3.0).turn_by(math.pi, 1.2)
    route.walk_to(9.0, 0.9, v).wait(4.0).walk_to(2.5, 1.3, v).turn_by(-math.pi, 1.2)
    route.walk_to(16.0, 1.2, v)
    people = [random_person(rng, 0, route)]
    sensors = [_lms("laser", DETECTION_HEIGHT, Pose2D(0.3, 1.25, 0.0))]
    return Scene(world, people, sensors)


def office_world() -> list[StaticObject]:
    """A 7 x 6 m office with tables, chairs, boxes, round bins and a coat stand."""
    objs: list[StaticObject] = [*room(0.0, 0.0, 7.0, 6.0, doors=(("north", 5.8, 0.9),))]
    objs += table(2.0, 4.8, 1.4, 0.8)
    objs += table(5.2, 1.0, 1.6, 0.8)
    objs += chair(2.0, 3.9, math.pi / 2)
    objs += chair(1.2, 4.4, 0.2)
    objs += chair(5.0, 2.0, -math.pi / 2)
    objs += chair(6.3, 3.2, 1.0)
    objs += [
        box(0.45, 1.5, 0.8, 0.6, 0.0, 1.2),
        box(6.5, 5.3, 0.6, 0.6, 0.3, 0.7),
        round_bin(1.0, 0.6),
        round_bin(6.6, 2.2, 0.12),
        pole(0.4, 5.5, 0.03),
    ]
    return objs


@register(
    "office",
    "cluttered office (tables, chairs, bins): two people moving and standing",
    "000 Sec. 2.3.1",
    30.0,
)
def _office(rng: np.random.Generator, duration: float) -> Scene:
    world = World(office_world())
    v = float(rng.uniform(0.9, 1.2))
    a = Route(1.0, 2.6, 0.0).walk_to(4.0, 3.0, v).wait(3.0).walk_to(3.5, 4.6, v).wait(4.0)
    a.walk_to(3.8, 2.5, v).walk_to(1.2, 2.8, v).wait(3.0).walk_to(4.5, 3.6, v)
    b = (
        Route(5.8, 5.4, -math.pi / 2, start=1.5)
        .walk_to(4.2, 1.9, v)
        .wait(2.0)
        .turn_by(math.pi, 1.5)
    )
    b.walk_to(6.2, 4.3, v).wait(5.0).walk_to(2.6, 1.8, v).wait(3.0).walk_to(5.5, 3.2, v)
    people = [random_person(rng, 0, a), random_person(rng, 1, b)]
    sensors = [_lms("laser", DETECTION_HEIGHT, Pose2D(3.5, 0.2, math.pi / 2))]
    return Scene(world, people, sensors)


@register(
    "figure-eight",
    "a person walking an 8-shaped path in a 2.5 m wide corridor",
    "000 Sec. 3.4.1",
    30.0,
)
def _figure_eight(rng: np.random.Generator, duration: float) -> Scene:
    world = World([*corridor_world(), round_bin(2.0, 2.2), box(9.0, 0.3, 0.6, 0.4)])
    v = float(rng.uniform(1.0, 1.2))
    cx, cy, r = 5.5, 1.25, 0.85
    route = Route(cx, cy, math.atan2(1.0, 1.0))
    laps = max(1, math.ceil(duration * v / (4 * math.pi * r)))
    for _ in range(laps):
        route.arc(cx + r, cy, -2 * math.pi, v)  # right loop clockwise
        route.arc(cx - r, cy, 2 * math.pi, v)  # left loop counter-clockwise
    people = [random_person(rng, 0, route)]
    sensors = [_lms("laser", TRACKING_HEIGHT, Pose2D(1.0, 1.25, 0.0))]
    return Scene(world, people, sensors)


@register(
    "turn-on-stance-leg",
    "a person moving along a line, turning 180 deg round the planted leg at every step",
    "000 Sec. 3.4.2",
    20.0,
)
def _turn_on_stance_leg(rng: np.random.Generator, duration: float) -> Scene:
    world = World([*corridor_world(), round_bin(3.0, 2.25)])
    sep = float(rng.uniform(0.28, 0.34))
    swing, pause = 0.7, 0.25
    n_steps = max(1, int(duration / (swing + pause)))
    n_steps = min(n_steps, int(9.0 / sep))
    steps, track = pivot_walk((9.5, 1.25), math.pi, n_steps, sep, swing, pause, t_start=0.5)
    person = random_person(rng, 0, None, gait=(steps, track))
    sensors = [_lms("laser", TRACKING_HEIGHT, Pose2D(0.3, 1.25, 0.0))]
    return Scene(world, [person], sensors)


@register(
    "narrow-corridor",
    "up to four people crossing, stopping, turning on the spot, entering and leaving",
    "000 Sec. 3.4.3",
    40.0,
)
def _narrow_corridor(rng: np.random.Generator, duration: float) -> Scene:
    width = 2.2
    world = World([*corridor_world(18.0, width), pole(13.0, 0.2, 0.03)])
    people: list[PersonSpec] = []
    lanes = (0.45, 0.95, 1.3, 1.75)
    pid = 0
    t = 0.0
    while t < duration - 2.0 and pid < 40:
        active = sum(
            1 for p in people if p.route is not None and p.route.t[0] <= t <= p.route.end_time
        )
        if active >= 4:
            t += 1.0
            continue
        going_in = bool(rng.random() < 0.5)
        lane = float(lanes[int(rng.integers(len(lanes)))])
        v = float(rng.uniform(0.9, 1.4))
        x0, x1 = (17.7, 0.8) if going_in else (0.8, 17.7)
        route = Route(x0, lane, math.pi if going_in else 0.0, start=t)
        xm = float(rng.uniform(3.0, 9.0))
        route.walk_to(xm, lane, v)
        if rng.random() < 0.5:
            route.wait(float(rng.uniform(1.0, 3.0)))
        if rng.random() < 0.4:
            route.turn_by(math.pi, 1.2).wait(0.5).turn_by(-math.pi, 1.2)
        other = float(lanes[int(rng.integers(len(lanes)))])
        route.walk_to(xm + (1.0 if not going_in else -1.0) * 1.5, other, v).walk_to(x1, other, v)
        people.append(random_person(rng, pid, route, leave_at_end=True))
        pid += 1
        t += float(rng.uniform(1.5, 5.0))
    sensors = [_lms("laser", TRACKING_HEIGHT, Pose2D(0.2, width / 2, 0.0))]
    return Scene(world, people, sensors)


@register(
    "robot-following",
    "a moving robot (0.33 m/s on average) following two people who stop now and then",
    "000 Sec. 3.4.4",
    40.0,
)
def _robot_following(rng: np.random.Generator, duration: float) -> Scene:
    objs = [*room(0.0, 0.0, 30.0, 6.0), pillar(10.0, 4.5), pillar(20.0, 1.5)]
    objs += [round_bin(6.0, 5.6), *table(15.0, 5.3), pole(25.0, 0.4)]
    world = World(objs)
    v = float(rng.uniform(0.45, 0.55))
    a = Route(3.0, 2.6, 0.0)
    b = Route(3.2, 3.4, 0.0)
    for x_stop in (8.0, 14.0, 20.0, 27.0):
        a.walk_to(x_stop, 2.6 + float(rng.uniform(-0.3, 0.3)), v).wait(float(rng.uniform(1.5, 3.0)))
    # person 2 strays out of the robot's view and comes back
    b.walk_to(9.0, 3.4, v).walk_to(11.0, 5.6, v).wait(4.0).walk_to(16.0, 3.6, v * 1.4)
    b.walk_to(22.0, 3.4, v).wait(2.0).walk_to(28.0, 3.3, v)
    people = [random_person(rng, 0, a), random_person(rng, 1, b)]
    track_a = sample_route(a, duration)
    # the robot drives along person 1's path 2.5 s behind, at most 0.5 m/s
    lag = 2.5 / 0.01
    xy = np.concatenate([np.repeat(track_a.xy[:1], int(lag), axis=0), track_a.xy])[
        : track_a.xy.shape[0]
    ]
    xy = xy - np.array([1.2, 0.0])
    robot_track = _robot_track_from_samples(track_a.times, xy, max_speed=0.5)
    sensors = [_lms("laser", TRACKING_HEIGHT, Pose2D(0.2, 0.0, 0.0), on_robot=True)]
    return Scene(world, people, sensors, robot=RobotSpec(robot_track))


def _robot_track_from_samples(
    times: NDArray[np.float64], xy: NDArray[np.float64], max_speed: float
) -> BodyTrack:
    """A robot track along the path of the samples ``xy`` (T, 2), never faster than
    ``max_speed`` [m/s] (one loop over the 100 Hz samples: the speed cap is sequential)."""
    dt = float(times[1] - times[0])
    # travel along the same path but never faster than max_speed
    seg = np.hypot(*np.diff(xy, axis=0).T)
    s_path = np.concatenate([[0.0], np.cumsum(seg)])
    s = np.zeros(times.size)
    for k in range(1, times.size):
        s[k] = min(s_path[k], s[k - 1] + max_speed * dt)
    x = gaussian_filter1d(np.interp(s, s_path, xy[:, 0]), 20, mode="nearest")
    y = gaussian_filter1d(np.interp(s, s_path, xy[:, 1]), 20, mode="nearest")
    vel = np.column_stack([np.gradient(x, dt), np.gradient(y, dt)])
    speed = np.hypot(vel[:, 0], vel[:, 1])
    heading = np.arctan2(vel[:, 1], vel[:, 0])
    for k in range(1, times.size):  # hold the heading while standing
        if speed[k] < 0.05:
            heading[k] = heading[k - 1]
    return BodyTrack(times, np.column_stack([x, y]), heading, vel)


def entrance_hall_scene(rng: np.random.Generator, duration: float, moving: bool) -> Scene:
    """Meetings: two parties (1-4 people each) enter by two doors, walk in formation to a
    meeting spot, stand together in a circle (one merged group), then split back into
    their parties and leave by other doors. Parties of different meetings cross the hall
    and pass each other. No collision avoidance: paths are spread over six spots.
    ``moving`` puts the scanner on a robot driving to and fro (000's dataset 2)."""
    w, h = 16.0, 12.0
    doors = (("west", 6.0, 1.6), ("east", 6.0, 1.6), ("north", 4.0, 1.6), ("north", 12.0, 1.6))
    world = World([*room(0.0, 0.0, w, h, doors=doors), pillar(5.0, 9.0), pillar(11.0, 9.0)])
    entries = [(1.3, 6.0), (w - 1.3, 6.0), (4.0, h - 1.3), (12.0, h - 1.3)]
    spots = [(4.5, 3.5), (8.0, 6.5), (11.5, 3.5), (8.0, 2.5), (4.5, 6.8), (11.5, 6.8)]
    people: list[PersonSpec] = []
    spans: list[tuple[float, float]] = []
    next_group = 0
    t = 0.0
    meeting = 0
    while t < duration - 4.0 and len(people) < 80:
        sizes = [int(rng.choice([1, 2, 2, 3, 4])), int(rng.choice([1, 1, 2, 3]))]
        present = sum(1 for a, b in spans if a <= t + 10.0 and b >= t)
        if present + sum(sizes) > 20:
            t += 2.0
            continue
        spot = spots[meeting % len(spots)]
        meeting += 1
        d_in = rng.choice(len(entries), size=2, replace=False)
        d_out = rng.choice(len(entries), size=2, replace=False)
        # party 0's block of slots faces its door, party 1's the rest of the circle
        first_door = entries[int(d_in[0])]
        facing = math.atan2(first_door[1] - spot[1], first_door[0] - spot[0])
        n_all = sum(sizes)
        start = facing - math.pi * (sizes[0] - 1) / n_all
        slots = circle_slots(spot, n_all, start=start)
        merged_id = next_group
        next_group += 1
        v = float(rng.uniform(0.9, 1.3))
        parties: list[tuple[list[Route], int, tuple[float, float]]] = []
        used = 0
        all_routes: list[Route] = []
        for j, size in enumerate(sizes):
            door = entries[int(d_in[j])]
            gid = -1
            if size > 1:
                gid = next_group
                next_group += 1
            offs = line_offsets(size)
            towards = np.subtract(spot, door)
            direction = math.atan2(towards[1], towards[0])
            c, s_ = math.cos(direction), math.sin(direction)
            routes = [
                Route(
                    door[0] + a * c - b * s_, door[1] + a * s_ + b * c, direction, start=t + 2.0 * j
                )
                for a, b in offs
            ]
            approach = np.asarray(spot) - 1.6 * towards / max(np.hypot(*towards), 1e-9)
            walk_in_formation(routes, np.array([door, approach]), v, offs)
            gather_in_circle(routes, slots[used : used + size], 0.8)
            used += size
            parties.append((routes, gid, entries[int(d_out[j])]))
            all_routes += routes
        t_merge = sync(all_routes)
        t_leave = t_merge + float(rng.uniform(4.0, 10.0))
        for routes, _gid, exit_door in parties:
            for r in routes:
                r.wait_until(t_leave)
            centre = np.mean([r.end for r in routes], axis=0)
            walk_in_formation(routes, np.array([centre, exit_door]), v)
        for routes, gid, _exit in parties:
            for r in routes:
                groups = ((-math.inf, gid), (t_merge, merged_id), (t_leave + 0.3, gid))
                people.append(random_person(rng, len(people), r, groups=groups, leave_at_end=True))
                spans.append((r.t[0], r.end_time))
        t += float(rng.uniform(3.0, 7.0))
    if not moving:
        pose = Pose2D(w / 2, 0.2, math.pi / 2)
        return Scene(world, people, [_lms("laser", DETECTION_HEIGHT, pose, rate_hz=GROUP_RATE)])
    # drive east and west along the south wall, stopping to look north into the hall
    route = Route(5.0, 1.2, math.pi / 2).wait(4.0)
    while route.end_time < duration:
        route.turn_by(-math.pi / 2, 2.0).walk_to(11.0, 1.2, 0.3).turn_by(math.pi / 2, 2.0)
        route.wait(4.0).turn_by(math.pi / 2, 2.0).walk_to(5.0, 1.2, 0.3)
        route.turn_by(-math.pi / 2, 2.0).wait(4.0)
    robot = RobotSpec(sample_route(route, duration, smoothing=0.5))
    sensor = _lms(
        "laser", DETECTION_HEIGHT, Pose2D(0.15, 0.0, 0.0), on_robot=True, rate_hz=GROUP_RATE
    )
    return Scene(world, people, [sensor], robot=robot)


register_scene(
    "entrance-hall",
    "up to 20 people in groups that meet, merge, split, pass each other and leave",
    "000 Sec. 4.6 (dataset 1)",
    60.0,
    entrance_hall_scene,
    moving=False,
)
register_scene(
    "entrance-hall-moving",
    "the entrance hall seen from a robot driving to and fro at 0.3 m/s",
    "000 Sec. 4.6 (dataset 2)",
    60.0,
    entrance_hall_scene,
    moving=True,
)
