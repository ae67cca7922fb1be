"""Vanished groups reported at their predictions for ``coast_time``
(:mod:`laserpeople.tracking.groups.coast`)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from laserpeople.tracking.groups import GroupTrackerParams
from laserpeople.tracking.groups.coast import CoastedReports
from laserpeople.tracks import Track


def _track(track_id: int, x: float, y: float, vx: float, vy: float, size: int = 2) -> Track:
    return Track(
        track_id=track_id,
        kind="group",
        position=np.array([x, y]),
        velocity=np.array([vx, vy]),
        covariance=np.eye(2) * 0.01,
        size=size,
        labels="3",
        contour=np.array([[x - 0.5, y], [x + 0.5, y]]),
    )


def test_a_vanished_group_is_reported_at_its_constant_velocity_prediction() -> None:
    """Reported from 8.0 s, last at 10.0 s at (1, 2) moving (0.5, -1) m/s: at 11.0 s at
    (1.5, 1.0), its contour moved by the same (0.5, -1) m, its id, size and labels kept,
    score 0 (not its last place, and not moved by the time since the previous scan only)."""
    c = CoastedReports(1.5)
    c.record(8.0, [_track(7, 0.0, 4.0, 0.5, -1.0)])
    c.record(9.9, [_track(7, 0.95, 2.1, 0.5, -1.0)])
    c.record(10.0, [_track(7, 1.0, 2.0, 0.5, -1.0)])
    (out,) = c.coasted(11.0, set())
    assert (out.track_id, out.size, out.labels, out.kind, out.score) == (7, 2, "3", "group", 0.0)
    np.testing.assert_allclose(out.position, [1.5, 1.0], atol=1e-12)
    np.testing.assert_allclose(out.contour, [[1.0, 1.0], [2.0, 1.0]], atol=1e-12)
    np.testing.assert_allclose(out.velocity, [0.5, -1.0], atol=1e-12)


def test_coasting_ends_after_the_set_time_and_when_the_id_is_reported() -> None:
    c = CoastedReports(1.0)
    c.record(8.0, [_track(7, 0.0, 0.0, 0.0, 0.0), _track(8, 5.0, 0.0, 0.0, 0.0)])
    c.record(10.0, [_track(7, 0.0, 0.0, 0.0, 0.0), _track(8, 5.0, 0.0, 0.0, 0.0)])
    assert c.coasted(10.0, set()) == []  # reported in this very scan
    assert [t.track_id for t in c.coasted(11.0, set())] == [7, 8]  # 1 s: still
    assert [t.track_id for t in c.coasted(11.0, {7})] == [8]  # 7 is reported again
    assert c.coasted(11.01, set()) == []
    c.record(11.5, [_track(9, 1.0, 1.0, 0.0, 0.0)])  # forgets what is older than 1 s
    assert len(c) == 1


def test_no_longer_than_the_group_was_reported() -> None:
    """A group reported from 10.0 s to 10.3 s is coasted until 10.6 s, not for the whole
    second; one reported from 9.0 s for the whole second."""
    c = CoastedReports(1.0)
    c.record(9.0, [_track(8, 5.0, 0.0, 0.0, 0.0)])
    for stamp in (10.0, 10.1, 10.2, 10.3):
        c.record(stamp, [_track(7, 0.0, 0.0, 0.0, 0.0), _track(8, 5.0, 0.0, 0.0, 0.0)])
    assert [t.track_id for t in c.coasted(10.6, set())] == [7, 8]
    assert [t.track_id for t in c.coasted(10.65, set())] == [8]
    assert [t.track_id for t in c.coasted(11.3, set())] == [8]


def test_a_group_seen_gone_is_not_coasted_again() -> None:
    """``gone`` sees the prediction of id 7 at 10.5 s (x >= 0.4 m): not reported then, nor
    at 10.6 s when ``gone`` would let it pass; id 8 is not seen gone."""
    c = CoastedReports(1.0)
    for stamp in (9.0, 10.0):
        c.record(stamp, [_track(7, 0.0, 0.0, 1.0, 0.0), _track(8, 5.0, 5.0, 1.0, 0.0)])

    def gone(t: Track) -> bool:
        return bool(t.position[1] < 1.0 and t.position[0] >= 0.4)

    assert [t.track_id for t in c.coasted(10.3, set(), gone)] == [7, 8]
    assert [t.track_id for t in c.coasted(10.5, set(), gone)] == [8]
    assert [t.track_id for t in c.coasted(10.6, set(), lambda t: False)] == [8]


def test_zero_seconds_coasts_nothing() -> None:
    c = CoastedReports(0.0)
    c.record(1.0, [_track(7, 0.0, 0.0, 0.0, 0.0)])
    assert c.coasted(1.1, set()) == [] and len(c) == 0


def test_setting_is_checked() -> None:
    with pytest.raises(ValueError, match="coast_time"):
        GroupTrackerParams(coast_time=-0.1)
    assert GroupTrackerParams.paper_preset["coast_time"] == 0.0


def _walker_reports(params: GroupTrackerParams) -> dict[int, list[tuple[int, float]]]:
    """A person walks along x at 1 m/s, unseen from 1.5 s to 2.5 s (longer than an unseen
    group's track lives), and on again; another stands 6 m away. Scan -> (id, x) of the
    groups reported near the walker's line."""
    from laserpeople.tracking.groups import GroupMHTTracker
    from test_track_groups import _frame, legs

    tracker = GroupMHTTracker(params)
    out: dict[int, list[tuple[int, float]]] = {}
    for k in range(32):
        stamp = 0.1 * k
        people = [(0.0, 6.0)] + ([] if 15 <= k < 25 else [(stamp, 0.0)])
        pts = np.concatenate([legs(p) for p in people])
        tracks = tracker.update(_frame(pts, k, stamp)).of_kind("group")
        out[k] = [(t.track_id, float(t.position[0])) for t in tracks if abs(t.position[1]) < 1]
    return out


def test_a_hidden_walker_is_reported_through_the_gap_under_its_id() -> None:
    """With ``coast_time`` 1 s the walker (reported from 0.3 s) is reported under its id in
    every scan of its 1-s gap, near where it walks (within 0.5 m); without (0, 000's
    reports) it is not reported in the last scans of the gap (its track was deleted). The
    frames have no scans, so nothing is seen gone."""
    coasting = _walker_reports(GroupTrackerParams(coast_time=1.0))
    walker = {i for i, _ in coasting[14]}
    assert len(walker) == 1
    for k in range(15, 25):
        assert [i for i, _ in coasting[k]] == list(walker), k
        assert abs(coasting[k][0][1] - 0.1 * k) < 0.5, k
    plain = _walker_reports(GroupTrackerParams(coast_time=0.0))
    assert any(not plain[k] for k in range(15, 25))


def test_a_place_is_seen_empty_only_where_beams_went_past_every_point() -> None:
    """One laser at the origin, beams every 1 deg over -90..90 deg. A point 2 m ahead is
    seen empty when its beam ends at 2.4 m (beyond by more than the 0.3 m margin), not at
    2.2 m (within the margin: something is there), nor at 1.0 m (behind a closer return:
    hidden), nor behind the laser (out of view); a set is seen empty only when all are."""
    from laserpeople.tracking.groups.occlusion import FrameShadows, ScanView

    def shadows(end: float) -> FrameShadows:
        ranges = np.full(181, 10.0)
        ranges[90] = end  # the beam straight ahead
        view = ScanView(np.zeros(2), 0.0, -np.pi / 2, np.pi / 180, ranges, False)
        return FrameShadows((view,))

    ahead = np.array([[2.0, 0.0]])
    assert shadows(2.4).seen_empty(ahead, 0.3)
    assert not shadows(2.2).seen_empty(ahead, 0.3)
    assert not shadows(1.0).seen_empty(ahead, 0.3)
    assert not shadows(10.0).seen_empty(np.array([[-2.0, 0.0]]), 0.3)
    both = np.array([[2.0, 0.0], [0.0, 2.0]])  # the second: beam at 90 deg ends at 10 m
    assert shadows(2.4).seen_empty(both, 0.3)
    assert not shadows(2.2).seen_empty(both, 0.3)
    assert not shadows(2.4).seen_empty(np.empty((0, 2)), 0.3)


def test_a_group_among_a_reported_groups_points_is_coasted_for_merged_seconds() -> None:
    """``coast_time`` 1 s, ``merged_coast_time`` 3 s, reported from 5.0 s to 10.0 s: while
    ``among`` holds it is coasted until 13.0 s and not at 13.01 s; within the first second
    it is coasted whether or not ``among`` holds; after it, the first scan ``among`` fails
    ends it (not coasted again at 12.1 s though ``among`` holds again)."""
    c = CoastedReports(1.0, 3.0)
    assert c.memory == 3.0
    for stamp in (5.0, 10.0):
        c.record(stamp, [_track(7, 0.0, 0.0, 0.5, 0.0)])

    def never(t: Track) -> bool:
        return False

    def always(t: Track) -> bool:
        return True

    assert [t.track_id for t in c.coasted(10.9, set(), None, never)] == [7]
    (out,) = c.coasted(12.5, set(), None, always)
    np.testing.assert_allclose(out.position, [1.25, 0.0], atol=1e-12)
    assert [t.track_id for t in c.coasted(13.0, set(), None, always)] == [7]
    assert c.coasted(13.01, set(), None, always) == []
    c.record(13.0, [_track(8, 0.0, 0.0, 0.0, 0.0)])  # 7, last reported at 10.0 s: kept
    assert len(c) == 2
    c.record(20.0, [_track(9, 0.0, 0.0, 0.0, 0.0)])
    c.record(25.0, [_track(9, 0.0, 0.0, 0.0, 0.0)])
    assert [t.track_id for t in c.coasted(26.5, set(), None, always)] == [9]
    assert c.coasted(26.6, set(), None, never) == []
    assert c.coasted(26.7, set(), None, always) == []
    plain = CoastedReports(1.0)  # merged_seconds 0: coast_time for every group
    for stamp in (5.0, 10.0):
        plain.record(stamp, [_track(7, 0.0, 0.0, 0.5, 0.0)])
    assert plain.coasted(11.5, set(), None, always) == []


def test_among_is_a_contour_point_within_blob_distance_of_a_reported_groups_point() -> None:
    """Reported group points at x = 0 and 5 m (y = 0); a coasted contour point 0.29 m from
    one of them is among them (blob_distance 0.3 m), 0.31 m not; a group without a contour
    is judged by its position; a reported group without points (occluded) counts for
    nothing."""
    from laserpeople.tracking.groups import GroupMHTTracker
    from laserpeople.tracking.groups.tracker import GroupEstimate
    from test_track_groups import _frame

    params = GroupTrackerParams()
    assert params.blob_distance == pytest.approx(0.3)
    tracker = GroupMHTTracker(params)
    frame = _frame(np.array([[0.0, 0.0], [5.0, 0.0], [9.0, 0.0]]), 0, 0.0)

    def estimate(members: list[int]) -> GroupEstimate:
        return GroupEstimate(
            1, ("0",), np.zeros(5), np.eye(5), np.array(members, dtype=np.int64),
            np.zeros((0, 2)), "",
        )  # fmt: skip

    among = tracker._among(frame, [estimate([0, 1]), estimate([])])
    near = _track(7, 5.0 + 0.5, 0.29, 0.0, 0.0)  # contour (5.0, 0.29) and (6.0, 0.29)
    far = _track(7, 5.0 + 0.5, 0.31, 0.0, 0.0)
    assert among(near) and not among(far)
    bare = dataclasses.replace(far, contour=np.empty((0, 2)), position=np.array([0.0, 0.29]))
    assert among(bare)
    assert not among(_track(7, 9.5, 0.0, 0.0, 0.0))  # point 2 is in no reported group
    assert not tracker._among(frame, [estimate([])])(near)


def test_merged_coast_time_is_checked() -> None:
    with pytest.raises(ValueError, match="merged_coast_time"):
        GroupTrackerParams(merged_coast_time=-0.1)
    with pytest.raises(ValueError, match="merged_coast_time"):
        GroupTrackerParams(merged_coast_time=float("inf"))
    assert GroupTrackerParams.paper_preset["merged_coast_time"] == 0.0


def test_in_tells_the_ids_whose_last_report_is_remembered() -> None:
    """``id in coasting``: remembered while within ``memory`` of the last record and not
    seen gone; an id reported for less time than it has been gone is remembered though not
    coasted; forgotten ones and ids never reported are not in it."""
    c = CoastedReports(1.0, merged_seconds=2.0)
    c.record(8.0, [_track(7, 0.0, 0.0, 1.0, 0.0), _track(8, 5.0, 5.0, 0.0, 0.0)])
    c.record(8.1, [_track(9, 9.0, 9.0, 0.0, 0.0)])
    assert (7 in c, 8 in c, 9 in c, 10 in c, "7" in c) == (True, True, True, False, False)
    assert [t.track_id for t in c.coasted(8.5, set())] == []  # 7, 8: reported 0 s; 9: 0.4 s
    assert 7 in c and 9 in c  # remembered, not coasted
    c.record(10.0, [_track(9, 9.0, 9.0, 0.0, 0.0)])  # 8.0 s is exactly 2.0 s before: kept
    assert (7 in c, 8 in c) == (True, True)
    c.record(10.05, [_track(9, 9.0, 9.0, 0.0, 0.0)])  # now 2.05 s: forgotten
    assert (7 in c, 8 in c, 9 in c) == (False, False, True)
    c.record(10.1, [_track(11, 0.0, 0.0, 1.0, 0.0)])
    c.record(10.5, [_track(11, 0.4, 0.0, 1.0, 0.0)])
    c.coasted(10.7, {9}, gone=lambda t: t.track_id == 11)  # seen gone: forgotten
    assert (11 in c, 9 in c) == (False, True)
