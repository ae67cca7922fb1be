"""The direct ROS 1 LaserScan decoder (io/laserscan_ros1.py) gives what rosbags' generic
deserialiser gives, on real bags and on written ones, and hands bytes that do not follow
the layout back to it."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from laserpeople.io import open_recording
from laserpeople.io.bag_guard import open_reader
from laserpeople.io.laserscan_ros1 import decode_laserscan, is_standard_laserscan
from laserpeople.io.rosbag_writer import write_laserscan_bag
from laserpeople.scan import Scan

REAL_BAGS = (
    "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag",
    "leg_tracker/rosbags/training_scans_res=0.33/positive_not_extracted/positive_1.bag",
    "mir/rosbags/corridor/corridor.bag",
    "leg_tracker_benchmarks/person_following_outdoor_1_first.bag",
)


def _same_message(fast: object, slow: object) -> None:
    """Every field the readers use: integers equal, floats within 1e-9 (relative), ranges
    and intensities within 1 um (NaN where NaN)."""
    a, b = fast, slow
    assert a.header.seq == b.header.seq  # type: ignore[attr-defined]
    assert a.header.stamp.sec == b.header.stamp.sec  # type: ignore[attr-defined]
    assert a.header.stamp.nanosec == b.header.stamp.nanosec  # type: ignore[attr-defined]
    assert a.header.frame_id == b.header.frame_id  # type: ignore[attr-defined]
    for name in (
        "angle_min",
        "angle_max",
        "angle_increment",
        "time_increment",
        "scan_time",
        "range_min",
        "range_max",
    ):
        x, y = float(getattr(a, name)), float(getattr(b, name))
        assert x == pytest.approx(y, rel=1e-9, abs=0.0, nan_ok=True), name
    for name in ("ranges", "intensities"):
        x, y = np.asarray(getattr(a, name)), np.asarray(getattr(b, name))
        assert x.shape == y.shape and x.dtype == y.dtype == np.float32, name
        np.testing.assert_allclose(x, y, rtol=0, atol=1e-6, equal_nan=True)


def _compare_bag(path: Path, limit: int = 400) -> int:
    """Decode up to ``limit`` scans of every LaserScan topic both ways; the count done."""
    reader = open_reader(path)
    done = 0
    try:
        scans = [c for c in reader.connections if c.msgtype.endswith("LaserScan")]
        assert scans, f"{path} has no LaserScan topic"
        for conn in scans:
            assert is_standard_laserscan(reader, conn)
            for k, (c, _, raw) in enumerate(reader.messages(connections=[conn])):
                if k == limit:
                    break
                fast = decode_laserscan(raw)
                assert fast is not None, f"{path} {conn.topic} message {k}: layout refused"
                _same_message(fast, reader.deserialize(raw, c.msgtype))
                done += 1
    finally:
        reader.close()
    return done


@pytest.mark.parametrize("name", REAL_BAGS)
def test_real_bags_decode_the_same_both_ways(shared_data: Path, name: str) -> None:
    path = shared_data / name
    if not path.exists():
        pytest.skip(f"{name} is not in the shared data")
    assert _compare_bag(path) > 0


def _written_bag(tmp_path: Path) -> Path:
    rng = np.random.default_rng(5)
    scans = []
    for k in range(6):
        ranges = rng.uniform(0.1, 9.0, 40 + k)
        ranges[[1, 7]] = [np.nan, np.inf]
        intensities = rng.uniform(0.0, 100.0, ranges.size) if k % 2 else None
        scans.append(
            Scan(
                1.5 + 0.1 * k,
                -1.2,
                0.02,
                ranges,
                range_min=0.05,
                range_max=10.0,
                intensities=intensities,
                sensor="/front_scan",
                index=k,
            )
        )
    path = tmp_path / "written.bag"
    write_laserscan_bag(path, scans, tf_topic=None)
    return path


def test_written_bag_decodes_the_same_both_ways_and_reads_the_same_scans(
    tmp_path: Path,
) -> None:
    path = _written_bag(tmp_path)
    assert _compare_bag(path) == 6
    # the recording reads the same scans as through the generic path
    import laserpeople.io.rosbag as rosbag

    rec = open_recording(path)
    fast = list(rec.scans())
    rec.close()
    original = rosbag.decode_laserscan
    rosbag.decode_laserscan = lambda raw: None  # type: ignore[assignment]
    try:
        rec = open_recording(path)
        slow = list(rec.scans())
        rec.close()
    finally:
        rosbag.decode_laserscan = original
    assert len(fast) == len(slow) == 6
    for a, b in zip(fast, slow, strict=True):
        assert a.stamp == pytest.approx(b.stamp, abs=1e-9)
        assert (a.angle_min, a.angle_increment) == pytest.approx(
            (b.angle_min, b.angle_increment), rel=1e-12
        )
        np.testing.assert_allclose(a.ranges, b.ranges, rtol=0, atol=1e-6, equal_nan=True)
        assert (a.intensities is None) == (b.intensities is None)
        if a.intensities is not None:
            np.testing.assert_allclose(a.intensities, b.intensities, rtol=0, atol=1e-6)


def test_bytes_off_the_layout_go_back_to_the_generic_path(tmp_path: Path) -> None:
    path = _written_bag(tmp_path)
    reader = open_reader(path)
    try:
        conn = next(c for c in reader.connections if c.msgtype.endswith("LaserScan"))
        raw = bytes(next(iter(reader.messages(connections=[conn])))[2])
    finally:
        reader.close()
    msg = decode_laserscan(raw)
    assert msg is not None and msg.ranges.size == 40
    assert math.isnan(float(msg.ranges[1])) and math.isinf(float(msg.ranges[7]))
    assert decode_laserscan(raw[:-1]) is None  # truncated
    assert decode_laserscan(raw + b"\x00") is None  # trailing bytes
    assert decode_laserscan(raw[:10]) is None  # not even a header
    huge = bytearray(raw)
    huge[12:16] = (10**6).to_bytes(4, "little")  # frame id longer than the message
    assert decode_laserscan(bytes(huge)) is None
    bad_id = bytearray(raw)
    bad_id[16] = 0xFF  # not UTF-8
    assert decode_laserscan(bytes(bad_id)) is None


def test_only_standard_ros1_laserscans_take_the_direct_path() -> None:
    class Conn:
        def __init__(self, msgtype: str, digest: str) -> None:
            self.msgtype, self.digest = msgtype, digest

    class Reader:
        def __init__(self, is2: bool) -> None:
            self.is2 = is2

    md5 = "90c7ef2dc6895d81024acba2ac42f369"
    assert is_standard_laserscan(Reader(False), Conn("sensor_msgs/msg/LaserScan", md5))
    assert not is_standard_laserscan(Reader(True), Conn("sensor_msgs/msg/LaserScan", md5))
    assert not is_standard_laserscan(Reader(False), Conn("sensor_msgs/msg/LaserScan", "0" * 32))
    assert not is_standard_laserscan(Reader(False), Conn("my_msgs/msg/LaserScan", md5))
