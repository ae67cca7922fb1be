"""Any tracks file this package writes, read back by one function: the tracks CSV of
``track -o``, the Parquet of ``batch --format parquet`` and the bag of ``track --bag`` /
``live --record``."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

from laserpeople.io.tracks_csv import TrackIdNames, check_read_arguments, iter_tracks_csv
from laserpeople.scan import CoordinateFrame
from laserpeople.tracks import TrackKind, Tracks


def read_tracks_file(
    path: str | Path,
    frame: CoordinateFrame = "world",
    kinds: tuple[TrackKind, ...] | None = None,
    ids: TrackIdNames | None = None,
) -> Iterator[Tracks]:
    """The tracks per scan of ``path``, chosen by its extension (``.parquet``) or content (a
    bag), else read as a tracks CSV.

    Args:
        frame: The frame of a CSV without a ``frame`` column (Parquet files and bags state
            theirs).
        kinds: Only these kinds (all when None).
        ids: Names of text track ids (CSV only; the other files hold numbers).

    Raises:
        TypeError, ValueError: an argument of the wrong type or value; names it.
    """
    from laserpeople.io import is_rosbag

    p = check_read_arguments("read_tracks_file", path, frame, kinds, ids)
    if p.suffix.lower() == ".parquet":
        from laserpeople.batch.parquet import iter_tracks_parquet

        return iter_tracks_parquet(p, frame, kinds=kinds)
    if is_rosbag(p):
        from laserpeople.io.tracks_bag import iter_tracks_bag

        return iter_tracks_bag(p, kinds=kinds)
    return iter_tracks_csv(p, frame=frame, kinds=kinds, ids=ids)


__all__ = ["read_tracks_file"]
