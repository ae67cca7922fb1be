"""CLEAR MOT against hand-computed cases."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.errors import EvaluationError
from laserpeople.evaluation import ClearMot, EvaluationParams, gated_assignment
from laserpeople.evaluation.synthetic import synthetic_sequence
from laserpeople.tracks import Track, Tracks
from laserpeople.truth import TruthFrame

NAN = [np.nan, np.nan]


def run(people, tracks, gate=0.75):
    metric = ClearMot(EvaluationParams(gate=gate))
    for truth, frame_tracks in zip(*synthetic_sequence(people, tracks), strict=True):
        metric.accumulate(truth, frame_tracks)
    return metric


def line(n, y, x0=0.0, dx=0.3):
    return np.column_stack([x0 + dx * np.arange(n), np.full(n, y)])


def test_perfect_tracking_is_mota_one_motp_zero():
    a, b = line(10, 0.0), line(10, 2.0)
    r = run({1: a, 2: b}, {7: a.copy(), 8: b.copy()}).result()
    assert r.mota == 1.0 and r.motp == 0.0
    assert (r.matches, r.misses, r.false_positives, r.id_switches) == (20, 0, 0, 0)
    assert r.recall == 1.0 and r.precision == 1.0 and r.num_frames == 10


def test_motp_is_mean_plain_distance_in_metres_not_squared():
    a = line(4, 0.0)
    offsets = np.array([[0.3, 0.4], [0.0, 0.5], [0.6, 0.0], [0.0, 0.0]])  # 0.5, 0.5, 0.6, 0
    r = run({1: a}, {5: a + offsets}).result()
    assert r.motp == pytest.approx((0.5 + 0.5 + 0.6 + 0.0) / 4)
    assert r.distance_sum == pytest.approx(1.6)


def test_known_switch_counts_two_and_mota():
    # Tracks 10 and 11 follow people 1 and 2, then swap for the last two frames.
    a, b = line(4, 0.0), line(4, 3.0)
    t10 = np.vstack([a[:2], b[2:]])
    t11 = np.vstack([b[:2], a[2:]])
    r = run({1: a, 2: b}, {10: t10, 11: t11}).result()
    assert r.id_switches == 2  # both people change track once
    assert r.misses == 0 and r.false_positives == 0
    assert r.mota == pytest.approx(1 - 2 / 8)


def test_false_positives_and_misses_counted_per_frame():
    a, b = line(5, 0.0), line(5, 4.0)
    far = line(5, 10.0)  # a track nowhere near anybody
    b_tracked = b.copy()
    b_tracked[[1, 3]] = np.nan  # person 2 untracked in two frames
    m = run({1: a, 2: b}, {1: a.copy(), 2: b_tracked, 3: far})
    r = m.result()
    assert r.false_positives == 5 and r.misses == 2 and r.matches == 8
    assert r.mota == pytest.approx(1 - (5 + 2 + 0) / 10)
    assert r.recall == pytest.approx(8 / 10) and r.precision == pytest.approx(8 / 13)
    table = m.frames()
    assert table.column("misses").tolist() == [0, 1, 0, 1, 0]
    assert table.column("false_positives").tolist() == [1, 1, 1, 1, 1]


def test_gate_is_inclusive():
    a = np.zeros((2, 2))
    r = run({1: a}, {1: np.array([[0.75, 0.0], [0.7501, 0.0]])}).result()
    assert r.matches == 1 and r.misses == 1 and r.false_positives == 1
    assert run({1: a}, {1: a + 0.6}, gate=1.0).result().matches == 2


def test_previous_correspondence_is_kept_over_a_closer_track():
    # Track 10 follows person 1 at 0.5 m; track 11 appears closer (0.1 m) in frame 2.
    a = line(3, 0.0)
    t10 = a + np.array([0.0, 0.5])
    t11 = np.vstack([NAN, NAN, a[2] + [0.0, -0.1]])
    r = run({1: a}, {10: t10, 11: t11}).result()
    assert r.id_switches == 0 and r.false_positives == 1
    assert r.motp == pytest.approx(0.5)


def test_correspondence_survives_a_miss_and_no_switch_is_counted():
    a = line(3, 0.0)
    t10 = a + np.array([0.0, 0.4])
    t10[1] = np.nan  # track lost in frame 1
    t11 = np.vstack([NAN, NAN, a[2] + [0.0, -0.1]])
    r = run({1: a}, {10: t10, 11: t11}).result()
    assert (r.id_switches, r.misses, r.false_positives) == (0, 1, 1)
    assert r.fragmentations == 1


def test_switch_after_a_gap_is_counted():
    a = line(3, 0.0)
    t10 = np.vstack([a[0], NAN, NAN])
    t11 = np.vstack([NAN, NAN, a[2]])
    r = run({1: a}, {10: t10, 11: t11}).result()
    assert r.id_switches == 1 and r.misses == 1 and r.fragmentations == 1


def test_fragmentation_needs_a_match_after_the_gap():
    a = line(5, 0.0)
    t = a.copy()
    t[[1, 3, 4]] = np.nan  # match, miss, match, miss, miss -> one fragmentation only
    assert run({1: a}, {1: t}).result().fragmentations == 1


def test_hungarian_minimises_total_distance_not_greedy():
    # Greedy (closest pair first) would pair p1-t1 (0.1) and leave p2-t2 at 0.7;
    # the optimum pairs p1-t2 (0.3) and p2-t1 (0.3): sum 0.6 < 0.8.
    people = {1: np.array([[0.0, 0.0]]), 2: np.array([[0.4, 0.0]])}
    tracks = {1: np.array([[0.1, 0.0]]), 2: np.array([[-0.3, 0.0]])}
    r = run(people, tracks, gate=0.75).result()
    assert r.matches == 2 and r.distance_sum == pytest.approx(0.6)


def test_gated_assignment_prefers_more_pairs_over_smaller_distance():
    d = np.array([[0.1, 0.5], [0.2, 9.0]])
    rows, cols = gated_assignment(d, 0.75)
    assert sorted(zip(rows.tolist(), cols.tolist(), strict=True)) == [(0, 1), (1, 0)]
    empty = gated_assignment(np.full((2, 3), 5.0), 0.75)
    assert empty[0].size == 0 and empty[1].size == 0


def test_frames_without_people_or_tracks():
    metric = ClearMot()
    metric.accumulate(TruthFrame.from_positions(0.0, 0, np.array([]), np.empty((0, 2))), None)
    r = metric.result()
    assert math.isnan(r.mota) and math.isnan(r.motp) and r.num_frames == 1
    metric.accumulate(
        TruthFrame.from_positions(0.1, 1, np.array([4]), np.array([[1.0, 1.0]])), None
    )
    r = metric.result()
    assert r.misses == 1 and r.mota == 0.0 and math.isnan(r.precision)


def test_only_the_scored_kind_counts_and_bad_input_is_reported():
    truth = TruthFrame.from_positions(0.0, 3, np.array([1]), np.array([[0.0, 0.0]]))
    leg = Track(1, "leg", [0.0, 0.0], [0, 0], np.eye(2))
    person = Track(2, "person", [0.1, 0.0], [0, 0], np.eye(2))
    metric = ClearMot()
    metric.accumulate(truth, Tracks(0.0, 3, (leg, person)))
    assert metric.result().matches == 1 and metric.result().false_positives == 0
    with pytest.raises(EvaluationError, match="scan 4"):
        metric.accumulate(truth, Tracks(0.0, 4, (person,)))
    with pytest.raises(EvaluationError, match="track id 2 appears more than once"):
        metric.accumulate(truth, Tracks(0.0, 3, (person, person)))


def test_two_people_claiming_one_track_the_most_recent_mapping_wins():
    # Track 10 followed person 1 (frames 0-1), then person 2 (frame 2, a switch for 2).
    # In frame 3 both people are within the gate of track 10: person 2, whose mapping is
    # the more recent, keeps it (py-motmetrics would give it to the lower person id).
    people = {
        1: np.array([[0.0, 0.0], [0.0, 0.0], NAN, [0.3, 0.0]]),
        2: np.array([[5.0, 0.0], [5.0, 0.0], [5.0, 0.0], [0.5, 0.0]]),
    }
    tracks = {
        10: np.array([[0.0, 0.0], [0.0, 0.0], [5.0, 0.1], [0.45, 0.0]]),
        11: np.array([[5.0, 0.0], [5.0, 0.0], NAN, NAN]),
    }
    m = run(people, tracks)
    r = m.result()
    assert r.id_switches == 1 and r.misses == 1
    assert m.frames().column("distance_sum_m")[3] == pytest.approx(0.05)
