"""The summary table of a batch run: one row per recording and laser topic.

Written as ``summary.parquet`` (typed columns, :data:`SUMMARY_COLUMNS`) and
``summary.csv`` (the same columns, the same order) in the output folder, each to a
temporary name and renamed.
"""

from __future__ import annotations

import csv
import os
from collections.abc import Sequence
from dataclasses import asdict, fields
from pathlib import Path
from typing import Any

from laserpeople.batch.task import TopicRow

_ARROW = {"str": "string", "int": "int64", "float": "float64"}

SUMMARY_COLUMNS: tuple[tuple[str, str], ...] = tuple(
    (f.name, _ARROW[str(f.type)]) for f in fields(TopicRow)
)
"""Column names and Arrow types of the summary (the fields of
:class:`~laserpeople.batch.task.TopicRow`)."""


def summary_schema() -> Any:
    """The ``pyarrow.Schema`` of the summary."""
    import pyarrow as pa

    return pa.schema([(name, pa.type_for_alias(kind)) for name, kind in SUMMARY_COLUMNS])


def write_summary(rows: Sequence[TopicRow], out: str | Path) -> tuple[Path, Path]:
    """Write ``summary.parquet`` and ``summary.csv`` to ``out``; returns their paths."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    records = [asdict(r) for r in rows]
    schema = summary_schema()
    table = pa.table(
        {
            name: pa.array([r[name] for r in records], type=schema.field(name).type)
            for name, _ in SUMMARY_COLUMNS
        },
        schema=schema,
    )
    parquet = folder / "summary.parquet"
    temp = folder / f".summary.parquet.{os.getpid()}.tmp"
    pq.write_table(table, temp)
    os.replace(temp, parquet)
    text = folder / "summary.csv"
    temp = folder / f".summary.csv.{os.getpid()}.tmp"
    with temp.open("w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=[name for name, _ in SUMMARY_COLUMNS])
        writer.writeheader()
        writer.writerows(records)
    os.replace(temp, text)
    return parquet, text


__all__ = ["SUMMARY_COLUMNS", "summary_schema", "write_summary"]
