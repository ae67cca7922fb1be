"""The direct ROS 1 TFMessage and Odometry decoders (io/pose_msgs_ros1.py) give what
rosbags' generic deserialiser gives, hand bytes that do not follow the layout back to it,
and leave the transform tree of a bag as it was; the ROS 1 reader builds the typestore of a
set of message definitions once."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pytest
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from laserpeople.io import ros1_reader
from laserpeople.io.bag_guard import open_reader
from laserpeople.io.pose_msgs_ros1 import (
    ODOMETRY_MD5,
    TF_MD5,
    decode_odometry,
    decode_tf_message,
    standard_pose_decoder,
)
from laserpeople.io.ros1_reader import Ros1Reader, Ros1ReaderError

TS = get_typestore(Stores.ROS1_NOETIC)
TS.register(
    get_types_from_msg("geometry_msgs/TransformStamped[] transforms", "tf2_msgs/msg/TFMessage")
)
CORRIDOR = "mir/rosbags/corridor/corridor.bag"


def _header(sec: int, nsec: int, frame: str, seq: int = 3) -> Any:
    t = TS.types
    return t["std_msgs/msg/Header"](
        seq=seq, stamp=t["builtin_interfaces/msg/Time"](sec=sec, nanosec=nsec), frame_id=frame
    )


def _tf(n: int) -> Any:
    t = TS.types
    out = []
    for k in range(n):
        v = t["geometry_msgs/msg/Vector3"](x=0.1 * k - 1.25, y=2.0 / 3.0 + k, z=0.31 + k)
        q = t["geometry_msgs/msg/Quaternion"](x=0.01 * k, y=-0.02, z=0.7071, w=0.7071 + k * 1e-3)
        out.append(
            t["geometry_msgs/msg/TransformStamped"](
                header=_header(100 + k, 250_000_000 + k, "odom" if k else "wörld", seq=k),
                child_frame_id=f"base_link_{k}",
                transform=t["geometry_msgs/msg/Transform"](translation=v, rotation=q),
            )
        )
    return t["tf2_msgs/msg/TFMessage"](transforms=out)


def _odometry() -> Any:
    import numpy as np

    t = TS.types
    pose = t["geometry_msgs/msg/Pose"](
        position=t["geometry_msgs/msg/Point"](x=1.5, y=-2.25, z=0.125),
        orientation=t["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.38268343, w=0.92387953),
    )
    twist = t["geometry_msgs/msg/Twist"](
        linear=t["geometry_msgs/msg/Vector3"](x=0.5, y=0.0, z=0.0),
        angular=t["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.1),
    )
    return t["nav_msgs/msg/Odometry"](
        header=_header(7, 999_999_999, "odom"),
        child_frame_id="base_footprint",
        pose=t["geometry_msgs/msg/PoseWithCovariance"](
            pose=pose, covariance=np.arange(36, dtype=np.float64)
        ),
        twist=t["geometry_msgs/msg/TwistWithCovariance"](
            twist=twist, covariance=np.zeros(36, dtype=np.float64)
        ),
    )


def _same_header(a: Any, b: Any) -> None:
    assert (a.seq, a.stamp.sec, a.stamp.nanosec, a.frame_id) == (
        b.seq,
        b.stamp.sec,
        b.stamp.nanosec,
        b.frame_id,
    )


def _same_tf(a: Any, b: Any) -> None:
    """Every field the transform tree reads, the floats bit for bit."""
    assert len(a.transforms) == len(b.transforms)
    for x, y in zip(a.transforms, b.transforms, strict=True):
        _same_header(x.header, y.header)
        assert x.child_frame_id == y.child_frame_id
        for f in "xyz":
            assert getattr(x.transform.translation, f) == getattr(y.transform.translation, f)
        for f in "xyzw":
            assert getattr(x.transform.rotation, f) == getattr(y.transform.rotation, f)


def _same_odometry(a: Any, b: Any) -> None:
    _same_header(a.header, b.header)
    assert a.child_frame_id == b.child_frame_id
    for f in "xyz":
        assert getattr(a.pose.pose.position, f) == getattr(b.pose.pose.position, f)
    for f in "xyzw":
        assert getattr(a.pose.pose.orientation, f) == getattr(b.pose.pose.orientation, f)


@pytest.mark.parametrize("n", [0, 1, 3])
def test_tf_message_as_rosbags_decodes_it(n: int) -> None:
    raw = bytes(TS.serialize_ros1(_tf(n), "tf2_msgs/msg/TFMessage"))
    mine = decode_tf_message(raw)
    assert mine is not None
    _same_tf(mine, TS.deserialize_ros1(raw, "tf2_msgs/msg/TFMessage"))
    assert decode_tf_message(memoryview(raw)) == mine


def test_odometry_as_rosbags_decodes_it() -> None:
    raw = bytes(TS.serialize_ros1(_odometry(), "nav_msgs/msg/Odometry"))
    mine = decode_odometry(raw)
    assert mine is not None
    _same_odometry(mine, TS.deserialize_ros1(raw, "nav_msgs/msg/Odometry"))


def test_bytes_off_the_layout_go_back_to_rosbags() -> None:
    """Every cut of a message, a byte more, a count or length beyond the end and a frame
    id that is not UTF-8 give None (the caller's deserialiser reports them)."""
    tf = bytes(TS.serialize_ros1(_tf(2), "tf2_msgs/msg/TFMessage"))
    odom = bytes(TS.serialize_ros1(_odometry(), "nav_msgs/msg/Odometry"))
    for raw, decode in ((tf, decode_tf_message), (odom, decode_odometry)):
        assert all(decode(raw[:cut]) is None for cut in range(len(raw)))
        assert decode(raw + b"\0") is None
    assert decode_tf_message((3).to_bytes(4, "little") + tf[4:]) is None  # one transform more
    # the first frame id ("wörld", after the count, seq, sec, nsec and its length) not UTF-8
    bad = bytearray(tf)
    bad[20] = 0xFF
    assert decode_tf_message(bytes(bad)) is None
    bad = bytearray(odom)
    bad[12:16] = (10**6).to_bytes(4, "little")  # frame id longer than the message
    assert decode_odometry(bytes(bad)) is None


class _Conn:
    def __init__(self, msgtype: str, digest: str) -> None:
        self.msgtype, self.digest = msgtype, digest


class _Reader:
    def __init__(self, is2: bool) -> None:
        self.is2 = is2


def test_only_the_standard_types_of_a_ros1_bag_are_decoded_directly() -> None:
    ros1, ros2 = _Reader(False), _Reader(True)
    assert standard_pose_decoder(ros1, _Conn("tf2_msgs/msg/TFMessage", TF_MD5)) is decode_tf_message
    assert standard_pose_decoder(ros1, _Conn("tf/msg/tfMessage", TF_MD5)) is decode_tf_message
    assert standard_pose_decoder(ros1, _Conn("nav_msgs/msg/Odometry", ODOMETRY_MD5)) is (
        decode_odometry
    )
    assert standard_pose_decoder(ros1, _Conn("tf2_msgs/msg/TFMessage", "0" * 32)) is None
    assert standard_pose_decoder(ros1, _Conn("nav_msgs/msg/Odometry", TF_MD5)) is None
    assert standard_pose_decoder(ros2, _Conn("tf2_msgs/msg/TFMessage", TF_MD5)) is None
    # the sums are the definitions' own
    assert TS.generate_msgdef("tf2_msgs/msg/TFMessage")[1] == TF_MD5
    assert TS.generate_msgdef("nav_msgs/msg/Odometry")[1] == ODOMETRY_MD5


def _shared(name: str) -> Path:
    root = Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "/work/shared/data"))
    path = root / name
    if not path.exists():
        pytest.skip(f"shared recording {path} not available")
    return path


def test_the_corridor_bags_pose_data_decode_as_rosbags_decodes_them() -> None:
    path = _shared(CORRIDOR)
    reader = open_reader(path)
    try:
        conns = [c for c in reader.connections if standard_pose_decoder(reader, c)]
        assert {c.msgtype for c in conns} == {"tf2_msgs/msg/TFMessage", "nav_msgs/msg/Odometry"}
        done = 0
        for conn, _, raw in reader.messages(connections=conns):
            decode = standard_pose_decoder(reader, conn)
            assert decode is not None
            mine, theirs = decode(raw), reader.deserialize(raw, conn.msgtype)
            if conn.msgtype.endswith("TFMessage"):
                _same_tf(mine, theirs)
            else:
                _same_odometry(mine, theirs)
            done += 1
        assert done == 802
    finally:
        reader.close()


def test_the_transform_tree_is_the_same_either_way(monkeypatch: pytest.MonkeyPatch) -> None:
    """The corridor bag's poses of its scans, its laser heights and its lasers' frame ids
    through the direct decoders and through rosbags' deserialiser alone: equal."""
    from laserpeople.io import rosbag

    path = _shared(CORRIDOR)

    def poses() -> tuple[list[Any], dict[str, float], dict[str, str]]:
        rec = rosbag.RosbagRecording(path)
        try:
            out = [(s.index, s.pose) for _, s in zip(range(300), rec.scans(), strict=False)]
            return out, rec.laser_heights(), rec.laser_frames()
        finally:
            rec.close()

    fast = poses()
    monkeypatch.setattr(rosbag, "standard_pose_decoder", lambda reader, conn: None)
    monkeypatch.setattr(rosbag, "decode_laserscan", lambda raw: None)
    slow = poses()
    assert fast == slow
    assert sum(p is not None for _, p in fast[0]) > 250
    assert set(fast[2]) == {"/RAWLASER1", "/ROBOTLASER1"} and all(fast[2].values())


def test_a_set_of_definitions_is_built_into_a_typestore_once(tmp_path: Path) -> None:
    from test_io_ros1_reader import _bag

    path = _bag(tmp_path)
    ros1_reader.TYPESTORES.clear()
    with Ros1Reader(path) as first, Ros1Reader(path) as second:
        assert first.typestore is second.typestore
        assert len(ros1_reader.TYPESTORES) == 1


def test_a_wrong_md5_sum_is_refused_at_every_open(tmp_path: Path) -> None:
    """A refused set of definitions is not kept: the second open refuses it too."""
    from rosbags.rosbag1 import Writer

    path = tmp_path / "wrong_md5.bag"
    with Writer(path) as writer:
        msgdef, _ = TS.generate_msgdef("std_msgs/msg/Int32")
        conn = writer.add_connection("/n", "std_msgs/msg/Int32", msgdef=msgdef, md5sum="0" * 32)
        msg = TS.types["std_msgs/msg/Int32"](data=7)
        writer.write(conn, 10**9, TS.serialize_ros1(msg, "std_msgs/msg/Int32"))
    for _ in range(2):
        with pytest.raises(Ros1ReaderError, match="hash mismatch"):
            Ros1Reader(path).open()


def test_the_cache_starts_afresh_when_full(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from test_io_ros1_reader import _bag

    ros1_reader.TYPESTORES.clear()
    monkeypatch.setattr(ros1_reader, "TYPESTORES_KEPT", 1)
    ros1_reader.TYPESTORES[(("x", "y", "z"),)] = object()
    path = _bag(tmp_path)
    with Ros1Reader(path) as reader:
        store = reader.typestore  # (a bag of standard types builds it when asked for)
        assert list(ros1_reader.TYPESTORES.values()) == [store]
