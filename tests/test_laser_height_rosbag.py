"""A ROS bag laser's mount height from its /tf_static (or first /tf) chain, against
hand-summed z translations."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from rosbags.rosbag1 import Writer

from laserpeople.io.rosbag import RosbagRecording
from laserpeople.pipeline.laser_height import laser_heights, upper_body_warning
from test_io_rosbag_tf import _typestore, three_beam_scan

TOL = 1e-9  # heights are sums of two or three float64 z translations


def _header(ts: Any, t: float, frame: str) -> Any:
    T = ts.types
    sec = int(t)
    return T["std_msgs/msg/Header"](
        seq=0,
        stamp=T["builtin_interfaces/msg/Time"](sec=sec, nanosec=round((t - sec) * 1e9)),
        frame_id=frame,
    )


def _tf(ts: Any, t: float, parent: str, child: str, z: float) -> Any:
    T = ts.types
    return T["geometry_msgs/msg/TransformStamped"](
        header=_header(ts, t, parent),
        child_frame_id=child,
        transform=T["geometry_msgs/msg/Transform"](
            translation=T["geometry_msgs/msg/Vector3"](x=0.2, y=0.1, z=z),
            rotation=T["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
        ),
    )


def _write(path: Path, *, with_tf: bool = True) -> None:
    """Lasers ``front`` (frame front_laser: /tf_static base_footprint -> base_link 0.3 m,
    base_link -> front_laser 0.8 m), ``back`` (frame back_laser: on /tf only, 0.2 m on
    base_link first, 0.6 m later), ``world`` (frame world_laser straight under map) and
    ``bare`` (frame bare_laser, named by no transform), ``chair`` (frame chair_laser: /tf
    odom -> chair_base 0.18 m, chair_base -> chair_laser 0.02 m); odom -> base_footprint
    0.05 m."""
    ts = _typestore()
    T = ts.types
    msgtype = "tf2_msgs/msg/TFMessage"
    with Writer(path) as w:
        if with_tf:
            static = w.add_connection("/tf_static", msgtype, typestore=ts)
            tf = w.add_connection("/tf", msgtype, typestore=ts)
            chain = [
                _tf(ts, 0.5, "base_footprint", "base_link", 0.3),
                _tf(ts, 0.5, "/base_link", "front_laser", 0.8),
            ]
            w.write(static, int(0.5e9), ts.serialize_ros1(T[msgtype](transforms=chain), msgtype))
            for k, back_z in enumerate((0.2, 0.6)):
                t = 1.0 + k
                moving = [
                    _tf(ts, t, "odom", "base_footprint", 0.05),
                    _tf(ts, t, "base_link", "back_laser", back_z),
                    _tf(ts, t, "map", "world_laser", 0.4),
                    _tf(ts, t, "odom", "chair_base", 0.18),
                    _tf(ts, t, "chair_base", "chair_laser", 0.02),
                ]
                w.write(tf, int(t * 1e9), ts.serialize_ros1(T[msgtype](transforms=moving), msgtype))
        for topic, frame in (
            ("/front", "front_laser"),
            ("/back", "back_laser"),
            ("/world", "world_laser"),
            ("/bare", "bare_laser"),
            ("/chair", "chair_laser"),
        ):
            conn = w.add_connection(topic, "sensor_msgs/msg/LaserScan", typestore=ts)
            laser = three_beam_scan(T, _header(ts, 1.5, frame))
            w.write(conn, int(1.5e9), ts.serialize_ros1(laser, "sensor_msgs/msg/LaserScan"))


def test_height_is_the_sum_of_the_chain_z_up_to_the_robot_frame(tmp_path: Path) -> None:
    bag = tmp_path / "tf.bag"
    _write(bag)
    with RosbagRecording(bag) as rec:
        heights = laser_heights(rec)
    # front: 0.3 + 0.8 up to base_footprint (not 0.8 = last link only, not 1.15 = past
    # the floor frame base_footprint into odom)
    assert heights["/front"] == pytest.approx(1.1, abs=TOL)
    # back: 0.3 + the first /tf value 0.2 (not the later 0.6)
    assert heights["/back"] == pytest.approx(0.5, abs=TOL)
    # straight under a world frame (a `live --record` bag) and named by no transform: unknown
    # chair: a base held above odom (no base_footprint): 0.02 + 0.18, not 0.02
    assert heights["/chair"] == pytest.approx(0.2, abs=TOL)
    assert set(heights) == {"/front", "/back", "/chair"}
    warning = upper_body_warning("upper-body-pf", ["/front", "/back"], heights)
    assert "/back at 0.50 m" in warning and "/front" not in warning
    # with poses off (--no-poses, the way past a damaged /tf) the transforms are not read
    with RosbagRecording(bag, poses=False) as rec:
        assert laser_heights(rec) == {}


def test_bag_without_tf_gives_no_height(tmp_path: Path) -> None:
    bag = tmp_path / "bare.bag"
    _write(bag, with_tf=False)
    with RosbagRecording(bag) as rec:
        assert laser_heights(rec) == {}
        assert "not recorded" in upper_body_warning("upper-body-pf", ["/front"], {})
