"""004's adapted MOTP (eqs. 10-11) against hand-computed values and Fig. 4's situations."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.evaluation import SchenkMotp, matching_value
from laserpeople.evaluation.synthetic import synthetic_sequence

N = 100  # frames


def run(people, tracks):
    metric = SchenkMotp()
    for truth, frame_tracks in zip(*synthetic_sequence(people, tracks), strict=True):
        metric.accumulate(truth, frame_tracks)
    return metric


def walk(y, n=N):
    """A person walking along x at 1.2 m/s, 10 Hz."""
    return np.column_stack([0.12 * np.arange(n), np.full(n, y)])


def test_matching_value_eq10_by_hand():
    d = np.array([0.0, 0.1, 0.2, 0.4, 1.0, 2.0])
    expected = [1.0, 1.0, 1.0, 0.008 / 0.064, 0.008, 0.001]
    assert matching_value(d).tolist() == pytest.approx(expected)
    assert matching_value(np.array([0.2001]))[0] < 1.0


def test_fig4e_exact_tracking_is_one():
    a, b = walk(0.0), walk(1.0)
    assert run({1: a, 2: b}, {1: a + 0.05, 2: b - 0.05}).result().motp == 1.0


def test_fig4a_one_filter_on_two_people_is_one_half():
    # Two people walking side by side 0.3 m apart; one filter in between (0.15 m from
    # each): matched to one of them with m = 1; the other gets a virtual track (m = 0).
    a, b = walk(0.0), walk(0.3)
    r = run({1: a, 2: b}, {7: (a + b) / 2}).result()
    assert r.motp == pytest.approx(0.5)
    assert r.denominator == 2 * N and len(r.matched) == 1


def test_fig4a_with_filter_jitter_is_near_but_below_one_half():
    rng = np.random.default_rng(4)
    a, b = walk(0.0), walk(0.3)
    r = run({1: a, 2: b}, {7: (a + b) / 2 + rng.normal(0.0, 0.06, (N, 2))}).result()
    assert 0.45 < r.motp < 0.5


def test_fig4b_two_filters_on_one_person_is_one_half():
    a = walk(0.0)
    r = run({1: a}, {1: a + np.array([0.0, 0.1]), 2: a - np.array([0.0, 0.1])}).result()
    assert r.motp == pytest.approx(0.5)


def test_fig4d_three_filters_on_two_people_is_two_thirds():
    a, b = walk(0.0), walk(1.0)
    r = run({1: a, 2: b}, {1: a + np.array([0.0, 0.1]), 2: a - np.array([0.0, 0.1]), 3: b}).result()
    assert r.motp == pytest.approx(2 / 3)


def test_fig4c_gap_and_distance_lower_the_score():
    a = walk(0.0)
    half = a.copy()
    half[N // 2 :] = np.nan  # track lost half way: m = 0 in the gap frames
    assert run({1: a}, {1: half}).result().motp == pytest.approx(0.5)
    assert run({1: a}, {1: a + np.array([0.0, 0.4])}).result().motp == pytest.approx(0.125)


def test_id_switch_is_penalised_by_distance_to_the_original_person():
    # 5 frames, 2 people 3 m apart, tracks swap after frame 3 (as in the IDF1 test):
    # matched 10-1, 11-2 give m = 1 in 3 frames each and m = 0.008 / 27 in 2 frames each.
    a, b = walk(0.0, 5), walk(3.0, 5)
    t10 = np.vstack([a[:3], b[3:]])
    t11 = np.vstack([b[:3], a[3:]])
    m = run({1: a, 2: b}, {10: t10, 11: t11})
    r = m.result()
    assert r.numerator == pytest.approx(6 + 4 * 0.008 / 27)
    assert r.motp == pytest.approx((6 + 4 * 0.008 / 27) / 10)
    table = m.frames()
    assert table.column("schenk_m_sum").tolist() == pytest.approx([2, 2, 2, 0.016 / 27, 0.016 / 27])
    assert table.column("schenk_max_count").tolist() == [2] * 5


def test_matching_is_one_to_one_over_the_whole_sequence():
    # Track 5 covers person 1 closely for 60 frames and person 2 for 40 frames; the
    # trajectory matching picks person 1 only, so frames on person 2 score 0 there.
    a, b = walk(0.0), walk(2.0)
    t = np.vstack([a[:60], b[60:]])
    r = run({1: a, 2: b}, {5: t}).result()
    assert r.matched == ((5, 1),)
    assert r.motp == pytest.approx((60 + 40 * 0.008 / 8) / (2 * N))


def test_empty_is_nan():
    assert math.isnan(run({}, {}).result().motp)
