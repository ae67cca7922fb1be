"""Property-based tests of the point trackers (csa, group-mht, feet-pf, upper-body-pf)
behind the shared point guard: empty frames for many scans, hundreds of points, NaN
points, repeated/backward/jumping stamps, missing sensor poses (issue 16)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from laserpeople.errors import LaserPeopleError
from laserpeople.frame import Frame
from laserpeople.scan import PointSet, Pose2D
from laserpeople.tracking import registry
from laserpeople.tracking.point_guard import GuardedTracker, PointFrameGuard

POINT_TRACKERS = sorted(
    n for n, e in registry.TRACKERS.items() if e.consumes & registry.POINT_FIELDS
)


def _frame(k: int, stamp: float, xy: np.ndarray, pose: bool = True) -> Frame:
    xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
    n = len(xy)
    pts = PointSet(stamp, xy, np.zeros(n, dtype=np.int64), np.arange(n), ("laser",), "world", k)
    return Frame(
        index=k,
        stamp=stamp,
        scans=(),
        topic="laser",
        frame="world",
        sensor_pose=Pose2D(0.0, 0.0, 0.0) if pose else None,
        points=pts,
        foreground=np.ones(n, dtype=bool),
    )


def test_point_trackers_are_guarded() -> None:
    assert {"csa", "group-mht", "feet-pf", "upper-body-pf"} <= set(POINT_TRACKERS)
    for name in POINT_TRACKERS:
        assert isinstance(registry.get(name).make(), GuardedTracker)


coordinate = st.one_of(
    st.floats(-8.0, 8.0), st.sampled_from([math.nan, math.inf, -math.inf, 1e300])
)
step = st.one_of(
    st.just(0.0), st.floats(0.05, 0.15), st.floats(-5.0, -0.01), st.floats(60.0, 600.0)
)
frame_strategy = st.tuples(
    step,
    st.lists(st.tuples(coordinate, coordinate), min_size=0, max_size=40),
    st.booleans(),
)


@pytest.mark.parametrize("name", POINT_TRACKERS)
@settings(
    max_examples=10,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(frames=st.lists(frame_strategy, min_size=1, max_size=15))
def test_hostile_frames_give_finite_tracks_and_counts(
    name: str, frames: list[tuple[float, list[tuple[float, float]], bool]]
) -> None:
    tracker = registry.get(name).make()
    stamp, last = 100.0, None
    backwards = dropped = no_pose = 0
    for k, (dt, points, pose) in enumerate(frames):
        stamp += dt
        xy = np.array(points, dtype=np.float64).reshape(-1, 2)
        dropped += int((~(np.abs(xy) <= 1e6).all(axis=1)).sum())
        no_pose += not pose
        if last is not None:
            backwards += stamp < last
        last = stamp if last is None else max(stamp, last)
        out = tracker.update(_frame(k, stamp, xy, pose))
        assert out.stamp == last  # a backward stamp is tracked at the previous one
        for t in out.tracks:
            assert np.all(np.isfinite(t.position)), (name, t)
    guard: PointFrameGuard = tracker.guard  # type: ignore[attr-defined]
    assert guard.backward_stamps == backwards
    assert guard.dropped_points == dropped
    assert guard.no_pose == no_pose
    if dropped:
        assert "non-finite positions" in guard.summary()


@pytest.mark.parametrize("name", POINT_TRACKERS)
def test_many_empty_frames_then_hundreds_of_points(name: str) -> None:
    tracker = registry.get(name).make()
    for k in range(1000):
        assert len(tracker.update(_frame(k, 0.1 * k, np.empty((0, 2))))) == 0
    rng = np.random.default_rng(1)
    xy = rng.uniform(-6.0, 6.0, size=(300, 2))
    for k in range(1000, 1004):
        out = tracker.update(_frame(k, 0.1 * k, xy + 0.01 * (k - 1000)))
    assert len(out) <= 300


def test_a_nan_stamp_is_an_error_naming_the_scan() -> None:
    tracker = registry.get("feet-pf").make()
    with pytest.raises(LaserPeopleError, match="scan 7"):
        tracker.update(_frame(7, math.nan, np.zeros((1, 2))))
