"""Line files written scan by scan, so that a killed writer leaves a valid file.

:class:`ScanLineWriter` writes the rows of one scan with a single ``write()`` system call
on an unbuffered file, so a process killed between two scans leaves only whole scans. A
kill *during* that call can still cut it: Linux checks for a fatal signal between the
pages it copies, so a scan larger than a page may be left half written. The cut then
falls inside a row (detected below) unless a page boundary happens to fall just after a
row's newline, in which case the last scan is short by its remaining rows. A failing write
(a full disk, ``-o /dev/full``) raises a :class:`~laserpeople.errors.RecordingError` that
says how many scans the file holds; those stay valid.

:func:`complete_lines` is the reading side: it yields the lines of a file and notices a
last line without its newline, which only a writer killed in the middle of a write (or a
file cut short) leaves. The readers of the tracks and detections CSV then drop the scan
that line belongs to and say so with a :class:`TornScanWarning`.
"""

from __future__ import annotations

import csv
import io
import warnings
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path
from typing import IO, Any

from laserpeople.errors import RecordingError


class TornScanWarning(UserWarning):
    """The last scan of a CSV was cut off mid-write and is left out."""


class ScanLineWriter:
    """CSV rows written whole scans at a time (one ``write()`` per scan, unbuffered).

    Args:
        path: The file to write (created or truncated).
        header: Column names, written first.
        what: What the file holds, for error messages (``"tracks CSV"``).
    """

    def __init__(self, path: str | Path, header: Sequence[str], what: str) -> None:
        self.path = Path(path)
        self.what = what
        self.scans = 0
        self._buf = io.StringIO()
        self._csv = csv.writer(self._buf, lineterminator="\n")
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._fh: IO[bytes] = open(self.path, "wb", buffering=0)  # noqa: SIM115
        except OSError as exc:
            raise RecordingError(
                f"cannot write the {what}: {exc.strerror or exc}",
                path=self.path,
                hint="choose a writable file path with -o",
            ) from exc
        try:
            self.write_rows([header], count=False)
        except RecordingError:
            self._fh.close()  # the caller never gets the writer to close it
            raise

    def write_rows(self, rows: Iterable[Sequence[Any]], *, count: bool = True) -> None:
        """Write ``rows`` (one scan's) with one system call.

        Raises:
            RecordingError: The write failed (disk full, file system gone); the file holds
                the scans written before this one.
        """
        self._buf.seek(0)
        self._buf.truncate()
        self._csv.writerows(rows)
        data = memoryview(self._buf.getvalue().encode("utf-8"))
        try:
            while data:  # a regular file takes it all at once; loop for the rare short write
                n = self._fh.write(data)
                data = data[n or 0 :]
        except OSError as exc:
            raise RecordingError(
                f"cannot write the {self.what}: {exc.strerror or exc}; it holds the "
                f"{self.scans} complete scan(s) written before",
                path=self.path,
                hint="free disk space or choose another path with -o",
            ) from exc
        if count:
            self.scans += 1

    def close(self) -> None:
        """Close the file."""
        if not self._fh.closed:
            self._fh.close()


def complete_lines(fh: IO[str], torn: list[str]) -> Iterator[str]:
    """The lines of ``fh``; a last line without ``\\n`` is not yielded but put in ``torn``."""
    for line in fh:
        if line.endswith("\n"):
            yield line
        else:
            torn.append(line)


def warn_torn(path: Path, scan: int | None) -> None:
    """Say that the last scan of ``path`` was cut off and left out."""
    what = f"scan {scan}" if scan is not None else "its last line"
    warnings.warn(
        f"{path}: the file ends in the middle of {what} (the writer was stopped while "
        f"writing it); {what} is left out",
        TornScanWarning,
        stacklevel=3,
    )


def torn_scan(torn: list[str]) -> int | None:
    """The scan index the torn last line starts with, if it can be read."""
    if not torn:
        return None
    head = torn[0].split(",", 1)[0].strip()
    return int(head) if head.isdigit() else None
