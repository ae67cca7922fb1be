from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from laserpeople.errors import PoseUnavailableError, ScanFormatError
from laserpeople.scan import PointSet, Pose2D, Scan, wrap_angle


def test_wrap_angle_interval() -> None:
    a = wrap_angle(np.array([np.pi, -np.pi, 3 * np.pi, 0.5, -0.5 - 2 * np.pi]))
    np.testing.assert_allclose(a, [np.pi, np.pi, np.pi, 0.5, -0.5])


def test_angles_as_ros_computes_them() -> None:
    scan = Scan(0.0, -1.0, 0.5, np.ones(5))
    np.testing.assert_allclose(scan.angles, [-1.0, -0.5, 0.0, 0.5, 1.0])
    assert scan.angle_max == pytest.approx(1.0)


def test_negative_increment_mirrors_the_beams() -> None:
    # MiR: angle_min +135 deg, increment negative -> beam 0 on the left, last on the right.
    inc = -math.radians(0.5)
    scan = Scan(0.0, math.radians(135), inc, np.full(541, 2.0))
    assert scan.angles[0] == pytest.approx(math.radians(135))
    assert scan.angles[-1] == pytest.approx(math.radians(-135))
    pts = scan.points()
    assert pts[0, 1] > 0 > pts[-1, 1]
    np.testing.assert_allclose(np.hypot(pts[:, 0], pts[:, 1]), 2.0)


def test_invalid_beams_are_nan_and_masked() -> None:
    ranges = np.array([1.0, np.nan, np.inf, 0.0, 0.05, 30.0, 2.0])
    scan = Scan(0.0, 0.0, 0.1, ranges, range_min=0.1, range_max=20.0)
    with warnings.catch_warnings():  # (NaN and inf ranges: no floating-point warning)
        warnings.simplefilter("error")
        valid = scan.valid
    assert valid.tolist() == [True, False, False, False, False, False, True]  # (a mask)
    assert scan.n_invalid == 5
    assert np.isnan(scan.points()[1:6]).all()
    pts, idx = scan.valid_points()
    np.testing.assert_array_equal(idx, [0, 6])
    np.testing.assert_allclose(pts[1], [2 * math.cos(0.6), 2 * math.sin(0.6)])


def test_world_frame_uses_pose() -> None:
    scan = Scan(0.0, 0.0, 0.1, np.array([1.0]), pose=Pose2D(1.0, 2.0, math.pi / 2))
    np.testing.assert_allclose(scan.points("world"), [[1.0, 3.0]], atol=1e-12)
    with pytest.raises(PoseUnavailableError):
        Scan(0.0, 0.0, 0.1, np.array([1.0])).points("world")


def test_transform_points_hand_computed_few_and_many() -> None:
    """A pose maps points by rotation then translation, whether it adds the translation
    broadcast (a few points) or column by column (a scan's many points): hand-computed
    values at a quarter turn, and the same sums either way (to 1e-12 m: a vectorised add
    may round differently on another CPU)."""
    pose = Pose2D(1.0, 2.0, math.pi / 2)
    few = np.array([[1.0, 0.0], [0.0, 1.0], [2.0, -1.0]])
    want = np.array([[1.0, 3.0], [0.0, 2.0], [2.0, 4.0]])  # (x, y) -> (1 - y, 2 + x)
    np.testing.assert_allclose(pose.transform_points(few), want, atol=1e-12)
    many = np.tile(few, (50, 1))  # beyond the few-points path
    np.testing.assert_allclose(pose.transform_points(many), np.tile(want, (50, 1)), atol=1e-12)
    rng = np.random.default_rng(3)
    for _ in range(20):
        pose = Pose2D(*rng.normal(scale=10.0, size=2), rng.uniform(-math.pi, math.pi))
        pts = rng.normal(scale=15.0, size=(int(rng.integers(1, 1200)), 2))
        broadcast = pts @ pose.rotation().T + np.array([pose.x, pose.y])
        np.testing.assert_allclose(pose.transform_points(pts), broadcast, rtol=0, atol=1e-12)
    one = pose.transform_points(np.array([1.0, 0.0]))  # one point as a (2,) row
    np.testing.assert_allclose(
        one, pose.transform_points(np.array([[1.0, 0.0]]))[0], rtol=0, atol=1e-12
    )


def test_pose_compose_and_inverse_are_consistent() -> None:
    a, b = Pose2D(1.0, -2.0, 0.7), Pose2D(-0.3, 0.4, -2.0)
    p = np.array([[0.5, 0.25]])
    np.testing.assert_allclose(
        a.compose(b).transform_points(p), a.transform_points(b.transform_points(p))
    )
    ident = a.compose(a.inverse())
    assert (ident.x, ident.y, ident.theta) == pytest.approx((0.0, 0.0, 0.0), abs=1e-12)
    np.testing.assert_allclose(a.inverse_transform_points(a.transform_points(p)), p)


def test_beam_count_must_match_header() -> None:
    Scan.from_angles(0.0, -1.0, 1.0, 0.5, np.ones(5))
    with pytest.raises(ScanFormatError, match="imply"):
        Scan.from_angles(0.0, -1.0, 1.0, 0.5, np.ones(9), source="x.bag", index=3)


def test_bad_header_names_file_and_scan() -> None:
    with pytest.raises(ScanFormatError) as info:
        Scan(0.0, 0.0, 0.0, np.ones(3), source="rec.bag", index=7)
    assert "rec.bag" in str(info.value) and "scan 7" in str(info.value)
    with pytest.raises(ScanFormatError, match="intensities"):
        Scan(0.0, 0.0, 0.1, np.ones(3), intensities=np.ones(2))


def test_pointset_merges_valid_points_of_scans() -> None:
    s1 = Scan(1.0, 0.0, 0.1, np.array([1.0, np.nan]), sensor="front", pose=Pose2D())
    s2 = Scan(1.1, 0.0, 0.1, np.array([2.0, 3.0]), sensor="rear", pose=Pose2D(0, 0, math.pi))
    ps = PointSet.from_scans([s1, s2])
    assert len(ps) == 3
    np.testing.assert_array_equal(ps.sensor_ids, [0, 1, 1])
    np.testing.assert_allclose(ps.points[1], [-2.0, 0.0], atol=1e-12)
    assert ps.stamp == 1.1
