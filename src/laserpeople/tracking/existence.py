"""A person's existence evidence on a moving robot, calibrated from labels.

The person layer (:mod:`laserpeople.tracking.person_tracks`) sums, per scan, the
log-likelihood ratio of what the laser gave a person candidate: "a person" vs "clutter".
With hand probabilities (``p_two``, ``p_one``, ...) one leg counts nothing and a scan
without a leg costs the same at 1 m as at 7 m, where a 0.35 deg scanner misses a walker in
about every other scan. On a moving robot the evidence of a scan is instead one of six
classes (:data:`EVIDENCE_CLASSES`), in one of three ranges from the laser, and its
log-likelihood ratio is read from a table fitted on labelled recordings
(:func:`fit_table`, ``benchmarks/fit_existence.py``):

    llr[r, c] = log (n_person[r, c] + a) / (N_person[r] + C a)
              - log (n_clutter[r, c] + a) / (N_clutter[r] + C a)

with the counts of candidate-scans near a labelled person (within 0.5 m) and far from
every one (beyond 1 m), Laplace smoothing ``a`` and C classes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param

FloatArray = NDArray[np.float64]

EVIDENCE_CLASSES = ("two", "one_moving", "one_strong", "one_medium", "one_weak", "none")
"""Evidence of one scan: both legs (a strong pair or a segment holding both), one leg whose
track moves consistently, one leg by detector margin (above ``score_edges[1]``, between,
below ``score_edges[0]``), no leg."""
TWO_E, MOVING_E, STRONG_E, MEDIUM_E, WEAK_E, NONE_E = range(6)
RANGE_NAMES = ("near", "mid", "far")


@dataclass(frozen=True)
class ExistenceParams:
    """Calibrated existence evidence on a moving robot (``people.existence``)."""

    config_section = "existence"

    calibrated: bool = param(
        True,
        "measured (docs/moving-robot.md): fitted on the real lobby dev recording and the "
        "moving-robot tuning seeds 0-9",
        "on a moving robot tracked in the world frame, a person's per-scan evidence is read "
        "from the fitted table below (by class and range) instead of p_two/p_one/q_*",
    )
    range_edges: tuple[float, ...] = param(
        (3.0, 5.0),
        "assumption: at 0.35 deg a leg has ~8 points at 3 m, ~4 at 5 m",
        "ranges [m] from the laser between the near, mid and far rows",
        "m",
    )
    score_edges: tuple[float, ...] = param(
        (0.3, 0.8),
        "assumption: AdaBoost margins of real legs at 3-7 m were 0.01-1.6",
        "detector margins between the weak, medium and strong one-leg classes",
    )
    llr_near: tuple[float, ...] = param(
        (1.61, 1.61, 0.0, 0.0, 0.0, -1.61),
        "fitted (benchmarks/fit_existence.py)",
        "log-likelihood ratio per evidence class (two, one_moving, one_strong, one_medium, "
        "one_weak, none) nearer than range_edges[0]",
    )
    llr_mid: tuple[float, ...] = param(
        (1.61, 1.61, 0.0, 0.0, 0.0, -1.61),
        "fitted (benchmarks/fit_existence.py)",
        "the same between range_edges[0] and range_edges[1]",
    )
    llr_far: tuple[float, ...] = param(
        (1.61, 1.61, 0.0, 0.0, 0.0, -1.61),
        "fitted (benchmarks/fit_existence.py)",
        "the same beyond range_edges[1]",
    )

    def __post_init__(self) -> None:
        if len(self.range_edges) != 2 or not 0.0 < self.range_edges[0] < self.range_edges[1]:
            raise ValueError("range_edges must be two increasing positive ranges [m]")
        if len(self.score_edges) != 2 or not self.score_edges[0] <= self.score_edges[1]:
            raise ValueError("score_edges must be two non-decreasing detector margins")
        for name in ("llr_near", "llr_mid", "llr_far"):
            row = getattr(self, name)
            if len(row) != len(EVIDENCE_CLASSES) or not all(math.isfinite(v) for v in row):
                raise ValueError(
                    f"{name} must hold {len(EVIDENCE_CLASSES)} finite values, one per class "
                    f"{EVIDENCE_CLASSES}"
                )

    def table(self) -> FloatArray:
        """The log-likelihood ratios (3 ranges, 6 classes)."""
        return np.array([self.llr_near, self.llr_mid, self.llr_far], dtype=np.float64)

    def range_bin(self, distance: float) -> int:
        """Row of a person ``distance`` [m] from the laser: 0 near, 1 mid, 2 far."""
        lo, hi = self.range_edges
        return 0 if distance < lo else (1 if distance < hi else 2)

    def one_leg_class(self, score: float, moving: bool) -> int:
        """Class of a scan with one leg of detector margin ``score`` (NaN: weak)."""
        if moving:
            return MOVING_E
        lo, hi = self.score_edges
        if score > hi:
            return STRONG_E
        return MEDIUM_E if score > lo else WEAK_E


def fit_table(
    person: NDArray[np.int64] | FloatArray,
    clutter: NDArray[np.int64] | FloatArray,
    smoothing: float = 1.0,
) -> FloatArray:
    """Log-likelihood ratios (R, C) from counts (R, C) of candidate-scans per range row and
    evidence class near a labelled person (``person``) and far from every one
    (``clutter``), each row's class frequencies smoothed by ``smoothing`` (Laplace)."""
    p = np.asarray(person, dtype=np.float64) + smoothing
    q = np.asarray(clutter, dtype=np.float64) + smoothing
    if p.shape != q.shape or p.ndim != 2:
        raise ValueError("person and clutter counts must be (ranges, classes) of one shape")
    if smoothing <= 0:
        raise ValueError("smoothing must be positive (a zero count would give an infinite ratio)")
    return np.log(p / p.sum(axis=1, keepdims=True)) - np.log(q / q.sum(axis=1, keepdims=True))
