"""Direct decoding of ROS 1 ``tf2_msgs/TFMessage`` (and ``tf/tfMessage``) and
``nav_msgs/Odometry`` messages, the pose data a bag's transform tree is read from.

Both are serialised little-endian without padding::

    TFMessage: uint32 n, then n times
        uint32 seq, uint32 sec, uint32 nsec, uint32 k + k bytes frame_id,
        uint32 k + k bytes child_frame_id,
        float64 translation x, y, z, float64 rotation x, y, z, w
    Odometry:
        uint32 seq, uint32 sec, uint32 nsec, uint32 k + k bytes frame_id,
        uint32 k + k bytes child_frame_id,
        float64 position x, y, z, orientation x, y, z, w, float64[36] pose covariance,
        float64 linear x, y, z, angular x, y, z, float64[36] twist covariance

:func:`decode_tf_message` and :func:`decode_odometry` read exactly that (the fields
:meth:`~laserpeople.io.rosbag.RosbagRecording.transform_tree` uses, the same floats and
strings as rosbags' deserialiser gives) and return None when the bytes do not follow it to
the last byte, so that the caller falls back to rosbags' deserialiser (which names what is
wrong). rosbags generates its deserialisers' code at the first message of a type: on the
corridor bag (401 transforms and 401 odometry messages) reading the pose data took 40 ms of
CPU that way, and a few ms decoded here. Only a connection whose type is the standard one,
by its MD5 sum, may use them (:func:`standard_pose_decoder`).
"""

from __future__ import annotations

import struct
from collections.abc import Callable
from typing import Any, NamedTuple

from laserpeople.io.laserscan_ros1 import Header, Time

TF_MD5 = "94810edda583a504dfda3829e70d7eec"
"""MD5 sum of the standard ``tf2_msgs/TFMessage`` definition (ROS 1; ``tf/tfMessage``
has the same fields and sum)."""

ODOMETRY_MD5 = "cd5e73d190d741a2f92e81eda573aca7"
"""MD5 sum of the standard ``nav_msgs/Odometry`` definition (ROS 1)."""

_U32 = struct.Struct("<I")
_STAMP = struct.Struct("<III")  # seq, sec, nsec
_SEVEN = struct.Struct("<7d")  # a translation and a rotation (or a position and orientation)
_COVARIANCE = 36 * 8  # bytes of a float64[36]
_TWIST = 6 * 8  # bytes of a linear and an angular vector


class Vector3(NamedTuple):
    """``geometry_msgs/Vector3`` (and ``Point``)."""

    x: float
    y: float
    z: float


class Quaternion(NamedTuple):
    """``geometry_msgs/Quaternion``."""

    x: float
    y: float
    z: float
    w: float


class Transform(NamedTuple):
    """``geometry_msgs/Transform``."""

    translation: Vector3
    rotation: Quaternion


class TransformStamped(NamedTuple):
    """``geometry_msgs/TransformStamped``."""

    header: Header
    child_frame_id: str
    transform: Transform


class TFMessage(NamedTuple):
    """``tf2_msgs/TFMessage``."""

    transforms: list[TransformStamped]


class Pose(NamedTuple):
    """``geometry_msgs/Pose``."""

    position: Vector3
    orientation: Quaternion


class PoseWithCovariance(NamedTuple):
    """``geometry_msgs/PoseWithCovariance`` without its covariance (not read)."""

    pose: Pose


class Odometry(NamedTuple):
    """The fields of ``nav_msgs/Odometry`` that the transform tree reads."""

    header: Header
    child_frame_id: str
    pose: PoseWithCovariance


def _string(raw: Any, at: int, size: int) -> tuple[str, int] | None:
    """The UTF-8 string at ``at`` (its uint32 length first) and the offset after it; None
    when it does not fit in ``size`` bytes or is not UTF-8."""
    if at + 4 > size:
        return None
    (k,) = _U32.unpack_from(raw, at)
    at += 4
    if at + k > size:
        return None
    try:
        return bytes(raw[at : at + k]).decode("utf-8"), at + k
    except UnicodeDecodeError:
        return None


def _header_and_child(raw: Any, at: int, size: int) -> tuple[Header, str, int] | None:
    """A ``Header`` and a ``child_frame_id`` from ``at``, and the offset after them."""
    if at + _STAMP.size > size:
        return None
    seq, sec, nsec = _STAMP.unpack_from(raw, at)
    frame = _string(raw, at + _STAMP.size, size)
    if frame is None:
        return None
    child = _string(raw, frame[1], size)
    if child is None:
        return None
    return Header(seq, Time(sec, nsec), frame[0]), child[0], child[1]


def _pose(raw: Any, at: int) -> tuple[Vector3, Quaternion]:
    """Three and four float64 from ``at`` (the caller checked they fit)."""
    x, y, z, qx, qy, qz, qw = _SEVEN.unpack_from(raw, at)
    return Vector3(x, y, z), Quaternion(qx, qy, qz, qw)


def decode_tf_message(raw: bytes | bytearray | memoryview) -> TFMessage | None:
    """The TFMessage serialised in ``raw`` (ROS 1), or None when ``raw`` does not follow
    the layout of the module docstring exactly."""
    size = len(raw)
    if size < 4:
        return None
    (n,) = _U32.unpack_from(raw, 0)
    at = 4
    out: list[TransformStamped] = []
    for _ in range(n):
        head = _header_and_child(raw, at, size)
        if head is None:
            return None
        header, child, at = head
        if at + _SEVEN.size > size:
            return None
        v, q = _pose(raw, at)
        at += _SEVEN.size
        out.append(TransformStamped(header, child, Transform(v, q)))
    return TFMessage(out) if at == size else None


def decode_odometry(raw: bytes | bytearray | memoryview) -> Odometry | None:
    """The Odometry serialised in ``raw`` (ROS 1), or None when ``raw`` does not follow
    the layout of the module docstring exactly."""
    size = len(raw)
    head = _header_and_child(raw, 0, size)
    if head is None:
        return None
    header, child, at = head
    if at + _SEVEN.size + _COVARIANCE + _TWIST + _COVARIANCE != size:
        return None
    v, q = _pose(raw, at)
    return Odometry(header, child, PoseWithCovariance(Pose(v, q)))


_DECODERS: dict[tuple[str, str], Callable[[Any], Any]] = {
    ("tf2_msgs/msg/TFMessage", TF_MD5): decode_tf_message,
    ("tf/msg/tfMessage", TF_MD5): decode_tf_message,
    ("nav_msgs/msg/Odometry", ODOMETRY_MD5): decode_odometry,
}


def standard_pose_decoder(reader: Any, conn: Any) -> Callable[[Any], Any] | None:
    """The direct decoder of ``conn``'s messages in ``reader`` when they are ROS 1 standard
    TFMessages or Odometry messages (by type and MD5 sum), else None."""
    if getattr(reader, "is2", True):
        return None
    return _DECODERS.get((conn.msgtype, getattr(conn, "digest", None) or ""))


__all__ = [
    "ODOMETRY_MD5",
    "TF_MD5",
    "decode_odometry",
    "decode_tf_message",
    "standard_pose_decoder",
]
