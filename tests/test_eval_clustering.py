"""Clustering error (000 Sec. 4.6.1) against hand-computed cases."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.errors import EvaluationError
from laserpeople.evaluation import (
    ClusteringError,
    beam_group_labels,
    clustering_error,
    frame_counts,
    partition_labels,
)
from laserpeople.truth import BeamLabels


def test_perfect_partition_has_no_error():
    truth = [{1, 2}, {3}, {4, 5, 6}]
    r = clustering_error([truth], [[{2, 1}, {6, 5, 4}, {3}]])
    assert (r.under_segmented, r.over_segmented, r.missed_groups) == (0, 0, 0)
    assert r.error == 0.0 and r.true_groups == 3 and r.clusters == 3


def test_merged_groups_are_one_under_segmentation():
    # One cluster holds groups {1,2} and {3,4}: it has too many points (under) and is
    # missing none of its dominant group (tie -> smaller label, fully inside): not over.
    r = clustering_error([[{1, 2}, {3, 4}]], [[{1, 2, 3, 4}]])
    assert (r.under_segmented, r.over_segmented) == (1, 0)
    assert r.under_rate == pytest.approx(1 / 2) and r.error == pytest.approx(1 / 2)


def test_split_group_is_over_segmented_once_per_piece():
    r = clustering_error([[{1, 2, 3}]], [[{1, 2}, {3}]])
    assert (r.under_segmented, r.over_segmented) == (0, 2)
    assert r.error == pytest.approx(2.0)


def test_wrong_points_make_an_under_segmentation():
    # Person 9 is not a person in the truth (e.g. a clutter track) but sits in a cluster.
    r = clustering_error([[{1, 2}]], [[{1, 2, 9}]])
    assert (r.under_segmented, r.over_segmented) == (1, 0)


def test_mixed_error_over_two_frames_and_missed_groups():
    truth = [[{1, 2}, {3}], [{1, 2}, {3}, {4}]]
    estimate = [
        [{1}, {2, 3}],  # {1}: over; {2,3}: under + over (dominant {1,2} tie->label 0 misses 1)
        [{1, 2}],  # {3} and {4} missed
    ]
    r = clustering_error(truth, estimate)
    assert (r.under_segmented, r.over_segmented, r.missed_groups) == (1, 2, 2)
    assert r.true_groups == 5
    assert r.error == pytest.approx(3 / 5)


def test_per_beam_labels_and_dominant_group():
    # 10 beams: group 0 on beams 0-5, group 1 on beams 6-8, beam 9 background.
    t = np.array([0, 0, 0, 0, 0, 0, 1, 1, 1, -1])
    # Cluster 7 takes beams 0-3 and 6 (dominant group 0, missing beams 4-5: over; also
    # holds a beam of group 1: under); cluster 8 takes 4-5 (over), beams 7-9 unassigned.
    e = np.array([7, 7, 7, 7, 8, 8, 7, -1, -1, -1])
    c = frame_counts(t, e)
    assert (c.true_groups, c.clusters, c.under_segmented, c.over_segmented) == (2, 2, 1, 2)
    assert c.missed_groups == 0
    assert frame_counts(t, np.full(10, -1)).missed_groups == 2


def test_beam_group_labels_give_people_alone_their_own_label():
    labels = BeamLabels(
        person=np.array([3, 3, 4, 5, -1]),
        leg=np.array([0, 1, 0, 0, -1]),
        group=np.array([2, 2, 2, -1, -1]),
        obj=np.array([-1, -1, -1, -1, 7]),
    )
    g = beam_group_labels(labels)
    assert g[:3].tolist() == [2, 2, 2] and g[4] == -1
    assert g[3] >= 0 and g[3] != 2


def test_clustering_error_counts_a_memoryless_merge_of_passing_groups():
    # The arithmetic of the measure on 000 Fig. 18 written as partitions: a clustering that
    # joins a person and a passing pair for 3 of 5 frames scores 3 under-segmentations per
    # 10 true groups. (The tracker itself against memory-less clustering on that scene:
    # tests/test_track_groups.py::test_fig18_tracker_keeps_a_passing_person_apart and
    # tests/test_track_groups_sim.py.)
    truth = [[{1, 2}, {3}]] * 5
    tracker = [[{1, 2}, {3}]] * 5
    memoryless = [[{1, 2}, {3}]] + [[{1, 2, 3}]] * 3 + [[{1, 2}, {3}]]
    assert clustering_error(truth, tracker).error == 0.0
    assert clustering_error(truth, memoryless).error == pytest.approx(3 / 10)


def test_bad_input_is_reported_and_empty_is_nan():
    with pytest.raises(EvaluationError, match="person 1 is in two true groups"):
        partition_labels([{1}, {1, 2}], [])
    with pytest.raises(EvaluationError, match="3 true labels but 2"):
        frame_counts(np.zeros(3, int), np.zeros(2, int))
    r = ClusteringError().result()
    assert math.isnan(r.error) and r.num_frames == 0
    metric = ClusteringError()
    metric.accumulate_partitions([{1}], [{1}], stamp=2.5)
    assert metric.frames().rows == ((0, 2.5, 1, 1, 0, 0, 0),)
