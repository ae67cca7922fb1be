"""People in simulated scenes step aside for each other (:mod:`laserpeople.sim.avoidance`)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.sim.avoidance import keep_apart
from laserpeople.sim.motion import Route
from laserpeople.sim.people import PersonSpec, plan_person

T_END = 12.0
BOUNDS = (-20.0, -20.0, 20.0, 20.0)
TIMES = np.arange(0.0, T_END, 0.02)


def _walker(
    pid: int, start: tuple[float, float], end: tuple[float, float], **kw: object
) -> PersonSpec:
    heading = math.atan2(end[1] - start[1], end[0] - start[0])
    route = Route(*start, heading=heading).walk_to(*end, speed=1.0)
    return PersonSpec(person_id=pid, route=route, hue=0.0, **kw)  # type: ignore[arg-type]


def _states(people: list[PersonSpec]):  # type: ignore[no-untyped-def]
    return [plan_person(p, T_END).state(TIMES) for p in people]


def _closest(a, b) -> float:  # type: ignore[no-untyped-def]
    return float(np.min(np.hypot(*(a.xy - b.xy).T)))


def test_two_walkers_head_on_pass_each_other_at_the_distance() -> None:
    # head on along y = 0 and y = 0.1: planned, they come 0.1 m close
    people = [_walker(0, (-5.0, 0.0), (5.0, 0.0)), _walker(1, (5.0, 0.1), (-5.0, 0.1))]
    before = _states(people)
    assert _closest(*before) < 0.15
    after_people = keep_apart(people, T_END, distance=0.6, group_distance=0.45, bounds=BOUNDS)
    after = _states(after_people)
    assert _closest(*after) >= 0.6 - 0.02
    # they pass each other sideways: each still gets where it was going, on its own side
    for b, a in zip(before, after, strict=True):
        assert np.hypot(*(a.xy[-1] - b.xy[-1])) < 0.01
    # ... without slowing down: along the way each keeps to its planned schedule
    for b, a in zip(before, after, strict=True):
        assert np.max(np.abs(a.xy[:, 0] - b.xy[:, 0])) < 0.1
    mid = np.argmin(np.abs(after[0].xy[:, 0] - after[1].xy[:, 0]))
    assert after[0].xy[mid, 1] < -0.1 and after[1].xy[mid, 1] > 0.2
    # a sidestep, not a sprint: no more than 0.3 m/s above the planned 1 m/s
    for a in after:
        assert np.max(np.hypot(*a.velocity.T)) < 1.3
    # the legs follow the bent path
    for a in after:
        centre = a.legs.mean(axis=1)
        assert np.max(np.hypot(*(centre - a.xy).T)) < 0.4


def test_walkers_on_one_line_pick_sides_rather_than_push_each_other_back() -> None:
    # they meet between two instants of the solver's 0.05 s grid, never exactly on one spot
    people = [_walker(0, (-5.0, 0.0), (5.0, 0.0)), _walker(1, (5.03, 0.0), (-5.0, 0.0))]
    before = _states(people)
    after = _states(keep_apart(people, T_END, distance=0.6, group_distance=0.45, bounds=BOUNDS))
    assert _closest(*after) >= 0.58
    for b, a in zip(before, after, strict=True):
        assert np.max(np.abs(a.xy[:, 0] - b.xy[:, 0])) < 0.1


def test_a_standing_person_gives_way_less_than_a_walker() -> None:
    stand = PersonSpec(person_id=1, route=Route(0.0, 0.05, heading=0.0).wait(T_END), hue=0.0)
    people = [_walker(0, (-5.0, 0.0), (5.0, 0.0)), stand]
    after = _states(keep_apart(people, T_END, distance=0.6, group_distance=0.45, bounds=BOUNDS))
    assert _closest(*after) >= 0.58
    walker_off = np.max(np.abs(after[0].xy[:, 1]))
    stander_off = np.max(np.hypot(*(after[1].xy - [0.0, 0.05]).T))
    assert walker_off > 2.0 * stander_off


def test_one_group_may_walk_closer_than_strangers() -> None:
    together = ((-math.inf, 3),)
    people = [
        _walker(0, (-5.0, 0.0), (5.0, 0.0), groups=together),
        _walker(1, (-5.0, 0.5), (5.0, 0.5), groups=together),
    ]
    kept = keep_apart(people, T_END, distance=0.6, group_distance=0.45, bounds=BOUNDS)
    assert kept == people  # 0.5 m apart is fine within a group: nobody is moved
    strangers = [_walker(0, (-5.0, 0.0), (5.0, 0.0)), _walker(1, (-5.0, 0.5), (5.0, 0.5))]
    apart = _states(keep_apart(strangers, T_END, distance=0.6, group_distance=0.45, bounds=BOUNDS))
    assert _closest(*apart) >= 0.58


def test_people_stay_inside_the_bounds() -> None:
    people = [_walker(0, (-5.0, 0.0), (5.0, 0.0)), _walker(1, (5.0, 0.05), (-5.0, 0.05))]
    tight = (-6.0, -0.2, 6.0, 0.45)
    after = _states(keep_apart(people, T_END, distance=0.6, group_distance=0.45, bounds=tight))
    for a in after:
        assert np.all(a.xy[:, 1] >= -0.2 - 0.01) and np.all(a.xy[:, 1] <= 0.45 + 0.01)


def test_people_without_a_route_are_refused() -> None:
    people = [_walker(0, (0.0, 0.0), (1.0, 0.0)), PersonSpec(person_id=1, route=None, hue=0.0)]
    with pytest.raises(ValueError, match="route"):
        keep_apart(people, T_END, distance=0.6, group_distance=0.45, bounds=BOUNDS)
