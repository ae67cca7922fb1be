"""Writers of ``sensor_msgs/LaserScan`` bags: ROS 1 ``.bag`` and ROS 2 ``.mcap`` / ``.db3``.

:func:`write_laserscan_bag` picks the format by extension. Each scan goes to the topic named
by its ``Scan.sensor`` (ROS 2 topics get a leading ``/``, as ROS 2 requires), with its
header stamp and the bag's log time both equal to ``Scan.stamp``. A scan with a known
pose also produces a ``tf2_msgs/TFMessage`` on ``/tf`` from ``world_frame`` to the scan's
frame at the same stamp, so that :class:`~laserpeople.io.rosbag.RosbagRecording` reads the
poses back.

:func:`open_bag` and :class:`BagSink` are the parts underneath, for writers that add
messages of their own (the Foxglove export adds markers). A bag is written under a
temporary name beside the target and moved into place when the ``with`` block ends
normally; if the block raises, nothing is left behind.
"""

from __future__ import annotations

import math
import os
import shutil
import warnings
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import Any

import numpy as np

from laserpeople.errors import LaserPeopleWarning, RecordingError
from laserpeople.scan import Pose2D, Scan

ROS1_SUFFIXES = frozenset({".bag"})
ROS2_SUFFIXES = frozenset({".mcap", ".db3"})
SCAN_TYPE = "sensor_msgs/msg/LaserScan"
TF_TYPE = "tf2_msgs/msg/TFMessage"


def split_stamp(stamp: float) -> tuple[int, int]:
    """A stamp in seconds as ROS time ``(sec, nanosec)``, nanoseconds rounded.

    Raises:
        RecordingError: The stamp is negative.
    """
    sec = math.floor(stamp)
    nanosec = round((stamp - sec) * 1e9)
    if nanosec >= 1_000_000_000:
        sec, nanosec = sec + 1, nanosec - 1_000_000_000
    if sec < 0:
        raise RecordingError(f"stamp {stamp} s is negative; ROS time cannot hold it")
    return int(sec), int(nanosec)


def sensor_topic(sensor: str, *, ros1: bool = False) -> str:
    """The topic a sensor's scans are written to: its name, with the leading ``/`` that
    ROS 2 requires (ROS 1 topics are written as named)."""
    return sensor if ros1 or sensor.startswith("/") else f"/{sensor}"


def sensor_frame_id(sensor: str) -> str:
    """The ``header.frame_id`` written for a sensor when none is given: its name without
    slashes."""
    return sensor.strip("/").replace("/", "_") or "laser"


class BagSink:
    """Serialises messages into an open rosbags writer, one connection per topic.

    Attributes:
        typestore: The rosbags typestore the messages are built from and serialised with.
        ros1: Whether the bag is ROS 1 (ROS 1 serialisation, headers with ``seq``).
        count: Scans written so far with :meth:`scan`.
    """

    def __init__(self, writer: Any, typestore: Any, ros1: bool) -> None:
        self.writer = writer
        self.typestore = typestore
        self.ros1 = ros1
        self.count = 0
        self._connections: dict[str, Any] = {}
        if TF_TYPE not in typestore.types:
            from rosbags.typesys import get_types_from_msg

            typestore.register(
                get_types_from_msg("geometry_msgs/TransformStamped[] transforms", TF_TYPE)
            )

    def header(self, stamp: float, frame_id: str) -> Any:
        """A ``std_msgs/Header`` with ``stamp`` [s] and ``frame_id``."""
        types = self.typestore.types
        sec, nanosec = split_stamp(stamp)
        time = types["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec)
        if self.ros1:
            return types["std_msgs/msg/Header"](seq=0, stamp=time, frame_id=frame_id)
        return types["std_msgs/msg/Header"](stamp=time, frame_id=frame_id)

    def write(self, topic: str, msgtype: str, msg: Any, stamp: float) -> None:
        """Serialise ``msg`` of type ``msgtype`` onto ``topic`` with log time ``stamp`` [s]."""
        data = (
            self.typestore.serialize_ros1(msg, msgtype)
            if self.ros1
            else self.typestore.serialize_cdr(msg, msgtype)
        )
        self.write_serialised(topic, msgtype, data, stamp)

    def write_serialised(self, topic: str, msgtype: str, data: bytes, stamp: float) -> None:
        """Write a message already serialised (ROS 1 bytes in a ``.bag``, CDR otherwise)
        onto ``topic`` with log time ``stamp`` [s]."""
        conn = self._connections.get(topic)
        if conn is None:
            conn = self.writer.add_connection(topic, msgtype, typestore=self.typestore)
            self._connections[topic] = conn
        sec, nanosec = split_stamp(stamp)
        self.writer.write(conn, sec * 1_000_000_000 + nanosec, data)

    def scan(self, scan: Scan, topic: str, frame_id: str, log_stamp: float | None = None) -> None:
        """Write ``scan`` as a ``sensor_msgs/LaserScan`` stamped ``scan.stamp``, logged at
        ``log_stamp`` [s] (default: the same; another models a message received later)."""
        intensities = (
            np.empty(0, dtype=np.float32)
            if scan.intensities is None
            else np.asarray(scan.intensities, dtype=np.float32)
        )
        msg = self.typestore.types[SCAN_TYPE](
            header=self.header(scan.stamp, frame_id),
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
        self.write(topic, SCAN_TYPE, msg, scan.stamp if log_stamp is None else log_stamp)
        self.count += 1

    def pose(self, stamp: float, parent: str, child: str, pose: Pose2D, topic: str) -> None:
        """Write ``pose`` of ``child`` in ``parent`` as a one-transform ``TFMessage``."""
        types = self.typestore.types
        half = 0.5 * pose.theta
        transform = types["geometry_msgs/msg/Transform"](
            translation=types["geometry_msgs/msg/Vector3"](x=float(pose.x), y=float(pose.y), z=0.0),
            rotation=types["geometry_msgs/msg/Quaternion"](
                x=0.0, y=0.0, z=math.sin(half), w=math.cos(half)
            ),
        )
        stamped = types["geometry_msgs/msg/TransformStamped"](
            header=self.header(stamp, parent), child_frame_id=child, transform=transform
        )
        self.write(topic, TF_TYPE, types[TF_TYPE](transforms=[stamped]), stamp)


@contextmanager
def open_bag(path: str | Path) -> Iterator[BagSink]:
    """Open a bag for writing; the format follows the extension (``.bag`` ROS 1 Noetic,
    ``.mcap`` / ``.db3`` ROS 2). An existing file is replaced when the block ends normally;
    if the block raises, the partial bag is discarded and the error passes through.

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
    from laserpeople.io.paths import left_by_killed_runs, staging_folder

    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        workdir = staging_folder(target)
    except OSError as exc:
        raise _unwritable(exc, target) from exc
    for left in left_by_killed_runs(target):
        warnings.warn(
            f"{target}: {left.name} beside it was left by an earlier run writing it that was "
            "killed (a bag without its index, not used): remove it",
            LaserPeopleWarning,
            stacklevel=3,
        )
    try:
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
        except OSError as exc:
            raise _unwritable(exc, target) from exc
        try:
            yield BagSink(writer, typestore, ros1)
        except BaseException:
            with suppress(Exception):  # the block's own error is the one to report
                writer.close()
            raise
        try:
            writer.close()
            os.replace(written, target)
        except OSError as exc:
            raise _unwritable(exc, target) from exc
    finally:
        shutil.rmtree(workdir, ignore_errors=True)


def _unwritable(exc: OSError, target: Path) -> RecordingError:
    """The error for a bag that could not be written: the system's reason, not the
    temporary file the bag is assembled in."""
    from laserpeople.io.paths import why_unwritable

    return RecordingError(
        f"cannot write the bag: {why_unwritable(exc, target)}",
        path=target,
        hint="free disk space, or give a path in a writable directory",
    )


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

    If the scan stream fails part way, the scans written so far are still closed into a
    valid bag at ``path``, then the error is raised again.

    Args:
        path: Output file.
        scans: Scans in time order (any sensors); streamed, never held in memory.
        frame_ids: ``header.frame_id`` per sensor name (default: :func:`sensor_frame_id`).
        world_frame: Parent frame of the poses written to ``tf_topic``.
        tf_topic: Topic for the sensor poses, or None to write no poses.

    Returns:
        The number of scans written.

    Raises:
        RecordingError: Unknown extension, or the file cannot be written.
    """
    frames = dict(frame_ids or {})
    failure: BaseException | None = None
    with open_bag(path) as sink:
        try:
            for scan in scans:
                frame_id = frames.get(scan.sensor) or sensor_frame_id(scan.sensor)
                sink.scan(scan, sensor_topic(scan.sensor, ros1=sink.ros1), frame_id)
                if tf_topic is not None and scan.pose is not None:
                    sink.pose(scan.stamp, world_frame, frame_id, scan.pose, tf_topic)
        except BaseException as exc:  # close what was written into a valid bag, then re-raise
            failure = exc
    if failure is not None:
        raise failure
    return sink.count
