"""The ROS 1 reader (io/ros1_reader.py) reads a bag as rosbags' AnyReader does, without
importing the ROS 2 readers."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from rosbags.highlevel import AnyReader, AnyReaderError

from laserpeople.io.bag_guard import open_reader
from laserpeople.io.ros1_reader import Ros1Reader, Ros1ReaderError
from test_io_rosbag_errors import _write_raw_bag


def _bag(tmp_path: Path) -> Path:
    path = tmp_path / "two_topics.bag"
    _write_raw_bag(
        path, [{"stamp": 1.0 + 0.1 * k, "n": 5 + k} for k in range(4)], extra_odometry=True
    )
    return path


def test_same_connections_and_messages_as_anyreader(tmp_path: Path) -> None:
    path = _bag(tmp_path)
    with AnyReader([path]) as any_reader, Ros1Reader(path) as ours:
        assert [(c.topic, c.msgtype) for c in ours.connections] == [
            (c.topic, c.msgtype) for c in any_reader.connections
        ]
        assert set(ours.typestore.fielddefs) == set(any_reader.typestore.fielddefs)
        theirs = list(any_reader.messages())
        mine = list(ours.messages())
        assert [(c.topic, t) for c, t, _ in mine] == [(c.topic, t) for c, t, _ in theirs]
        for (conn, _, raw), (_, _, raw_any) in zip(mine, theirs, strict=True):
            assert bytes(raw) == bytes(raw_any)  # the same serialised message
            a = ours.deserialize(raw, conn.msgtype)
            b = any_reader.deserialize(raw_any, conn.msgtype)
            if conn.msgtype.endswith("LaserScan"):
                # ranges [m], decoded by each reader's type store: within 1 um
                np.testing.assert_allclose(a.ranges, b.ranges, rtol=0, atol=1e-6)  # type: ignore[attr-defined]
                assert a.header.stamp.sec == b.header.stamp.sec  # type: ignore[attr-defined]
        scans = [c for c in ours.connections if c.topic == "/scan"]
        assert len(list(ours.messages(connections=scans))) == 4


def test_open_reader_takes_it_for_a_ros1_bag_and_refuses_bad_data(tmp_path: Path) -> None:
    path = _bag(tmp_path)
    reader = open_reader(path)
    try:
        assert isinstance(reader, Ros1Reader) and not reader.is2
        conn = reader.connections[0]
        with pytest.raises(Ros1ReaderError):
            reader.deserialize(b"\x01", conn.msgtype)
    finally:
        reader.close()
    assert reader.stack is None
    with pytest.raises(Ros1ReaderError, match="not open"):
        reader.close()


def test_reading_a_ros1_bag_imports_no_ros2_reader(tmp_path: Path) -> None:
    path = _bag(tmp_path)
    code = (
        "import sys\n"
        "from laserpeople.io import open_recording\n"
        f"rec = open_recording({str(path)!r})\n"
        "n = sum(1 for _ in rec.scans())\n"
        "rec.close()\n"
        "print(n, sorted(m for m in sys.modules if m.startswith('rosbags.rosbag2')))\n"
    )
    src = str(Path(__file__).resolve().parents[1] / "src")
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        check=True,
        env={"PYTHONPATH": src, "PATH": ""},
    ).stdout
    assert out.strip() == "4 []"


def test_a_definition_that_disagrees_with_its_md5_sum_is_refused(tmp_path: Path) -> None:
    """A connection whose MD5 sum is not its message definition's (a bag written with
    another version of the type) is refused on open, naming the type, as AnyReader
    refuses it; through open_reader as a RecordingError naming the file."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    from laserpeople.errors import RecordingError

    path = tmp_path / "wrong_md5.bag"
    ts = get_typestore(Stores.ROS1_NOETIC)
    with Writer(path) as writer:
        msgdef, md5 = ts.generate_msgdef("std_msgs/msg/Int32")
        assert md5 != "0" * 32
        conn = writer.add_connection("/n", "std_msgs/msg/Int32", msgdef=msgdef, md5sum="0" * 32)
        msg = ts.types["std_msgs/msg/Int32"](data=7)
        writer.write(conn, 10**9, ts.serialize_ros1(msg, "std_msgs/msg/Int32"))
    with pytest.raises(Ros1ReaderError, match=r"std_msgs/msg/Int32.*hash mismatch"):
        Ros1Reader(path).open()
    with pytest.raises(AnyReaderError), AnyReader([path]):
        pass
    with pytest.raises(RecordingError) as err:
        open_reader(path)
    assert str(path) in str(err.value)
    # the same bag with the right sum reads
    good = tmp_path / "right_md5.bag"
    with Writer(good) as writer:
        conn = writer.add_connection("/n", "std_msgs/msg/Int32", typestore=ts)
        writer.write(conn, 10**9, ts.serialize_ros1(msg, "std_msgs/msg/Int32"))
    with Ros1Reader(good) as reader:
        ((c, _, raw),) = list(reader.messages())
        assert reader.deserialize(raw, c.msgtype).data == 7  # type: ignore[attr-defined]
