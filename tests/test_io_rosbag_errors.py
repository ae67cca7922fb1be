"""Errors of the bag reader: each is a LaserPeopleError naming the file (and scan)."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag1 import Writer
from rosbags.typesys import Stores, get_typestore

from laserpeople.errors import (
    LaserPeopleError,
    MessageTypeError,
    RecordingError,
    ScanFormatError,
    TopicNotFoundError,
    UnsortedStampsError,
)
from laserpeople.io import open_recording
from laserpeople.io.rosbag import RosbagRecording


def _write_raw_bag(
    path: Path,
    scans: list[dict[str, float | int]],
    *,
    topic: str = "/scan",
    extra_odometry: bool = False,
) -> None:
    """A ROS 1 bag written with rosbags directly; each dict gives stamp, log, n, angle_max."""
    ts = get_typestore(Stores.ROS1_NOETIC)
    T = ts.types
    with Writer(path) as writer:
        conn = writer.add_connection(topic, "sensor_msgs/msg/LaserScan", typestore=ts)
        for k, spec in enumerate(scans):
            stamp = float(spec["stamp"])
            n = int(spec.get("n", 5))
            sec = int(stamp)
            header = T["std_msgs/msg/Header"](
                seq=k,
                stamp=T["builtin_interfaces/msg/Time"](sec=sec, nanosec=round((stamp - sec) * 1e9)),
                frame_id="laser",
            )
            msg = T["sensor_msgs/msg/LaserScan"](
                header=header,
                angle_min=-0.2,
                angle_max=float(spec.get("angle_max", -0.2 + (n - 1) * 0.1)),
                angle_increment=float(spec.get("inc", 0.1)),
                time_increment=0.0,
                scan_time=0.0,
                range_min=0.1,
                range_max=10.0,
                ranges=np.linspace(1.0, 2.0, n, dtype=np.float32),
                intensities=np.empty(0, dtype=np.float32),
            )
            log = int(float(spec.get("log", stamp)) * 1e9)
            writer.write(conn, log, ts.serialize_ros1(msg, "sensor_msgs/msg/LaserScan"))
        if extra_odometry:
            oconn = writer.add_connection("/odom", "nav_msgs/msg/Odometry", typestore=ts)
            odo = T["nav_msgs/msg/Odometry"](
                header=T["std_msgs/msg/Header"](
                    seq=0, stamp=T["builtin_interfaces/msg/Time"](sec=1, nanosec=0), frame_id="odom"
                ),
                child_frame_id="laser",
                pose=T["geometry_msgs/msg/PoseWithCovariance"](
                    pose=T["geometry_msgs/msg/Pose"](
                        position=T["geometry_msgs/msg/Point"](x=1.0, y=2.0, z=0.0),
                        orientation=T["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
                    ),
                    covariance=np.zeros(36),
                ),
                twist=T["geometry_msgs/msg/TwistWithCovariance"](
                    twist=T["geometry_msgs/msg/Twist"](
                        linear=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
                        angular=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
                    ),
                    covariance=np.zeros(36),
                ),
            )
            writer.write(oconn, int(1e9), ts.serialize_ros1(odo, "nav_msgs/msg/Odometry"))


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(RecordingError, match="file not found") as err:
        RosbagRecording(tmp_path / "nope.bag")
    assert str(tmp_path / "nope.bag") in str(err.value)
    with pytest.raises(RecordingError, match="file not found"):
        open_recording(tmp_path / "nope.mcap")


def test_missing_topic_lists_the_topics_there(tmp_path: Path) -> None:
    path = tmp_path / "a.bag"
    _write_raw_bag(path, [{"stamp": 1.0}], extra_odometry=True)
    with RosbagRecording(path) as rec, pytest.raises(TopicNotFoundError) as err:
        next(iter(rec.scans(["/front"])))
    text = str(err.value)
    assert str(path) in text and "'/front'" in text
    assert "/scan" in text and "/odom (nav_msgs/msg/Odometry)" in text


def test_wrong_message_type_on_requested_topic(tmp_path: Path) -> None:
    path = tmp_path / "a.bag"
    _write_raw_bag(path, [{"stamp": 1.0}], extra_odometry=True)
    with RosbagRecording(path) as rec, pytest.raises(MessageTypeError, match="nav_msgs") as err:
        list(rec.scans(["odom"]))
    assert str(path) in str(err.value)


def test_odometry_drives_poses_when_there_is_no_tf(tmp_path: Path) -> None:
    path = tmp_path / "a.bag"
    _write_raw_bag(path, [{"stamp": 1.0}, {"stamp": 1.04}, {"stamp": 2.0}], extra_odometry=True)
    with RosbagRecording(path) as rec:
        scans = list(rec.scans())
        assert rec.world_frame == "odom"
        assert [s.pose is not None for s in scans] == [True, True, False]
        assert scans[0].pose is not None and (scans[0].pose.x, scans[0].pose.y) == (1.0, 2.0)
        assert rec.scans_without_pose == 1
        assert "1 of 3 scans have no pose" in rec.pose_summary()
    with RosbagRecording(path, poses=False) as rec:
        assert all(s.pose is None for s in rec.scans())
        assert rec.scans_without_pose == 0
    with pytest.raises(MessageTypeError):
        RosbagRecording(path, odometry_topics=["/scan"]).transform_tree()


def test_unsorted_stamps_within_a_topic(tmp_path: Path) -> None:
    path = tmp_path / "a.bag"
    # log times increase, header stamps go back at the third scan
    _write_raw_bag(
        path,
        [
            {"stamp": 1.0, "log": 1.0},
            {"stamp": 1.1, "log": 1.1},
            {"stamp": 1.05, "log": 1.2},
        ],
    )
    with RosbagRecording(path) as rec, pytest.raises(UnsortedStampsError) as err:
        list(rec.scans())
    assert err.value.scan == 2
    assert str(path) in str(err.value) and "scan 2" in str(err.value)


def test_beam_count_disagreeing_with_header(tmp_path: Path) -> None:
    path = tmp_path / "a.bag"
    _write_raw_bag(path, [{"stamp": 1.0}, {"stamp": 1.1, "n": 5, "angle_max": 2.0}])
    with RosbagRecording(path) as rec:
        it = rec.scans()
        assert next(it).n_beams == 5
        with pytest.raises(ScanFormatError, match="5 beams") as err:
            next(it)
    assert err.value.scan == 1 and str(path) in str(err.value)


def test_zero_increment_is_a_scan_format_error(tmp_path: Path) -> None:
    path = tmp_path / "a.bag"
    _write_raw_bag(path, [{"stamp": 1.0, "inc": 0.0, "angle_max": -0.2}])
    with RosbagRecording(path) as rec, pytest.raises(ScanFormatError, match="angle_increment"):
        list(rec.scans())


def _copy_cut(src: Path, dst: Path, keep: float) -> Path:
    data = src.read_bytes()
    dst.write_bytes(data[: int(len(data) * keep)])
    return dst


def test_truncated_bag(shared_data: Path, tmp_path: Path) -> None:
    src = next(shared_data.rglob("demo_stationary_simple_environment.bag"))
    for keep in (0.5, 0.999, 0.0005):
        bad = _copy_cut(src, tmp_path / f"cut{keep}.bag", keep)
        with pytest.raises(RecordingError, match="rosbag reindex") as err:
            RosbagRecording(bad)
        assert str(bad) in str(err.value)


def test_corrupt_bag_fails_at_the_bad_scan(shared_data: Path, tmp_path: Path) -> None:
    src = next(shared_data.rglob("demo_stationary_simple_environment.bag"))
    bad = tmp_path / "corrupt.bag"
    shutil.copy(src, bad)
    data = bytearray(bad.read_bytes())
    mid = len(data) // 2
    data[mid : mid + 5000] = b"\xff" * 5000
    bad.write_bytes(bytes(data))
    rec = RosbagRecording(bad)  # the index at the end is intact
    n = 0
    with pytest.raises(RecordingError, match="corrupt or truncated") as err:
        for _ in rec.scans():
            n += 1
    rec.close()
    assert 0 < n < 1265
    assert err.value.scan == n and str(bad) in str(err.value)


def test_not_a_bag(tmp_path: Path) -> None:
    path = tmp_path / "text.bag"
    path.write_text("hello\n")
    with pytest.raises(LaserPeopleError):
        RosbagRecording(path)
    folder = tmp_path / "ros2"
    folder.mkdir()
    (folder / "metadata.yaml").write_text("not: [a bag")
    with pytest.raises(RecordingError):
        open_recording(folder)


def test_zero_header_stamps_fall_back_to_bag_time_and_are_counted(tmp_path: Path) -> None:
    path = tmp_path / "a.bag"
    _write_raw_bag(path, [{"stamp": 0.0, "log": 5.0}, {"stamp": 0.0, "log": 5.1}])
    with RosbagRecording(path) as rec:
        assert [s.stamp for s in rec.scans()] == pytest.approx([5.0, 5.1], abs=1e-9)
        assert rec.scans_with_log_time == 2
