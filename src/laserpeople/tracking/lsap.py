"""Compiled rectangular linear assignment with its optimal dual solution (numba).

The shortest augmenting path method (Crouse 2016, "On implementing 2D rectangular
assignment algorithms", IEEE TAES 52(4), Sec. IV.B): rows are added one at a time; for
each, a Dijkstra search over the columns with reduced costs ``c_ij - u_i - v_j`` finds the
cheapest augmenting path to a free column, the duals are raised so that the path's pairs
stay tight, and the path is flipped. The duals are kept feasible throughout, so on return
``u_i + v_j <= c_ij`` for every pair, with equality on the assignment, and ``v_j = 0`` on
the columns left free (the dual of "every row assigned, every column at most once").

Ties are broken as :func:`scipy.optimize.linear_sum_assignment` breaks them (the columns
scanned from the last to the first, a remaining column replaced by the last one when it is
settled, the first column of least reduced cost taken unless a later one of equal cost is
free), so both return the same assignment for the same matrix, ties included; the tests
check that on random matrices with many ties. The cost is summed in the order numpy's
``sum`` uses (pairwise, eight partial sums), so it is the same float too.

This module imports numba (~0.4 s) and compiles on first use (cached in ``__pycache__``
next to this file, or numba's user cache when that is read-only): import it only where an
assignment is solved (:mod:`laserpeople.tracking.assignment` does so on first use).
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]

OK = 0
"""Status: solved."""
INFEASIBLE = 1
"""Status: no assignment of finite cost covers the smaller side."""
INVALID = 2
"""Status: the matrix holds NaN or -inf."""


@njit(cache=True)
def _block_sum(values: FloatArray, lo: int, n: int) -> float:  # pragma: no cover - jit
    """Sum of ``values[lo:lo + n]``, n <= 128, in numpy's order: plain below 8 terms,
    else eight partial sums, combined pairwise, then the rest added one by one."""
    if n < 8:
        out = 0.0
        for i in range(lo, lo + n):
            out += values[i]
        return out
    r0 = values[lo]
    r1 = values[lo + 1]
    r2 = values[lo + 2]
    r3 = values[lo + 3]
    r4 = values[lo + 4]
    r5 = values[lo + 5]
    r6 = values[lo + 6]
    r7 = values[lo + 7]
    i = 8
    stop = n - n % 8
    while i < stop:
        r0 += values[lo + i]
        r1 += values[lo + i + 1]
        r2 += values[lo + i + 2]
        r3 += values[lo + i + 3]
        r4 += values[lo + i + 4]
        r5 += values[lo + i + 5]
        r6 += values[lo + i + 6]
        r7 += values[lo + i + 7]
        i += 8
    out = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        out += values[lo + i]
        i += 1
    return out


@njit(cache=True)
def _half(n: int) -> int:  # pragma: no cover - jit
    """Where numpy splits a sum of n > 128 terms: half, down to a multiple of 8."""
    half = n // 2
    return half - half % 8


@njit(cache=True)
def pairwise_sum(values: FloatArray) -> float:  # pragma: no cover - jit
    """Sum of the contiguous float64 ``values`` (N,) in numpy's order (``np.add.reduce``:
    blocks of at most 128 terms, :func:`_block_sum`, halved recursively above that; here
    with an explicit stack, as numba cannot cache a recursive function)."""
    n = values.shape[0]
    if n <= 128:
        return _block_sum(values, 0, n)
    depth = 64
    los = np.empty(depth, dtype=np.intp)
    ns = np.empty(depth, dtype=np.intp)
    stage = np.empty(depth, dtype=np.intp)  # 0: left half pending, 1: right half pending
    left = np.empty(depth)
    los[0] = 0
    ns[0] = n
    stage[0] = 0
    sp = 1
    val = 0.0
    while sp > 0:
        top = sp - 1
        m = ns[top]
        if m > 128:  # descend into the left half
            los[sp] = los[top]
            ns[sp] = _half(m)
            stage[sp] = 0
            sp += 1
            continue
        val = _block_sum(values, los[top], m)
        sp -= 1
        while sp > 0:  # hand the value up until a right half is pending
            parent = sp - 1
            if stage[parent] == 0:
                left[parent] = val
                stage[parent] = 1
                half = _half(ns[parent])
                los[sp] = los[parent] + half
                ns[sp] = ns[parent] - half
                stage[sp] = 0
                sp += 1
                break
            val = left[parent] + val
            sp -= 1
    return val


@njit(cache=True)
def _solve_wide(
    cost: FloatArray, col4row: IntArray, u: FloatArray, v: FloatArray
) -> int:  # pragma: no cover - jit
    """Solve the (R, C) problem ``cost`` with R <= C in place: ``col4row`` (R,) gets each
    row's column, ``u`` (R,) and ``v`` (C,) the optimal duals (all three are overwritten).
    Returns a status (:data:`OK`, :data:`INFEASIBLE`, :data:`INVALID`).

    Written with plain loops (no slicing or numpy calls): numba compiles them several
    times faster, which is what a first run without a cache pays."""
    n_rows, n_cols = cost.shape
    for i in range(n_rows):
        for j in range(n_cols):
            c = cost[i, j]
            if c != c or c == -np.inf:
                return INVALID
    row4col = np.empty(n_cols, dtype=np.intp)
    pred = np.empty(n_cols, dtype=np.intp)  # the row before each column on its path
    dist = np.empty(n_cols)  # reduced length of the shortest path to each column
    todo = np.empty(n_cols, dtype=np.intp)  # columns not yet settled
    row_seen = np.empty(n_rows, dtype=np.bool_)
    col_seen = np.empty(n_cols, dtype=np.bool_)
    for i in range(n_rows):
        u[i] = 0.0
        col4row[i] = -1
    for j in range(n_cols):
        v[j] = 0.0
        row4col[j] = -1
    for start in range(n_rows):
        for j in range(n_cols):
            todo[j] = n_cols - 1 - j
            dist[j] = np.inf
            col_seen[j] = False
        for i in range(n_rows):
            row_seen[i] = False
        n_todo = n_cols
        reach = 0.0  # length of the path to the last settled column
        row = start
        sink = -1
        while sink < 0:
            row_seen[row] = True
            best = -1
            least = np.inf
            ui = u[row]
            for k in range(n_todo):
                j = todo[k]
                d = reach + cost[row, j] - ui - v[j]
                if d < dist[j]:
                    pred[j] = row
                    dist[j] = d
                dj = dist[j]
                if dj < least or (dj == least and row4col[j] < 0):
                    least = dj
                    best = k
            reach = least
            if reach == np.inf:
                return INFEASIBLE
            j = todo[best]
            col_seen[j] = True
            n_todo -= 1
            todo[best] = todo[n_todo]
            if row4col[j] < 0:
                sink = j
            else:
                row = row4col[j]
        # duals: every settled row and column moves by how much shorter its path was
        u[start] += reach
        for i in range(n_rows):
            if row_seen[i] and i != start:
                u[i] += reach - dist[col4row[i]]
        for j in range(n_cols):
            if col_seen[j]:
                v[j] -= reach - dist[j]
        # flip the path
        j = sink
        while True:
            i = pred[j]
            row4col[j] = i
            prev = col4row[i]
            col4row[i] = j
            j = prev
            if i == start:
                break
    return OK


@njit(cache=True)
def _solve(
    cost: FloatArray, rows: IntArray, cols: IntArray, u: FloatArray, v: FloatArray
) -> tuple[int, float]:  # pragma: no cover - jit
    """Solve the C-contiguous (R, C) problem ``cost`` into ``rows``, ``cols`` (L,),
    L = min(R, C) (rows increasing, as scipy returns them), and the duals ``u`` (R,),
    ``v`` (C,). Returns the status and the cost (numpy's summation order)."""
    n_rows, n_cols = cost.shape
    size = min(n_rows, n_cols)
    if size == 0:
        for i in range(n_rows):
            u[i] = 0.0
        for j in range(n_cols):
            v[j] = 0.0
        return OK, 0.0
    if n_rows <= n_cols:
        status = _solve_wide(cost, cols, u, v)
        if status != OK:
            return status, 0.0
        for i in range(n_rows):
            rows[i] = i
    else:  # solve the transpose; list the pairs by row
        tall = np.empty((n_cols, n_rows))
        for i in range(n_rows):
            for j in range(n_cols):
                tall[j, i] = cost[i, j]
        row4col = np.empty(n_cols, dtype=np.intp)
        status = _solve_wide(tall, row4col, v, u)
        if status != OK:
            return status, 0.0
        col4row = np.empty(n_rows, dtype=np.intp)
        for i in range(n_rows):
            col4row[i] = -1
        for j in range(n_cols):
            col4row[row4col[j]] = j
        k = 0
        for i in range(n_rows):
            if col4row[i] >= 0:
                rows[k] = i
                cols[k] = col4row[i]
                k += 1
    picked = np.empty(size)
    for k in range(size):
        picked[k] = cost[rows[k], cols[k]]
    return status, pairwise_sum(picked)


@njit(cache=True)
def solve_duals(
    cost: FloatArray,
) -> tuple[int, IntArray, IntArray, float, FloatArray, FloatArray]:  # pragma: no cover - jit
    """The minimum-cost assignment of the C-contiguous (R, C) matrix ``cost`` and its dual
    solution.

    Returns:
        ``(status, rows, cols, total, u, v)``: rows (L,) increasing and their columns (L,),
        L = min(R, C), as :func:`scipy.optimize.linear_sum_assignment` returns them; total,
        the sum of the chosen entries (numpy's summation order); the optimal duals u (R,),
        v (C,) with ``u_i + v_j <= cost_ij`` (up to rounding), equal on the chosen pairs and
        0 on the rows (R > C) or columns (R < C) left out. Unless status is :data:`OK`, the
        rest is undefined.
    """
    n_rows, n_cols = cost.shape
    size = min(n_rows, n_cols)
    rows = np.empty(size, dtype=np.intp)
    cols = np.empty(size, dtype=np.intp)
    u = np.empty(n_rows)
    v = np.empty(n_cols)
    status, total = _solve(cost, rows, cols, u, v)
    return status, rows, cols, total, u, v


@njit(cache=True)
def murty_children(
    matrix: FloatArray, pair_rows: IntArray, pair_cols: IntArray
) -> tuple[FloatArray, IntArray, IntArray, IntArray, FloatArray]:  # pragma: no cover - jit
    """Murty's subproblems of one solution, made and solved.

    Subproblem t forbids pair t and forces pairs 0..t-1 (the forced pair's row and column
    set to inf except the pair itself), all on ``matrix``.

    Args:
        matrix: (R, C) C-contiguous cost matrix of the solved (sub)problem, inf =
            infeasible.
        pair_rows: (K,) rows of the solution's pairs to partition on, in order.
        pair_cols: (K,) their columns.

    Returns:
        ``(matrices, status, rows, cols, costs)``: the subproblems' matrices (K, R, C),
        status (K,) (:data:`OK` or not), each one's best assignment rows (K, L) and
        columns (K, L), L = min(R, C) (as :func:`solve_duals`; undefined where the status
        is not :data:`OK`), and its cost (K,).
    """
    n_rows, n_cols = matrix.shape
    n_sub = pair_rows.shape[0]
    size = min(n_rows, n_cols)
    mats = np.empty((n_sub, n_rows, n_cols))
    status = np.empty(n_sub, dtype=np.intp)
    rows = np.empty((n_sub, size), dtype=np.intp)
    cols = np.empty((n_sub, size), dtype=np.intp)
    costs = np.empty(n_sub)
    u = np.empty(n_rows)
    v = np.empty(n_cols)
    chain = np.empty((n_rows, n_cols))  # the earlier pairs forced
    for i in range(n_rows):
        for j in range(n_cols):
            chain[i, j] = matrix[i, j]
    for t in range(n_sub):
        r = pair_rows[t]
        c = pair_cols[t]
        sub = mats[t]
        for i in range(n_rows):
            for j in range(n_cols):
                sub[i, j] = chain[i, j]
        sub[r, c] = np.inf
        status[t], costs[t] = _solve(sub, rows[t], cols[t], u, v)
        for j in range(n_cols):
            if j != c:
                chain[r, j] = np.inf
        for i in range(n_rows):
            if i != r:
                chain[i, c] = np.inf
    return mats, status, rows, cols, costs
