"""The one way this package reads a CSV file: :class:`CsvRows`.

Python's :mod:`csv` refuses a field longer than its field limit with a bare
``_csv.Error``, and a damaged file can hold one (a line without a newline, a quote that
never closes). :class:`CsvRows` reads with an explicit :data:`FIELD_LIMIT` and turns any
``csv.Error`` into a :class:`~laserpeople.errors.RecordingError` that names the file, the
line and what to do. Every CSV reader (tracks, truth, detections) uses it.
"""

from __future__ import annotations

import codecs
import csv
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

from laserpeople.errors import RecordingError

FIELD_LIMIT = 131_072
"""Longest field [characters] a CSV cell may hold (Python's default limit; a tracks CSV's
longest cells, group contours, are a few hundred characters)."""


class CsvRows:
    """Rows of a CSV as dicts keyed by the header (like :class:`csv.DictReader`).

    Args:
        lines: The file's lines (an open text file or any iterable of lines).
        path: The file, for error messages.
        what: What the file is ("tracks CSV"), for error messages.
        hint: What to do about a damaged file.

    Raises:
        RecordingError: (when reading the header or a row) a field is longer than
            :data:`FIELD_LIMIT` or the CSV is malformed; names the file and the line.
    """

    def __init__(self, lines: Iterable[str], path: str | Path, what: str, hint: str) -> None:
        if csv.field_size_limit() != FIELD_LIMIT:
            csv.field_size_limit(FIELD_LIMIT)
        self._reader = csv.DictReader(_without_bom(lines))
        self.path = Path(path)
        self.what = what
        self.hint = hint

    def _error(self, exc: csv.Error) -> RecordingError:
        text = str(exc)
        if "field larger than field limit" in text:
            text = f"a field is longer than {FIELD_LIMIT:,} characters (the limit)"
        return RecordingError(  # (line_num counts the lines read before the bad one)
            f"line {self._reader.line_num + 1}: not a readable {self.what}: {text}",
            path=self.path,
            hint=self.hint,
        )

    @property
    def fieldnames(self) -> list[str]:
        """The header's column names (empty for an empty file)."""
        try:
            return list(self._reader.fieldnames or [])
        except csv.Error as exc:
            raise self._error(exc) from exc

    @fieldnames.setter
    def fieldnames(self, names: list[str]) -> None:
        self._reader.fieldnames = names

    def require(self, columns: Iterable[str], expected: str) -> list[str]:
        """The header's column names (stripped of spaces), checked to hold ``columns``.

        Raises:
            RecordingError: the file is empty, or a column is missing; names them, the
                ``expected`` header, and the separator when the header is separated by ``;``
                or tabs.
        """
        names = [c.strip() for c in self.fieldnames]
        if not names:
            raise RecordingError(
                f"the {self.what} is empty: no header line",
                path=self.path,
                hint=f"expected header {expected}; was the file cut short when written?",
            )
        self.fieldnames = names
        missing = [c for c in columns if c not in names]
        if not missing:
            return names
        hint = f"expected header {expected}" + columns_to_rename(missing, names)
        other = csv_format_of(names)
        if other is not None and other[0] != self.what:
            hint += f"; this header is that of {other[1]}"
        if len(names) == 1:
            sep = next((s for s in (";", "\t", "|") if s in names[0]), None)
            if sep is not None:
                shown = "tabs" if sep == "\t" else repr(sep)
                hint += f"; this header is separated by {shown}: save the CSV with commas"
        raise RecordingError(
            f"not a {self.what}: missing column(s) {', '.join(missing)}", path=self.path, hint=hint
        )

    def __iter__(self) -> Iterator[dict[str, Any]]:
        return self

    def __next__(self) -> dict[str, Any]:
        try:
            return next(self._reader)
        except csv.Error as exc:
            raise self._error(exc) from exc


COLUMN_ALIASES: dict[str, tuple[str, ...]] = {
    "scan": ("scan_index", "seq", "frame_index", "frame_id", "index"),
    "stamp": ("timestamp", "time", "t", "secs", "sec", "stamp_s", "time_s"),
    "track_id": ("id", "track", "trackid", "tid", "object_id"),
    "person_id": ("id", "person", "personid", "pid", "label"),
    "x": ("pos_x", "position_x", "px", "x_m"),
    "y": ("pos_y", "position_y", "py", "y_m"),
}
"""Names other tools give the columns of this program's CSVs (compared in lower case)."""


def columns_to_rename(missing: Iterable[str], names: Iterable[str]) -> str:
    """A hint naming the columns of a header of column ``names`` that stand for the
    ``missing`` ones: the same name in other case or spacing (``SCAN``), or one of
    :data:`COLUMN_ALIASES` (``timestamp`` for ``stamp``), and what a missing column none
    stands for holds (:data:`COLUMN_MEANINGS`); empty when there is nothing to say. Each
    column of the header is named for one missing column at most."""
    by_lower: dict[str, str] = {}
    for name in names:
        by_lower.setdefault(name.strip().lower(), name)
    renames: dict[str, str] = {}  # missing column -> the header's column standing for it
    for column in missing:
        for candidate in (column, *COLUMN_ALIASES.get(column, ())):
            found = by_lower.pop(candidate, None)
            if found is not None and found != column:
                renames[column] = found
                break
    text = "".join(
        f"; {COLUMN_MEANINGS[c]}" for c in missing if c in COLUMN_MEANINGS and c not in renames
    )
    if renames:
        shown = ", ".join(f"{found} to {column}" for column, found in renames.items())
        text += (
            f"; rename the column(s) {shown} (stamps in seconds, positions in metres, as this "
            "program writes them)"
        )
    return text


COLUMN_MEANINGS = {
    "scan": "scan is the 0-based index of each scan on its laser topic, by which tracks and "
    "truth are paired",
    "kind": "kind is leg, person or group (person for tracks of people)",
}
"""What a missing column holds, said when no column of the header stands for it."""


CSV_FORMATS: tuple[tuple[str, frozenset[str], str], ...] = (
    (
        "tracks CSV",
        frozenset({"scan", "track_id", "kind", "x", "y"}),
        "a tracks CSV (`laserpeople track -o`): give it as TRACKS",
    ),
    (
        "ground-truth CSV",
        frozenset({"scan", "stamp", "person_id", "x", "y"}),
        "a ground-truth CSV: give it with --truth",
    ),
    (
        "detections CSV",
        frozenset({"scan", "stamp", "x", "y", "score"}),
        "a detections CSV (`laserpeople detect -o`): legs, not tracks or truth",
    ),
)
"""The CSV files of this program by the columns their headers hold: what each is called
(:attr:`CsvRows.what`), the columns that tell it, and what to say of it."""


def csv_format_of(names: Iterable[str]) -> tuple[str, str] | None:
    """Which of :data:`CSV_FORMATS` a header of column ``names`` is (its name and what to
    say of it), or None."""
    have = set(names)
    for what, columns, said in CSV_FORMATS:
        if columns <= have:
            return what, said
    return None


BOM = "\ufeff"
"""The byte order mark a spreadsheet's "CSV UTF-8" export puts before the header."""


def _without_bom(lines: Iterable[str]) -> Iterator[str]:
    """``lines`` with a byte order mark before the first one left out."""
    it = iter(lines)
    first = next(it, None)
    if first is None:
        return
    yield first.removeprefix(BOM)
    yield from it


def not_utf8(path: str | Path) -> str:
    """Where the file ``path`` first stops being UTF-8 text, for an error message:
    ``line 2,001 (byte 126,198) is not UTF-8``. (A decoding error of a text file read in
    chunks gives the position within a chunk, not in the file.)"""
    decoder = codecs.getincrementaldecoder("utf-8")()
    offset, line = 0, 1
    try:
        with open(path, "rb") as fh:
            while chunk := fh.read(1 << 20):
                try:
                    decoder.decode(chunk)
                except UnicodeDecodeError as exc:
                    held = len(exc.object) - len(chunk)  # bytes of a character begun before
                    at = max(exc.start - held, 0)
                    line += chunk.count(b"\n", 0, at)
                    return f"line {line:,} (byte {offset + at:,}) is not UTF-8"
                line += chunk.count(b"\n")
                offset += len(chunk)
    except OSError:
        pass
    return "it is not UTF-8 text"
