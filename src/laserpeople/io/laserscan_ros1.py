"""Direct decoding of ROS 1 ``sensor_msgs/LaserScan`` messages with ``np.frombuffer``.

A ROS 1 LaserScan is serialised little-endian without padding::

    uint32 seq, uint32 sec, uint32 nsec, uint32 n + n bytes frame_id,
    float32 angle_min, angle_max, angle_increment, time_increment, scan_time,
    range_min, range_max,
    uint32 n + n float32 ranges, uint32 m + m float32 intensities

:func:`decode_laserscan` reads exactly that (the ranges and intensities as float32 views
of the message bytes, as rosbags' own deserialiser gives them) and returns None when the
bytes do not follow it to the last byte, so that the caller falls back to rosbags' generic
deserialiser (which names what is wrong). Only a connection whose type is the standard
LaserScan, by its MD5 sum, may use it (:func:`is_standard_laserscan`).
"""

from __future__ import annotations

import struct
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

LASERSCAN_MD5 = "90c7ef2dc6895d81024acba2ac42f369"
"""MD5 sum of the standard ``sensor_msgs/LaserScan`` definition (ROS 1)."""

_HEAD = struct.Struct("<IIII")  # seq, sec, nsec, frame_id length
_BODY = struct.Struct("<7fI")  # angles, increments, limits, ranges length
_COUNT = struct.Struct("<I")


class Time(NamedTuple):
    """``builtin_interfaces/Time`` as rosbags names its fields."""

    sec: int
    nanosec: int


class Header(NamedTuple):
    """``std_msgs/Header``."""

    seq: int
    stamp: Time
    frame_id: str


class LaserScanMessage(NamedTuple):
    """The fields of a decoded LaserScan that the readers use (rosbags' names)."""

    header: Header
    angle_min: float
    angle_max: float
    angle_increment: float
    time_increment: float
    scan_time: float
    range_min: float
    range_max: float
    ranges: NDArray[np.float32]
    intensities: NDArray[np.float32]


def is_standard_laserscan(reader: Any, conn: Any) -> bool:
    """Whether messages of ``conn`` in ``reader`` are ROS 1 standard LaserScans."""
    return (
        not getattr(reader, "is2", True)
        and conn.msgtype == "sensor_msgs/msg/LaserScan"
        and getattr(conn, "digest", None) == LASERSCAN_MD5
    )


def decode_laserscan(raw: bytes | bytearray | memoryview) -> LaserScanMessage | None:
    """The LaserScan serialised in ``raw`` (ROS 1), or None when ``raw`` does not follow
    the layout of the module docstring exactly (too short, too long, a length beyond the
    end, a frame id that is not UTF-8)."""
    size = len(raw)
    if size < _HEAD.size:
        return None
    seq, sec, nsec, n_id = _HEAD.unpack_from(raw, 0)
    at = _HEAD.size + n_id
    if at + _BODY.size > size:
        return None
    try:
        frame_id = bytes(raw[_HEAD.size : at]).decode("utf-8")
    except UnicodeDecodeError:
        return None
    a_min, a_max, a_inc, t_inc, t_scan, r_min, r_max, n = _BODY.unpack_from(raw, at)
    at += _BODY.size
    if at + 4 * n + _COUNT.size > size:
        return None
    ranges = np.frombuffer(raw, dtype="<f4", count=n, offset=at)
    at += 4 * n
    (m,) = _COUNT.unpack_from(raw, at)
    at += _COUNT.size
    if at + 4 * m != size:
        return None
    intensities = np.frombuffer(raw, dtype="<f4", count=m, offset=at)
    return LaserScanMessage(
        Header(seq, Time(sec, nsec), frame_id),
        a_min,
        a_max,
        a_inc,
        t_inc,
        t_scan,
        r_min,
        r_max,
        ranges,
        intensities,
    )


__all__ = [
    "LASERSCAN_MD5",
    "LaserScanMessage",
    "decode_laserscan",
    "is_standard_laserscan",
]
