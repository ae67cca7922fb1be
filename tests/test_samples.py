"""Per-frame figures in bounded memory (laserpeople.samples)."""

from __future__ import annotations

import math

import pytest

from laserpeople.samples import RECENT, Samples, quantile


def test_quantile_nearest_rank_by_hand() -> None:
    values = [5.0, 1.0, 4.0, 2.0, 3.0]
    # nearest rank: the ceil(q n)-th smallest
    assert quantile(values, 0.5) == 3.0
    assert quantile(values, 0.2) == 1.0
    assert quantile(values, 0.21) == 2.0  # ceil(1.05) = 2nd, not the 1st (rounding down)
    assert quantile(values, 0.99) == 5.0
    assert quantile(values, 0.0) == 1.0
    assert quantile([], 0.5) == 0.0
    assert quantile([1.0, 2.0, 3.0, 4.0], 0.5) == 2.0  # the lower of the middle two


def test_exact_below_capacity() -> None:
    s = Samples(capacity=100)
    for v in range(1, 51):
        s.append(float(v))
    assert len(s) == 50 and not s.sampled
    assert sorted(s) == [float(v) for v in range(1, 51)]
    assert s.quantile(0.5) == 25.0 and s.quantile(0.99) == 50.0
    assert math.isclose(s.mean, 25.5, rel_tol=1e-12)


def test_bounded_beyond_capacity_with_a_uniform_sample() -> None:
    s = Samples(capacity=1000, seed=3)
    n = 200_000
    for v in range(n):
        s.append(float(v))
    kept = list(s)
    assert len(s) == n and s.sampled and len(kept) == 1000  # memory stays at capacity
    assert math.isclose(s.mean, (n - 1) / 2, rel_tol=1e-12)  # the mean is of every value
    # a uniform sample of 0..n-1: its median near n/2 (a sample of the first 1000 values,
    # or of the last, would be far off); 1000 draws put it within 0.1 n with room to spare
    assert abs(s.quantile(0.5) - n / 2) < 0.1 * n
    assert sum(v < n / 2 for v in kept) == pytest.approx(500, abs=100)
    # the last values are kept exactly, in order
    assert s.recent(3) == [float(n - 3), float(n - 2), float(n - 1)]
    assert len(s.recent(10 * RECENT)) == RECENT


def test_same_run_same_sample() -> None:
    a, b = Samples(capacity=10, seed=0), Samples(capacity=10, seed=0)
    for v in range(1000):
        a.append(v * 0.5)
        b.append(v * 0.5)
    assert list(a) == list(b)


def test_capacity_must_be_positive() -> None:
    with pytest.raises(ValueError, match="capacity"):
        Samples(capacity=0)
