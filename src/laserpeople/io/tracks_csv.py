"""Tracks CSV: one row per track per scan, written and flushed scan by scan.

Header::

    scan,stamp,track_id,kind,x,y,vx,vy,cov_xx,cov_xy,cov_yy,size,labels

``scan`` is the 0-based index of the scan on its topic, positions [m] and velocities
[m/s] are in the frame chosen when writing (``--output-frame``), ``size`` is the
estimated number of people (1 for legs and persons), ``labels`` the group label set.
Files written with a ``topic`` go on with ``topic``: the laser topic the tracks come from,
or ``fused`` when several lasers made each frame (then ``scan`` is the index of the first
laser's scan); ``frame``: ``world`` or ``sensor``, the frame of the positions
(:func:`read_tracks_frame`; ``view`` draws the tracks in it); and
``sensor_x,sensor_y,sensor_yaw``: the pose of the (first) laser in the world frame at that
scan ([m], [m], [rad]; empty where the recording gives no pose), with which a reader moves
the tracks into the other frame (``evaluate`` scores world-frame tracks against labels in
each scan's laser frame). Files written with ``contours`` (by the trackers of groups) end
with a ``contour`` column: a group's outline as ``x y;x y;...`` [m] in the frame of the
positions, empty for legs, persons and groups without one.
Readers accept files with and without these columns.
A scan with no tracks writes no row. Every scan's rows go to the file in one ``write()``
before the next scan is processed (:mod:`laserpeople.io.scan_lines`), so a crash or a kill
leaves a valid file with the scans done so far; a reader that finds the last scan cut off
anyway (a file cut short) leaves that scan out with a ``TornScanWarning``.

``track_id`` may be any text when reading (other trackers write UUIDs): an id that is not
a plain integer gets the integer :data:`STRING_ID_BASE` + k (k = 0, 1, ... in order of
first appearance), so that :class:`~laserpeople.tracks.Track` keeps integer ids and every
metric and drawing works unchanged; :class:`TrackIdNames` maps them back to the text.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any, get_args

import numpy as np

from laserpeople.errors import (
    LaserPeopleWarning,
    PoseUnavailableError,
    RecordingError,
)
from laserpeople.io.csv_read import CsvRows, not_utf8
from laserpeople.io.paths import path_argument
from laserpeople.io.scan_lines import ScanLineFile, ScanLineWriter, complete_lines, warn_torn
from laserpeople.scan import CoordinateFrame, Pose2D
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
TOPIC_COLUMN = "topic"
FRAME_COLUMN = "frame"
"""The frame of the positions (world / sensor), written with the topic column."""
CONTOUR_COLUMN = "contour"
SENSOR_POSE_COLUMNS = ("sensor_x", "sensor_y", "sensor_yaw")
"""The laser's pose in the world frame ([m], [m], [rad]), written with the topic column."""
KNOWN_COLUMNS = (*HEADER, TOPIC_COLUMN, FRAME_COLUMN, *SENSOR_POSE_COLUMNS, CONTOUR_COLUMN)
"""Every column a reader of tracks CSVs reads; others are said not read."""


def format_contour(contour: np.ndarray) -> str:
    """``"x y;x y;..."`` [m, 3 decimals] of a contour (K, 2); empty for K = 0."""
    return ";".join(f"{x:.3f} {y:.3f}" for x, y in np.asarray(contour).reshape(-1, 2))


def parse_contour(text: str) -> np.ndarray:
    """The contour (K, 2) of :func:`format_contour`'s text (K = 0 for an empty text)."""
    if not text.strip():
        return np.empty((0, 2))
    return np.array([[float(v) for v in p.split()] for p in text.split(";")]).reshape(-1, 2)


def convert_tracks(tracks: Tracks, frame: CoordinateFrame) -> Tracks:
    """The same tracks expressed in ``frame`` (uses ``tracks.sensor_pose``)."""
    if tracks.frame == frame:
        return tracks
    pose = tracks.sensor_pose
    if pose is None:
        raise PoseUnavailableError(
            f"cannot express tracks in the {frame} frame: the scan has no sensor pose",
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


class TracksCsvWriter(ScanLineFile):
    """Write :class:`~laserpeople.tracks.Tracks` to CSV, flushing after every scan.

    Example:
        >>> with TracksCsvWriter("tracks.csv", frame="world") as out:  # doctest: +SKIP
        ...     for tracks in tracker_outputs:
        ...         out.write(tracks)
    """

    def __init__(
        self,
        path: str | Path,
        frame: CoordinateFrame = "world",
        topic: str | None = None,
        contours: bool = False,
    ) -> None:
        self.path = Path(path)
        self.frame = frame
        self.topic = topic
        header = (
            HEADER if topic is None else (*HEADER, TOPIC_COLUMN, FRAME_COLUMN, *SENSOR_POSE_COLUMNS)
        )
        self._out = ScanLineWriter(
            self.path, (*header, CONTOUR_COLUMN) if contours else header, "tracks CSV"
        )
        self.rows = 0
        self.contours = contours
        self._tail: tuple[str, ...] = () if topic is None else (topic, frame)

    def write(self, tracks: Tracks) -> None:
        """Append the rows of one scan with one ``write()`` (see the module docstring).

        Raises:
            RecordingError: The write failed (disk full); the file keeps the earlier scans.
        """
        tracks = convert_tracks(tracks, self.frame)
        rows = []
        scan, stamp = tracks.scan_index, f"{tracks.stamp:.6f}"
        pose = _pose_cells(tracks.sensor_pose) if self.topic is not None else ()
        for t in tracks.tracks:
            # (Python floats: formatting a numpy scalar costs twice as much; same text)
            x, y = t.position.tolist()
            vx, vy = t.velocity.tolist()
            (cxx, cxy), (_, cyy) = t.covariance.tolist()
            rows.append(
                (
                    scan,
                    stamp,
                    t.track_id,
                    t.kind,
                    f"{x:.4f}",
                    f"{y:.4f}",
                    f"{vx:.4f}",
                    f"{vy:.4f}",
                    f"{cxx:.6g}",
                    f"{cxy:.6g}",
                    f"{cyy:.6g}",
                    t.size,
                    t.labels,
                    *self._tail,
                    *pose,
                    *((format_contour(t.contour),) if self.contours else ()),
                )
            )
        name = f"scan {scan}" + (f" of {self.topic}" if self.topic else "")
        if rows:
            self._out.write_rows(rows, scan=name)
            self.rows += len(rows)
        else:
            self._out.pass_scan(name)


def _pose_cells(pose: Pose2D | None) -> tuple[str, str, str]:
    """The ``sensor_x,sensor_y,sensor_yaw`` cells of ``pose`` (empty cells for None)."""
    if pose is None:
        return ("", "", "")
    return (f"{pose.x:.6f}", f"{pose.y:.6f}", f"{pose.theta:.9f}")


def parse_pose_cells(row: dict[str, Any], path: Path, line: int) -> Pose2D | None:
    """The sensor pose of a row's ``sensor_x,sensor_y,sensor_yaw`` cells; None when the
    columns are missing or all empty.

    Raises:
        RecordingError: some cells empty and others not, or a cell that is not a finite
            number (the message names the file and line).
    """
    cells = [(row.get(c) or "").strip() for c in SENSOR_POSE_COLUMNS]
    if not any(cells):
        return None
    try:
        x, y, yaw = (float(c) for c in cells)
    except ValueError as exc:
        raise RecordingError(
            f"line {line}: the sensor pose {','.join(cells)} is not three numbers",
            path=path,
            hint="sensor_x, sensor_y, sensor_yaw are all numbers or all empty",
        ) from exc
    if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(yaw)):
        raise RecordingError(
            f"line {line}: the sensor pose {','.join(cells)} is not finite", path=path
        )
    return Pose2D(x, y, yaw)


def parse_frame_cell(text: str, path: Path, line: int) -> CoordinateFrame | None:
    """A ``frame`` cell of a CSV: ``sensor`` or ``world``; None when empty.

    Raises:
        RecordingError: anything else (the message names the file and line).
    """
    text = text.strip()
    if text == "sensor" or text == "world":
        return "sensor" if text == "sensor" else "world"
    if not text:
        return None
    raise RecordingError(
        f"line {line}: frame {text!r} is neither sensor nor world",
        path=path,
        hint="the frame column says which frame x, y are in: sensor or world",
    )


def _parse_row(
    row: dict[str, Any], path: Path, line: int, ids: TrackIdNames
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
            track_id=ids.to_int(row["track_id"]),
            kind=kind,
            position=np.array([float(row["x"]), float(row["y"])]),
            velocity=np.array([_number(row, "vx", "nan"), _number(row, "vy", "nan")]),
            covariance=np.array([[cxx, cxy], [cxy, cyy]]),
            size=size,
            labels=row.get("labels") or "",
            contour=parse_contour(row.get(CONTOUR_COLUMN) or ""),
        )
        scan, stamp = int(row["scan"]), float(row["stamp"])
        if not 0 <= scan < ID_LIMIT:
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


ID_LIMIT = 2**62
"""Scan indices (and the integer ids of a truth CSV) read from a CSV stay below this, so
that they fit int64 arrays with room to spare."""

STAMP_TOLERANCE = 1e-6
"""Largest difference [s] between the stamps of rows of the same scan (tracks and truth
CSVs)."""

STRING_ID_BASE = 1 << 40
"""First integer given to a track id that is not an integer (far above any id a tracker
of this package writes)."""


class TrackIdNames:
    """The text ids of a tracks CSV and the integers that stand for them.

    Example:
        >>> names = TrackIdNames()
        >>> names.to_int("7"), names.to_int("a1b2") == STRING_ID_BASE
        (7, True)
        >>> names.name(STRING_ID_BASE)
        'a1b2'
    """

    def __init__(self) -> None:
        self._ints: dict[str, int] = {}
        self._names: dict[int, str] = {}

    def __len__(self) -> int:
        return len(self._names)

    def to_int(self, text: str) -> int:
        """The integer id of ``text``: itself when it is a plain integer (``"7"``, ``"-3"``)
        of magnitude below :data:`STRING_ID_BASE`, else (other text, or a longer number) a
        new or known id from :data:`STRING_ID_BASE` on, the same for every row."""
        t = text.strip()
        if not t:
            raise ValueError("track_id is empty")
        digits = t[1:] if t[:1] in "+-" else t
        if digits.isascii() and digits.isdigit():
            value = int(t)
            if -STRING_ID_BASE < value < STRING_ID_BASE:
                return value
        got = self._ints.get(t)
        if got is None:
            got = STRING_ID_BASE + len(self._ints)
            self._ints[t] = got
            self._names[got] = t
        return got

    def name(self, track_id: int) -> str:
        """The id as written in the CSV."""
        return self._names.get(int(track_id), str(int(track_id)))


TRACKS_HINT = "give the tracks CSV written by `laserpeople track -o tracks.csv`"


def _existing_csv(path: str | Path) -> Path:
    """``path`` when it names a file; RecordingError with a hint otherwise."""
    p = Path(path)
    if not p.exists():
        raise RecordingError("file not found", path=p, hint=TRACKS_HINT)
    if p.is_dir():
        raise RecordingError("is a directory, not a tracks CSV", path=p, hint=TRACKS_HINT)
    return p


def _first_row_value(path: str | Path, column: str) -> str | None:
    """``column`` of a tracks CSV's first row; None without the column, rows or value."""
    p = _existing_csv(path)
    try:
        with open(p, newline="", encoding="utf-8") as fh:
            reader = CsvRows(fh, p, "tracks CSV", TRACKS_HINT)
            if column not in reader.fieldnames:
                return None
            row = next(reader, None)
    except UnicodeDecodeError as exc:
        raise RecordingError(f"not a text CSV: {not_utf8(p)}", path=p, hint=TRACKS_HINT) from exc
    except OSError as exc:
        raise RecordingError(f"cannot read the tracks CSV: {exc}", path=p) from exc
    return None if row is None else (row.get(column) or None)


def read_tracks_topic(path: str | Path) -> str | None:
    """The ``topic`` of a tracks CSV's first row, or None for files without the column
    (written before it existed) or without rows."""
    return _first_row_value(path, TOPIC_COLUMN)


def read_tracks_frame(path: str | Path) -> CoordinateFrame | None:
    """The frame (world / sensor) a tracks CSV's positions are in, from its ``frame``
    column; None for files without the column (written before it existed, or by other
    programs) or without rows."""
    value = _first_row_value(path, FRAME_COLUMN)
    return value if value in ("world", "sensor") else None  # type: ignore[return-value]


def count_track_kinds(path: str | Path) -> dict[str, int]:
    """Rows per ``kind`` of a tracks CSV (empty for a file without the column or rows, or
    one that cannot be read as text)."""
    p = _existing_csv(path)
    counts: dict[str, int] = {}
    try:
        with open(p, newline="", encoding="utf-8") as fh:
            reader = CsvRows(
                (line for line in fh if not line.startswith("#")), p, "tracks CSV", TRACKS_HINT
            )
            if "kind" not in reader.fieldnames:
                return counts
            for row in reader:
                kind = row.get("kind") or ""
                counts[kind] = counts.get(kind, 0) + 1
    except (OSError, UnicodeDecodeError, RecordingError):
        return {}  # unreadable: the reader that follows says what is wrong, and where
    return counts


def check_read_arguments(
    function: str, path: object, frame: object, kinds: object, ids: object
) -> Path:
    """The arguments of a tracks reader (:func:`iter_tracks_csv`,
    :func:`~laserpeople.io.tracks_files.read_tracks_file`) checked before any file is read:
    ``path`` as a :class:`~pathlib.Path`.

    Raises:
        TypeError: an argument of the wrong type; ValueError: a frame or kind that does not
            exist. Both name the function, the argument and what it takes.
    """
    p = path_argument(path, "path", function)
    if frame not in ("world", "sensor"):
        raise ValueError(f"{function}(): frame must be 'world' or 'sensor', got {frame!r}")
    if kinds is not None:
        if isinstance(kinds, str) or not isinstance(kinds, tuple | list | set | frozenset):
            raise TypeError(
                f"{function}(): kinds must be a tuple of kinds such as ('person',), "
                f"got {type(kinds).__name__} {kinds!r}"
            )
        unknown = [k for k in kinds if k not in TRACK_KINDS]
        if unknown:
            raise ValueError(
                f"{function}(): unknown kind(s) {', '.join(map(repr, unknown))} in kinds; "
                f"the kinds are {', '.join(TRACK_KINDS)}"
            )
    if ids is not None and not isinstance(ids, TrackIdNames):
        raise TypeError(
            f"{function}(): ids must be a TrackIdNames or None, got {type(ids).__name__}"
        )
    return p


def iter_tracks_csv(
    path: str | Path,
    frame: CoordinateFrame = "world",
    kinds: tuple[TrackKind, ...] | None = None,
    ids: TrackIdNames | None = None,
) -> Iterator[Tracks]:
    """Read a tracks CSV back as one :class:`Tracks` per scan that has rows, in scan order.

    ``frame`` is the frame of a file without a ``frame`` column (a file that has one says
    its frame per scan: ``sensor`` or ``world``); ``kinds`` keeps only those kinds;
    ``ids`` (if given) collects the text ids that are not integers (see the module
    docstring), so that reports can print them as written.

    Raises:
        RecordingError: the file is missing, a directory, not UTF-8 text or unreadable, lacks
            a column, has a bad row, or its scans go backwards or repeat (rows of one scan
            must be together, as ``laserpeople track`` writes them); the message names the
            file and the line or scan. Raised as the file is read.
        TypeError, ValueError: an argument of the wrong type or value (at the call).
    """
    p = check_read_arguments("iter_tracks_csv", path, frame, kinds, ids)
    return _iter_tracks_csv(p, frame, kinds, ids)


def _iter_tracks_csv(
    path: Path,
    frame: CoordinateFrame,
    kinds: tuple[TrackKind, ...] | None,
    ids: TrackIdNames | None,
) -> Iterator[Tracks]:
    p = _existing_csv(path)
    try:
        yield from _read_tracks(p, frame, kinds, ids if ids is not None else TrackIdNames())
    except UnicodeDecodeError as exc:
        raise RecordingError(f"not a text CSV: {not_utf8(p)}", path=p, hint=TRACKS_HINT) from exc
    except OSError as exc:
        raise RecordingError(f"cannot read the tracks CSV: {exc.strerror or exc}", path=p) from exc


def _read_tracks(
    p: Path, frame: CoordinateFrame, kinds: tuple[TrackKind, ...] | None, ids: TrackIdNames
) -> Iterator[Tracks]:
    with open(p, newline="", encoding="utf-8") as fh:
        torn: list[str] = []
        reader = CsvRows(complete_lines(fh, torn), p, "tracks CSV", TRACKS_HINT)
        columns = reader.require(("scan", "stamp", "track_id", "kind", "x", "y"), ",".join(HEADER))
        unread = [c for c in columns if c not in KNOWN_COLUMNS]
        if unread:
            warnings.warn(
                f"{p}: column(s) {', '.join(unread)} not read (a tracks CSV's columns are "
                f"{','.join(HEADER)}[,{','.join(KNOWN_COLUMNS[len(HEADER) :])}])",
                LaserPeopleWarning,
                stacklevel=4,
            )
        current: list[Track] = []
        rows_of: dict[tuple[str, int], int] = {}  # (kind, track id) -> line, in this scan
        key: tuple[int, float] | None = None
        last = -1
        scan_frame = frame
        pose: Pose2D | None = None
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
                    yield Tracks(key[1], key[0], tuple(current), scan_frame, pose)
                current = []
                rows_of = {}
                key = (scan, stamp)
                last = scan
                scan_frame = parse_frame_cell(row.get(FRAME_COLUMN) or "", p, line) or frame
                pose = parse_pose_cells(row, p, line)
            elif abs(stamp - key[1]) > STAMP_TOLERANCE:
                raise RecordingError(
                    f"line {line}: stamp {stamp} differs from {key[1]} given earlier "
                    "for the same scan",
                    path=p,
                    scan=scan,
                    hint="all rows of one scan must carry the same stamp",
                )
            first = rows_of.setdefault((track.kind, track.track_id), line)
            if first != line:
                raise RecordingError(
                    f"lines {first} and {line}: {track.kind} track "
                    f"{str(row.get('track_id', '')).strip()} has two rows in scan {scan}",
                    path=p,
                    scan=scan,
                    hint="a track has one row per scan: delete one of them, or give the "
                    "second track its own track_id",
                )
            if kinds is None or track.kind in kinds:
                current.append(track)
        if torn:
            cut = warn_torn(p, torn)
            if key is not None and cut == key[0]:
                return
        if key is not None and current:
            yield Tracks(key[1], key[0], tuple(current), scan_frame, pose)
