"""HOTA: Higher Order Tracking Accuracy (Luiten et al., "HOTA: A Higher Order Metric for
Evaluating Multi-Object Tracking", IJCV 2021), for people as 2D points in metres.

Similarity of a person at p and a track at q (both world frame, metres)::

    S(p, q) = max(0, 1 - |p - q| / d0)

with d0 = :attr:`HotaParams.zero_distance` = 1.5 m by default: twice the project's 0.75 m
CLEAR MOT gate, so that alpha = 0.5 is that gate (a pair at distance d is a match for every
alpha <= 1 - d / d0; at d >= 1.5 m for none). This is TrackEval's Euclidean similarity for
point trackers, whose MOT15_3D setting pairs zero_distance 2 m with a 1 m gate in the same
way; it takes the place of the boxes' IoU.

For each alpha in 0.05, 0.10, ..., 0.95 (19 values) and each frame, people and tracks are
matched one to one; a matched pair with S >= alpha is a true positive (TP), people and
tracks left are FN and FP. With, per TP pair c of person g and track t, TPA(c) = frames in
which g and t are a TP pair, FNA(c) = frames of g - TPA(c), FPA(c) = frames of t - TPA(c):

    DetA  = |TP| / (|TP| + |FN| + |FP|)
    AssA  = (1 / |TP|) sum_c TPA(c) / (TPA(c) + FNA(c) + FPA(c))
    LocA  = (1 / |TP|) sum_c S(c)
    HOTA_alpha = sqrt(DetA_alpha * AssA_alpha)

and HOTA, DetA, AssA, LocA are the means over the 19 alphas (paper eqs. 3-10). The
matching within a frame follows the reference implementation (TrackEval's ``HOTA``
metric), made once per frame for all alphas: it maximises the sum of A_max(g, t) x S(g, t),
where A_max is the pair's global alignment score, sum over frames of
S / (sum_row S + sum_col S - S), divided by (frames of g + frames of t - that sum), so that
pairs who are together throughout are preferred. Recordings are pooled as TrackEval
combines sequences: TP, FN and FP are summed, AssA, AssRe, AssPr and LocA are averaged
weighted by each recording's TP (:func:`combine_hota`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment

from laserpeople.config import param
from laserpeople.errors import ConfigError
from laserpeople.evaluation.detail import FrameTable, frames_not_kept
from laserpeople.evaluation.matching import frame_points
from laserpeople.evaluation.pair_sums import IdIndex
from laserpeople.tracks import Tracks
from laserpeople.truth import TruthFrame

EPS = float(np.finfo(float).eps)

HOTA_COLUMNS = ("scan", "stamp", "num_truth", "num_tracks", "tp_alpha_050", "similarity_050")
"""Per-frame columns: people, tracks, TP pairs at alpha = 0.5 and their summed similarity."""


@dataclass(frozen=True)
class HotaParams:
    """How HOTA scores people as 2D points (see the module docstring)."""

    config_section = "hota"

    zero_distance: float = param(
        1.5,
        "assumption: 2 x the 0.75 m CLEAR MOT gate, so alpha = 0.5 is the gate (as TrackEval's "
        "MOT15_3D; docs/batch.md)",
        "distance d0 at which the similarity S = max(0, 1 - d / d0) reaches 0",
        "m",
    )
    alphas: tuple[float, ...] = param(
        tuple(round(0.05 * k, 2) for k in range(1, 20)),
        "Luiten et al. 2021 Sec. 5 (0.05, 0.10, ..., 0.95)",
        "similarity thresholds alpha that HOTA, DetA, AssA and LocA are averaged over",
    )
    kind: str = param(
        "person",
        "assumption: people are what the benchmarks label",
        "track kind compared with the people of the truth",
    )

    def __post_init__(self) -> None:
        if not (self.zero_distance > 0.0):
            raise ConfigError(f"hota zero_distance must be positive, got {self.zero_distance}")
        if not self.alphas or not all(0.0 < a <= 1.0 for a in self.alphas):
            raise ConfigError(f"hota alphas must lie in (0, 1], got {self.alphas}")


@dataclass(frozen=True)
class HotaResult:
    """HOTA and its parts, means over alpha, with the per-alpha values.

    Attributes:
        hota: Mean over alpha of sqrt(DetA_alpha AssA_alpha).
        deta: Detection accuracy.
        assa: Association accuracy.
        loca: Localisation accuracy (mean similarity of TP pairs).
        deta_re: Detection recall TP / (TP + FN).
        deta_pr: Detection precision TP / (TP + FP).
        assa_re: Association recall.
        assa_pr: Association precision.
        alphas: The thresholds.
        hota_alpha, deta_alpha, assa_alpha, loca_alpha: Per alpha.
        assre_alpha, asspr_alpha: Association recall and precision per alpha.
        tp, fn, fp: Counts per alpha.
        zero_distance: d0 [m].
    """

    hota: float
    deta: float
    assa: float
    loca: float
    deta_re: float
    deta_pr: float
    assa_re: float
    assa_pr: float
    alphas: tuple[float, ...]
    hota_alpha: tuple[float, ...]
    deta_alpha: tuple[float, ...]
    assa_alpha: tuple[float, ...]
    loca_alpha: tuple[float, ...]
    assre_alpha: tuple[float, ...]
    asspr_alpha: tuple[float, ...]
    tp: tuple[int, ...]
    fn: tuple[int, ...]
    fp: tuple[int, ...]
    zero_distance: float


def similarity(distances: NDArray[np.float64], zero_distance: float) -> NDArray[np.float64]:
    """S = max(0, 1 - d / d0) of distances [m] (any shape)."""
    return np.maximum(0.0, 1.0 - np.asarray(distances, dtype=np.float64) / zero_distance)


@dataclass(frozen=True, eq=False)
class _Frame:
    scan: int
    stamp: float
    truth: NDArray[np.int64]  # dense person indices (G,)
    tracks: NDArray[np.int64]  # dense track indices (T,)
    sim: NDArray[np.float64]  # (G, T)


class Hota:
    """Accumulates HOTA frame by frame (a :class:`~laserpeople.evaluation.protocol.Metric`).

    HOTA's matching needs every frame's similarities for the global alignment score, so
    memory grows with the recording: one (people x tracks) matrix per scored frame.
    """

    def __init__(self, params: HotaParams | None = None, *, keep_frames: bool = True) -> None:
        self.params = params or HotaParams()
        self.keep_frames = keep_frames
        self._truth_index = IdIndex()
        self._track_index = IdIndex()
        self._frames: list[_Frame] = []

    def accumulate(self, truth_frame: TruthFrame, tracks: Tracks | None) -> None:
        """Store one frame's ids and similarities."""
        pts = frame_points(truth_frame, tracks, self.params.kind)
        self._frames.append(
            _Frame(
                pts.scan_index,
                float(pts.stamp),
                self._truth_index.indices(pts.truth_ids),
                self._track_index.indices(pts.track_ids),
                similarity(pts.distances, self.params.zero_distance),
            )
        )

    def _matches(self) -> list[tuple[NDArray[np.int64], NDArray[np.int64]]]:
        """Per frame, the matched (row, column) pairs (before the alpha threshold)."""
        n_g, n_t = len(self._truth_index), len(self._track_index)
        potential = np.zeros((n_g, n_t))
        g_count = np.zeros(n_g)
        t_count = np.zeros(n_t)
        for f in self._frames:
            if f.sim.size:
                denom = f.sim.sum(0)[None, :] + f.sim.sum(1)[:, None] - f.sim
                ratio = np.zeros_like(f.sim)
                ok = denom > EPS
                ratio[ok] = f.sim[ok] / denom[ok]
                potential[f.truth[:, None], f.tracks[None, :]] += ratio
            g_count[f.truth] += 1
            t_count[f.tracks] += 1
        align = potential / np.maximum(g_count[:, None] + t_count[None, :] - potential, EPS)
        out = []
        for f in self._frames:
            if not f.sim.size:
                empty = np.empty(0, dtype=np.int64)
                out.append((empty, empty))
                continue
            score = align[f.truth[:, None], f.tracks[None, :]] * f.sim
            rows, cols = linear_sum_assignment(-score)
            out.append((rows.astype(np.int64), cols.astype(np.int64)))
        return out

    def result(self) -> HotaResult:
        """HOTA over the frames accumulated so far."""
        alphas = np.asarray(self.params.alphas, dtype=np.float64)
        n_a, n_g, n_t = len(alphas), len(self._truth_index), len(self._track_index)
        tp = np.zeros(n_a, dtype=np.int64)
        fn = np.zeros(n_a, dtype=np.int64)
        fp = np.zeros(n_a, dtype=np.int64)
        loc = np.zeros(n_a)
        pair_counts = np.zeros((n_a, n_g, n_t))
        g_count = np.zeros(n_g)
        t_count = np.zeros(n_t)
        for f, (rows, cols) in zip(self._frames, self._matches(), strict=True):
            g_count[f.truth] += 1
            t_count[f.tracks] += 1
            s = f.sim[rows, cols]
            for a, alpha in enumerate(alphas):
                keep = s >= alpha - EPS
                n = int(keep.sum())
                tp[a] += n
                fn[a] += len(f.truth) - n
                fp[a] += len(f.tracks) - n
                loc[a] += float(s[keep].sum())
                pair_counts[a, f.truth[rows[keep]], f.tracks[cols[keep]]] += 1
        union = g_count[:, None] + t_count[None, :]
        assa = np.zeros(n_a)
        assre = np.zeros(n_a)
        asspr = np.zeros(n_a)
        for a in range(n_a):
            m = pair_counts[a]
            assa[a] = np.sum(m * m / np.maximum(1.0, union - m)) / max(1, tp[a])
            assre[a] = np.sum(m * m / np.maximum(1.0, g_count[:, None])) / max(1, tp[a])
            asspr[a] = np.sum(m * m / np.maximum(1.0, t_count[None, :])) / max(1, tp[a])
        loca = np.where(tp > 0, loc / np.maximum(tp, 1), 1.0)
        return _finish(alphas, tp, fn, fp, assa, assre, asspr, loca, self.params.zero_distance)

    def frames(self) -> FrameTable:
        """Per frame: people, tracks, and at alpha = 0.5 the TP pairs and their similarity."""
        if not self.keep_frames:
            raise frames_not_kept("Hota")
        rows = []
        for f, (r, c) in zip(self._frames, self._matches(), strict=True):
            s = f.sim[r, c]
            keep = s >= 0.5 - EPS
            rows.append(
                (
                    f.scan,
                    f.stamp,
                    len(f.truth),
                    len(f.tracks),
                    int(keep.sum()),
                    float(s[keep].sum()),
                )
            )
        return FrameTable(HOTA_COLUMNS, tuple(rows))


def _finish(
    alphas: NDArray[np.float64],
    tp: NDArray[np.int64],
    fn: NDArray[np.int64],
    fp: NDArray[np.int64],
    assa: NDArray[np.float64],
    assre: NDArray[np.float64],
    asspr: NDArray[np.float64],
    loca: NDArray[np.float64],
    zero_distance: float,
) -> HotaResult:
    """The means and per-alpha tuples from the per-alpha counts and association sums."""
    deta = tp / np.maximum(1, tp + fn + fp)
    hota = np.sqrt(deta * assa)
    return HotaResult(
        hota=float(hota.mean()),
        deta=float(deta.mean()),
        assa=float(assa.mean()),
        loca=float(loca.mean()),
        deta_re=float((tp / np.maximum(1, tp + fn)).mean()),
        deta_pr=float((tp / np.maximum(1, tp + fp)).mean()),
        assa_re=float(assre.mean()),
        assa_pr=float(asspr.mean()),
        alphas=tuple(float(a) for a in alphas),
        hota_alpha=tuple(float(v) for v in hota),
        deta_alpha=tuple(float(v) for v in deta),
        assa_alpha=tuple(float(v) for v in assa),
        loca_alpha=tuple(float(v) for v in loca),
        assre_alpha=tuple(float(v) for v in assre),
        asspr_alpha=tuple(float(v) for v in asspr),
        tp=tuple(int(v) for v in tp),
        fn=tuple(int(v) for v in fn),
        fp=tuple(int(v) for v in fp),
        zero_distance=zero_distance,
    )


def combine_hota(results: Sequence[HotaResult]) -> HotaResult:
    """HOTA over several recordings (TrackEval's combination of sequences): TP, FN, FP
    summed per alpha; AssA, AssRe, AssPr and LocA averaged weighted by TP (LocA is 1 at an
    alpha with no TP at all, as for one recording).

    Raises:
        ValueError: No results, or results of different alphas or zero distances.
    """
    if not results:
        raise ValueError("no HOTA results to combine")
    first = results[0]
    if any(r.alphas != first.alphas or r.zero_distance != first.zero_distance for r in results):
        raise ValueError("HOTA results of different alphas or zero distances")
    tp = np.sum([r.tp for r in results], axis=0).astype(np.int64)
    fn = np.sum([r.fn for r in results], axis=0).astype(np.int64)
    fp = np.sum([r.fp for r in results], axis=0).astype(np.int64)

    def weighted(name: str) -> NDArray[np.float64]:
        values = np.array([getattr(r, name) for r in results])
        weights = np.array([r.tp for r in results], dtype=np.float64)
        return np.asarray(
            (values * weights).sum(axis=0) / np.maximum(1e-10, weights.sum(axis=0)),
            dtype=np.float64,
        )

    return _finish(
        np.asarray(first.alphas),
        tp,
        fn,
        fp,
        weighted("assa_alpha"),
        weighted("assre_alpha"),
        weighted("asspr_alpha"),
        # An alpha without a TP in any recording counts LocA = 1, as in one recording and
        # in TrackEval's combination (max(1e-10, sum) / max(1e-10, TP)).
        np.where(tp > 0, weighted("loca_alpha"), 1.0),
        first.zero_distance,
    )


def hota_summary(result: HotaResult) -> dict[str, float]:
    """The headline numbers (``hota``, ``deta``, ``assa``, ``loca``), NaN-free."""
    return {
        k: (v if math.isfinite(v) else 0.0)
        for k, v in (
            ("hota", result.hota),
            ("deta", result.deta),
            ("assa", result.assa),
            ("loca", result.loca),
        )
    }


__all__ = [
    "HOTA_COLUMNS",
    "Hota",
    "HotaParams",
    "HotaResult",
    "combine_hota",
    "hota_summary",
    "similarity",
]
