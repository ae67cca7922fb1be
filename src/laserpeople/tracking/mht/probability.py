"""Hypothesis probabilities of the MHT with the labels detected / occluded / deleted for
tracks and matched / new / false alarm for measurements (000 eqs. 2-15), in log space.

After Reid's cancellations (000 eqs. 11-14) a child hypothesis has the probability (eq. 15)

    p(child) = eta'' * prod_i N(z_i)^delta_i * prod_tracks p_label|class * lambda_new^N_new
               * lambda_fal^N_fal * p(parent)

where each track contributes the probability of its label conditioned on its class (free or
approved, eqs. 9-10) and eta'' depends only on the number of measurements M_k, so it is the
same for all children of one generation and is removed by normalising. The explicit
combinatorial forms (eqs. 11-13) are here too, to check the cancellation (eq. 14).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

DETECTED, OCCLUDED, DELETED = 0, 1, 2
"""Track labels (columns of the (T, 3) label log-probability arrays)."""
TRACK_LABELS = ("detected", "occluded", "deleted")

MATCHED, NEW, FALSE_ALARM = 0, 1, 2
"""Measurement labels."""
MEASUREMENT_LABELS = ("matched", "new", "false_alarm")


@dataclass(frozen=True)
class LabelProbabilities:
    """Probabilities of the three track labels for one class of track (they sum to 1)."""

    p_det: float
    p_occ: float
    p_del: float

    def __post_init__(self) -> None:
        values = (self.p_det, self.p_occ, self.p_del)
        if any(not 0.0 < v < 1.0 for v in values):
            raise ValueError(f"label probabilities must be in (0, 1), got {values}")
        if abs(sum(values) - 1.0) > 1e-6:
            raise ValueError(
                f"p_det + p_occ + p_del must be 1 (Arras et al. 2008 eq. 8), got {sum(values)}"
            )

    def log(self) -> FloatArray:
        """``log([p_det, p_occ, p_del])`` (3,)."""
        return np.log(np.array([self.p_det, self.p_occ, self.p_del]))


def log_child_weight(
    parent_log_weight: float,
    matched_loglik: Sequence[float],
    track_labels: Sequence[int],
    track_label_log_probs: FloatArray,
    n_new: int,
    n_false_alarm: int,
    log_lambda_new: float,
    log_lambda_fal: float,
) -> float:
    """log of the unnormalised 000 eq. 15 for one child hypothesis.

    Args:
        parent_log_weight: log p(parent).
        matched_loglik: log N(z_i; z_hat, S) of every matched measurement.
        track_labels: Label (DETECTED/OCCLUDED/DELETED) of every track of the parent.
        track_label_log_probs: (T, 3) log label probabilities of each track given its class.
        n_new: Measurements labelled new track.
        n_false_alarm: Measurements labelled false alarm.
        log_lambda_new: log of the new-track density [1/m^2].
        log_lambda_fal: log of the false-alarm density [1/m^2].
    """
    labels = np.asarray(track_labels, dtype=np.intp)
    label_term = float(track_label_log_probs[np.arange(labels.size), labels].sum())
    return (
        parent_log_weight
        + float(np.sum(matched_loglik))
        + label_term
        + n_new * log_lambda_new
        + n_false_alarm * log_lambda_fal
    )


def normalise(log_weights: FloatArray) -> FloatArray:
    """Log weights shifted so that their probabilities sum to 1 (the eta'' of eq. 15)."""
    w = np.asarray(log_weights, dtype=np.float64)
    if w.size == 0:
        return w
    from scipy.special import logsumexp  # here: scipy.special costs a start-up of 0.2 s

    return w - float(logsumexp(w))


def _poisson(n: int, mean: float) -> float:
    return math.exp(-mean) * mean**n / math.factorial(n)


def assignment_set_probability_combinatorial(
    counts_free: tuple[int, int, int],
    counts_approved: tuple[int, int, int],
    n_new: int,
    n_fal: int,
    free: LabelProbabilities,
    approved: LabelProbabilities,
    lambda_new: float,
    lambda_fal: float,
    volume: float,
) -> float:
    """p(Psi_j(k) | parent) from its three factors (000 eqs. 11, 12, 13), without cancelling.

    ``counts_*`` are (N_det, N_occ, N_del) of the free and the approved tracks.
    """
    ndf, nof, nxf = counts_free
    nda, noa, nxa = counts_approved
    nf, na = sum(counts_free), sum(counts_approved)
    m = ndf + nda + n_new + n_fal
    f = math.factorial
    eq11 = f(nf) / (f(ndf) * f(nof) * f(nxf)) * free.p_det**ndf * free.p_occ**nof * free.p_del**nxf
    eq11 *= (
        f(na)
        / (f(nda) * f(noa) * f(nxa))
        * approved.p_det**nda
        * approved.p_occ**noa
        * approved.p_del**nxa
    )
    eq11 *= _poisson(n_fal, lambda_fal * volume) * _poisson(n_new, lambda_new * volume)
    eq12 = (
        math.comb(m, ndf)
        * math.comb(m - ndf, nda)
        * math.comb(m - ndf - nda, n_new)
        * math.comb(m - ndf - nda - n_new, n_fal)
    )
    eq13 = (
        f(nf)
        // f(nf - ndf)
        * math.comb(nf - ndf, nof)
        * math.comb(nf - ndf - nof, nxf)
        * f(na)
        // f(na - nda)
        * math.comb(na - nda, noa)
        * math.comb(na - nda - noa, nxa)
    )
    return eq11 / (eq12 * eq13)


def assignment_set_probability_eq14(
    counts_free: tuple[int, int, int],
    counts_approved: tuple[int, int, int],
    n_new: int,
    n_fal: int,
    free: LabelProbabilities,
    approved: LabelProbabilities,
    lambda_new: float,
    lambda_fal: float,
    volume: float,
) -> float:
    """p(Psi_j(k) | parent) by 000 eq. 14, with its constant written out:
    eta' = exp(-(lambda_new + lambda_fal) V) / M_k! (depends on M_k only)."""
    ndf, nof, nxf = counts_free
    nda, noa, nxa = counts_approved
    m = ndf + nda + n_new + n_fal
    eta = math.exp(-(lambda_new + lambda_fal) * volume) / math.factorial(m)
    return (
        eta
        * free.p_det**ndf
        * free.p_occ**nof
        * free.p_del**nxf
        * approved.p_det**nda
        * approved.p_occ**noa
        * approved.p_del**nxa
        * lambda_new**n_new
        * lambda_fal**n_fal
        * volume ** (n_new + n_fal)
    )
