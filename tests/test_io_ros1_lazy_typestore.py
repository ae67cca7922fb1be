"""A ROS 1 bag of standard types only (LaserScan, TFMessage, Odometry by type and MD5 sum)
builds its typestore when first asked for it; any other type builds it on open."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag1 import Writer
from rosbags.typesys import Stores, get_typestore

from laserpeople.io import open_recording
from laserpeople.io import ros1_reader as ros1
from laserpeople.io.ros1_reader import Ros1Reader, Ros1ReaderError, standard_types
from test_io_rosbag_errors import _write_raw_bag


@pytest.fixture
def builds(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The typestores built (their connection counts), with an empty cache."""
    built: list[int] = []
    real = ros1._checked_typestore

    def counted(connections: list[object]) -> object:
        built.append(len(connections))
        return real(connections)  # type: ignore[arg-type]

    monkeypatch.setattr(ros1, "_checked_typestore", counted)
    monkeypatch.setattr(ros1, "TYPESTORES", {})
    return built


def test_the_standard_types_are_the_fast_decoders(builds: list[int]) -> None:
    from laserpeople.io.laserscan_ros1 import LASERSCAN_MD5
    from laserpeople.io.pose_msgs_ros1 import ODOMETRY_MD5, TF_MD5

    ts = get_typestore(Stores.ROS1_NOETIC)
    assert {
        ("sensor_msgs/msg/LaserScan", LASERSCAN_MD5),
        ("nav_msgs/msg/Odometry", ODOMETRY_MD5),
        ("tf2_msgs/msg/TFMessage", TF_MD5),
    } <= standard_types()
    for msgtype in ("sensor_msgs/msg/LaserScan", "nav_msgs/msg/Odometry"):
        assert (msgtype, ts.generate_msgdef(msgtype)[1]) in standard_types()
    assert len(standard_types()) == 4  # (and tf/msg/tfMessage, of TFMessage's sum)


def test_standard_types_only_build_at_first_use(tmp_path: Path, builds: list[int]) -> None:
    path = tmp_path / "std.bag"
    _write_raw_bag(path, [{"stamp": 1.0 + 0.1 * k, "n": 5} for k in range(3)], extra_odometry=True)
    with Ros1Reader(path) as reader:
        assert builds == []
        assert reader.is_standard("nav_msgs/msg/Odometry")
        assert not reader.is_standard("std_msgs/msg/Int32")  # (no such connection)
        assert set(reader.typestore.fielddefs) >= {
            "sensor_msgs/msg/LaserScan",
            "nav_msgs/msg/Odometry",
        }
        assert builds == [2]
        reader.typestore  # noqa: B018  (built once)
        assert builds == [2]
    # reading its scans and listing its topics builds none (decoded from their bytes)
    ros1.TYPESTORES.clear()
    builds.clear()
    rec = open_recording(path)
    try:
        assert [t.name for t in rec.topics()] == ["/scan"]
        scans = list(rec.scans())
    finally:
        rec.close()
    assert builds == [] and len(scans) == 3
    np.testing.assert_allclose(scans[0].ranges, np.linspace(1.0, 2.0, 5), rtol=0, atol=1e-6)


def _int32_bag(path: Path, msgtype: str, md5: str, msgdef_of: str = "std_msgs/msg/Int32") -> None:
    ts = get_typestore(Stores.ROS1_NOETIC)
    with Writer(path) as writer:
        msgdef = ts.generate_msgdef(msgdef_of)[0]
        conn = writer.add_connection("/n", msgtype, msgdef=msgdef, md5sum=md5)
        msg = ts.types["std_msgs/msg/Int32"](data=7)
        writer.write(conn, 10**9, ts.serialize_ros1(msg, "std_msgs/msg/Int32"))


def test_another_type_builds_on_open(tmp_path: Path, builds: list[int]) -> None:
    path = tmp_path / "int.bag"
    ts = get_typestore(Stores.ROS1_NOETIC)
    _int32_bag(path, "std_msgs/msg/Int32", ts.generate_msgdef("std_msgs/msg/Int32")[1])
    with Ros1Reader(path):
        assert builds == [1]
    # beside standard LaserScans too (every connection must be standard)
    mixed = tmp_path / "mixed.bag"
    with Writer(mixed) as writer:
        writer.add_connection("/scan", "sensor_msgs/msg/LaserScan", typestore=ts)
        ints = writer.add_connection("/n", "std_msgs/msg/Int32", typestore=ts)
        writer.write(
            ints,
            10**9,
            ts.serialize_ros1(ts.types["std_msgs/msg/Int32"](data=7), "std_msgs/msg/Int32"),
        )
    with Ros1Reader(mixed):
        assert builds == [1, 2]


def test_a_standard_sum_over_another_definition_is_refused_at_first_use(
    tmp_path: Path, builds: list[int]
) -> None:
    """A LaserScan connection with the standard MD5 sum but another definition opens (its
    messages are decoded by the sum's layout) and is refused, naming the type, when its
    typestore is asked for."""
    path = tmp_path / "odd.bag"
    md5 = "90c7ef2dc6895d81024acba2ac42f369"
    _int32_bag(path, "sensor_msgs/msg/LaserScan", md5)
    with Ros1Reader(path) as reader:
        assert builds == []
        with pytest.raises(Ros1ReaderError, match=r"LaserScan.*hash mismatch"):
            reader.typestore  # noqa: B018
