"""Play a ROS bag into Zenoh as a robot would publish it (scans, /tf, odometry as CDR).

For trying ``laserpeople live`` without a robot, and for the tests and benchmarks: every
``sensor_msgs/LaserScan``, ``tf2_msgs/TFMessage`` and ``nav_msgs/Odometry`` message of the
bag goes out on its topic, in the bag's log-time order, at ``speed`` times the recorded
rate (ROS 1 messages are converted to CDR by rosbags; ROS 2 messages go out as recorded).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from laserpeople.errors import RecordingError
from laserpeople.live.messages import ODOMETRY_TYPE, SCAN_TYPE, Message
from laserpeople.live.runner import TF_TYPE

PLAYED_TYPES = (SCAN_TYPE, TF_TYPE, ODOMETRY_TYPE)


@dataclass
class ReplayCounts:
    """What a replay sent.

    Attributes:
        messages: Messages sent, per topic.
        seconds: Wall time of the replay [s].
    """

    messages: dict[str, int]
    seconds: float = 0.0


def replay_bag(
    path: str | Path,
    publish: Callable[[Sequence[Message]], None],
    *,
    speed: float = 1.0,
    topics: Sequence[str] | None = None,
    max_scans: int | None = None,
    should_stop: Callable[[], bool] = lambda: False,
) -> ReplayCounts:
    """Publish the scans, transforms and odometry of the bag ``path``.

    Args:
        path: A ROS 1 ``.bag`` or ROS 2 bag.
        publish: Sends messages (e.g. ``Publishers(...).publish``).
        speed: Multiple of the recorded rate (``inf``: as fast as possible).
        topics: Laser topics to play (default: every one); transforms always go.
        max_scans: Stop after this many scans (all lasers).
        should_stop: Checked between messages.

    Raises:
        RecordingError: The bag cannot be read, or has none of ``topics``.
    """
    from rosbags.highlevel import AnyReader

    if not speed > 0:
        raise RecordingError(f"replay speed {speed} must be positive", path=path)
    from laserpeople.live.messages import ros2_typestore

    typestore = ros2_typestore()
    counts: dict[str, int] = {}
    scans = 0
    start = time.monotonic()
    try:
        with AnyReader([Path(path)]) as reader:
            conns = [
                c
                for c in reader.connections
                if c.msgtype in PLAYED_TYPES
                and (c.msgtype != SCAN_TYPE or topics is None or c.topic in topics)
            ]
            if not any(c.msgtype == SCAN_TYPE for c in conns):
                raise RecordingError(
                    f"no laser topic {', '.join(topics or [])} to replay".strip(), path=path
                )
            first: int | None = None
            for conn, log_time, raw in reader.messages(connections=conns):
                if should_stop():
                    break
                first = log_time if first is None else first
                due = start + (log_time - first) * 1e-9 / speed
                wait = due - time.monotonic()
                if wait > 0:
                    time.sleep(wait)
                data = _cdr(reader, raw, conn.msgtype, typestore)
                publish([Message(conn.topic, conn.msgtype, data, log_time * 1e-9)])
                counts[conn.topic] = counts.get(conn.topic, 0) + 1
                if conn.msgtype == SCAN_TYPE:
                    scans += 1
                    if max_scans is not None and scans >= max_scans:
                        break
    except RecordingError:
        raise
    except Exception as exc:  # rosbags' errors on a damaged or foreign file
        raise RecordingError(f"cannot replay: {exc}", path=path) from exc
    return ReplayCounts(counts, time.monotonic() - start)


def _cdr(reader: Any, raw: bytes, msgtype: str, typestore: Any) -> bytes:
    if reader.is2:
        return bytes(raw)
    # a ROS 1 message, decoded with the bag's own definitions, re-encoded as ROS 2 CDR
    # (the ROS 2 definitions leave out the header's seq)
    return bytes(typestore.serialize_cdr(reader.deserialize(raw, msgtype), msgtype))


__all__ = ["ReplayCounts", "replay_bag"]
