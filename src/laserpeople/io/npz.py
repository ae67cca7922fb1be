"""The project's own recording format: scans plus optional ground truth in one ``.npz``.

Layout (format ``laserpeople-recording``, version 1). K scans, B beams in all, F truth
frames, P person-entries in all; scans of every sensor are interleaved in time order:

======================  ==========  =====================================================
key                     shape       meaning
======================  ==========  =====================================================
format, version         ()          ``"laserpeople-recording"``, 1
meta_json               ()          free JSON text (scenario, seed, sensors' models, ...)
sensor_names            (S,)        sensor (topic) names
scan_sensor             (K,)        index into ``sensor_names``
scan_index              (K,)        0-based index of the scan on its sensor
scan_stamp              (K,)        [s]
scan_angle_min/_incr    (K,)        [rad]
scan_range_min/_max     (K,)        [m]
scan_pose               (K, 3)      sensor pose x, y, theta in the world frame; NaN = unknown
scan_offset             (K+1,)      beams of scan k are ``offset[k]:offset[k+1]``
ranges                  (B,)        float32 [m]
intensities             (B,)        float32, only when every scan has intensities
beam_person/leg/        (B,)        int32 per-beam ground truth (see :class:`BeamLabels`),
 group/obj                          only when every scan has labels
truth_stamp             (F,)        [s]
truth_scan_index        (F,)
truth_offset            (F+1,)      entries of frame f are ``offset[f]:offset[f+1]``
truth_person_id         (P,)
truth_xy, truth_vxy     (P, 2)      [m], [m/s], world frame (or as ``truth_frame`` says)
truth_group             (P,)        -1 = walks alone
truth_legs              (P, 2, 2)   [m]
truth_hue               (P,)        [deg]
truth_frame             ()          optional text, ``world`` or ``sensor``: the frame of the
                                    truth's positions (written when the frames state it;
                                    absent: not stated)
======================  ==========  =====================================================

Files are written uncompressed so that reading memory-maps the arrays: iterating over
the scans of a long recording uses constant memory. ``allow_pickle`` is never enabled.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import struct
import zipfile
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.errors import RecordingError, TopicNotFoundError
from laserpeople.io.damage import DamagedRecords, OnError
from laserpeople.io.paths import not_found, staging_name, why_unwritable
from laserpeople.io.topics import check_names
from laserpeople.scan import CoordinateFrame, Pose2D, Scan
from laserpeople.spelling import did_you_mean
from laserpeople.truth import BeamLabels, TruthFrame

FORMAT = "laserpeople-recording"
VERSION = 1

_LABEL_KEYS = ("person", "leg", "group", "obj")


@dataclass(frozen=True)
class TopicInfo:
    """Summary of one topic (sensor) of a recording."""

    name: str
    msgtype: str
    count: int


def _open_members(path: Path) -> dict[str, NDArray[Any]]:
    """Memory-map every stored (uncompressed) ``.npy`` member of an ``.npz``; load the rest."""
    arrays: dict[str, NDArray[Any]] = {}
    try:
        with zipfile.ZipFile(path) as zf, open(path, "rb") as fh:
            for info in zf.infolist():
                if not info.filename.endswith(".npy"):
                    continue
                key = info.filename[:-4]
                if info.compress_type != zipfile.ZIP_STORED or info.file_size == 0:
                    with zf.open(info) as member:
                        arrays[key] = np.lib.format.read_array(member, allow_pickle=False)
                    continue
                fh.seek(info.header_offset)
                local = fh.read(30)
                if local[:4] != b"PK\x03\x04":
                    raise RecordingError(f"corrupt zip entry {info.filename}", path=path)
                name_len, extra_len = struct.unpack("<HH", local[26:30])
                fh.seek(info.header_offset + 30 + name_len + extra_len)
                major, _minor = np.lib.format.read_magic(fh)
                if major == 1:
                    shape, fortran, dtype = np.lib.format.read_array_header_1_0(fh)
                else:
                    shape, fortran, dtype = np.lib.format.read_array_header_2_0(fh)
                if dtype.hasobject:
                    raise RecordingError(
                        f"array {key!r} holds Python objects, which are never loaded",
                        path=path,
                        hint="recordings must contain plain numeric or string arrays",
                    )
                offset = fh.tell()
                count = math.prod(int(d) for d in shape)
                if offset + count * dtype.itemsize > os.path.getsize(path):
                    raise RecordingError(f"array {key!r} is truncated", path=path)
                if count == 0:
                    arrays[key] = np.empty(shape, dtype=dtype)
                else:
                    arrays[key] = np.memmap(
                        path,
                        dtype=dtype,
                        mode="r",
                        offset=offset,
                        shape=shape,
                        order="F" if fortran else "C",
                    )
    except RecordingError:
        raise
    except Exception as exc:  # zipfile/numpy parsing a damaged file: any exception type
        if isinstance(exc, FileNotFoundError):
            raise RecordingError("file not found", path=path) from exc
        raise RecordingError(
            f"not a readable .npz recording: {exc}",
            path=path,
            hint="the file is corrupt or truncated; re-create it",
        ) from exc
    return arrays


def _text_scalar(array: NDArray[Any] | None) -> str:
    """The text of a 0-d string array ("" when missing or not a text scalar)."""
    if array is None or array.shape != () or array.dtype.kind not in "US":
        return ""
    value = array[()]
    return value.decode("utf-8", "replace") if isinstance(value, bytes) else str(value)


def _check_layout(a: dict[str, NDArray[Any]], path: Path) -> None:
    """Shapes, types and offsets of the scan and truth arrays agree (else RecordingError).

    Values inside a scan (stamps, angles) are checked when the scan is read, so that one
    damaged scan can be skipped.
    """

    def bad(message: str) -> RecordingError:
        return RecordingError(
            message, path=path, hint="the file is damaged or truncated; re-create it"
        )

    names = a["sensor_names"]
    if names.ndim != 1 or names.dtype.kind not in "US":
        raise bad(f"sensor_names must be a list of names, got {names.dtype} {names.shape}")
    k = a["scan_stamp"].shape[0] if a["scan_stamp"].ndim == 1 else -1
    if k < 0:
        raise bad(f"scan_stamp must be one-dimensional, got shape {a['scan_stamp'].shape}")
    for key in ("scan_sensor", "scan_index", "scan_angle_min", "scan_angle_incr"):
        _check_column(a, key, (k,), bad)
    for key in ("scan_stamp", "scan_range_min", "scan_range_max"):
        _check_column(a, key, (k,), bad)
    _check_column(a, "scan_pose", (k, 3), bad)
    for key in ("scan_sensor", "scan_index", "scan_offset"):
        if a[key].dtype.kind not in "iu":
            raise bad(f"{key} must hold integers, got {a[key].dtype}")
    ranges = a["ranges"]
    if ranges.ndim != 1 or ranges.dtype.kind not in "fiu":
        raise bad(f"ranges must be a one-dimensional numeric array, got {ranges.dtype}")
    _check_offsets(a["scan_offset"], k, ranges.shape[0], "scan_offset", bad)
    if k and names.shape[0] == 0:
        raise bad("sensor_names is empty but there are scans")
    sensor = np.asarray(a["scan_sensor"], dtype=np.int64)
    if k and (sensor.min() < 0 or sensor.max() >= names.shape[0]):
        raise bad(f"scan_sensor holds values outside 0..{names.shape[0] - 1}")
    index = np.asarray(a["scan_index"], dtype=np.int64)
    for s in np.unique(sensor):
        own = index[sensor == s]
        if own.size and (own.min() < 0 or np.any(np.diff(own) < 0)):
            at = int(np.argmax(np.diff(own) < 0)) + 1 if own.size > 1 else 0
            raise bad(
                f"scan_index of sensor {str(names[s])!r} is negative or goes back "
                f"(at its scan number {at})"
            )
    for key in ("intensities", *(f"beam_{x}" for x in _LABEL_KEYS)):
        if key in a and (a[key].shape != ranges.shape or a[key].dtype.kind not in "fiub"):
            raise bad(f"{key} must be numeric with one value per beam")
    if "truth_stamp" not in a:
        return
    f = a["truth_stamp"].shape[0] if a["truth_stamp"].ndim == 1 else -1
    if f < 0:
        raise bad("truth_stamp must be one-dimensional")
    need = (
        "truth_scan_index",
        "truth_offset",
        "truth_person_id",
        "truth_xy",
        "truth_vxy",
        "truth_group",
        "truth_legs",
        "truth_hue",
    )
    missing = [key for key in need if key not in a]
    if missing:
        raise bad(f"truth lacks {', '.join(missing)}")
    _check_column(a, "truth_scan_index", (f,), bad)
    if a["truth_offset"].dtype.kind not in "iu" or a["truth_scan_index"].dtype.kind not in "iu":
        raise bad("truth_offset and truth_scan_index must hold integers")
    p = a["truth_person_id"].shape[0] if a["truth_person_id"].ndim == 1 else -1
    _check_offsets(a["truth_offset"], f, p, "truth_offset", bad)
    for key, shape in (
        ("truth_person_id", (p,)),
        ("truth_xy", (p, 2)),
        ("truth_vxy", (p, 2)),
        ("truth_group", (p,)),
        ("truth_legs", (p, 2, 2)),
        ("truth_hue", (p,)),
    ):
        _check_column(a, key, shape, bad)
    if a["truth_person_id"].dtype.kind not in "iu" or a["truth_group"].dtype.kind not in "iu":
        raise bad("truth_person_id and truth_group must hold integers")
    stamps = np.asarray(a["truth_stamp"], dtype=np.float64)
    if not np.all(np.isfinite(stamps)):
        raise bad("truth_stamp holds a value that is not finite")


def _check_column(a: dict[str, NDArray[Any]], key: str, shape: tuple[int, ...], bad: Any) -> None:
    arr = a[key]
    if arr.shape != shape or arr.dtype.kind not in "fiu":
        raise bad(f"{key} must be numeric of shape {shape}, got {arr.dtype} {arr.shape}")


def _check_offsets(off: NDArray[Any], n: int, total: int, key: str, bad: Any) -> None:
    if off.shape != (n + 1,) or off.dtype.kind not in "iu":
        raise bad(f"{key} must be {n + 1} integers, got {off.dtype} {off.shape}")
    o = np.asarray(off, dtype=np.int64)
    if o[0] != 0 or o[-1] != total or np.any(np.diff(o) < 0):
        raise bad(f"{key} does not run from 0 to {total} without going back")


class NpzRecording:
    """Reader of a ``.npz`` recording; scans stream from memory-mapped arrays.

    Example:
        >>> rec = NpzRecording("scene.npz")            # doctest: +SKIP
        >>> for scan in rec.scans(): ...               # doctest: +SKIP
    """

    def __init__(self, path: str | Path, *, on_error: OnError = "stop") -> None:
        self.path = Path(path)
        self.damaged = DamagedRecords(self.path, on_error)
        if not self.path.exists():
            raise RecordingError(not_found(self.path), path=self.path)
        if self.path.is_dir():
            raise RecordingError("is a directory, not an .npz recording", path=self.path)
        self._a = _open_members(self.path)
        fmt = _text_scalar(self._a.get("format"))
        if fmt != FORMAT:
            raise RecordingError(
                f"not a laserpeople recording (format {fmt or 'missing'!r})",
                path=self.path,
                hint="create recordings with `laserpeople simulate` or io.write_recording",
            )
        version = self._a.get("version")
        if version is None or version.shape != () or version.dtype.kind not in "iu":
            raise RecordingError(
                "the 'version' entry is not an integer scalar",
                path=self.path,
                hint="the file is damaged or was not written by laserpeople; re-create it",
            )
        if int(version[()]) > VERSION:
            raise RecordingError(
                f"recording version {int(version[()])} is newer than this laserpeople reads "
                f"({VERSION})",
                path=self.path,
                hint="upgrade laserpeople",
            )
        required = (
            "sensor_names",
            "scan_sensor",
            "scan_index",
            "scan_stamp",
            "scan_angle_min",
            "scan_angle_incr",
            "scan_range_min",
            "scan_range_max",
            "scan_pose",
            "scan_offset",
            "ranges",
        )
        missing = [k for k in required if k not in self._a]
        if missing:
            raise RecordingError(f"recording lacks {', '.join(missing)}", path=self.path)
        _check_layout(self._a, self.path)
        self.sensor_names: tuple[str, ...] = tuple(str(s) for s in self._a["sensor_names"])
        self.meta: dict[str, Any] = {}
        if "meta_json" in self._a:
            try:
                meta = json.loads(_text_scalar(self._a["meta_json"]) or "{}")
            except (ValueError, RecursionError) as exc:
                raise RecordingError(
                    f"meta_json is not valid JSON: {str(exc)[:100]}", path=self.path
                ) from exc
            self.meta = meta if isinstance(meta, dict) else {}

    def __enter__(self) -> NpzRecording:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Release the memory maps."""
        self._a = {}

    @property
    def n_scans(self) -> int:
        """Number of scans of all sensors."""
        return int(self._a["scan_stamp"].size)

    @property
    def has_truth(self) -> bool:
        """Whether the recording carries per-frame ground truth."""
        return "truth_stamp" in self._a and self._a["truth_stamp"].size > 0

    @property
    def has_labels(self) -> bool:
        """Whether the recording carries per-beam labels."""
        return "beam_person" in self._a

    def topics(self) -> list[TopicInfo]:
        """One entry per sensor with its scan count."""
        counts = np.bincount(
            np.asarray(self._a["scan_sensor"], dtype=np.int64), minlength=len(self.sensor_names)
        )
        return [
            TopicInfo(n, "sensor_msgs/msg/LaserScan", int(c))
            for n, c in zip(self.sensor_names, counts, strict=True)
        ]

    def _sensor_ids(self, topics: Sequence[str] | None) -> set[int]:
        if not topics:
            return set(range(len(self.sensor_names)))
        check_names(topics)
        ids = set()
        for t in topics:
            name = t.lstrip("/") if t not in self.sensor_names else t
            if name not in self.sensor_names:
                guess = did_you_mean(t, self.sensor_names, key=lambda n: n.lstrip("/"), lead="; ")
                raise TopicNotFoundError(
                    f"no topic {t!r}{guess}",
                    path=self.path,
                    hint=f"topics here: {', '.join(self.sensor_names)}",
                )
            ids.add(self.sensor_names.index(name))
        return ids

    def scans(self, topics: Sequence[str] | None = None) -> Iterator[Scan]:
        """Scans in time order, of the given topics (all when None)."""
        a = self._a
        wanted = self._sensor_ids(topics)
        sensor = a["scan_sensor"]
        offsets = a["scan_offset"]
        have_int = "intensities" in a
        self.damaged.reset()
        read: dict[int, int] = {}
        for k in range(self.n_scans):
            s = int(sensor[k])
            if s not in wanted:
                continue
            lo, hi = int(offsets[k]), int(offsets[k + 1])
            pose_v = np.asarray(a["scan_pose"][k], dtype=np.float64)
            pose = Pose2D.from_array(pose_v) if np.all(np.isfinite(pose_v)) else None
            labels = None
            if self.has_labels:
                labels = BeamLabels(*(np.array(a[f"beam_{key}"][lo:hi]) for key in _LABEL_KEYS))
            try:
                scan = self._scan(k, s, lo, hi, pose, labels, have_int)
            except RecordingError as exc:
                self.damaged.record(
                    exc.detail,
                    topic=self.sensor_names[s],
                    scan=int(a["scan_index"][k]),
                    read=read.get(s, 0),
                    kind=type(exc),
                )
                continue
            read[s] = read.get(s, 0) + 1
            yield scan
        self.damaged.check_read(sum(read.values()))

    def _scan(
        self,
        k: int,
        s: int,
        lo: int,
        hi: int,
        pose: Pose2D | None,
        labels: BeamLabels | None,
        have_int: bool,
    ) -> Scan:
        a = self._a
        return Scan(
            stamp=float(a["scan_stamp"][k]),
            angle_min=float(a["scan_angle_min"][k]),
            angle_increment=float(a["scan_angle_incr"][k]),
            ranges=np.array(a["ranges"][lo:hi], dtype=np.float64),
            range_min=float(a["scan_range_min"][k]),
            range_max=float(a["scan_range_max"][k]),
            intensities=np.array(a["intensities"][lo:hi]) if have_int else None,
            sensor=self.sensor_names[s],
            pose=pose,
            index=int(a["scan_index"][k]),
            source=str(self.path),
            labels=labels,
        )

    def truth_frame(self) -> CoordinateFrame | None:
        """The frame of the truth's positions, as the file states it (``truth_frame``);
        None when it does not.

        Raises:
            RecordingError: it states another frame than ``world`` or ``sensor``.
        """
        stated = _text_scalar(self._a.get("truth_frame")) or ""
        if stated == "world" or stated == "sensor":
            return "world" if stated == "world" else "sensor"
        if stated:
            raise RecordingError(
                f"truth_frame is {stated!r}, neither world nor sensor",
                path=self.path,
                hint="write the recording again with write_recording",
            )
        return None

    def truth(self) -> Iterator[TruthFrame]:
        """Ground-truth frames in time order (none when the recording has no truth).

        A frame whose positions are not finite, whose person ids repeat or whose scan index
        does not come after the previous frame's is damaged: it ends the read or is skipped
        and counted, by the recording's ``on_error`` (see :mod:`laserpeople.io.damage`).
        """
        if not self.has_truth:
            return
        a = self._a
        off = a["truth_offset"]
        last, read = -1, 0
        frame_of_truth = self.truth_frame()
        for f in range(int(a["truth_stamp"].size)):
            lo, hi = int(off[f]), int(off[f + 1])
            frame = TruthFrame(
                stamp=float(a["truth_stamp"][f]),
                scan_index=int(a["truth_scan_index"][f]),
                person_ids=np.array(a["truth_person_id"][lo:hi]),
                positions=np.array(a["truth_xy"][lo:hi]),
                velocities=np.array(a["truth_vxy"][lo:hi]),
                group_ids=np.array(a["truth_group"][lo:hi]),
                leg_positions=np.array(a["truth_legs"][lo:hi]),
                hues=np.array(a["truth_hue"][lo:hi]),
                frame=frame_of_truth,
            )
            reason = _truth_damage(frame, last)
            if reason:
                self.damaged.record(reason, topic="truth", scan=frame.scan_index, read=read)
                continue
            last, read = frame.scan_index, read + 1
            yield frame


def _truth_damage(frame: TruthFrame, last: int) -> str:
    """Why ``frame`` cannot be used after a frame of scan ``last`` ("" when it can)."""
    if frame.scan_index <= last:
        return f"its scan index does not come after scan {last}"
    if not np.isfinite(frame.positions).all():
        return "a position is not finite"
    if np.unique(frame.person_ids).size != frame.person_ids.size:
        return "a person id repeats"
    return ""


def write_recording(
    path: str | Path,
    scans: Iterable[Scan],
    truth: Iterable[TruthFrame] = (),
    meta: dict[str, Any] | None = None,
) -> Path:
    """Write scans (any sensors, in the order given) and ground truth to ``path``.

    The file is written to a temporary name and renamed at the end, so an existing file
    is never left half-written.
    """
    path = Path(path)
    scan_list = list(scans)
    names: list[str] = []
    for s in scan_list:
        if s.sensor not in names:
            names.append(s.sensor)
    k = len(scan_list)
    lengths = np.array([s.n_beams for s in scan_list], dtype=np.int64)
    offsets = np.zeros(k + 1, dtype=np.int64)
    np.cumsum(lengths, out=offsets[1:])
    arrays: dict[str, NDArray[Any]] = {
        "format": np.array(FORMAT),
        "version": np.array(VERSION),
        "meta_json": np.array(json.dumps(meta or {})),
        "sensor_names": np.array(names if names else [""], dtype=str)[: len(names)],
        "scan_sensor": np.array([names.index(s.sensor) for s in scan_list], dtype=np.int32),
        "scan_index": np.array([s.index for s in scan_list], dtype=np.int64),
        "scan_stamp": np.array([s.stamp for s in scan_list], dtype=np.float64),
        "scan_angle_min": np.array([s.angle_min for s in scan_list], dtype=np.float64),
        "scan_angle_incr": np.array([s.angle_increment for s in scan_list], dtype=np.float64),
        "scan_range_min": np.array([s.range_min for s in scan_list], dtype=np.float64),
        "scan_range_max": np.array([s.range_max for s in scan_list], dtype=np.float64),
        "scan_pose": np.array(
            [s.pose.as_array() if s.pose else (math.nan,) * 3 for s in scan_list], dtype=np.float64
        ).reshape(k, 3),
        "scan_offset": offsets,
        "ranges": (np.concatenate([s.ranges for s in scan_list]) if k else np.empty(0)).astype(
            np.float32
        ),
    }
    if k and all(s.intensities is not None for s in scan_list):
        arrays["intensities"] = np.concatenate([s.intensities for s in scan_list]).astype(
            np.float32
        )
    if k and all(s.labels is not None for s in scan_list):
        for key in _LABEL_KEYS:
            arrays[f"beam_{key}"] = np.concatenate(
                [getattr(s.labels, key) for s in scan_list]
            ).astype(np.int32)
    frames = list(truth)
    if frames:
        sizes = np.array([len(f) for f in frames], dtype=np.int64)
        toff = np.zeros(len(frames) + 1, dtype=np.int64)
        np.cumsum(sizes, out=toff[1:])
        arrays.update(
            truth_stamp=np.array([f.stamp for f in frames], dtype=np.float64),
            truth_scan_index=np.array([f.scan_index for f in frames], dtype=np.int64),
            truth_offset=toff,
            truth_person_id=np.concatenate([f.person_ids for f in frames]).astype(np.int64),
            truth_xy=np.concatenate([f.positions for f in frames]).reshape(-1, 2),
            truth_vxy=np.concatenate([f.velocities for f in frames]).reshape(-1, 2),
            truth_group=np.concatenate([f.group_ids for f in frames]).astype(np.int64),
            truth_legs=np.concatenate([f.leg_positions for f in frames]).reshape(-1, 2, 2),
            truth_hue=np.concatenate([f.hues for f in frames]).astype(np.float64),
        )
        stated = {f.frame for f in frames}
        if len(stated) == 1 and None not in stated:
            arrays["truth_frame"] = np.array(stated.pop())
    tmp = staging_name(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays)  # type: ignore[arg-type]
        os.replace(tmp, path)
    except OSError as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise RecordingError(
            f"cannot write the recording: {why_unwritable(exc, path)}",
            path=path,
            hint="choose a writable file path",
        ) from exc
    return path
