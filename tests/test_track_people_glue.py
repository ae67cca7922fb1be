"""The leg tracker's glue around the MHT and the person layer's kept arrays: the same
decisions and floats as the arrays they replace (segment widths as numpy's ``hypot``
decides them, measurement covariances, log rates, the input guard's flat checks, the rows
kept), and the sensor frame's person layer without one-leg births or leg paths."""

from __future__ import annotations

import math
import random
import warnings
from dataclasses import replace

import numpy as np
import pytest

from laserpeople.scan import Pose2D
from laserpeople.tracking.guard import MAX_COORDINATE, InputGuard
from laserpeople.tracking.legs import LegLabelModel, LegMHTTracker, LegTrackerParams
from laserpeople.tracking.person_tracks import (
    LegObservation,
    PersonTracker,
    PersonTrackParams,
    segment_holds_two_legs,
    within_width,
)
from laserpeople.tracking.point_model import PointMeasurements
from laserpeople.tracks import Detections

P = PersonTrackParams()


def _hypot_disagreements(n: int = 40_000) -> list[tuple[float, float, float, float]]:
    """(dx, dy, numpy's hypot, Python's) of random differences where the two differ."""
    rng = random.Random(35)
    out = []
    for _ in range(n):
        dx, dy = rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6)
        a, b = float(np.hypot(dx, dy)), math.hypot(dx, dy)
        if a != b:
            out.append((dx, dy, a, b))
    return out


def test_within_width_decides_as_numpy_hypot_at_and_beside_the_bounds() -> None:
    """Bounds equal to numpy's hypot of a difference and the floats either side: every
    decision is numpy's, also where Python's ``math.hypot`` rounds the other way (found on
    this machine in about 1 of 160 random differences)."""
    odd = _hypot_disagreements()
    below = [c for c in odd if c[3] < c[2]]  # Python's below numpy's: at low = numpy's
    above = [c for c in odd if c[3] > c[2]]
    cases = below[:20] + above[:20]
    rng = random.Random(7)
    cases += [
        (dx, dy, float(np.hypot(dx, dy)), 0.0)
        for dx, dy in ((rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6)) for _ in range(200))
    ]
    for dx, dy, w, _ in cases:
        for low in (np.nextafter(w, -1.0), w, np.nextafter(w, 2.0)):
            assert within_width(dx, dy, float(low), 1.0) == (low <= w <= 1.0)
        for high in (np.nextafter(w, -1.0), w, np.nextafter(w, 2.0)):
            assert within_width(dx, dy, 0.0, float(high)) == (0.0 <= w <= high)
        # far from both bounds
        assert within_width(dx, dy, 0.5 * w, 2.0 * w)
        assert not within_width(dx, dy, 2.0 * w, 3.0 * w)
        assert not within_width(dx, dy, 0.1 * w, 0.5 * w)


def test_segment_holds_two_legs_at_a_width_where_python_and_numpy_hypot_differ() -> None:
    odd = _hypot_disagreements()
    if not odd:  # (a C library whose hypot is Python's: nothing to tell apart)
        pytest.skip("numpy's and Python's hypot agree on every difference tried")
    for dx, dy, w, _ in odd[:10]:
        pts = np.array(
            [[0.0, 0.0], [0.3 * dx, 0.3 * dy], [0.5 * dx, 0.5 * dy], [0.7 * dx, 0.7 * dy], [dx, dy]]
        )
        at = replace(P, wide_min_width=w, wide_max_width=1.0)
        over = replace(P, wide_min_width=float(np.nextafter(w, 2.0)), wide_max_width=1.0)
        assert segment_holds_two_legs(pts, 1.0, at)
        assert not segment_holds_two_legs(pts, 1.0, over)
        top = replace(P, wide_min_width=0.01, wide_max_width=w)
        under = replace(P, wide_min_width=0.01, wide_max_width=float(np.nextafter(w, 0.0)))
        assert segment_holds_two_legs(pts, 1.0, top)
        assert not segment_holds_two_legs(pts, 1.0, under)


def test_measurement_covariances_of_pairs_and_single_legs() -> None:
    """std^2 I per person (pair_std 0.1 m, one_leg_std 0.25 m; within 1e-15 m^2), in the
    order asked, beyond the 16 rows kept at first."""
    t = PersonTracker(replace(P, pair_std=0.1, one_leg_std=0.25))
    for stds in ([0.25], [0.1], [0.25, 0.1, 0.25], [0.1] * 3, [0.25] * 40, [0.1, 0.25] * 20):
        want = np.zeros((len(stds), 2, 2))
        want[:, 0, 0] = want[:, 1, 1] = [s**2 for s in stds]  # (as the update wrote them)
        got = t._meas_covs(stds)
        assert got.shape == want.shape
        np.testing.assert_allclose(got, want, rtol=0.0, atol=1e-15)
    assert t._meas_covs([0.25] * 3)[0, 0, 0] == pytest.approx(0.0625, abs=1e-15)
    assert t._meas_covs([0.1])[0, 1, 1] == pytest.approx(0.01, abs=1e-15)


def test_measurement_log_rates_are_the_densities_per_measurement() -> None:
    params = LegTrackerParams(lambda_new=0.002, lambda_fal=0.005)
    labels = LegLabelModel(params)
    for m in (0, 3, 16, 40, 5):
        meas = PointMeasurements(np.zeros((m, 2)), np.tile(np.eye(2), (m, 1, 1)))
        new, fal = labels.measurement_log_rates(meas)
        assert new.shape == fal.shape == (m,)
        np.testing.assert_allclose(new, np.full(m, math.log(0.002)), rtol=0.0, atol=1e-12)
        np.testing.assert_allclose(fal, np.full(m, math.log(0.005)), rtol=0.0, atol=1e-12)
        assert not (new.flags.writeable or fal.flags.writeable)  # (rows kept between scans)


def test_guard_drops_positions_beyond_the_bound_either_way_and_nan_without_warnings() -> None:
    """The largest magnitude decides: a position beyond MAX_COORDINATE on the negative
    side, minus infinity and NaN are dropped (with no floating-point warning); one at the
    bound is kept, and a clean scan is handed on as it is."""
    pos = np.array(
        [
            [1.0, 0.0],
            [-2 * MAX_COORDINATE, 0.0],
            [0.0, -math.inf],
            [math.nan, 1.0],
            [-MAX_COORDINATE, MAX_COORDINATE],
        ]
    )
    cov = np.tile(np.eye(2) * 1e-3, (5, 1, 1))
    guard = InputGuard()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        kept = guard.check(Detections(0.0, 0, pos, cov, np.ones(5)))
    assert guard.dropped_detections == 3
    assert kept.positions.tolist() == [[1.0, 0.0], [-MAX_COORDINATE, MAX_COORDINATE]]
    clean = Detections(0.1, 1, pos[[0, 4]], cov[:2], np.ones(2))
    assert guard.check(clean) is clean  # (nothing to change: the same object)
    assert guard.dropped_detections == 3
    for far in (pos[[0, 1]], pos[[0, 2]]):  # each alone: far or infinite on the negative side
        assert len(guard.check(Detections(0.2, 2, far, cov[:2], np.ones(2)))) == 1
    assert guard.dropped_detections == 5


def _dets(stamp: float, k: int, xy: np.ndarray, pose: Pose2D | None = None) -> Detections:
    return Detections(
        stamp, k, xy, np.tile(np.eye(2) * 1e-3, (len(xy), 1, 1)), np.ones(len(xy)), sensor_pose=pose
    )


def test_kept_rows_name_every_detection_beyond_the_rows_kept_at_first() -> None:
    tracker = LegMHTTracker(LegTrackerParams(people_policy="tracks"))
    xy = np.column_stack([np.arange(40) * 1.0, np.zeros(40)])
    tracker.update(_dets(0.0, 0, xy))
    assert tracker._kept.tolist() == list(range(40))
    tracker.update(_dets(0.1, 1, xy[:3]))
    assert tracker._kept.tolist() == [0, 1, 2]


def _one_leg(x: float) -> dict[int, LegObservation]:
    return {7: LegObservation(7, np.array([x, 0.0]), True, 0.0, 0, False, score=0.8)}


def test_sensor_frame_person_layer_has_no_one_leg_births_nor_leg_paths() -> None:
    """In the sensor frame the lasers never count as moving: a walking single leg gives
    no person even with ``moving`` set, and no leg paths are kept; in the world frame the
    same leg is confirmed (from its third scan: young_credit)."""
    world, sensor = PersonTracker(P), PersonTracker(P)
    sensor.world_frame = False
    for t in (world, sensor):
        t.moving = True
    out_w, out_s = [], []
    for k in range(10):
        out_w.append(len(world.update(_one_leg(0.1 * k), 0.1 * k, 1.0)))
        out_s.append(len(sensor.update(_one_leg(0.1 * k), 0.1 * k, 1.0)))
    assert out_w.index(1) == 2 and out_s == [0] * 10
    assert world._leg_paths and not sensor._leg_paths and not sensor._leg_first
    assert not sensor.persons  # (not even a candidate born from the one leg)


def test_leg_tracker_tells_its_person_layer_the_tracking_frame() -> None:
    xy = np.array([[1.0, 0.0], [1.0, 0.3]])
    sensor = LegMHTTracker(LegTrackerParams(people_policy="tracks"))
    sensor.update(_dets(0.0, 0, xy))
    world = LegMHTTracker(LegTrackerParams(people_policy="tracks"))
    world.update(_dets(0.0, 0, xy, Pose2D(0.0, 0.0, 0.0)))
    assert sensor.person_tracks is not None and not sensor.person_tracks.world_frame
    assert world.person_tracks is not None and world.person_tracks.world_frame
