"""The adapted MOTP of 004 (Schenk et al., Sec. 3.2, eqs. 10-11) for point-like tracks.

Matching value of a track at distance d [m] from a person (eq. 10)::

    m = min(1, h / d^3),   h = 0.008 m^3  ->  m = 1 for d <= 0.2 m, 0.125 at 0.4 m, 0.008 at 1 m

Every track trajectory T is matched to at most one ground-truth trajectory G and vice versa,
once for the whole sequence ("the best suitable" one). We take the matching that maximises
the summed matching value over the frames in which both exist (Hungarian algorithm on the
(tracks x people) sums). People left without a track get a virtual track with m = 0, tracks
left without a person count m = 0, and a person's matched track that is absent in a frame
(a gap) gives m = 0 in that frame. Then (eq. 11)::

    MOTP = sum_i sum_{j in G_i} m_ij / sum_i max(N_i^T, N_i^G)

over the frames i. 004 Fig. 4: one track on two people gives 1/2, two tracks on one
person 1/2, three tracks on two people 2/3, and an exact result 1. Because matching is per
trajectory, a track that swaps from person A to person B is penalised by its distance to A.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.evaluation.detail import FrameTable, frames_not_kept
from laserpeople.evaluation.matching import frame_points
from laserpeople.evaluation.pair_sums import PairSums
from laserpeople.evaluation.params import EvaluationParams
from laserpeople.tracks import Tracks
from laserpeople.truth import TruthFrame

SCHENK_COLUMNS = ("scan", "stamp", "schenk_m_sum", "schenk_max_count")

DETAIL_MIN_M = 1e-6
"""Smallest matching value kept for the per-frame table (d <= 20 m at h = 0.008). The
sequence-wide MOTP uses every pair; only the per-frame column leaves out the smaller values
(each below 1e-6) of pairs farther apart."""


def matching_value(distance: NDArray[np.float64], h: float = 0.008) -> NDArray[np.float64]:
    """004 eq. 10: m = min(1, h / d^3) for distances ``d`` [m] (any shape); m(0) = 1."""
    d = np.asarray(distance, dtype=np.float64)
    with np.errstate(divide="ignore"):
        return np.minimum(1.0, h / d**3)


@dataclass(frozen=True)
class SchenkMotpResult:
    """004's adapted MOTP over all scored frames.

    Attributes:
        motp: eq. 11, in [0, 1] (NaN when no frame had a person or a track).
        numerator: Summed matching values of the matched pairs.
        denominator: Sum over frames of max(tracks, people).
        matched: The trajectory matching, as (track id, person id) pairs.
        h: The threshold h of eq. 10 [m^3].
    """

    motp: float
    numerator: float
    denominator: int
    matched: tuple[tuple[int, int], ...]
    h: float


class SchenkMotp:
    """Accumulates 004's MOTP: per (track, person) pair the summed matching value, and per
    frame max(N^T, N^G)."""

    def __init__(self, params: EvaluationParams | None = None, *, keep_frames: bool = True) -> None:
        self.params = params or EvaluationParams()
        self.keep_frames = keep_frames
        self._values = PairSums()
        self._denominator = 0
        self._frame_pairs: list[tuple[int, float, int, np.ndarray, np.ndarray, np.ndarray]] = []

    def accumulate(self, truth_frame: TruthFrame, tracks: Tracks | None) -> None:
        """Add the matching values of one frame."""
        pts = frame_points(truth_frame, tracks, self.params.kind)
        m = matching_value(pts.distances, self.params.schenk_h).T  # (T, G)
        r, c = self._values.add(pts.track_ids, pts.truth_ids, m)
        count = max(len(pts.track_ids), len(pts.truth_ids))
        self._denominator += count
        if self.keep_frames:
            t_local, g_local = np.nonzero(m >= DETAIL_MIN_M)
            self._frame_pairs.append(
                (
                    pts.scan_index,
                    float(pts.stamp),
                    count,
                    r[t_local].astype(np.int32),
                    c[g_local].astype(np.int32),
                    m[t_local, g_local],
                )
            )

    def result(self) -> SchenkMotpResult:
        """eq. 11 over the frames accumulated so far (solves the trajectory matching)."""
        matching = self._values.matching()
        numerator = matching.total
        return SchenkMotpResult(
            motp=numerator / self._denominator if self._denominator else math.nan,
            numerator=numerator,
            denominator=self._denominator,
            matched=matching.id_pairs,
            h=self.params.schenk_h,
        )

    def frames(self) -> FrameTable:
        """Per frame: the summed matching values under the final matching (pairs with
        m < :data:`DETAIL_MIN_M` left out) and max(N^T, N^G)."""
        if not self.keep_frames:
            raise frames_not_kept("SchenkMotp")
        partner = self._values.matching().partner()
        out = []
        for scan, stamp, count, t_idx, g_idx, m in self._frame_pairs:
            value = float(m[partner[t_idx] == g_idx].sum()) if t_idx.size else 0.0
            out.append((scan, stamp, value, count))
        return FrameTable(SCHENK_COLUMNS, tuple(out))
