"""Readers and writers of laser recordings, detections and tracks.

:func:`open_recording` picks the reader by file extension; every reader offers the
:class:`RecordingSource` protocol: ``topics()``, ``scans(topics)`` (a time-ordered stream
of :class:`~laserpeople.scan.Scan` in constant memory), ``truth()`` and ``has_truth``.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

from laserpeople.errors import RecordingError
from laserpeople.io.npz import NpzRecording, TopicInfo, write_recording
from laserpeople.io.paths import empty_file, not_found
from laserpeople.io.sniff import check_extension, unfinished_bag_files, unfinished_recording
from laserpeople.scan import Scan
from laserpeople.truth import TruthFrame

__all__ = [
    "NpzRecording",
    "RecordingSource",
    "TopicInfo",
    "is_rosbag",
    "open_recording",
    "write_recording",
]

ROSBAG_SUFFIXES = frozenset({".bag", ".db3", ".mcap"})


@runtime_checkable
class RecordingSource(Protocol):
    """What every recording reader offers."""

    path: Path

    @property
    def has_truth(self) -> bool:
        """Whether per-frame ground truth is available."""
        ...

    def topics(self) -> list[TopicInfo]:
        """The laser topics (sensors) with message type and count."""
        ...

    def scans(self, topics: Sequence[str] | None = None) -> Iterator[Scan]:
        """Scans of the given topics (all laser topics when None) in time order."""
        ...

    def truth(self) -> Iterator[TruthFrame]:
        """Ground-truth frames in time order; empty when there is none."""
        ...

    def close(self) -> None:
        """Release files."""
        ...


def is_rosbag(path: str | Path) -> bool:
    """Whether ``path`` names a ROS 1 or ROS 2 bag (by extension, or a ROS 2 bag folder)."""
    p = Path(path)
    return p.suffix.lower() in ROSBAG_SUFFIXES or (p.is_dir() and (p / "metadata.yaml").exists())


def open_recording(path: str | Path, **options: Any) -> RecordingSource:
    """Open a recording by its extension: ``.npz``, ``.bag``, ``.db3``/``.mcap`` (or a ROS 2
    bag folder), CARMEN ``.log``/``.clf``/``.txt``.

    ``options`` go to the reader: e.g. ``poses=False``, ``world_frame="odom"`` or
    ``mounts=...`` for bags (:class:`~laserpeople.io.rosbag.RosbagRecording`), ``poses`` and
    ``skip_bad_lines`` for CARMEN logs. Every reader takes ``on_error="stop"|"skip"``:
    what to do with a damaged scan in the middle of a recording (see
    :mod:`laserpeople.io.damage`); the ``.npz`` reader takes no other option.

    Raises:
        TypeError: ``path`` is no str or path (names what it got).
        RecordingError: the recording cannot be opened (names the file and why).
    """
    from laserpeople.io.paths import path_argument

    p = path_argument(path, "path", "open_recording")
    if not p.exists():
        raise RecordingError(not_found(p), path=p, hint="check the path")
    suffix = p.suffix.lower()
    if p.is_dir() and not (p / "metadata.yaml").exists():
        neko = (p / "xy_data.txt").is_file()
        storage = unfinished_bag_files(p)
        if storage:
            raise RecordingError(
                f"is {unfinished_recording(p)}",
                path=p,
                hint=f"wait for the recording to end, or give {storage[0]} itself"
                + (f" ({len(storage)} storage files: one at a time)" if len(storage) > 1 else "")
                + f"; `ros2 bag reindex {p}` writes the missing metadata.yaml",
            )
        raise RecordingError(
            "is a directory, not a recording",
            path=p,
            hint="a neko7055 directory is read by `laserpeople train --neko DIR`"
            if neko
            else "give a file, or a ROS 2 bag folder (one with metadata.yaml)",
        )
    if p.is_file() and p.stat().st_size == 0:
        raise empty_file(p, "a recording")
    check_extension(p)
    if suffix == ".npz":
        extra = set(options) - {"on_error"}
        if extra:
            raise RecordingError(
                f"options {', '.join(sorted(extra))} do not apply to .npz recordings", path=p
            )
        return NpzRecording(p, **options)
    if is_rosbag(p):
        from laserpeople.io.rosbag import RosbagRecording

        return RosbagRecording(p, **options)
    if suffix in {".log", ".clf", ".carmen", ".txt", ".gz"}:
        from laserpeople.io.carmen import CarmenRecording

        return CarmenRecording(p, **options)
    if suffix in {".csv", ".parquet"}:
        raise RecordingError(
            f"a {suffix} table (tracks, detections or ground truth), not a recording",
            path=p,
            hint=f"give the recording it was made from; a {suffix} goes to `view --tracks` or "
            "`evaluate` (TRACKS or --truth)",
        )
    raise RecordingError(
        f"unknown recording format {suffix or '(no extension)'!r}",
        path=p,
        hint="use .bag, .mcap, .db3, a ROS 2 bag folder, a CARMEN .log/.clf, or .npz",
    )
