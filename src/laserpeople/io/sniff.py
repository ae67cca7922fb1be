"""What a recording's first bytes say it is, against what its extension says.

The reader is chosen by the extension. A ROS 1 bag renamed ``.mcap`` or ``.txt``, or an
``.npz`` named ``.bag``, would otherwise fail in its reader's words ("File magic is
invalid", "no laser lines", "not a zip file") and send the user to repair a file that is
whole; :func:`check_extension` names what the file is and the extension to give it.
"""

from __future__ import annotations

from pathlib import Path

from laserpeople.errors import RecordingError

FORMATS: tuple[tuple[bytes, str, str], ...] = (
    (b"#ROSBAG V2.0\n", "a ROS 1 bag", ".bag"),
    (b"\x89MCAP0\r\n", "an MCAP file", ".mcap"),
    (b"SQLite format 3\x00", "a ROS 2 SQLite bag", ".db3"),
    (b"PK\x03\x04", "a zip archive (an .npz recording)", ".npz"),
)
"""(first bytes, what the file is, the extension its reader is chosen by)."""


def content_format(path: Path) -> tuple[str, str] | None:
    """(what the file is, its extension) from its first bytes, or None for anything else
    (text such as a CARMEN log, a folder, an unreadable or short file)."""
    if path.is_dir():
        return None
    try:
        with path.open("rb") as fh:
            head = fh.read(16)
    except OSError:  # the reader says what is wrong
        return None
    for magic, what, suffix in FORMATS:
        if head.startswith(magic):
            return what, suffix
    return None


def check_extension(path: Path) -> None:
    """Refuse a file whose first bytes are those of another format than its extension's.

    Raises:
        RecordingError: names what the file is and the extension to rename it to.
    """
    found = content_format(path)
    if found is None:
        return
    what, suffix = found
    if path.suffix.lower() == suffix:
        return
    named = f"named {path.suffix!r}" if path.suffix else "has no extension"
    raise RecordingError(
        f"is {what} by its first bytes, but {named}",
        path=path,
        hint=f"rename it to {path.stem}{suffix}: the reader is chosen by the extension",
    )
