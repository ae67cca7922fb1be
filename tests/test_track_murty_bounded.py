"""Murty's method solving a subproblem only when its solution is needed
(:class:`~laserpeople.tracking.assignment.BoundedMurtyStream`, the MHT's) is seen from
outside exactly as :class:`~laserpeople.tracking.assignment.MurtyStream`: the same costs,
bounds, flags and solve counts after every call, the same solutions (pairs and cost floats)
in the same order, equal costs included; and so is the MHT's multi-parent k best built on
it, with fewer assignment problems solved."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import laserpeople.tracking.mht.matrix as matrix_mod
from laserpeople.tracking.assignment import (
    BoundedMurtyStream,
    MurtyStream,
    optimal_duals,
    sibling_bounds,
    solve,
)
from test_track_murty_incremental import children, random_matrix, stream_trace, tie_cost


def mht_square(
    rng: np.random.Generator, n: int, m: int, ties: bool
) -> tuple[np.ndarray, np.ndarray]:
    """An MHT assignment matrix (tracks and measurement slots; 000 Table 9) and its key."""
    if ties:
        mat = random_matrix(rng, n, m)
    else:
        tm = rng.normal(0.0, 3.0, (n, m))
        tm[rng.random((n, m)) < 0.4] = np.inf
        mat = matrix_mod.build_matrix(
            tm, np.log(rng.uniform(0.05, 0.9, (n, 3))), rng.normal(-3, 1, m), rng.normal(-3, 1, m)
        )
    return mat.square()


@pytest.mark.parametrize("seed", range(300))
def test_bounded_stream_seen_as_murty_stream(seed: int) -> None:
    rng = np.random.default_rng(20_000 + seed)
    if seed % 3 == 2:  # an MHT matrix
        cost, key = mht_square(rng, int(rng.integers(1, 6)), int(rng.integers(0, 6)), seed % 2 == 0)
    else:  # any matrix, rectangular ones too
        r, c = (int(x) for x in rng.integers(1, 7, 2))
        cost = tie_cost(rng, r, c) if seed % 2 else rng.normal(0.0, 3.0, (r, c)).round(1)
        key = None if seed % 5 == 0 else rng.random((r, c)) < 0.7
    call_seed = int(rng.integers(1 << 30))
    bounded = BoundedMurtyStream(cost, key)
    new = stream_trace(bounded, 120, np.random.default_rng(call_seed))  # type: ignore[arg-type]
    old = stream_trace(MurtyStream(cost, key), 120, np.random.default_rng(call_seed))
    assert new == old
    assert bounded.n_assignments <= bounded.n_solved + 1


def test_bounded_stream_yields_every_solution_in_order() -> None:
    rng = np.random.default_rng(3)
    cost = rng.normal(0.0, 1.0, (4, 4))
    costs = [s.cost for s in BoundedMurtyStream(cost)]
    every = sorted(
        float(cost[np.arange(4), list(p)].sum()) for p in itertools.permutations(range(4))
    )
    assert len(costs) == 24
    np.testing.assert_allclose(costs, every)


def test_bounded_stream_solves_fewer() -> None:
    """The point of it: on a crowded MHT matrix, far fewer assignment problems than
    MurtyStream solves, for the same first solutions."""
    rng = np.random.default_rng(11)
    cost, key = mht_square(rng, 8, 6, False)
    bounded, plain = BoundedMurtyStream(cost, key), MurtyStream(cost, key)
    for _ in range(5):
        a, b = bounded.pop(), plain.pop()
        assert a is not None and b is not None
        assert (a.cost, a.rows.tolist(), a.cols.tolist()) == (
            b.cost,
            b.rows.tolist(),
            b.cols.tolist(),
        )
    assert bounded.n_solved == plain.n_solved
    assert bounded.n_assignments < plain.n_solved / 2


@pytest.mark.parametrize("seed", range(300))
def test_sibling_bounds_below_each_subproblems_best(seed: int) -> None:
    rng = np.random.default_rng(seed)
    size = int(rng.integers(1, 7))
    if seed % 3 == 0:
        cost, key = mht_square(rng, int(rng.integers(1, 5)), int(rng.integers(0, 4)), seed % 2 == 0)
        size = cost.shape[0]
    else:
        cost = tie_cost(rng, size, size) if seed % 2 else rng.normal(0.0, 3.0, (size, size))
        key = np.ones((size, size), dtype=bool)
    sol = solve(cost)
    if sol is None:
        return
    pairs = [(r, c) for r, c in zip(sol.rows.tolist(), sol.cols.tolist(), strict=True) if key[r, c]]
    rng.shuffle(pairs)  # (any order of the key pairs)
    pairs = [tuple(p) for p in pairs]
    bounds = sibling_bounds(cost, sol, pairs)  # type: ignore[arg-type]
    for t in range(len(pairs)):
        sub = cost.copy()
        for r, c in pairs[:t]:
            keep = sub[r, c]
            sub[r, :] = np.inf
            sub[:, c] = np.inf
            sub[r, c] = keep
        sub[pairs[t]] = np.inf
        best = solve(sub)
        if bounds[t] == np.inf:
            assert best is None
        elif best is not None:
            assert sol.cost - 1e-9 <= best.cost
            assert bounds[t] <= best.cost


def test_sibling_bounds_by_hand() -> None:
    # best: row 0 -> col 0 (1), row 1 -> col 1 (1), cost 2; duals u = (1, 1), v = (0, 0)
    # (reduced costs [[0, 3], [2, 0]]). Forbid (0, 0): row 0 must take col 1 (+3), column
    # 0 row 1 (+2): bound 7 = 4 + 3, the cost of the other assignment. Force (0, 0) and
    # forbid (1, 1): nothing left for row 1: inf.
    cost = np.array([[1.0, 4.0], [3.0, 1.0]])
    sol = solve(cost)
    assert sol is not None
    bounds = sibling_bounds(cost, sol, [(0, 0), (1, 1)])
    assert bounds[0] == pytest.approx(7.0)
    assert bounds[0] <= 7.0
    assert bounds[1] == np.inf
    u, v = optimal_duals(cost, sol.cols)  # type: ignore[misc]
    np.testing.assert_allclose(u + v[sol.cols], cost[[0, 1], sol.cols])
    assert (cost - u[:, None] - v[None, :] >= -1e-12).all()


@pytest.mark.parametrize("seed", range(100))
def test_k_best_children_same_with_bounded_stream(
    seed: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    rng = np.random.default_rng(40_000 + seed)
    n, m = int(rng.integers(1, 6)), int(rng.integers(1, 6))
    mats = [random_matrix(rng, n, m) for _ in range(int(rng.integers(1, 5)))]
    priors = [float(p) for p in rng.integers(0, 3, len(mats))]
    budget = float(rng.choice([np.inf, 3, 10, 30]))
    new = children(priors, mats, budget)
    monkeypatch.setattr(matrix_mod, "BoundedMurtyStream", MurtyStream)
    old = children(priors, mats, budget)
    assert new == old
    assert new[0]
