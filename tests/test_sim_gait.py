"""Gait: stance foot planted while the other swings, step length and cadence grow with speed,
feet side by side when standing, turning on the spot, the pivot walk of 000 Sec. 3.4.2."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.sim.gait import GaitParams, cadence, pivot_walk, plan_footsteps
from laserpeople.sim.motion import Route, sample_route


def _walk(speed: float, hip: float = 0.1) -> tuple[np.ndarray, np.ndarray, object]:
    route = Route(0.0, 0.0, 0.0).walk_to(12.0, 0.0, speed)
    track = sample_route(route, route.end_time + 2.0)
    steps = plan_footsteps(track, hip)
    times = np.arange(0.0, route.end_time + 2.0, 0.005)
    return times, steps.positions(times), steps


def test_stance_foot_stays_put_while_the_other_swings() -> None:
    times, legs, steps = _walk(1.3)
    for i in range(steps.foot.size):  # type: ignore[attr-defined]
        swing_leg = int(steps.foot[i])  # type: ignore[attr-defined]
        inside = (times > steps.t0[i]) & (times < steps.t1[i])  # type: ignore[attr-defined]
        stance = legs[inside, 1 - swing_leg]
        assert np.ptp(stance, axis=0).max() < 1e-12  # planted: not a micrometre of motion
        swing = legs[inside, swing_leg]
        assert np.ptp(swing, axis=0).max() > 0.05
    # the feet alternate while walking steadily
    middle = (steps.t0 > 1.0) & (steps.t1 < 8.0)  # type: ignore[attr-defined]
    seq = steps.foot[middle]  # type: ignore[attr-defined]
    assert seq.size > 8 and np.all(np.diff(seq) != 0)


def test_step_length_and_cadence_grow_with_speed() -> None:
    lengths, rates = [], []
    for v in (0.6, 1.3, 2.6):
        _, _, steps = _walk(v)
        middle = (steps.t0 > 2.0) & (steps.t1 < 12.0 / v - 1.0)  # type: ignore[attr-defined]
        t0 = steps.t0[middle]  # type: ignore[attr-defined]
        rates.append(1.0 / np.median(np.diff(t0)))
        stride = np.linalg.norm(steps.p1[middle] - steps.p0[middle], axis=1)  # type: ignore[attr-defined]
        lengths.append(np.median(stride) / 2.0)  # a foot travels two step lengths per swing
        assert rates[-1] == pytest.approx(cadence(v, GaitParams()), rel=0.05)
        assert lengths[-1] == pytest.approx(v / rates[-1], rel=0.05)
    assert lengths[0] < lengths[1] < lengths[2]
    assert rates[0] < rates[1] < rates[2]
    assert 0.55 < lengths[1] < 0.8  # adult walking at 1.3 m/s


def test_standing_person_has_feet_side_by_side() -> None:
    route = Route(0.0, 0.0, 0.0).walk_to(3.0, 0.0, 1.2).wait(4.0)
    track = sample_route(route, route.end_time)
    legs = plan_footsteps(track, 0.1).positions(np.array([route.end_time - 0.5]))[0]
    np.testing.assert_allclose(legs.mean(axis=0), [3.0, 0.0], atol=0.03)
    assert np.linalg.norm(legs[0] - legs[1]) == pytest.approx(0.2, abs=0.05)
    assert legs[0, 1] > legs[1, 1]  # leg 0 is the left one when facing +x


def test_turning_on_the_spot_moves_the_feet_round_the_body() -> None:
    route = Route(0.0, 0.0, 0.0).wait(0.5).turn_by(math.pi, 2.0).wait(2.0)
    track = sample_route(route, route.end_time)
    steps = plan_footsteps(track, 0.1)
    legs = steps.positions(np.array([0.2, route.end_time - 0.2]))
    assert steps.foot.size >= 2
    # facing -x at the end: the left foot is now on the -y side
    assert legs[0, 0, 1] > 0 > legs[1, 0, 1]
    all_legs = steps.positions(np.arange(0.0, route.end_time, 0.01))
    gap = np.linalg.norm(all_legs[:, 0] - all_legs[:, 1], axis=1)
    assert gap.min() >= 0.12  # legs never pass through each other


def test_pivot_walk_swings_round_the_planted_leg() -> None:
    steps, track = pivot_walk((0.0, 0.0), 0.0, 6, leg_separation=0.3)
    times = np.arange(track.times[0], track.times[-1], 0.01)
    legs = steps.positions(times)
    d = np.linalg.norm(legs[:, 0] - legs[:, 1], axis=1)
    np.testing.assert_allclose(d, 0.3, atol=3e-3)  # a circle (24 chords) round the stance foot
    # progress along +x, one separation per step; the body turns half a turn per step
    assert legs[-1].max(axis=0)[0] == pytest.approx(6 * 0.3, abs=1e-9)
    h = np.unwrap(track.heading)
    assert abs(h[-1] - h[0]) == pytest.approx(6 * math.pi, abs=0.2)
