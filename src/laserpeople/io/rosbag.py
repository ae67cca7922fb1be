"""Reader of ROS bags (ROS 1 ``.bag``, ROS 2 ``.db3``/``.mcap`` or bag folders) via ``rosbags``.

Every ``sensor_msgs/LaserScan`` topic is a sensor. :meth:`RosbagRecording.scans` streams
the scans of one or several topics in the order of their header stamps, one message at a
time (constant memory; each topic is read by its own bag reader and the streams are
merged). ``Scan.sensor`` is the topic name, ``Scan.index`` the 0-based index of the
message on its topic, ``Scan.stamp`` the header stamp (the bag's receive time only when
the header stamp is zero; :attr:`RosbagRecording.scans_with_log_time` counts those).

Sensor poses come from ``/tf`` and ``/tf_static`` and from ``nav_msgs/Odometry`` topics
(see :mod:`laserpeople.io.poses`). The pose topics are read once, before the first scan,
and kept in memory (a few numbers per transform message). A scan with no pose gets
``pose=None``; :attr:`RosbagRecording.scans_without_pose` counts them and
:meth:`RosbagRecording.pose_summary` says why.
"""

from __future__ import annotations

import heapq
import math
import tempfile
from collections import Counter, defaultdict
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from laserpeople.errors import (
    MessageTypeError,
    RecordingError,
    TopicNotFoundError,
    UnsortedStampsError,
)
from laserpeople.io.bag_guard import CORRUPT_HINT, describe, open_reader
from laserpeople.io.damage import BACKWARD_HINT, DamagedRecords, OnError, stamp_back
from laserpeople.io.laserscan_ros1 import decode_laserscan, is_standard_laserscan
from laserpeople.io.mcap_tail import ended_copy, missing_end, whole_records
from laserpeople.io.npz import TopicInfo
from laserpeople.io.paths import not_found
from laserpeople.io.pose_msgs_ros1 import standard_pose_decoder
from laserpeople.io.poses import (
    KNOWN_MOUNTS,
    PoseParams,
    PoseSamples,
    TransformTree,
    add_mounts,
    mounts_to_use,
    normalise_frame,
    stray_mount_notes,
    yaw_and_tilt,
)
from laserpeople.io.topics import match_topics
from laserpeople.scan import Pose2D, Scan
from laserpeople.spelling import did_you_mean
from laserpeople.truth import TruthFrame

LASERSCAN = "sensor_msgs/msg/LaserScan"
TF_TYPES = frozenset({"tf2_msgs/msg/TFMessage", "tf/msg/tfMessage"})
ODOMETRY_TYPES = frozenset({"nav_msgs/msg/Odometry"})
_LASERSCAN_FIELDS = frozenset(
    {"header", "angle_min", "angle_max", "angle_increment", "range_min", "range_max", "ranges"}
)
_CORRUPT_HINT = CORRUPT_HINT
_describe = describe


METADATA_LIMIT = 1 * 2**20
"""Largest ``metadata.yaml`` of a ROS 2 bag folder [bytes] (real ones are a few KiB)."""
METADATA_DEPTH = 64
"""Deepest nesting of ``[`` / ``{`` in ``metadata.yaml`` (real ones nest 3 deep)."""


def _check_metadata(path: Path) -> None:
    """Refuse a ``metadata.yaml`` that is too large or nested too deep to parse quickly."""
    try:
        size = path.stat().st_size
        if size > METADATA_LIMIT:
            raise RecordingError(
                f"metadata.yaml is {size} bytes, more than the {METADATA_LIMIT} accepted",
                path=path,
                hint="the bag's metadata is damaged; regenerate it with `ros2 bag reindex`",
            )
        text = path.read_bytes()
    except OSError as exc:
        raise RecordingError(f"cannot read metadata.yaml: {exc}", path=path) from exc
    depth = deepest = 0
    for byte in text:
        if byte in b"[{":
            depth += 1
            deepest = max(deepest, depth)
        elif byte in b"]}":
            depth = max(depth - 1, 0)
    if deepest > METADATA_DEPTH:
        raise RecordingError(
            f"metadata.yaml nests {deepest} levels deep (at most {METADATA_DEPTH} accepted)",
            path=path,
            hint="the bag's metadata is damaged; regenerate it with `ros2 bag reindex`",
        )


def _check_connection(conn: Any, path: Path) -> None:
    """The bag's index entry of a topic has a text name and type and an integer count."""
    ok = (
        isinstance(conn.topic, str)
        and isinstance(conn.msgtype, str)
        and isinstance(conn.msgcount, int)
        and not isinstance(conn.msgcount, bool)
        and conn.msgcount >= 0
    )
    if not ok:
        raise RecordingError(
            f"the bag's index describes a topic as name {conn.topic!r:.60}, type "
            f"{conn.msgtype!r:.60}, count {conn.msgcount!r:.30}",
            path=path,
            hint=_CORRUPT_HINT,
        )


def scan_from_message(
    msg: Any, stamp: float, topic: str, index: int, source: str, *, intensities: bool = True
) -> Scan:
    """A :class:`Scan` of a decoded ``sensor_msgs/LaserScan`` (no pose yet); without its
    intensities when ``intensities`` is False.

    Raises:
        RecordingError: its beams disagree with its angles or limits (``Scan.from_angles``).
    """
    values = msg.intensities if intensities and len(msg.intensities) else None
    return Scan.from_angles(
        stamp,
        float(msg.angle_min),
        float(msg.angle_max),
        float(msg.angle_increment),
        msg.ranges,
        range_min=float(msg.range_min),
        range_max=float(msg.range_max),
        intensities=values,
        sensor=topic,
        pose=None,
        index=index,
        source=source,
    )


def _stamp(header: Any) -> float:
    return float(header.stamp.sec) + 1e-9 * float(header.stamp.nanosec)


def _is_laserscan(reader: Any, msgtype: str) -> bool:
    """LaserScan itself, or a custom type defined in the bag with LaserScan's fields."""
    if msgtype == LASERSCAN:
        return True
    standard = getattr(reader, "is_standard", None)
    if standard is not None and standard(msgtype):  # (TFMessage, Odometry: no typestore built)
        return False
    fields = reader.typestore.fielddefs.get(msgtype)
    if not fields:
        return False
    return {name for name, _ in fields[1]} >= _LASERSCAN_FIELDS


class RosbagRecording:
    """A ROS 1 or ROS 2 bag as a :class:`~laserpeople.io.RecordingSource`.

    Args:
        path: A ``.bag`` file, a ``.db3`` or ``.mcap`` file, or a ROS 2 bag folder.
        poses: Look up sensor poses (``False``: every scan gets ``pose=None``, uncounted).
        world_frame: Fixed frame the poses are given in; default: the first of
            :attr:`PoseParams.world_frames` present, else the root of the lasers' frames.
        odometry_topics: ``nav_msgs/Odometry`` topics to use (default: all of them); a
            transform already on ``/tf`` is taken from there.
        mounts: Extra fixed transforms ``child frame -> (parent frame, pose)`` for laser
            mounts a bag lacks; they win over the bag's own, unless they would cut a laser
            off from the bag's own transforms (see
            :func:`~laserpeople.io.poses.mounts_to_use`; listed in :attr:`mount_notes`).
        pose_params: Interpolation tolerances.
        on_error: ``"stop"`` (default) ends at the first damaged scan with an error naming
            it; ``"skip"`` leaves damaged scans out and counts them in :attr:`damaged`
            (see :mod:`laserpeople.io.damage`).

    Raises:
        RecordingError: The file is missing, corrupt, truncated or not a bag.
    """

    def __init__(
        self,
        path: str | Path,
        *,
        poses: bool = True,
        world_frame: str | None = None,
        odometry_topics: Sequence[str] | None = None,
        mounts: Mapping[str, tuple[str, Pose2D]] | None = None,
        pose_params: PoseParams | None = None,
        on_error: OnError = "stop",
    ) -> None:
        self.path = Path(path)
        self.damaged = DamagedRecords(self.path, on_error)
        if not self.path.exists():
            raise RecordingError(not_found(self.path), path=self.path, hint="check the path")
        if self.path.is_dir() and not (self.path / "metadata.yaml").is_file():
            raise RecordingError(
                "is a directory, not a bag",
                path=self.path,
                hint="give a .bag/.mcap/.db3 file, or a ROS 2 bag folder with metadata.yaml",
            )
        self.use_poses = poses
        self.pose_params = pose_params or PoseParams()
        self._world_request = world_frame
        self._odometry_request = None if odometry_topics is None else tuple(odometry_topics)
        self._mounts = dict(mounts or {})
        if self.path.is_dir():
            _check_metadata(self.path / "metadata.yaml")
        self._read_path = self.path
        self._copy_dir: tempfile.TemporaryDirectory[str] | None = None
        if missing_end(self.path):
            self._read_up_to_the_cut()
        self._reader = self._open()
        self._connections: dict[str, list[Any]] = defaultdict(list)
        for conn in self._reader.connections:
            _check_connection(conn, self.path)
            self._connections[conn.topic].append(conn)
        self._tree: TransformTree | None = None
        self._mount_z: dict[str, tuple[str, float]] = {}
        """Parent frame and z translation [m] per child frame, for :meth:`laser_heights`."""
        self._static_z: set[str] = set()
        self.world_frame: str | None = None
        self.scans_without_pose = 0
        self.scans_with_log_time = 0
        self.scans_read = 0
        self.pose_misses: Counter[tuple[str, str]] = Counter()
        self.pose_messages_skipped = 0
        self.pose_samples_dropped = 0
        self.mount_notes: list[str] = []
        """Given mounts left out, one line each (see
        :func:`~laserpeople.io.poses.mounts_to_use`)."""
        self.frame_changes: dict[str, FrameChange] = {}
        """Per laser topic whose ``header.frame_id`` changed within the last read: the
        first frame, the first scan in another frame and how many scans were in others."""
        self._first_frames: dict[str, str] = {}  # laser topic -> its first scan's frame
        self.other_types: dict[str, dict[str, int]] = {}
        """Per laser topic of the last read that also carries other types of message: their
        counts by type (left out of the scans)."""

    # -- opening -------------------------------------------------------------------------
    def _open(self) -> Any:
        try:
            return open_reader(self._read_path)
        except RecordingError as exc:  # (the copy of an MCAP cut short: name the file)
            raise exc.moved(self._read_path, self.path) from exc

    def _read_up_to_the_cut(self) -> None:
        """An MCAP without its end records: an error (``stop``), or (``skip``) read from a
        copy of its whole records, ended, with what was left out in :attr:`damaged`."""
        size = self.path.stat().st_size
        kept, records = whole_records(self.path)
        what = (
            "the MCAP ends without its end records (the recorder was stopped before it "
            "closed the file, or the copy was cut short)"
        )
        if not records:
            raise RecordingError(
                f"{what}, and no record before the cut is whole: nothing can be read",
                path=self.path,
                hint="re-copy or re-record it",
            )
        if self.damaged.on_error == "stop":
            raise RecordingError(
                what,
                path=self.path,
                hint=f"--on-error skip reads its whole records, {kept:,} of its {size:,} bytes; "
                "`mcap recover` writes a repaired copy",
            )
        try:
            self._copy_dir = tempfile.TemporaryDirectory(prefix="laserpeople-mcap-")
            self._read_path, _ = ended_copy(self.path, self._copy_dir.name)
        except OSError as exc:
            if self._copy_dir is not None:
                self._copy_dir.cleanup()
                self._copy_dir = None
            raise RecordingError(
                f"{what}; its whole records cannot be copied to read them "
                f"({exc.strerror or exc}, in {tempfile.gettempdir()})",
                path=self.path,
                hint="free space there or point TMPDIR elsewhere; or `mcap recover` it",
            ) from exc
        self.damaged.cut = (
            f"{what}: read its whole records, {kept:,} of its {size:,} bytes; the "
            f"{size - kept:,} bytes after the cut are left out"
            if kept < size
            else f"{what}: read its {size:,} bytes, whole records up to the cut"
        )

    def __enter__(self) -> RosbagRecording:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Close the bag (and remove the copy of an MCAP cut short)."""
        if self._reader is not None and self._reader.stack is not None:
            self._reader.close()
        if self._copy_dir is not None:
            self._copy_dir.cleanup()
            self._copy_dir = None

    # -- topics ----------------------------------------------------------------------------
    @property
    def has_truth(self) -> bool:
        """Bags carry no ground truth in this project's sense."""
        return False

    def truth(self) -> Iterator[TruthFrame]:
        """No ground truth in bags: an empty stream."""
        return iter(())

    def all_topics(self) -> list[TopicInfo]:
        """Every topic of the bag with its message type and count."""
        return [
            TopicInfo(topic, conns[0].msgtype, sum(c.msgcount for c in conns))
            for topic, conns in self._connections.items()
        ]

    def topics(self) -> list[TopicInfo]:
        """The laser scan topics with the counts of their laser scans (a topic that carries
        other types of message too is one: those are left out of its scans, and said)."""
        found = []
        for topic, conns in self._connections.items():
            lasers = [c for c in conns if _is_laserscan(self._reader, c.msgtype)]
            if lasers:
                found.append(TopicInfo(topic, lasers[0].msgtype, sum(c.msgcount for c in lasers)))
        return found

    def _match(self, topics: Sequence[str], what: str, hint: str) -> list[str]:
        """Bag topic names for ``topics`` (a leading slash is optional)."""
        return match_topics(
            topics,
            list(self._connections),
            key=lambda name: name.lstrip("/"),
            path=self.path,
            what=what,
            hint=hint,
        )

    def resolve_topics(self, topics: Sequence[str] | None) -> list[str]:
        """Bag topic names for ``topics`` (all laser topics when None); checks they exist and
        carry laser scans. A leading slash is optional."""
        lasers = [t.name for t in self.topics()]
        if not topics:
            if not lasers:
                raise TopicNotFoundError(
                    "no sensor_msgs/LaserScan topic in this bag",
                    path=self.path,
                    hint=f"topics here: {self._topic_list()}",
                )
            return lasers
        names = self._match(
            topics,
            "topic",
            f"laser topics here: {', '.join(lasers) or 'none'}; all topics: {self._topic_list()}",
        )
        for name in names:
            if name not in lasers:
                raise MessageTypeError(
                    f"topic {name!r} carries {self._connections[name][0].msgtype}, "
                    "not sensor_msgs/LaserScan",
                    path=self.path,
                    hint=f"laser topics here: {', '.join(lasers) or 'none'}",
                )
        return names

    def _topic_list(self) -> str:
        return ", ".join(f"{t.name} ({t.msgtype})" for t in self.all_topics()) or "none"

    # -- poses -----------------------------------------------------------------------------
    def _pose_topics(self) -> tuple[list[Any], list[Any]]:
        tf_conns, odom_conns = [], []
        wanted_odom = None
        if self._odometry_request is not None:
            names = self._match(
                self._odometry_request, "odometry topic", f"all topics: {self._topic_list()}"
            )
            for name in names:
                if self._connections[name][0].msgtype not in ODOMETRY_TYPES:
                    raise MessageTypeError(
                        f"topic {name!r} carries {self._connections[name][0].msgtype}, "
                        "not nav_msgs/Odometry",
                        path=self.path,
                    )
            wanted_odom = set(names)
        for topic, conns in self._connections.items():
            msgtype = conns[0].msgtype
            if msgtype in TF_TYPES:
                tf_conns.extend(conns)
            elif msgtype in ODOMETRY_TYPES and (wanted_odom is None or topic in wanted_odom):
                odom_conns.extend(conns)
        return tf_conns, odom_conns

    def transform_tree(self) -> TransformTree:
        """All pose data of the bag as a :class:`TransformTree` (read once, then cached).

        Given mounts come first, then ``/tf_static``, ``/tf`` and odometry: the first
        source naming a frame's parent wins. A given mount that would cut its laser off
        from the bag's own transforms is left out and noted in :attr:`mount_notes`.
        """
        if self._tree is not None:
            return self._tree
        tf_conns, odom_conns = self._pose_topics()
        static, tf, odom = PoseSamples(), PoseSamples(), PoseSamples()
        reader = self._reader
        pose_conns = tf_conns + odom_conns
        try:
            # an empty connection list would mean "every topic" to rosbags
            direct = {id(c): standard_pose_decoder(reader, c) for c in pose_conns}
            for conn, _, raw in reader.messages(connections=pose_conns) if pose_conns else ():
                try:
                    decode = direct.get(id(conn))
                    msg: Any = None
                    if decode is not None and isinstance(raw, bytes | bytearray | memoryview):
                        msg = decode(raw)  # (None: not the standard layout)
                    if msg is None:
                        msg = reader.deserialize(raw, conn.msgtype)
                    if conn.msgtype in TF_TYPES:
                        msg.transforms  # noqa: B018  (a record filed under another type)
                    else:
                        msg.pose.pose  # noqa: B018
                except Exception as exc:
                    if self.damaged.on_error == "stop":
                        raise RecordingError(
                            f"damaged pose message on {conn.topic!r}: {_describe(exc)}",
                            path=self.path,
                            hint="use --on-error skip to leave damaged messages out",
                        ) from exc
                    self.pose_messages_skipped += 1
                    continue
                if conn.msgtype in TF_TYPES:
                    target = static if "static" in conn.topic else tf
                    for tr in msg.transforms:
                        q, v = tr.transform.rotation, tr.transform.translation
                        self._note_z(tr, "static" in conn.topic)
                        target.add(
                            tr.header.frame_id,
                            tr.child_frame_id,
                            _stamp(tr.header),
                            (float(v.x), float(v.y)),
                            yaw_and_tilt(q.x, q.y, q.z, q.w),
                            conn.topic,
                        )
                elif msg.child_frame_id.strip():
                    q, v = msg.pose.pose.orientation, msg.pose.pose.position
                    odom.add(
                        msg.header.frame_id,
                        msg.child_frame_id,
                        _stamp(msg.header),
                        (float(v.x), float(v.y)),
                        yaw_and_tilt(q.x, q.y, q.z, q.w),
                        conn.topic,
                    )
        except RecordingError:
            raise
        except Exception as exc:  # any failure of the third-party parser on a damaged file
            raise RecordingError(
                f"cannot read pose data (/tf, odometry): {_describe(exc)}",
                path=self.path,
                hint=_CORRUPT_HINT,
            ) from exc
        self.pose_samples_dropped = static.dropped + tf.dropped + odom.dropped
        own = TransformTree(self.pose_params)
        for samples, fixed in ((static, True), (tf, False), (odom, False)):
            samples.add_to(own, static=fixed)
        mounts, self.mount_notes = mounts_to_use(self._mounts, own.edges())
        if self._mounts:
            self.mount_notes += stray_mount_notes(self._mounts, self.laser_frames(), own.frames())
        tree = TransformTree(self.pose_params)
        add_mounts(tree, mounts)
        for samples, fixed in ((static, True), (tf, False), (odom, False)):
            samples.add_to(tree, static=fixed)
        self._tree = tree
        return tree

    def _note_z(self, tr: Any, static: bool) -> None:
        """Keep the z translation [m] of a transform: the first one per child frame, a
        ``/tf_static`` one winning over ``/tf``."""
        child = normalise_frame(str(tr.child_frame_id))
        z = float(tr.transform.translation.z)
        if not math.isfinite(z) or (child in self._mount_z and not static):
            return
        if static and child in self._static_z:
            return
        if static:
            self._static_z.add(child)
        self._mount_z[child] = (normalise_frame(str(tr.header.frame_id)), z)

    def laser_heights(self, topics: Sequence[str] | None = None) -> dict[str, float]:
        """Mount height [m] above the floor of each laser topic (all when None) whose frame
        the bag's ``/tf_static`` (else the first ``/tf`` message naming it) chains up to a
        floor frame: the sum of the chain's z translations. The walk up stops at
        ``base_footprint`` or a world frame (:attr:`PoseParams.world_frames`, on the floor
        by ROS REP 105 / 120; so a ``base_link`` held above ``odom`` counts), else at the
        chain's root. Rotations about x and y are ignored (a tilted link's offset is taken
        as vertical). Topics whose frame no transform names, or whose frame hangs straight
        under a world frame (a recording of ``live --record``), are absent. Given
        ``--mount`` poses carry no height; with poses off (``--no-poses``) the transforms
        are not read and no height is known."""
        if not self.use_poses:
            return {}
        self.transform_tree()
        floor = {normalise_frame(f) for f in (*self.pose_params.world_frames, *FLOOR_FRAMES)}
        world = {normalise_frame(f) for f in self.pose_params.world_frames}
        out: dict[str, float] = {}
        for topic, frame in self.laser_frames(topics).items():
            if frame not in self._mount_z or self._mount_z[frame][0] in world:
                continue
            z, seen = 0.0, {frame}
            while frame not in floor and frame in self._mount_z:
                parent, dz = self._mount_z[frame]
                z, frame = z + dz, parent
                if frame in seen:  # a cycle in the transforms: no height
                    break
                seen.add(frame)
            else:
                out[topic] = z
        return out

    def laser_frames(self, topics: Sequence[str] | None = None) -> dict[str, str]:
        """``header.frame_id`` of the first message of each laser topic (read once per
        topic, then kept: known also after :meth:`close`)."""
        out: dict[str, str] = {}
        for name in self.resolve_topics(topics):
            if name in self._first_frames:
                out[name] = self._first_frames[name]
                continue
            try:
                for conn, _, raw in self._reader.messages(connections=self._connections[name]):
                    try:
                        # (a standard LaserScan decoded directly, as the scans are: rosbags'
                        # deserialiser would be generated for this one message)
                        msg: Any = None
                        if is_standard_laserscan(self._reader, conn) and isinstance(
                            raw, bytes | bytearray | memoryview
                        ):
                            msg = decode_laserscan(raw)
                        if msg is None:
                            msg = self._reader.deserialize(raw, conn.msgtype)
                        out[name] = normalise_frame(str(msg.header.frame_id))
                    except Exception:
                        if self.damaged.on_error == "stop":
                            raise
                        continue
                    break
            except Exception as exc:  # any failure of the third-party parser
                raise RecordingError(
                    f"cannot read topic {name!r}: {_describe(exc)}",
                    path=self.path,
                    hint=_CORRUPT_HINT,
                ) from exc
            if name in out:
                self._first_frames[name] = out[name]
        return out

    def pose_frame(self) -> str | None:
        """The fixed frame the scans' poses are given in: ``world_frame`` when asked for,
        else picked from ``/tf`` and odometry as :meth:`scans` picks it; None without poses."""
        return self._setup_poses()[1]

    def _setup_poses(self) -> tuple[TransformTree | None, str | None]:
        if not self.use_poses:
            return None, None
        tree = self.transform_tree()
        if self._world_request is not None:
            world = normalise_frame(self._world_request)
        elif not tree.frames():
            world = None
        else:
            world = tree.pick_world(self.laser_frames().values())
        self.world_frame = world
        return tree, world

    def pose_problem(self, topics: Sequence[str] | None = None) -> str | None:
        """Why the scans of ``topics`` (default: every laser topic) can have no pose, for
        an error that needs them: no pose data at all, or the laser frames that /tf does
        not link to the world frame, with the transforms the recording has and what to do
        (``--mount mir100`` for a MiR robot's frames). None when every laser frame is
        linked, or poses were not asked for.

        Raises:
            RecordingError: the bag cannot be read.
        """
        if not self.use_poses:
            return None
        tree, world = self._setup_poses()
        if tree is None or not tree.frames():
            return "the recording has no /tf, /tf_static or odometry to give sensor poses"
        frames = sorted(set(self.laser_frames(topics).values()))
        unlinked = [f for f in frames if world is None or tree.chain(world, f) is None]
        if not unlinked:
            return None
        edges = ", ".join(f"{p} -> {c}" for p, c, _ in tree.edges())
        target = (
            repr(world)
            if world
            else "a world frame (" + ", ".join(self.pose_params.world_frames) + ")"
        )
        return (
            f"/tf links no laser frame {', '.join(map(repr, unlinked))} to {target} "
            f"(transforms in the recording: {edges}); {_mount_hint(tree, world)}"
        )

    def pose_summary(self) -> str:
        """One line per reason why scans of the last :meth:`scans` run got no pose."""
        if not self.use_poses:
            return "poses not requested"
        if self.scans_without_pose == 0:
            return f"every scan has a pose in frame {self.world_frame!r}"
        lines = [
            f"{self.scans_without_pose} of {self.scans_read} scans have no pose"
            + (f" in frame {self.world_frame!r}" if self.world_frame else "")
        ]
        for (topic, reason), n in sorted(self.pose_misses.items()):
            lines.append(f"  {topic}: {n} scans: {reason}")
        if self._tree is not None and self._tree.frames():
            edges = ", ".join(f"{p} -> {c} ({src})" for p, c, src in self._tree.edges())
            lines.append(f"  transforms in the recording: {edges}")
        missing = {topic for (topic, reason), _ in self.pose_misses.items() if "chain" in reason}
        if missing:
            lines.append("  " + _mount_hint(self._tree, self.world_frame))
        return "\n".join(lines)

    def read_notes(self) -> list[str]:
        """Lines for the user about what the last read took other than as written: scans
        stamped with the bag's log time (a zero header stamp), laser topics whose
        ``header.frame_id`` changed (:class:`FrameChange`)."""
        lines = []
        if self.scans_with_log_time:
            lines.append(
                f"{self.scans_with_log_time} scans with a zero header stamp were stamped with "
                "the time the bag logged them"
            )
        for topic, change in sorted(self.frame_changes.items()):
            lines.append(change.describe(topic))
        for topic, types in sorted(self.other_types.items()):
            shown = ", ".join(f"{n} {msgtype}" for msgtype, n in sorted(types.items()))
            lines.append(
                f"{topic} also carries messages of another type: {shown} messages left out "
                "(only its laser scans are read)"
            )
        return lines

    # -- scans -----------------------------------------------------------------------------
    def scans(self, topics: Sequence[str] | None = None) -> Iterator[Scan]:
        """Scans of ``topics`` (all laser topics when None) in header-stamp order.

        Raises:
            TopicNotFoundError: A topic is not in the bag (the message lists those that are).
            MessageTypeError: A topic does not carry laser scans.
            UnsortedStampsError: Header stamps go backwards within a topic.
            ScanFormatError: A scan's beam count disagrees with its angles.
            RecordingError: The bag is corrupt or truncated.
        """
        names = self.resolve_topics(topics)
        tree, world = self._setup_poses()
        self.scans_without_pose = 0
        self.scans_with_log_time = 0
        self.scans_read = 0
        self.frame_changes = {}
        self.other_types = {}
        self.pose_misses.clear()
        self.damaged.reset()
        streams = [self._topic_scans(name, tree, world) for name in names]
        merged = streams[0] if len(streams) == 1 else heapq.merge(*streams, key=_by_stamp)
        for scan in merged:
            self.scans_read += 1
            yield scan
        self.damaged.check_read(self.scans_read)

    def _topic_scans(
        self, topic: str, tree: TransformTree | None, world: str | None
    ) -> Iterator[Scan]:
        source = str(self.path)
        index = -1
        read = 0
        last = -math.inf
        first_frame: str | None = None
        reader = self._open()
        try:
            conns = [c for c in reader.connections if c.topic == topic]
            others = [c for c in conns if not _is_laserscan(reader, c.msgtype)]
            for c in others:  # (a second type on the topic: not damage, left out and said)
                counts = self.other_types.setdefault(topic, {})
                counts[c.msgtype] = counts.get(c.msgtype, 0) + c.msgcount
            conns = [c for c in conns if c not in others]
            fast = {id(c) for c in conns if is_standard_laserscan(reader, c)}
            try:
                messages = reader.messages(connections=conns)
            except Exception as exc:
                self.damaged.end(_describe(exc), topic=topic, scan=0, read=0)
                return
            while True:
                try:
                    item = next(messages, None)
                except Exception as exc:  # the storage itself is damaged: no way to go on
                    self.damaged.end(_describe(exc), topic=topic, scan=index + 1, read=read)
                    return
                if item is None:
                    listed = sum(c.msgcount for c in conns)
                    if index < 0 and listed > 0:  # index and storage disagree: not "no scans"
                        self.damaged.end(
                            f"the bag's index lists {listed} messages on this topic but its "
                            "storage gives none",
                            topic=topic,
                            scan=0,
                            read=0,
                        )
                    return
                index += 1
                try:
                    conn, log_time, raw = item
                    msg = self._decode(reader, conn, topic, raw, id(conn) in fast)
                    stamp = _stamp(msg.header)
                    if stamp == 0.0 and log_time != 0:
                        stamp = log_time * 1e-9
                        self.scans_with_log_time += 1
                    n_int, n_ranges = len(msg.intensities), len(msg.ranges)
                    odd = n_int not in (0, n_ranges)  # (unused by tracking: left out, said)
                    scan = scan_from_message(msg, stamp, topic, index, source, intensities=not odd)
                    if odd:
                        self.damaged.drop_intensities(
                            topic=topic, scan=index, intensities=n_int, ranges=n_ranges
                        )
                except RecordingError as exc:
                    self.damaged.record(
                        exc.detail, topic=topic, scan=index, read=read, kind=type(exc)
                    )
                    continue
                except Exception as exc:  # a message the deserialiser cannot decode
                    self.damaged.record(_describe(exc), topic=topic, scan=index, read=read)
                    continue
                if stamp < last:  # (a stamp going back would unsort the lasers' merge)
                    self.damaged.record(
                        stamp_back(stamp, last),
                        topic=topic,
                        scan=index,
                        read=read,
                        kind=UnsortedStampsError,
                        hint=BACKWARD_HINT,
                    )
                    continue
                last = stamp
                frame_id = str(msg.header.frame_id)
                if first_frame is None:
                    first_frame = frame_id
                elif frame_id != first_frame:
                    change = self.frame_changes.get(topic)
                    if change is None:
                        change = self.frame_changes[topic] = FrameChange(first_frame, index)
                    change.count(frame_id)
                if tree is not None:
                    pose, reason = self._pose(tree, world, frame_id, stamp)
                    if pose is None:
                        self.scans_without_pose += 1
                        self.pose_misses[(topic, reason)] += 1
                    else:
                        try:  # a pose beyond the bounds of Scan makes the scan damaged
                            scan = replace(scan, pose=pose)
                        except RecordingError as exc:
                            self.damaged.record(
                                exc.detail, topic=topic, scan=index, read=read, kind=type(exc)
                            )
                            continue
                read += 1
                yield scan
        finally:
            reader.close()

    def _decode(self, reader: Any, conn: Any, topic: str, raw: Any, fast: bool = False) -> Any:
        """Deserialise one scan message; a record filed under a connection of another topic
        or type (a damaged connection id) is a :class:`RecordingError`. ``fast``: the
        connection carries standard ROS 1 LaserScans, decoded directly
        (:mod:`laserpeople.io.laserscan_ros1`) unless the bytes do not follow their layout,
        which rosbags' deserialiser then reports."""
        if fast and conn.topic == topic and isinstance(raw, bytes | bytearray | memoryview):
            msg = decode_laserscan(raw)
            if msg is not None:
                return msg
        if conn.topic != topic or not _is_laserscan(reader, conn.msgtype):
            raise RecordingError(
                f"record belongs to connection {conn.topic!r} ({conn.msgtype}), "
                "not to this laser topic",
                path=self.path,
            )
        if not isinstance(raw, bytes | bytearray | memoryview):
            raise RecordingError(f"message data is {type(raw).__name__}, not bytes", path=self.path)
        return reader.deserialize(raw, conn.msgtype)

    def _pose(
        self, tree: TransformTree, world: str | None, frame: str, stamp: float
    ) -> tuple[Pose2D | None, str]:
        if world is None or not tree.frames():
            reason = (
                "no pose data (no /tf, /tf_static or odometry)"
                if not tree.frames()
                else "no world frame: laser frames not connected to "
                + " or ".join(self.pose_params.world_frames)
            )
            return None, reason
        return tree.lookup(world, frame, stamp)


@dataclass
class FrameChange:
    """A laser topic whose ``header.frame_id`` changed mid-recording (a driver restarted
    with another frame, two lasers publishing on one topic).

    Attributes:
        first: The frame of the topic's first scan.
        at: Index of the first scan in another frame.
        others: Scans in each other frame.
    """

    first: str
    at: int
    others: Counter[str] = field(default_factory=Counter)

    def count(self, frame_id: str) -> None:
        """Count one scan in ``frame_id`` (not :attr:`first`)."""
        self.others[frame_id] += 1

    def describe(self, topic: str) -> str:
        """One line for the user: what changed, from which scan, and what it means."""
        most = sorted(self.others.items(), key=lambda item: (-item[1], item[0]))
        frames = ", ".join(f"{n} in {frame!r}" for frame, n in most)
        return (
            f"{topic}: header.frame_id changed from {self.first!r} at scan {self.at} ({frames}): "
            "with poses each scan is placed by its own frame; in the sensor frame (no poses) "
            "the positions of those scans are in their own frame, not in the first one's"
        )


FLOOR_FRAMES = ("base_footprint",)
"""Robot frames on the floor under the robot (ROS REP 120), where
:meth:`RosbagRecording.laser_heights` stops summing a laser's z."""


def _mount_hint(tree: TransformTree | None, world: str | None = None) -> str:
    """What to do when laser frames are not linked to the world: a ``world`` frame that no
    transform of the recording names is said to be misspelt (with the closest frames);
    else name a known robot whose mounts hang off a frame of the recording, else the
    general --mount form."""
    frames = set(tree.frames()) if tree is not None else set()
    if world is not None and frames and world not in frames:
        return (
            f"no transform of the recording names the world frame {world!r}"
            + did_you_mean(world, sorted(frames), lead=": ")
            + f" (its frames: {', '.join(sorted(frames))}; check --world-frame)"
        )
    for robot, mounts in KNOWN_MOUNTS.items():
        if any(parent in frames for parent, _ in mounts.values()):
            return f"the laser mounts are missing from /tf: try --mount {robot}"
    return "the laser mounts are missing from /tf: give them with --mount CHILD=PARENT:x,y,theta"


def _by_stamp(scan: Scan) -> float:
    return scan.stamp
