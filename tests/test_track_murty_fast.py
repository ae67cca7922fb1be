"""The cheaper paths of Murty's method (session 12) give bit for bit what the old ones gave:
the solver's cost summed from one flat ``take``, a subset's square matching matrix taken
from its base's, and a popped matching's columns read without ``col_of_row``."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

from laserpeople.tracking.assignment import MurtyStream, solve
from laserpeople.tracking.mht.matrix import AssignmentMatrix, _MatchingStream, build_matrix

# two code paths giving the same bits may hold on one CPU only: CI runs these again on
# another CPU path (.ci/run)
pytestmark = pytest.mark.regression


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


def _old_choices(
    tm: np.ndarray, lp: np.ndarray
) -> tuple[list[list[tuple[float, int, int, int]]], list[float], list[int]]:
    """Each track's sorted labels, cheapest label and gate as the session-11 listing made
    them (one comprehension per track; cheapest and gates by ``_Lister`` itself)."""
    from laserpeople.tracking.mht.listing import _Lister
    from laserpeople.tracking.mht.probability import DELETED, DETECTED, OCCLUDED

    c_occ, c_del = (-lp[:, OCCLUDED]).tolist(), (-lp[:, DELETED]).tolist()
    rows = tm.tolist()
    choices = []
    for i in range(tm.shape[0]):
        ch = [(c, DETECTED, j, 1 << j) for j, c in enumerate(rows[i]) if c < np.inf]
        if c_occ[i] < np.inf:
            ch.append((c_occ[i], OCCLUDED, -1, 0))
        if c_del[i] < np.inf:
            ch.append((c_del[i], DELETED, -1, 0))
        ch.sort()
        choices.append(ch)
    lister = _Lister(choices, [], [], [0.0], [0.0], 1, 1.0)
    return choices, lister.cheapest, lister.gates


@pytest.mark.parametrize("seed", range(30))
def test_listing_setup_in_one_pass_is_the_old_one(
    seed: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The listing's per-track labels, cheapest label and gate made in one pass are those
    the old setup made (ties and impossible labels included), so the children are too."""
    import laserpeople.tracking.mht.listing as listing

    rng = np.random.default_rng(3000 + seed)
    n, m = int(rng.integers(1, 9)), int(rng.integers(0, 6))
    tm = rng.integers(-2, 3, (n, m)).astype(np.float64)  # many equal costs
    tm[rng.random((n, m)) < 0.4] = np.inf
    lp = np.log(rng.dirichlet(np.ones(3), n)).round(0)
    lp[rng.random((n, 3)) < 0.2] = -np.inf
    want = _old_choices(tm, lp)
    seen: list[tuple[object, object, object]] = []
    original = listing._Lister.__init__

    def spy(self: object, *args: Any) -> None:
        choices, cheapest, gates = args[0], args[7], args[8]
        seen.append((choices, cheapest, gates))
        original(self, *args)  # type: ignore[arg-type]

    monkeypatch.setattr(listing._Lister, "__init__", spy)
    monkeypatch.setattr(listing, "COMPILED", None)  # (the Python listing's setup)
    rows = [sorted(rng.choice(n, size=int(rng.integers(1, n + 1)), replace=False).tolist())]
    rows.append([int(n - 1), 0] if n > 1 else [0])
    listing.enumerate_children(
        [0.5, 0.25], rows, tm, lp, np.full(m, -1.0), np.full(m, -2.0), 20, 9.0, shortcut=False
    )
    assert len(seen) == 1
    assert seen[0] == want
