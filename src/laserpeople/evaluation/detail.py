"""Per-frame detail of a metric: a small table with named columns, one row per scored scan."""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from laserpeople.errors import EvaluationError
from laserpeople.io.paths import write_text_file

Cell = int | float


@dataclass(frozen=True, eq=False)
class FrameTable:
    """Rows of numbers with named columns; the first column identifies the frame (``scan``,
    or ``frame`` for the clustering error), the second is its ``stamp`` [s].

    Attributes:
        columns: Column names.
        rows: One tuple per scored frame, in scoring order.
    """

    columns: tuple[str, ...]
    rows: tuple[tuple[Cell, ...], ...]

    def __post_init__(self) -> None:
        for row in self.rows:
            if len(row) != len(self.columns):
                raise ValueError(f"row {row} does not have the {len(self.columns)} columns")

    def __len__(self) -> int:
        return len(self.rows)

    def __iter__(self) -> Iterator[dict[str, Cell]]:
        for row in self.rows:
            yield dict(zip(self.columns, row, strict=True))

    def column(self, name: str) -> NDArray[np.float64]:
        """One column as a float array (R,)."""
        k = self.columns.index(name)
        return np.array([row[k] for row in self.rows], dtype=np.float64)

    def join(self, other: FrameTable) -> FrameTable:
        """This table with the columns of ``other`` (same frames, same order) appended."""
        if len(other) != len(self) or any(
            a[0] != b[0] for a, b in zip(self.rows, other.rows, strict=True)
        ):
            raise ValueError("tables cover different frames")
        extra = [k for k, c in enumerate(other.columns) if c not in self.columns]
        columns = self.columns + tuple(other.columns[k] for k in extra)
        rows = tuple(
            a + tuple(b[k] for k in extra) for a, b in zip(self.rows, other.rows, strict=True)
        )
        return FrameTable(columns, rows)

    def to_csv(self, path: str | Path) -> None:
        """Write the table as CSV with a header line (NaN written as an empty cell), whole:
        a failed write leaves no torn file and an older file as it was."""
        buf = io.StringIO()
        out = csv.writer(buf, lineterminator="\n")
        out.writerow(self.columns)
        out.writerows(_format(self.columns, row) for row in self.rows)
        write_text_file(
            path, buf.getvalue(), "per-frame table", EvaluationError, "give a writable file path"
        )


def _format(columns: Sequence[str], row: Sequence[Cell]) -> list[str]:
    cells = []
    for name, value in zip(columns, row, strict=True):
        if isinstance(value, float):
            if math.isnan(value):
                cells.append("")
            else:
                cells.append(f"{value:.6f}" if name == "stamp" else f"{value:.6g}")
        else:
            cells.append(str(value))
    return cells


def frames_not_kept(metric: str) -> EvaluationError:
    """The error of asking a metric made with ``keep_frames=False`` for its per-frame table."""
    return EvaluationError(
        f"{metric} was created without per-frame detail",
        hint="create it with keep_frames=True (costs memory per frame)",
    )
