"""Tracks CSV: one row per track per scan, written and flushed scan by scan.

Header::

    scan,stamp,track_id,kind,x,y,vx,vy,cov_xx,cov_xy,cov_yy,size,labels

``scan`` is the 0-based index of the scan on its topic, positions [m] and velocities
[m/s] are in the frame chosen when writing (``--output-frame``), ``size`` is the
estimated number of people (1 for legs and persons), ``labels`` the group label set.
A scan with no tracks writes no row. Every scan's rows go to the file in one ``write()``
before the next scan is processed (:mod:`laserpeople.io.scan_lines`), so a crash or a kill
leaves a valid file with the scans done so far; a reader that finds the last scan cut off
anyway (a file cut short) leaves that scan out with a ``TornScanWarning``.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any, get_args

import numpy as np

from laserpeople.errors import LaserPeopleError, RecordingError
from laserpeople.io.scan_lines import ScanLineWriter, complete_lines, torn_scan, warn_torn
from laserpeople.scan import CoordinateFrame
from laserpeople.tracks import TRACK_KINDS, Track, TrackKind, Tracks

HEADER = (
    "scan",
    "stamp",
    "track_id",
    "kind",
    "x",
    "y",
    "vx",
    "vy",
    "cov_xx",
    "cov_xy",
    "cov_yy",
    "size",
    "labels",
)


def convert_tracks(tracks: Tracks, frame: CoordinateFrame) -> Tracks:
    """The same tracks expressed in ``frame`` (uses ``tracks.sensor_pose``)."""
    if tracks.frame == frame:
        return tracks
    pose = tracks.sensor_pose
    if pose is None:
        raise LaserPeopleError(
            f"cannot express tracks in the {frame} frame: "
            f"scan {tracks.scan_index} has no sensor pose",
            scan=tracks.scan_index,
            hint="use --output-frame sensor, or a recording with /tf or odometry",
        )
    rot = pose.rotation()
    if frame == "world":
        pos = lambda p: pose.transform_points(p[None])[0]  # noqa: E731
        r = rot
    else:
        pos = lambda p: pose.inverse_transform_points(p[None])[0]  # noqa: E731
        r = rot.T
    converted = tuple(
        Track(
            t.track_id,
            t.kind,
            pos(t.position),
            r @ t.velocity,
            r @ t.covariance @ r.T,
            t.size,
            t.labels,
            t.score,
            t.members,
            pose.transform_points(t.contour)
            if frame == "world"
            else pose.inverse_transform_points(t.contour),
        )
        for t in tracks.tracks
    )
    return Tracks(tracks.stamp, tracks.scan_index, converted, frame, pose)


class TracksCsvWriter:
    """Write :class:`~laserpeople.tracks.Tracks` to CSV, flushing after every scan.

    Example:
        >>> with TracksCsvWriter("tracks.csv", frame="world") as out:  # doctest: +SKIP
        ...     for tracks in tracker_outputs:
        ...         out.write(tracks)
    """

    def __init__(self, path: str | Path, frame: CoordinateFrame = "world") -> None:
        self.path = Path(path)
        self.frame = frame
        self._out = ScanLineWriter(self.path, HEADER, "tracks CSV")
        self.rows = 0

    def write(self, tracks: Tracks) -> None:
        """Append the rows of one scan with one ``write()`` (see the module docstring).

        Raises:
            RecordingError: The write failed (disk full); the file keeps the earlier scans.
        """
        tracks = convert_tracks(tracks, self.frame)
        rows = []
        for t in tracks.tracks:
            c = t.covariance
            rows.append(
                (
                    tracks.scan_index,
                    f"{tracks.stamp:.6f}",
                    t.track_id,
                    t.kind,
                    f"{t.position[0]:.4f}",
                    f"{t.position[1]:.4f}",
                    f"{t.velocity[0]:.4f}",
                    f"{t.velocity[1]:.4f}",
                    f"{c[0, 0]:.6g}",
                    f"{c[0, 1]:.6g}",
                    f"{c[1, 1]:.6g}",
                    t.size,
                    t.labels,
                )
            )
        if rows:
            self._out.write_rows(rows)
            self.rows += len(rows)

    def close(self) -> None:
        """Close the file."""
        self._out.close()

    def __enter__(self) -> TracksCsvWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


NAMED_ID_BASE = 2**62
"""Track ids that are not decimal integers below this get ids from here up (see
:class:`TrackIdMap`)."""


class TrackIdMap:
    """Integer ids for the ``track_id`` column, which may hold any text.

    A decimal integer ``0 <= id < 2**62`` (what ``laserpeople track`` writes, and 12-digit
    ids of other tools) is kept as it is; any other text (``"p7"``, ``"-3"``, a 30-digit
    number, a UUID) gets the next free integer from :data:`NAMED_ID_BASE` up, the same one
    for every row of the file. :attr:`names` maps those integers back to the text, for
    reports.
    """

    def __init__(self) -> None:
        self._ids: dict[str, int] = {}
        self.names: dict[int, str] = {}

    def __call__(self, text: str) -> int:
        """The integer id of ``text`` (raises ValueError for an empty id)."""
        text = text.strip()
        if not text:
            raise ValueError("track_id is empty")
        if text.isascii() and text.isdigit() and len(text) <= 19:
            value = int(text)
            if value < NAMED_ID_BASE:
                return value
        known = self._ids.get(text)
        if known is None:
            known = NAMED_ID_BASE + len(self._ids)
            self._ids[text] = known
            self.names[known] = text
        return known


def _parse_row(
    row: dict[str, Any], path: Path, line: int, ids: TrackIdMap
) -> tuple[int, float, Track]:
    if None in row or any(v is None for v in row.values()):
        raise RecordingError(
            f"line {line}: {'more' if None in row else 'fewer'} fields than the header has",
            path=path,
            hint=f"tracks CSV needs the columns {','.join(HEADER)}",
        )
    try:
        kind = row["kind"]
        if kind not in get_args(TrackKind):
            raise ValueError(f"kind {kind!r} is not one of {', '.join(TRACK_KINDS)}")
        cxx, cxy, cyy = (_number(row, k, "nan") for k in ("cov_xx", "cov_xy", "cov_yy"))
        size = int(row.get("size") or 1)
        if not 0 <= size <= 1_000_000:
            raise ValueError(f"size {size} is not a number of people")
        track = Track(
            track_id=ids(row["track_id"]),
            kind=kind,
            position=np.array([float(row["x"]), float(row["y"])]),
            velocity=np.array([_number(row, "vx", "nan"), _number(row, "vy", "nan")]),
            covariance=np.array([[cxx, cxy], [cxy, cyy]]),
            size=size,
            labels=row.get("labels") or "",
        )
        scan, stamp = int(row["scan"]), float(row["stamp"])
        if not 0 <= scan < NAMED_ID_BASE:
            raise ValueError(f"scan {scan} is negative or too large")
        if not math.isfinite(stamp):
            raise ValueError("stamp is not finite")
    except (KeyError, TypeError, ValueError) as exc:
        raise RecordingError(
            f"line {line}: {exc}",
            path=path,
            hint=f"tracks CSV needs the columns {','.join(HEADER)}",
        ) from exc
    if not (math.isfinite(track.position[0]) and math.isfinite(track.position[1])):
        raise RecordingError(f"line {line}: position is not finite", path=path)
    return scan, stamp, track


def _number(row: dict[str, Any], key: str, empty: str) -> float:
    """A float cell (``empty`` when the cell is missing or blank)."""
    return float(row.get(key) or empty)


TRACKS_HINT = "give the tracks CSV written by `laserpeople track -o tracks.csv`"


def iter_tracks_csv(
    path: str | Path, frame: CoordinateFrame = "world", kinds: tuple[TrackKind, ...] | None = None
) -> Iterator[Tracks]:
    """Read a tracks CSV back as one :class:`Tracks` per scan that has rows, in scan order.

    ``frame`` states which frame the file was written in; ``kinds`` keeps only those kinds.

    Raises:
        RecordingError: the file is missing, a directory, not UTF-8 text or unreadable, lacks
            a column, has a bad row, or its scans go backwards or repeat (rows of one scan
            must be together, as ``laserpeople track`` writes them); the message names the
            file and the line or scan.
    """
    p = Path(path)
    if not p.exists():
        raise RecordingError("file not found", path=p, hint=TRACKS_HINT)
    if p.is_dir():
        raise RecordingError("is a directory, not a tracks CSV", path=p, hint=TRACKS_HINT)
    try:
        yield from _read_tracks(p, frame, kinds)
    except UnicodeDecodeError as exc:
        raise RecordingError(
            f"not a text CSV (byte {exc.start} is not UTF-8)", path=p, hint=TRACKS_HINT
        ) from exc
    except OSError as exc:
        raise RecordingError(f"cannot read the tracks CSV: {exc.strerror or exc}", path=p) from exc


def _read_tracks(
    p: Path, frame: CoordinateFrame, kinds: tuple[TrackKind, ...] | None
) -> Iterator[Tracks]:
    with open(p, newline="", encoding="utf-8") as fh:
        torn: list[str] = []
        reader = csv.DictReader(complete_lines(fh, torn))
        columns = reader.fieldnames or []
        missing = [c for c in ("scan", "stamp", "track_id", "kind", "x", "y") if c not in columns]
        if missing:
            raise RecordingError(
                f"not a tracks CSV: missing column(s) {', '.join(missing)}",
                path=p,
                hint=f"expected header {','.join(HEADER)}",
            )
        current: list[Track] = []
        key: tuple[int, float] | None = None
        last = -1
        ids = TrackIdMap()
        for line, row in enumerate(reader, start=2):
            scan, stamp, track = _parse_row(row, p, line, ids)
            if key is None or scan != key[0]:
                if scan <= last:
                    raise RecordingError(
                        f"line {line}: rows of scan {scan} come after scan {last}",
                        path=p,
                        scan=scan,
                        hint="sort the tracks CSV by scan; all rows of one scan must be together",
                    )
                if key is not None and current:
                    yield Tracks(key[1], key[0], tuple(current), frame)
                current = []
                key = (scan, stamp)
                last = scan
            if kinds is None or track.kind in kinds:
                current.append(track)
        if torn:
            cut = torn_scan(torn)
            warn_torn(p, cut)
            if key is not None and cut == key[0]:
                return
        if key is not None and current:
            yield Tracks(key[1], key[0], tuple(current), frame)
