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
truth_xy, truth_vxy     (P, 2)      [m], [m/s], world frame
truth_group             (P,)        -1 = walks alone
truth_legs              (P, 2, 2)   [m]
truth_hue               (P,)        [deg]
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
from laserpeople.scan import Pose2D, Scan
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
                count = int(np.prod(shape)) if shape else 1
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
    except (zipfile.BadZipFile, ValueError, OSError, struct.error) as exc:
        if isinstance(exc, FileNotFoundError):
            raise RecordingError("file not found", path=path) from exc
        raise RecordingError(
            f"not a readable .npz recording: {exc}",
            path=path,
            hint="the file is corrupt or truncated; re-create it",
        ) from exc
    return arrays


class NpzRecording:
    """Reader of a ``.npz`` recording; scans stream from memory-mapped arrays.

    Example:
        >>> rec = NpzRecording("scene.npz")            # doctest: +SKIP
        >>> for scan in rec.scans(): ...               # doctest: +SKIP
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        if not self.path.exists():
            raise RecordingError("file not found", path=self.path)
        if self.path.is_dir():
            raise RecordingError("is a directory, not an .npz recording", path=self.path)
        self._a = _open_members(self.path)
        fmt = str(self._a["format"][()]) if "format" in self._a else ""
        if fmt != FORMAT:
            raise RecordingError(
                f"not a laserpeople recording (format {fmt or 'missing'!r})",
                path=self.path,
                hint="create recordings with `laserpeople simulate` or io.write_recording",
            )
        version = int(self._a["version"][()])
        if version > VERSION:
            raise RecordingError(
                f"recording version {version} is newer than this laserpeople reads ({VERSION})",
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
        self.sensor_names: tuple[str, ...] = tuple(str(s) for s in self._a["sensor_names"])
        offsets = self._a["scan_offset"]
        if offsets.size != self._a["scan_stamp"].size + 1 or (
            offsets.size and int(offsets[-1]) != self._a["ranges"].size
        ):
            raise RecordingError(
                "scan offsets do not match the ranges",
                path=self.path,
                hint="the file is corrupt or truncated; re-create it",
            )
        self.meta: dict[str, Any] = (
            json.loads(str(self._a["meta_json"][()])) if "meta_json" in self._a else {}
        )

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
        ids = set()
        for t in topics:
            name = t.lstrip("/") if t not in self.sensor_names else t
            if name not in self.sensor_names:
                raise TopicNotFoundError(
                    f"no topic {t!r}",
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
            yield Scan(
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

    def truth(self) -> Iterator[TruthFrame]:
        """Ground-truth frames in time order (none when the recording has no truth)."""
        if not self.has_truth:
            return
        a = self._a
        off = a["truth_offset"]
        for f in range(int(a["truth_stamp"].size)):
            lo, hi = int(off[f]), int(off[f + 1])
            yield TruthFrame(
                stamp=float(a["truth_stamp"][f]),
                scan_index=int(a["truth_scan_index"][f]),
                person_ids=np.array(a["truth_person_id"][lo:hi]),
                positions=np.array(a["truth_xy"][lo:hi]),
                velocities=np.array(a["truth_vxy"][lo:hi]),
                group_ids=np.array(a["truth_group"][lo:hi]),
                leg_positions=np.array(a["truth_legs"][lo:hi]),
                hues=np.array(a["truth_hue"][lo:hi]),
            )


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
    tmp = path.with_name(path.name + ".partial")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays)  # type: ignore[arg-type]
        os.replace(tmp, path)
    except OSError as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise RecordingError(
            f"cannot write the recording: {exc.strerror or exc}",
            path=path,
            hint="choose a writable file path",
        ) from exc
    return path
