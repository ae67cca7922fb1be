"""Colour appearance of a person (002 Sec. 2): hue histograms, their online mean and
covariance (002 eqs. 1-5), and the Gaussian log-likelihoods of 002 eqs. 6-8.

A colour measurement ``y`` of one person is the vector of relative frequencies of the hue
of the person's pixels over ``B`` bins (002 assumes these follow a Gaussian with mean
``mu_i`` and covariance ``Sigma_i`` per person). With ``B = 6`` the bins are centred on the
six basic colours of 002 Table 1 (red 0, yellow 60, ..., magenta 300 degrees); finer bins
(any ``B``) split the circle evenly starting at red.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param

FloatArray = NDArray[np.float64]

TABLE1_HUES_DEG: dict[str, float] = {
    "red": 0.0,
    "yellow": 60.0,
    "green": 120.0,
    "cyan": 180.0,
    "blue": 240.0,
    "magenta": 300.0,
}
"""The six basic colours and their hue [deg] (002 Table 1)."""

LOG_2PI = math.log(2.0 * math.pi)


@dataclass(frozen=True)
class AppearanceParams:
    """How colour observations become measurements and likelihoods."""

    config_section = "appearance"

    bins: int = param(
        6, "002 Table 1 (six basic colours); finer bins allowed", "hue histogram bins"
    )
    min_saturation: float = param(
        0.2,
        "assumption: hue is undefined for grey pixels (HSV, Gonzalez & Woods)",
        "pixels with a lower saturation are ignored",
    )
    min_value: float = param(
        0.15, "assumption: hue is undefined for dark pixels", "pixels darker are ignored"
    )
    covariance_floor: float = param(
        1e-3,
        "assumption: a histogram's frequencies sum to 1, so its covariance (002 eq. 2) is "
        "singular; also needed after a single observation",
        "variance added to every bin of Sigma_i before eq. 6",
    )
    min_hue_samples: int = param(
        10,
        "assumption",
        "an observation with fewer valid hue samples is not used",
    )

    def __post_init__(self) -> None:
        if self.bins < 2:
            raise ValueError("bins must be at least 2")
        if not self.covariance_floor > 0:
            raise ValueError("covariance_floor must be positive")


def hue_histogram(hues_rad: FloatArray, bins: int = 6) -> FloatArray:
    """Relative frequencies (bins,) of hues [rad]; bin ``b`` is centred on ``b * 360/bins``
    degrees, so with 6 bins the centres are the colours of 002 Table 1. All zeros when no
    hue is given."""
    h = np.asarray(hues_rad, dtype=np.float64).reshape(-1)
    if h.size == 0:
        return np.zeros(bins)
    width = 2.0 * math.pi / bins
    idx = np.floor((np.mod(h, 2.0 * math.pi) + 0.5 * width) / width).astype(np.int64) % bins
    return np.bincount(idx, minlength=bins).astype(np.float64) / h.size


def measurement(hues_rad: FloatArray, params: AppearanceParams | None = None) -> FloatArray | None:
    """The colour measurement y (bins,) of hue samples [rad] (an
    :class:`~laserpeople.frame.AppearanceObservation`'s ``hues``); None when there are fewer
    than ``min_hue_samples``."""
    p = params or AppearanceParams()
    h = np.asarray(hues_rad, dtype=np.float64).reshape(-1)
    if h.size < p.min_hue_samples:
        return None
    return hue_histogram(h, p.bins)


class OnlineGaussian:
    """Mean and covariance of measurements learnt one at a time (002 eqs. 1-5).

    After ``k`` measurements ``mean`` is eq. 1 and ``covariance`` eq. 2 (the unbiased
    estimate; zero while ``k < 2``), updated with eqs. 3-5 without storing old values.
    """

    def __init__(self, dim: int) -> None:
        self.k = 0
        self.mean = np.zeros(dim)
        self.covariance = np.zeros((dim, dim))

    def add(self, y: FloatArray) -> None:
        """Learn one measurement ``y`` (dim,)."""
        y = np.asarray(y, dtype=np.float64).reshape(-1)
        k = self.k
        if k == 0:
            self.mean = y.copy()
            self.k = 1
            return
        new_mean = k / (k + 1) * self.mean + y / (k + 1)  # eq. 4
        delta = new_mean - self.mean  # eq. 3
        r = y - new_mean
        self.covariance = (  # eq. 5
            np.outer(r, r) / k + (k - 1) / k * self.covariance + np.outer(delta, delta)
        )
        self.mean = new_mean
        self.k = k + 1

    def copy(self) -> OnlineGaussian:
        """An independent copy."""
        out = OnlineGaussian(self.mean.size)
        out.k = self.k
        out.mean = self.mean.copy()
        out.covariance = self.covariance.copy()
        return out


def log_likelihoods(
    y: FloatArray, means: FloatArray, covariances: FloatArray, floor: float
) -> FloatArray:
    """log p_{i,j} of 002 eq. 6 for every learnt person i and measurement j.

    Args:
        y: Measurements (J, B).
        means: Learnt means mu_i (I, B).
        covariances: Learnt covariances Sigma_i (I, B, B); ``floor * I`` is added.
        floor: Variance floor (see :class:`AppearanceParams`).

    Returns:
        (I, J) log-densities.
    """
    y = np.asarray(y, dtype=np.float64).reshape(-1, np.shape(means)[-1])
    mu = np.asarray(means, dtype=np.float64)
    b = mu.shape[-1]
    sig = np.asarray(covariances, dtype=np.float64) + floor * np.eye(b)
    chol = np.linalg.cholesky(sig)  # (I, B, B)
    diff = y[None, :, :] - mu[:, None, :]  # (I, J, B)
    sol = np.linalg.solve(chol[:, None, :, :], diff[..., None])[..., 0]
    d2 = np.einsum("ijb,ijb->ij", sol, sol)
    logdet = 2.0 * np.log(np.diagonal(chol, axis1=1, axis2=2)).sum(axis=1)  # (I,)
    return -0.5 * d2 - 0.5 * (b * LOG_2PI + logdet)[:, None]


def assign_identities(cost: FloatArray) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """The permutation sigma minimising sum_i cost[i, sigma(i)] (002 eq. 8 with cost = the
    negative log of eq. 7), by the Hungarian algorithm; rectangular matrices assign
    min(I, J) pairs.

    Returns:
        ``(rows, cols)``: person i = rows[k] is given track cols[k].
    """
    from scipy.optimize import linear_sum_assignment

    c = np.asarray(cost, dtype=np.float64)
    if c.size == 0:
        return np.empty(0, dtype=np.int64), np.empty(0, dtype=np.int64)
    rows, cols = linear_sum_assignment(c)
    return rows.astype(np.int64), cols.astype(np.int64)


def assignment_margin(
    cost: FloatArray,
) -> tuple[NDArray[np.int64], NDArray[np.int64], float]:
    """The best assignment of :func:`assign_identities` and by how much the second best
    assignment costs more (Murty's second solution: the best with one of its pairs
    forbidden, over each pair; ``inf`` when there is no other assignment).

    With cost = minus summed log-likelihoods (002 eq. 7) the margin is the log of the
    likelihood ratio of the best assignment against its strongest rival: a sequential test
    decides once it exceeds a threshold.

    Returns:
        ``(rows, cols, margin)``.
    """
    c = np.asarray(cost, dtype=np.float64)
    rows, cols = assign_identities(c)
    if rows.size == 0:
        return rows, cols, math.inf
    best = float(c[rows, cols].sum())
    big = 1e6 + 2.0 * float(np.abs(c).sum())
    second = math.inf
    for r, k in zip(rows, cols, strict=True):
        alt = c.copy()
        alt[r, k] = big
        ar, ac = assign_identities(alt)
        total = float(alt[ar, ac].sum())
        if total < big:
            second = min(second, total)
    return rows, cols, second - best
