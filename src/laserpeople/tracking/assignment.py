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
from scipy.optimize import linear_sum_assignment

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]
BoolArray = NDArray[np.bool_]


@dataclass(frozen=True, eq=False)
class Assignment:
    """One solution of an assignment problem.

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
    try:
        rows, cols = linear_sum_assignment(cost)
    except ValueError:  # scipy: "cost matrix is infeasible"
        return None
    total = float(cost[rows, cols].sum())
    if total == np.inf:
        return None
    return Assignment(total, rows, cols)


@dataclass(eq=False)
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
        if self.front_solved():
            return
        bound, _, node = heapq.heappop(self._heap)
        if node.matrix is None:
            node.solution = self._solve_sub(node.forced, node.forbidden)
        else:
            node.solution = solve(node.matrix)
        self.n_solved += 1
        if node.solution is not None:
            self._push(bound, node)

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
        forced_set = set(node.forced)
        key_pairs = [
            (r, c)
            for r, c in zip(sol.rows.tolist(), sol.cols.tolist(), strict=True)
            if self.key[r, c] and (r, c) not in forced_set
        ]
        forced = node.forced
        if not self.incremental:
            for pair in key_pairs:
                self._push(sol.cost, _Node(None, forced, (*node.forbidden, pair)))
                forced = (*forced, pair)
            return sol
        # the subproblems' matrices, each from the previous one: forbid the next pair,
        # force it for the ones after (the same matrices as built from the base, since the
        # forced pairs have distinct rows and columns and are never forbidden)
        matrix = node.matrix
        if matrix is None:
            matrix = _constrained(self.cost, node.forced, node.forbidden)
        node.matrix = None
        last = len(key_pairs) - 1
        for t, (r, c) in enumerate(key_pairs):
            sub = matrix.copy()
            sub[r, c] = np.inf
            self._push(sol.cost, _Node(None, forced, (*node.forbidden, (r, c)), sub))
            forced = (*forced, (r, c))
            if t < last:
                matrix = matrix.copy() if t == 0 else matrix
                keep = matrix[r, c]
                matrix[r, :] = np.inf
                matrix[:, c] = np.inf
                matrix[r, c] = keep
        return sol

    def __iter__(self) -> Iterator[Assignment]:
        while (sol := self.pop()) is not None:
            yield sol


@dataclass(eq=False, slots=True)
class _Sub:
    """A subproblem of :class:`BoundedMurtyStream`: subproblem ``t`` of the solution of
    its parent subproblem, whose matrix is ``parent`` and unforced key pairs ``pairs``
    (it forces ``pairs[:t]`` and forbids ``pairs[t]``); a lower bound of its best cost; and
    once solved, its matrix and best solution."""

    parent: FloatArray
    pairs: list[tuple[int, int]]
    t: int
    forced: tuple[tuple[int, int], ...]
    forbidden: tuple[tuple[int, int], ...]
    lower: float
    matrix: FloatArray | None = None
    solution: Assignment | None = None

    def build(self) -> FloatArray:
        """The subproblem's matrix: what :meth:`MurtyStream.pop`'s chain of siblings makes
        (the same entries: the parent's, or inf)."""
        out = self.parent.copy()
        for r, c in self.pairs[: self.t]:
            keep = out[r, c]
            out[r, :] = np.inf
            out[:, c] = np.inf
            out[r, c] = keep
        r, c = self.pairs[self.t]
        out[r, c] = np.inf
        return out


class BoundedMurtyStream:
    """:class:`MurtyStream` (incremental), seen from outside exactly: the same
    :meth:`peek_cost`, :meth:`front_solved` and :attr:`n_solved` after every call and the
    same solutions from :meth:`pop` in the same order, equal costs included; but a
    subproblem :class:`MurtyStream` would have solved is only solved when its solution is
    needed (to know the cost of the front, or the order of two subproblems).

    :class:`MurtyStream` queues the subproblems of a popped solution at that solution's
    cost and solves each as it reaches its front; a caller merging streams
    (:func:`~laserpeople.tracking.mht.matrix.k_best_children`) refines a stream whose front
    is unsolved, so nearly every subproblem queued is solved, although few of their
    solutions are ever popped. Here a refined subproblem is only marked solved: its entry
    gets the counter :class:`MurtyStream` gives its solution and waits at a lower bound of
    its cost (:func:`sibling_bounds`, from the dual solution of the popped solution; inf:
    infeasible). The front of the marked entries is solved when it could come before the
    front of the unmarked ones, or is popped. Entries compare as ``(cost, counter)`` in
    both classes and a bound is never above its cost, so the front is the same.

    :attr:`n_solved` counts the subproblems :class:`MurtyStream` would have solved (what a
    caller's budget counts), :attr:`n_assignments` those solved here.

    Args:
        cost: (R, C) cost matrix, ``inf`` = infeasible pair (square: bounds; otherwise
            every subproblem waits at its parent's cost, and is solved when refined).
        key: (R, C) mask of the pairs that identify a solution (default: all pairs).
    """

    def __init__(self, cost: FloatArray, key: BoolArray | None = None) -> None:
        self.cost = np.asarray(cost, dtype=np.float64)
        self.key = np.ones(self.cost.shape, dtype=bool) if key is None else np.asarray(key)
        if self.key.shape != self.cost.shape:
            raise ValueError(f"key shape {self.key.shape} != cost shape {self.cost.shape}")
        self._counter = itertools.count()
        # MurtyStream's unsolved entries: (bound, counter, subproblem)
        self._open: list[tuple[float, int, _Sub]] = []
        # its solved ones: (cost, or a lower bound while not solved here, counter, sub)
        self._marked: list[tuple[float, int, _Sub]] = []
        self.n_solved = 0
        self.n_assignments = 0
        root = _Sub(self.cost, [], 0, (), (), -math.inf, matrix=self.cost)
        self._open.append((0.0, next(self._counter), root))
        self._known: tuple[float, bool] | None = None  # the front until the queues change

    def _marked_front(self, limit: tuple[float, int] | None) -> tuple[float, int] | None:
        """The front entry of the marked ones when it comes before ``limit`` (the front of
        the unmarked ones; None: there is none), else None; solves marked subproblems
        (dropping the infeasible ones) until that is known."""
        marked = self._marked
        while marked:
            value, count, sub = marked[0]
            if sub.solution is not None:
                return (value, count) if limit is None or (value, count) < limit else None
            if limit is not None and (value, count) > limit:
                return None
            heapq.heappop(marked)
            if sub.matrix is None:
                sub.matrix = sub.build()
            self.n_assignments += 1
            sol = solve(sub.matrix)
            if sol is not None:
                sub.solution = sol
                heapq.heappush(marked, (sol.cost, count, sub))
        return None

    def _front(self) -> tuple[float, bool]:
        """MurtyStream's front: its cost (or bound) and whether it is solved."""
        if self._known is None:
            limit = (self._open[0][0], self._open[0][1]) if self._open else None
            front = self._marked_front(limit)
            if front is not None:
                self._known = (front[0], True)
            elif limit is not None:
                self._known = (limit[0], False)
            else:
                self._known = (math.inf, True)
        return self._known

    def peek_cost(self) -> float:
        """As :meth:`MurtyStream.peek_cost`."""
        return self._front()[0]

    def front_solved(self) -> bool:
        """As :meth:`MurtyStream.front_solved`."""
        return self._front()[1]

    def refine(self) -> None:
        """As :meth:`MurtyStream.refine` (the subproblem is marked solved, see above)."""
        if self.front_solved():
            return
        self._known = None
        bound, _, sub = heapq.heappop(self._open)
        self.n_solved += 1
        count = next(self._counter)  # the counter MurtyStream gives its solution
        if sub.lower < math.inf:
            heapq.heappush(self._marked, (max(bound, sub.lower), count, sub))

    def pop(self) -> Assignment | None:
        """As :meth:`MurtyStream.pop`."""
        while not self.front_solved():
            self.refine()
        if not self._marked:
            return None
        self._known = None
        _, _, sub = heapq.heappop(self._marked)  # (solved: _front made sure)
        sol, matrix = sub.solution, sub.matrix
        assert sol is not None and matrix is not None
        forced_set = set(sub.forced)
        pairs = [
            (r, c)
            for r, c in zip(sol.rows.tolist(), sol.cols.tolist(), strict=True)
            if self.key[r, c] and (r, c) not in forced_set
        ]
        if not pairs:
            return sol
        if matrix.shape[0] == matrix.shape[1]:
            bounds = sibling_bounds(matrix, sol, pairs)
        else:
            bounds = [-math.inf] * len(pairs)
        forced = sub.forced
        for t, pair in enumerate(pairs):
            child = _Sub(matrix, pairs, t, forced, (*sub.forbidden, pair), bounds[t])
            heapq.heappush(self._open, (sol.cost, next(self._counter), child))
            forced = (*forced, pair)
        return sol

    def __iter__(self) -> Iterator[Assignment]:
        while (sol := self.pop()) is not None:
            yield sol


def optimal_duals(cost: FloatArray, cols: IntArray) -> tuple[FloatArray, FloatArray] | None:
    """Dual variables ``(u, v)`` of the optimal assignment row i -> ``cols[i]`` of the
    square matrix ``cost``: ``u_i + v_j <= cost_ij`` everywhere, with equality on the
    assignment, so their sum is its cost. ``v`` are shortest distances in the graph of
    reassignments (column ``cols[i]`` -> column j at ``cost_ij - cost_i,cols[i]``), by
    Bellman-Ford from 0; None when that does not settle in N rounds (rounding in an
    assignment that is optimal only up to it)."""
    n = cost.shape[0]
    on = cost[np.arange(n), cols]
    step = cost - on[:, None]  # (inf where cost is)
    v = np.minimum(step.min(axis=0), 0.0)  # (the first round, from 0)
    for _ in range(n):
        nxt = np.minimum(v, (v[cols][:, None] + step).min(axis=0))
        if not (nxt < v).any():
            return on - v[cols], v
        v = nxt
    return None


def sibling_bounds(
    matrix: FloatArray, sol: Assignment, pairs: list[tuple[int, int]]
) -> list[float]:
    """Lower bounds of the best costs of the subproblems of ``sol`` (the optimal assignment
    of the square ``matrix``) whose unforced key pairs are ``pairs``: subproblem t forces
    ``pairs[:t]`` and forbids ``pairs[t]`` (Murty); inf when it has no assignment.

    With optimal duals ``(u, v)`` (:func:`optimal_duals`; their sum is ``sol.cost``) and
    reduced costs ``R = cost - u - v >= 0``, subproblem t's row ``r_t`` must take another
    column than those of ``pairs[:t + 1]``, and column ``c_t`` another row than theirs:
    raising ``u_r`` by the least such ``R`` in the row, then ``v_c`` by the least in the
    column keeps the duals feasible for the subproblem, so its cost is at least ``sol.cost``
    plus both (Miller, Stone and Cox 1997). Lowered by a relative 1e-9 (rounding of the
    duals); ``-inf`` for all when the duals cannot be had."""
    k, n = len(pairs), matrix.shape[0]
    duals = optimal_duals(matrix, sol.col_of_row(n))
    if duals is None:
        return [-math.inf] * k
    u, v = duals
    rs = np.array([p[0] for p in pairs], dtype=np.intp)
    cs = np.array([p[1] for p in pairs], dtype=np.intp)
    order = np.arange(k)[:, None]
    col_pos = np.full(n, k)
    col_pos[cs] = order[:, 0]
    row_pos = np.full(n, k)
    row_pos[rs] = order[:, 0]
    # reduced costs of row r_t (K, N) and of column c_t (K, N), without what t rules out
    in_row = np.where(col_pos <= order, np.inf, matrix[rs] - u[rs, None] - v)
    in_col = np.where(row_pos <= order, np.inf, matrix[:, cs].T - u - v[cs, None])
    lower = (sol.cost + in_row.min(axis=1) + in_col.min(axis=1)).tolist()
    return [b - 1e-9 * (1.0 + abs(b)) if b < math.inf else math.inf for b in lower]


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
