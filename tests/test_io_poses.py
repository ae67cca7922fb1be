"""Planar poses from quaternions, pose interpolation and transform chains (hand-computed)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.errors import ConfigError
from laserpeople.io.poses import (
    PoseParams,
    PoseTrack,
    TransformTree,
    parse_mounts,
    yaw_and_tilt,
)
from laserpeople.scan import Pose2D


def _quat_yaw(yaw: float) -> tuple[float, float, float, float]:
    return 0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)


def test_yaw_of_a_pure_yaw_quaternion() -> None:
    yaw, tilt = yaw_and_tilt(*_quat_yaw(0.5))
    assert yaw == pytest.approx(0.5)
    assert tilt == pytest.approx(0.0, abs=1e-12)


def test_yaw_wraps_and_tolerates_unnormalised_quaternions() -> None:
    x, y, z, w = _quat_yaw(3.5)  # 3.5 rad wraps to 3.5 - 2 pi
    yaw, _ = yaw_and_tilt(2 * x, 2 * y, 2 * z, 2 * w)
    assert yaw == pytest.approx(3.5 - 2 * math.pi)


def test_upside_down_quaternion_reports_full_tilt() -> None:
    # roll = pi about x: q = (1, 0, 0, 0); the z axis points down
    _, tilt = yaw_and_tilt(1.0, 0.0, 0.0, 0.0)
    assert tilt == pytest.approx(math.pi)


def test_interpolation_is_linear_in_xy_and_on_the_circle_in_theta() -> None:
    track = PoseTrack(np.array([0.0, 1.0]), np.array([[0.0, 0.0, 3.0], [2.0, 4.0, -3.0]]))
    pose = track.at(0.25, tolerance=0.0, max_gap=2.0)
    assert pose is not None
    assert pose.x == pytest.approx(0.5)
    assert pose.y == pytest.approx(1.0)
    # 3.0 -> -3.0 the short way is +0.2832 rad across pi; a quarter of it from 3.0
    assert pose.theta == pytest.approx(3.0 + 0.25 * (2 * math.pi - 6.0))


def test_interpolation_sorts_unsorted_samples() -> None:
    track = PoseTrack(np.array([1.0, 0.0]), np.array([[2.0, 0.0, 0.0], [0.0, 0.0, 0.0]]))
    pose = track.at(0.5, tolerance=0.0, max_gap=2.0)
    assert pose is not None and pose.x == pytest.approx(1.0)


def test_no_extrapolation_beyond_tolerance_and_no_bridging_of_gaps() -> None:
    track = PoseTrack(np.array([0.0, 1.0, 3.0]), np.array([[0, 0, 0], [1, 0, 0], [3, 0, 0.0]]))
    assert track.at(-0.04, tolerance=0.05, max_gap=1.5) == Pose2D(0, 0, 0)  # held, not moved
    assert track.at(-0.06, tolerance=0.05, max_gap=1.5) is None
    assert track.at(3.04, tolerance=0.05, max_gap=1.5) == Pose2D(3, 0, 0)
    assert track.at(3.06, tolerance=0.05, max_gap=1.5) is None
    assert track.at(2.0, tolerance=0.05, max_gap=1.5) is None  # 2 s gap > 1.5 s
    exact = track.at(1.0, tolerance=0.0, max_gap=1.5)
    assert exact is not None and exact.x == pytest.approx(1.0)


def _tree() -> TransformTree:
    tree = TransformTree(PoseParams(tolerance=0.0, max_gap=1.0))
    tree.add_track(
        "odom",
        "base_link",
        np.array([0.0, 1.0]),
        np.array([[0.0, 0.0, 0.0], [2.0, 0.0, math.pi / 2]]),
    )
    tree.add_static("/base_link", "laser", Pose2D(0.5, 0.0, math.pi))
    return tree


def test_chain_composition_matches_hand_computation() -> None:
    tree = _tree()
    pose, reason = tree.lookup("odom", "laser", 1.0)
    # base at (2, 0) heading +90 deg; laser 0.5 m ahead of base -> (2, 0.5), heading 270 deg
    assert reason == ""
    assert pose is not None
    assert (pose.x, pose.y) == pytest.approx((2.0, 0.5))
    assert pose.theta == pytest.approx(-math.pi / 2)
    mid, _ = tree.lookup("odom", "/laser", 0.5)
    # base at (1, 0) heading 45 deg
    assert mid is not None
    assert (mid.x, mid.y) == pytest.approx((1 + 0.5 / math.sqrt(2), 0.5 / math.sqrt(2)))


def test_lookup_explains_missing_poses() -> None:
    tree = _tree()
    pose, reason = tree.lookup("odom", "front_laser", 0.5)
    assert pose is None and "no transform chain" in reason and "front_laser" in reason
    pose, reason = tree.lookup("odom", "laser", 5.0)
    assert pose is None and "not covered" in reason
    tree.add_static("base_link", "flipped", Pose2D(), tilt=math.pi)
    pose, reason = tree.lookup("odom", "flipped", 0.5)
    assert pose is None and "tilted by 180 deg" in reason


def test_world_frame_prefers_map_then_odom_then_common_root() -> None:
    tree = _tree()
    assert tree.pick_world(["laser"]) == "odom"
    tree.add_static("map", "odom", Pose2D(1.0, 0.0, 0.0))
    assert tree.pick_world(["laser"]) == "map"
    other = TransformTree()
    other.add_static("world", "laser", Pose2D())
    assert other.pick_world(["laser"]) == "world"


def test_first_parent_wins_and_conflicts_are_recorded() -> None:
    tree = _tree()
    tree.add_static("map", "laser", Pose2D())
    assert tree.chain("odom", "laser") == ["laser", "base_link", "odom"]
    assert len(tree.conflicts) == 1 and "'laser'" in tree.conflicts[0]


def test_parse_mounts() -> None:
    mounts = parse_mounts(["front=/base_footprint:0.4,0.2,0.785"])
    assert mounts == {"front": ("base_footprint", Pose2D(0.4, 0.2, 0.785))}
    with pytest.raises(ConfigError, match="CHILD=PARENT"):
        parse_mounts(["front:0.4,0.2"])
    with pytest.raises(ConfigError):
        parse_mounts(["front=base:1,2"])


def test_known_robot_mounts_by_name() -> None:
    from laserpeople.io.poses import MIR100_LASER_MOUNTS

    assert parse_mounts(["MiR100"]) == MIR100_LASER_MOUNTS
    front = MIR100_LASER_MOUNTS["front_laser_link"][1]
    # mir_v1.urdf.xacro: laser_dx 0.392 + actuated wheel dx 0.037646, laser_dy 0.2358
    assert (front.x, front.y, math.degrees(front.theta)) == pytest.approx((0.429646, 0.2358, 45))
