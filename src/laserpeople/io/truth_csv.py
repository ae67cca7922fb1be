"""Ground truth as CSV: one row per annotated person per scan.

Header (extra columns are ignored; ``group_id`` is optional)::

    scan,stamp,person_id,x,y[,group_id][,frame]

``scan`` is the 0-based index of the scan on its topic (as in the tracks CSV), ``stamp`` its
time [s], ``person_id`` an integer ``0 <= id < 2**62`` or a name (``alice``, ``p3``: text that is no
number; each name is numbered after the largest integer id of the file, in the order first
seen, and the reader says which number each name got), ``x, y`` the person's position [m] in the
world frame, ``group_id`` the group (-1 or empty: walks alone), ``frame`` the frame of x, y
(``world``, or ``sensor``: the laser's frame at that scan; one for the whole file; without
it the frame is not stated, and the scorer says it took the tracks'). The annotation may be
sparse: only scans that appear in the file are scored. A scan that was annotated and holds
nobody is one row with ``person_id``, ``x`` and ``y`` empty. Rows may come in any order;
they are grouped by scan.
"""

from __future__ import annotations

import csv
import math
import warnings
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from laserpeople.errors import LaserPeopleWarning, RecordingError
from laserpeople.io.csv_read import CsvRows, not_utf8
from laserpeople.io.paths import path_argument
from laserpeople.io.tracks_csv import ID_LIMIT, STAMP_TOLERANCE, parse_frame_cell
from laserpeople.scan import CoordinateFrame
from laserpeople.truth import NONE_ID, TruthFrame

TRUTH_CSV_HEADER = ("scan", "stamp", "person_id", "x", "y", "group_id")
REQUIRED = ("scan", "stamp", "person_id", "x", "y")
TRUTH_HINT = "give a CSV scan,stamp,person_id,x,y[,group_id]"


def read_truth_csv(path: str | Path) -> list[TruthFrame]:
    """Read a truth CSV into one :class:`TruthFrame` per annotated scan, in scan order.

    Raises:
        RecordingError: the file is missing, lacks a column, or a row is malformed (the
            message names the line); a person appears twice in one scan; the rows of one
            scan disagree on its stamp.
        TypeError: ``path`` is no str or path.
    """
    p = path_argument(path, "path", "read_truth_csv")
    if p.is_dir():
        raise RecordingError(
            "is a directory, not a ground-truth CSV", path=p, hint="give the CSV file itself"
        )
    if not p.is_file():
        raise RecordingError("ground-truth CSV not found", path=p, hint="check the path")
    try:
        return _read_truth_csv(p)
    except UnicodeDecodeError as exc:
        raise RecordingError(
            f"not a text CSV: {not_utf8(p)}",
            path=p,
            hint="give a CSV scan,stamp,person_id,x,y; a recording with truth must end in .npz",
        ) from exc
    except OSError as exc:
        raise RecordingError(
            f"cannot read the ground-truth CSV: {exc.strerror or exc}", path=p
        ) from exc


Person = tuple[int | str, float, float, int]
"""One truth row's person: id (an integer or a name), x, y [m], group id."""

NAMES_SHOWN = 10
"""Names whose numbers the reader's note lists (then "and k more")."""


def number_names(ids: list[int | str], path: Path) -> dict[int | str, int]:
    """The integer id of every person id of a file: an integer stays itself; a name gets
    the next number after the file's largest integer id (0 without any), in the order first
    seen in ``ids``. Warns (:class:`LaserPeopleWarning`) with each name's number when there
    are names."""
    numbers: dict[int | str, int] = {i: i for i in ids if isinstance(i, int)}
    names = [i for i in dict.fromkeys(ids) if isinstance(i, str)]
    if not names:
        return numbers
    start = max((i for i in ids if isinstance(i, int)), default=-1) + 1
    if start + len(names) > ID_LIMIT:
        raise RecordingError(
            f"{len(names)} person_id names do not fit after the integer id {start - 1}",
            path=path,
            hint="give every person a name, or every person an integer id",
        )
    numbers.update({name: start + k for k, name in enumerate(names)})
    shown = ", ".join(f"{name} = {start + k}" for k, name in enumerate(names[:NAMES_SHOWN]))
    more = f" and {len(names) - NAMES_SHOWN} more" if len(names) > NAMES_SHOWN else ""
    warnings.warn(
        f"{path}: person_id is a name for {len(names)} people, numbered in the order first "
        f"seen{' after the largest integer id' if start else ''}: {shown}{more} (the "
        "figures and pictures name people by these numbers)",
        LaserPeopleWarning,
        stacklevel=4,
    )
    return numbers


def _read_truth_csv(p: Path) -> list[TruthFrame]:
    scans: dict[int, tuple[float, list[Person]]] = {}
    frame: CoordinateFrame | None = None
    with open(p, newline="", encoding="utf-8") as fh:
        reader = CsvRows(fh, p, "ground-truth CSV", TRUTH_HINT)
        columns = reader.require(REQUIRED, f"{','.join(REQUIRED)}[,group_id][,frame]")
        unread = [c for c in columns if c not in (*TRUTH_CSV_HEADER, "frame")]
        if unread:
            warnings.warn(
                f"{p}: column(s) {', '.join(unread)} not read (a ground-truth CSV's columns "
                f"are {','.join(REQUIRED)}[,group_id][,frame])",
                LaserPeopleWarning,
                stacklevel=3,
            )
        for line, row in enumerate(reader, start=2):
            scan, stamp, person = _parse_row(row, p, line)
            frame = _file_frame(row, frame, p, line)
            stamp_seen, people = scans.setdefault(scan, (stamp, []))
            if abs(stamp_seen - stamp) > STAMP_TOLERANCE:
                raise RecordingError(
                    f"line {line}: stamp {stamp} differs from {stamp_seen} given earlier "
                    f"for the same scan",
                    path=p,
                    scan=scan,
                    hint="all rows of one scan must carry the same stamp",
                )
            if person is None:
                continue
            if any(q[0] == person[0] for q in people):
                raise RecordingError(
                    f"line {line}: person {person[0]} appears twice in this scan",
                    path=p,
                    scan=scan,
                    hint="give each person once per scan",
                )
            people.append(person)
    if not scans:
        raise RecordingError(
            "the ground-truth CSV has no rows", path=p, hint="annotate at least one scan"
        )
    numbers = number_names([q[0] for _, people in scans.values() for q in people], p)
    frames = []
    for scan in sorted(scans):
        stamp, people = scans[scan]
        ids = np.array([numbers[q[0]] for q in people], dtype=np.int64)
        xy = np.array([(q[1], q[2]) for q in people], dtype=np.float64).reshape(-1, 2)
        n = ids.size
        frames.append(
            TruthFrame(
                stamp=stamp,
                scan_index=scan,
                person_ids=ids,
                positions=xy,
                velocities=np.full((n, 2), np.nan),
                group_ids=np.array([q[3] for q in people], dtype=np.int64),
                leg_positions=np.full((n, 2, 2), np.nan),
                hues=np.full(n, np.nan),
                frame=frame,
            )
        )
    return frames


def _file_frame(
    row: dict[str, str | None], frame: CoordinateFrame | None, path: Path, line: int
) -> CoordinateFrame | None:
    """The file's frame after ``row``: its ``frame`` cell if given (``sensor`` or
    ``world``, the same on every row that gives one), else ``frame`` as before."""
    given = parse_frame_cell(row.get("frame") or "", path, line)
    if given is None:
        return frame
    if frame is not None and given != frame:
        raise RecordingError(
            f"line {line}: frame {given!r} differs from {frame!r} given earlier",
            path=path,
            hint="one truth CSV holds positions in one frame",
        )
    return given


def _person_id(text: str) -> int | str:
    """A person_id cell: an integer ``0 <= id < 2**62``, or a name (text that is no
    number). Raises ValueError for a number that is no such integer."""
    try:
        person = int(text)
    except ValueError:
        try:
            float(text)
        except ValueError:
            if not text:
                raise ValueError("column person_id is empty, not an id") from None
            return text
        raise ValueError(
            f"column person_id is {text!r}, a number but not an integer (a table program "
            "that wrote ids as 3.0: save the column as integers, or name each person)"
        ) from None
    if not 0 <= person < ID_LIMIT:
        raise ValueError(f"person_id {person} is negative or too large")
    return person


def _parse_row(
    row: dict[str, str | None], path: Path, line: int
) -> tuple[int, float, Person | None]:
    def cell(key: str) -> str:
        value = row.get(key)
        return "" if value is None else value.strip()

    def number(key: str, kind: type[int] | type[float]) -> int | float:
        text = cell(key)
        try:
            return kind(text)
        except ValueError:
            what = "an integer" if kind is int else "a number"
            shown = repr(text) if text else "empty"
            raise ValueError(f"column {key} is {shown}, not {what}") from None

    try:
        extra = row.get(None) or []  # type: ignore[call-overload]
        if any(str(v).strip() for v in extra):
            raise ValueError(f"{len(extra)} more field(s) than the header has columns")
        scan = int(number("scan", int))
        stamp = float(number("stamp", float))
        if not 0 <= scan < ID_LIMIT:
            raise ValueError(f"scan {scan} is negative or too large")
        if not math.isfinite(stamp):
            raise ValueError("stamp is not finite")
        if cell("person_id") == "" and cell("x") == "" and cell("y") == "":
            return scan, stamp, None
        person = _person_id(cell("person_id"))
        x, y = float(number("x", float)), float(number("y", float))
        if not (math.isfinite(x) and math.isfinite(y)):
            raise ValueError("x or y is not finite")
        group_text = cell("group_id")
        group = int(number("group_id", int)) if group_text else NONE_ID
        if group >= ID_LIMIT:
            raise ValueError(f"group_id {group} is larger than {ID_LIMIT - 1}")
        group = max(group, NONE_ID)
    except ValueError as exc:
        raise RecordingError(
            f"line {line}: {exc}",
            path=path,
            hint="each row is scan (int), stamp (s), person_id (an integer or a name), "
            "x, y (m) [, group_id]; an empty scan is scan,stamp,,,",
        ) from exc
    return scan, stamp, (person, x, y, group)


def write_truth_csv(path: str | Path, frames: Iterable[TruthFrame]) -> int:
    """Write truth frames as a truth CSV (a frame without people becomes an empty-scan row;
    a ``frame`` column when the frames state their frame).

    Returns:
        The number of rows written.
    """
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    rows = 0
    stated: bool | None = None
    with open(p, "w", newline="", encoding="utf-8") as fh:
        out = csv.writer(fh, lineterminator="\n")
        for frame in frames:
            if stated is None:
                stated = frame.frame is not None
                out.writerow(TRUTH_CSV_HEADER + (("frame",) if stated else ()))
            tail = (frame.frame or "",) if stated else ()
            if len(frame) == 0:
                out.writerow((frame.scan_index, f"{frame.stamp:.6f}", "", "", "", "", *tail))
                rows += 1
                continue
            for pid, (x, y), gid in zip(
                frame.person_ids.tolist(),
                frame.positions.tolist(),
                frame.group_ids.tolist(),
                strict=True,
            ):
                out.writerow(
                    (
                        frame.scan_index,
                        f"{frame.stamp:.6f}",
                        pid,
                        f"{x:.4f}",
                        f"{y:.4f}",
                        gid,
                        *tail,
                    )
                )
                rows += 1
        if stated is None:
            out.writerow(TRUTH_CSV_HEADER)
    return rows
