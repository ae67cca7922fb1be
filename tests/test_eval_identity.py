"""IDF1 against hand-computed cases."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.evaluation import EvaluationParams, IdentityF1
from laserpeople.evaluation.synthetic import synthetic_sequence


def run(people, tracks, gate=0.75):
    metric = IdentityF1(EvaluationParams(gate=gate))
    for truth, frame_tracks in zip(*synthetic_sequence(people, tracks), strict=True):
        metric.accumulate(truth, frame_tracks)
    return metric


def line(n, y):
    return np.column_stack([0.3 * np.arange(n), np.full(n, y)])


def test_perfect_tracking_is_idf1_one():
    a, b = line(6, 0.0), line(6, 2.0)
    r = run({1: a, 2: b}, {5: a + 0.1, 6: b}).result()
    assert (r.idf1, r.idp, r.idr) == (1.0, 1.0, 1.0)
    assert (r.idtp, r.idfp, r.idfn) == (12, 0, 0)
    assert set(r.matched) == {(5, 1), (6, 2)}


def test_identity_swap_mid_sequence_by_hand():
    # 5 frames; tracks 10/11 follow people 1/2 for 3 frames, then swap for 2 frames.
    # Best matching 10-1, 11-2: IDTP = 3 + 3 = 6; IDFP = 10 - 6 = 4; IDFN = 10 - 6 = 4.
    # IDF1 = 2*6 / (2*6 + 4 + 4) = 0.6.
    a, b = line(5, 0.0), line(5, 3.0)
    t10 = np.vstack([a[:3], b[3:]])
    t11 = np.vstack([b[:3], a[3:]])
    m = run({1: a, 2: b}, {10: t10, 11: t11})
    r = m.result()
    assert (r.idtp, r.idfp, r.idfn) == (6, 4, 4)
    assert r.idf1 == pytest.approx(0.6) and r.idp == pytest.approx(0.6)
    assert set(r.matched) == {(10, 1), (11, 2)}
    assert m.frames().column("idtp").tolist() == [2, 2, 2, 0, 0]


def test_one_track_covering_two_people_in_turn():
    # Track 9 follows person 1 for 4 frames, then person 2 for 2 frames; both people are
    # present all 6 frames. IDTP = 4 (matched to person 1); IDFN = 12 - 4; IDFP = 6 - 4.
    a, b = line(6, 0.0), line(6, 3.0)
    t = np.vstack([a[:4], b[4:]])
    r = run({1: a, 2: b}, {9: t}).result()
    assert (r.idtp, r.idfn, r.idfp) == (4, 8, 2)
    assert r.idf1 == pytest.approx(2 * 4 / (12 + 6))


def test_nothing_at_all_is_nan():
    r = run({}, {}).result()
    assert math.isnan(r.idf1) and r.idtp == 0
