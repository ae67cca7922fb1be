"""The demo scene used by ``laserpeople demo``: a few seconds of everything at once."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from laserpeople.scan import Pose2D
from laserpeople.sim.groups import walk_in_formation
from laserpeople.sim.motion import Route
from laserpeople.sim.people import random_person
from laserpeople.sim.scenarios import register
from laserpeople.sim.sensors import SensorSpec
from laserpeople.sim.simulator import Scene
from laserpeople.sim.world import World, box, chair, pole, room, round_bin, table


@register(
    "demo",
    "two people walking as a group, one walking alone, one standing; leg-like clutter",
    "demo",
    8.0,
)
def _demo(rng: np.random.Generator, duration: float) -> Scene:
    objs = [*room(0.0, 0.0, 9.0, 7.0, doors=(("west", 3.5, 1.4),))]
    objs += [*table(6.8, 5.6, 1.2, 0.7), *chair(6.8, 4.8, math.pi / 2), *chair(5.4, 5.9, 0.0)]
    objs += [round_bin(1.2, 6.3), pole(8.5, 2.0, 0.03), box(8.4, 0.6, 0.8, 0.6)]
    world = World(objs)
    pair = [Route(0.8, 3.1, 0.0), Route(0.8, 3.85, 0.0)]
    v_pair, v_loner = float(rng.uniform(1.0, 1.2)), float(rng.uniform(1.1, 1.3))
    walk_in_formation(pair, np.array([[0.8, 3.5], [4.5, 3.5], [6.5, 2.0], [8.0, 1.8]]), v_pair)
    loner = Route(7.5, 6.4, -math.pi / 2, start=0.5).walk_to(6.0, 3.8, v_loner)
    loner.walk_to(2.5, 1.2, v_loner)
    standing = Route(3.0, 5.6, -1.2).wait(duration)
    people = [
        random_person(rng, 0, pair[0], groups=((-math.inf, 0),)),
        random_person(rng, 1, pair[1], groups=((-math.inf, 0),)),
        random_person(rng, 2, loner),
        # feet 0.28 m apart: a person at ease, whose legs the scanner sees as two segments
        replace(random_person(rng, 3, standing), hip_half_width=0.14),
    ]
    sensors = [
        SensorSpec("laser", "hokuyo-utm-30lx", 0.2, Pose2D(4.5, 0.15, math.pi / 2), rate_hz=20.0)
    ]
    return Scene(world, people, sensors)
