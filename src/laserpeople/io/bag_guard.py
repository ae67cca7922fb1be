"""Bounds on what a damaged bag can make the ``rosbags`` readers allocate, and the one
guarded way to open a bag (:func:`open_reader`) and read its messages (:func:`bag_messages`).

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
import contextlib
import io
import os
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, BinaryIO

if TYPE_CHECKING:
    from laserpeople.errors import RecordingError

CHUNK_LIMIT = 256 * 2**20
"""Largest decompressed chunk [bytes] a bag may hold; larger ones are reported corrupt."""

_installed = False
_installed_ros2 = False


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


def install(ros2: bool = True) -> None:
    """Put the bounded helpers into ``rosbags`` (once per process; idempotent): into the
    ROS 1 reader, and with ``ros2`` into the MCAP reader too (importing it costs 0.1 s: a
    ROS 1 bag does not need it)."""
    global _installed, _installed_ros2
    if not _installed:
        _install_ros1()
        _installed = True
    if ros2 and not _installed_ros2:
        _install_mcap()
        _installed_ros2 = True


def _install_ros1() -> None:
    from rosbags.rosbag1 import reader as r1

    e1 = r1.ReaderError
    m1: Any = r1  # the module is patched in place: no static types for that
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


def _install_mcap() -> None:
    from rosbags.rosbag2 import storage_mcap as mc

    e2 = mc.ReaderError
    m2: Any = mc  # the module is patched in place: no static types for that
    if hasattr(mc, "read_exact"):
        m2.read_exact = _bounded_read(e2)
    if hasattr(mc, "DECOMPRESSORS"):
        m2.DECOMPRESSORS = {
            **mc.DECOMPRESSORS,
            "lz4": _guard(lambda d, n: _lz4(d, n, e2), e2),
            "zstd": _guard(lambda d, n: _zstd(d, n, e2), e2),
        }


CORRUPT_HINT = (
    "the bag is corrupt or truncated; for a ROS 1 bag try `rosbag reindex`, "
    "otherwise re-record or re-copy it"
)
"""What to do about a bag the parser cannot read."""


def describe(exc: BaseException) -> str:
    """An exception of a third-party parser as text for an error message (cut to 300
    characters)."""
    text = str(exc)
    if len(text) > 300:
        text = text[:300] + "..."
    kind = type(exc)
    name = kind.__name__ if kind.__name__ != "error" else f"{kind.__module__}.error"
    return f"{name}: {text}" if text else name


BAG_MAGIC = (b"#ROSBAG V2.0\n", b"\x89MCAP0\r\n", b"SQLite format 3\x00")
"""How a ROS 1 bag, an MCAP file and a ROS 2 SQLite bag begin."""


def check_bag_file(path: Path) -> None:
    """Refuse a file that cannot be a bag (empty, or not starting as a ROS 1 bag, MCAP or
    SQLite file does) with a message that says so, before a parser reports it in its own
    words. A folder (a ROS 2 bag) is left to the reader.

    Raises:
        RecordingError: the file is empty or starts otherwise; names the file.
    """
    from laserpeople.errors import RecordingError
    from laserpeople.io.sniff import check_extension

    if path.is_dir():
        return
    try:
        with path.open("rb") as fh:
            head = fh.read(16)
    except OSError as exc:
        raise RecordingError(f"cannot read the file: {exc.strerror or exc}", path=path) from exc
    if not head:
        from laserpeople.io.paths import empty_file

        raise empty_file(path, "a bag")
    if any(head.startswith(m[: len(head)]) for m in BAG_MAGIC):
        check_extension(path)  # a whole bag of another kind than its extension says
        return
    check_extension(path)  # e.g. an .npz named .bag
    text = all(32 <= b < 127 or b in b"\t\r\n" for b in head)
    raise RecordingError(
        f"not a bag: it starts with {'text' if text else 'other binary data'} "
        f"({head.decode('ascii', 'replace')!r}), not as a ROS 1 bag, an MCAP or a ROS 2 "
        "SQLite file does",
        path=path,
        hint="check that this is the recording: a renamed or wrongly exported file is not a bag",
    )


def open_reader(
    path: str | Path,
    *,
    register: Callable[[Any], None] | None = None,
    hint: str = CORRUPT_HINT,
) -> Any:
    """Open a bag-like file (ROS 1 ``.bag``, ROS 2 ``.mcap``/``.db3`` or bag folder) with
    the bounds of :func:`install` in place: the one way every reader of this package opens a
    bag (recordings, truth bags, tracks bags, leg labels).

    Args:
        path: The bag.
        register: Adds message types to the typestore before the bag is opened.
        hint: What the user should do when the bag cannot be opened.

    Returns:
        An open ``rosbags.highlevel.AnyReader``, or for a ROS 1 bag without ``register``
        a :class:`~laserpeople.io.ros1_reader.Ros1Reader` with its interface (close it, or
        use it in ``with``).

    Raises:
        RecordingError: The file is missing, or any failure of the parser on a damaged
            file (rosbags' own errors, ``OverflowError``, ``struct.error``, sqlite/apsw
            errors, ``UnicodeDecodeError``, ``MemoryError``), naming the file.
    """
    from laserpeople.errors import RecordingError
    from laserpeople.io.paths import not_found

    p = Path(path)
    if not p.exists():
        raise RecordingError(not_found(p), path=p, hint="check the path")
    if p.is_dir() and not (p / "metadata.yaml").exists():
        raise RecordingError(
            "is a folder without metadata.yaml, not a bag",
            path=p,
            hint="give a bag file (.bag, .mcap, .db3) or a ROS 2 bag folder (one with "
            "metadata.yaml)",
        )
    if p.is_dir():
        check_storage_files(p)
    # a ROS 1 bag (AnyReader's rule: a .bag file) read without the ROS 2 readers, unless
    # the caller registers types (they reach AnyReader's default typestore)
    ros1 = p.suffix == ".bag" and register is None
    install(ros2=not ros1)
    check_bag_file(p)
    reader: Any = None
    try:
        if ros1:
            from laserpeople.io.ros1_reader import Ros1Reader

            reader = Ros1Reader(p)
            reader.open()
            return reader
        from rosbags.highlevel import AnyReader
        from rosbags.typesys import Stores, get_typestore

        reader = AnyReader([p])
        # ROS 1 bags carry their message definitions: the default types (0.15 s to import)
        # are needed only for ROS 2 bags and for types registered by the caller
        if reader.is2 or register is not None:
            typestore = get_typestore(Stores.LATEST)
            if register is not None:
                register(typestore)
            reader.default_typestore = typestore
        reader.open()
    except Exception as exc:  # any failure of the third-party parser on a damaged file
        if reader is not None:
            with contextlib.suppress(Exception):
                reader.close()
        foreign = foreign_mcap(p)
        if foreign is not None:
            raise foreign from None
        raise RecordingError(f"cannot open bag: {describe(exc)}", path=p, hint=hint) from exc
    return reader


def check_storage_files(folder: Path) -> None:
    """Refuse a ROS 2 bag folder whose ``metadata.yaml`` names storage files that are not
    in it (a copy of the folder without them, or renamed), before rosbags says "Some
    database files are missing". A ``metadata.yaml`` that cannot be read is left to rosbags.

    Raises:
        RecordingError: names the missing files, the storage files the folder holds and what
            to do.
    """
    from laserpeople.errors import RecordingError

    try:
        from ruamel.yaml import YAML

        info = YAML(typ="safe").load((folder / "metadata.yaml").read_text(encoding="utf-8"))
        names = [str(n) for n in info["rosbag2_bagfile_information"]["relative_file_paths"]]
    except Exception:  # (no ruamel, or a file of another layout: rosbags reports it)
        return
    missing = [n for n in names if not (folder / n).is_file()]
    if not missing:
        return
    held = sorted(
        f.name for f in folder.iterdir() if f.suffix in (".db3", ".mcap") or ".db3." in f.name
    )
    count = "s" if len(missing) > 1 else ""
    raise RecordingError(
        f"metadata.yaml names the storage file{count} {', '.join(missing)}, not in the folder"
        + (f" (it holds {', '.join(held)})" if held else " (it holds no .db3 or .mcap file)"),
        path=folder,
        hint="copy the whole bag folder, its storage files with metadata.yaml"
        + (
            f"; or give {folder / held[0]} itself (`ros2 bag reindex` writes a "
            "metadata.yaml that names the files there)"
            if held
            else ""
        ),
    )


MCAP_SCAN_BYTES = 1 << 20
"""Bytes of an MCAP read for its schemas' encodings when it is no ROS 2 bag."""


def foreign_mcap(path: Path) -> RecordingError | None:
    """The error for an MCAP file that holds no ROS 2 messages (its header's profile is not
    ``ros2``: e.g. Foxglove's JSON or Protobuf schemas, or ROS 1 messages), naming its
    profile and its schemas' encodings; None for any other file (a folder, no MCAP, a
    ``ros2`` profile, a header that cannot be read)."""
    import struct

    from laserpeople.errors import RecordingError

    magic = BAG_MAGIC[1]
    try:
        if path.is_dir():
            return None
        with path.open("rb") as fh:
            data = fh.read(MCAP_SCAN_BYTES)
    except OSError:
        return None
    if not data.startswith(magic) or len(data) < len(magic) + 13 or data[len(magic)] != 0x01:
        return None
    at = len(magic) + 9
    (n,) = struct.unpack_from("<I", data, at)
    profile = data[at + 4 : at + 4 + n].decode("utf-8", "replace")
    if profile == "ros2":
        return None
    encodings: list[str] = []  # of the schemas outside chunks (Schema records, op 0x03)
    at = len(magic)
    with contextlib.suppress(struct.error):  # (a record cut off: the encodings so far)
        while at + 9 <= len(data):
            op, length = struct.unpack_from("<BQ", data, at)
            body = data[at + 9 : at + 9 + length]
            if op == 0x03:
                (n,) = struct.unpack_from("<I", body, 2)
                (m,) = struct.unpack_from("<I", body, 6 + n)
                encodings.append(body[10 + n : 10 + n + m].decode("utf-8", "replace"))
            at += 9 + length
    schemas = f"; schemas in {', '.join(sorted(set(encodings)))}" if encodings else ""
    ros1 = profile == "ros1"
    return RecordingError(
        f"an MCAP of {'ROS 1 messages' if ros1 else 'no ROS messages'} (profile "
        f"{profile!r}{schemas}), not a ROS 2 bag: laserpeople reads sensor_msgs/LaserScan "
        "from ROS 1 .bag files and ROS 2 bags (MCAP of profile 'ros2', .db3) only",
        path=path,
        hint="record the scans as a ROS 1 .bag"
        if ros1
        else "record the scans with ROS (`ros2 bag record -s mcap /scan`), or give the "
        "recording this file was made from",
    )


def bag_messages(
    reader: Any, connections: Sequence[Any], path: str | Path, what: str
) -> Iterator[tuple[Any, int, Any]]:
    """``(connection, log time [ns], decoded message)`` of ``connections`` in log-time order;
    a record the parser cannot read or decode ends the read with a
    :class:`~laserpeople.errors.RecordingError` naming the file, ``what`` is read and the
    index of the bad message.
    """
    from laserpeople.errors import RecordingError

    if not connections:  # an empty list would mean "every topic" to rosbags
        return
    index = -1
    try:
        messages = reader.messages(connections=list(connections))
        for conn, log_time, raw in messages:
            index += 1
            yield conn, log_time, reader.deserialize(raw, conn.msgtype)
    except RecordingError:
        raise
    except Exception as exc:  # any failure of the third-party parser on a damaged file
        raise RecordingError(
            f"cannot read {what} (message {index + 1}): {describe(exc)}",
            path=path,
            hint=CORRUPT_HINT,
        ) from exc
