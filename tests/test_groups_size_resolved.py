"""Group size counted from what the laser resolves (``size_count = "resolved"``): blobs at
d_hs as 000, one-leg blobs paired as ``"legs"``, and a blob wider than a leg counted by
the legs its beams' arc holds; hand-made clusters with hand-counted people."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from laserpeople.tracking.groups.observations import (
    MATCHING_EXACT,
    GroupObservations,
    SizeCounting,
    matched_legs,
    resolved_people,
)
from laserpeople.tracking.groups.params import GroupTrackerParams

RESOLVED = SizeCounting("resolved", pair_distance=0.7, leg_radius=0.12, leg_width=0.18)
LEGS = SizeCounting("legs", pair_distance=0.7, leg_radius=0.12)


def _run(x: float, y: float, n: int, step: float) -> np.ndarray:
    """``n`` points ``step`` apart along y, centred at (x, y): a leg or legs run together."""
    return np.column_stack([np.full(n, x), y + step * (np.arange(n) - (n - 1) / 2)])


def _count(pts: np.ndarray, counting: SizeCounting, spacing: float | None) -> list[float]:
    n = len(pts)
    gap = None if spacing is None else np.full(n, spacing)
    return GroupObservations.from_points(
        pts, np.arange(n), 1.3, 0.3, counting, spacing=gap
    ).n_hs.tolist()


def test_two_legs_of_one_walker_are_one_person() -> None:
    # one-leg blobs (radius 0.06 m) 0.4 m apart: a pair, as with "legs"
    pts = np.vstack([_run(4.0, 0.0, 3, 0.06), _run(4.0, 0.4, 3, 0.06)])
    assert _count(pts, RESOLVED, 0.06) == [1.0]
    assert _count(pts, LEGS, 0.06) == [1.0]


@pytest.mark.parametrize(
    ("n_points", "people"),
    [(5, 1.0), (7, 1.0), (9, 2.0), (12, 2.0), (15, 3.0)],
)
def test_a_wide_blob_counts_the_legs_its_arc_holds(n_points: int, people: float) -> None:
    # 0.06 m per beam, radius > 0.12 m from 5 points on: arc 0.30 m (round 1.67 = 2 legs:
    # one person), 0.42 (2 legs), 0.54 (3 legs: floor(2) = 2 people), 0.72 (4: 2),
    # 0.90 (5: floor(3) = 3); "legs" counts every one of them as one person
    pts = _run(4.0, 0.0, n_points, 0.06)
    assert _count(pts, RESOLVED, 0.06) == [people]
    assert _count(pts, LEGS, 0.06) == [1.0]


def test_the_arc_weighs_each_point_by_its_beam_spacing() -> None:
    # one blob 0.48 m long: near (49 beams 0.01 m apart) its arc is 0.49 m (3 legs, two
    # people); far (5 beams 0.12 m apart) 0.60 m (round 3.3 = 3 legs, two people). Counting
    # points instead of the arc would make the near blob 49 legs.
    near, far = _run(1.0, 0.0, 49, 0.01), _run(9.0, 0.0, 5, 0.12)
    assert _count(near, RESOLVED, 0.01) == [2.0]
    assert _count(far, RESOLVED, 0.12) == [2.0]
    # the same blob seen with a spacing of 0.005 m holds 0.245 m: 1 leg, one person
    assert _count(near, RESOLVED, 0.005) == [1.0]


def test_direct_blob_counts_and_unknown_spacing() -> None:
    blob = np.array([0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1])
    radius = np.array([0.05, 0.3])
    got = resolved_people(blob, radius, RESOLVED, np.full(13, 0.07))
    # blob 0 is leg-sized (one person before pairing); blob 1: arc 0.70 m, 4 legs: 2
    assert got.tolist() == [1.0, 2.0]
    assert resolved_people(blob, radius, RESOLVED, None).tolist() == [1.0, 1.0]


def test_the_observations_keep_the_spacing_of_their_points() -> None:
    walker = np.vstack([_run(4.0, 0.0, 3, 0.06), _run(4.0, 0.4, 3, 0.06)])
    pts = np.vstack([walker, walker + np.array([0.0, 3.0])])  # a second cluster 3 m away
    spacing = np.linspace(0.05, 0.06, 12)
    obs = GroupObservations.from_points(pts, np.arange(12), 1.3, 0.3, RESOLVED, spacing=spacing)
    assert obs.n_hs.tolist() == [1.0, 1.0]
    assert obs.spacing is not None
    np.testing.assert_allclose(np.sort(obs.spacing), spacing, atol=1e-12)


def test_bad_counting_settings_are_refused() -> None:
    with pytest.raises(ValueError, match="leg_width"):
        SizeCounting("resolved", leg_width=0.0)
    with pytest.raises(ValueError, match="size counting method"):
        SizeCounting("heads")
    with pytest.raises(ValueError, match="size_count"):
        GroupTrackerParams(size_count="heads")


DEFAULT = GroupTrackerParams().counting()
"""The default counting: "resolved" with the maximum matching, ``pair_arc`` and
``person_width``."""


def _blobs(centres: list[float], points: int = 3, step: float = 0.04) -> np.ndarray:
    """One-leg blobs (``points`` points ``step`` apart along y) at x = 4 m, centred at
    each of ``centres`` along y."""
    return np.vstack([_run(4.0, y, points, step) for y in centres])


def test_the_default_counting_is_resolved_with_its_rules() -> None:
    assert DEFAULT.method == "resolved"
    assert pytest.approx(0.22) == DEFAULT.pair_arc
    assert pytest.approx(0.6) == DEFAULT.person_width


def test_legs_of_people_walking_in_file_are_matched_not_nearest() -> None:
    # four one-leg blobs on a line, 0.58, 0.50 and 0.58 m apart: two walkers with long
    # strides, 0.50 m from one to the next. Mutual nearest neighbours pair the middle two
    # (0.50 m) and leave the outer two alone (as "legs" counts): 3 people. The maximum
    # matching pairs 0-1 and 2-3: 2 people.
    pts = _blobs([0.0, 0.58, 1.08, 1.66])
    mutual = replace(DEFAULT, method="legs")
    assert _count(pts, DEFAULT, 0.04) == [2.0]
    assert _count(pts, mutual, 0.04) == [3.0]


def test_a_chain_too_long_to_search_is_paired_closest_first() -> None:
    # 14 one-leg blobs 0.5 m apart (more than MATCHING_EXACT linked): 7 pairs, 7 people
    assert MATCHING_EXACT < 14
    pts = _blobs([0.5 * k for k in range(14)])
    assert _count(pts, DEFAULT, 0.04) == [7.0]
    pairs = matched_legs(np.column_stack([np.zeros(14), 0.5 * np.arange(14)]), 0.7,
                         np.zeros(14, dtype=np.int64))  # fmt: skip
    assert sorted(pairs.ravel().tolist()) == list(range(14))
    assert np.all(np.abs(np.diff(pairs, axis=1)) == 1)


def test_matching_prefers_the_shorter_pairs_and_stays_in_its_cluster() -> None:
    # a triangle 0.5, 0.6, 0.65 m: one pair, the shortest (0-1)
    centre = np.array([[0.0, 0.0], [0.5, 0.0], [0.0, 0.6]])
    assert matched_legs(centre, 0.7, np.zeros(3, dtype=np.int64)).tolist() == [[0, 1]]
    # the same blobs in three clusters: no pair
    assert matched_legs(centre, 0.7, np.arange(3, dtype=np.int64)).shape == (0, 2)


def test_a_leg_sized_blob_whose_arc_holds_two_legs_is_not_paired() -> None:
    # far away (0.12 m per beam): a blob of two beams 0.16 m apart (radius 0.08 m, leg-sized)
    # covers an arc of 0.24 m, both legs of one person; the one-beam blob 0.5 m away is
    # a second person. With pair_arc 0 (or mutual neighbours) they pair into one person.
    pts = np.vstack([_run(8.0, 0.0, 2, 0.16), _run(8.0, 0.5, 1, 0.16)])
    assert _count(pts, DEFAULT, 0.12) == [2.0]
    assert _count(pts, replace(DEFAULT, pair_arc=0.0), 0.12) == [1.0]
    # an arc just below pair_arc (two beams of 0.105 m: 0.21 m) is one leg: paired
    assert _count(pts, DEFAULT, 0.105) == [1.0]


def test_a_blob_wider_than_a_person_holds_two_whatever_its_arc() -> None:
    # four points 0.25, 0.2, 0.25 m apart (one blob at d_hs 0.3 m, radius 0.35 m, 0.7 m
    # across) at 0.06 m per beam: an arc of 0.24 m is one person by the legs it covers, but
    # no person is 0.7 m wide at the laser: ceil(0.7 / 0.6) = 2
    pts = np.column_stack([np.full(4, 4.0), [-0.35, -0.1, 0.1, 0.35]])
    assert _count(pts, DEFAULT, 0.06) == [2.0]
    assert _count(pts, replace(DEFAULT, person_width=0.0), 0.06) == [1.0]
    # 0.56 m across: one person
    assert _count(pts * np.array([1.0, 0.8]), DEFAULT, 0.06) == [1.0]


def test_bad_matching_settings_are_refused() -> None:
    with pytest.raises(ValueError, match="person_width"):
        SizeCounting("resolved", person_width=-0.1)


def test_a_continuous_blob_of_three_legs_arc_is_one_person() -> None:
    # nine points 0.06 m apart at 0.06 m per beam: an arc of 0.54 m (3 legs: two people
    # by the arc), 0.48 m across. No gap between scan neighbours wider than surface_gap
    # (0.15 m): one surface, a torso, one person; without the rule two.
    assert pytest.approx(0.15) == DEFAULT.surface_gap
    torso = _run(4.0, 0.0, 9, 0.06)
    assert _count(torso, DEFAULT, 0.06) == [1.0]
    assert _count(torso, replace(DEFAULT, surface_gap=0.0), 0.06) == [2.0]
    # the legs of two people run together: two runs of four points 0.06 m apart with a
    # gap between them (arc 0.48 m: 3 legs, 0.56 m across). A gap of 0.14 m is still one
    # surface, one of 0.16 m is two people
    for gap, people in ((0.14, 1.0), (0.16, 2.0)):
        ys = np.r_[0.06 * np.arange(4), 0.18 + gap + 0.06 * np.arange(4)]
        assert _count(np.column_stack([np.full(8, 4.0), ys]), DEFAULT, 0.06) == [people]


def test_the_surface_rule_leaves_four_legs_arc_and_blobs_wider_than_a_person() -> None:
    # twelve points 0.04 m apart at 0.06 m per beam: arc 0.72 m, 4 legs (two people by
    # floor(4 / 2 + 1/2) as three legs are), 0.44 m across: still two people
    assert _count(_run(4.0, 0.0, 12, 0.04), DEFAULT, 0.06) == [2.0]
    # nine points 0.08 m apart: three legs' arc (0.54 m) but 0.64 m across, wider than
    # person_width: two people, continuous or not
    assert _count(_run(4.0, 0.0, 9, 0.08), DEFAULT, 0.06) == [2.0]
    # a continuous blob that counts one person by its arc stays one (five points: 0.30 m)
    assert _count(_run(4.0, 0.0, 5, 0.06), DEFAULT, 0.06) == [1.0]


def test_a_negative_surface_gap_is_refused() -> None:
    with pytest.raises(ValueError, match="surface_gap"):
        SizeCounting("resolved", surface_gap=-0.1)
    with pytest.raises(ValueError, match="surface_gap"):
        GroupTrackerParams(surface_gap=-0.1)


def test_a_blob_not_in_one_run_of_the_scan_is_not_taken_for_a_surface() -> None:
    # the torso's nine points, its last four first in scan order (a blob wrapping round
    # the scan's end), with a one-point blob 0.9 m away between the runs: the gap between
    # its runs is not seen, so the blob keeps its count by the arc (two people, and one
    # for the point). In one run: one person and one.
    torso = _run(4.0, 0.0, 9, 0.06)
    other = np.array([[4.9, 0.0]])
    assert _count(np.vstack([torso, other]), DEFAULT, 0.06) == [2.0]
    assert _count(np.vstack([torso[5:], other, torso[:5]]), DEFAULT, 0.06) == [3.0]


def test_at_torso_height_no_two_blobs_are_paired() -> None:
    """Three leg-sized blobs (radius 0.06 m) 0.5 and 0.6 m apart: at leg height two are
    one person's legs (two people), at torso height each is a body (three people), for
    ``"resolved"`` and ``"legs"`` alike; a wide blob is counted by its arc either way."""
    pts = np.vstack([_run(4.0, 0.0, 3, 0.06), _run(4.0, 0.5, 3, 0.06), _run(4.0, 1.1, 3, 0.06)])
    for counting in (RESOLVED, LEGS):
        assert _count(pts, counting, 0.06) == [2.0]
        assert _count(pts, replace(counting, torso=True), 0.06) == [3.0]
    wide = np.vstack([_run(4.0, 0.0, 10, 0.06), _run(4.0, 1.0, 3, 0.06)])  # 0.54 m: 3 legs
    assert _count(wide, replace(RESOLVED, torso=True), 0.06) == _count(wide, RESOLVED, 0.06)


def test_the_group_tracker_counts_without_pairs_when_told_it_is_at_torso_height() -> None:
    """use_torso_height(True) takes the pairs away from the observations and from the
    re-clustered parts, unless torso_pairs; use_torso_height(False) brings them back."""
    from laserpeople.tracking.groups import GroupMHTTracker

    tracker = GroupMHTTracker(GroupTrackerParams())
    assert not tracker.counting.torso and not tracker.branches.s.counting.torso
    tracker.use_torso_height(True)
    assert tracker.counting.torso and tracker.branches.s.counting.torso
    assert replace(tracker.counting, torso=False) == GroupTrackerParams().counting()
    tracker.use_torso_height(False)
    assert not tracker.counting.torso and not tracker.branches.s.counting.torso
    keep = GroupMHTTracker(GroupTrackerParams(torso_pairs=True))
    keep.use_torso_height(True)
    assert not keep.counting.torso and not keep.branches.s.counting.torso


def test_the_count_range_pairs_legs_within_the_near_and_the_far_stride() -> None:
    """Six one-leg blobs along a line, 0.65, 0.95, 0.8, 1.1 and 0.5 m apart (one cluster
    at d_P 1.3 m): paired within 0.7 m (the count) 0-1 and 4-5, 4 people; within the near
    stride 0.6 m only 4-5, 5 people (the most); within the far stride 0.9 m also 2-3, 3
    people (the fewest)."""
    pts = _blobs([0.0, 0.65, 1.6, 2.4, 3.5, 4.0])
    ranged = replace(DEFAULT, stride_range=(0.6, 0.9))
    obs = GroupObservations.from_points(pts, np.arange(len(pts)), 1.3, 0.3, ranged)
    assert obs.n_hs.tolist() == [4.0]
    assert obs.n_range is not None and obs.n_range.tolist() == [[3.0, 5.0]]
    # no range: the count alone; 000's blobs: no range either (nothing is paired)
    none = replace(DEFAULT, stride_range=(0.0, 0.0))
    assert GroupObservations.from_points(pts, np.arange(len(pts)), 1.3, 0.3, none).n_range is None
    blobs = replace(ranged, method="blobs")
    assert GroupObservations.from_points(pts, np.arange(len(pts)), 1.3, 0.3, blobs).n_range is None


def test_the_size_read_is_the_prediction_within_the_range() -> None:
    """Predicted 2.0, 3.4, 6.0 and 1.0 people, walking at 0.5 m/s, against ranges [3, 5],
    [3, 5], [3, 5] and [2, 2] (counts 4, 4, 4, 2): read 3 (the nearer end), 3.4 (inside:
    kept), 5 and 2. Standing (0.2 m/s, below stride_speed 0.3 m/s) the low end is the
    count: 4, 4, 5, 2. A track a split or merge made this scan reads the count: 4. Without
    a range the count."""
    from laserpeople.tracking.groups.observations import size_reading

    predicted = np.zeros((4, 5))
    predicted[:, 4] = [2.0, 3.4, 6.0, 1.0]
    predicted[:, 2:4] = [0.3, 0.4]  # 0.5 m/s
    n_hs = np.array([4.0, 4.0, 4.0, 2.0])
    ranges = np.array([[3.0, 5.0], [3.0, 5.0], [3.0, 5.0], [2.0, 2.0]])
    old = np.zeros(4, dtype=bool)
    got = size_reading(predicted, n_hs, ranges, old, 0.3)
    np.testing.assert_allclose(got, [3.0, 3.4, 5.0, 2.0], atol=1e-12)
    standing = predicted.copy()
    standing[:, 2:4] = [0.12, 0.16]  # 0.2 m/s
    got = size_reading(standing, n_hs, ranges, old, 0.3)
    np.testing.assert_allclose(got, [4.0, 4.0, 5.0, 2.0], atol=1e-12)
    fresh = np.array([True, True, False, False])
    got = size_reading(predicted, n_hs, ranges, fresh, 0.3)
    np.testing.assert_allclose(got, [4.0, 4.0, 5.0, 2.0], atol=1e-12)
    np.testing.assert_allclose(size_reading(predicted, n_hs, None, old, 0.3), n_hs, atol=1e-12)


def test_a_group_keeps_its_size_while_the_scan_allows_it() -> None:
    """Three people, each two leg blobs 0.5 m apart, walking at 1 m/s for ten scans (3
    people, range [3, 3]); then the middle one's legs are 0.8 m apart for ten scans: 4
    people by the count at 0.7 m, [3, 4] by the strides. The group's size stays 3 (within
    0.05); without a range, or standing (a stride_speed above its speed), it becomes 4."""
    from laserpeople.frame import Frame
    from laserpeople.scan import PointSet
    from laserpeople.tracking.groups import GroupMHTTracker

    def frame(centres: list[float], k: int) -> Frame:
        pts = _blobs(centres) + np.array([0.1 * k, 0.0])  # 1 m/s along x
        n = len(pts)
        ps = PointSet(0.1 * k, pts, np.zeros(n, dtype=np.int64), np.arange(n),
                      frame="world", index=k)  # fmt: skip
        return Frame(index=k, stamp=0.1 * k, scans=(), topic="sim", frame="world", points=ps,
                     foreground=np.ones(n, dtype=bool))  # fmt: skip

    before = [0.0, 0.5, 1.5, 2.0, 3.0, 3.5]
    after = [0.0, 0.5, 1.5, 2.3, 3.3, 3.8]
    sizes = []
    for near, far, speed in ((0.6, 0.9, 0.3), (0.0, 0.0, 0.3), (0.6, 0.9, 2.0)):
        params = GroupTrackerParams(stride_near=near, stride_far=far, stride_speed=speed)
        tracker = GroupMHTTracker(params)
        for k in range(20):
            tracker.update(frame(before if k < 10 else after, k))
        assert len(tracker.last_groups) == 1
        sizes.append(tracker.last_groups[0].size)
    np.testing.assert_allclose(sizes, [3.0, 4.0, 4.0], atol=0.05)


def test_bad_stride_ranges_are_refused() -> None:
    for near, far in ((0.8, 0.9), (0.6, 0.65), (-0.1, 0.9), (0.6, float("inf")), (0.0, 0.9)):
        with pytest.raises(ValueError, match="stride"):
            GroupTrackerParams(stride_near=near, stride_far=far)
        with pytest.raises(ValueError, match="stride_range"):
            SizeCounting("resolved", pair_distance=0.7, stride_range=(near, far))
    assert GroupTrackerParams(stride_near=0.0, stride_far=0.0).counting().stride_range == (0, 0)
    assert GroupTrackerParams(stride_near=0.7, stride_far=0.7).counting().ranged
    with pytest.raises(ValueError, match="stride_speed"):
        GroupTrackerParams(stride_speed=-0.1)
