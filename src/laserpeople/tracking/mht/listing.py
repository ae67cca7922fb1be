"""The k best children of a cluster by branch and bound over its labelled assignments.

A child of a parent hypothesis labels each of the parent's tracks *detected* (with one
gated measurement, no measurement used twice), *occluded* or *deleted*, and each measurement
left over *new* or *false alarm*; its cost is the parent's plus the sum of the label costs
(000 eq. 15 in -log). Most clusters are small, and listing their children depth first is
far cheaper than Murty's method on assignment matrices (:func:`~laserpeople.tracking.mht.
matrix.k_best_children`), which gives the same children. A subtree is cut as soon as a
lower bound of its cost exceeds what can still be kept: the current k-th best child, or
the best child plus the ratio-pruning gap.

The lower bound of a partial labelling: its cost so far, plus for every track still to
label its cheapest label, plus for every unused measurement no track still to label can
take its cheaper unmatched label (and 0, or that label if negative, for the others).
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Sequence
from operator import itemgetter
from types import ModuleType

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracking.mht import compiled
from laserpeople.tracking.mht.matrix import LabelledAssignment
from laserpeople.tracking.mht.probability import (
    DELETED,
    DETECTED,
    FALSE_ALARM,
    MATCHED,
    OCCLUDED,
)
from laserpeople.tracking.mht.probability import NEW as NEW_LABEL

FloatArray = NDArray[np.float64]

LISTING_LIMIT = 1_000_000
"""Largest number of children (an upper bound, before cutting) a cluster may have to be
listed without a budget (:data:`LISTING_BUDGET`). (The cuts usually leave a few dozen of
them to visit.)"""

LISTING_BUDGET = 2_000
"""Steps of the depth-first listing (a track or measurement labelled) allowed to a cluster
with more than :data:`LISTING_LIMIT` children; when they run out the cluster goes to
Murty's method, whose cost does not grow with the number of children. Crowded clusters
(eight to twelve legs of a few people close together, four or five parents) have 10^8 to
10^10 children, of which the cuts leave a few hundred steps: listed, they take a third of
the CPU of Murty's method (simulated hall, 20 people). The budget bounds the work lost on
a cluster whose cuts do not bite (many equal costs) to about what Murty's method costs."""


MAX_LISTED_MEASUREMENTS = 10
"""Clusters with more measurements go to Murty's method (the bounds table has 2^m
entries)."""


def set_up(extension: ModuleType) -> None:
    """Give the compiled listing this module's class of labels and constants."""
    extension.setup(
        LabelledAssignment,
        MAX_LISTED_MEASUREMENTS,
        (DETECTED, OCCLUDED, DELETED),
        (MATCHED, NEW_LABEL, FALSE_ALARM),
        LISTING_LIMIT,
        LISTING_BUDGET,
    )


_extension, IMPLEMENTATION = compiled.load()
"""Which listing :func:`list_children` runs (:mod:`~laserpeople.tracking.mht.compiled`)."""
if _extension is not None:
    set_up(_extension)
COMPILED = None if _extension is None else _extension.list_children
"""The compiled :func:`list_children_python` (the same children and cost floats), or None:
it returns NotImplemented for the calls the Python listing takes (the shortcut, a NaN
prior, ``k < 1``)."""
COMPILED_K_BEST = None if _extension is None else _extension.k_best_plain
"""The compiled ``MHT._k_best`` of the plain MHT on the scan's tables (the same children
and cost floats), or None: it returns NotImplemented for the clusters the Python one takes
(the shortcut, Murty's method, a degraded cluster, a node not scored this scan)."""
COMPILED_COMPONENTS = None if _extension is None else _extension.components
"""The compiled :func:`~.core.components_python` (the same components, in the same
order), or None: it returns NotImplemented for input the Python one takes."""
COMPILED_PRUNE = None if _extension is None else _extension.prune
"""The compiled :func:`~.hypothesis.prune_children` (the same hypotheses in the same order
with the same log weights), or None: it returns NotImplemented for children the Python one
takes (a weight or a total not finite, an N-scan ancestor that cannot be hashed)."""
COMPILED_PLAN_PLAIN = None if _extension is None else _extension.plan_plain
"""The compiled ``MHT._plan_plain`` (the same pairs and births in the same order), or None:
it returns NotImplemented for solutions the Python one takes (not the listing's)."""
COMPILED_ASSEMBLE_PLAIN = None if _extension is None else _extension.assemble_plain
"""The compiled ``MHT._assemble`` of the plain MHT before its pruning (the same children,
made in the same order by the same calls), or None: it returns NotImplemented for solutions
the Python one takes (not the listing's)."""
COMPILED_MAKE_PLAIN = None if _extension is None else _extension.make_plain
"""The compiled ``MHT._make_detected_children`` and ``MHT._new_nodes_deferred`` of the
plain MHT (the same nodes, ids and order), or None: it returns NotImplemented (nothing
made) for input the Python code takes."""
COMPILED_DETECTION_COSTS = None if _extension is None else _extension.detection_costs
"""The compiled ``core._detection_costs_python`` (the same floats), written to an array
given, or None."""
COMPILED_STATIC_FEW = None if _extension is None else _extension.static_few
"""The compiled ``OccupancyGrid._static_few_python`` (the same values), or None: it
returns NotImplemented where the Python one decides otherwise."""


def children_bound(rows: Sequence[Sequence[int]], n_labels: Sequence[int], m: int) -> int:
    """An upper bound of the number of children of the parents ``rows`` (track indices),
    given each track's number of possible labels and ``m`` measurements."""
    total = 0
    for r in rows:
        count = 2**m
        for i in r:
            count *= n_labels[i]
        total += count
    return total


def enumerate_children(
    priors: Sequence[float],
    rows: Sequence[Sequence[int]],
    track_meas_cost: FloatArray,
    label_log_probs: FloatArray,
    log_new: FloatArray,
    log_fal: FloatArray,
    k: int,
    max_gap: float,
    limit: int = LISTING_LIMIT,
    shortcut: bool = True,
    budget: int = LISTING_BUDGET,
) -> list[tuple[int, LabelledAssignment, float]] | None:
    """The ``k`` best children (at most ``max_gap`` above the best) of the parents.

    Args:
        priors: Cost (-log weight) of each parent, with its model prior.
        rows: Each parent's tracks, as indices into the node arrays below.
        track_meas_cost: (n, m) ``-(log p_det + log N)``, inf where not gated.
        label_log_probs: (n, 3) log p of detected/occluded/deleted per node.
        log_new, log_fal: (m,) log densities of new tracks and false alarms.
        k: Most children to return.
        max_gap: Children costing more than the best plus this are dropped.
        limit: List without a budget up to this :func:`children_bound`.
        budget: Beyond ``limit``, give up (None) after this many listing steps (0: at
            once).
        shortcut: Clusters of at most one track per parent and at most one measurement
            (most clusters: one leg, its own detection) are listed by
            :func:`single_children`, which gives the same children without the bounds.

    Returns:
        ``(parent index, labels, total cost)`` in nondecreasing total cost (equal costs in
        the order found), or None when the cluster is too big to list (more than
        :data:`MAX_LISTED_MEASUREMENTS` measurements, or over ``limit`` and ``budget``).
        The children of :func:`list_children` on the same costs as plain floats.
    """
    return list_children(
        priors,
        rows,
        *plain_costs(track_meas_cost, label_log_probs, log_new, log_fal),
        k,
        max_gap,
        limit=limit,
        shortcut=shortcut,
        budget=budget,
    )


PlainCosts = tuple[list[list[float]], list[float], list[float], list[float], list[float]]
"""The costs :func:`list_children` takes: per node the detection costs (one per
measurement), per node the occluded and the deleted costs, per measurement the new and the
false-alarm costs."""


def plain_costs(
    track_meas_cost: FloatArray,
    label_log_probs: FloatArray,
    log_new: FloatArray,
    log_fal: FloatArray,
) -> PlainCosts:
    """:func:`enumerate_children`'s arrays as :func:`list_children`'s plain floats (the
    log-probabilities negated: the same floats)."""
    lps = np.asarray(label_log_probs, dtype=np.float64).tolist()
    return (
        np.asarray(track_meas_cost, dtype=np.float64).tolist(),
        [-r[OCCLUDED] for r in lps],
        [-r[DELETED] for r in lps],
        [-c for c in np.asarray(log_new, dtype=np.float64).tolist()],
        [-c for c in np.asarray(log_fal, dtype=np.float64).tolist()],
    )


def list_children(
    priors: Sequence[float],
    rows: Sequence[Sequence[int]],
    tm: list[list[float]],
    c_occ: list[float],
    c_del: list[float],
    c_new: list[float],
    c_fal: list[float],
    k: int,
    max_gap: float,
    limit: int = LISTING_LIMIT,
    shortcut: bool = True,
    budget: int = LISTING_BUDGET,
) -> list[tuple[int, LabelledAssignment, float]] | None:
    """:func:`enumerate_children` on costs given as plain floats (-log; the MHT core takes
    them from its per-scan tables without an array per cluster): ``tm`` per node the
    costs of matching each of the ``m`` measurements (inf where not gated), ``c_occ`` and
    ``c_del`` per node the costs of its occluded and deleted labels, ``c_new`` and
    ``c_fal`` per measurement the costs of its new and false-alarm labels. The other
    arguments and the result are :func:`enumerate_children`'s.

    Runs the compiled listing (:data:`COMPILED`) where it is built, else
    :func:`list_children_python`, the reference: the same children and cost floats."""
    if COMPILED is not None:
        out = COMPILED(
            priors, rows, tm, c_occ, c_del, c_new, c_fal, k, max_gap, limit, shortcut, budget
        )
        if out is not NotImplemented:
            return out
    return list_children_python(
        priors, rows, tm, c_occ, c_del, c_new, c_fal, k, max_gap, limit, shortcut, budget
    )


def list_children_python(
    priors: Sequence[float],
    rows: Sequence[Sequence[int]],
    tm: list[list[float]],
    c_occ: list[float],
    c_del: list[float],
    c_new: list[float],
    c_fal: list[float],
    k: int,
    max_gap: float,
    limit: int = LISTING_LIMIT,
    shortcut: bool = True,
    budget: int = LISTING_BUDGET,
) -> list[tuple[int, LabelledAssignment, float]] | None:
    """:func:`list_children` in Python (the reference of the compiled listing, and what
    runs without it)."""
    m = len(c_new)
    if shortcut and m <= 1 and all(len(r) <= 1 for r in rows):
        tm_single = [row[0] for row in tm] if m else [math.inf] * len(tm)
        meas = (c_new[0], c_fal[0]) if m else None
        single = single_children(priors, rows, tm_single, c_occ, c_del, meas, k, max_gap)
        return [(pi, _single_labels(tl, ml, total), total) for total, pi, tl, ml in single]
    if m > MAX_LISTED_MEASUREMENTS:  # (before building the choices it would not use)
        return None
    # each track's finite labels, cheapest first: (cost, label, measurement or -1, its bit
    # or 0), with the cheapest cost and the measurements in the gate (a bit mask), in one
    # pass per track
    choices: list[list[tuple[float, int, int, int]]] = []
    cheapest: list[float] = []
    gates: list[int] = []
    inf = math.inf
    bits = [1 << j for j in range(m)]
    for row, occ, dele in zip(tm, c_occ, c_del, strict=True):
        ch: list[tuple[float, int, int, int]] = []
        gate = 0
        for j, c in enumerate(row):
            if c < inf:
                ch.append((c, DETECTED, j, bits[j]))
                gate |= bits[j]
        if occ < inf:
            ch.append((occ, OCCLUDED, -1, 0))
        if dele < inf:
            ch.append((dele, DELETED, -1, 0))
        ch.sort()
        choices.append(ch)
        cheapest.append(ch[0][0] if ch else inf)
        gates.append(gate)
    steps = 0  # listing steps allowed (0: no budget)
    if children_bound(rows, [len(c) for c in choices], m) > limit:
        if budget <= 0:
            return None
        steps = budget
    meas_choices = [
        sorted(c for c in ((c_new[j], NEW_LABEL), (c_fal[j], FALSE_ALARM)) if c[0] < math.inf)
        for j in range(m)
    ]
    meas_min = [ch[0][0] if ch else math.inf for ch in meas_choices]
    # lower bounds of the measurements in a bit mask: unmatched for sure / perhaps matched
    full = (1 << m) - 1
    unmatched_lb = [0.0] * (full + 1)
    maybe_lb = [0.0] * (full + 1)
    for mask in range(1, full + 1):
        low = (mask & -mask).bit_length() - 1
        rest = mask & (mask - 1)
        unmatched_lb[mask] = unmatched_lb[rest] + meas_min[low]
        maybe_lb[mask] = maybe_lb[rest] + min(0.0, meas_min[low])

    tables = (choices, meas_choices, meas_min, unmatched_lb, maybe_lb, k, max_gap, cheapest, gates)
    lister: _Lister
    if steps:
        budgeted = _BudgetedLister(*tables)
        budgeted.left = steps
        lister = budgeted
    else:  # (counts nothing)
        lister = _Lister(*tables)
    by_prior = priors.__getitem__ if isinstance(priors, list) else lambda p: priors[p]
    try:
        for pi in sorted(range(len(rows)), key=by_prior):  # the likeliest first
            if math.isfinite(priors[pi]):
                lister.parent(pi, float(priors[pi]), list(rows[pi]))
    except _OutOfStepsError:
        return None
    found, best = lister.found, lister.best
    found.sort(key=itemgetter(0))  # stable: equal totals stay in the order found
    out: list[tuple[int, LabelledAssignment, float]] = []
    for total, _, pi, tl, tmeas, used, free in found[:k]:
        if total <= best + max_gap:
            if free is None:
                ml = [MATCHED] * m
            else:
                ml = [MATCHED if used >> j & 1 else free[j] for j in range(m)]
            out.append((pi, LabelledAssignment(tl, tmeas, ml, total), total))
    return out


def _single_labels(tl: int, ml: int, total: float) -> LabelledAssignment:
    """The labels of a :func:`single_children` child: track label ``tl`` (-1: the parent
    has no track) and measurement label ``ml`` (-1: no measurement)."""
    return LabelledAssignment(
        [] if tl < 0 else [tl],
        () if tl < 0 else ((0,) if tl == DETECTED else (-1,)),
        [] if ml < 0 else [ml],
        total,
    )


def single_children(
    priors: Sequence[float],
    rows: Sequence[Sequence[int]],
    tm: Sequence[float],
    c_occ: Sequence[float],
    c_del: Sequence[float],
    meas: tuple[float, float] | None,
    k: int,
    max_gap: float,
) -> list[tuple[float, int, int, int]]:
    """The children of a cluster whose parents have at most one track each and which has
    at most one measurement, from plain floats (:func:`enumerate_children`'s shortcut; the
    core's shortcut for such clusters calls this directly): every child is written out (at
    most five per parent), in the order the depth-first listing visits them, then the ``k``
    best within ``max_gap`` of the best are kept, equal costs in that order.

    The result is the listing's: its cuts only drop children that would not be kept (a cut
    child costs at least a lower bound above the best plus the gap, or at least the k-th
    best found before it), and the costs are summed in the same order (parent, track label,
    measurement label), so they are the same floats.

    Args:
        priors: Cost of each parent.
        rows: Each parent's track (a node index) or none.
        tm: Per node, the cost of matching it with the measurement (inf: not gated, or no
            measurement).
        c_occ, c_del: Per node, the costs of its occluded and deleted labels.
        meas: The costs (new, false alarm) of the measurement, or None without one.
        k, max_gap: As :func:`enumerate_children`.

    Returns:
        ``(total cost, parent, track label or -1 without a track, measurement label or -1
        without a measurement)``, best first (equal costs in listing order); a detected
        track is matched with the measurement.
    """
    meas_ch: list[tuple[float, int]] = []
    if meas is not None:
        both = ((meas[0], NEW_LABEL), (meas[1], FALSE_ALARM))
        meas_ch = sorted(c for c in both if c[0] < math.inf)
    found: list[tuple[float, int, int, int]] = []  # in listing order
    for pi in sorted(range(len(rows)), key=lambda p: priors[p]):
        if not math.isfinite(priors[pi]):
            continue
        prior = float(priors[pi])
        if not rows[pi]:
            if meas is not None:
                found += [(prior + c, pi, -1, lab) for c, lab in meas_ch]
            else:
                found.append((prior, pi, -1, -1))
            continue
        i = rows[pi][0]
        ch = [(c_occ[i], OCCLUDED), (c_del[i], DELETED)]
        if tm[i] < math.inf:
            ch.append((tm[i], DETECTED))
        for c, lab in sorted(c for c in ch if c[0] < math.inf):
            cost = prior + c
            if lab == DETECTED:
                found.append((cost, pi, lab, MATCHED))
            elif meas is not None:
                found += [(cost + cm, pi, lab, ml) for cm, ml in meas_ch]
            else:
                found.append((cost, pi, lab, -1))
    if not found:
        return []
    best = min(f[0] for f in found)
    found.sort(key=_total)  # stable: equal costs stay in listing order
    return [f for f in found[:k] if f[0] <= best + max_gap]


def _total(child: tuple[float, int, int, int]) -> float:
    return child[0]


class _OutOfStepsError(Exception):
    """The listing used up its steps (:data:`LISTING_BUDGET`)."""


class _Lister:
    """Depth-first listing with cuts (see the module doc); children go to ``found``.

    The cut thresholds are kept as two floats, updated by :meth:`_record`: ``_limit``, the
    best total so far plus the gap (the same float the sum gives each time), and ``_kth``,
    the k-th best total once k children are kept, NaN before (no bound compares ``>=`` to
    NaN, as no bound is cut by the k-th best before there is one)."""

    def __init__(
        self,
        choices: list[list[tuple[float, int, int, int]]],
        meas_choices: list[list[tuple[float, int]]],
        meas_min: list[float],
        unmatched_lb: list[float],
        maybe_lb: list[float],
        k: int,
        max_gap: float,
        cheapest: list[float] | None = None,
        gates: list[int] | None = None,
    ) -> None:
        self.choices = choices
        self.meas_choices = meas_choices
        self.meas_min = meas_min
        self.unmatched_lb = unmatched_lb
        self.maybe_lb = maybe_lb
        self.k = k
        self.max_gap = max_gap
        self.m = len(meas_choices)
        # (each track's cheapest label and gate, unless the caller has them)
        self.cheapest = (
            [ch[0][0] if ch else math.inf for ch in choices] if cheapest is None else cheapest
        )
        self.gates = [sum([c[3] for c in ch]) for ch in choices] if gates is None else gates
        self.full = (1 << self.m) - 1
        # (total, order found, parent, track labels, their measurements, measurements used
        # (bit mask), the unmatched measurements' labels or None when all are used)
        self.found: list[
            tuple[float, int, int, list[int], tuple[int, ...], int, tuple[int, ...] | None]
        ] = []
        self.best = math.inf
        self._limit = math.inf + max_gap  # best + max_gap
        self._kth = math.nan  # the k-th best total once there are k
        self._kept: list[float] = []  # max-heap (negated) of the k best totals
        self._free_labels = [MATCHED] * self.m
        # the parent being listed
        self._pi = 0
        self._rows: list[int] = []
        self._suffix: list[float] = []
        self._reach: list[int] = []
        self._labels: list[int] = []
        self._meas: list[int] = []

    def parent(self, pi: int, prior: float, rows: list[int]) -> None:
        """List the children of parent ``pi`` (cost ``prior``, tracks ``rows``)."""
        depth = len(rows)
        suffix = [0.0] * (depth + 1)  # cheapest labels of the tracks from t on
        reach = [0] * (depth + 1)  # measurements gated by the tracks from t on
        cheapest, gates = self.cheapest, self.gates
        for t in range(depth - 1, -1, -1):
            suffix[t] = suffix[t + 1] + cheapest[rows[t]]
            reach[t] = reach[t + 1] | gates[rows[t]]
        self._pi, self._rows, self._suffix, self._reach = pi, rows, suffix, reach
        self._labels, self._meas = [0] * depth, [0] * depth
        full = self.full
        bound = (
            prior + suffix[0] + self.unmatched_lb[full & ~reach[0]] + self.maybe_lb[full & reach[0]]
        )
        if bound > self._limit or bound >= self._kth:
            return
        if depth:
            self._tracks(0, prior, 0)
        else:
            self._measurements(0, prior, 0, self.unmatched_lb[full])

    def _tracks(self, t: int, cost: float, used: int) -> None:
        """Label the tracks from ``t`` on, at least one (the caller has checked this
        subtree's bound); each child's bound is checked here, before the call (most
        children are cut)."""
        full, unmatched_lb, maybe_lb = self.full, self.unmatched_lb, self.maybe_lb
        suffix, reach = self._suffix[t + 1], self._reach[t + 1]
        labels, meas = self._labels, self._meas
        last = t + 1 == len(self._rows)
        limit, kth = self._limit, self._kth
        for c, lab, j, bit in self.choices[self._rows[t]]:
            if used & bit:
                continue
            child_used = used | bit
            child_cost = cost + c
            free = full & ~child_used
            bound = child_cost + suffix + unmatched_lb[free & ~reach] + maybe_lb[free & reach]
            if bound > limit or bound >= kth:
                continue
            labels[t] = lab
            meas[t] = j
            if not last:
                self._tracks(t + 1, child_cost, child_used)
            elif child_used == full:  # the measurements next: none left to label
                self._record(child_cost, child_used)
            else:
                self._measurements(0, child_cost, child_used, unmatched_lb[free])
            limit, kth = self._limit, self._kth

    def _measurements(self, j: int, cost: float, used: int, rest_lb: float) -> None:
        """Label the measurements from ``j`` on that no track took (new / false alarm)."""
        m = self.m
        while j < m and used >> j & 1:
            j += 1
        if j == m:
            self._record(cost, used)
            return
        rest = rest_lb - self.meas_min[j]
        free = self._free_labels
        for c, lab in self.meas_choices[j]:
            bound = cost + c + rest
            if bound > self._limit or bound >= self._kth:
                break
            free[j] = lab
            self._measurements(j + 1, cost + c, used, rest)

    def _record(self, total: float, used: int) -> None:
        found = self.found
        found.append(
            (
                total,
                len(found),
                self._pi,
                self._labels[:],
                tuple(self._meas),
                used,
                None if used == self.full else tuple(self._free_labels),
            )
        )
        if total < self.best:
            self.best = total
            self._limit = total + self.max_gap
        kept = self._kept
        if len(kept) < self.k:
            heapq.heappush(kept, -total)
            if len(kept) == self.k:
                self._kth = -kept[0]
        elif total < -kept[0]:
            heapq.heapreplace(kept, -total)
            self._kth = -kept[0]


class _BudgetedLister(_Lister):
    """A :class:`_Lister` that raises :class:`_OutOfStepsError` once it has taken ``left``
    listing steps (a track or a measurement labelled; set after construction). The plain
    lister counts nothing."""

    left = 0

    def _tracks(self, t: int, cost: float, used: int) -> None:
        self.left -= 1
        if self.left < 0:
            raise _OutOfStepsError
        super()._tracks(t, cost, used)

    def _measurements(self, j: int, cost: float, used: int, rest_lb: float) -> None:
        self.left -= 1
        if self.left < 0:
            raise _OutOfStepsError
        super()._measurements(j, cost, used, rest_lb)
