"""The summary table of a batch run: one row per recording and laser topic.

Written as ``summary.parquet`` (typed columns, :data:`SUMMARY_COLUMNS`) and
``summary.csv`` (the same columns, the same order) in the output folder, each to a
temporary name and renamed.
"""

from __future__ import annotations

import contextlib
import csv
import os
from collections.abc import Iterator, Sequence
from dataclasses import asdict, fields
from pathlib import Path
from typing import Any

from laserpeople.batch.task import TopicRow
from laserpeople.errors import RecordingError

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
    with _written_whole(parquet) as temp:
        pq.write_table(table, temp)
    text = folder / "summary.csv"
    with _written_whole(text) as temp, temp.open("w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=[name for name, _ in SUMMARY_COLUMNS])
        writer.writeheader()
        writer.writerows(records)
    return parquet, text


@contextlib.contextmanager
def _written_whole(path: Path) -> Iterator[Path]:
    """A staging name beside ``path``, renamed to it when the block ends; a write that
    fails (a full disk) removes it and is a :class:`RecordingError` naming ``path``."""
    temp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        yield temp
        os.replace(temp, path)
    except OSError as exc:
        with contextlib.suppress(OSError):
            temp.unlink(missing_ok=True)
        why = os.strerror(exc.errno) if exc.errno else str(exc)
        raise RecordingError(
            f"cannot write the batch summary: {why}; the tracks and the manifest are kept",
            path=path,
            hint="free disk space, then run the same command again: it writes the summary "
            "without tracking the recordings done again",
        ) from exc


__all__ = ["SUMMARY_COLUMNS", "summary_schema", "write_summary"]
