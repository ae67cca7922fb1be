"""A robot driving down a hallway into a lobby among people: the seed draws all.

Modelled on the leg_tracker benchmark recording ``general_tracking_moving_1`` (Leigh et al.
2015: a robot driving through the hallways and the lobby of a building). Per seed:

- a hallway 18-30 m long and 2.2-3.5 m wide (along +x from x = 0) opening into a lobby
  10-15 m by 9-14 m, with pillars, bins, poles and 4-post chairs in the lobby;
- a scanner like the benchmark's: 270 deg, 0.25-0.5 deg, 7.5-15 Hz, range_max 8-12 m, on
  a robot that starts at the hallway's closed end, drives down its middle at 0.4-0.9 m/s,
  pauses sometimes, and crosses the lobby to one or two waypoints; odometry errors drawn
  (the scans carry odometry poses and the truth is in the same odometry frame);
- people, each with drawn body, speed and cadence: 1-3 walk *towards* the robot down the
  hallway from ahead of it (0.6-1.0 m off its line, so they pass it), 0-2 come from behind
  and *overtake* it, 1-2 *groups* of 2-3 stand together in the lobby (and leave after a
  while, or not), and 0-2 wander in the lobby.

A person is in the ground truth of a scan only while the scanner can see them in that scan:
inside its 270 deg field of view, within its range and not fully occluded (some beam hits
them first; range noise and dropout aside). That is how the benchmark recording's
annotators labelled it: their labels end when a person leaves the view, so a tracker that
reports someone behind the robot makes a false positive, and one that stops reporting
them there loses nothing (:attr:`MovingRobotParams.truth_in_view`).

**Seeds:** tune on :data:`TUNING_SEEDS` (0-9); :data:`HELD_BACK_SEEDS` (100-119) are the
test set (``benchmarks/people_suite.py``, family ``moving-robot``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from laserpeople.config import param
from laserpeople.scan import Pose2D
from laserpeople.sim.motion import Route
from laserpeople.sim.people import BodyParams, PersonSpec, random_person, with_feet_apart
from laserpeople.sim.scenarios import register_scene
from laserpeople.sim.scenarios.randomised import (
    drawn_gait,
    drawn_laser,
    drawn_robot,
    four_posts,
    free_spot,
    one_laser_scene,
)
from laserpeople.sim.sensors import LaserModel
from laserpeople.sim.simulator import Scene
from laserpeople.sim.world import StaticObject, pillar, pole, round_bin, wall

TUNING_SEEDS = range(0, 10)
"""Seeds of the moving-robot family that may be looked at while tuning."""
HELD_BACK_SEEDS = range(100, 120)
"""Seeds reserved for testing; never tune on them."""


@dataclass(frozen=True)
class MovingRobotParams:
    """Ranges the moving-robot scenes are drawn from (uniformly unless stated)."""

    config_section = "sim_moving_robot"

    robot_speed_min: float = param(0.4, "assumed (indoor robot)", "slowest robot speed", "m/s")
    robot_speed_max: float = param(
        0.9, "assumed (the benchmark robot drives ~0.7 m/s)", "fastest robot speed", "m/s"
    )
    speed_min: float = param(0.6, "assumed", "slowest walking speed", "m/s")
    speed_max: float = param(1.5, "assumed (brisk walk)", "fastest walking speed", "m/s")
    odometry_scale_max: float = param(
        2.0, "as the randomised family", "largest factor on the default odometry errors", ""
    )
    truth_in_view: bool = param(
        True,
        "as the leg_tracker benchmark's labels (Leigh et al. 2015), which end when a person "
        "leaves the view",
        "a person is scored in a frame only while the scanner can see them in that scan "
        "(inside its field of view, within range, not fully occluded); false: when it hit "
        "them within truth_seen_within",
        "",
    )
    truth_seen_within: float = param(
        2.0,
        "as the randomised family",
        "with truth_in_view false, a person is scored in a frame when the scanner hit them "
        "within this time of it",
        "s",
    )


def _u(rng: np.random.Generator, lo: float, hi: float) -> float:
    return float(rng.uniform(lo, hi))


def benchmark_like_laser(rng: np.random.Generator) -> LaserModel:
    """A 270 deg scanner with drawn resolution, rate, range, noise and dropout."""
    res = _u(rng, 0.25, 0.5)
    fov = res * round(270.0 / res)
    return drawn_laser(
        rng,
        f"moving-robot-{res:.3f}deg",
        fov,
        res,
        (7.5, 10.0, 12.5, 15.0),
        (8.0, 12.0),
        0.02,
        "moving-robot (laserpeople.sim.scenarios.moving_robot)",
    )


def moving_robot_scene(
    rng: np.random.Generator, duration: float, params: MovingRobotParams | None = None
) -> Scene:
    """One scene of the family (module docstring)."""
    p = params or MovingRobotParams()
    hall_len, hall_w = _u(rng, 18.0, 30.0), _u(rng, 2.2, 3.5)
    lob_w, lob_h = _u(rng, 10.0, 15.0), _u(rng, 9.0, 14.0)
    mid = hall_w / 2
    x1, x2 = hall_len, hall_len + lob_w
    yb, yt = mid - lob_h / 2, mid + lob_h / 2
    objs: list[StaticObject] = [
        wall(0.0, 0.0, x1, 0.0),
        wall(0.0, hall_w, x1, hall_w),
        wall(0.0, 0.0, 0.0, hall_w),
        wall(x1, yb, x1, 0.0),
        wall(x1, hall_w, x1, yt),
        wall(x1, yb, x2, yb),
        wall(x1, yt, x2, yt),
        wall(x2, yb, x2, yt),
    ]
    taken: list[tuple[float, float, float]] = []

    def way_in_clear(x: float, y: float) -> bool:
        return not (abs(y - mid) < 1.0 and x < x1 + 4.0)  # the robot's way into the lobby

    def lobby_point(clear: float, margin: float = 1.0) -> tuple[float, float] | None:
        xs, ys = (x1 + margin, x2 - margin), (yb + margin, yt - margin)
        return free_spot(rng, xs, ys, taken, clear, way_in_clear)

    counts = {
        "pillars": int(rng.integers(0, 4)),
        "bins": int(rng.integers(0, 3)),
        "poles": int(rng.integers(0, 3)),
        "chairs": int(rng.integers(0, 5)),
    }
    for family, n in counts.items():
        for _ in range(n):
            spot = lobby_point(0.9)
            if spot is None:
                continue
            x, y = spot
            if family == "pillars":
                objs.append(pillar(x, y, _u(rng, 0.15, 0.35)))
            elif family == "bins":
                objs.append(round_bin(x, y, _u(rng, 0.1, 0.2)))
            elif family == "poles":
                objs.append(pole(x, y, _u(rng, 0.02, 0.05)))
            else:
                side = _u(rng, 0.35, 0.5)
                a = _u(rng, -math.pi, math.pi)
                objs += four_posts("chair-leg", x, y, side, side, a, _u(rng, 0.01, 0.025))
            taken.append((x, y, 0.5))

    # the robot: down the hallway's middle, then into the lobby
    v = _u(rng, p.robot_speed_min, p.robot_speed_max)
    route = Route(1.0, mid, 0.0)
    pause_at = _u(rng, 4.0, hall_len - 2.0) if rng.random() < 0.4 else None
    if pause_at is not None:
        route.walk_to(pause_at, mid, v)
        route.wait(_u(rng, 1.0, 3.0))
    route.walk_to(x1 + 1.5, mid, v)
    while route.end_time < duration:
        spot = lobby_point(0.8, margin=1.5)
        if spot is None:
            route.wait(2.0)
            continue
        route.walk_to(spot[0], spot[1], v)
        if rng.random() < 0.5:
            route.wait(_u(rng, 1.0, 3.0))
    robot = drawn_robot(rng, route, duration, p.odometry_scale_max)
    hall_time = (x1 - 1.0) / v  # about when the robot reaches the lobby

    body = BodyParams()
    people: list[PersonSpec] = []

    def add(r: Route) -> None:
        gait = drawn_gait(rng, 0.8, 1.25)
        people.append(
            with_feet_apart(random_person(rng, len(people), r, params=body, gait_params=gait))
        )

    # towards the robot: start ahead of it in the hallway (or in the lobby's mouth), walk
    # down the hallway past it to its closed end
    for _ in range(int(rng.integers(1, 4))):
        speed = _u(rng, p.speed_min, p.speed_max)
        side = float(rng.choice([-1.0, 1.0]))
        off = min(_u(rng, 0.6, 1.0), hall_w / 2 - 0.3)
        start_t = _u(rng, 0.0, 0.5 * duration)
        x0 = _u(rng, 8.0, x1 + 3.0)
        y0 = mid + side * off
        r = Route(x0, y0, math.pi, start=start_t)
        r.walk_to(0.8, y0, speed)
        r.wait(_u(rng, 1.0, 4.0))
        r.walk_to(x1 - 1.0, mid - side * off, speed)
        add(r)
    # overtaking: from behind the robot, faster than it, on one side
    for _ in range(int(rng.integers(0, 3))):
        speed = max(_u(rng, p.speed_min, p.speed_max), v + 0.4)
        side = float(rng.choice([-1.0, 1.0]))
        off = min(_u(rng, 0.6, 1.0), hall_w / 2 - 0.3)
        r = Route(0.6, mid + side * off, 0.0, start=_u(rng, 1.0, 0.4 * hall_time + 1.0))
        r.walk_to(x1 + 2.0, mid + side * off, speed)
        spot = lobby_point(0.5)
        if spot is not None:
            r.walk_to(spot[0], spot[1], speed)
        add(r)
    # groups standing in the lobby
    for _ in range(int(rng.integers(1, 3))):
        spot = lobby_point(1.2, margin=1.5)
        if spot is None:
            continue
        taken.append((spot[0], spot[1], 1.0))
        size = int(rng.integers(2, 4))
        facing0 = _u(rng, -math.pi, math.pi)
        radius = _u(rng, 0.35, 0.6)
        leave = _u(rng, 0.5 * duration, 1.5 * duration)
        for k in range(size):
            a = facing0 + 2 * math.pi * k / size
            x, y = spot[0] + radius * math.cos(a), spot[1] + radius * math.sin(a)
            r = Route(x, y, a + math.pi)
            r.wait(leave)
            speed = _u(rng, p.speed_min, p.speed_max)
            exit_spot = lobby_point(0.3, margin=0.8)
            if exit_spot is not None:
                r.walk_to(exit_spot[0], exit_spot[1], speed)
            add(r)
    # wanderers in the lobby
    for _ in range(int(rng.integers(0, 3))):
        first = lobby_point(0.4)
        if first is None:
            continue
        speed = _u(rng, p.speed_min, p.speed_max)
        r = Route(first[0], first[1], _u(rng, -math.pi, math.pi))
        while r.end_time < duration:
            spot = lobby_point(0.4)
            if spot is not None:
                r.walk_to(spot[0], spot[1], speed)
            r.wait(_u(rng, 0.5, 3.0))
        add(r)

    laser = benchmark_like_laser(rng)
    height = _u(rng, 0.15, 0.35)
    notes = {
        "family": "moving-robot",
        "hallway_m": [round(hall_len, 2), round(hall_w, 2)],
        "lobby_m": [round(lob_w, 2), round(lob_h, 2)],
        "robot_speed_mps": round(v, 2),
        "scanner": {
            "resolution_deg": round(laser.resolution_deg, 4),
            "rate_hz": laser.rate_hz,
            "range_max_m": round(laser.range_max, 2),
        },
        "clutter": counts,
        "people": len(people),
    }
    mount = Pose2D(0.3, 0.0, 0.0)
    return one_laser_scene(
        objs, people, laser, height, mount, robot, notes, p.truth_seen_within, p.truth_in_view
    )


register_scene(
    "moving-robot",
    "a robot driving down a hallway into a lobby; people walk towards it, overtake it, "
    "stand in groups (the seed draws all; tune on seeds 0-9, seeds 100-119 are held back)",
    "the leg_tracker benchmark's moving-robot recording (docs/moving-robot.md)",
    40.0,
    moving_robot_scene,
)
