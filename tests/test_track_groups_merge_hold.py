"""Young merges reported as their parents (``merge_hold``, tracking/groups/merge_hold.py)."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.tracking.groups import GroupTrackerParams
from laserpeople.tracking.groups.merge_hold import MergeHold, Reported


def _rep(
    family: int,
    name: tuple[str, ...],
    x: float,
    vx: float,
    n: float,
    stamp: float,
    members: list[int] | None = None,
    event: str = "",
) -> Reported:
    mean = np.array([x, 0.0, vx, 0.0, n])
    idx = np.array(members if members is not None else [], dtype=np.int64)
    return Reported(family, family, name, mean, np.eye(5), idx, event, 1.0, stamp)


def test_a_young_merge_is_reported_as_its_parents_at_their_halves() -> None:
    hold = MergeHold(1.0)
    # scan 0: two groups walking towards each other, A at x=-1 (+1 m/s), B at x=+1 (-1 m/s)
    first = [_rep(1, ("1",), -1.0, 1.0, 2.0, 0.0), _rep(2, ("2",), 1.0, -1.0, 3.0, 0.0)]
    assert hold.apply(0.0, first, np.empty((0, 2))) == first
    # scan at 0.5 s: one merged observation; points at x = -0.6, -0.4 (near A's
    # prediction -0.5) and 0.3, 0.5, 0.7 (near B's prediction +0.5)
    pts = np.array([[-0.6, 0.0], [-0.4, 0.0], [0.3, 0.0], [0.5, 0.0], [0.7, 0.0]])
    merged = _rep(9, ("1", "2"), 0.0, 0.0, 5.0, 0.5, [0, 1, 2, 3, 4], "merge")
    out = hold.apply(0.5, [merged], pts)
    assert [r.track_id for r in out] == [1, 2]
    # each parent at the centroid of its half (not its prediction -0.5 / +0.5, not 0)
    assert out[0].mean[0] == pytest.approx(-0.5, abs=1e-9)
    assert out[1].mean[0] == pytest.approx(0.5, abs=1e-9)
    assert list(out[0].members) == [0, 1] and list(out[1].members) == [2, 3, 4]
    assert [r.mean[4] for r in out] == [2.0, 3.0]  # their own sizes, not the merge's 5
    assert hold.held_scans == 1
    # still held at 0.9 s: the halves moved on (A now predicted at -0.1, B at +0.1)
    pts2 = np.array([[-0.3, 0.0], [0.4, 0.0]])
    merged2 = _rep(9, ("1", "2"), 0.05, 0.0, 5.0, 0.9, [0, 1], "merge")
    out2 = hold.apply(0.9, [merged2], pts2)
    assert [r.mean[0] for r in out2] == pytest.approx([-0.3, 0.4], abs=1e-9)
    # 1 s after the merge it is reported itself
    merged3 = _rep(9, ("1", "2"), 0.1, 0.0, 5.0, 1.5, [0, 1], "merge")
    assert hold.apply(1.5, [merged3], pts2) == [merged3]


def test_an_occluded_merge_reports_the_parents_at_their_predictions() -> None:
    hold = MergeHold(1.0)
    hold.apply(
        0.0,
        [_rep(1, ("1",), -1.0, 1.0, 2.0, 0.0), _rep(2, ("2",), 1.0, 0.0, 1.0, 0.0)],
        np.empty((0, 2)),
    )
    merged = _rep(9, ("1", "2"), 0.0, 0.0, 3.0, 0.2, None, "merge")
    out = hold.apply(0.2, [merged], np.empty((0, 2)))
    assert [r.mean[0] for r in out] == pytest.approx([-0.8, 1.0], abs=1e-9)


def test_only_merges_of_groups_reported_last_scan_are_held() -> None:
    hold = MergeHold(1.0)
    hold.apply(
        0.0,
        [_rep(1, ("1",), -1.0, 0.0, 2.0, 0.0), _rep(2, ("2",), 1.0, 0.0, 2.0, 0.0)],
        np.empty((0, 2)),
    )
    # a merge whose labels are not the two groups' (a third group's) is reported at once,
    # and so is a group that was not made by a merge
    other = _rep(9, ("3", "4"), 0.0, 0.0, 4.0, 0.1, None, "merge")
    born = _rep(1, ("1",), -1.0, 0.0, 2.0, 0.1)
    assert hold.apply(0.1, [born, other], np.empty((0, 2))) == [born, other]


def test_zero_seconds_reports_every_merge_at_once() -> None:
    hold = MergeHold(0.0)
    hold.apply(
        0.0,
        [_rep(1, ("1",), -1.0, 0.0, 2.0, 0.0), _rep(2, ("2",), 1.0, 0.0, 2.0, 0.0)],
        np.empty((0, 2)),
    )
    merged = _rep(9, ("1", "2"), 0.0, 0.0, 4.0, 0.1, None, "merge")
    assert hold.apply(0.1, [merged], np.empty((0, 2))) == [merged]


def test_merge_hold_must_not_be_negative() -> None:
    with pytest.raises(ValueError, match="merge_hold"):
        GroupTrackerParams(merge_hold=-1.0)


def test_a_parent_back_in_the_best_hypothesis_ends_the_hold() -> None:
    hold = MergeHold(1.0)
    first = [_rep(1, ("1",), -1.0, 0.0, 2.0, 0.0), _rep(2, ("2",), 1.0, 0.0, 2.0, 0.0)]
    hold.apply(0.0, first, np.empty((0, 2)))
    merged = _rep(9, ("1", "2"), 0.0, 0.0, 4.0, 0.1, None, "merge")
    assert [r.track_id for r in hold.apply(0.1, [merged], np.empty((0, 2)))] == [1, 2]
    # another group is now reported with id 2: the merge is reported, ids stay unique
    other = _rep(2, ("5",), 3.0, 0.0, 1.0, 0.2)
    merged2 = _rep(9, ("1", "2"), 0.0, 0.0, 4.0, 0.2, None, "merge")
    out = hold.apply(0.2, [other, merged2], np.empty((0, 2)))
    assert [r.track_id for r in out] == [2, 9]
