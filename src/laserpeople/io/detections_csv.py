"""Detections CSV: one row per detected leg, written and flushed scan by scan.

Header::

    scan,stamp,x,y,score

``scan`` is the 0-based index of the scan on its topic, ``stamp`` its time [s], ``x, y`` the
leg centre [m] in the sensor frame (or, for fused lasers, in the frame the caller states),
``score`` the detector's margin (AdaBoost F(e)).

With ``segment_columns`` every segment of the scan gets a row (detected or not) with the
extra columns ``segment,first_beam,n_beams,is_leg`` and the caller's value columns (the
``detect --all-segments`` command hands in the 14 feature names, ``f1_n_points ...
f14_mean_speed``; this file format does not know the classifier); ``score`` is empty for
segments of fewer than three points, which are not classified.

Files written with a ``topic`` end with one more column, ``topic``: the laser topic of
the row, or ``fused``. Readers accept files with and without it.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

import numpy as np

from laserpeople.errors import RecordingError
from laserpeople.io.csv_read import CsvRows, not_utf8
from laserpeople.io.scan_lines import ScanLineFile, ScanLineWriter, complete_lines, warn_torn
from laserpeople.scan import Scan
from laserpeople.tracks import Detections

HEADER = ("scan", "stamp", "x", "y", "score")
SEGMENT_COLUMNS = ("segment", "first_beam", "n_beams", "is_leg")
"""The per-segment columns before the caller's value columns (``--all-segments``)."""
TOPIC_COLUMN = "topic"
_INT_COLUMNS = frozenset({"scan", "segment", "first_beam", "n_beams", "is_leg"})


def _num(value: float) -> str:
    return "" if not math.isfinite(value) else repr(float(value))


class DetectionsCsvWriter(ScanLineFile):
    """Writes detections (or all classified segments) to a CSV file, flushing per scan.

    Args:
        path: The CSV to write.
        segment_columns: Names of the per-segment value columns (e.g. feature names); when
            given, rows come from :meth:`write_segments` with
            ``segment,first_beam,n_beams,is_leg`` and these columns after ``score``.
        topic: When given, every row ends with a ``topic`` column (pass the row's topic to
            :meth:`write` / :meth:`write_segments`; this value is the default).
    """

    def __init__(
        self,
        path: str | Path,
        *,
        segment_columns: tuple[str, ...] | None = None,
        topic: str | None = None,
    ) -> None:
        self.path = Path(path)
        self.segment_columns = segment_columns
        self.all_segments = segment_columns is not None
        self.topic = topic
        header = HEADER + ((*SEGMENT_COLUMNS, *segment_columns) if segment_columns else ())
        self._out = ScanLineWriter(
            self.path,
            header + ((TOPIC_COLUMN,) if topic is not None else ()),
            "detections CSV",
        )
        self.rows = 0

    def _tail(self, topic: str | None) -> list[str]:
        if self.topic is None:
            return []
        return [topic if topic is not None else self.topic]

    def write(self, detections: Detections, topic: str | None = None) -> None:
        """One row per detection, positions as given (sensor frame for one laser); the
        scan's rows go to the file in one ``write()``."""
        tail = self._tail(topic)
        rows = []
        for (x, y), score in zip(detections.positions, detections.scores, strict=True):
            rows.append(
                [
                    detections.scan_index,
                    repr(float(detections.stamp)),
                    repr(float(x)),
                    repr(float(y)),
                    _num(score),
                    *tail,
                ]
            )
        self._scan_rows(rows, detections.scan_index, topic if topic is not None else self.topic)

    def _scan_rows(self, rows: list[list[Any]], index: int, topic: str | None) -> None:
        """Write one scan's ``rows``, or count the scan when it has none."""
        name = f"scan {index}" + (f" of {topic}" if topic else "")
        if rows:
            self._out.write_rows(rows, scan=name)
            self.rows += len(rows)
        else:
            self._out.pass_scan(name)

    def write_segments(
        self,
        scan: Scan,
        centres: np.ndarray,
        first_beams: np.ndarray,
        sizes: np.ndarray,
        is_leg: np.ndarray,
        scores: np.ndarray,
        values: np.ndarray,
        topic: str | None = None,
    ) -> None:
        """One row per segment of ``scan`` with its ``values`` (S, len(segment_columns))
        (the ``--all-segments`` layout), all in one ``write()``."""
        tail = self._tail(topic if topic is not None else scan.sensor)
        rows = []
        for i in range(centres.shape[0]):
            row: list[Any] = [
                scan.index,
                repr(float(scan.stamp)),
                repr(float(centres[i, 0])),
                repr(float(centres[i, 1])),
                _num(scores[i]),
                i,
                int(first_beams[i]),
                int(sizes[i]),
                int(bool(is_leg[i])),
            ]
            row.extend(_num(v) for v in values[i])
            row.extend(tail)
            rows.append(row)
        self._scan_rows(rows, scan.index, topic if topic is not None else scan.sensor)


def _value(key: str, value: str) -> float | int | str:
    if key == TOPIC_COLUMN:
        return value
    if key in _INT_COLUMNS:
        return int(value)
    return float(value) if value != "" else math.nan


def iter_detections_csv(path: str | Path) -> Iterator[dict[str, float | int | str]]:
    """Rows of a detections CSV as dicts (``scan`` int, ``topic`` str when present, others
    float; empty -> NaN).

    A last scan cut off mid-write is left out with a ``TornScanWarning``.

    Raises:
        RecordingError: the file is missing, not a detections CSV, not UTF-8, or a row is
            malformed (the message names the line).
    """
    p = Path(path)
    try:
        fh = p.open(newline="", encoding="utf-8")
    except OSError as exc:
        raise RecordingError(f"cannot read detections: {exc}", path=p) from exc
    try:
        with fh:
            yield from _read_detections(fh, p)
    except UnicodeDecodeError as exc:
        raise RecordingError(f"not a text CSV: {not_utf8(p)}", path=p) from exc
    except (OSError, csv.Error) as exc:
        raise RecordingError(f"cannot read detections: {exc}", path=p) from exc


def _read_detections(fh: IO[str], p: Path) -> Iterator[dict[str, float | int | str]]:
    torn: list[str] = []
    reader = CsvRows(
        complete_lines(fh, torn), p, "detections CSV", "expected the header " + ",".join(HEADER)
    )
    if tuple(reader.fieldnames[:5]) != HEADER:
        raise RecordingError(
            f"not a detections CSV (header {reader.fieldnames!r:.200})",
            path=p,
            hint="expected the header " + ",".join(HEADER),
        )
    held: list[dict[str, float | int | str]] = []
    for line, row in enumerate(reader, start=2):
        if None in row or any(v is None for v in row.values()):
            raise RecordingError(
                f"line {line}: {'more' if None in row else 'fewer'} fields than the header",
                path=p,
            )
        try:
            parsed = {k: _value(k, v) for k, v in row.items()}
        except (TypeError, ValueError) as exc:
            raise RecordingError(f"line {line}: {str(exc)[:100]}", path=p) from exc
        if held and held[0]["scan"] != parsed["scan"]:
            yield from held
            held = []
        held.append(parsed)
    if torn:
        cut = warn_torn(p, torn)
        if held and cut == held[0]["scan"]:
            return
    yield from held
