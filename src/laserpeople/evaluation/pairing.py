"""Pair ground-truth frames with the tracks of the same scan (by scan index)."""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import dataclass

import numpy as np

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
        tracks_frame: The frame the first paired scan's tracks were compared in (empty
            before one).
        truth_frame: The frame its truth states (empty: not stated, or none paired).
        tracks_moved_from: The tracks' own frame when they were moved into the truth's frame
            with their sensor pose (empty: compared in their own frame).
        truth_scans: First and last scan index of the truth frames ((-1, -1): none).
        truth_stamps: Their stamps [s].
        tracks_scans: First and last scan index with track rows ((-1, -1): none).
        tracks_stamps: Their stamps [s].
        paired_stamps: The truth's and the tracks' stamps [s] of the first and the last
            paired scan: (truth first, truth last, tracks first, tracks last); NaN before a
            pair.
        truth_distances: Sum [m] and count of the distances from the origin of the labelled
            people of the paired scans.
        tracks_distances: The same of their tracks.
    """

    frames_scored: int = 0
    frames_without_tracks: int = 0
    track_scans_unscored: int = 0
    max_stamp_offset: float = 0.0
    min_stamp_difference: float = float("inf")
    max_stamp_difference: float = float("-inf")
    tracks_frame: str = ""
    truth_frame: str = ""
    tracks_moved_from: str = ""
    truth_scans: tuple[int, int] = (-1, -1)
    truth_stamps: tuple[float, float] = (math.nan, math.nan)
    tracks_scans: tuple[int, int] = (-1, -1)
    tracks_stamps: tuple[float, float] = (math.nan, math.nan)
    paired_stamps: tuple[float, float, float, float] = (math.nan,) * 4
    truth_distances: tuple[float, int] = (0.0, 0)
    tracks_distances: tuple[float, int] = (0.0, 0)

    STAMP_TOLERANCE = 0.05
    """Largest stamp difference [s] (or spread of the differences) taken as the same scan:
    assumption, half a scan period of a 10 Hz laser."""

    def frame_check(self) -> str:
        """Which frame the positions were compared in, when the truth does not state its
        own (a truth CSV without a ``frame`` column; :func:`frame_points` compares the
        tracks as they are), or when the tracks were moved into the truth's frame with
        their sensor poses: empty otherwise, or when nothing was paired."""
        if self.tracks_moved_from:
            return (
                f"the tracks, written in the {self.tracks_moved_from} frame, were moved into "
                f"the {self.tracks_frame} frame of the truth with each scan's sensor pose"
            )
        if not self.tracks_frame or self.truth_frame:
            return ""
        return (
            f"scored in the {self.tracks_frame} frame of the tracks; the truth does not "
            "state its frame (a truth CSV can, in a frame column)"
        )

    def overlap_check(self) -> str:
        """A warning when truth and tracks share no scan: every scored truth frame had no
        track rows while the tracks have rows on other scans (truth of another recording,
        topic or time range would score as all missed, silently); empty otherwise."""
        if not self.frames_scored or self.frames_without_tracks < self.frames_scored:
            return ""
        if self.tracks_scans[0] < 0:
            return ""
        return (
            f"no scored scan has track rows: the truth covers scans {_span(self.truth_scans)} "
            f"(stamps {_span(self.truth_stamps)} s), the tracks scans "
            f"{_span(self.tracks_scans)} (stamps {_span(self.tracks_stamps)} s); check that "
            "truth and tracks come from the same recording and laser topic"
        )

    def disjoint(self) -> EvaluationError | None:
        """The error to raise when truth and tracks cover scans that do not overlap at all
        (every track scan before the truth's first or after its last) and their stamps are
        not of one clock (:meth:`one_clock`): truth of another recording, topic or time
        range, which would score as all missed (MOTA 0). None otherwise (a tracker that
        reported nothing in the scans the truth covers of its own recording is all missed,
        with :meth:`overlap_check`'s warning), or when either is empty."""
        if not self.frames_scored or self.frames_without_tracks < self.frames_scored:
            return None
        (truth_first, truth_last), (tracks_first, tracks_last) = (
            self.truth_scans,
            self.tracks_scans,
        )
        if tracks_first < 0 or not (tracks_last < truth_first or tracks_first > truth_last):
            return None
        if self.one_clock():
            return None
        return EvaluationError(
            f"truth and tracks share no scan: the truth covers scans {_span(self.truth_scans)} "
            f"(stamps {_span(self.truth_stamps)} s), the tracks scans "
            f"{_span(self.tracks_scans)} (stamps {_span(self.tracks_stamps)} s); nothing was "
            "scored (not all missed)",
            hint="give the truth and the tracks of the same recording and laser topic",
        )

    def one_clock(self) -> bool:
        """Whether the tracks' first scan has the stamp the truth's scans give it: the
        truth's first stamp plus the scans between at the truth's mean scan period (the
        tracks' when the truth spans one scan), within :data:`CLOCK_TOLERANCE` s plus
        :data:`CLOCK_DRIFT` of the time between (scans a driver dropped make the stamps
        run ahead of the count). False when no period is known."""
        (truth_first, truth_last), (tracks_first, tracks_last) = (
            self.truth_scans,
            self.tracks_scans,
        )
        if truth_last > truth_first:
            period = (self.truth_stamps[1] - self.truth_stamps[0]) / (truth_last - truth_first)
        elif tracks_last > tracks_first:
            period = (self.tracks_stamps[1] - self.tracks_stamps[0]) / (tracks_last - tracks_first)
        else:
            return False
        between = (tracks_first - truth_first) * period
        expected = self.truth_stamps[0] + between
        return abs(expected - self.tracks_stamps[0]) <= CLOCK_TOLERANCE + CLOCK_DRIFT * abs(between)

    def stamp_check(self) -> tuple[str, bool]:
        """What the paired scans' stamps say, and whether it is a warning: nothing when
        they agree; a note when every truth stamp is off by the same amount (another clock,
        as a truth CSV written with the bag's receive time: the scan indices pair them);
        a warning when the differences vary (different recordings or topics)."""
        if self.max_stamp_offset <= self.STAMP_TOLERANCE:
            return "", False
        spread = self.max_stamp_difference - self.min_stamp_difference
        if spread <= self.STAMP_TOLERANCE:
            mean = 0.5 * (self.max_stamp_difference + self.min_stamp_difference)
            shift = self.scan_shift(mean)
            if shift:
                return (
                    f"truth stamps are {mean:+.3f} s from the tracks' on every scored scan: "
                    f"{abs(shift)} scan periods, so the truth's scan numbers may be {shift:+d} "
                    "off (a truth counted from another first scan, or of another topic); "
                    "truth and tracks were paired by scan index",
                    True,
                )
            return (
                f"truth stamps are {mean:+.3f} s from the tracks' on every scored scan (another "
                "clock, e.g. the bag's receive time); truth and tracks were paired by scan "
                "index",
                False,
            )
        return (
            f"truth and track stamps differ by up to {self.max_stamp_offset:.3f} s for the "
            f"same scan index, by amounts varying over {spread:.3f} s: "
            + (self.stamp_unit() or "check that they come from the same recording and topic"),
            True,
        )

    def stamp_unit(self) -> str:
        """What to say when the tracks' stamps run a power of a thousand times as fast as
        the truth's over the paired scans (within :data:`UNIT_TOLERANCE`): stamps written in
        milliseconds, microseconds or nanoseconds where seconds are read (or the truth's);
        empty otherwise, or with fewer than two paired stamps apart."""
        truth_first, truth_last, tracks_first, tracks_last = self.paired_stamps
        truth_span, tracks_span = truth_last - truth_first, tracks_last - tracks_first
        if not (truth_span > 0 and tracks_span > 0):
            return ""
        ratio = tracks_span / truth_span
        for factor, unit in STAMP_UNITS:
            for scale, whose, other in (
                (ratio, "tracks'", "truth's"),
                (1 / ratio, "truth's", "tracks'"),
            ):
                if abs(scale / factor - 1.0) <= UNIT_TOLERANCE:
                    return (
                        f"over the paired scans the {whose} stamps advance {factor:,.0f} times "
                        f"as far as the {other}: are they in {unit}? Stamps are read in "
                        f"seconds: write the {whose} in seconds (the scores stand: scans are "
                        "paired by index)"
                    )
        return ""

    def position_unit(self) -> str:
        """What to say when the tracks of the paired scans lie a power of a thousand times
        as far from the origin as the labelled people on average (within a factor
        :data:`POSITION_UNIT_SPREAD` of it): positions written in millimetres or micrometres
        where metres are read (or the truth's); empty otherwise."""
        (truth_sum, truth_n), (tracks_sum, tracks_n) = self.truth_distances, self.tracks_distances
        if not (truth_n and tracks_n and truth_sum > 0 and tracks_sum > 0):
            return ""
        ratio = (tracks_sum / tracks_n) / (truth_sum / truth_n)
        for factor, unit in POSITION_UNITS:
            for scale, whose, other in (
                (ratio, "tracks", "people"),
                (1 / ratio, "people", "tracks"),
            ):
                if 1 / POSITION_UNIT_SPREAD <= scale / factor <= POSITION_UNIT_SPREAD:
                    return (
                        f"the {whose} are {scale:,.0f} times as far from the origin as the "
                        f"{other} on average: are their positions in {unit}? Positions are "
                        "read in metres"
                    )
        return ""

    def scan_shift(self, offset: float) -> int:
        """How many scans the truth's scan numbers are ahead of the tracks' when the
        constant stamp ``offset`` [s] (truth minus tracks) is a whole number of the tracks'
        mean scan periods (within :data:`SHIFT_TOLERANCE` of a period, fewer than the scans
        the tracks span): a label numbered ``i`` then has the stamp of the tracks' scan
        ``i - shift``. 0 when it is not (another clock's offset: under a period, or far
        beyond the recording)."""
        scans = self.tracks_scans[1] - self.tracks_scans[0]
        if scans < 1:
            return 0
        period = (self.tracks_stamps[1] - self.tracks_stamps[0]) / scans
        if not period > 0:
            return 0
        periods = offset / period
        k = round(periods)
        if k == 0 or abs(k) >= scans or abs(periods - k) > SHIFT_TOLERANCE:
            return 0
        return -int(k)


SHIFT_TOLERANCE = 0.02
"""Largest distance, in scan periods, of a constant stamp offset from a whole number of
periods for truth and tracks to be taken as paired scans apart: a simulated laser's period
is exact, and a real laser's mean period over a recording varies far less; an unrelated
clock offset falls this close to a whole number 4 % of the time (the leg_tracker
benchmark's -130.29 s at 10 Hz is 0.22 periods off, its 0.064 s at 7.5 Hz 0.48)."""


STAMP_UNITS = ((1e3, "milliseconds"), (1e6, "microseconds"), (1e9, "nanoseconds"))
"""Units other tools write stamps in, by how many of them make a second."""

UNIT_TOLERANCE = 0.01
"""Largest relative distance of the ratio of the paired stamps' spans from a unit's
factor for the stamps to be taken as in that unit: the stamps of one scan written by two
programs agree to far better than 1 % over any span of scans (rounding to microseconds)."""


POSITION_UNITS = ((1e3, "millimetres"), (1e6, "micrometres"))
"""Units other tools write positions in, by how many of them make a metre."""

POSITION_UNIT_SPREAD = 3.0
"""Largest factor between the ratio of the mean distances from the origin of tracks and
labelled people and a unit's factor for positions to be taken as in that unit: tracks lie
near the people they follow, but their mean distance differs with the false tracks and the
people missed, and a laser frame's origin (the sensor) and a world frame's differ; a
factor of 3 keeps millimetres (1,000) apart from metres (1) and from micrometres."""


CLOCK_TOLERANCE = 0.5
"""Largest difference [s] between a stamp and the one extrapolated from another part of
the same recording at its mean scan period, for them to be of one clock (five periods of a
10 Hz laser)."""

CLOCK_DRIFT = 0.02
"""Share of the time between the two parts added to :data:`CLOCK_TOLERANCE`: a driver
that drops 2 scans in 100 puts its stamps 2 % ahead of the count of scans recorded."""


def _span(pair: tuple[float, float]) -> str:
    """``first-last`` of a range of scan indices or stamps."""
    return "-".join(f"{v:.3f}" if isinstance(v, float) else str(v) for v in pair)


def _add_distances(total: tuple[float, int], positions: np.ndarray) -> tuple[float, int]:
    """``total`` (sum [m], count) with the distances from the origin of ``positions`` (N, 2)
    [m] added."""
    if not len(positions):
        return total
    distances = np.hypot(positions[:, 0], positions[:, 1])
    return total[0] + float(distances.sum()), total[1] + len(positions)


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

    def seen(tracks: Tracks | None) -> Tracks | None:
        if tracks is not None:
            if stats.tracks_scans[0] < 0:
                stats.tracks_scans, stats.tracks_stamps = (
                    (tracks.scan_index, 0),
                    (tracks.stamp, 0.0),
                )
            stats.tracks_scans = (stats.tracks_scans[0], tracks.scan_index)
            stats.tracks_stamps = (stats.tracks_stamps[0], tracks.stamp)
        return tracks

    def advance(current: Tracks) -> Tracks | None:
        nxt = next(track_iter, None)
        if nxt is not None and nxt.scan_index <= current.scan_index:
            raise EvaluationError(
                f"tracks of scan {nxt.scan_index} come after scan {current.scan_index}",
                scan=nxt.scan_index,
                hint="sort the tracks CSV by scan; all rows of one scan must be together",
            )
        return seen(nxt)

    pending = seen(pending)

    for truth in truth_frames:
        if truth.scan_index <= last_truth:
            raise EvaluationError(
                f"ground truth of scan {truth.scan_index} comes after scan {last_truth}",
                scan=truth.scan_index,
                hint="ground-truth frames must be in increasing scan order, one per scan",
            )
        last_truth = truth.scan_index
        if stats.truth_scans[0] < 0:
            stats.truth_scans, stats.truth_stamps = (truth.scan_index, 0), (truth.stamp, 0.0)
        stats.truth_scans = (stats.truth_scans[0], truth.scan_index)
        stats.truth_stamps = (stats.truth_stamps[0], truth.stamp)
        while pending is not None and pending.scan_index < truth.scan_index:
            stats.track_scans_unscored += 1
            pending = advance(pending)
        matched: Tracks | None = None
        if pending is not None and pending.scan_index == truth.scan_index:
            matched = pending
            if not stats.tracks_frame:
                # (as frame_points: tracks that know their sensor pose are moved into the
                # frame the truth states; against truth that states none, compared as they are)
                stats.tracks_frame = truth.frame or pending.frame
                stats.truth_frame = truth.frame or ""
                if stats.tracks_frame != pending.frame:
                    stats.tracks_moved_from = pending.frame
            diff = truth.stamp - pending.stamp
            stats.truth_distances = _add_distances(stats.truth_distances, truth.positions)
            if pending.tracks:
                positions = np.array([t.position for t in pending.tracks])
                stats.tracks_distances = _add_distances(stats.tracks_distances, positions)
            if math.isnan(stats.paired_stamps[0]):
                stats.paired_stamps = (truth.stamp, truth.stamp, pending.stamp, pending.stamp)
            truth_first, _, tracks_first, _ = stats.paired_stamps
            stats.paired_stamps = (truth_first, truth.stamp, tracks_first, pending.stamp)
            stats.max_stamp_offset = max(stats.max_stamp_offset, abs(diff))
            stats.min_stamp_difference = min(stats.min_stamp_difference, diff)
            stats.max_stamp_difference = max(stats.max_stamp_difference, diff)
            pending = advance(pending)
        stats.frames_scored += 1
        stats.frames_without_tracks += matched is None
        yield truth, matched
    while pending is not None:
        stats.track_scans_unscored += 1
        pending = advance(pending)
