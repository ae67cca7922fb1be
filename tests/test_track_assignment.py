"""Hungarian, Murty's k-best and the multi-parent form against brute-force enumeration."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from laserpeople.tracking.assignment import (
    MurtyStream,
    ParentProblem,
    k_best_multi,
    murty,
    solve,
    subset_sums,
)


def brute_force(cost: np.ndarray) -> list[tuple[float, frozenset[tuple[int, int]]]]:
    """Every complete assignment (all rows if R <= C, else all columns) of finite cost."""
    r, c = cost.shape
    out = []
    if r <= c:
        for cols in itertools.permutations(range(c), r):
            total = sum(cost[i, j] for i, j in enumerate(cols))
            if np.isfinite(total):
                out.append((float(total), frozenset(enumerate(cols))))
    else:
        for rows in itertools.permutations(range(r), c):
            total = sum(cost[i, j] for j, i in enumerate(rows))
            if np.isfinite(total):
                out.append((float(total), frozenset((i, j) for j, i in enumerate(rows))))
    out.sort(key=lambda x: x[0])
    return out


def random_cost(rng: np.random.Generator, r: int, c: int, p_inf: float) -> np.ndarray:
    cost = rng.normal(0.0, 3.0, (r, c)).round(3)
    cost[rng.random((r, c)) < p_inf] = np.inf
    return cost


def test_solve_infeasible_returns_none() -> None:
    cost = np.array([[1.0, np.inf], [2.0, np.inf]])
    assert solve(cost) is None


def test_solve_empty() -> None:
    sol = solve(np.empty((0, 0)))
    assert sol is not None and sol.cost == 0.0 and sol.rows.size == 0


@pytest.mark.parametrize("shape", [(1, 1), (2, 3), (3, 3), (4, 4), (3, 5), (5, 3), (4, 6)])
def test_murty_matches_brute_force(shape: tuple[int, int]) -> None:
    rng = np.random.default_rng(sum(shape) * 7 + shape[0])
    for trial in range(8):
        cost = random_cost(rng, *shape, p_inf=0.25 if trial % 2 else 0.0)
        truth = brute_force(cost)
        got = murty(cost, k=len(truth) + 5)
        assert len(got) == len(truth), "Murty must find every feasible assignment once"
        np.testing.assert_allclose([g.cost for g in got], [t[0] for t in truth], atol=1e-9)
        assert len({frozenset(g.pairs()) for g in got}) == len(got)
        assert {frozenset(g.pairs()) for g in got} == {t[1] for t in truth}
        for g in got:
            assert g.cost == pytest.approx(sum(cost[r, c] for r, c in g.pairs()))


def test_murty_k_smaller_than_all_and_max_cost() -> None:
    rng = np.random.default_rng(3)
    cost = random_cost(rng, 4, 4, 0.0)
    truth = brute_force(cost)
    got = murty(cost, k=5)
    np.testing.assert_allclose([g.cost for g in got], [t[0] for t in truth[:5]])
    capped = murty(cost, k=100, max_cost=truth[3][0])
    assert len(capped) == sum(1 for t in truth if t[0] <= truth[3][0])


def test_murty_infeasible_problem_is_empty() -> None:
    cost = np.array([[np.inf, np.inf], [1.0, 2.0]])
    assert murty(cost, k=3) == []
    assert MurtyStream(cost).pop() is None


def test_murty_with_key_mask_skips_equivalent_solutions() -> None:
    """A zero-cost padded block makes many assignments equivalent; with the key mask each
    distinct meaning is produced once, in order."""
    rng = np.random.default_rng(11)
    n, m = 2, 2
    size = n + m
    cost = np.full((size, size), np.inf)
    cost[:n, :m] = rng.normal(0, 1, (n, m))
    cost[np.arange(n), m + np.arange(n)] = 1.5  # track unmatched
    cost[n + np.arange(m), np.arange(m)] = 2.0  # measurement unmatched
    cost[n:, m:] = 0.0
    key = np.zeros_like(cost, dtype=bool)
    key[:n, :] = True
    key[:, :m] = True
    got = murty(cost, k=100, key=key)
    meanings = [frozenset((r, c) for r, c in g.pairs() if key[r, c]) for g in got]
    assert len(set(meanings)) == len(meanings)
    # all meanings from brute force, deduplicated
    truth: dict[frozenset[tuple[int, int]], float] = {}
    for total, pairs in brute_force(cost):
        k = frozenset(p for p in pairs if key[p])
        truth[k] = min(truth.get(k, np.inf), total)
    assert set(meanings) == set(truth)
    np.testing.assert_allclose([g.cost for g in got], sorted(truth.values()))


def test_k_best_multi_is_global_order_over_parents() -> None:
    rng = np.random.default_rng(5)
    problems = [
        ParentProblem(float(rng.uniform(0, 3)), random_cost(rng, 3, 3, 0.2)) for _ in range(4)
    ]
    every = sorted(
        (p.prior_cost + t[0], i) for i, p in enumerate(problems) for t in brute_force(p.cost)
    )
    got = k_best_multi(problems, k=10)
    np.testing.assert_allclose([g[2] for g in got], [e[0] for e in every[:10]])
    for i, sol, total in got:
        assert total == pytest.approx(problems[i].prior_cost + sol.cost)
    # ratio pruning: nothing beyond best + gap
    gap = 1.0
    pruned = k_best_multi(problems, k=100, max_gap=gap)
    assert len(pruned) == sum(1 for e in every if e[0] <= every[0][0] + gap)


def test_subset_sums_order_and_completeness() -> None:
    rng = np.random.default_rng(2)
    pens = rng.uniform(0, 2, 6).tolist()
    got = list(subset_sums(pens))
    assert len(got) == 2**6
    assert len({s for _, s in got}) == 2**6
    sums = [v for v, _ in got]
    assert sums == sorted(sums)
    for v, s in got:
        assert v == pytest.approx(sum(pens[i] for i in s))


def test_subset_sums_rejects_negative() -> None:
    with pytest.raises(ValueError):
        list(subset_sums([1.0, -0.5]))


def test_subset_sums_skips_impossible_items() -> None:
    got = list(subset_sums([0.5, float("inf"), 0.2]))
    assert len(got) == 4
    assert all(1 not in s for _, s in got)
    assert [v for v, _ in got] == sorted(v for v, _ in got)
