"""Line files written scan by scan, so that a killed writer leaves a valid file.

:class:`ScanLineWriter` writes the rows of one scan so that a process killed at any
moment (SIGKILL, a power cut of the process) leaves every scan either complete or
detectably torn, never silently short; a Ctrl-C, which stops it between two pages, cuts
the scan it was writing back off. An existing file is emptied only when the first scan
is handed to the writer (or it is closed after a run that ended well): a run that fails
before any scan (:meth:`ScanLineWriter.abandon`) leaves the file as it was (and removes
one it made, which held the header alone).

A single ``write()`` is not enough: Linux checks for a fatal signal between the pages it
copies, so a kill can cut a scan larger than a page at a page boundary, which may fall
just after a row. The writer therefore writes a
scan page by page *from its end backwards* (``pwrite``): until the page holding the
scan's first byte is written, the scan's start is a hole that reads as NUL bytes, and
one page is copied whole or not at all. A failing write
(a full disk, ``-o /dev/full``) raises a :class:`~laserpeople.errors.RecordingError` that
says how many scans the file holds; those stay valid.

:func:`complete_lines` is the reading side: it yields the lines of a file and notices a
last line without its newline (a file cut short, or written by another program) or a line
with NUL bytes (the hole a killed writer leaves). The readers of the tracks and detections
CSV then drop the scan that line belongs to and say so with a :class:`TornScanWarning`.
"""

from __future__ import annotations

import contextlib
import csv
import io
import mmap
import os
import stat
import warnings
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path
from typing import IO, Any, Self

from laserpeople.errors import LaserPeopleWarning, RecordingError
from laserpeople.io.paths import lock_for_one_writer, why_unwritable

PAGE = mmap.PAGESIZE  # bytes the kernel copies between two checks for a fatal signal


class TornScanWarning(LaserPeopleWarning):
    """The last scan of a CSV was cut off mid-write and is left out."""


class ScanLineWriter:
    """CSV rows written whole scans at a time, a scan's pages from its end backwards.

    A failing write names the scan it failed at and what the file holds: the scans handed
    to :meth:`write_rows` or :meth:`pass_scan` before it, with rows or without (a scan with
    no track or leg has no row but is in the file all the same).

    Args:
        path: The file to write (created, or emptied when the first scan comes).
        header: Column names, written first.
        what: What the file holds, for error messages (``"tracks CSV"``).

    Attributes:
        scans: Scans handled (their rows, if any, written).
        scans_with_rows: Of those, the scans that have rows.
        last: Name of the last scan handled (``"scan 41 of /scan"``; ``""``: none).
    """

    def __init__(self, path: str | Path, header: Sequence[str], what: str) -> None:
        self.path = Path(path)
        self.what = what
        self.scans = 0
        self.scans_with_rows = 0
        self.last = ""
        self._end = 0  # bytes of complete rows in the file
        self._buf = io.StringIO()
        self._csv = csv.writer(self._buf, lineterminator="\n")
        self._header: Sequence[str] | None = header  # None once written
        self.created = False
        """Whether this writer made the file (there was none at its path)."""
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            # opened without truncating: a file another run is writing is left to it, and
            # one of an earlier run stays as it is until the first scan comes
            try:
                fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
                self.created = True
            except FileExistsError:
                fd = os.open(self.path, os.O_WRONLY, 0o666)
            self._fh: IO[bytes] = open(fd, "wb", buffering=0)  # noqa: SIM115
            self._seekable = self._fh.seekable()  # False for a pipe or a terminal
            self._regular = stat.S_ISREG(os.fstat(fd).st_mode)  # (not a device or a pipe)
        except OSError as exc:
            raise self._unwritable(exc) from exc
        try:
            claim(fd, self.path, what)
            if self.created or not self._regular:  # (no earlier file to keep)
                self._begin()
        except BaseException:
            self._fh.close()  # the caller never gets the writer to close it
            raise

    def _unwritable(self, exc: OSError) -> RecordingError:
        """The error for a file that cannot be opened, emptied or written: names it."""
        return RecordingError(
            f"cannot write the {self.what}: {why_unwritable(exc, self.path)}",
            path=self.path,
            hint="choose a writable file path with -o",
        )

    def _begin(self) -> None:
        """Empty the file and write the header, once, before the first scan.

        Raises:
            RecordingError: the file cannot be emptied or written; names it.
        """
        header, self._header = self._header, None
        if header is None:
            return
        try:
            if self._regular:
                os.ftruncate(self._fh.fileno(), 0)
        except OSError as exc:
            raise self._unwritable(exc) from exc
        self.write_rows([header], count=False)

    def pass_scan(self, scan: str) -> None:
        """Count the scan named ``scan`` (``"scan 41 of /scan"``), which has no rows.

        Raises:
            RecordingError: the first scan, and the header cannot be written.
        """
        self._begin()
        self.scans += 1
        self.last = scan

    def write_rows(
        self, rows: Iterable[Sequence[Any]], *, count: bool = True, scan: str = ""
    ) -> None:
        """Write ``rows`` (those of the scan named ``scan``), complete or detectably torn if
        the process dies.

        Raises:
            RecordingError: The write failed (disk full, file system gone); the file holds
                the scans handled before this one, and the message says so.
        """
        if count:
            self._begin()
        self._buf.seek(0)
        self._buf.truncate()
        self._csv.writerows(rows)
        data = self._buf.getvalue().encode("utf-8")
        try:
            if self._seekable:
                self._write_backwards(data)
            else:
                self._write_forwards(data)
        except KeyboardInterrupt:  # Ctrl-C between two pages: the file ends with whole scans
            if self._seekable:
                self._undo()
            raise
        except OSError as exc:
            if self._seekable:
                self._undo()
            raise RecordingError(self._stopped(exc, scan), path=self.path, hint=(
                "free disk space or choose another path with -o"
            )) from exc  # fmt: skip
        self._end += len(data)
        if count:
            self.scans += 1
            self.scans_with_rows += 1
            self.last = scan

    def _stopped(self, exc: OSError, scan: str) -> str:
        """What a write that failed at ``scan`` left: the scans the file holds, whole."""
        at = f" at {scan}" if scan else ""
        why = exc.strerror or exc
        if not self._end:
            return f"cannot write the {self.what}: {why} (not even its header)"
        if not self.scans:
            return f"cannot write the {self.what}{at}: {why}; it holds the header alone"
        upto = f", up to {self.last}" if self.last else ""
        return (
            f"cannot write the {self.what}{at}: {why}; it holds the rows of "
            f"the {self.scans} scan{'' if self.scans == 1 else 's'} handled before "
            f"({self.scans_with_rows} with rows"
            f"{upto}), whole: {scan or 'that scan'} and the scans after it are missing"
        )

    def _write_backwards(self, data: bytes) -> None:
        fd = self._fh.fileno()
        start = self._end
        cuts = list(range(start - start % PAGE + PAGE, start + len(data), PAGE))
        for lo, hi in reversed(list(zip([start, *cuts], [*cuts, start + len(data)], strict=True))):
            view = memoryview(data)[lo - start : hi - start]
            at = lo
            while view:  # a regular file takes a page at once; loop for the rare short write
                n = os.pwrite(fd, view, at)
                view, at = view[n:], at + n

    def _write_forwards(self, data: bytes) -> None:
        view = memoryview(data)
        while view:
            n = self._fh.write(view)
            view = view[n or 0 :]

    def _undo(self) -> None:
        """Cut the file back to its complete scans after a failed write (best effort)."""
        try:
            os.ftruncate(self._fh.fileno(), self._end)
        except OSError:
            return

    @property
    def begun(self) -> bool:
        """Whether the file was emptied and its header written (a scan came, or it was
        closed)."""
        return self._header is None

    def close(self) -> None:
        """Close the file; one that no scan came to holds the header alone.

        Raises:
            RecordingError: the header cannot be written (the file is closed all the same).
        """
        if self._fh.closed:
            return
        try:
            self._begin()
        finally:
            self._fh.close()

    def abandon(self) -> bool:
        """Close the file after a run that failed: one that no scan came to is left as it
        was before the writer opened it (a file the writer made is removed); one that scans
        came to holds them, as after :meth:`close`.

        Returns:
            Whether the file was left as it was (or removed, when the writer made it).
        """
        if self._fh.closed:
            return False
        kept = not self.scans
        self._header = None
        self._fh.close()
        if kept and self.created:
            with contextlib.suppress(OSError):
                self.path.unlink()
        return kept


class ScanLineFile:
    """The lifetime of a writer that keeps its rows in a :class:`ScanLineWriter`
    (``self._out``): closing, abandoning after a failed run, and use in a ``with``
    block (closed on success, abandoned on an error)."""

    _out: ScanLineWriter

    def close(self) -> None:
        """Close the file (one that no scan came to holds the header alone)."""
        self._out.close()

    @property
    def created(self) -> bool:
        """Whether this writer made the file (there was none at its path)."""
        return self._out.created

    def abandon(self) -> bool:
        """Close the file after a failed run; a file no scan came to is left as it was
        (see :meth:`ScanLineWriter.abandon`).

        Returns:
            Whether the file was left as it was.
        """
        return self._out.abandon()

    def __enter__(self) -> Self:
        return self

    def __exit__(self, kind: object, *exc: object) -> None:
        if kind is None:
            self.close()
        else:
            self.abandon()


def claim(fd: int, path: Path, what: str) -> None:
    """Take the file ``fd`` (``path``) for this writer alone: two runs writing one file at
    once would mix their rows into a file neither wrote (it is emptied when the first scan
    comes, :meth:`ScanLineWriter._begin`). An exclusive lock
    (``flock``, released when the file is closed) on a regular file; pipes, terminals and
    devices are taken as they are.

    Raises:
        RecordingError: another process holds the file; names it, before anything of it is
            changed.
    """
    if not stat.S_ISREG(os.fstat(fd).st_mode):
        return
    if not lock_for_one_writer(fd):
        raise RecordingError(
            f"another run is writing this {what} now: two runs writing one file would "
            "mix their rows; it is left as it is",
            path=path,
            hint="give each run its own -o, or wait until the other has finished",
        )


def complete_lines(fh: IO[str], torn: list[str]) -> Iterator[str]:
    """The lines of ``fh`` up to the first torn one, which goes into ``torn`` with the rest.

    A line is torn when it lacks its ``\\n`` (only the last line can) or holds a NUL byte
    (the unwritten start of a scan a killed writer leaves; no later line is whole).
    """
    for line in fh:
        if "\0" in line or not line.endswith("\n"):
            torn.append(line)
            torn.extend(fh)
            return
        yield line


def warn_torn(path: Path, torn: list[str]) -> int | None:
    """Say that the last scan of ``path`` was cut off and is left out; return its index.

    The index is ``None`` when the torn part starts with the scan's unwritten first bytes,
    so every complete line before it belongs to a complete scan.
    """
    head = torn[0].split(",", 1)[0].strip()
    scan = int(head) if head.isdigit() else None
    what = f"scan {scan}" if scan is not None else "the scan after the last complete one"
    after = f", with the {len(torn) - 1} line(s) after it" if len(torn) > 1 else ""
    warnings.warn(
        f"{path}: {what} is cut off (the writer was stopped while writing it, or the file is "
        f"damaged there); it is left out{after}",
        TornScanWarning,
        stacklevel=3,
    )
    return scan
