"""Groups on static places are not reported (``group_tracker.static_groups`` false), and
walls are not grouped (``group_tracker.max_blob_size``)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np
import pytest

from laserpeople.clustering import single_linkage
from laserpeople.frame import Frame
from laserpeople.scan import PointSet
from laserpeople.tracking.groups import GroupMHTTracker, GroupTrackerParams
from laserpeople.tracking.groups.observations import GroupObservations, within_size
from laserpeople.tracking.mht.core import MHTParams
from laserpeople.tracks import Tracks

OBJECT = np.array([5.0, 0.0])
DT = 0.1
EVERY_SCAN = GroupTrackerParams(confirm_scans=1, cluster_distance=1.3)
"""Every group reported from its first scan in the best hypothesis (000), so that the
tests here see the static-place rule alone (confirmation: test_track_groups_confirm.py);
at 000's d_P (1.3 m), which the walkers' lanes are laid out for."""


def _blob(centre: np.ndarray) -> np.ndarray:
    """Two leg-like arcs 0.3 m apart around ``centre`` (8 points)."""
    ang = np.linspace(-1.0, 1.0, 4)
    return np.concatenate(
        [
            np.column_stack([centre[0] + dx + 0.06 * np.sin(ang), centre[1] - 0.06 * np.cos(ang)])
            for dx in (-0.15, 0.15)
        ]
    )


def _frame(points: np.ndarray, index: int) -> Frame:
    n = len(points)
    stamp = index * DT
    ps = PointSet(
        stamp, points, np.zeros(n, dtype=np.int64), np.arange(n), frame="world", index=index
    )
    return Frame(
        index=index,
        stamp=stamp,
        scans=(),
        topic="sim",
        frame="world",
        points=ps,
        foreground=np.ones(n, dtype=bool),
    )


class PlaceModel:
    """A static world model whose answer is ``seconds(position, now)`` per position."""

    def __init__(self, seconds: Callable[[np.ndarray, float], np.ndarray]) -> None:
        self.seconds = seconds
        self.now = 0.0
        self.asked = 0

    def static_time(self, positions: np.ndarray) -> np.ndarray:
        self.asked += len(positions)
        return self.seconds(np.asarray(positions).reshape(-1, 2), self.now)


def _near_object(pos: np.ndarray, _now: float) -> np.ndarray:
    """Places within 0.5 m of the object: static for 1000 s; elsewhere 0."""
    return np.where(np.linalg.norm(pos - OBJECT, axis=1) < 0.5, 1000.0, 0.0)


def _track(
    centres_at: Callable[[int], list[np.ndarray]],
    steps: int,
    model: PlaceModel | None,
    params: GroupTrackerParams | None = None,
) -> tuple[GroupMHTTracker, list[Tracks]]:
    tracker = GroupMHTTracker(params if params is not None else EVERY_SCAN)
    if model is not None:
        assert tracker.wants_static_model
        tracker.use_static_model(model)  # type: ignore[arg-type]
    out = []
    for k in range(steps):
        if model is not None:
            model.now = k * DT
        pts = np.concatenate([_blob(c) for c in centres_at(k)])
        out.append(tracker.update(_frame(pts, k)))
    return tracker, out


def _reported_near(tracks: Tracks, place: np.ndarray, radius: float = 0.6) -> int:
    return sum(float(np.linalg.norm(t.position - place)) < radius for t in tracks.of_kind("group"))


def _holds(tracks: Tracks, place: np.ndarray, radius: float = 0.3) -> bool:
    """Whether a reported group's contour has a point within ``radius`` of ``place``."""
    return any(
        t.contour is not None and bool((np.linalg.norm(t.contour - place, axis=1) < radius).any())
        for t in tracks.of_kind("group")
    )


def test_a_group_on_a_static_place_is_not_reported() -> None:
    # 000's behaviour (static_groups = true): the object is a group from the second scan on
    params = GroupTrackerParams(static_groups=True, confirm_scans=1)
    assert not GroupMHTTracker(params).wants_static_model
    _, out = _track(lambda k: [OBJECT], 30, None, params)
    assert [len(t.of_kind("group")) for t in out] == [0] + [1] * 29
    model = PlaceModel(_near_object)
    tracker, out = _track(lambda k: [OBJECT], 30, model)
    assert all(len(t.of_kind("group")) == 0 for t in out)
    assert tracker.static_groups_hidden == 29
    assert model.asked > 0


def test_a_group_that_walked_in_and_stands_stays_reported() -> None:
    """A person walks 3 m and stands for 20 s; the place it stands on becomes static from
    the moment it stopped (as an occupancy grid sees it), so it is never static for longer
    than the person has stood there."""
    stop = 30  # frames of walking at 1 m/s

    def centre(k: int) -> list[np.ndarray]:
        return [np.array([0.1 * min(k, stop), 0.0])]

    def since_stop(pos: np.ndarray, now: float) -> np.ndarray:
        near = np.linalg.norm(pos - [3.0, 0.0], axis=1) < 0.5
        return np.where(near, max(0.0, now - stop * DT), 0.0)

    tracker, out = _track(centre, stop + 200, PlaceModel(since_stop))
    assert tracker.static_groups_hidden == 0
    assert all(len(t.of_kind("group")) == 1 for t in out[1:])


def test_a_group_that_never_walked_is_hidden_once_its_place_is_static_for_long() -> None:
    """A person standing since before the recording began: not reported once its place has
    been static for longer than static_time (10 s), as the person layer does."""

    def since_start(pos: np.ndarray, now: float) -> np.ndarray:
        return np.full(len(pos), now)

    tracker, out = _track(lambda k: [np.array([2.0, 1.0])], 150, PlaceModel(since_start))
    shown = [len(t.of_kind("group")) for t in out]
    assert shown[1:95] == [1] * 94  # static for up to 9.4 s: still reported
    assert shown[105:] == [0] * 45
    assert tracker.static_groups_hidden == sum(1 for s in shown[1:] if s == 0)


@pytest.mark.parametrize("lane", [0.8, 1.1])
@pytest.mark.parametrize("model_prior", ["choice", "normalised"])
def test_an_object_a_walker_passes_is_hidden_again(lane: float, model_prior: str) -> None:
    """A person walks past the object within d_P (the two are one observation and may
    merge, then split): the walker is in a reported group all along; the object is hidden
    before the walker comes, and again by static_time (10 s) after the walker's last walk
    as a group of its own (the half of a split holding the object may be reported until
    then, since it comes from a group someone walked in). With eq. 32 as ``"choice"``,
    N-scan 8 and the Kalman velocity in eqs. 25-27 (``velocity_window`` 0) the two merge
    while close; with the default (normalised, N-scan 3) the walker passes without merging
    and the object is never reported."""
    model = PlaceModel(_near_object)

    def centres(k: int) -> list[np.ndarray]:
        return [OBJECT, np.array([0.1 * k, lane])]

    params = EVERY_SCAN
    if model_prior == "choice":
        params = replace(params, model_prior="choice", mht=MHTParams(n_scan=8), velocity_window=0.0)
    tracker, out = _track(centres, 200, model, params)
    for k, tracks in enumerate(out[2:], start=2):
        assert _holds(tracks, np.array([0.1 * k, lane])), k
    near = [k for k, tracks in enumerate(out) if _holds(tracks, OBJECT, 0.2)]
    walker_near = [k for k in range(200) if abs(0.1 * k - OBJECT[0]) <= 2.0]
    assert tracker.static_groups_hidden > 0
    if model_prior == "normalised":
        assert near == []
        return
    assert near  # the walker and the object are reported as one group while close
    assert min(near) >= min(walker_near)  # never before the walker came
    assert max(near) <= max(walker_near) + 110  # hidden again at most 11 s after
    assert not any(_holds(t, OBJECT, 0.2) for t in out[-20:])
    assert tracker.static_groups_hidden > 0


def test_static_group_parameters_are_checked() -> None:
    with pytest.raises(ValueError, match="static_share"):
        GroupTrackerParams(static_share=0.0)
    with pytest.raises(ValueError, match="must not be negative"):
        GroupTrackerParams(arrival_slack=-1.0)


# ------------------------------------------------------------------ walls (max_blob_size)


def test_within_size_by_hand() -> None:
    wall = np.column_stack([np.arange(0.0, 3.0, 0.1), np.full(30, 2.0)])  # 2.9 m, one blob
    person = _blob(np.array([0.0, 0.0]))  # 0.42 m across
    far = np.array([[10.0, 10.0]])  # a blob of one point spans 0 m
    pts = np.vstack([person, wall, far])
    blobs = single_linkage(pts, 0.3)
    keep = within_size(pts, blobs, 2.0)
    np.testing.assert_array_equal(keep, [True] * len(person) + [False] * 30 + [True])
    assert within_size(pts, blobs, 3.0).all()  # 2.9 m is within 3 m
    assert within_size(np.empty((0, 2)), np.empty(0, dtype=np.int64), 2.0).shape == (0,)
    obs = GroupObservations.from_points(pts, np.arange(len(pts)), 1.3, 0.3, None, 2.0)
    assert len(obs.points) == len(person) + 1 and len(obs) == 2  # the wall left out
    assert len(GroupObservations.from_points(wall, np.arange(30), 1.3, 0.3, None, 2.0)) == 0


def test_a_wall_in_the_foreground_is_not_a_group() -> None:
    wall = np.column_stack([np.linspace(-2.0, 2.0, 60), np.full(60, 3.0)])

    def run(params: GroupTrackerParams) -> tuple[GroupMHTTracker, list[Tracks]]:
        tracker = GroupMHTTracker(params)
        out = []
        for k in range(20):
            person = _blob(np.array([0.1 * k, 2.2]))  # walks along the wall, 0.8 m off it
            out.append(tracker.update(_frame(np.vstack([wall, person]), k)))
        return tracker, out

    tracker, out = run(GroupTrackerParams(static_groups=True, confirm_scans=1))
    assert tracker.wide_points_left_out == 20 * len(wall)
    for k, tracks in enumerate(out[1:], start=1):
        (group,) = tracks.of_kind("group")  # the person alone, not joined to the wall
        assert group.contour is not None and len(group.contour) == 8
        assert np.linalg.norm(group.position - [0.1 * k, 2.2]) < 0.15
    tracker, out = run(GroupTrackerParams(static_groups=True, max_blob_size=0.0, confirm_scans=1))
    assert tracker.wide_points_left_out == 0  # 0 keeps every point: person and wall are one
    assert all(len(t.of_kind("group")[0].contour) == 68 for t in out[1:])  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="max_blob_size"):
        GroupTrackerParams(max_blob_size=-1.0)


def test_walk_times_are_forgotten_for_groups_long_gone() -> None:
    from laserpeople.tracking.groups.tracker import _stems

    assert _stems("3-0-1") == ["3-0-1", "3-0", "3"]
    model = PlaceModel(_near_object)
    tracker, _ = _track(lambda k: [np.array([0.1 * k, 2.0])], 12, model)  # a walker
    assert tracker._walked_at  # it walked
    kept = dict(tracker._walked_at)
    tracker._walked_at.update({f"{9000 + i}": 1.0 for i in range(100)})  # gone long ago
    tracker.update(_frame(_blob(np.array([1.2, 2.0])), 12))
    tracker.forget_gone(12)  # every FORGET_EVERY scans
    assert tracker._walked_at == kept  # only the walker's labels are left
