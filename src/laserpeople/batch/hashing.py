"""Content hashes of recordings: what the manifest keys a recording by (not its name or time).

A file hashes to the SHA-256 of its bytes; a folder (a ROS 2 bag) to the SHA-256 of its
files' relative names and content hashes, in name order. Renaming or touching a recording
does not make it new; changing one byte does.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

from laserpeople.errors import RecordingError
from laserpeople.io.paths import not_found

CHUNK = 1 << 20
"""Bytes read at a time [B]."""


def content_hash(path: str | Path) -> str:
    """SHA-256 (hex) of a file's bytes, or of a folder's files (see the module docstring).

    Raises:
        RecordingError: The path does not exist or cannot be read.
    """
    p = Path(path)
    try:
        if p.is_dir():
            digest = hashlib.sha256()
            for child in sorted(q for q in p.rglob("*") if q.is_file()):
                digest.update(child.relative_to(p).as_posix().encode() + b"\0")
                digest.update(content_hash(child).encode() + b"\n")
            return digest.hexdigest()
        digest = hashlib.sha256()
        with p.open("rb") as f:
            while block := f.read(CHUNK):
                digest.update(block)
        return digest.hexdigest()
    except FileNotFoundError:
        raise RecordingError(not_found(p), path=p, hint="check the path or the glob") from None
    except OSError as exc:
        raise RecordingError(f"cannot read: {exc.strerror or exc}", path=p) from None


__all__ = ["content_hash"]
