"""Round trips through the LaserScan bag writers (.bag, .mcap, .db3) and open_recording."""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from rosbags.highlevel import AnyReader

from laserpeople.errors import RecordingError
from laserpeople.io import open_recording
from laserpeople.io.rosbag import RosbagRecording
from laserpeople.io.rosbag_writer import (
    open_bag,
    sensor_frame_id,
    sensor_topic,
    split_stamp,
    write_laserscan_bag,
)
from laserpeople.scan import Pose2D, Scan


def _scans() -> list[Scan]:
    rng = np.random.default_rng(3)
    out = []
    for k in range(12):
        for s, name in enumerate(("front", "/back")):
            r = rng.uniform(0.5, 8.0, 9)
            r[2], r[5] = np.nan, np.inf
            out.append(
                Scan(
                    1_700_000_000.123456 + 0.1 * k + 0.03 * s,
                    2.3 if s else -1.0,
                    -0.25 if s else 0.25,  # the second laser turns clockwise, as on the MiR
                    r,
                    range_min=0.05,
                    range_max=7.5,
                    intensities=rng.uniform(0, 100, 9) if s else None,
                    sensor=name,
                    index=k,
                    pose=Pose2D(0.1 * k, -0.2 * k, 3.1 - 0.05 * k) if k < 10 else None,
                )
            )
    return out


@pytest.mark.parametrize("suffix", [".bag", ".mcap", ".db3"])
def test_round_trip(tmp_path: Path, suffix: str) -> None:
    original = _scans()
    path = tmp_path / f"out{suffix}"
    assert write_laserscan_bag(path, original) == len(original)
    assert path.is_file()
    assert [p.name for p in tmp_path.iterdir()] == [path.name]  # no temporary left behind
    rec = open_recording(path)
    try:
        assert isinstance(rec, RosbagRecording)
        ros2 = suffix != ".bag"
        names = {t.name: t.count for t in rec.topics()}
        assert names == {("/front" if ros2 else "front"): 12, "/back": 12}
        back = list(rec.scans())
        assert rec.world_frame == "odom"
        assert rec.scans_without_pose == 4  # the last two scans of each laser had no pose
    finally:
        rec.close()
    assert len(back) == len(original)
    for a, b in zip(original, back, strict=True):
        assert b.sensor.lstrip("/") == a.sensor.lstrip("/")
        assert b.index == a.index
        assert b.stamp == pytest.approx(a.stamp, abs=1e-9)
        assert b.angle_min == pytest.approx(a.angle_min, rel=1e-7)
        assert b.angle_increment == pytest.approx(a.angle_increment, rel=1e-7)
        np.testing.assert_allclose(b.angles, a.angles, atol=1e-6)
        np.testing.assert_array_equal(b.valid, a.valid)
        np.testing.assert_allclose(b.ranges[a.valid], a.ranges[a.valid], rtol=1e-7)
        assert b.range_min == pytest.approx(a.range_min) and b.range_max == pytest.approx(7.5)
        if a.intensities is None:
            assert b.intensities is None
        else:
            assert b.intensities is not None
            np.testing.assert_allclose(b.intensities, a.intensities, rtol=1e-6)
        if a.pose is None:
            assert b.pose is None
        else:
            assert b.pose is not None
            assert (b.pose.x, b.pose.y) == pytest.approx((a.pose.x, a.pose.y), abs=1e-9)
            assert math.remainder(b.pose.theta - a.pose.theta, 2 * math.pi) == pytest.approx(
                0.0, abs=1e-9
            )


def test_written_bag_has_the_expected_messages(tmp_path: Path) -> None:
    path = tmp_path / "out.mcap"
    write_laserscan_bag(path, _scans(), frame_ids={"front": "front_laser"}, tf_topic=None)
    with AnyReader([path]) as reader:
        topics = {c.topic: c.msgtype for c in reader.connections}
        assert topics == {
            "/front": "sensor_msgs/msg/LaserScan",
            "/back": "sensor_msgs/msg/LaserScan",
        }
        conn = next(c for c in reader.connections if c.topic == "/front")
        _, log, raw = next(iter(reader.messages(connections=[conn])))
        msg: Any = reader.deserialize(raw, conn.msgtype)
    assert msg.header.frame_id == "front_laser"
    assert (msg.header.stamp.sec, msg.header.stamp.nanosec) == (1_700_000_000, 123456001)
    assert log == 1_700_000_000_123456001
    assert msg.angle_max == pytest.approx(-1.0 + 8 * 0.25)


def test_failing_stream_keeps_a_valid_bag_of_what_was_written(tmp_path: Path) -> None:
    def broken() -> Iterator[Scan]:
        yield from _scans()[:5]
        raise RuntimeError("simulated failure")

    for suffix in (".bag", ".mcap"):
        path = tmp_path / f"partial{suffix}"
        with pytest.raises(RuntimeError, match="simulated"):
            write_laserscan_bag(path, broken())
        with RosbagRecording(path) as rec:
            assert len(list(rec.scans())) == 5


def test_existing_file_is_replaced_and_bad_extension_refused(tmp_path: Path) -> None:
    path = tmp_path / "out.bag"
    path.write_text("old")
    write_laserscan_bag(path, _scans()[:2])
    with RosbagRecording(path) as rec:
        assert len(list(rec.scans())) == 2
    with pytest.raises(RecordingError, match="extension"):
        write_laserscan_bag(tmp_path / "out.txt", _scans())


def test_stamp_splitting_and_sensor_naming() -> None:
    assert split_stamp(12.25) == (12, 250_000_000)
    assert split_stamp(3.9999999999) == (4, 0)  # rounding up carries into the seconds
    with pytest.raises(RecordingError, match="negative"):
        split_stamp(-0.5)
    assert sensor_topic("front") == "/front" and sensor_topic("/back") == "/back"
    assert sensor_topic("front", ros1=True) == "front"
    assert sensor_frame_id("/robot/front/") == "robot_front" and sensor_frame_id("/") == "laser"


def test_open_bag_adds_messages_and_discards_a_failed_block(tmp_path: Path) -> None:
    path = tmp_path / "extra.mcap"
    with open_bag(path) as sink:
        sink.scan(_scans()[0], "/front", "front")
        text = sink.typestore.types["std_msgs/msg/String"](data="hello")
        sink.write("/note", "std_msgs/msg/String", text, 5.5)
    assert sink.count == 1
    with AnyReader([path]) as reader:
        conn = next(c for c in reader.connections if c.topic == "/note")
        _, log, raw = next(iter(reader.messages(connections=[conn])))
        assert reader.deserialize(raw, conn.msgtype).data == "hello"
    assert log == 5_500_000_000
    with pytest.raises(RuntimeError, match="abandon"), open_bag(path) as sink:
        sink.scan(_scans()[0], "/front", "front")
        raise RuntimeError("abandon")
    assert [p.name for p in tmp_path.iterdir()] == [path.name]  # the old file, no temporaries
    with RosbagRecording(path) as rec:
        assert len(list(rec.scans())) == 1


def test_real_bag_round_trip_keeps_the_negative_increment(
    shared_data: Path, tmp_path: Path
) -> None:
    src = next(shared_data.rglob("legs-test-split-*.bag"))
    with RosbagRecording(src) as rec:
        originals = []
        for scan in rec.scans():
            originals.append(scan)
            if len(originals) == 30:
                break
    out = tmp_path / "mir.mcap"
    write_laserscan_bag(out, originals)
    with RosbagRecording(out) as rec:
        back = list(rec.scans())
    assert [s.sensor for s in back] == ["/" + s.sensor for s in originals]
    for a, b in zip(originals, back, strict=True):
        assert b.angle_increment == pytest.approx(a.angle_increment) and b.angle_increment < 0
        np.testing.assert_array_equal(b.ranges, a.ranges)
        np.testing.assert_array_equal(b.valid, a.valid)


CUSTOM_SCAN = """
std_msgs/Header header
float32 angle_min
float32 angle_max
float32 angle_increment
float32 time_increment
float32 scan_time
float32 range_min
float32 range_max
float32[] ranges
float32[] intensities
uint8 quality
"""


def test_custom_scan_type_defined_in_a_ros2_bag_folder(tmp_path: Path) -> None:
    """A vendor's LaserScan-like type, known only from the bag's own definitions."""
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    ts = get_typestore(Stores.LATEST)
    ts.register(get_types_from_msg(CUSTOM_SCAN, "vendor_msgs/msg/Scan2D"))
    T = ts.types
    folder = tmp_path / "ros2bag"
    with Writer(folder, version=9) as writer:
        conn = writer.add_connection("/vendor_scan", "vendor_msgs/msg/Scan2D", typestore=ts)
        for k in range(3):
            msg = T["vendor_msgs/msg/Scan2D"](
                header=T["std_msgs/msg/Header"](
                    stamp=T["builtin_interfaces/msg/Time"](sec=10 + k, nanosec=0),
                    frame_id="laser",
                ),
                angle_min=0.0,
                angle_max=0.3,
                angle_increment=0.1,
                time_increment=0.0,
                scan_time=0.0,
                range_min=0.0,
                range_max=5.0,
                ranges=np.array([1.0, 2.0, 3.0, 4.0], dtype=np.float32),
                intensities=np.empty(0, dtype=np.float32),
                quality=7,
            )
            writer.write(conn, (10 + k) * 10**9, ts.serialize_cdr(msg, "vendor_msgs/msg/Scan2D"))
    rec = open_recording(folder)
    try:
        assert [(t.name, t.msgtype, t.count) for t in rec.topics()] == [
            ("/vendor_scan", "vendor_msgs/msg/Scan2D", 3)
        ]
        scans = list(rec.scans())
    finally:
        rec.close()
    assert [s.stamp for s in scans] == [10.0, 11.0, 12.0]
    np.testing.assert_allclose(scans[0].ranges, [1, 2, 3, 4])
