"""Property-based tests of every tracker's ``update`` with hostile detections."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from laserpeople.errors import LaserPeopleError
from laserpeople.tracking import registry
from laserpeople.tracking.guard import JUMP, MAX_COORDINATE, InputGuard
from laserpeople.tracks import Detections

# the trackers fed by leg detections (the adapter's inner tracker takes them directly)
TRACKERS = sorted(n for n, e in registry.TRACKERS.items() if e.consumes == frozenset({"legs"}))


def _dets(stamp: float, k: int, xy: np.ndarray) -> Detections:
    m = xy.shape[0]
    return Detections(stamp, k, xy, np.tile(np.eye(2) * 0.01, (m, 1, 1)), np.ones(m))


coordinate = st.one_of(
    st.floats(-20.0, 20.0),
    st.sampled_from([math.nan, math.inf, -math.inf, 1e300]),
)
scan_strategy = st.lists(st.tuples(coordinate, coordinate), min_size=0, max_size=25)
step_strategy = st.one_of(
    st.just(0.0),  # repeated stamp
    st.floats(0.05, 0.15),
    st.floats(-5.0, -0.01),  # backwards
    st.floats(60.0, 600.0),  # a jump of minutes
)


@pytest.mark.parametrize("name", TRACKERS)
@settings(
    max_examples=15,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(
    scans=st.lists(st.tuples(step_strategy, scan_strategy), min_size=1, max_size=30),
    duplicate=st.booleans(),
)
def test_hostile_scans_give_finite_bounded_tracks(
    name: str, scans: list[tuple[float, list[tuple[float, float]]]], duplicate: bool
) -> None:
    entry = registry.get(name)
    tracker = entry.make().tracker  # type: ignore[attr-defined]
    stamp = 100.0
    seen_finite = 0
    backwards = 0
    last = None
    for k, (step, points) in enumerate(scans):
        stamp += step
        xy = np.array(points, dtype=np.float64).reshape(-1, 2)
        if duplicate and len(xy):
            xy = np.vstack([xy, xy])  # every detection twice
        seen_finite += int((np.abs(xy) <= MAX_COORDINATE).all(axis=1).sum())
        if last is not None:
            backwards += stamp < last
        last = max(stamp, last) if last is not None else stamp
        out = tracker.update(_dets(stamp, k, xy))
        for t in out.tracks:
            assert np.all(np.isfinite(t.position)), (name, t)
            assert np.all(np.isfinite(t.covariance))
        legs = [t for t in out.tracks if t.kind == "leg"]
        assert len(legs) <= seen_finite  # no track without a detection behind it
        assert out.stamp == last  # a backward stamp is tracked at the previous one
    guard: InputGuard = tracker.guard  # type: ignore[attr-defined]
    assert guard.backward_stamps == backwards
    dropped = sum(
        int(
            (~(np.abs(np.array(p, dtype=float).reshape(-1, 2)) <= MAX_COORDINATE).all(axis=1)).sum()
        )
        * (2 if duplicate else 1)
        for _, p in scans
    )
    assert guard.dropped_detections == dropped
    assert tracker.dropped_detections == dropped  # type: ignore[attr-defined]


@pytest.mark.parametrize("name", TRACKERS)
def test_thousands_of_empty_scans_then_people(name: str) -> None:
    entry = registry.get(name)
    tracker = entry.make().tracker  # type: ignore[attr-defined]
    for k in range(3000):
        out = tracker.update(_dets(0.1 * k, k, np.empty((0, 2))))
        assert len(out) == 0
    for k in range(3000, 3030):
        out = tracker.update(_dets(0.1 * k, k, np.array([[1.0, 0.1 * (k - 3000)], [1.3, 0.0]])))
    assert 0 < len(out.of_kind("leg")) <= 2


@pytest.mark.parametrize("name", TRACKERS)
def test_many_detections_in_one_scan(name: str) -> None:
    entry = registry.get(name)
    tracker = entry.make().tracker  # type: ignore[attr-defined]
    rng = np.random.default_rng(0)
    xy = rng.uniform(-10, 10, size=(120, 2))
    for k in range(3):
        out = tracker.update(_dets(0.1 * k, k, xy + 0.01 * k))
    assert len(out.of_kind("leg")) <= 120


def test_guard_counts_and_clamps() -> None:
    guard = InputGuard()
    a = guard.check(_dets(10.0, 0, np.array([[1.0, 2.0], [math.nan, 0.0]])))
    assert len(a) == 1 and guard.dropped_detections == 1
    b = guard.check(_dets(9.0, 1, np.zeros((0, 2))))
    assert b.stamp == 10.0 and guard.backward_stamps == 1
    guard.check(_dets(10.0, 2, np.zeros((0, 2))))
    assert guard.repeated_stamps == 1
    guard.check(_dets(10.0 + 2 * JUMP, 3, np.zeros((0, 2))))
    assert guard.stamp_jumps == 1
    assert "stamped before" in guard.summary() and "jumps in time" in guard.summary()
    assert "first: scan 1" in guard.summary()
    with pytest.raises(LaserPeopleError, match="scan 4"):
        guard.check(_dets(math.nan, 4, np.zeros((0, 2))))


def test_guard_says_the_first_backward_scan_and_the_largest_step_back() -> None:
    guard = InputGuard()
    for k, stamp in enumerate([5.0, 4.75, 5.5, 5.0, 4.5, 6.0]):
        guard.check(_dets(stamp, 10 + k, np.zeros((0, 2))))
    # 4.75 is 0.25 s before 5.0; 5.0 is 0.5 s and 4.5 1.0 s before the clamped 5.5
    assert guard.backward_stamps == 3 and guard.first_backward == 11
    assert math.isclose(guard.largest_backward, 1.0, abs_tol=1e-12)
    assert "by up to 1 s (first: scan 11;" in guard.summary()


def test_guard_drops_non_finite_and_far_detections_without_warnings() -> None:
    """NaN, infinite and far positions and NaN covariances are dropped and counted, with
    no floating-point warning (numpy's comparisons raise none on NaN)."""
    pos = np.array(
        [[1.0, 2.0], [math.nan, 0.0], [0.0, math.inf], [2 * MAX_COORDINATE, 0.0], [3.0, -1.0]]
    )
    dets = _dets(1.0, 0, pos)
    cov = dets.covariances.copy()
    cov[4, 1, 1] = math.nan
    dets = Detections(1.0, 0, pos, cov, dets.scores)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        kept = InputGuard().check(dets)
    np.testing.assert_allclose(kept.positions, [[1.0, 2.0]], atol=1e-12)  # the clean one
