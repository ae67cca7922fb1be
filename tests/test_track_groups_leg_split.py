"""The walkers' point split (tracking/groups/leg_split.py): segments claimed by the walker
of their nearest moved last-scan point, a walker releasing a second person, the walkers'
places, two walkers' legs in one blob at d_hs cut between them, and the observations'
blobs cut with them."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.tracking.groups import GroupTrackerParams
from laserpeople.tracking.groups.leg_split import (
    SplitSettings,
    SplitWalkerTracker,
    claim_segments,
    release_extras,
    walker_places,
)
from laserpeople.tracking.groups.observations import (
    GroupObservations,
    SizeCounting,
    close_pairs,
    component_labels,
)
from laserpeople.tracking.groups.walkers import WalkerSettings, walker_detections


def _disc(cx: float, cy: float, r: float, n: int = 6) -> np.ndarray:
    a = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    return np.column_stack([cx + r * np.cos(a), cy + r * np.sin(a)])


def test_segments_go_to_the_walker_most_of_their_points_vote_for() -> None:
    # walker 0's last points at x = 0, 0.1; walker 1's at x = 0.5, 0.6 (all y = 0)
    previous = np.array([[0.0, 0.0], [0.1, 0.0], [0.5, 0.0], [0.6, 0.0]])
    previous_owner = np.array([0, 0, 1, 1])
    centres = np.array([[0.05, 0.0], [0.55, 0.0]])
    points = np.array(
        [
            [0.05, 0.02],  # segment 0: nearest last point (0, 0) or (0.1, 0): walker 0
            [0.12, 0.0],  # segment 0: (0.1, 0), 0.02 m: walker 0
            [0.32, 0.0],  # segment 0: (0.5, 0) at 0.18 m beats (0.1, 0) at 0.22: walker 1
            [0.33, 0.0],  # segment 1: (0.5, 0) at 0.17 m: walker 1
            [0.05, 0.45],  # segment 2: no last point within 0.25 m; centre 0 at 0.45 m
            [3.0, 0.0],  # segment 3: nothing near
        ]
    )
    segments = np.array([0, 0, 0, 1, 2, 3])
    owner = claim_segments(points, segments, previous, previous_owner, centres, 0.25, 0.5)
    # segment 0: two votes for walker 0, one for walker 1
    assert owner.tolist() == [0, 1, 0, -1]
    # a centre gate of 0.4 m leaves segment 2 unclaimed
    owner = claim_segments(points, segments, previous, previous_owner, centres, 0.25, 0.4)
    assert owner.tolist() == [0, 1, -1, -1]
    # no walkers: nothing is claimed
    none = claim_segments(
        points, segments, previous[:0], previous_owner[:0], centres[:0], 0.25, 0.5
    )
    assert none.tolist() == [-1, -1, -1, -1]


def test_a_walker_holding_two_people_keeps_the_one_nearest_its_prediction() -> None:
    # walker 0 holds a wide blob (a person seen as one blob, radius 0.2 m) at (0, 0) and
    # another at (1, 0); walker 1 holds its two legs at (3, 0) and (3.4, 0)
    pts = np.concatenate(
        [_disc(0.0, 0.0, 0.2), _disc(1.0, 0.0, 0.2), _disc(3.0, 0.0, 0.05), _disc(3.4, 0.0, 0.05)]
    )
    owner = np.repeat([0, 0, 1, 1], 6)
    pairs, length = close_pairs(pts, 0.3)
    links = pairs[length < 0.3]
    centres = np.array([[0.2, 0.0], [3.2, 0.0]])
    out = release_extras(pts, owner, links, centres, 0.7, 0.12)
    # the blob at (1, 0) is 0.8 m from walker 0's prediction, the one at (0, 0) 0.2 m
    assert out.tolist() == [0] * 6 + [-1] * 6 + [1] * 12
    # predicted nearer the second blob: the first is released
    out = release_extras(pts, owner, links, np.array([[0.9, 0.0], [3.2, 0.0]]), 0.7, 0.12)
    assert out.tolist() == [-1] * 6 + [0] * 6 + [1] * 12


def test_a_walkers_place_is_the_mean_of_its_blobs_and_a_lone_leg_is_marked() -> None:
    pts = np.concatenate([_disc(0.0, 0.0, 0.05), _disc(0.4, 0.0, 0.05), _disc(2.0, 1.0, 0.05)])
    owner = np.repeat([0, 0, 1], 6)
    pairs, length = close_pairs(pts, 0.3)
    places, seen, lone = walker_places(pts, owner, pairs[length < 0.3], 3, 0.12)
    np.testing.assert_allclose(places[:2], [[0.2, 0.0], [2.0, 1.0]], atol=1e-12)
    assert seen.tolist() == [True, True, False]
    assert lone.tolist() == [False, True, False]


def _leg_points(centre: np.ndarray, heading: float, phase: float) -> np.ndarray:
    """Two legs (discs of radius 0.05 m) 0.1 m either side of ``centre`` across the
    heading, swinging +-0.15 m along it."""
    along = np.array([math.cos(heading), math.sin(heading)])
    across = np.array([-along[1], along[0]])
    swing = 0.15 * math.sin(phase)
    a = centre + 0.1 * across + swing * along
    b = centre - 0.1 * across - swing * along
    return np.concatenate([_disc(*a, 0.05), _disc(*b, 0.05)])


def _step(tracker: SplitWalkerTracker, pts: np.ndarray, stamp: float) -> np.ndarray:
    pairs, length = close_pairs(pts, 1.3)
    keep = length < 1.3
    return tracker.assign(pts, pairs[keep], length[keep], 0.3, stamp)


def test_two_walkers_legs_in_one_blob_are_split_between_them() -> None:
    """A walks east along y = 0, B west along y = 0.42: A's left leg (y = 0.1) and B's right
    leg (y = 0.32) are 0.12 m apart at the edges (two segments at 0.1 m), one blob at d_hs =
    0.3 m while they pass; the walkers of session 13 (unions of blobs) make them one walker
    there, the split keeps every point with its own walker."""
    tracker = SplitWalkerTracker(WalkerSettings(on=True), SplitSettings())
    welded = 0
    for k in range(40):
        t = 0.1 * k
        a = _leg_points(np.array([-1.0 + 0.05 * k, 0.0]), 0.0, 2.0 * t)
        b = _leg_points(np.array([1.0 - 0.05 * k, 0.42]), math.pi, 2.0 * t + 1.0)
        pts = np.concatenate([a, b])
        owner = _step(tracker, pts, t)
        ids = tracker.ids[owner]
        assert np.unique(ids[:12]).size == 1 and np.unique(ids[12:]).size == 1
        assert ids[0] != ids[12]
        pairs, length = close_pairs(pts, 0.3)
        blobs = component_labels(len(pts), pairs[length < 0.3])
        _, walker = walker_detections(pts, blobs, 0.7, 0.12)
        welded += int(np.intersect1d(walker[blobs[:12]], walker[blobs[12:]]).size > 0)
    assert welded >= 5  # the blob walkers do weld them while they pass
    assert len(tracker) == 2


def test_a_lone_walkers_points_stay_together() -> None:
    tracker = SplitWalkerTracker(WalkerSettings(on=True), SplitSettings())
    for k in range(30):
        t = 0.1 * k
        pts = _leg_points(np.array([0.12 * k, 1.0]), 0.0, 6.0 * t)
        owner = _step(tracker, pts, t)
        assert np.unique(owner).size == 1
    assert len(tracker) == 1 and tracker.ids.tolist() == [0]
    np.testing.assert_allclose(tracker.means[0, 2:4], [1.2, 0.0], atol=0.2)


def test_a_blob_cut_between_two_clusters_counts_on_both_sides() -> None:
    """Two leg-sized discs 0.2 m apart are one blob at d_hs; a filter that cuts every link
    between them makes two observations of one person each (without cutting the blob, one
    of them would hold no blob and count 0 people)."""
    pts = np.concatenate([_disc(0.0, 0.0, 0.05), _disc(0.3, 0.0, 0.05)])

    def cut(p: np.ndarray, b: np.ndarray, links: np.ndarray) -> np.ndarray:
        return (links[:, 0] < 6) == (links[:, 1] < 6)

    counting = SizeCounting("blobs")
    obs = GroupObservations.from_points(pts, np.arange(12), 1.3, 0.3, counting, keep_links=cut)
    assert len(obs) == 2
    assert obs.n_hs.tolist() == [1.0, 1.0]
    plain = GroupObservations.from_points(pts, np.arange(12), 1.3, 0.3, counting)
    assert len(plain) == 1 and plain.n_hs.tolist() == [1.0]


def test_split_settings_are_checked() -> None:
    with pytest.raises(ValueError, match="positive"):
        SplitSettings(point_gate=0.0)
    with pytest.raises(ValueError, match="must not be negative"):
        SplitSettings(release_distance=-0.1)
    with pytest.raises(ValueError, match="walker_split needs walkers"):
        GroupTrackerParams(walker_split=True)
