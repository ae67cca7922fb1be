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
    new = renamed(path, suffix)
    hint = f"rename it to {new}: the reader is chosen by the extension"
    if path.name.lower().endswith(ACTIVE_BAG):
        hint = (
            f"`rosbag record` writes a bag under this name while it records and renames it to "
            f"{new} when it stops: wait for it; a bag left so by a recorder stopped hard reads "
            f"once renamed to {new} (`rosbag reindex` it if its index is missing)"
        )
    raise RecordingError(f"is {what} by its first bytes, but {named}", path=path, hint=hint)


ACTIVE_BAG = ".bag.active"
"""The ending of the name of a ROS 1 bag that ``rosbag record`` is writing."""


def renamed(path: Path, suffix: str) -> str:
    """The name ``path`` should have for the extension ``suffix``: ``run.bag`` for
    ``run.txt`` and for ``run.bag.active`` (its last extension dropped when the one before
    is ``suffix`` already), ``run.bag`` for ``run``."""
    stem = path.stem
    return stem if Path(stem).suffix.lower() == suffix else f"{stem}{suffix}"


def unfinished_bag_files(path: Path) -> list[Path]:
    """The ROS 2 storage files (``.mcap``, ``.db3``) directly in the folder ``path`` when
    it has no ``metadata.yaml``: ``ros2 bag record`` writes that file when it stops, so such
    a folder is a bag still being recorded, or one whose recorder was stopped hard (each
    storage file reads alone). Empty for anything else."""
    if not path.is_dir() or (path / "metadata.yaml").exists():
        return []
    try:
        return sorted(
            p for p in path.iterdir() if p.suffix.lower() in (".mcap", ".db3") and p.is_file()
        )
    except OSError:
        return []


def unfinished_recording(path: Path) -> str:
    """What a recording still being written looks like, said of ``path``: a ROS 1 bag
    named ``.bag.active`` (``rosbag record``'s name while it records) or a ROS 2 bag
    folder without ``metadata.yaml`` (:func:`unfinished_bag_files`); empty otherwise."""
    if path.name.lower().endswith(ACTIVE_BAG):
        return "named as a bag `rosbag record` is still writing, or left by one stopped hard"
    files = unfinished_bag_files(path)
    if not files:
        return ""
    return (
        "a ROS 2 bag folder without metadata.yaml (`ros2 bag record` writes it when it "
        f"stops: still recording, or stopped hard); its {files[0].name} reads alone"
    )
