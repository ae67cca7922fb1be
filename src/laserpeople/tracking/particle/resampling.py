"""Systematic resampling and effective sample size, vectorised over a bank of filters.

A bank holds F particle filters of P particles each; weights are (F, P) arrays, each row
summing to one (Thrun et al., Probabilistic Robotics, Table 4.4 "low variance sampler").
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def normalise(weights: NDArray[np.floating]) -> NDArray[np.float64]:
    """Rows of ``weights`` (F, P) scaled to sum to one; a row summing to zero (or not finite)
    becomes uniform."""
    w = np.asarray(weights, dtype=np.float64)
    total = w.sum(axis=-1, keepdims=True)
    bad = ~(np.isfinite(total) & (total > 0.0))
    out = np.where(bad, 1.0, w) / np.where(bad, w.shape[-1], total)
    return np.asarray(out, dtype=np.float64)


def effective_sample_size(weights: NDArray[np.floating]) -> NDArray[np.float64]:
    """ESS = 1 / sum_i w_i^2 per row of normalised ``weights`` (F, P) -> (F,)."""
    w = np.asarray(weights, dtype=np.float64)
    return np.asarray(1.0 / np.sum(w * w, axis=-1), dtype=np.float64)


def systematic_resample(
    weights: NDArray[np.floating], rng: np.random.Generator
) -> NDArray[np.int64]:
    """Indices (F, P) of the particles drawn by systematic resampling from each row of
    normalised ``weights`` (F, P): one uniform offset u ~ U[0, 1/P) per filter and the
    draws u + k/P, k = 0..P-1. All filters in one ``searchsorted`` (rows offset by their
    index)."""
    w = np.asarray(weights, dtype=np.float64)
    f, p = w.shape
    cum = np.cumsum(w, axis=1)
    cum[:, -1] = 1.0  # guard against round-off
    u = (rng.random((f, 1)) + np.arange(p)[None, :]) / p
    rows = np.arange(f, dtype=np.float64)[:, None]
    flat = np.searchsorted((cum + rows).ravel(), (u + rows).ravel(), side="right")
    idx = flat.reshape(f, p) - (np.arange(f) * p)[:, None]
    return np.asarray(np.minimum(idx, p - 1), dtype=np.int64)


__all__ = ["effective_sample_size", "normalise", "systematic_resample"]
