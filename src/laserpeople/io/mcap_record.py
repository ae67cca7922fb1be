"""An MCAP written frame by frame that stays a readable recording when writing fails.

:func:`~laserpeople.io.rosbag_writer.open_bag` assembles a bag beside its target and drops
it when the block raises: right for outputs written in one go, wrong for ``live --record``,
where a full disk after an hour would lose the hour. :class:`McapRecorder` instead:

- ends a chunk and flushes the file after every whole frame (:meth:`McapRecorder.checkpoint`),
  so the file on disk always holds whole frames up to a known byte;
- when a write fails (a full disk, an I/O error), cuts the file back to the last whole frame
  and ends it with the MCAP end records without a summary (59 bytes, which readers answer by
  scanning the data), then moves it into place (:meth:`McapRecorder.salvage`);
- when the file being written was removed meanwhile, writes it again beside the target from
  the still-open file; when it cannot be moved into place (the folder made read-only), leaves
  it where it is and names it.
"""

from __future__ import annotations

import os
import shutil
import struct
import tempfile
import warnings
from contextlib import suppress
from pathlib import Path
from typing import Any

from laserpeople.errors import LaserPeopleWarning, RecordingError
from laserpeople.io.rosbag_writer import BagSink

MCAP_MAGIC = b"\x89MCAP0\r\n"


def mcap_ending() -> bytes:
    """The records that end an MCAP without a summary: DataEnd (data CRC 0: not checked),
    Footer (summary start 0: none) and the closing magic; 59 bytes."""
    data_end = b"\x0f" + struct.pack("<QI", 4, 0)
    footer = b"\x02" + struct.pack("<QQQI", 20, 0, 0, 0)
    return data_end + footer + MCAP_MAGIC


class McapRecorder:
    """A ROS 2 ``.mcap`` written under a hidden name beside ``path`` and moved into place
    when closed, kept up to its last whole frame when writing fails.

    Args:
        path: The ``.mcap`` to write (an existing file is replaced when it is closed).

    Attributes:
        sink: Where messages go.
        kept_bytes: Bytes of the file up to the end of the last whole frame.

    Raises:
        RecordingError: The folder cannot be written.
    """

    def __init__(self, path: str | Path) -> None:
        from rosbags.rosbag2 import StoragePlugin
        from rosbags.rosbag2 import Writer as Writer2
        from rosbags.typesys import Stores, get_typestore

        self.path = Path(path)
        if self.path.is_dir():  # (found out only when it is moved into place, at the end)
            raise self._error(IsADirectoryError(21, "is a folder, not a file"))
        from laserpeople.io.paths import left_by_killed_runs, staging_folder

        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._workdir = staging_folder(self.path)
        except OSError as exc:
            raise self._error(exc) from exc
        for left in left_by_killed_runs(self.path):
            warnings.warn(
                f"{self.path}: {left.name} beside it holds the frames of an earlier recording "
                f"into it that was killed: `laserpeople track {left / 'out' / 'out.mcap'} "
                "--on-error skip` reads them; move or remove the folder",
                LaserPeopleWarning,
                stacklevel=2,
            )
        self._staged = self._workdir / "out" / "out.mcap"
        self._writer: Any = Writer2(
            self._workdir / "out", version=9, storage_plugin=StoragePlugin.MCAP
        )
        try:
            self._writer.open()
            storage: Any = self._writer.storage
            storage.bio.flush()
            # read-write (rosbags opens it write-only): a removed file can be copied back
            bio = self._staged.open("r+b")
            bio.seek(0, os.SEEK_END)
            storage.bio.close()
            storage.bio = bio
            self._fd = os.dup(bio.fileno())
            self.kept_bytes: int = bio.tell()
        except OSError as exc:
            shutil.rmtree(self._workdir, ignore_errors=True)
            raise self._error(exc) from exc
        self.sink = BagSink(self._writer, get_typestore(Stores.LATEST), False)
        self._closed = False

    def _error(self, exc: OSError) -> RecordingError:
        from laserpeople.io.paths import why_unwritable

        return RecordingError(
            f"cannot write the recording: {why_unwritable(exc, self.path)}",
            path=self.path,
            hint="free disk space, or give a path in a writable directory",
        )

    def checkpoint(self) -> None:
        """Write out what the sink holds (a whole frame): end the chunk and flush.

        Raises:
            OSError: The file refused the bytes (the caller salvages).
        """
        storage = self._writer.storage
        if storage.chunk.bio.tell():
            storage.close_chunk()
        storage.bio.flush()
        self.kept_bytes = storage.bio.tell()

    def close(self) -> None:
        """End the file with its summary and move it into place; if that fails, keep it up to
        the last checkpoint (see :meth:`salvage`).

        Raises:
            OSError: The file could not be ended; it was salvaged, and the error passes on.
            RecordingError: It could not be moved into place (the message says where it is).
        """
        if self._closed:
            return
        try:
            self.checkpoint()
            self._writer.close()
        except OSError as exc:
            if self._writer.storage is not None:
                self.salvage(exc)
                raise
            # the MCAP is whole; only the bag folder's metadata.yaml (not kept) failed
        self._place()

    def salvage(self, exc: OSError) -> Path:
        """After ``exc`` from a write: cut the file back to the last checkpoint, end it there
        and move it into place.

        Returns:
            Where the recording is (``path``).

        Raises:
            RecordingError: It could not be ended or moved (the message says where it is).
        """
        if self._closed:
            return self.path
        storage, self._writer.storage = self._writer.storage, None
        if storage is not None:
            with suppress(OSError):  # its buffer may still hold the bytes the disk refused
                storage.bio.close()
        try:
            os.ftruncate(self._fd, self.kept_bytes)
            os.pwrite(self._fd, mcap_ending(), self.kept_bytes)
        except OSError as end_exc:
            self._closed = True
            os.close(self._fd)
            raise RecordingError(
                f"cannot write the recording ({exc.strerror or exc}), nor end it "
                f"({end_exc.strerror or end_exc}): the whole frames are in {self._staged} "
                "without the MCAP end records",
                path=self.path,
                hint="free disk space; `mcap recover` can end that file",
            ) from end_exc
        return self._place()

    def _place(self) -> Path:
        """Move the ended file into place (written again from the open file if it was
        removed), close it and remove the hidden folder."""
        self._closed = True
        try:
            if os.fstat(self._fd).st_nlink == 0:
                self._rewrite()
            else:
                os.replace(self._staged, self.path)
        except OSError as exc:
            kept = self._staged if self._staged.exists() else None
            raise RecordingError(
                f"the recording is complete but cannot be moved into place ({exc.strerror or exc})"
                + (f": it is {kept}" if kept else ": it was removed while being written"),
                path=self.path,
                hint="move that file where you want it" if kept else "record into another folder",
            ) from exc
        finally:
            os.close(self._fd)
        shutil.rmtree(self._workdir, ignore_errors=True)
        return self.path

    def _rewrite(self) -> None:
        """Copy the open (removed) file to a hidden name beside ``path``, then rename it."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        fd, name = tempfile.mkstemp(prefix=f".{self.path.name}.", dir=self.path.parent)
        try:
            with os.fdopen(fd, "wb") as out, os.fdopen(os.dup(self._fd), "rb") as src:
                src.seek(0)
                shutil.copyfileobj(src, out)
            os.replace(name, self.path)
        except BaseException:
            with suppress(OSError):
                os.unlink(name)
            raise


__all__ = ["MCAP_MAGIC", "McapRecorder", "mcap_ending"]
