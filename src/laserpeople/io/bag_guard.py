"""Bounds on what a damaged bag can make the ``rosbags`` readers allocate.

A ROS 1 record or an MCAP record starts with its length. In a damaged file that length
can be anything (``0xFFFFFFFF``, ``2**64 - 1``), and ``rosbags`` passes it straight to
``file.read(length)``, which allocates that many bytes before reading (4 GiB, or an
``OverflowError``). A compressed chunk can also expand without limit. :func:`install`
replaces the few module-level helpers of ``rosbags`` that do this with versions that

* refuse a read longer than what is left of the file or buffer (the record is truncated
  or its length is corrupt), before allocating anything, and
* decompress a chunk into at most :data:`CHUNK_LIMIT` bytes (and no more than the chunk
  header declares).

Memory for reading a bag is thereby bounded by the largest chunk, at most
:data:`CHUNK_LIMIT` (ROS 1 bags are written in 768 KiB chunks, MCAP in 1 MiB ones).
The replacement raises the reader's own ``ReaderError``, which
:class:`~laserpeople.io.rosbag.RosbagRecording` turns into a
:class:`~laserpeople.errors.RecordingError` naming the file and scan.
"""

from __future__ import annotations

import bz2
import io
import os
from collections.abc import Callable
from typing import Any, BinaryIO

CHUNK_LIMIT = 256 * 2**20
"""Largest decompressed chunk [bytes] a bag may hold; larger ones are reported corrupt."""

_installed = False


def _remaining(src: BinaryIO) -> int | None:
    """Bytes left to read in ``src`` (None when it cannot be told)."""
    try:
        pos = src.tell()
        if isinstance(src, io.BytesIO):
            return len(src.getbuffer()) - pos
        return os.fstat(src.fileno()).st_size - pos
    except (OSError, ValueError, AttributeError, io.UnsupportedOperation):
        return None


def _bounded_read(error: type[Exception]) -> Callable[[BinaryIO, int], bytes]:
    def read(src: BinaryIO, size: int) -> bytes:
        left = _remaining(src)
        if size < 0 or (left is not None and size > left):
            raise error(
                f"record at byte {src.tell()} claims {size} bytes but only {left} are left "
                "(the record is truncated or its length field is corrupt)"
            )
        data = src.read(size)
        if len(data) != size:
            raise error(f"record at byte {src.tell()} is truncated: {len(data)} of {size} bytes")
        return data

    return read


def _limited(declared: int | None, error: type[Exception]) -> int:
    if declared is not None and (declared < 0 or declared > CHUNK_LIMIT):
        raise error(
            f"chunk declares {declared} uncompressed bytes, more than the {CHUNK_LIMIT} "
            "this reader accepts (corrupt chunk header)"
        )
    return CHUNK_LIMIT if declared is None else declared


def _lz4(data: bytes, declared: int | None, error: type[Exception]) -> bytes:
    import lz4.frame  # type: ignore[import-untyped]

    limit = _limited(declared, error)
    dec = lz4.frame.LZ4FrameDecompressor()
    out = dec.decompress(data, max_length=limit + 1)
    if len(out) > limit:
        raise error(f"chunk expands beyond {limit} bytes (corrupt or hostile compression)")
    return bytes(out)


def _bz2(data: bytes, declared: int | None, error: type[Exception]) -> bytes:
    limit = _limited(declared, error)
    dec = bz2.BZ2Decompressor()
    out = dec.decompress(data, max_length=limit + 1)
    if len(out) > limit:
        raise error(f"chunk expands beyond {limit} bytes (corrupt or hostile compression)")
    return out


def _zstd(data: bytes, declared: int | None, error: type[Exception]) -> bytes:
    try:
        from compression import zstd  # type: ignore[import-not-found]
    except ImportError:
        from backports import zstd

    limit = _limited(declared, error)
    dec = zstd.ZstdDecompressor()
    out = dec.decompress(data, max_length=limit + 1)
    if len(out) > limit:
        raise error(f"chunk expands beyond {limit} bytes (corrupt or hostile compression)")
    return bytes(out)


def _guard(fn: Callable[..., bytes], error: type[Exception]) -> Callable[..., bytes]:
    """Turn the decompressors' own exceptions into the reader's ``ReaderError``."""

    def call(*args: Any) -> bytes:
        try:
            return fn(*args)
        except error:
            raise
        except (MemoryError, OverflowError, ValueError, RuntimeError, OSError, EOFError) as exc:
            raise error(f"cannot decompress chunk: {type(exc).__name__}: {exc}") from exc

    return call


def _guarded_index_read(original: Callable[..., None], error: type[Exception]) -> Any:
    """ROS 1 ``IDXDATA`` records are read with ``bio.read(size)`` for a ``size`` taken from
    the record: check it against the file before the original reads it."""

    def read_index_data(self: Any, pos: int, indexes: Any) -> None:
        bio = self.bio
        start = bio.tell()
        head = bio.read(55)
        if len(head) == 55:
            size = int.from_bytes(head[51:55], "little")
            left = _remaining(bio)
            if left is not None and size > left:
                raise error(
                    f"index record at byte {start} claims {size} bytes but only {left} are "
                    "left (truncated or corrupt)"
                )
        bio.seek(start)
        original(self, pos, indexes)

    return read_index_data


def install() -> None:
    """Put the bounded helpers into ``rosbags`` (once per process; idempotent)."""
    global _installed
    if _installed:
        return
    from rosbags.rosbag1 import reader as r1
    from rosbags.rosbag2 import storage_mcap as mc

    e1, e2 = r1.ReaderError, mc.ReaderError
    m1: Any = r1  # the modules are patched in place: no static types for that
    m2: Any = mc
    if hasattr(r1, "read_bytes"):
        m1.read_bytes = _bounded_read(e1)
    if hasattr(r1, "decompressors"):
        m1.decompressors = {
            **r1.decompressors,
            "lz4": _guard(lambda d: _lz4(d, None, e1), e1),
            "bz2": _guard(lambda d: _bz2(d, None, e1), e1),
        }
    if hasattr(r1, "Reader") and hasattr(r1.Reader, "read_index_data"):
        m1.Reader.read_index_data = _guarded_index_read(r1.Reader.read_index_data, e1)
    if hasattr(mc, "read_exact"):
        m2.read_exact = _bounded_read(e2)
    if hasattr(mc, "DECOMPRESSORS"):
        m2.DECOMPRESSORS = {
            **mc.DECOMPRESSORS,
            "lz4": _guard(lambda d, n: _lz4(d, n, e2), e2),
            "zstd": _guard(lambda d, n: _zstd(d, n, e2), e2),
        }
    _installed = True
