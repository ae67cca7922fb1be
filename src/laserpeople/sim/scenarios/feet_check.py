"""Scenes for the feet tracker (004 Sec. 2.1) unlike 004's own experiments.

004's scenes (:mod:`laserpeople.sim.scenarios.schenk`) have four LMS151 (0.5 deg, 50 Hz)
2 m either side of one walking line and an empty room. These two are drawn per seed the
other way round: one scanner of 0.25 deg at 0.2 m above the floor in a corner of the
room, at a scan rate drawn from 15-40 Hz, legs of 0.06-0.08 m radius, clutter whose
posts and bins look like legs, and people who walk, stop for a few seconds and walk on.

- ``feet-crossing``: three or four people cross a 7 x 6 m hall between its sides, some
  stopping on the way, among bins, poles and a table.
- ``feet-office``: two or three people walk between desks and chairs in a cluttered
  office and stand at them.

**Seeds:** tune on :data:`TUNING_SEEDS` (0-9); :data:`HELD_BACK_SEEDS` (100-119) are for
reporting only.
"""

from __future__ import annotations

import math

import numpy as np

from laserpeople.scan import Pose2D
from laserpeople.sim.motion import Route
from laserpeople.sim.people import BASIC_HUES, BodyParams, PersonSpec, random_person
from laserpeople.sim.scenarios import register
from laserpeople.sim.scenarios.arras import office_world
from laserpeople.sim.sensors import LASER_MODELS, SensorSpec
from laserpeople.sim.simulator import Scene
from laserpeople.sim.world import StaticObject, World, chair, pole, room, round_bin, table

TUNING_SEEDS = range(0, 10)
"""Seeds that may be looked at while tuning."""
HELD_BACK_SEEDS = range(100, 120)
"""Seeds for reporting only; never tune on them."""

LEG_RADIUS = (0.06, 0.08)
"""Range of the people's leg radius [m]."""
RATES_HZ = (15.0, 20.0, 25.0, 40.0)
"""Scan rates drawn from [Hz] (the 0.25 deg scanner's model runs at 40 Hz)."""
LASER_HEIGHT = 0.2
"""Mounting height of the scanner [m]."""


def _body() -> BodyParams:
    return BodyParams(leg_radius_min=LEG_RADIUS[0], leg_radius_max=LEG_RADIUS[1])


def _laser(rng: np.random.Generator, pose: Pose2D) -> SensorSpec:
    """The 0.25 deg scanner (Hokuyo UTM-30LX geometry) at :data:`LASER_HEIGHT`."""
    assert LASER_MODELS["hokuyo-utm-30lx"].resolution_deg == 0.25
    return SensorSpec(
        "laser", "hokuyo-utm-30lx", LASER_HEIGHT, pose, rate_hz=float(rng.choice(RATES_HZ))
    )


def _person(rng: np.random.Generator, pid: int, route: Route) -> PersonSpec:
    return random_person(rng, pid, route, hue=float(BASIC_HUES[pid % 6]), params=_body())


def _stop(rng: np.random.Generator, route: Route, chance: float) -> None:
    """With probability ``chance`` stand still for 1.5-5 s."""
    if rng.random() < chance:
        route.wait(float(rng.uniform(1.5, 5.0)))


@register(
    "feet-crossing",
    "3-4 people crossing a hall, some stopping; clutter; one 0.25 deg laser at 0.2 m, "
    "legs 0.06-0.08 m (tune on seeds 0-9, seeds 100-119 are held back)",
    "004 Sec. 2.1 on scenes unlike its experiments",
    16.0,
)
def _crossing(rng: np.random.Generator, duration: float) -> Scene:
    w, h = 7.0, 6.0
    objs: list[StaticObject] = [*room(0.0, 0.0, w, h)]
    objs += table(float(rng.uniform(1.0, 1.8)), float(rng.uniform(4.4, 5.0)), 1.2, 0.7)
    objs += [
        round_bin(float(rng.uniform(5.5, 6.5)), float(rng.uniform(4.5, 5.5))),
        round_bin(float(rng.uniform(0.4, 0.8)), float(rng.uniform(1.5, 3.0)), 0.12),
        pole(float(rng.uniform(5.8, 6.6)), float(rng.uniform(1.0, 2.0)), 0.035),
        pole(float(rng.uniform(3.0, 4.0)), float(rng.uniform(5.4, 5.7)), 0.03),
    ]
    objs += chair(float(rng.uniform(4.5, 5.2)), float(rng.uniform(5.2, 5.6)), 0.3)
    n = int(rng.integers(3, 5))
    people = []
    for i in range(n):
        v = float(rng.uniform(0.6, 1.4))
        start = float(rng.uniform(0.0, 3.0))
        if i % 2 == 0:  # across the hall, left to right or back
            y0, y1 = rng.uniform(1.5, 4.5, 2)
            x0, x1 = (0.5, w - 0.5) if rng.random() < 0.5 else (w - 0.5, 0.5)
        else:  # from the far side towards the laser's side or back
            x0, x1 = rng.uniform(1.5, 5.5, 2)
            y0, y1 = (h - 0.5, 0.8) if rng.random() < 0.5 else (0.8, h - 0.5)
        r = Route(float(x0), float(y0), 0.0, start=start)
        mx, my = 0.5 * (x0 + x1) + rng.normal(0.0, 0.4), 0.5 * (y0 + y1) + rng.normal(0.0, 0.4)
        r.walk_to(float(mx), float(my), v)
        _stop(rng, r, 0.6)
        r.walk_to(float(x1), float(y1), v)
        _stop(rng, r, 0.5)
        people.append(_person(rng, i, r))
    laser = _laser(rng, Pose2D(0.15, 0.15, math.pi / 4))
    return Scene(World(objs), people, [laser])


@register(
    "feet-office",
    "2-3 people walking between desks and standing in a cluttered office; one 0.25 deg "
    "laser at 0.2 m, legs 0.06-0.08 m (tune on seeds 0-9, seeds 100-119 are held back)",
    "004 Sec. 2.1 on scenes unlike its experiments",
    20.0,
)
def _office(rng: np.random.Generator, duration: float) -> Scene:
    objs = office_world()
    # free places in the office to walk between (clear of its furniture)
    spots = np.array(
        [
            [1.0, 2.6],
            [3.0, 3.0],
            [3.5, 4.4],
            [4.2, 2.0],
            [1.2, 1.0],
            [4.6, 3.6],
            [2.8, 1.4],
            [5.8, 4.5],
        ]
    )
    n = int(rng.integers(2, 4))
    people = []
    for i in range(n):
        order = rng.permutation(len(spots))[:4]
        v = float(rng.uniform(0.6, 1.3))
        x, y = spots[order[0]] + rng.normal(0.0, 0.1, 2)
        r = Route(float(x), float(y), 0.0, start=float(rng.uniform(0.0, 2.0)))
        for k in order[1:]:
            x, y = spots[k] + rng.normal(0.0, 0.1, 2)
            r.walk_to(float(x), float(y), v)
            _stop(rng, r, 0.7)
        people.append(_person(rng, i, r))
    laser = _laser(rng, Pose2D(6.8, 0.2, 3 * math.pi / 4))
    return Scene(World(objs), people, [laser])


__all__ = ["HELD_BACK_SEEDS", "LASER_HEIGHT", "LEG_RADIUS", "RATES_HZ", "TUNING_SEEDS"]
