"""Observation links cut between points that move apart (``motion_cut``): the cut on the
velocity difference's length, the blobs' trail velocities, and the tracker's wiring."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.tracking.groups import GroupMHTTracker, GroupObservations, GroupTrackerParams
from laserpeople.tracking.groups.motion import BlobMotion

# three points in a row 1.0 m apart: one cluster at d_P = 1.3 m
ROW = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
IDX = np.arange(3, dtype=np.int64)


def _clusters(velocity: np.ndarray | None, cut: float) -> list[list[int]]:
    obs = GroupObservations.from_points(ROW, IDX, 1.3, 0.3, velocity=velocity, velocity_cut=cut)
    return sorted(sorted(obs.cluster_members(i).tolist()) for i in range(len(obs)))


def test_a_link_is_cut_on_the_length_of_the_velocity_difference() -> None:
    """(0.4, 0) against (0, 0.4): each component 0.4 apart, the difference 0.566 m/s long,
    so a cut at 0.5 m/s parts them (a cut per component, or on the speeds, 0.4 and 0.4,
    would not); (0, 0) against (0.45, 0.2) is 0.492 m/s apart and stays linked."""
    v = np.array([[0.4, 0.0], [0.0, 0.4], [0.45, 0.2]])
    assert _clusters(v, 0.5) == [[0], [1, 2]]
    v = np.array([[0.0, 0.0], [0.45, 0.2], [0.45, 0.2]])
    assert _clusters(v, 0.5) == [[0, 1, 2]]


def test_the_cut_takes_the_difference_at_the_threshold_and_not_below() -> None:
    v = np.array([[0.0, 0.0], [0.5, 0.0], [0.5, 0.0]])
    assert _clusters(v, 0.5) == [[0], [1, 2]]  # 0.5 m/s apart: cut (>=)
    assert _clusters(v, 0.5001) == [[0, 1, 2]]


def test_unknown_velocities_and_a_zero_cut_keep_the_links() -> None:
    v = np.array([[0.0, 0.0], [np.nan, np.nan], [2.0, 0.0]])
    assert _clusters(v, 0.5) == [[0, 1, 2]]  # the unknown point links both
    assert _clusters(np.array([[0.0, 0.0], [2.0, 0.0], [4.0, 0.0]]), 0.0) == [[0, 1, 2]]
    assert _clusters(None, 0.5) == [[0, 1, 2]]


def test_a_blob_the_cut_parts_counts_once_on_each_side() -> None:
    """Two points 0.2 m apart are one blob at d_hs = 0.3 m; moving 1 m/s apart they are
    two observations of one person each, not one blob in two clusters."""
    pts = np.array([[0.0, 0.0], [0.2, 0.0]])
    v = np.array([[0.0, 0.0], [1.0, 0.0]])
    obs = GroupObservations.from_points(pts, np.arange(2), 1.3, 0.3, velocity=v, velocity_cut=0.5)
    assert len(obs) == 2
    np.testing.assert_array_equal(obs.n_hs, [1.0, 1.0])


def test_blob_trails_give_each_blob_its_own_slope() -> None:
    """A standing leg at (0, 0) and a walker's blob from (3, 0) at 1.2 m/s along y, 10
    scans/s: unknown until the trail spans 0.5 s, then (0, 0) and (0, 1.2) m/s; a slope
    over the whole trail, not the last step (the last step jitters by 0.05 m: 1.2 + 0.5
    m/s)."""
    motion = BlobMotion(0.3, gate=0.5, window=1.0, min_span=0.5)
    out = np.empty((2, 2))
    for k in range(11):
        t = 0.1 * k
        jitter = 0.05 if k == 10 else 0.0
        pts = np.array([[0.0, 0.0], [3.0, 1.2 * t + jitter]])
        out = motion.update(t, pts)
        if k < 5:
            assert np.isnan(out).all()
    np.testing.assert_allclose(out[0], [0.0, 0.0], atol=1e-9)
    # least squares over t = 0..1.0 s with the last point 0.05 m high: slope 1.2 + 0.05 *
    # (1.0 - 0.5) / sum (t - 0.5)^2 = 1.2 + 0.025 / 1.1 (the end points: 1.25)
    np.testing.assert_allclose(out[1], [0.0, 1.2 + 0.025 / 1.1], atol=1e-9)


def test_a_blob_beyond_the_gate_starts_a_new_trail() -> None:
    motion = BlobMotion(0.3, gate=0.5, window=1.0, min_span=0.5)
    for k in range(8):
        motion.update(0.1 * k, np.array([[0.0, 0.1 * k]]))
    assert np.isfinite(motion.update(0.8, np.array([[0.0, 0.8]]))).all()
    assert np.isnan(motion.update(0.9, np.array([[0.0, 1.5]]))).all()  # 0.6 m from (0, 0.9)


def test_the_tracker_keeps_blob_trails_only_with_motion_cut_set() -> None:
    assert GroupMHTTracker(GroupTrackerParams(motion_cut=0.0)).motion is None
    assert isinstance(GroupMHTTracker(GroupTrackerParams(motion_cut=0.5)).motion, BlobMotion)
    with pytest.raises(ValueError, match="motion_cut"):
        GroupTrackerParams(motion_cut=-0.1)
