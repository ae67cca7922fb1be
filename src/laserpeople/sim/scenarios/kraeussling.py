"""002's three-person crossing (Kräußling et al., Sec. 3).

Three people in blue, yellow and red (002 Sec. 3; hues from 002 Table 1) start at
position 1 (upper right), 2 (upper left) and 3 (lower middle) of the surveillance area,
walk together (persons 1 and 2 merge first, then 3 joins), stand as one cluster, split
and walk to the positions given by one of the 3! = 6 permutations. The robot (B21) has
two scanners back to back for a 360 deg view; their model and height are not in the
paper (SICK LMS 200 at 0.35 m assumed). The robot sits at the origin facing +y; the
area lies in front of it.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from laserpeople.scan import Pose2D
from laserpeople.sim.groups import sync
from laserpeople.sim.motion import Route
from laserpeople.sim.people import random_person
from laserpeople.sim.scenarios import register
from laserpeople.sim.sensors import SensorSpec
from laserpeople.sim.simulator import Scene
from laserpeople.sim.world import World, box, room

PERMUTATIONS: tuple[tuple[int, int, int], ...] = tuple(
    (a, b, c) for a, b, c in itertools.permutations((1, 2, 3))
)
"""The six permutations: person i (1-based) ends at position ``PERMUTATIONS[k][i-1]``."""
POSITIONS = {1: (1.6, 4.6), 2: (-1.6, 4.6), 3: (0.0, 1.9)}
"""Positions 1 (upper right), 2 (upper left), 3 (lower middle) [m]."""
HUES = (240.0, 60.0, 0.0)
"""Blue, yellow and red clothes of persons 1, 2, 3 (002 Sec. 3, Table 1) [deg]."""
CENTRE = (0.0, 3.5)


def crossing_scene(rng: np.random.Generator, permutation: int) -> Scene:
    """The crossing with permutation number ``permutation`` (0-5) of :data:`PERMUTATIONS`."""
    perm = PERMUTATIONS[permutation % 6]
    world = World([*room(-4.0, -2.0, 4.0, 7.0), box(-3.3, 6.3, 0.8, 0.8), box(3.4, -1.4, 0.6, 0.6)])
    v = float(rng.uniform(0.7, 0.9))
    routes = [Route(*POSITIONS[i + 1], -math.pi / 2 if i < 2 else math.pi / 2) for i in range(3)]
    for r in routes:
        r.wait(1.5)
    # persons 1 and 2 meet side by side (0.7 m apart), person 3 joins just below them
    place = {
        0: (CENTRE[0] + 0.35, CENTRE[1] + 0.1),
        1: (CENTRE[0] - 0.35, CENTRE[1] + 0.1),
        2: (CENTRE[0], CENTRE[1] - 0.55),
    }
    pair = [0, 1]
    for i in pair:
        routes[i].walk_to(*place[i], speed=v)
    t_pair = sync([routes[0], routes[1]])
    routes[2].wait_until(t_pair - 1.0)
    routes[2].walk_to(*place[2], speed=v)
    t_all = sync(routes)
    t_split = t_all + float(rng.uniform(1.5, 3.0))
    for r in routes:
        r.wait_until(t_split)
    for i, r in enumerate(routes):
        # one after another, so that crossing paths do not make them collide
        r.wait(1.2 * i).walk_to(*POSITIONS[perm[i]], speed=v).wait(2.0)
    groups = [
        ((-math.inf, -1), (t_pair, 0), (t_split + 0.8, -1)),
        ((-math.inf, -1), (t_pair, 0), (t_split + 0.8, -1)),
        ((-math.inf, -1), (t_all, 0), (t_split + 0.8, -1)),
    ]
    people = [random_person(rng, i, routes[i], hue=HUES[i], groups=groups[i]) for i in range(3)]
    sensors = [
        SensorSpec("front", "sick-lms200", 0.35, Pose2D(0.0, 0.0, math.pi / 2), rate_hz=10.0),
        SensorSpec(
            "rear", "sick-lms200", 0.35, Pose2D(0.0, 0.0, -math.pi / 2), rate_hz=10.0, phase=0.05
        ),
    ]
    notes = {
        "permutation": list(perm),
        "permutation_index": permutation % 6,
        "positions": {str(k): list(v_) for k, v_ in POSITIONS.items()},
        "merge_times_s": [t_pair, t_all],
        "split_time_s": t_split,
    }
    return Scene(world, people, sensors, notes=notes)


@register(
    "crossing-3",
    "three people (blue, yellow, red) meet and swap places; the seed picks 1 of 6 permutations",
    "002 Sec. 3",
    16.0,
)
def _crossing(rng: np.random.Generator, duration: float) -> Scene:
    return crossing_scene(rng, int(rng.integers(6)))


for _k, _perm in enumerate(PERMUTATIONS):

    def _build(rng: np.random.Generator, duration: float, k: int = _k) -> Scene:
        return crossing_scene(rng, k)

    register(
        f"crossing-3-p{_k}",
        f"three-person crossing, permutation 123 -> {''.join(map(str, _perm))}",
        "002 Sec. 3",
        16.0,
    )(_build)
