"""Sensor poses from /tf + /tf_static chains in a bag, checked against hand-computed values."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from rosbags.rosbag1 import Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from laserpeople.io.poses import PoseParams
from laserpeople.io.rosbag import RosbagRecording

GAPS = PoseParams(max_gap=1.5)  # the /tf samples below are 1 s apart


def _typestore() -> Any:
    ts = get_typestore(Stores.ROS1_NOETIC)
    ts.register(
        get_types_from_msg("geometry_msgs/TransformStamped[] transforms", "tf2_msgs/msg/TFMessage")
    )
    return ts


def three_beam_scan(types: Any, header: Any) -> Any:
    """A ROS 1 LaserScan of three beams 0.1 rad apart, each 1 m, with ``header``."""
    return types["sensor_msgs/msg/LaserScan"](
        header=header,
        angle_min=0.0,
        angle_max=0.2,
        angle_increment=0.1,
        time_increment=0.0,
        scan_time=0.0,
        range_min=0.0,
        range_max=5.0,
        ranges=np.ones(3, dtype=np.float32),
        intensities=np.empty(0, dtype=np.float32),
    )


def _transform(
    ts: Any,
    stamp: float,
    parent: str,
    child: str,
    x: float,
    y: float,
    yaw: float,
    roll: float = 0.0,
) -> Any:
    T = ts.types
    sec = int(stamp)
    # yaw about z, then roll about x: q = q_z(yaw) * q_x(roll)
    cz, sz = math.cos(yaw / 2), math.sin(yaw / 2)
    cx, sx = math.cos(roll / 2), math.sin(roll / 2)
    q = (cz * sx, sz * sx, sz * cx, cz * cx)
    return T["geometry_msgs/msg/TransformStamped"](
        header=T["std_msgs/msg/Header"](
            seq=0,
            stamp=T["builtin_interfaces/msg/Time"](sec=sec, nanosec=round((stamp - sec) * 1e9)),
            frame_id=parent,
        ),
        child_frame_id=child,
        transform=T["geometry_msgs/msg/Transform"](
            translation=T["geometry_msgs/msg/Vector3"](x=x, y=y, z=0.3),
            rotation=T["geometry_msgs/msg/Quaternion"](x=q[0], y=q[1], z=q[2], w=q[3]),
        ),
    )


def _write(path: Path, *, flipped: bool = False) -> None:
    ts = _typestore()
    T = ts.types
    with Writer(path) as w:
        static = w.add_connection("/tf_static", "tf2_msgs/msg/TFMessage", typestore=ts)
        tf = w.add_connection("/tf", "tf2_msgs/msg/TFMessage", typestore=ts)
        scan = w.add_connection("/front", "sensor_msgs/msg/LaserScan", typestore=ts)
        mount = _transform(
            ts,
            0.5,
            "/base_link",
            "front_laser",
            0.5,
            0.0,
            math.pi / 2,
            roll=math.pi if flipped else 0.0,
        )
        msg = T["tf2_msgs/msg/TFMessage"](transforms=[mount])
        w.write(static, int(0.5e9), ts.serialize_ros1(msg, "tf2_msgs/msg/TFMessage"))
        for k in range(3):  # map -> odom fixed offset, odom -> base_link moving
            t = 1.0 + k
            msg = T["tf2_msgs/msg/TFMessage"](
                transforms=[
                    _transform(ts, t, "map", "odom", 10.0, 0.0, 0.0),
                    _transform(ts, t, "odom", "base_link", 1.0 * k, 0.0, 0.25 * k),
                ]
            )
            w.write(tf, int(t * 1e9), ts.serialize_ros1(msg, "tf2_msgs/msg/TFMessage"))
        for t in (1.5, 2.0, 3.5):
            sec = int(t)
            laser = three_beam_scan(
                T,
                T["std_msgs/msg/Header"](
                    seq=0,
                    stamp=T["builtin_interfaces/msg/Time"](sec=sec, nanosec=round((t - sec) * 1e9)),
                    frame_id="front_laser",
                ),
            )
            w.write(scan, int(t * 1e9), ts.serialize_ros1(laser, "sensor_msgs/msg/LaserScan"))


def test_tf_static_and_tf_chain_in_map_frame(tmp_path: Path) -> None:
    path = tmp_path / "tf.bag"
    _write(path)
    with RosbagRecording(path, pose_params=GAPS) as rec:
        scans = list(rec.scans())
        assert rec.world_frame == "map"  # preferred over odom
        summary = rec.pose_summary()
    # t = 1.5: base at (0.5, 0) heading 0.125 in odom; odom at (10, 0) in map;
    # laser 0.5 m ahead of base, turned +90 deg
    p = scans[0].pose
    assert p is not None
    a = 0.125
    assert (p.x, p.y) == pytest.approx((10.5 + 0.5 * math.cos(a), 0.5 * math.sin(a)))
    assert p.theta == pytest.approx(a + math.pi / 2)
    q = scans[1].pose
    assert q is not None and q.theta == pytest.approx(0.25 + math.pi / 2)
    assert scans[2].pose is None  # 0.5 s after the last /tf sample
    assert "1 of 3 scans have no pose in frame 'map'" in summary
    assert "base_link -> front_laser (/tf_static)" in summary


def test_odom_as_requested_world_frame(tmp_path: Path) -> None:
    path = tmp_path / "tf.bag"
    _write(path)
    with RosbagRecording(path, world_frame="odom", pose_params=GAPS) as rec:
        first = next(iter(rec.scans()))
    assert first.pose is not None
    assert first.pose.x == pytest.approx(0.5 + 0.5 * math.cos(0.125))


def test_upside_down_mount_is_reported_not_mirrored(tmp_path: Path) -> None:
    path = tmp_path / "flip.bag"
    _write(path, flipped=True)
    with RosbagRecording(path, pose_params=GAPS) as rec:
        scans = list(rec.scans())
        summary = rec.pose_summary()
    assert all(s.pose is None for s in scans)
    assert "tilted by 180 deg" in summary
