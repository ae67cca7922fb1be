"""The compiled assignment solver (:mod:`laserpeople.tracking.lsap`) against scipy's
``linear_sum_assignment``: the same assignment (ties included) and the same cost float on
thousands of random matrices (rectangular both ways, integer ties, inf and huge entries,
the MHT's square matching matrices), an optimal dual solution (feasible, tight on the
assignment, zero on what is left free), and Murty's method on it the same as on scipy."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

import laserpeople.tracking.assignment as assignment_mod
from laserpeople.tracking import lsap
from laserpeople.tracking.assignment import Assignment, MurtyStream, solve
from laserpeople.tracking.mht.matrix import AssignmentMatrix
from laserpeople.tracking.mht.probability import DELETED, FALSE_ALARM, NEW, OCCLUDED


def random_problem(rng: np.random.Generator, kind: int) -> np.ndarray:
    """A cost matrix of one of four kinds: small integers (ties everywhere), reals, reals
    with huge finite entries, or the MHT's square matching matrix; inf entries in all."""
    if kind == 3:
        return mht_square(rng, int(rng.integers(0, 7)), int(rng.integers(0, 7)))
    r, c = (int(x) for x in rng.integers(0, 13, 2))
    if kind == 0:
        cost = rng.integers(-2, 3, (r, c)).astype(np.float64)
    else:
        cost = rng.normal(0.0, 3.0, (r, c))
        if kind == 2:
            cost[rng.random((r, c)) < 0.3] = 1e12
    cost[rng.random((r, c)) < rng.uniform(0.0, 0.6)] = np.inf
    return cost


def mht_square(rng: np.random.Generator, n: int, m: int) -> np.ndarray:
    """The (n + m) square matching matrix of a random parent problem with integer costs
    (:meth:`AssignmentMatrix.square`)."""
    tm = rng.integers(-3, 3, (n, m)).astype(np.float64)
    tm[rng.random((n, m)) < 0.4] = np.inf
    occ = rng.integers(0, 3, n).astype(np.float64)
    dele = rng.integers(0, 3, n).astype(np.float64)
    new = rng.integers(0, 3, m).astype(np.float64)
    fal = rng.integers(0, 3, m).astype(np.float64)
    matrix = AssignmentMatrix(
        tm.tolist(),
        [[j for j in range(m) if np.isfinite(tm[i, j])] for i in range(n)],
        [OCCLUDED if o <= d else DELETED for o, d in zip(occ, dele, strict=True)],
        np.minimum(occ, dele).tolist(),
        np.abs(occ - dele).tolist(),
        [FALSE_ALARM if f <= w else NEW for w, f in zip(new, fal, strict=True)],
        np.minimum(new, fal).tolist(),
        np.abs(new - fal).tolist(),
    )
    return matrix.square()[0]


def scipy_solve(cost: np.ndarray) -> Assignment | None:
    """What :func:`~laserpeople.tracking.assignment.solve` returned with scipy's solver."""
    cost = np.asarray(cost, dtype=np.float64)
    if cost.size == 0:
        empty = np.empty(0, dtype=np.intp)
        return Assignment(0.0, empty, empty)
    try:
        rows, cols = linear_sum_assignment(cost)
    except ValueError:
        return None
    total = float(cost[rows, cols].sum())
    return None if total == np.inf else Assignment(total, rows, cols)


@pytest.mark.parametrize("kind", range(4))
def test_same_assignment_and_cost_as_scipy(kind: int) -> None:
    rng = np.random.default_rng(100 + kind)
    feasible = 0
    for _ in range(1500):
        cost = random_problem(rng, kind)
        status, rows, cols, total, _, _ = lsap.solve_duals(np.ascontiguousarray(cost))
        ref = scipy_solve(cost)
        if ref is None:
            assert status == lsap.INFEASIBLE
            assert solve(cost) is None
            continue
        feasible += 1
        assert status == lsap.OK
        assert rows.tolist() == ref.rows.tolist()
        assert cols.tolist() == ref.cols.tolist()
        assert total.hex() == ref.cost.hex()
        sol = solve(cost)
        assert sol is not None and sol.cost.hex() == ref.cost.hex()
        assert sol.cols.tolist() == ref.cols.tolist()
    assert feasible > 600  # both outcomes are exercised


@pytest.mark.parametrize("kind", range(4))
def test_duals_are_optimal(kind: int) -> None:
    """u_i + v_j <= c_ij everywhere, equality on the assignment, 0 on the rows or columns
    left free and <= 0 on the larger side (the dual of "every row of the smaller side once,
    every one of the larger side at most once"), so that sum(u) + sum(v) is the cost."""
    rng = np.random.default_rng(200 + kind)
    checked = 0
    for _ in range(1500):
        cost = random_problem(rng, kind)
        status, rows, cols, total, u, v = lsap.solve_duals(np.ascontiguousarray(cost))
        if status != lsap.OK or cost.size == 0:
            continue
        checked += 1
        scale = 1e-9 * (1.0 + np.abs(cost[np.isfinite(cost) & (cost < 1e11)]).sum())
        if kind == 2:
            scale = 1e-9 * 1e12 * cost.shape[0]
        reduced = cost - u[:, None] - v[None, :]
        assert (reduced[np.isfinite(cost)] >= -scale).all()
        np.testing.assert_allclose(reduced[rows, cols], 0.0, atol=scale)
        assert abs(u.sum() + v.sum() - total) <= scale * max(cost.shape)
        r, c = cost.shape
        if r <= c:
            free = np.setdiff1d(np.arange(c), cols)
            assert (v[free] == 0.0).all() and (v <= scale).all()
        else:
            free = np.setdiff1d(np.arange(r), rows)
            assert (u[free] == 0.0).all() and (u <= scale).all()
    assert checked > 600


def test_invalid_and_infeasible_entries() -> None:
    assert lsap.solve_duals(np.array([[1.0, np.nan], [0.0, 2.0]]))[0] == lsap.INVALID
    assert lsap.solve_duals(np.array([[1.0, -np.inf], [0.0, 2.0]]))[0] == lsap.INVALID
    assert lsap.solve_duals(np.array([[np.inf, np.inf], [0.0, 2.0]]))[0] == lsap.INFEASIBLE
    assert solve(np.array([[1.0, np.nan]])) is None
    with pytest.raises(ValueError):
        linear_sum_assignment(np.array([[1.0, np.nan]]))  # what solve() caught before
    with pytest.raises(ValueError, match="matrix"):
        solve(np.zeros(3))


def test_constant_matrix_gives_the_identity_as_scipy() -> None:
    for shape in [(4, 4), (3, 6), (6, 3)]:
        sol = solve(np.ones(shape))
        rows, cols = linear_sum_assignment(np.ones(shape))
        assert sol is not None
        assert (sol.rows.tolist(), sol.cols.tolist()) == (rows.tolist(), cols.tolist())


def test_sum_in_numpys_order() -> None:
    """The cost is the float numpy's sum gives (pairwise, eight partial sums): checked on
    lengths that take each branch of it (< 8, <= 128, halved above)."""
    rng = np.random.default_rng(5)
    differs = 0
    for n in [*range(0, 40), 127, 128, 129, 136, 255, 256, 257, 300, 1000, 4099]:
        values = rng.normal(0.0, 1.0, n) * 10.0 ** rng.uniform(-6, 6, n)
        assert lsap.pairwise_sum(values).hex() == float(np.sum(values)).hex()
        plain = 0.0
        for x in values.tolist():
            plain += x
        differs += plain != float(np.sum(values))
    assert differs > 10  # the order matters


def test_murty_children_are_the_constrained_problems() -> None:
    """Subproblem t of a solution forbids its pair t and forces pairs 0..t-1 (their rows and
    columns at inf except the pair); each is solved as by scipy."""
    rng = np.random.default_rng(9)
    for _ in range(200):
        cost = mht_square(rng, int(rng.integers(1, 6)), int(rng.integers(1, 6)))
        ref = scipy_solve(cost)
        assert ref is not None
        pairs = list(zip(ref.rows.tolist(), ref.cols.tolist(), strict=True))
        rng.shuffle(pairs)
        pr = np.array([p[0] for p in pairs], dtype=np.intp)
        pc = np.array([p[1] for p in pairs], dtype=np.intp)
        mats, status, rows, cols, costs = lsap.murty_children(cost, pr, pc)
        for t in range(len(pairs)):
            expect = cost.copy()
            for r, c in pairs[:t]:
                keep = expect[r, c]
                expect[r, :] = np.inf
                expect[:, c] = np.inf
                expect[r, c] = keep
            expect[pairs[t]] = np.inf
            np.testing.assert_array_equal(mats[t], expect)
            sub = scipy_solve(expect)
            assert (status[t] == lsap.OK) == (sub is not None)
            if sub is not None:
                assert rows[t].tolist() == sub.rows.tolist()
                assert cols[t].tolist() == sub.cols.tolist()
                assert costs[t].hex() == sub.cost.hex()


def stream_trace(stream: MurtyStream, steps: int, rng: np.random.Generator) -> list[object]:
    """Every observable of a stream under a random mix of refine and pop calls."""
    trace: list[object] = []
    for _ in range(steps):
        trace.append((stream.peek_cost(), stream.front_solved(), stream.n_solved))
        if rng.random() < 0.5 and not stream.front_solved():
            stream.refine()
            continue
        sol = stream.pop()
        if sol is None:
            trace.append(None)
            break
        trace.append((sol.cost.hex(), sol.rows.tolist(), sol.cols.tolist()))
    return trace


@pytest.mark.parametrize("seed", range(200))
def test_murty_stream_same_as_with_scipy(seed: int, monkeypatch: pytest.MonkeyPatch) -> None:
    """The stream (subproblems solved in batches by compiled code) against the stream
    that builds each subproblem from the base and solves it with scipy when refined (what
    Murty's method did before): the same observables after every call, ties included."""
    rng = np.random.default_rng(3000 + seed)
    if seed % 2:
        n, m = int(rng.integers(1, 7)), int(rng.integers(1, 7))
        cost = mht_square(rng, n, m)
        key = np.zeros(cost.shape, dtype=bool)  # as AssignmentMatrix.square's
        key[:n, :] = True
        key[:, :m] = True
    else:
        cost = random_problem(rng, int(rng.integers(0, 3)))
        key = None if seed % 3 == 0 else rng.random(cost.shape) < 0.7
    call_seed = int(rng.integers(1 << 30))
    new = stream_trace(MurtyStream(cost, key), 120, np.random.default_rng(call_seed))
    monkeypatch.setattr(assignment_mod, "solve", scipy_solve)
    old = stream_trace(
        MurtyStream(cost, key, incremental=False), 120, np.random.default_rng(call_seed)
    )
    assert new == old
