"""Tracks as Parquet: the columns of the tracks CSV, typed (``--format parquet``).

One row per track per scan, as in :mod:`laserpeople.io.tracks_csv`, with the schema
:data:`TRACKS_SCHEMA`: ``scan`` int64, ``stamp`` float64 [s], ``track_id`` int64, ``kind``
string (leg, person, group), ``x``, ``y`` [m], ``vx``, ``vy`` [m/s], ``cov_xx``,
``cov_xy``, ``cov_yy`` [m^2] float64, ``size`` int32, ``labels`` string, ``topic`` string,
``sensor_x``, ``sensor_y`` [m], ``sensor_yaw`` [rad] float64 (the laser's pose in the world
frame at that scan; NaN when the recording gives none), ``contour`` string (``x y;x y;...``
[m], empty for legs and persons). Positions are in the frame named by the file's key-value
metadata ``frame`` (``world`` or ``sensor``). Rows are buffered and written as row groups of
:data:`ROW_GROUP` rows; numbers are not rounded.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from laserpeople.errors import RecordingError
from laserpeople.frame import Frame
from laserpeople.io.paths import why_unwritable
from laserpeople.io.tracks_csv import convert_tracks, format_contour, parse_contour
from laserpeople.scan import CoordinateFrame, Pose2D
from laserpeople.tracks import Track, TrackKind, Tracks

ROW_GROUP = 65_536
"""Rows per Parquet row group."""

COLUMNS: tuple[tuple[str, str], ...] = (
    ("scan", "int64"),
    ("stamp", "float64"),
    ("track_id", "int64"),
    ("kind", "string"),
    ("x", "float64"),
    ("y", "float64"),
    ("vx", "float64"),
    ("vy", "float64"),
    ("cov_xx", "float64"),
    ("cov_xy", "float64"),
    ("cov_yy", "float64"),
    ("size", "int32"),
    ("labels", "string"),
    ("topic", "string"),
    ("sensor_x", "float64"),
    ("sensor_y", "float64"),
    ("sensor_yaw", "float64"),
    ("contour", "string"),
)
"""Column names and Arrow types of a tracks Parquet file."""


def tracks_schema() -> Any:
    """The ``pyarrow.Schema`` of :data:`COLUMNS`."""
    import pyarrow as pa

    return pa.schema([(name, pa.type_for_alias(kind)) for name, kind in COLUMNS])


class TracksParquetSink:
    """A pipeline sink writing tracks to Parquet (see the module docstring).

    Args:
        path: The file to write.
        frame: Frame of the written positions (default: the tracks' own frame).
    """

    def __init__(self, path: str | Path, frame: CoordinateFrame | None = None) -> None:
        self.path = Path(path)
        self.frame = frame
        self.rows = 0
        self._columns: dict[str, list[Any]] = {name: [] for name, _ in COLUMNS}
        self._writer: Any = None
        self.written_frame: CoordinateFrame | None = None
        self._closed = False

    def write(self, frame: Frame, tracks: Tracks | None) -> None:
        """Append the frame's tracks."""
        if tracks is None:
            return
        if self.written_frame is None:
            self.written_frame = self.frame or tracks.frame
        tracks = convert_tracks(tracks, self.written_frame)
        cols = self._columns
        pose = tracks.sensor_pose
        nan = float("nan")
        sensor = (nan, nan, nan) if pose is None else (pose.x, pose.y, pose.theta)
        for t in tracks.tracks:
            c = t.covariance
            for name, value in (
                ("scan", tracks.scan_index),
                ("stamp", tracks.stamp),
                ("track_id", t.track_id),
                ("kind", t.kind),
                ("x", t.position[0]),
                ("y", t.position[1]),
                ("vx", t.velocity[0]),
                ("vy", t.velocity[1]),
                ("cov_xx", c[0, 0]),
                ("cov_xy", c[0, 1]),
                ("cov_yy", c[1, 1]),
                ("size", t.size),
                ("labels", t.labels),
                ("topic", frame.topic),
                ("sensor_x", sensor[0]),
                ("sensor_y", sensor[1]),
                ("sensor_yaw", sensor[2]),
                ("contour", format_contour(t.contour)),
            ):
                cols[name].append(value)
        self.rows += len(tracks.tracks)
        if len(cols["scan"]) >= ROW_GROUP:
            self._flush()

    def _flush(self) -> None:
        import pyarrow as pa
        import pyarrow.parquet as pq

        schema = tracks_schema().with_metadata({"frame": self.written_frame or "sensor"})
        table = pa.table(
            {
                name: pa.array(values, type=schema.field(name).type)
                for name, values in self._columns.items()
            },
            schema=schema,
        )
        scans = self._columns["scan"]
        try:
            if self._writer is None:
                self._writer = pq.ParquetWriter(self.path, schema)
            self._writer.write_table(table)
        except OSError as exc:
            raise self._unwritable(exc, scans[-1] if scans else None) from exc
        self._columns = {name: [] for name, _ in COLUMNS}

    def _unwritable(self, exc: OSError, scan: int | None) -> RecordingError:
        """The error of a write that failed (a full disk): pyarrow's own words name its
        source file; this names the Parquet file, the last scan buffered and the reason."""
        why = os.strerror(exc.errno) if exc.errno else why_unwritable(exc, self.path)
        at = f" with the rows up to scan {scan}" if scan is not None else ""
        return RecordingError(
            f"cannot write the tracks Parquet{at}: {why}",
            path=self.path,
            hint="free disk space or choose another output folder",
        )

    def close(self) -> None:
        """Write what is buffered and close; with no frame at all, a file with the schema
        and no row."""
        if self._closed:
            return
        if self._writer is None or self._columns["scan"]:
            self._flush()
        try:
            self._writer.close()
        except OSError as exc:
            raise self._unwritable(exc, None) from exc
        self._closed = True


def iter_tracks_parquet(
    path: str | Path,
    frame: CoordinateFrame = "world",
    kinds: tuple[TrackKind, ...] | None = None,
) -> Iterator[Tracks]:
    """Read a tracks Parquet file back as one :class:`Tracks` per scan that has rows, in
    file order, in the frame its metadata names (``frame`` for a file without that key;
    ``kinds`` keeps only those kinds), each with its sensor pose when the file has one.

    Raises:
        RecordingError: The file is missing or not a tracks Parquet file.
    """
    import numpy as np
    import pyarrow.parquet as pq

    p = Path(path)
    try:
        table = pq.read_table(p)
    except (OSError, ValueError) as exc:
        raise RecordingError(f"cannot read the tracks Parquet file: {exc}", path=p) from None
    missing = [
        name for name, _ in COLUMNS if name not in table.column_names and name not in _OPTIONAL
    ]
    if missing:
        raise RecordingError(
            f"not a tracks Parquet file: no column {', '.join(missing)}",
            path=p,
            hint="give a file written by `laserpeople batch --format parquet`",
        )
    stated = (table.schema.metadata or {}).get(b"frame", b"").decode(errors="replace")
    if stated in ("world", "sensor"):
        frame = "world" if stated == "world" else "sensor"
    cols = {
        name: table.column(name).to_pylist() for name, _ in COLUMNS if name in table.column_names
    }
    nan = [float("nan")] * table.num_rows
    poses = zip(*(cols.get(name, nan) for name in _OPTIONAL), strict=True)
    current: list[Track] = []
    scan: int | None = None
    stamp = 0.0
    pose: Pose2D | None = None
    for k, (sx, sy, syaw) in enumerate(poses):
        if scan is not None and cols["scan"][k] != scan:
            yield Tracks(stamp, scan, tuple(current), frame=frame, sensor_pose=pose)
            current = []
        if scan is None or cols["scan"][k] != scan:
            known = all(v is not None and math.isfinite(v) for v in (sx, sy, syaw))
            pose = Pose2D(sx, sy, syaw) if known else None
        scan, stamp = cols["scan"][k], cols["stamp"][k]
        if kinds is not None and cols["kind"][k] not in kinds:
            continue
        current.append(
            Track(
                cols["track_id"][k],
                cols["kind"][k],
                np.array([cols["x"][k], cols["y"][k]]),
                np.array([cols["vx"][k], cols["vy"][k]]),
                np.array(
                    [[cols["cov_xx"][k], cols["cov_xy"][k]], [cols["cov_xy"][k], cols["cov_yy"][k]]]
                ),
                size=cols["size"][k],
                labels=cols["labels"][k],
                contour=parse_contour(cols["contour"][k]),
            )
        )
    if scan is not None:
        yield Tracks(stamp, scan, tuple(current), frame=frame, sensor_pose=pose)


_OPTIONAL = ("sensor_x", "sensor_y", "sensor_yaw")
"""Columns a file may lack (written before they existed): no sensor pose."""


__all__ = ["COLUMNS", "ROW_GROUP", "TracksParquetSink", "iter_tracks_parquet", "tracks_schema"]
