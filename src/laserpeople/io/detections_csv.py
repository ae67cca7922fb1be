"""Detections CSV: one row per detected leg, written and flushed scan by scan.

Header::

    scan,stamp,x,y,score

``scan`` is the 0-based index of the scan on its topic, ``stamp`` its time [s], ``x, y`` the
leg centre [m] in the sensor frame, ``score`` the detector's margin (AdaBoost F(e)).

With ``all_segments=True`` every segment of the scan gets a row (detected or not) with the
extra columns ``segment,first_beam,n_beams,is_leg`` and the 14 features
(``f1_n_points ... f14_mean_speed``); ``score`` is empty for segments of fewer than three
points, which are not classified.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

import numpy as np

from laserpeople.detection.features import FEATURE_NAMES
from laserpeople.errors import RecordingError
from laserpeople.scan import Scan
from laserpeople.tracks import Detections

HEADER = ("scan", "stamp", "x", "y", "score")
SEGMENT_COLUMNS = (
    "segment",
    "first_beam",
    "n_beams",
    "is_leg",
    *(f"f{i + 1}_{name}" for i, name in enumerate(FEATURE_NAMES)),
)


def _num(value: float) -> str:
    return "" if not math.isfinite(value) else repr(float(value))


class DetectionsCsvWriter:
    """Writes detections (or all classified segments) to a CSV file, flushing per scan."""

    def __init__(self, path: str | Path, *, all_segments: bool = False) -> None:
        self.path = Path(path)
        self.all_segments = all_segments
        try:
            self._fh: IO[str] = self.path.open("w", newline="", encoding="utf-8")
        except OSError as exc:
            raise RecordingError(f"cannot write detections: {exc}", path=self.path) from exc
        self._writer = csv.writer(self._fh)
        self._writer.writerow(HEADER + (SEGMENT_COLUMNS if all_segments else ()))
        self._fh.flush()
        self.rows = 0

    def write(self, detections: Detections) -> None:
        """One row per detection (sensor frame)."""
        if detections.frame != "sensor":
            raise ValueError("detections CSV holds sensor-frame positions")
        for (x, y), score in zip(detections.positions, detections.scores, strict=True):
            self._writer.writerow(
                [
                    detections.scan_index,
                    repr(float(detections.stamp)),
                    repr(float(x)),
                    repr(float(y)),
                    _num(score),
                ]
            )
            self.rows += 1
        self._fh.flush()

    def write_segments(
        self,
        scan: Scan,
        centres: np.ndarray,
        first_beams: np.ndarray,
        sizes: np.ndarray,
        is_leg: np.ndarray,
        scores: np.ndarray,
        features: np.ndarray,
    ) -> None:
        """One row per segment of ``scan`` with its features (the ``--all-segments`` layout)."""
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
            row.extend(_num(v) for v in features[i])
            self._writer.writerow(row)
            self.rows += 1
        self._fh.flush()

    def close(self) -> None:
        """Close the file."""
        self._fh.close()

    def __enter__(self) -> DetectionsCsvWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def iter_detections_csv(path: str | Path) -> Iterator[dict[str, float | int]]:
    """Rows of a detections CSV as dicts (``scan`` int, others float; empty -> NaN)."""
    p = Path(path)
    try:
        fh = p.open(newline="", encoding="utf-8")
    except OSError as exc:
        raise RecordingError(f"cannot read detections: {exc}", path=p) from exc
    with fh:
        reader = csv.DictReader(fh)
        if reader.fieldnames is None or tuple(reader.fieldnames[:5]) != HEADER:
            raise RecordingError(
                f"not a detections CSV (header {reader.fieldnames!r})",
                path=p,
                hint="expected the header " + ",".join(HEADER),
            )
        for line, row in enumerate(reader, start=2):
            try:
                yield {
                    k: (
                        int(v)
                        if k in ("scan", "segment", "first_beam", "n_beams", "is_leg")
                        else (float(v) if v != "" else math.nan)
                    )
                    for k, v in row.items()
                }
            except (TypeError, ValueError) as exc:
                raise RecordingError(f"line {line}: {exc}", path=p) from exc
