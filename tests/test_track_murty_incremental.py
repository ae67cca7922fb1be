"""Murty's method with subproblem matrices made incrementally (``MurtyStream(incremental=
True)``, the default) gives exactly what building every subproblem from the base matrix
gives: the same solutions (pairs and cost floats) in the same order, equal costs included,
after the same number of solves, also through the MHT's multi-parent k best."""

from __future__ import annotations

import functools
import heapq
import itertools

import numpy as np
import pytest

import laserpeople.tracking.mht.matrix as matrix_mod
from laserpeople.tracking.assignment import MurtyStream, solve, subset_sums
from laserpeople.tracking.mht.matrix import AssignmentMatrix, Work, k_best_children
from laserpeople.tracking.mht.probability import DELETED, FALSE_ALARM, NEW, OCCLUDED


def tie_cost(rng: np.random.Generator, r: int, c: int) -> np.ndarray:
    """Small integers (many equal costs, many equal totals) with infeasible pairs."""
    cost = rng.integers(0, 4, (r, c)).astype(np.float64)
    cost[rng.random((r, c)) < rng.uniform(0.0, 0.5)] = np.inf
    return cost


def stream_trace(stream: MurtyStream, steps: int, rng: np.random.Generator) -> list[object]:
    """Every observable of a stream under a random mix of refine / pop calls (what a
    caller merging streams sees), solutions as exact floats and pairs."""
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


@pytest.mark.parametrize("seed", range(300))
def test_incremental_stream_equals_base_built(seed: int) -> None:
    rng = np.random.default_rng(seed)
    r, c = (int(x) for x in rng.integers(1, 7, 2))
    cost = tie_cost(rng, r, c) if seed % 2 else rng.normal(0.0, 3.0, (r, c)).round(1)
    key = None if seed % 3 == 0 else rng.random((r, c)) < 0.7
    call_seed = int(rng.integers(1 << 30))
    new = stream_trace(MurtyStream(cost, key), 80, np.random.default_rng(call_seed))
    old = stream_trace(
        MurtyStream(cost, key, incremental=False), 80, np.random.default_rng(call_seed)
    )
    assert new == old
    solved = any(isinstance(x, tuple) and len(x) == 3 and isinstance(x[0], str) for x in new)
    assert solved == (solve(cost) is not None)


def test_incremental_stream_does_not_touch_the_cost_matrix() -> None:
    cost = tie_cost(np.random.default_rng(7), 5, 5)
    before = cost.copy()
    list(MurtyStream(cost))
    np.testing.assert_array_equal(cost, before)


def random_matrix(rng: np.random.Generator, n: int, m: int) -> AssignmentMatrix:
    """A parent's assignment problem with integer costs (ties everywhere)."""
    tm = rng.integers(-3, 3, (n, m)).astype(np.float64)
    tm[rng.random((n, m)) < 0.4] = np.inf
    options = [[j for j in range(m) if np.isfinite(tm[i, j])] for i in range(n)]
    occ = rng.integers(0, 3, n).astype(np.float64)
    dele = rng.integers(0, 3, n).astype(np.float64)
    new = rng.integers(0, 3, m).astype(np.float64)
    fal = rng.integers(0, 3, m).astype(np.float64)
    return AssignmentMatrix(
        tm.tolist(),
        options,
        [OCCLUDED if o <= d else DELETED for o, d in zip(occ, dele, strict=True)],
        np.minimum(occ, dele).tolist(),
        np.abs(occ - dele).tolist(),
        [FALSE_ALARM if f <= w else NEW for w, f in zip(new, fal, strict=True)],
        np.minimum(new, fal).tolist(),
        np.abs(new - fal).tolist(),
    )


def children(
    priors: list[float], mats: list[AssignmentMatrix], budget: float
) -> tuple[list[object], int, bool]:
    work = Work(max_solves=budget)
    out = k_best_children(priors, mats, 15, 6.0, enumerate_limit=1, work=work)
    flat = [
        (i, d.track_label, d.track_measurement, d.measurement_label, d.cost.hex(), t.hex())
        for i, d, t in out
    ]
    return flat, work.solves, work.truncated


@pytest.mark.parametrize("seed", range(60))
def test_k_best_children_same_with_incremental_murty(
    seed: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    rng = np.random.default_rng(1000 + seed)
    n, m = int(rng.integers(1, 5)), int(rng.integers(1, 6))
    mats = [random_matrix(rng, n, m) for _ in range(int(rng.integers(1, 4)))]
    priors = [float(p) for p in rng.integers(0, 3, len(mats))]
    budget = float(rng.choice([np.inf, 5, 20]))
    new = children(priors, mats, budget)
    monkeypatch.setattr(
        matrix_mod, "MurtyStream", functools.partial(MurtyStream, incremental=False)
    )
    old = children(priors, mats, budget)
    assert new == old
    assert new[0]  # some child


def reference_k_best_children(
    priors: list[float], matrices: list[AssignmentMatrix], k: int, max_gap: float, work: Work
) -> list[tuple[int, matrix_mod.LabelledAssignment, float]]:
    """:func:`k_best_children` as it was before the bound refinements were run in a loop
    (every refined bound queued and popped again), with every subproblem matrix built from
    the base: the reference the current code must match exactly."""
    counter = itertools.count()
    heap: list[matrix_mod._Entry] = []
    streams: dict[int, matrix_mod._MatchingStream] = {}
    for i, (prior, mat) in enumerate(zip(priors, matrices, strict=True)):
        bound = mat.lower_bound()
        if np.isfinite(bound):
            heap.append((prior + bound, matrix_mod._BOUND, next(counter), i, None))
    heapq.heapify(heap)
    out: list[tuple[int, matrix_mod.LabelledAssignment, float]] = []
    best = np.inf
    while heap and len(out) < k:
        total, kind, _, i, state = heapq.heappop(heap)
        if out and total > best + max_gap:
            break
        if kind == matrix_mod._BOUND:
            if out and work.solves >= work.max_solves:
                work.truncated = True
                continue
            if i not in streams:
                streams[i] = matrix_mod._MatchingStream(matrices[i], 1)
                if streams[i]._murty is not None:
                    cost, key = matrices[i].square()
                    streams[i]._murty = MurtyStream(cost, key, incremental=False)
            if streams[i].refine():
                work.solves += 1
            matrix_mod._push_stream(heap, counter, priors[i], i, streams[i])
        elif kind == matrix_mod._MATCHING:
            matching = streams[i].pop()
            variants = subset_sums(matrix_mod._penalties(matrices[i], matching))
            state = matrix_mod._VariantState(i, matching, variants)
            matrix_mod._push_variant(heap, counter, priors[i], state)
            matrix_mod._push_stream(heap, counter, priors[i], i, streams[i])
        else:
            assert state is not None
            labels = matrix_mod.decode(matrices[i], state.matching, state.flipped, state.extra)
            out.append((i, labels, total))
            best = min(best, total)
            matrix_mod._push_variant(heap, counter, priors[i], state)
    return out


@pytest.mark.parametrize("seed", range(150))
def test_k_best_children_same_as_reference(seed: int) -> None:
    rng = np.random.default_rng(5000 + seed)
    n, m = int(rng.integers(1, 5)), int(rng.integers(1, 6))
    mats = [random_matrix(rng, n, m) for _ in range(int(rng.integers(1, 5)))]
    priors = [float(p) for p in rng.integers(0, 3, len(mats))]
    budget = float(rng.choice([np.inf, 1, 3, 10, 30]))
    gap = float(rng.choice([np.inf, 2.0, 6.0]))
    k = int(rng.integers(1, 25))
    work_new, work_old = Work(max_solves=budget), Work(max_solves=budget)
    new = k_best_children(priors, mats, k, gap, enumerate_limit=1, work=work_new)
    old = reference_k_best_children(priors, mats, k, gap, work_old)

    def flat(res: list[tuple[int, matrix_mod.LabelledAssignment, float]]) -> list[object]:
        return [
            (i, d.track_label, d.track_measurement, d.measurement_label, d.cost.hex(), t.hex())
            for i, d, t in res
        ]

    assert flat(new) == flat(old)
    assert (work_new.solves, work_new.truncated) == (work_old.solves, work_old.truncated)
    assert new
