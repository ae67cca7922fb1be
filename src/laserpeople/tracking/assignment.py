"""Linear assignment: the best (Hungarian) and the k best (Murty 1968) solutions.

Costs are a (R, C) matrix; ``inf`` marks an infeasible pairing. A solution assigns every
row when R <= C (every column when R > C), like :func:`scipy.optimize.linear_sum_assignment`
which solves each subproblem. Murty's method partitions the solution space of the best
solution into subproblems that force the first pairs of that solution and forbid the next,
so it yields solutions in nondecreasing cost without repetition.

Solutions may be compared by a subset of their pairs (``key``): when a cost matrix carries
interchangeable padding pairs (zero-cost dummies of an MHT assignment matrix), only the
pairs that mean something decide whether two solutions differ, and Murty partitions on
those pairs only, so no hypothesis is produced twice. The key must be such that a
solution is determined by its key pairs (for example: all pairs in a set of rows plus all
pairs in a set of columns that every solution covers).

:func:`k_best_multi` is the multi-parent form (Cox & Hingorani 1996, used by 000 Sec.
4.5.2): one Murty stream per parent problem, each offset by the parent's own cost
(-log probability), merged by a priority queue so that the k globally best children over
all parents come out in order.
"""

from __future__ import annotations

import heapq
import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.lazy_scipy import linear_sum_assignment

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]
BoolArray = NDArray[np.bool_]


@dataclass(eq=False, slots=True)
class Assignment:
    """One solution of an assignment problem (not frozen: one is made per Murty subproblem
    solved, and a frozen dataclass costs several times as much to make; nothing changes
    it).

    Attributes:
        cost: Sum of the chosen entries.
        rows: Row indices (K,) of the chosen pairs, increasing.
        cols: Column index (K,) paired with each row.
    """

    cost: float
    rows: IntArray
    cols: IntArray

    def pairs(self) -> set[tuple[int, int]]:
        """The chosen (row, column) pairs."""
        return set(zip(self.rows.tolist(), self.cols.tolist(), strict=True))

    def col_of_row(self, n_rows: int) -> IntArray:
        """Column of each row (n_rows,), -1 where the row is unassigned."""
        out = np.full(n_rows, -1, dtype=np.intp)
        out[self.rows] = self.cols
        return out


def solve(cost: FloatArray) -> Assignment | None:
    """The minimum-cost assignment, or None when no assignment of finite cost exists."""
    cost = np.asarray(cost, dtype=np.float64)
    if cost.size == 0:
        empty = np.empty(0, dtype=np.intp)
        return Assignment(0.0, empty, empty)
    return _solve(cost)


_ROW_STARTS: dict[tuple[int, int], IntArray] = {}
"""Flat index of each row's first entry, per (R, C) with R <= C (few shapes occur)."""


def _solve(cost: FloatArray) -> Assignment | None:
    """:func:`solve` of a non-empty float64 matrix: the same solver call, and the cost as
    the same sum of the same entries in the same order (the chosen entries gathered by one
    flat ``take`` instead of two-dimensional fancy indexing; with R <= C the solver's rows
    are 0..R-1)."""
    try:
        rows, cols = linear_sum_assignment(cost)
    except ValueError:  # scipy: "cost matrix is infeasible"
        return None
    r, c = cost.shape
    if r <= c:
        starts = _ROW_STARTS.get((r, c))
        if starts is None:
            starts = _ROW_STARTS[(r, c)] = np.arange(0, r * c, c, dtype=np.intp)
        flat = cols + starts
    else:
        flat = rows * c + cols
    total = float(np.add.reduce(cost.take(flat)))
    if total == math.inf:
        return None
    return Assignment(total, rows, cols)


@dataclass(eq=False, slots=True)
class _Node:
    """A Murty subproblem: the base cost with forced and forbidden pairs, and its best
    solution once solved (None while only a lower bound is known).

    ``matrix`` is the subproblem's cost matrix: the base with the forbidden pairs at inf
    and the rows and columns of the forced pairs at inf except those pairs. It is made
    when the node is queued (from its parent's, one pair at a time) and dropped once the
    node's own subproblems are queued."""

    solution: Assignment | None
    forced: tuple[tuple[int, int], ...]
    forbidden: tuple[tuple[int, int], ...]
    matrix: FloatArray | None = None


class MurtyStream:
    """Solutions of one assignment problem in nondecreasing cost (lazy Murty).

    The subproblems of a popped solution are queued unsolved, with that solution's cost as
    their lower bound, and solved only when they reach the front of the queue; a caller
    merging several streams (:func:`k_best_multi`) calls :meth:`refine` until the front is
    solved, so subproblems that never matter are never solved.

    Args:
        cost: (R, C) cost matrix, ``inf`` = infeasible pair.
        key: (R, C) mask of the pairs that identify a solution (default: all pairs).
        incremental: Make each subproblem's matrix from its sibling's when the subproblems
            are queued (one copy and a few entries each) instead of from the base matrix
            when it is solved (a copy and every constraint again); the matrices, hence the
            solutions, are the same (False is kept to test that).
    """

    def __init__(
        self, cost: FloatArray, key: BoolArray | None = None, incremental: bool = True
    ) -> None:
        self.cost = np.asarray(cost, dtype=np.float64)
        self.key = np.ones(self.cost.shape, dtype=bool) if key is None else np.asarray(key)
        if self.key.shape != self.cost.shape:
            raise ValueError(f"key shape {self.key.shape} != cost shape {self.cost.shape}")
        self._heap: list[tuple[float, int, _Node]] = []
        self._counter = itertools.count()
        self.n_solved = 0
        self.incremental = incremental
        self._push(0.0, _Node(None, (), (), self.cost if incremental else None))

    def _push(self, bound: float, node: _Node) -> None:
        cost = node.solution.cost if node.solution is not None else bound
        heapq.heappush(self._heap, (cost, next(self._counter), node))

    def peek_cost(self) -> float:
        """Cost of the next solution, or a lower bound of it when :meth:`front_solved` is
        False (inf when exhausted)."""
        return self._heap[0][0] if self._heap else float("inf")

    def front_solved(self) -> bool:
        """Whether :meth:`peek_cost` is the exact cost of the next solution."""
        return not self._heap or self._heap[0][2].solution is not None

    def refine(self) -> None:
        """Solve the subproblem at the front (dropping it when infeasible)."""
        heap = self._heap
        if not heap or heap[0][2].solution is not None:
            return
        _, _, node = heapq.heappop(heap)
        matrix = node.matrix
        if matrix is None:
            node.solution = self._solve_sub(node.forced, node.forbidden)
        else:
            node.solution = _solve(matrix) if matrix.size else solve(matrix)
        self.n_solved += 1
        if node.solution is not None:
            heapq.heappush(heap, (node.solution.cost, next(self._counter), node))

    def _solve_sub(
        self, forced: tuple[tuple[int, int], ...], forbidden: tuple[tuple[int, int], ...]
    ) -> Assignment | None:
        """The best solution of the subproblem (built from the base matrix; the queued
        nodes carry theirs, see :meth:`pop`)."""
        return solve(_constrained(self.cost, forced, forbidden))

    def pop(self) -> Assignment | None:
        """The next best solution, or None when there is none left."""
        while not self.front_solved():
            self.refine()
        if not self._heap:
            return None
        _, _, node = heapq.heappop(self._heap)
        sol = node.solution
        assert sol is not None
        rows, cols = sol.rows, sol.cols
        pairs = zip(rows.tolist(), cols.tolist(), self.key[rows, cols].tolist(), strict=True)
        if node.forced:
            forced_set = set(node.forced)
            key_pairs = [(r, c) for r, c, k in pairs if k and (r, c) not in forced_set]
        else:
            key_pairs = [(r, c) for r, c, k in pairs if k]
        forced = node.forced
        if not self.incremental:
            for pair in key_pairs:
                self._push(sol.cost, _Node(None, forced, (*node.forbidden, pair)))
                forced = (*forced, pair)
            return sol
        # the subproblems' matrices, each from the previous one: forbid the next pair,
        # force it for the ones after (the same matrices as built from the base, since the
        # forced pairs have distinct rows and columns and are never forbidden); the
        # entries are written through a flat view (a row is a slice, a column a stride)
        matrix = node.matrix
        if matrix is None:
            matrix = _constrained(self.cost, node.forced, node.forbidden)
        node.matrix = None
        heap, counter, bound, forbidden = self._heap, self._counter, sol.cost, node.forbidden
        n_cols = matrix.shape[1]
        last = len(key_pairs) - 1
        inf = math.inf
        flat = matrix.reshape(-1)
        for t, (r, c) in enumerate(key_pairs):
            sub = matrix.copy()
            at = r * n_cols + c
            sub.reshape(-1)[at] = inf
            heapq.heappush(
                heap, (bound, next(counter), _Node(None, forced, (*forbidden, (r, c)), sub))
            )
            forced = (*forced, (r, c))
            if t < last:
                if t == 0:
                    matrix = matrix.copy()
                    flat = matrix.reshape(-1)
                keep = flat[at]
                flat[r * n_cols : (r + 1) * n_cols] = inf
                flat[c::n_cols] = inf
                flat[at] = keep
        return sol

    def __iter__(self) -> Iterator[Assignment]:
        while (sol := self.pop()) is not None:
            yield sol


def _constrained(
    cost: FloatArray, forced: tuple[tuple[int, int], ...], forbidden: tuple[tuple[int, int], ...]
) -> FloatArray:
    """``cost`` with the ``forbidden`` pairs at inf and the rows and columns of the
    ``forced`` pairs at inf except those pairs (a copy; ``cost`` itself when there are no
    constraints)."""
    if not forced and not forbidden:
        return cost
    out = cost.copy()
    for r, c in forbidden:
        out[r, c] = np.inf
    for r, c in forced:
        keep = out[r, c]
        out[r, :] = np.inf
        out[:, c] = np.inf
        out[r, c] = keep
    return out


def murty(
    cost: FloatArray, k: int, key: BoolArray | None = None, max_cost: float = np.inf
) -> list[Assignment]:
    """The ``k`` best assignments in nondecreasing cost (fewer if fewer exist or if the
    next one costs more than ``max_cost``)."""
    out: list[Assignment] = []
    stream = MurtyStream(cost, key)
    while len(out) < k:
        while not stream.front_solved():
            stream.refine()
        if stream.peek_cost() > max_cost:
            break
        sol = stream.pop()
        if sol is None:
            break
        out.append(sol)
    return out


@dataclass(frozen=True, eq=False)
class ParentProblem:
    """One parent's assignment problem for :func:`k_best_multi`.

    Attributes:
        prior_cost: The parent's own cost, -log of its probability (times any model prior).
        cost: (R, C) assignment cost matrix of its children.
        key: (R, C) identifying pairs (None: all).
    """

    prior_cost: float
    cost: FloatArray
    key: BoolArray | None = None


def k_best_multi(
    problems: Sequence[ParentProblem], k: int, max_gap: float = np.inf
) -> list[tuple[int, Assignment, float]]:
    """The ``k`` globally best children over several parents.

    A parent's Murty stream is started only when a lower bound of its best child (its prior
    plus the sum of its row minima) comes up in the queue, so parents that cannot contribute
    cost nothing beyond that bound.

    Args:
        problems: One assignment problem per parent.
        k: Maximum number of children.
        max_gap: Stop when a child's total cost exceeds the best child's by more than this
            (ratio pruning: ``max_gap = -log(ratio)``).

    Returns:
        ``(problem index, assignment, total cost)`` with total = prior + assignment cost, in
        nondecreasing total cost.
    """
    streams: dict[int, MurtyStream] = {}
    # entries: (cost or bound, is_solved, index); unsolved bounds sort before equal solved
    heap: list[tuple[float, int, int]] = []
    for i, p in enumerate(problems):
        bound = _lower_bound(p.cost)
        if np.isfinite(bound):
            heap.append((p.prior_cost + bound, 0, i))
    heapq.heapify(heap)
    out: list[tuple[int, Assignment, float]] = []
    best = np.inf
    while heap and len(out) < k:
        total, solved, i = heapq.heappop(heap)
        if out and total > best + max_gap:
            break
        if not solved:
            if i not in streams:
                streams[i] = MurtyStream(problems[i].cost, problems[i].key)
            stream = streams[i]
            stream.refine()
            c = stream.peek_cost()
            if np.isfinite(c):
                heapq.heappush(heap, (problems[i].prior_cost + c, int(stream.front_solved()), i))
            continue
        sol = streams[i].pop()
        assert sol is not None
        out.append((i, sol, total))
        best = min(best, total)
        nxt = streams[i].peek_cost()
        if np.isfinite(nxt):
            heapq.heappush(heap, (problems[i].prior_cost + nxt, int(streams[i].front_solved()), i))
    return out


def _lower_bound(cost: FloatArray) -> float:
    """A lower bound of any assignment's cost: the sum of the smaller side's minima."""
    if cost.size == 0:
        return 0.0
    axis = 1 if cost.shape[0] <= cost.shape[1] else 0
    return float(cost.min(axis=axis).sum())


def subset_sums(penalties: Sequence[float]) -> Iterator[tuple[float, tuple[int, ...]]]:
    """All subsets of non-negative ``penalties`` in nondecreasing sum, lazily.

    Yields ``(sum, indices)`` starting with the empty set. Each subset comes exactly once:
    from a subset whose largest sorted position is i, the successors are "add i+1" and
    "replace i by i+1". Subsets with an infinite penalty (an impossible label) are never
    yielded.
    """
    order = sorted(range(len(penalties)), key=lambda i: penalties[i])
    vals = [float(penalties[i]) for i in order]
    if any(v < 0 for v in vals):
        raise ValueError("penalties must be non-negative")
    yield 0.0, ()
    vals = [v for v in vals if v != math.inf]
    if not vals:
        return
    heap: list[tuple[float, int, tuple[int, ...]]] = [(vals[0], 0, (0,))]
    while heap:
        s, i, subset = heapq.heappop(heap)
        yield s, tuple(sorted(order[x] for x in subset))
        if i + 1 < len(vals):
            heapq.heappush(heap, (s + vals[i + 1], i + 1, (*subset, i + 1)))
            heapq.heappush(heap, (s - vals[i] + vals[i + 1], i + 1, (*subset[:-1], i + 1)))
