"""Does a tracks or truth file belong to a recording? (scan count, stamps, topic)."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

import numpy as np

from laserpeople.io import RecordingSource
from laserpeople.io.tracks_csv import read_tracks_topic
from laserpeople.io.tracks_files import read_tracks_file
from laserpeople.pipeline.sources import FUSED
from laserpeople.truth import TruthFrame

STAMP_TOLERANCE = 0.01
"""Largest stamp difference [s] between a tracks row and its scan that still counts as the
same scan (the CSV stores stamps to the microsecond)."""


def tracks_mismatch(tracks_csv: str | Path, recording: RecordingSource, topic: str) -> list[str]:
    """Why ``tracks_csv`` does not belong to ``topic`` of ``recording`` (empty when it does):
    another topic in its ``topic`` column, scan indices beyond the topic's scans, or stamps
    that differ from the scans' by more than :data:`STAMP_TOLERANCE`."""
    problems: list[str] = []
    rows = [(t.scan_index, t.stamp) for t in read_tracks_file(tracks_csv)]  # checks the file
    csv = Path(tracks_csv).suffix.lower() == ".csv"
    csv_topic = read_tracks_topic(tracks_csv) if csv else None
    if csv_topic not in (None, "", FUSED, topic) and csv_topic.strip("/") != topic.strip("/"):
        problems.append(f"the tracks are of topic {csv_topic}, the drawing shows {topic}")
    if not rows:
        return problems
    stamps = np.array([s.stamp for s in recording.scans([topic])])
    index = np.array([r[0] for r in rows], dtype=np.int64)
    csv_stamps = np.array([r[1] for r in rows])
    beyond = index >= stamps.size
    if beyond.any():
        problems.append(
            f"the tracks reach scan {int(index.max())} but {topic} has {stamps.size} scans"
        )
    inside = ~beyond
    gap = np.abs(csv_stamps[inside] - stamps[index[inside]])
    off = gap > STAMP_TOLERANCE
    if off.any():
        first = int(np.flatnonzero(off)[0])
        i = int(index[inside][first])
        problems.append(
            f"{int(off.sum())} of {int(inside.sum())} scans with tracks have other stamps than "
            f"the recording's (scan {i}: {csv_stamps[inside][first]:.3f} s in the tracks, "
            f"{stamps[i]:.3f} s in the recording)"
        )
    return problems


def truth_mismatch(
    truth: Iterable[TruthFrame], recording: RecordingSource, topic: str
) -> list[str]:
    """Why ``truth`` does not belong to ``topic`` of ``recording`` (empty when it may):
    labels of scans beyond the topic's scans. (Stamps are not compared: labels may carry
    another clock's, as the leg_tracker benchmarks' do.)"""
    count = next((t.count for t in recording.topics() if t.name == topic), None)
    last = max((f.scan_index for f in truth), default=-1)
    if count is None or last < count:
        return []
    return [f"the truth labels scans up to {last} but {topic} has {count} scans"]


__all__ = ["STAMP_TOLERANCE", "tracks_mismatch", "truth_mismatch"]
