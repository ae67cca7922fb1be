"""Animated GIF written frame by frame: memory does not grow with the number of frames.

Pillow's multi-frame GIF writer keeps every frame until the file is closed (680 MB for a
737-frame animation). Here each frame is quantised to the fixed palette, compared with the
previous frame, and only the rectangle that changed is LZW-coded (by Pillow, as a one-frame
GIF whose image block is copied) and appended to the open file. At any time one frame and
the previous frame's palette indices are held.

File layout (GIF89a): header, logical screen with the fixed 256-colour global table, the
NETSCAPE2.0 looping extension, then per frame a graphic control extension (delay in
centiseconds, disposal "leave in place") and an image block for the changed rectangle.
"""

from __future__ import annotations

import io
import struct
from pathlib import Path
from typing import BinaryIO

import numpy as np
from numpy.typing import NDArray

from laserpeople.errors import LaserPeopleError

IndexImage = NDArray[np.uint8]


class GifFormatError(LaserPeopleError):
    """The image coder returned a GIF this writer cannot take apart (a bug, not the user's)."""


def _sub_blocks(data: bytes, pos: int) -> int:
    """Position after the data sub-blocks starting at ``pos`` (ends with a zero length)."""
    while True:
        n = data[pos]
        pos += 1
        if n == 0:
            return pos
        pos += n


def image_block(gif: bytes) -> tuple[bytes | None, bytes, bool]:
    """The colour table and the image block of a one-frame GIF.

    Returns ``(table, block, interlaced)``: ``table`` is the frame's colour table (global
    or local, raw RGB bytes; None when it has none), ``block`` the image data (the LZW
    minimum code size and the data sub-blocks up to and including their terminator) and
    ``interlaced`` whether the rows are stored interlaced.
    """
    if gif[:3] != b"GIF":
        raise GifFormatError("the image coder did not return a GIF")
    packed = gif[10]
    pos = 13
    table: bytes | None = None
    if packed & 0x80:
        size = 3 * (2 ** ((packed & 7) + 1))
        table = gif[pos : pos + size]
        pos += size
    while pos < len(gif):
        tag = gif[pos]
        if tag == 0x21:  # extension: label, then sub-blocks
            pos = _sub_blocks(gif, pos + 2)
        elif tag == 0x2C:  # image descriptor: 9 bytes after the separator
            img_packed = gif[pos + 9]
            pos += 10
            if img_packed & 0x80:
                size = 3 * (2 ** ((img_packed & 7) + 1))
                table = gif[pos : pos + size]
                pos += size
            start = pos
            end = _sub_blocks(gif, pos + 1)
            return table, gif[start:end], bool(img_packed & 0x40)
        else:
            break
    raise GifFormatError("the image coder returned a GIF without an image")


def _table_bits(table: bytes) -> int:
    """The 3-bit size field of a colour table of ``len(table) // 3`` entries."""
    entries = len(table) // 3
    bits = max(1, int(entries - 1).bit_length())
    return bits - 1


class GifWriter:
    """Appends palette-index frames to an animated GIF file.

    Args:
        path: The file to write (its directory is created).
        size: ``(width, height)`` [px] of every frame.
        palette: The global colour table: 256 RGB triples, flat (768 ints).
        loop: Play forever (otherwise once).

    Use as a context manager; :meth:`add` takes each frame as a (height, width) uint8
    array of palette indices and a display time [s].
    """

    def __init__(
        self, path: str | Path, size: tuple[int, int], palette: list[int], *, loop: bool = True
    ) -> None:
        if len(palette) != 768:
            raise ValueError(f"the palette needs 256 RGB triples, got {len(palette) // 3}")
        self.path = Path(path)
        self.size = (int(size[0]), int(size[1]))
        self.frames = 0
        self._palette = bytes(palette)
        self._previous: IndexImage | None = None
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._file: BinaryIO = self.path.open("wb")
        w, h = self.size
        self._file.write(b"GIF89a" + struct.pack("<HHBBB", w, h, 0xF7, 0, 0) + self._palette)
        if loop:
            self._file.write(b"\x21\xff\x0bNETSCAPE2.0\x03\x01\x00\x00\x00")

    def __enter__(self) -> GifWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def add(self, indices: IndexImage, seconds: float) -> None:
        """Append one frame shown for ``seconds`` (GIF delays are whole centiseconds, at
        least 2: browsers slow shorter ones down)."""
        h, w = indices.shape
        if (w, h) != self.size:
            raise LaserPeopleError(
                f"frame {self.frames} is {w}x{h} px, the animation is "
                f"{self.size[0]}x{self.size[1]}",
                path=self.path,
            )
        x0, y0, x1, y1 = self._changed(indices)
        self._previous = indices
        delay = max(2, round(seconds * 100.0))
        # graphic control extension: disposal 1 (leave the frame in place), no transparency
        self._file.write(struct.pack("<BBBBHBB", 0x21, 0xF9, 4, 1 << 2, delay, 0, 0))
        table, block, interlaced = image_block(_encode(indices[y0:y1, x0:x1], self._palette))
        packed = 0x40 if interlaced else 0
        local = b""
        if table is not None and table != self._palette:
            # the coder changed the table: ship it with the frame
            packed |= 0x80 | _table_bits(table)
            local = table
        self._file.write(struct.pack("<BHHHHB", 0x2C, x0, y0, x1 - x0, y1 - y0, packed))
        self._file.write(local + block)
        self._file.flush()  # a viewer or an interrupted run sees every finished frame
        self.frames += 1

    def _changed(self, indices: IndexImage) -> tuple[int, int, int, int]:
        """``(x0, y0, x1, y1)`` of the rectangle that differs from the previous frame (the
        whole frame first; one pixel when nothing changed)."""
        prev = self._previous
        h, w = indices.shape
        if prev is None:
            return 0, 0, w, h
        diff = prev != indices
        rows = np.flatnonzero(diff.any(axis=1))
        if rows.size == 0:
            return 0, 0, 1, 1
        cols = np.flatnonzero(diff[rows[0] : rows[-1] + 1].any(axis=0))
        return int(cols[0]), int(rows[0]), int(cols[-1]) + 1, int(rows[-1]) + 1

    def close(self) -> None:
        """Write the trailer and close the file."""
        if not self._file.closed:
            self._file.write(b"\x3b")
            self._file.close()


def _encode(indices: IndexImage, palette: bytes) -> bytes:
    """A one-frame GIF of palette ``indices`` (LZW-coded by Pillow)."""
    from PIL import Image

    img = Image.frombytes("P", (indices.shape[1], indices.shape[0]), indices.tobytes())
    img.putpalette(palette)
    buf = io.BytesIO()
    img.save(buf, format="GIF", optimize=False, interlace=False)
    return buf.getvalue()
