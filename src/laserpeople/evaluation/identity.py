"""Identity measures IDF1, IDP, IDR (Ristani et al., "Performance measures and a data set for
multi-target, multi-camera tracking", ECCV workshops 2016).

Whole trajectories are matched once, one track to at most one person, so that the number of
frames in which a matched pair is within the gate (IDTP) is as large as possible. This is
the same matching as Ristani's min-cost bipartite matching with the dummy nodes: a pair's
cost there is (frames of the person) + (frames of the track) - 2 x (its frames within the
gate), unmatched people and tracks cost their own frames, so the total cost is
(all person frames) + (all track frames) - 2 IDTP.

IDFN = person frames - IDTP, IDFP = track frames - IDTP,
IDF1 = 2 IDTP / (2 IDTP + IDFP + IDFN), IDP = IDTP / (IDTP + IDFP), IDR = IDTP / (IDTP + IDFN).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from laserpeople.evaluation.detail import FrameTable, frames_not_kept
from laserpeople.evaluation.matching import frame_points
from laserpeople.evaluation.pair_sums import PairSums
from laserpeople.evaluation.params import EvaluationParams
from laserpeople.tracks import Tracks
from laserpeople.truth import TruthFrame

IDENTITY_COLUMNS = ("scan", "stamp", "num_truth", "num_tracks", "idtp")


@dataclass(frozen=True)
class IdentityResult:
    """IDF1 and its parts over all scored frames.

    Attributes:
        idf1: Identity F1 score (NaN when there was neither a person nor a track).
        idp: Identity precision (NaN without tracks).
        idr: Identity recall (NaN without people).
        idtp: Person frames covered by the person's matched track within the gate.
        idfp: Track frames not counted in IDTP.
        idfn: Person frames not counted in IDTP.
        num_truth: People summed over frames.
        num_tracks: Tracks summed over frames.
        matched: The trajectory matching, as (track id, person id) pairs.
        gate: Matching gate used [m].
    """

    idf1: float
    idp: float
    idr: float
    idtp: int
    idfp: int
    idfn: int
    num_truth: int
    num_tracks: int
    matched: tuple[tuple[int, int], ...]
    gate: float


class IdentityF1:
    """Accumulates what IDF1 needs: per (track, person) pair, the frames within the gate.

    Memory is one number per pair of ids ever seen, whatever the recording length.
    """

    def __init__(self, params: EvaluationParams | None = None, *, keep_frames: bool = True) -> None:
        self.params = params or EvaluationParams()
        self.keep_frames = keep_frames
        self._within = PairSums()
        self._num_truth = 0
        self._num_tracks = 0
        # Per frame: scan, stamp, truth and track column indices of the pairs within the gate.
        self._frame_pairs: list[tuple[int, float, int, int, np.ndarray, np.ndarray]] = []

    def accumulate(self, truth_frame: TruthFrame, tracks: Tracks | None) -> None:
        """Count the pairs of one frame that are within the gate."""
        pts = frame_points(truth_frame, tracks, self.params.kind)
        within = (pts.distances <= self.params.gate).T.astype(np.float64)  # (T, G)
        r, c = self._within.add(pts.track_ids, pts.truth_ids, within)
        self._num_truth += len(pts.truth_ids)
        self._num_tracks += len(pts.track_ids)
        if self.keep_frames:
            t_local, g_local = np.nonzero(within)
            self._frame_pairs.append(
                (
                    pts.scan_index,
                    float(pts.stamp),
                    len(pts.truth_ids),
                    len(pts.track_ids),
                    r[t_local].astype(np.int32),
                    c[g_local].astype(np.int32),
                )
            )

    def result(self) -> IdentityResult:
        """IDF1 over the frames accumulated so far (solves the trajectory matching)."""
        matching = self._within.matching()
        idtp = round(matching.total)
        total = self._num_truth + self._num_tracks
        return IdentityResult(
            idf1=2.0 * idtp / total if total else math.nan,
            idp=idtp / self._num_tracks if self._num_tracks else math.nan,
            idr=idtp / self._num_truth if self._num_truth else math.nan,
            idtp=idtp,
            idfp=self._num_tracks - idtp,
            idfn=self._num_truth - idtp,
            num_truth=self._num_truth,
            num_tracks=self._num_tracks,
            matched=matching.id_pairs,
            gate=self.params.gate,
        )

    def frames(self) -> FrameTable:
        """Per frame: people, tracks and IDTP under the final trajectory matching."""
        if not self.keep_frames:
            raise frames_not_kept("IdentityF1")
        partner = self._within.matching().partner()
        out = []
        for scan, stamp, n_truth, n_tracks, t_idx, g_idx in self._frame_pairs:
            idtp = int(np.count_nonzero(partner[t_idx] == g_idx)) if t_idx.size else 0
            out.append((scan, stamp, n_truth, n_tracks, idtp))
        return FrameTable(IDENTITY_COLUMNS, tuple(out))
