"""Reported ids handed over to the groups that take a vanished group's place
(``id_memory``, ``id_gate``; :mod:`laserpeople.tracking.groups.handover`)."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.tracking.groups import GroupTrackerParams
from laserpeople.tracking.groups.confirm import Candidate
from laserpeople.tracking.groups.handover import IdHandover, Vanished
from laserpeople.tracking.groups.model import GroupPayload
from laserpeople.tracking.mht.tracktree import TrackNode


def _state(x: float, y: float, vx: float = 0.0, vy: float = 0.0) -> np.ndarray:
    return np.array([x, y, vx, vy, 1.0])


def test_prediction_is_constant_velocity() -> None:
    v = Vanished(2.0, np.array([1.0, 2.0]), np.array([0.5, -1.0]))
    np.testing.assert_allclose(v.predicted(3.5), [1.75, 0.5], atol=1e-12)


def test_a_vanished_id_goes_to_the_group_at_its_prediction_not_its_last_place() -> None:
    """A party walking at 1 m/s vanished 1.5 s ago: a new group 1.5 m further on takes its
    id; one at its last place (1.5 m behind the prediction, outside the 1 m gate) does not."""
    h = IdHandover(memory=2.0, gate=1.0)
    h.record(10.0, [7], [_state(0.0, 0.0, 1.0, 0.0)])
    assert h.hand_over(11.5, [np.array([1.6, 0.1])], set()) == [7]
    assert h.hand_over(11.5, [np.array([0.0, 0.0])], set()) == [None]


def test_gate_and_memory_bound_the_handover() -> None:
    h = IdHandover(memory=2.0, gate=1.0)
    h.record(10.0, [3], [_state(0.0, 0.0)])
    assert h.hand_over(11.0, [np.array([0.99, 0.0])], set()) == [3]
    assert h.hand_over(11.0, [np.array([1.01, 0.0])], set()) == [None]
    assert h.hand_over(12.0, [np.array([0.0, 0.0])], set()) == [3]  # 2 s: still
    assert h.hand_over(12.01, [np.array([0.0, 0.0])], set()) == [None]
    h.record(12.5, [4], [_state(5.0, 5.0)])  # forgets what is older than memory
    assert len(h) == 1


def test_ids_reported_now_are_not_handed_over_and_each_id_goes_once() -> None:
    h = IdHandover(memory=2.0, gate=1.0)
    h.record(1.0, [1, 2], [_state(0.0, 0.0), _state(0.5, 0.0)])
    # id 1 is reported in this scan: only 2 can go, to the nearer of the two new groups
    out = h.hand_over(1.1, [np.array([0.0, 0.1]), np.array([0.5, 0.05])], {1})
    assert out == [None, 2]


def test_nearest_pairs_first() -> None:
    """Both new groups lie within the gate of both vanished ids: the nearest pair is taken
    first (0.1 m: new group 1 takes id 5), the other pair follows (new group 0, id 6),
    though new group 0 is nearer to id 5 (0.3 m) than to id 6 (0.7 m)."""
    h = IdHandover(memory=2.0, gate=1.0)
    h.record(1.0, [5, 6], [_state(0.0, 0.0), _state(1.0, 0.0)])
    out = h.hand_over(1.1, [np.array([0.3, 0.0]), np.array([0.1, 0.0])], set())
    assert out == [6, 5]


def test_the_same_scan_is_never_handed_over() -> None:
    h = IdHandover(memory=2.0, gate=1.0)
    h.record(1.0, [5], [_state(0.0, 0.0)])
    assert h.hand_over(1.0, [np.array([0.0, 0.0])], set()) == [None]


def test_memory_zero_hands_nothing_over() -> None:
    h = IdHandover(memory=0.0, gate=1.0)
    h.record(1.0, [5], [_state(0.0, 0.0)])
    assert h.hand_over(1.1, [np.array([0.0, 0.0])], set()) == [None]


@pytest.mark.parametrize(
    ("name", "value"), [("id_memory", -1.0), ("id_gate", 0.0), ("take_over_distance", -0.1)]
)
def test_settings_are_checked(name: str, value: float) -> None:
    with pytest.raises(ValueError, match=name):
        GroupTrackerParams(**{name: value})  # type: ignore[arg-type]


def _walker_hidden_for_a_while(params: GroupTrackerParams) -> tuple[list[int], list[int]]:
    """A person walks along x at 1 m/s, unseen from 1.0 s to 2.2 s (longer than an unseen
    group's track lives), and on again; another stands 6 m away throughout. The ids
    reported for the walker before it is hidden and from 0.3 s after it is seen again."""
    from laserpeople.tracking.groups import GroupMHTTracker
    from test_track_groups import _frame, legs

    tracker = GroupMHTTracker(params)
    before: list[int] = []
    after: list[int] = []
    for k in range(45):
        stamp = 0.1 * k
        people = [(0.0, 6.0)] + ([] if 10 <= k < 22 else [(stamp, 0.0)])
        pts = np.concatenate([legs(p) for p in people])
        out = tracker.update(_frame(pts, k, stamp)).of_kind("group")
        walker = [t.track_id for t in out if abs(t.position[1]) < 1.0]
        if k < 10:
            before.extend(walker)
        elif k >= 25:
            after.extend(walker)
    return before, after


def test_a_walker_seen_again_keeps_its_id() -> None:
    """With the handover the walker who comes back where its prediction is keeps its id;
    without (``id_memory = 0``, 000) it comes back under a new one."""
    before, after = _walker_hidden_for_a_while(GroupTrackerParams())
    assert before and after and set(before) == set(after)
    before, after = _walker_hidden_for_a_while(GroupTrackerParams(id_memory=0.0))
    assert before and after and not set(before) & set(after)


def _group(family: int, x: float, seen: bool) -> TrackNode:
    members = np.arange(3, dtype=np.int64) if seen else np.empty(0, dtype=np.int64)
    payload = GroupPayload(np.zeros((1, 2)), (str(family),), members=members)
    mean = np.array([x, 0.0, 0.0, 0.0, 1.0])
    return TrackNode(family, family, -1, mean, np.eye(5), 0.0, "detected", payload=payload)


@pytest.mark.parametrize(("x", "taken"), [(0.9, True), (1.1, False)])
def test_a_new_group_beside_a_coasting_one_takes_its_place(x: float, taken: bool) -> None:
    """Group 1 is reported and coasts (unseen this scan) at 0 m; new group 2 is seen at
    ``x``. Within ``take_over_distance`` (1 m) the new group is confirmed at once and the
    coasting one hidden, for good; farther, both stay as they were. A coasting group that
    is not confirmed, or a new group that is not seen, takes nothing over."""
    from laserpeople.tracking.groups import GroupMHTTracker

    tracker = GroupMHTTracker(GroupTrackerParams())
    tracker.confirmation.confirm(1)
    nodes = [_group(1, 0.0, seen=False), _group(2, x, seen=True)]
    cands = [Candidate(n.family, "", (str(n.family),)) for n in nodes]
    out = tracker._take_over_coasting(nodes, cands)
    assert [c.visible for c in out] == [not taken, True]
    assert tracker.confirmation.is_confirmed(2) is taken
    again = tracker._take_over_coasting(nodes, cands)  # the next scan: still hidden
    assert [c.visible for c in again] == [not taken, True]
    fresh = GroupMHTTracker(GroupTrackerParams())  # group 1 never confirmed
    assert all(c.visible for c in fresh._take_over_coasting(nodes, cands))
    assert not fresh.confirmation.is_confirmed(2)
    unseen = [_group(1, 0.0, seen=False), _group(2, x, seen=False)]
    tracker = GroupMHTTracker(GroupTrackerParams())
    tracker.confirmation.confirm(1)
    assert all(c.visible for c in tracker._take_over_coasting(unseen, cands))
