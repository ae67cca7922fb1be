"""Systematic resampling, effective sample size and the filter bank."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.tracking.particle.bank import FilterBank
from laserpeople.tracking.particle.resampling import (
    effective_sample_size,
    normalise,
    systematic_resample,
)


def reference_systematic(w: np.ndarray, u0: float) -> np.ndarray:
    """Thrun et al. Table 4.4, one filter, as a loop."""
    p = len(w)
    out, c, i = [], w[0], 0
    for m in range(p):
        u = u0 / p + m / p
        while u >= c:
            i += 1
            c += w[i]
        out.append(i)
    return np.array(out)


def test_vectorised_equals_the_textbook_loop() -> None:
    rng = np.random.default_rng(0)
    w = normalise(rng.random((6, 50)) ** 4)
    idx = systematic_resample(w, np.random.default_rng(7))
    offsets = np.random.default_rng(7).random(6)
    for f in range(6):
        assert idx[f].tolist() == reference_systematic(w[f], offsets[f]).tolist()


def test_counts_are_floor_or_ceil_of_expected() -> None:
    rng = np.random.default_rng(1)
    w = normalise(rng.random((20, 100)))
    idx = systematic_resample(w, rng)
    for f in range(20):
        counts = np.bincount(idx[f], minlength=100)
        expected = 100 * w[f]
        assert np.all(counts >= np.floor(expected) - 1e-9)
        assert np.all(counts <= np.ceil(expected) + 1e-9)


def test_effective_sample_size_and_normalise() -> None:
    w = np.array([[0.25, 0.25, 0.25, 0.25], [1.0, 0.0, 0.0, 0.0], [0.5, 0.5, 0.0, 0.0]])
    assert effective_sample_size(w).tolist() == pytest.approx([4.0, 1.0, 2.0])
    n = normalise(np.array([[0.0, 0.0], [1.0, 3.0], [np.nan, 1.0]]))
    assert n.tolist() == [[0.5, 0.5], [0.25, 0.75], [0.5, 0.5]]


def test_bank_resamples_only_degenerate_filters_and_keeps_ids() -> None:
    bank = FilterBank(4, 1)
    bank.add(np.arange(8, dtype=float).reshape(2, 4, 1), 0.0)
    lik = np.array([[1.0, 1.0, 1.0, 1.0], [0.0, 0.0, 0.0, 1.0]])
    bank.reweight(lik, np.random.default_rng(0), 0.5)
    assert bank.states[0, :, 0].tolist() == [0, 1, 2, 3]  # ESS 4: untouched
    assert bank.states[1, :, 0].tolist() == [7, 7, 7, 7]  # ESS 1: resampled
    assert bank.weights[1].tolist() == [0.25] * 4
    bank.add(np.zeros((1, 4, 1)), 1.0)
    bank.keep(np.array([False, True, True]))
    assert bank.ids.tolist() == [1, 2]
    bank.replace_by(0, 1)  # filter 1 (id 2) takes over the older id 1
    assert bank.ids.tolist() == [1, 1]
