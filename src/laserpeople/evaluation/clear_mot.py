"""CLEAR MOT (Bernardin & Stiefelhagen, "Evaluating multiple object tracking performance: the
CLEAR MOT metrics", EURASIP JIVP 2008): MOTA, MOTP, misses, false positives, ID switches.

Per frame t, with the mapping M (each person's last matched track, kept across frames):

1. Every person whose last matched track is present in frame t within the gate keeps it
   (a track can be kept by one person only; when two people claim the same track, the one
   whose mapping was made most recently keeps it, ties by the smaller person id; this is
   the one place where py-motmetrics differs: it gives the track to the person listed
   first).
2. The remaining people and tracks are matched one to one by the Hungarian algorithm,
   first maximising the number of pairs within the gate, then minimising their summed
   distance.
3. A pair made in step 2 whose person was last matched to another track is an ID switch;
   the mapping is updated. People left unmatched are misses, tracks left unmatched are
   false positives.

MOTA = 1 - (misses + false positives + ID switches) / (people summed over frames);
MOTP = (summed distance of all matches) / (number of matches), in metres: the plain
Euclidean distance, not its square. A fragmentation is a person's track coverage being
interrupted: a run of misses between two matches of the same person (as counted by
py-motmetrics).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from laserpeople.evaluation.detail import FrameTable, frames_not_kept
from laserpeople.evaluation.matching import frame_points, gated_assignment
from laserpeople.evaluation.params import EvaluationParams
from laserpeople.tracks import Tracks
from laserpeople.truth import TruthFrame

CLEAR_MOT_COLUMNS = (
    "scan",
    "stamp",
    "num_truth",
    "num_tracks",
    "matches",
    "misses",
    "false_positives",
    "id_switches",
    "fragmentations",
    "distance_sum_m",
)


@dataclass(frozen=True)
class ClearMotResult:
    """CLEAR MOT over all scored frames.

    Attributes:
        mota: Multiple object tracking accuracy (NaN when no person was present at all).
        motp: Mean distance of the matched pairs [m] (NaN when nothing was matched).
        matches: Matched (person, track) pairs summed over frames.
        misses: People left unmatched, summed over frames (false negatives).
        false_positives: Tracks left unmatched, summed over frames.
        id_switches: Matches to a different track than the person's last match.
        fragmentations: Interruptions of a person's coverage (miss run between matches).
        num_truth: People summed over frames.
        num_tracks: Tracks of the scored kind summed over frames.
        num_frames: Frames scored.
        recall: matches / num_truth (NaN when num_truth is 0).
        precision: matches / num_tracks (NaN when num_tracks is 0).
        distance_sum: Summed distance of all matches [m].
        gate: Matching gate used [m].
    """

    mota: float
    motp: float
    matches: int
    misses: int
    false_positives: int
    id_switches: int
    fragmentations: int
    num_truth: int
    num_tracks: int
    num_frames: int
    recall: float
    precision: float
    distance_sum: float
    gate: float


class ClearMot:
    """Accumulates CLEAR MOT frame by frame (see the module docstring for the rules).

    Example:
        >>> metric = ClearMot()  # doctest: +SKIP
        >>> for truth, tracks in pairs:  # doctest: +SKIP
        ...     metric.accumulate(truth, tracks)
        >>> metric.result().mota  # doctest: +SKIP
    """

    def __init__(self, params: EvaluationParams | None = None, *, keep_frames: bool = True) -> None:
        self.params = params or EvaluationParams()
        self.keep_frames = keep_frames
        self._last_track: dict[int, int] = {}
        self._last_time: dict[int, int] = {}
        self._last_was_match: dict[int, bool] = {}
        self._gap_open: set[int] = set()
        self._frame = 0
        self._pairs: dict[int, int] = {}
        self._rows: list[tuple[int | float, ...]] = []
        self._totals = np.zeros(8, dtype=np.int64)
        self._distance_sum = 0.0

    def accumulate(self, truth_frame: TruthFrame, tracks: Tracks | None) -> None:
        """Score one frame: ``tracks`` are the tracker's output for ``truth_frame``'s scan."""
        pts = frame_points(truth_frame, tracks, self.params.kind)
        gate = self.params.gate
        dist = pts.distances
        n_truth, n_tracks = dist.shape
        truth_ids = pts.truth_ids.tolist()
        track_ids = pts.track_ids.tolist()
        truth_done = np.zeros(n_truth, dtype=bool)
        track_done = np.zeros(n_tracks, dtype=bool)
        pairs: list[tuple[int, int]] = []

        # Step 1: keep last correspondences that are still valid.
        column_of = {tid: j for j, tid in enumerate(track_ids)}
        kept = []
        for i, oid in enumerate(truth_ids):
            last = self._last_track.get(oid)
            j = column_of.get(last) if last is not None else None
            if j is not None and dist[i, j] <= gate:
                kept.append((-self._last_time[oid], oid, i, j))
        for _, _, i, j in sorted(kept):
            if not track_done[j]:
                truth_done[i] = track_done[j] = True
                pairs.append((i, j))

        # Step 2: Hungarian on what is left; count switches.
        free_i = np.flatnonzero(~truth_done)
        free_j = np.flatnonzero(~track_done)
        r, c = gated_assignment(dist[np.ix_(free_i, free_j)], gate)
        switches = 0
        for i, j in zip(free_i[r].tolist(), free_j[c].tolist(), strict=True):
            oid = truth_ids[i]
            if oid in self._last_track and self._last_track[oid] != track_ids[j]:
                switches += 1
            truth_done[i] = track_done[j] = True
            pairs.append((i, j))

        fragments = 0
        for i, oid in enumerate(truth_ids):
            if truth_done[i]:
                if oid in self._gap_open:
                    fragments += 1
                    self._gap_open.discard(oid)
                self._last_was_match[oid] = True
            else:
                if self._last_was_match.get(oid, False):
                    self._gap_open.add(oid)
                self._last_was_match[oid] = False
        self._pairs = {truth_ids[i]: track_ids[j] for i, j in pairs}
        for oid, tid in self._pairs.items():
            self._last_track[oid] = tid
            self._last_time[oid] = self._frame
        self._frame += 1

        matches = len(pairs)
        dsum = float(sum(dist[i, j] for i, j in pairs))
        counts = np.array(
            [
                n_truth,
                n_tracks,
                matches,
                n_truth - matches,
                n_tracks - matches,
                switches,
                fragments,
                1,
            ],
            dtype=np.int64,
        )
        self._totals += counts
        self._distance_sum += dsum
        if self.keep_frames:
            self._rows.append((pts.scan_index, float(pts.stamp), *counts[:7].tolist(), dsum))

    @property
    def last_pairs(self) -> Mapping[int, int]:
        """Truth id -> track id of the pairs made in the frame accumulated last (kept or
        newly assigned; empty before the first frame), read-only."""
        return MappingProxyType(self._pairs)

    def result(self) -> ClearMotResult:
        """CLEAR MOT over the frames accumulated so far."""
        n_truth, n_tracks, matches, misses, fps, switches, frags, frames = (
            int(v) for v in self._totals
        )
        return ClearMotResult(
            mota=1.0 - (misses + fps + switches) / n_truth if n_truth else math.nan,
            motp=self._distance_sum / matches if matches else math.nan,
            matches=matches,
            misses=misses,
            false_positives=fps,
            id_switches=switches,
            fragmentations=frags,
            num_truth=n_truth,
            num_tracks=n_tracks,
            num_frames=frames,
            recall=matches / n_truth if n_truth else math.nan,
            precision=matches / n_tracks if n_tracks else math.nan,
            distance_sum=self._distance_sum,
            gate=self.params.gate,
        )

    def frames(self) -> FrameTable:
        """Per-frame counts: columns :data:`CLEAR_MOT_COLUMNS`."""
        if not self.keep_frames:
            raise frames_not_kept("ClearMot")
        return FrameTable(CLEAR_MOT_COLUMNS, tuple(self._rows))
