"""The Viterbi-based algorithm (VBA) of 002 Sec. 2: one step over a cluster's estimates, and
how its paths' scores and its people's unseen paths are carried from step to step."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracking import kalman

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True, eq=False)
class ViterbiStep:
    """The result of one VBA step (:func:`viterbi_step`) on M measurements and E estimates.

    Attributes:
        selected: (M,) bool, measurements inside at least one estimate's gate.
        predecessor: (S,) index of the old estimate each selected measurement continues.
        means: New estimates (S, 4), the predecessors updated with their measurements.
        covs: Their covariances (S, 4, 4).
        scores: Path log-likelihoods (S,), shifted so that the best is 0.
    """

    selected: NDArray[np.bool_]
    predecessor: IntArray
    means: FloatArray
    covs: FloatArray
    scores: FloatArray


def gate_loglik(
    means: FloatArray, covs: FloatArray, z: FloatArray, point_var: float, gate: float, cap: float
) -> tuple[NDArray[np.bool_], FloatArray]:
    """Gate membership and log N(z_m; H x_e, H P_e H^T + point_var I), both (E, M), for
    one measurement noise shared by all measurements (cheaper than
    :func:`kalman.mahalanobis_and_loglik`, which takes one covariance per measurement)."""
    a = covs[:, 0, 0] + point_var
    b = covs[:, 0, 1]
    d = covs[:, 1, 1] + point_var
    det = a * d - b * b
    vx = z[None, :, 0] - means[:, 0, None]
    vy = z[None, :, 1] - means[:, 1, None]
    d2 = (d[:, None] * vx * vx - 2.0 * b[:, None] * vx * vy + a[:, None] * vy * vy) / det[:, None]
    inside = (d2 <= gate) & (vx * vx + vy * vy <= cap * cap)
    loglik = -0.5 * d2 - kalman.LOG_2PI - 0.5 * np.log(det)[:, None]
    return inside, loglik


def viterbi_step(
    pred_means: FloatArray,
    pred_covs: FloatArray,
    scores: FloatArray,
    z: FloatArray,
    point_var: float,
    gate: float,
    max_gate_distance: float,
    origin: IntArray | None = None,
) -> ViterbiStep:
    """One step of the Viterbi-based algorithm (002 Sec. 2; Kräußling et al. 2004a).

    Every old estimate e (predicted to ``pred_means[e]``) has a validation gate; a
    measurement in at least one gate is selected, and its new estimate continues the old
    estimate with the best path score ``scores[e] + log N(z; H x_e, H P_e H^T + R)`` among
    the estimates gating it (the Viterbi recursion), updated with the measurement.

    Args:
        pred_means: Predicted estimates (E, 4).
        pred_covs: Their covariances (E, 4, 4).
        scores: Path log-likelihoods of the old estimates (E,).
        z: Measurements (M, 2) [m].
        point_var: Variance of one measurement about the estimate, R = point_var * I [m^2].
        gate: Squared Mahalanobis radius of a gate.
        max_gate_distance: Euclidean cap on a gate [m].
        origin: The person (E,) each estimate's path started from, or None (002). With
            it, a measurement first picks its person (:func:`person_first`), then the
            best of that person's estimates (``person_mixture``).
    """
    z = np.asarray(z, dtype=np.float64).reshape(-1, 2)
    m = z.shape[0]
    r = np.broadcast_to(np.eye(2) * point_var, (m, 2, 2))
    inside, loglik = gate_loglik(pred_means, pred_covs, z, point_var, gate, max_gate_distance)
    selected: NDArray[np.bool_] = np.asarray(inside.any(axis=0), dtype=bool)
    total = np.where(inside, np.asarray(scores, dtype=np.float64)[:, None] + loglik, -np.inf)
    total = total[:, selected]
    if origin is not None and total.size:
        total = person_first(total, origin)
    pred = np.argmax(total, axis=0).astype(np.int64)
    best = total[pred, np.arange(pred.size)]
    zs = z[selected]
    means, covs = kalman.update_batch(pred_means[pred], pred_covs[pred], zs, r[: zs.shape[0]])
    if best.size:
        best = best - best.max()
    return ViterbiStep(selected, pred, means, covs, best)


def person_first(total: FloatArray, origin: IntArray) -> FloatArray:
    """Path scores ``total`` (E, S) of E old estimates for S measurements (path score plus
    transition log-likelihood, -inf outside a gate) with every estimate that is not of the
    measurement's person set to -inf (see ``person_mixture``).

    A measurement's person is argmax over people p of sum(exp(total[e])) / sqrt(n_p) over
    the n_p paths e of p that gate it: a person with many paths (one per leg point) gets
    no more chances to take a point than one with few (the sum alone), yet a person whose
    two legs both gate a point is not diluted by its other leg (the mean). ``origin`` (E,)
    gives the person each path started from."""
    _, inv = np.unique(origin, return_inverse=True)
    n_people = int(inv.max()) + 1
    w = np.exp(total - np.max(total, axis=0, keepdims=True))  # (E, S); 0 outside gates
    mix = np.zeros((n_people, total.shape[1]))
    cnt = np.zeros_like(mix)
    np.add.at(mix, inv, w)
    np.add.at(cnt, inv, np.isfinite(total).astype(np.float64))
    best = np.argmax(mix / np.sqrt(np.maximum(cnt, 1.0)), axis=0)  # (S,) each one's person
    return np.where(inv[:, None] == best[None, :], total, -np.inf)


def per_person_scores(scores: FloatArray, origin: IntArray) -> FloatArray:
    """Path scores (E,) shifted so that the best path of every person (``origin`` (E,),
    the person each path started from) scores 0: paths compete on their whole history
    only with the paths of the same person, and between people only the last step's fit
    counts."""
    s = np.asarray(scores, dtype=np.float64)
    if s.size == 0:
        return s.copy()
    _, inv = np.unique(origin, return_inverse=True)
    best = np.full(int(inv.max()) + 1, -np.inf)
    np.maximum.at(best, inv, s)
    return s - best[inv]


Estimates = tuple[FloatArray, FloatArray, FloatArray, IntArray]
"""A cluster's estimates: means (E, 4), covariances (E, 4, 4), path scores (E,) and the
person each path started from (E,)."""


def coast_people(
    new: Estimates,
    predicted: Estimates,
    continued: dict[int, float],
    times: tuple[float, float],
    max_unseen: float,
) -> Estimates:
    """The estimates ``new`` after a VBA step at ``times[0]`` [s], with the ``predicted``
    estimates (the old ones, predicted to then) of every person none of whose paths the
    step continued appended unchanged, while that person's paths were last continued at
    most ``max_unseen`` [s] ago (see ``coast_people``). Updates ``continued`` (person ->
    when its paths were last continued [s]; a person it lacks, e.g. one counted into the
    cluster, counts from ``times[1]``, the cluster's last scan with measurements)."""
    stamp, before = times
    kept = {int(o) for o in new[3]}
    for o in kept:
        continued[o] = stamp
    old_origin = predicted[3]
    for o in {int(o) for o in old_origin}:
        continued.setdefault(o, before)  # its clock runs from the cluster's last scan
    coast = [
        o for o in sorted({int(o) for o in old_origin} - kept) if stamp - continued[o] <= max_unseen
    ]
    if not coast:
        return new
    sel = np.isin(old_origin, coast)
    means, covs, scores, origin = (
        np.concatenate([a, b[sel]]) for a, b in zip(new, predicted, strict=True)
    )
    return means, covs, scores, origin.astype(np.int64)
