"""The group tracker's bookkeeping is bounded by the tracks alive, not by the length of the
run (issue 12, docs/groups.md "Speed and memory"): a scene of episodes in
which a group arrives, splits, merges again and leaves is tracked for twice as many
episodes, and what the tracker keeps from scan to scan stays below the same bound."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.frame import Frame
from laserpeople.scan import PointSet
from laserpeople.tracking.groups import GroupMHTTracker, GroupTrackerParams
from laserpeople.tracking.groups import tracker as tracker_module
from laserpeople.tracking.groups.confirm import Candidate, Confirmation, ConfirmSettings

EPISODE = 110
"""Frames of one episode (0.1 s each): 70 of the scripted split and merge, 40 empty."""
BOOKKEEPING = (
    "reported",
    "roots",
    "shown",
    "formatted",
    "event_at",
    "walked_at",
    "reported_ids",
    "anchors",
    "merged_labels",
    "confirmed",
    "seen",
    "reported_roots",
)
"""Sizes of :meth:`GroupMHTTracker.state_counts` that would grow with the run if nothing forgot
(or could, as ``walked_at`` with a static world model, and ``reported_ids``)."""
BOUND = 24
"""Most entries any of them may hold: one episode makes some 10 families and labels."""


def _legs(x: float, y: float) -> np.ndarray:
    """Four points of a person's two legs at (x, y) [m]."""
    return np.array([[x - 0.15, y], [x - 0.1, y], [x + 0.1, y], [x + 0.15, y]])


def _people_at(k: int) -> list[tuple[float, float]]:
    """Three people stand together; two walk 1.8 m away and come back (a split and a
    merge), then all are gone until the next episode (their tracks die)."""
    t = k % EPISODE
    if t >= 70:
        return []
    y = 0.12 * min(max(t - 10, 0), 15, max(40 - t, 0)) if t < 40 else 0.0
    return [(3.0, 0.0), (3.8, y), (4.6, y)]


class _Static:
    """A static world model: everything west of x = 5 m has stood for 100 s."""

    def static_time(self, positions: np.ndarray) -> np.ndarray:
        return np.where(positions[:, 0] < 5.0, 100.0, 0.0)


def _track(episodes: int, static: bool) -> tuple[GroupMHTTracker, dict[str, int]]:
    """Track ``episodes`` episodes; the tracker and the largest size of each kept
    structure over the run."""
    tracker = GroupMHTTracker(GroupTrackerParams(static_time=1.0, cluster_distance=1.3))
    if static:
        tracker.use_static_model(_Static())  # type: ignore[arg-type]
    largest: dict[str, int] = {}
    for k in range(episodes * EPISODE):
        people = _people_at(k)
        pts = np.concatenate([_legs(x, y) for x, y in people]) if people else np.empty((0, 2))
        n = len(pts)
        ps = PointSet(
            0.1 * k, pts, np.zeros(n, dtype=np.int64), np.arange(n), frame="world", index=k
        )
        frame = Frame(index=k, stamp=0.1 * k, scans=(), topic="sim", frame="world", points=ps,
                      foreground=np.ones(n, dtype=bool))  # fmt: skip
        tracker.update(frame)
        for key, size in tracker.state_counts().items():
            largest[key] = max(largest.get(key, 0), size)
    return tracker, largest


@pytest.mark.parametrize("static", [False, True], ids=["plain", "static-model"])
def test_bookkeeping_does_not_grow_with_the_length_of_the_run(static: bool) -> None:
    short, short_sizes = _track(6, static)
    long, long_sizes = _track(12, static)
    # the scene makes new families, labels, splits and merges in every episode ...
    assert long.mht.tree.families_created >= 1.8 * short.mht.tree.families_created
    assert long.event_counts["split"] >= 12 and long.event_counts["merge"] >= 12
    assert long.event_counts["split"] >= 1.8 * short.event_counts["split"]
    if static:
        assert long.static_groups_hidden > 0 and long_sizes["walked_at"] > 0
    # ... yet what is kept of them stays as large as in a run half as long
    for key in BOOKKEEPING:
        assert long_sizes[key] <= BOUND, key
        assert long_sizes[key] <= short_sizes[key] + 2, key


def test_events_keep_the_latest_and_count_all(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(tracker_module, "EVENTS_KEPT", 3)
    tracker, _ = _track(8, static=False)
    total = tracker.event_counts["split"] + tracker.event_counts["merge"]
    assert total >= 16
    assert 3 <= len(tracker.events) <= 6
    stamps = [e.stamp for e in tracker.events]
    assert stamps == sorted(stamps) and stamps[-1] > 0.1 * 7 * EPISODE  # the latest


def test_confirmation_forgets_families_and_roots_no_track_carries() -> None:
    confirm = Confirmation(ConfirmSettings(scans=1, window=2, event_scans=1))
    assert confirm.select(0, [Candidate(5, "", ("5",)), Candidate(7, "", ("7",))]) == [True] * 2
    assert confirm.sizes()["confirmed"] == 2 and confirm.sizes()["reported_roots"] == 2
    confirm.prune([7], {"7"})
    assert confirm.sizes()["confirmed"] == 1 and confirm.sizes()["reported_roots"] == 1
    # a live family stays confirmed, and a split of its reported group is still known
    assert confirm.select(1, [Candidate(7, "", ("7",)), Candidate(9, "split", ("7-0",))]) == [
        True,
        True,
    ]
