"""An MCAP file without its end records: a recorder stopped before it closed the file (a
kill, a power cut; ``live --record`` leaves its frames so in a hidden folder) or a copy cut
short. Its records up to the cut are whole and readable; the readers refuse the file, since
they look for the closing magic first.

:func:`missing_end` tells such a file; :func:`ended_copy` copies its whole records, up to
the first record the cut reached, and ends the copy with the records that end an MCAP
without a summary (:func:`~laserpeople.io.mcap_record.mcap_ending`), which the readers scan.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from laserpeople.io.mcap_record import MCAP_MAGIC, mcap_ending

DATA_END = 0x0F
"""Opcode of the record after the data section (the summary follows it)."""

LAST_OPCODE = 0x0F
"""Largest opcode of MCAP 0 (a byte above it, or 0, is not the start of a record)."""


def missing_end(path: str | Path) -> bool:
    """Whether ``path`` is an ``.mcap`` file that starts as an MCAP does but does not end
    with the closing magic."""
    p = Path(path)
    if p.suffix.lower() != ".mcap" or not p.is_file():
        return False
    size = p.stat().st_size
    with p.open("rb") as fh:
        head = fh.read(len(MCAP_MAGIC))
        if head != MCAP_MAGIC:
            return False
        if size < 2 * len(MCAP_MAGIC):
            return True
        fh.seek(size - len(MCAP_MAGIC))
        return fh.read() != MCAP_MAGIC


def whole_records(path: str | Path) -> tuple[int, int]:
    """The byte after the last whole record of the data section of the MCAP at ``path``,
    and how many whole records come before it after the header record: records are read by
    their lengths from the magic on, up to one that reaches beyond the file, is not a record
    (opcode 0 or above :data:`LAST_OPCODE`) or ends the data (:data:`DATA_END`)."""
    p = Path(path)
    size = p.stat().st_size
    at, records = len(MCAP_MAGIC), -1
    with p.open("rb") as fh:
        fh.seek(at)
        while True:
            head = fh.read(9)
            if len(head) < 9:
                return at, max(records, 0)
            op, length = head[0], int.from_bytes(head[1:], "little")
            if op == 0 or op >= DATA_END or at + 9 + length > size:
                return at, max(records, 0)
            at += 9 + length
            records += 1
            fh.seek(at)


def ended_copy(path: str | Path, folder: str | Path) -> tuple[Path, int]:
    """A copy in ``folder`` of the whole records of the MCAP at ``path``, ended (see the
    module docstring); and how many bytes of ``path`` it holds."""
    p = Path(path)
    end, _ = whole_records(p)
    copy = Path(folder) / p.name
    with p.open("rb") as src, copy.open("wb") as out:
        left = end
        while left:
            block = src.read(min(left, 1 << 20))
            if not block:
                break
            out.write(block)
            left -= len(block)
        out.write(mcap_ending())
    shutil.copymode(p, copy)
    return copy, end


__all__ = ["DATA_END", "LAST_OPCODE", "ended_copy", "missing_end", "whole_records"]
