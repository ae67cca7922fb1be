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
        "arrival_s": max(r.end_time for r in routes) - 2.0,
    }
    return Scene(world, people, sensors, notes=notes)


def _world() -> World:
    return World([*room(-4.0, -2.0, 4.0, 7.0), box(-3.3, 6.3, 0.8, 0.8), box(3.4, -1.4, 0.6, 0.6)])


def _sensors() -> list[SensorSpec]:
    return [
        SensorSpec("front", "sick-lms200", 0.35, Pose2D(0.0, 0.0, math.pi / 2), rate_hz=10.0),
        SensorSpec(
            "rear", "sick-lms200", 0.35, Pose2D(0.0, 0.0, -math.pi / 2), rate_hz=10.0, phase=0.05
        ),
    ]


def positions_of(occupants: str) -> tuple[int, int, int]:
    """Position (1-3) of persons 1, 2, 3 for an arrangement written as 002 writes it: the
    persons occupying positions 1, 2, 3 ("213": person 2 at position 1, person 1 at 2)."""
    occ = [int(c) for c in occupants]
    if sorted(occ) != [1, 2, 3]:
        raise ValueError(f"not an arrangement of 1, 2, 3: {occupants!r}")
    where = [0, 0, 0]
    for position, person in enumerate(occ, start=1):
        where[person - 1] = position
    return where[0], where[1], where[2]


def crossings_scene(rng: np.random.Generator, arrangements: tuple[str, ...]) -> Scene:
    """Three people in blue, yellow, red who start in ``arrangements[0]`` and cross into
    each following arrangement in turn (002 Sec. 3: "213 -> 123", "123 -> 213 -> 231").

    Every crossing runs as in :func:`crossing_scene`: the two upper people meet side by
    side at the centre, the lower one joins, they stand, then leave one after another.
    """
    world = _world()
    v = float(rng.uniform(0.7, 0.9))
    where = [positions_of(a) for a in arrangements]
    routes = [
        Route(*POSITIONS[where[0][i]], -math.pi / 2 if where[0][i] < 3 else math.pi / 2)
        for i in range(3)
    ]
    for r in routes:
        r.wait(1.5)
    slot = {1: (0.35, 0.1), 2: (-0.35, 0.1), 3: (0.0, -0.55)}
    changes: list[list[tuple[float, int]]] = [[(-math.inf, -1)] for _ in range(3)]
    merges, splits, arrivals = [], [], []
    for c in range(1, len(arrangements)):
        start = where[c - 1]
        upper = [i for i in range(3) if start[i] < 3]
        lower = next(i for i in range(3) if start[i] == 3)
        for i in upper:
            dx, dy = slot[start[i]]
            routes[i].walk_to(CENTRE[0] + dx, CENTRE[1] + dy, speed=v)
        t_pair = sync([routes[i] for i in upper])
        routes[lower].wait_until(t_pair - 1.0)
        routes[lower].walk_to(CENTRE[0] + slot[3][0], CENTRE[1] + slot[3][1], speed=v)
        t_all = sync(routes)
        t_split = t_all + float(rng.uniform(1.5, 3.0))
        for r in routes:
            r.wait_until(t_split)
        for i, r in enumerate(routes):
            r.wait(1.2 * i).walk_to(*POSITIONS[where[c][i]], speed=v)
        t_arrive = sync(routes)
        for r in routes:
            r.wait(2.0)
        for i in range(3):
            changes[i].append((t_pair if i in upper else t_all, c - 1))
            changes[i].append((t_split + 0.8, -1))
        merges.append([t_pair, t_all])
        splits.append(t_split)
        arrivals.append(t_arrive)
    people = [
        random_person(rng, i, routes[i], hue=HUES[i], groups=tuple(changes[i])) for i in range(3)
    ]
    notes = {
        "arrangements": list(arrangements),
        "positions": {str(k): list(v_) for k, v_ in POSITIONS.items()},
        "merge_times_s": merges,
        "split_times_s": splits,
        "arrival_s": arrivals,
    }
    return Scene(world, people, _sensors(), notes=notes)


@register(
    "crossing-3-swap",
    "three-person crossing with swapped start: 213 -> 123 (person 2 starts at position 1)",
    "002 Sec. 3 (Figs. 8-9)",
    18.0,
)
def _crossing_swap(rng: np.random.Generator, duration: float) -> Scene:
    return crossings_scene(rng, ("213", "123"))


@register(
    "crossing-3-twice",
    "two consecutive three-person crossings: 123 -> 213 -> 231",
    "002 Sec. 3 (Figs. 10-12)",
    32.0,
)
def _crossing_twice(rng: np.random.Generator, duration: float) -> Scene:
    return crossings_scene(rng, ("123", "213", "231"))


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
