"""The assignment matrix of one parent hypothesis (000 Table 9, with occlusion as its own
label, 000 Sec. 3.3.1) and the k best labelled assignments over several parents.

Every entry is a cost, -log of a factor of 000 eq. 15. A track is *detected* (matched to a
gated measurement: ``-(log p_det|class + log N(z; z_hat, S))``), *occluded*
(``-log p_occ|class``) or *deleted* (``-log p_del|class``); a measurement is *matched*, a
*new* track (``-log lambda_new``) or a *false alarm* (``-log lambda_fal``). A hypothesis's
cost is the sum of its entries, so ``exp(-cost)`` is eq. 15 without the parent and without
the constant eta''.

The two unmatched labels of a track (occluded/deleted), and those of a measurement
(new/false alarm), do not interact with the rest of the assignment. The square matrix of
size n + m therefore holds the *matching* only, with the cheaper unmatched label of every
track and measurement on the diagonals of its off-diagonal blocks (Cox & Hingorani's
layout); Murty enumerates matchings, and each matching expands into its label variants in
nondecreasing cost (switching an unmatched item to its dearer label adds a fixed penalty;
:func:`~laserpeople.tracking.assignment.subset_sums`). Merging all parents' matching streams
and all matchings' variant streams in one priority queue yields the k globally best
children (the multi-parent form, 000 Sec. 4.5.2) with far fewer assignment solves than a
matrix with one column per label.
"""

from __future__ import annotations

import heapq
import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracking.assignment import MurtyStream, subset_sums
from laserpeople.tracking.mht.probability import (
    DELETED,
    DETECTED,
    FALSE_ALARM,
    MATCHED,
    NEW,
    OCCLUDED,
)

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]
BoolArray = NDArray[np.bool_]


@dataclass(frozen=True, eq=False)
class AssignmentMatrix:
    """One parent's assignment problem, as plain lists (clusters are small; list access is
    faster than numpy for them).

    Attributes:
        track_meas_cost: n rows of m costs of matching track i with measurement j (inf
            outside the gate).
        options: Per track, the measurements in its gate.
        track_unmatched: Per track, the cheaper unmatched label (OCCLUDED or DELETED).
        track_unmatched_cost: Its cost.
        track_penalty: Extra cost of the other unmatched label (>= 0, inf if impossible).
        meas_unmatched: Per measurement, the cheaper unmatched label (NEW/FALSE_ALARM).
        meas_unmatched_cost: Its cost.
        meas_penalty: Extra cost of the other one (>= 0, inf if impossible).
        base: The problem this one is a :meth:`subset` of (None: made directly).
        base_rows: The tracks of ``base`` this one holds, in order.
    """

    track_meas_cost: list[list[float]]
    options: list[list[int]]
    track_unmatched: list[int]
    track_unmatched_cost: list[float]
    track_penalty: list[float]
    meas_unmatched: list[int]
    meas_unmatched_cost: list[float]
    meas_penalty: list[float]
    base: AssignmentMatrix | None = field(default=None, repr=False)
    base_rows: tuple[int, ...] = ()
    _squares: dict[int, tuple[FloatArray, BoolArray]] = field(
        default_factory=dict, repr=False, compare=False
    )

    @property
    def n_tracks(self) -> int:
        """n."""
        return len(self.track_unmatched)

    @property
    def n_measurements(self) -> int:
        """m."""
        return len(self.meas_unmatched)

    def subset(self, rows: Sequence[int]) -> AssignmentMatrix:
        """The problem of the tracks ``rows`` only (same measurements); its :meth:`square`
        is taken from this one's, made once for all the subsets."""
        return AssignmentMatrix(
            [self.track_meas_cost[r] for r in rows],
            [self.options[r] for r in rows],
            [self.track_unmatched[r] for r in rows],
            [self.track_unmatched_cost[r] for r in rows],
            [self.track_penalty[r] for r in rows],
            self.meas_unmatched,
            self.meas_unmatched_cost,
            self.meas_penalty,
            self,
            tuple(rows),
        )

    def square(self) -> tuple[FloatArray, BoolArray]:
        """The (n + m) square matching matrix and its identifying-pairs mask.

        Rows ``[tracks | measurement slots]``, columns ``[measurements | track slots]``:
        track i unmatched = (i, m + i), measurement j unmatched = (n + j, j), slot-slot
        pairs cost 0 (Cox & Hingorani's layout). Only pairs in track rows and measurement
        columns identify a matching; the zero-cost slot pairings do not.
        """
        made = self._squares.get(0)
        if made is not None:
            return made
        n, m = self.n_tracks, self.n_measurements
        if self.base is not None:
            # the base's square with the rows [these tracks | every measurement slot] and
            # the columns [every measurement | these tracks' slots]: the same entries
            full, _ = self.base.square()
            base_n = self.base.n_tracks
            rows = np.array([*self.base_rows, *range(base_n, base_n + m)], dtype=np.intp)
            cols = np.array([*range(m), *(m + i for i in self.base_rows)], dtype=np.intp)
            cost = full.take(rows, axis=0).take(cols, axis=1)
        else:
            size = n + m
            cost = np.full((size, size), np.inf)
            if n and m:
                cost[:n, :m] = np.array(self.track_meas_cost, dtype=np.float64).reshape(n, m)
            cost[np.arange(n), m + np.arange(n)] = self.track_unmatched_cost
            cost[n + np.arange(m), np.arange(m)] = self.meas_unmatched_cost
            cost[n:, m:] = 0.0
        cost.flags.writeable = False  # shared by the streams of this problem
        made = self._squares[0] = (cost, _square_key(n, m))
        return made

    def lower_bound(self) -> float:
        """A lower bound of the cost of every matching: the larger of "every track at its
        cheapest entry, plus every measurement's unmatched cost where negative" and the
        same from the measurements' side."""
        rows = 0.0
        col_min = list(self.meas_unmatched_cost)
        for row, opts, unmatched in zip(
            self.track_meas_cost, self.options, self.track_unmatched_cost, strict=True
        ):
            best = unmatched
            for j in opts:
                c = row[j]
                if c < best:
                    best = c
                if c < col_min[j]:
                    col_min[j] = c
            rows += best
        by_rows = rows + sum(min(0.0, c) for c in self.meas_unmatched_cost)
        by_cols = sum(col_min) + sum(min(0.0, c) for c in self.track_unmatched_cost)
        return max(by_rows, by_cols)


_SQUARE_KEYS: dict[tuple[int, int], BoolArray] = {}


def _square_key(n: int, m: int) -> BoolArray:
    """The identifying-pairs mask of :meth:`AssignmentMatrix.square` for n tracks and m
    measurements: track rows and measurement columns (read-only, shared)."""
    key = _SQUARE_KEYS.get((n, m))
    if key is None:
        key = np.zeros((n + m, n + m), dtype=bool)
        key[:n, :] = True
        key[:, :m] = True
        key.flags.writeable = False
        _SQUARE_KEYS[(n, m)] = key
    return key


def build_matrix(
    track_meas_cost: FloatArray,
    track_label_log_probs: FloatArray,
    log_lambda_new: FloatArray,
    log_lambda_fal: FloatArray,
) -> AssignmentMatrix:
    """Assemble a parent's assignment problem.

    Args:
        track_meas_cost: (n, m) ``-(log p_det + log N)`` for gated pairs, inf elsewhere.
        track_label_log_probs: (n, 3) log p of detected/occluded/deleted per track.
        log_lambda_new: (m,) log new-track density per measurement [log 1/m^2].
        log_lambda_fal: (m,) log false-alarm density per measurement [log 1/m^2].
    """
    tm = np.asarray(track_meas_cost, dtype=np.float64)
    n = tm.shape[0]
    c_occ = -track_label_log_probs[:, OCCLUDED]
    c_del = -track_label_log_probs[:, DELETED]
    c_new = -np.asarray(log_lambda_new, dtype=np.float64)
    c_fal = -np.asarray(log_lambda_fal, dtype=np.float64)
    options: list[list[int]] = [[] for _ in range(n)]
    for i, j in zip(*np.nonzero(np.isfinite(tm)), strict=True):
        options[int(i)].append(int(j))
    return AssignmentMatrix(
        track_meas_cost=tm.tolist(),
        options=options,
        track_unmatched=np.where(c_occ <= c_del, OCCLUDED, DELETED).tolist(),
        track_unmatched_cost=np.minimum(c_occ, c_del).tolist(),
        track_penalty=_penalty(c_occ, c_del).tolist(),
        meas_unmatched=np.where(c_fal <= c_new, FALSE_ALARM, NEW).tolist(),
        meas_unmatched_cost=np.minimum(c_new, c_fal).tolist(),
        meas_penalty=_penalty(c_new, c_fal).tolist(),
    )


def _penalty(a: FloatArray, b: FloatArray) -> FloatArray:
    """Extra cost of the dearer of two labels; inf when it is impossible (inf cost), also
    when both are (then no variant exists anyway)."""
    with np.errstate(invalid="ignore"):
        return np.where(np.isfinite(a) & np.isfinite(b), np.abs(a - b), np.inf)


@dataclass(frozen=True, eq=False)
class Matching:
    """Which measurement each track is matched with.

    Attributes:
        cost: Total cost with every unmatched item at its cheaper label.
        track_meas: Local measurement index per track (n values), -1 when unmatched.
    """

    cost: float
    track_meas: tuple[int, ...]


def enumerate_matchings(matrix: AssignmentMatrix, limit: int) -> list[Matching] | None:
    """All matchings of finite cost sorted by cost, or None when there could be more than
    ``limit`` (then Murty's method is used). Small clusters are the common case;
    enumerating them directly avoids dozens of assignment solves."""
    options = matrix.options
    count = 1
    for o in options:
        count *= len(o) + 1
        if count > limit:
            return None
    n, m = matrix.n_tracks, matrix.n_measurements
    tu = matrix.track_unmatched_cost
    mu = matrix.meas_unmatched_cost
    tml = matrix.track_meas_cost
    out: list[Matching] = []
    choice = [-1] * n
    used = [False] * m

    def rec(i: int, cost: float) -> None:
        if i == n:
            if cost < math.inf:
                out.append(Matching(cost, tuple(choice)))
            return
        choice[i] = -1
        rec(i + 1, cost + tu[i])
        for j in options[i]:
            if not used[j]:
                used[j] = True
                choice[i] = j
                rec(i + 1, cost + tml[i][j] - mu[j])
                used[j] = False
        choice[i] = -1

    rec(0, math.fsum(mu))
    out.sort(key=lambda mt: mt.cost)
    return out


class _MatchingStream:
    """Matchings of one parent in nondecreasing cost: a sorted list for small problems,
    lazy Murty on the square matrix otherwise."""

    def __init__(self, matrix: AssignmentMatrix, enumerate_limit: int) -> None:
        self.matrix = matrix
        listed = enumerate_matchings(matrix, enumerate_limit)
        self._list = listed
        self._pos = 0
        self._murty: MurtyStream | None = None
        if listed is None:
            cost, key = matrix.square()
            self._murty = MurtyStream(cost, key)

    def peek_cost(self) -> float:
        if self._murty is not None:
            return self._murty.peek_cost()
        assert self._list is not None
        return self._list[self._pos].cost if self._pos < len(self._list) else np.inf

    def front_solved(self) -> bool:
        return self._murty.front_solved() if self._murty is not None else True

    def refine(self) -> bool:
        """Solve the front subproblem; whether an assignment problem was solved."""
        if self._murty is not None and not self._murty.front_solved():
            self._murty.refine()
            return True
        return False

    def pop(self) -> Matching:
        if self._murty is not None:
            sol = self._murty.pop()
            assert sol is not None
            n, m = self.matrix.n_tracks, self.matrix.n_measurements
            # square: every row is assigned, so the rows are 0..n+m-1 and the first n
            # columns are the tracks'
            col_of_row = sol.cols[:n].tolist()
            return Matching(sol.cost, tuple(c if c < m else -1 for c in col_of_row))
        assert self._list is not None
        out = self._list[self._pos]
        self._pos += 1
        return out


@dataclass(eq=False, slots=True)
class LabelledAssignment:
    """The labels one child hypothesis gives (not frozen: one is made per child listed, and
    a frozen dataclass costs several times as much to make; nothing changes it).

    Attributes:
        track_label: Per track: DETECTED / OCCLUDED / DELETED.
        track_measurement: Per track: local measurement index if detected, -1 else.
        measurement_label: Per measurement: MATCHED / NEW / FALSE_ALARM.
        cost: Cost of the assignment (without the parent's).
    """

    track_label: list[int]
    track_measurement: tuple[int, ...]
    measurement_label: list[int]
    cost: float


def unmatched_items(matrix: AssignmentMatrix, matching: Matching) -> tuple[list[int], list[int]]:
    """Unmatched tracks and unmatched measurements of a matching (local indices)."""
    matched = set(matching.track_meas)
    tracks = [i for i, j in enumerate(matching.track_meas) if j < 0]
    meas = [j for j in range(matrix.n_measurements) if j not in matched]
    return tracks, meas


def decode(
    matrix: AssignmentMatrix, matching: Matching, flipped: Sequence[int] = (), extra: float = 0.0
) -> LabelledAssignment:
    """Labels of a matching with the unmatched items at positions ``flipped`` (indices into
    the concatenation of :func:`unmatched_items`) switched to their dearer label."""
    tu = matrix.track_unmatched
    mu = matrix.meas_unmatched
    track_label = [DETECTED if j >= 0 else tu[i] for i, j in enumerate(matching.track_meas)]
    matched = set(matching.track_meas)
    meas_label = [MATCHED if j in matched else mu[j] for j in range(len(mu))]
    if flipped:
        tracks_u, meas_u = unmatched_items(matrix, matching)
        for f in flipped:
            if f < len(tracks_u):
                i = tracks_u[f]
                track_label[i] = DELETED if track_label[i] == OCCLUDED else OCCLUDED
            else:
                j = meas_u[f - len(tracks_u)]
                meas_label[j] = NEW if meas_label[j] == FALSE_ALARM else FALSE_ALARM
    return LabelledAssignment(track_label, matching.track_meas, meas_label, matching.cost + extra)


def _penalties(matrix: AssignmentMatrix, matching: Matching) -> list[float]:
    tracks_u, meas_u = unmatched_items(matrix, matching)
    tp = matrix.track_penalty
    mp = matrix.meas_penalty
    return [*(tp[i] for i in tracks_u), *(mp[j] for j in meas_u)]


@dataclass
class Work:
    """Work done by :func:`k_best_children`, and its budget.

    Attributes:
        max_solves: Assignment problems it may solve (Murty subproblems); once they are
            spent (and a child was found), no further matching is looked for, and the
            children are the label variants of the matchings in hand.
        solves: Assignment problems solved.
        truncated: The budget ran out before the k best were all found.
    """

    max_solves: float = math.inf
    solves: int = 0
    truncated: bool = False


def k_best_children(
    priors: Sequence[float],
    matrices: Sequence[AssignmentMatrix],
    k: int,
    max_gap: float = np.inf,
    enumerate_limit: int = 32,
    work: Work | None = None,
) -> list[tuple[int, LabelledAssignment, float]]:
    """The ``k`` globally best labelled assignments over several parents.

    Args:
        priors: Each parent's own cost (-log of its probability times its model prior).
        matrices: Each parent's assignment problem.
        k: Maximum number of children.
        max_gap: Stop when a child costs more than the best child plus this
            (ratio pruning, ``-log(min_ratio)``).
        enumerate_limit: Problems with at most this many matchings are enumerated
            directly instead of by Murty's method.
        work: Counts the assignment problems solved and bounds them (see :class:`Work`).

    Returns:
        ``(parent index, labels, total cost)`` in nondecreasing total cost.
    """
    counter = itertools.count()
    heap: list[_Entry] = []
    streams: dict[int, _MatchingStream] = {}
    for i, (prior, mat) in enumerate(zip(priors, matrices, strict=True)):
        bound = mat.lower_bound()
        if math.isfinite(bound):
            heap.append((prior + bound, _BOUND, next(counter), i, None))
    heapq.heapify(heap)
    out: list[tuple[int, LabelledAssignment, float]] = []
    best = np.inf
    while heap and len(out) < k:
        total, kind, _, i, state = heapq.heappop(heap)
        if out and total > best + max_gap:
            break
        if kind == _BOUND:
            if i not in streams:
                streams[i] = _MatchingStream(matrices[i], enumerate_limit)
            stream, prior = streams[i], priors[i]
            while True:
                if work is not None and out and work.solves >= work.max_solves:
                    work.truncated = True  # this parent's further matchings are given up;
                    break  # the label variants of those in hand still come out
                solved = stream.refine()
                if work is not None and solved:
                    work.solves += 1
                nxt = stream.peek_cost()
                if not math.isfinite(nxt):
                    break
                total = prior + nxt
                if stream.front_solved() or (heap and total >= heap[0][0]):
                    _push_stream(heap, counter, prior, i, stream)
                    break
                # a bound below every queued entry would come out next: refine it now
                # (what the next turn would do, without queueing it)
                if out and total > best + max_gap:
                    return out
        elif kind == _MATCHING:
            matching = streams[i].pop()
            variants = subset_sums(_penalties(matrices[i], matching))
            _push_variant(heap, counter, priors[i], _VariantState(i, matching, variants))
            _push_stream(heap, counter, priors[i], i, streams[i])
        else:
            assert state is not None
            out.append((i, decode(matrices[i], state.matching, state.flipped, state.extra), total))
            best = min(best, total)
            _push_variant(heap, counter, priors[i], state)
    return out


_VARIANT, _MATCHING, _BOUND = 0, 1, 2
"""Queue entry kinds: the next label variant of a matching, a parent's next matching, a
lower bound of a parent's next matching (its stream must be refined). At equal cost a
known child comes out before a bound is refined: a bound equal to the cost of a child
already in hand cannot beat it, and refining first solved, for a cluster of 100 tracks
and measurements, some 1,900 Murty subproblems before the first child (issue 16)."""


@dataclass(eq=False)
class _VariantState:
    """A matching, its stream of label variants, and the variant queued now."""

    parent: int
    matching: Matching
    variants: Iterator[tuple[float, tuple[int, ...]]]
    flipped: tuple[int, ...] = ()
    extra: float = 0.0


_Entry = tuple[float, int, int, int, "_VariantState | None"]
"""Queue entry: (cost, kind, unique tiebreak, parent index, variant state); plain tuples
compare fast and never reach the last two fields."""


def _push_stream(
    heap: list[_Entry], counter: Iterator[int], prior: float, i: int, stream: _MatchingStream
) -> None:
    nxt = stream.peek_cost()
    if math.isfinite(nxt):
        kind = _MATCHING if stream.front_solved() else _BOUND
        heapq.heappush(heap, (prior + nxt, kind, next(counter), i, None))


def _push_variant(
    heap: list[_Entry], counter: Iterator[int], prior: float, state: _VariantState
) -> None:
    nxt = next(state.variants, None)
    if nxt is not None and math.isfinite(nxt[0]):
        state.extra, state.flipped = nxt
        cost = prior + state.matching.cost + state.extra
        heapq.heappush(heap, (cost, _VARIANT, next(counter), state.parent, state))
