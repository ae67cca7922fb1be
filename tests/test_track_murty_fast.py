"""The cheaper paths of Murty's method (session 12) give bit for bit what the old ones gave:
the solver's cost summed from one flat ``take``, a subset's square matching matrix taken
from its base's, and a popped matching's columns read without ``col_of_row``."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

from laserpeople.tracking.assignment import MurtyStream, solve
from laserpeople.tracking.mht.matrix import AssignmentMatrix, _MatchingStream, build_matrix


def old_solve(cost: np.ndarray) -> tuple[str, list[int], list[int]] | None:
    """The session-11 ``solve``: the cost by two-dimensional fancy indexing and ``sum``."""
    try:
        rows, cols = linear_sum_assignment(cost)
    except ValueError:
        return None
    total = float(cost[rows, cols].sum())
    if total == np.inf:
        return None
    return total.hex(), rows.tolist(), cols.tolist()


@pytest.mark.parametrize("seed", range(40))
def test_solve_sums_the_same_floats(seed: int) -> None:
    rng = np.random.default_rng(seed)
    for _ in range(50):
        r, c = (int(x) for x in rng.integers(1, 25, 2))
        cost = rng.normal(0.0, 10.0, (r, c)) * 10.0 ** rng.uniform(-3, 3, (r, c))
        cost[rng.random((r, c)) < rng.uniform(0.0, 0.7)] = np.inf
        sol = solve(cost)
        old = old_solve(cost)
        got = None if sol is None else (sol.cost.hex(), sol.rows.tolist(), sol.cols.tolist())
        assert got == old


def test_solve_rows_start_cache_does_not_mix_shapes() -> None:
    # (2, 6) and (3, 4) both have 12 entries; the flat offsets are per shape
    a = np.arange(12, dtype=np.float64).reshape(2, 6)
    b = np.arange(12, dtype=np.float64)[::-1].reshape(3, 4).copy()
    for cost in (a, b, a, b):
        sol = solve(cost)
        assert sol is not None
        assert sol.cost == float(cost[sol.rows, sol.cols].sum())


def random_problem(rng: np.random.Generator, n: int, m: int) -> AssignmentMatrix:
    tm = rng.normal(0.0, 3.0, (n, m))
    tm[rng.random((n, m)) < 0.5] = np.inf
    lp = np.log(rng.dirichlet(np.ones(3), n))
    lp[rng.random((n, 3)) < 0.1] = -np.inf
    return build_matrix(tm, lp, rng.normal(-2.0, 1.0, m), rng.normal(-3.0, 1.0, m))


def direct_square(mat: AssignmentMatrix) -> tuple[np.ndarray, np.ndarray]:
    """The square matrix and key made from the problem's own lists (the old way)."""
    return AssignmentMatrix(
        mat.track_meas_cost,
        mat.options,
        mat.track_unmatched,
        mat.track_unmatched_cost,
        mat.track_penalty,
        mat.meas_unmatched,
        mat.meas_unmatched_cost,
        mat.meas_penalty,
    ).square()


@pytest.mark.parametrize("seed", range(60))
def test_subset_square_is_taken_from_the_base(seed: int) -> None:
    rng = np.random.default_rng(1000 + seed)
    n, m = int(rng.integers(0, 9)), int(rng.integers(0, 14))
    base = random_problem(rng, n, m)
    for _ in range(6):
        rows = rng.permutation(n)[: int(rng.integers(0, n + 1))].tolist()
        sub = base.subset(rows)
        cost, key = sub.square()
        want_cost, want_key = direct_square(sub)
        assert cost.tobytes() == want_cost.tobytes()
        np.testing.assert_array_equal(key, want_key)
        assert not cost.flags.writeable and not key.flags.writeable
        assert sub.square()[0] is cost  # made once


@pytest.mark.parametrize("seed", range(40))
def test_matching_stream_from_the_base_square_is_the_same(seed: int) -> None:
    rng = np.random.default_rng(2000 + seed)
    n, m = int(rng.integers(1, 7)), int(rng.integers(1, 9))
    base = random_problem(rng, n, m)
    rows = rng.permutation(n)[: int(rng.integers(1, n + 1))].tolist()
    sub = base.subset(rows)
    fast = _MatchingStream(sub, 0)  # limit 0: always Murty's method
    cost, key = direct_square(sub)
    stream = MurtyStream(cost, key)
    for _ in range(30):
        sol = stream.pop()
        while not fast.front_solved():
            fast.refine()
        if sol is None:
            assert not np.isfinite(fast.peek_cost())
            break
        want = tuple(int(c) if c < m else -1 for c in sol.col_of_row(len(rows) + m)[: len(rows)])
        got = fast.pop()
        assert (got.cost.hex(), got.track_meas) == (sol.cost.hex(), want)
