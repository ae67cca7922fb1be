"""Writers of ``sensor_msgs/LaserScan`` bags: ROS 1 ``.bag`` and ROS 2 ``.mcap`` / ``.db3``.

:func:`write_laserscan_bag` picks the format by extension. Each scan goes to the topic named
by its ``Scan.sensor`` (ROS 2 topics get a leading ``/``, as ROS 2 requires), with its
header stamp and the bag's log time both equal to ``Scan.stamp``. A scan with a known
pose also produces a ``tf2_msgs/TFMessage`` on ``/tf`` from ``world_frame`` to the scan's
frame at the same stamp, so that :class:`~laserpeople.io.rosbag.RosbagRecording` reads the
poses back.

The bag is written under a temporary name beside the target and moved into place when
done. If the scan stream fails part way, the scans written so far are still closed into a
valid bag at the target path, then the error is raised again.
"""

from __future__ import annotations

import math
import os
import shutil
import tempfile
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from laserpeople.errors import RecordingError
from laserpeople.scan import Pose2D, Scan

ROS1_SUFFIXES = frozenset({".bag"})
ROS2_SUFFIXES = frozenset({".mcap", ".db3"})


def _split_stamp(stamp: float) -> tuple[int, int]:
    sec = math.floor(stamp)
    nanosec = round((stamp - sec) * 1e9)
    if nanosec >= 1_000_000_000:
        sec, nanosec = sec + 1, nanosec - 1_000_000_000
    if sec < 0:
        raise RecordingError(f"stamp {stamp} s is negative; ROS time cannot hold it")
    return int(sec), int(nanosec)


def default_frame_id(sensor: str) -> str:
    """The ``header.frame_id`` written for a sensor when none is given."""
    return sensor.strip("/").replace("/", "_") or "laser"


class _BagSink:
    """Serialises scans and poses into an open rosbags writer."""

    def __init__(self, writer: Any, typestore: Any, ros1: bool) -> None:
        self.writer = writer
        self.typestore = typestore
        self.ros1 = ros1
        self.connections: dict[str, Any] = {}
        self.count = 0
        if "tf2_msgs/msg/TFMessage" not in typestore.types:
            from rosbags.typesys import get_types_from_msg

            typestore.register(
                get_types_from_msg(
                    "geometry_msgs/TransformStamped[] transforms", "tf2_msgs/msg/TFMessage"
                )
            )
        types = typestore.types
        self.Time = types["builtin_interfaces/msg/Time"]
        self.Header = types["std_msgs/msg/Header"]
        self.LaserScan = types["sensor_msgs/msg/LaserScan"]
        self.TFMessage = types["tf2_msgs/msg/TFMessage"]
        self.TransformStamped = types["geometry_msgs/msg/TransformStamped"]
        self.Transform = types["geometry_msgs/msg/Transform"]
        self.Vector3 = types["geometry_msgs/msg/Vector3"]
        self.Quaternion = types["geometry_msgs/msg/Quaternion"]

    def _header(self, stamp: float, frame_id: str) -> Any:
        sec, nanosec = _split_stamp(stamp)
        time = self.Time(sec=sec, nanosec=nanosec)
        if self.ros1:
            return self.Header(seq=0, stamp=time, frame_id=frame_id)
        return self.Header(stamp=time, frame_id=frame_id)

    def _connection(self, topic: str, msgtype: str) -> Any:
        conn = self.connections.get(topic)
        if conn is None:
            conn = self.writer.add_connection(topic, msgtype, typestore=self.typestore)
            self.connections[topic] = conn
        return conn

    def _write(self, topic: str, msgtype: str, msg: Any, stamp: float) -> None:
        conn = self._connection(topic, msgtype)
        data = (
            self.typestore.serialize_ros1(msg, msgtype)
            if self.ros1
            else self.typestore.serialize_cdr(msg, msgtype)
        )
        sec, nanosec = _split_stamp(stamp)
        self.writer.write(conn, sec * 1_000_000_000 + nanosec, data)

    def scan(self, scan: Scan, topic: str, frame_id: str) -> None:
        intensities = (
            np.empty(0, dtype=np.float32)
            if scan.intensities is None
            else np.asarray(scan.intensities, dtype=np.float32)
        )
        msg = self.LaserScan(
            header=self._header(scan.stamp, frame_id),
            angle_min=float(scan.angle_min),
            angle_max=float(scan.angle_max),
            angle_increment=float(scan.angle_increment),
            time_increment=0.0,
            scan_time=0.0,
            range_min=float(scan.range_min),
            range_max=float(scan.range_max),
            ranges=np.asarray(scan.ranges, dtype=np.float32),
            intensities=intensities,
        )
        self._write(topic, "sensor_msgs/msg/LaserScan", msg, scan.stamp)
        self.count += 1

    def pose(self, stamp: float, parent: str, child: str, pose: Pose2D, topic: str) -> None:
        half = 0.5 * pose.theta
        transform = self.Transform(
            translation=self.Vector3(x=float(pose.x), y=float(pose.y), z=0.0),
            rotation=self.Quaternion(x=0.0, y=0.0, z=math.sin(half), w=math.cos(half)),
        )
        stamped = self.TransformStamped(
            header=self._header(stamp, parent), child_frame_id=child, transform=transform
        )
        self._write(topic, "tf2_msgs/msg/TFMessage", self.TFMessage(transforms=[stamped]), stamp)


def write_laserscan_bag(
    path: str | Path,
    scans: Iterable[Scan],
    *,
    frame_ids: Mapping[str, str] | None = None,
    world_frame: str = "odom",
    tf_topic: str | None = "/tf",
) -> int:
    """Write ``scans`` as ``sensor_msgs/LaserScan`` to a ROS 1 ``.bag`` or a ROS 2 ``.mcap`` /
    ``.db3`` file (chosen by the extension of ``path``; an existing file is replaced).

    Args:
        path: Output file.
        scans: Scans in time order (any sensors); streamed, never held in memory.
        frame_ids: ``header.frame_id`` per sensor name (default: the sensor name
            without slashes).
        world_frame: Parent frame of the poses written to ``tf_topic``.
        tf_topic: Topic for the sensor poses, or None to write no poses.

    Returns:
        The number of scans written.

    Raises:
        RecordingError: Unknown extension, or the file cannot be written.
    """
    from rosbags.typesys import Stores, get_typestore

    target = Path(path)
    suffix = target.suffix.lower()
    if suffix not in ROS1_SUFFIXES | ROS2_SUFFIXES:
        raise RecordingError(
            f"cannot write a bag with extension {suffix or '(none)'!r}",
            path=target,
            hint="use .bag (ROS 1), .mcap or .db3 (ROS 2)",
        )
    ros1 = suffix in ROS1_SUFFIXES
    target.parent.mkdir(parents=True, exist_ok=True)
    workdir = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
    frames = dict(frame_ids or {})
    failure: BaseException | None = None
    try:
        if ros1:
            from rosbags.rosbag1 import Writer as Writer1

            written = workdir / "out.bag"
            writer: Any = Writer1(written)
            typestore = get_typestore(Stores.ROS1_NOETIC)
        else:
            from rosbags.rosbag2 import StoragePlugin
            from rosbags.rosbag2 import Writer as Writer2

            plugin = StoragePlugin.MCAP if suffix == ".mcap" else StoragePlugin.SQLITE3
            bagdir = workdir / "out"
            written = bagdir / f"out{suffix}"
            writer = Writer2(bagdir, version=9, storage_plugin=plugin)
            typestore = get_typestore(Stores.LATEST)
        writer.open()
        sink = _BagSink(writer, typestore, ros1)
        try:
            for scan in scans:
                topic = scan.sensor if ros1 or scan.sensor.startswith("/") else f"/{scan.sensor}"
                frame_id = frames.get(scan.sensor) or default_frame_id(scan.sensor)
                sink.scan(scan, topic, frame_id)
                if tf_topic is not None and scan.pose is not None:
                    sink.pose(scan.stamp, world_frame, frame_id, scan.pose, tf_topic)
        except BaseException as exc:  # close what was written into a valid bag, then re-raise
            failure = exc
        writer.close()
        os.replace(written, target)
    except OSError as exc:
        raise RecordingError(f"cannot write bag: {exc}", path=target) from exc
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
    if failure is not None:
        raise failure
    return sink.count
