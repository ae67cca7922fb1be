"""Pair ground-truth frames with the tracks of the same scan (by scan index)."""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from laserpeople.errors import EvaluationError
from laserpeople.tracks import Tracks
from laserpeople.truth import TruthFrame


@dataclass
class PairingCounts:
    """What :func:`pair_by_scan` saw.

    Attributes:
        frames_scored: Truth frames handed on for scoring.
        frames_without_tracks: Of those, frames whose scan had no track rows (all missed).
        track_scans_unscored: Scans with tracks but no truth frame (not scored; with a sparse
            annotation these are the scans nobody annotated).
        max_stamp_offset: Largest |truth stamp - tracks stamp| over paired scans [s]; a large
            value means truth and tracks come from different recordings or topics.
    """

    frames_scored: int = 0
    frames_without_tracks: int = 0
    track_scans_unscored: int = 0
    max_stamp_offset: float = 0.0


def pair_by_scan(
    truth_frames: Iterable[TruthFrame],
    tracks: Iterable[Tracks],
    counts: PairingCounts | None = None,
) -> Iterator[tuple[TruthFrame, Tracks | None]]:
    """Yield ``(truth, tracks of that scan or None)`` for every truth frame, in order.

    Both inputs must come in strictly increasing scan order (as the recording and the tracks
    CSV are written); they are merged in one pass without holding either in memory.
    ``counts`` (if given) is updated as the pairs are produced.

    Raises:
        EvaluationError: a scan index repeats or goes backwards in either input.
    """
    stats = counts if counts is not None else PairingCounts()
    track_iter = iter(tracks)
    pending: Tracks | None = next(track_iter, None)
    last_truth = -1

    def advance(current: Tracks) -> Tracks | None:
        nxt = next(track_iter, None)
        if nxt is not None and nxt.scan_index <= current.scan_index:
            raise EvaluationError(
                f"tracks of scan {nxt.scan_index} come after scan {current.scan_index}",
                scan=nxt.scan_index,
                hint="sort the tracks CSV by scan; all rows of one scan must be together",
            )
        return nxt

    for truth in truth_frames:
        if truth.scan_index <= last_truth:
            raise EvaluationError(
                f"ground truth of scan {truth.scan_index} comes after scan {last_truth}",
                scan=truth.scan_index,
                hint="ground-truth frames must be in increasing scan order, one per scan",
            )
        last_truth = truth.scan_index
        while pending is not None and pending.scan_index < truth.scan_index:
            stats.track_scans_unscored += 1
            pending = advance(pending)
        matched: Tracks | None = None
        if pending is not None and pending.scan_index == truth.scan_index:
            matched = pending
            stats.max_stamp_offset = max(stats.max_stamp_offset, abs(truth.stamp - pending.stamp))
            pending = advance(pending)
        stats.frames_scored += 1
        stats.frames_without_tracks += matched is None
        yield truth, matched
    while pending is not None:
        stats.track_scans_unscored += 1
        pending = advance(pending)
