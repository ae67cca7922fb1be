"""ROS 2 messages as CDR bytes, without ROS: decode scans, tf and odometry; encode tracks.

Everything goes through rosbags' typestore (:func:`rosbags.typesys.get_typestore`), which
holds the ROS 2 message definitions and serialises CDR (little-endian, with the 4-byte
encapsulation header that DDS, ``zenoh-bridge-ros2dds`` and ``rmw_zenoh`` put on the wire).
The tracks are the very messages ``laserpeople track --bag`` writes
(:class:`~laserpeople.io.tracks_bag.TracksBagWriter`: ``people_msgs/People`` per kind and one
``visualization_msgs/MarkerArray``), serialised into memory instead of a bag.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from laserpeople.errors import RecordingError
from laserpeople.io.poses import normalise_frame, yaw_and_tilt
from laserpeople.io.rosbag import scan_from_message
from laserpeople.io.rosbag_writer import TF_TYPE, BagSink
from laserpeople.io.tracks_bag import (
    MARKER_TOPIC,
    MARKERS_TYPE,
    PEOPLE_TYPE,
    TRACK_TOPICS,
    TracksBagWriter,
)
from laserpeople.scan import Pose2D, Scan
from laserpeople.tracks import Tracks

SCAN_TYPE = "sensor_msgs/msg/LaserScan"
ODOMETRY_TYPE = "nav_msgs/msg/Odometry"
OUTPUT_PREFIX = "/laserpeople"
"""Prefix of the topics the tracks are published on (as ``track --bag`` writes them)."""


def ros2_typestore() -> Any:
    """A rosbags typestore with the ROS 2 message definitions, ``tf2_msgs/TFMessage`` and
    the ``people_msgs`` types registered."""
    from rosbags.typesys import Stores, get_typestore

    from laserpeople.io.tracks_bag import register_people_types

    store = get_typestore(Stores.LATEST)
    if TF_TYPE not in store.types:
        from rosbags.typesys import get_types_from_msg

        store.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", TF_TYPE))
    register_people_types(store)
    return store


@dataclass(frozen=True)
class Message:
    """One serialised message.

    Attributes:
        topic: ROS topic (with its leading ``/``).
        msgtype: ROS 2 type name (``people_msgs/msg/People``).
        data: CDR bytes.
        stamp: The message's time [s].
    """

    topic: str
    msgtype: str
    data: bytes
    stamp: float


class MemorySink(BagSink):
    """A :class:`~laserpeople.io.rosbag_writer.BagSink` that serialises into a list instead
    of a bag, so the bag writers' messages can go on a wire.

    Args:
        typestore: From :func:`ros2_typestore`.
        prefix: Topics under ``/laserpeople`` are moved under this prefix.

    Attributes:
        messages: The messages serialised since the last :meth:`take`.
    """

    def __init__(self, typestore: Any, prefix: str = OUTPUT_PREFIX) -> None:
        super().__init__(None, typestore, ros1=False)
        self.prefix = prefix
        self.messages: list[Message] = []
        self.frame_ids: dict[str, str] = {}
        """Frame ids replaced in headers (``world`` -> ``odom``, a laser's topic name -> its
        ``header.frame_id``)."""

    def header(self, stamp: float, frame_id: str) -> Any:
        """A header with ``frame_id`` replaced by :attr:`frame_ids`."""
        return super().header(stamp, self.frame_ids.get(frame_id, frame_id))

    def write(self, topic: str, msgtype: str, msg: Any, stamp: float) -> None:
        """Serialise ``msg`` to CDR and keep it."""
        topic = moved_topic(topic, self.prefix)
        data = bytes(self.typestore.serialize_cdr(msg, msgtype))
        self.messages.append(Message(topic, msgtype, data, stamp))

    def take(self) -> list[Message]:
        """The messages serialised since the last call."""
        out, self.messages = self.messages, []
        return out


def moved_topic(topic: str, prefix: str) -> str:
    """``topic`` (under ``/laserpeople``) moved under ``prefix``; other topics as they are."""
    if not topic.startswith(OUTPUT_PREFIX + "/"):
        return topic
    head = "/" + prefix.strip("/") if prefix.strip("/") else ""
    return head + topic[len(OUTPUT_PREFIX) :]


def output_topics(prefix: str = OUTPUT_PREFIX) -> dict[str, str]:
    """Topic -> ROS 2 type of everything :class:`TrackEncoder` publishes."""
    topics = {moved_topic(t, prefix): PEOPLE_TYPE for t in TRACK_TOPICS.values()}
    topics[moved_topic(MARKER_TOPIC, prefix)] = MARKERS_TYPE
    return topics


class TrackEncoder:
    """Tracks of one frame -> the ``track --bag`` messages as CDR bytes.

    Each frame is encoded once: asked again for the frame it encoded last (the same
    ``scans`` and ``tracks`` objects), it gives the same messages, so the publisher and the
    ``--record`` sink share one encoding (see :class:`~laserpeople.live.sinks.RecordSink`).

    Args:
        typestore: From :func:`ros2_typestore`.
        prefix: Topic prefix of the published tracks (default ``/laserpeople``).

    Attributes:
        encoded: Frames encoded so far.
    """

    def __init__(self, typestore: Any, prefix: str = OUTPUT_PREFIX) -> None:
        self.sink = MemorySink(typestore, prefix)
        self._writer = TracksBagWriter(self.sink, scans=False)
        self._last: tuple[tuple[Scan, ...], Tracks, list[Message]] | None = None
        self.encoded = 0

    def encode(self, scans: tuple[Scan, ...], tracks: Tracks) -> list[Message]:
        """The People (people, legs, groups) and MarkerArray messages of one frame."""
        last = self._last
        if last is not None and last[0] is scans and last[1] is tracks:
            return last[2]
        self._writer.write(scans, tracks)
        messages = self.sink.take()
        self._last = (scans, tracks, messages)
        self.encoded += 1
        return messages


@dataclass(frozen=True)
class TransformSample:
    """One planar transform read from ``/tf``, ``/tf_static`` or odometry.

    Attributes:
        parent: Parent frame id (no leading slash).
        child: Child frame id.
        stamp: Time [s].
        pose: Child in parent.
        tilt: Tilt of the child's z axis from vertical [rad].
    """

    parent: str
    child: str
    stamp: float
    pose: Pose2D
    tilt: float


def _stamp(header: Any) -> float:
    return float(header.stamp.sec) + 1e-9 * float(header.stamp.nanosec)


class RosDecoder:
    """CDR bytes -> scans and transforms.

    Args:
        typestore: From :func:`ros2_typestore`.
    """

    def __init__(self, typestore: Any) -> None:
        self.typestore = typestore

    def _decode(self, data: bytes, msgtype: str, topic: str) -> Any:
        try:
            return self.typestore.deserialize_cdr(data, msgtype)
        except Exception as exc:  # any failure of the third-party decoder on foreign bytes
            raise RecordingError(
                f"topic {topic!r}: cannot decode {len(data)} bytes as {msgtype}: {exc}",
                hint="check that the topic carries this type (ros2 topic info)",
            ) from exc

    def scan(self, data: bytes, topic: str, index: int) -> tuple[Scan, str]:
        """A ``sensor_msgs/LaserScan`` as a :class:`Scan` (no pose) and its frame id.

        Raises:
            RecordingError: The bytes are not a LaserScan, or its beams disagree with its
                angles.
        """
        msg = self._decode(data, SCAN_TYPE, topic)
        scan = scan_from_message(msg, _stamp(msg.header), topic, index, f"live {topic}")
        return scan, normalise_frame(str(msg.header.frame_id))

    def transforms(self, data: bytes, topic: str) -> list[TransformSample]:
        """The transforms of a ``tf2_msgs/TFMessage`` (samples with a value that is not
        finite are left out)."""
        msg = self._decode(data, TF_TYPE, topic)
        out = []
        for tr in msg.transforms:
            q, v = tr.transform.rotation, tr.transform.translation
            sample = _sample(tr.header.frame_id, tr.child_frame_id, _stamp(tr.header), v, q)
            if sample is not None:
                out.append(sample)
        return out

    def odometry(self, data: bytes, topic: str) -> list[TransformSample]:
        """The pose of a ``nav_msgs/Odometry`` as a transform (none without a child frame)."""
        msg = self._decode(data, ODOMETRY_TYPE, topic)
        if not str(msg.child_frame_id).strip():
            return []
        p = msg.pose.pose
        sample = _sample(
            msg.header.frame_id, msg.child_frame_id, _stamp(msg.header), p.position, p.orientation
        )
        return [] if sample is None else [sample]


def _sample(parent: str, child: str, stamp: float, v: Any, q: Any) -> TransformSample | None:
    yaw, tilt = yaw_and_tilt(q.x, q.y, q.z, q.w)
    x, y = float(v.x), float(v.y)
    if not all(math.isfinite(a) for a in (stamp, x, y, yaw)):
        return None
    return TransformSample(
        normalise_frame(str(parent)), normalise_frame(str(child)), stamp, Pose2D(x, y, yaw), tilt
    )


class RosEncoder:
    """Scans and transforms -> CDR bytes (what a robot publishes; for tests and benchmarks).

    Args:
        typestore: From :func:`ros2_typestore`.
    """

    def __init__(self, typestore: Any) -> None:
        self.sink = MemorySink(typestore)

    def scan(self, scan: Scan, topic: str, frame_id: str) -> bytes:
        """``scan`` as a ``sensor_msgs/LaserScan``."""
        self.sink.scan(scan, topic, frame_id)
        return self.sink.take()[-1].data

    def transform(self, stamp: float, parent: str, child: str, pose: Pose2D) -> bytes:
        """One transform as a ``tf2_msgs/TFMessage``."""
        self.sink.pose(stamp, parent, child, pose, "/tf")
        return self.sink.take()[-1].data


__all__ = [
    "OUTPUT_PREFIX",
    "MemorySink",
    "Message",
    "RosDecoder",
    "RosEncoder",
    "TrackEncoder",
    "TransformSample",
    "moved_topic",
    "output_topics",
    "ros2_typestore",
]
