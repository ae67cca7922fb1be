"""Hypotheses, clusters of interacting tracks, and the pruning strategies (000 Sec. 3.3.2).

A :class:`Hypothesis` is one consistent set of track nodes (at most one per family) with a
log probability. The hypothesis tree is kept as each hypothesis's chain of ancestor ids over
the last N generations, which is all that N-scan-back pruning needs; older history is
dropped so memory is bounded.

A :class:`Cluster` holds the families that compete (or competed in the last N scans) for
measurements, and its own set of hypotheses over them, normalised to sum to 1 (Cox &
Hingorani's clustering: cost grows with crowding, not with the number of targets).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Hashable, Sequence
from dataclasses import dataclass, field

from laserpeople.tracking.mht.tracktree import TrackNode

_hypothesis_ids = itertools.count()


def logsumexp(values: Sequence[float]) -> float:
    """log(sum(exp(values))) without overflow (a short list: plain Python is fastest)."""
    top = max(values)
    if top == -math.inf:
        return top
    return top + math.log(math.fsum([math.exp(v - top) for v in values]))


def new_hypothesis_id() -> int:
    """A fresh, process-wide unique hypothesis id."""
    return next(_hypothesis_ids)


@dataclass(eq=False, slots=True)
class Hypothesis:
    """One global interpretation of the data within a cluster.

    Attributes:
        log_weight: log probability (normalised within its cluster and generation).
        tracks: Track nodes, sorted by family; a family absent from it does not exist
            in this hypothesis (never born, false alarm, or deleted).
        ancestors: Ids of its ancestors, oldest first, at most N of them (N-scan depth);
            for a hypothesis formed by joining clusters, an ancestor is the tuple of the
            parts' ancestors of that generation.
        hypothesis_id: Unique id.
        model: Index of the model (branch problem) of its parent it came from (0 when the
            tracker has a single model per parent; the group tracker's split/merge models).
    """

    log_weight: float
    tracks: tuple[TrackNode, ...]
    ancestors: tuple[Hashable, ...] = ()
    # (the counter's own __next__, new_hypothesis_id's ids without a Python call each)
    hypothesis_id: int = field(default_factory=_hypothesis_ids.__next__)
    model: int = 0

    def families(self) -> tuple[int, ...]:
        """Families present, increasing."""
        return tuple(t.family for t in self.tracks)

    def key(self) -> tuple[int, ...]:
        """Identity of the content: the node ids."""
        return tuple(t.node_id for t in self.tracks)


@dataclass(eq=False)
class Cluster:
    """Families that interact and the hypotheses over them.

    Attributes:
        families: The families of the cluster (any present in at least one hypothesis).
        hypotheses: Hypotheses, best first, log weights normalised.
    """

    families: frozenset[int]
    hypotheses: list[Hypothesis]

    def best(self) -> Hypothesis:
        """The most probable hypothesis."""
        return self.hypotheses[0]


def normalise_hypotheses(hyps: list[Hypothesis]) -> list[Hypothesis]:
    """Sort best first and normalise the log weights so the probabilities sum to 1."""
    if not hyps:
        return hyps
    total = logsumexp([h.log_weight for h in hyps])
    for h in hyps:
        h.log_weight -= total
    hyps.sort(key=lambda h: -h.log_weight)
    return hyps


def ratio_prune(hyps: Sequence[Hypothesis], min_ratio: float) -> list[Hypothesis]:
    """Drop hypotheses whose probability is below ``min_ratio`` times the best's
    (000 Sec. 4.5.2). Keeps the best always; renormalises."""
    if not hyps:
        return []
    best = max(h.log_weight for h in hyps)
    floor = best + math.log(min_ratio) if min_ratio > 0 else -math.inf
    return normalise_hypotheses([h for h in hyps if h.log_weight >= floor])


def n_scan_prune(hyps: Sequence[Hypothesis], depth: int) -> list[Hypothesis]:
    """N-scan-back pruning (000 Sec. 3.3.2): among the ancestors ``depth`` generations back,
    keep the one whose leaves carry the most probability mass and discard all other
    branches. ``depth = 0`` keeps only the best leaf. Hypotheses whose recorded history is
    shorter than ``depth`` (the cluster was just formed) are not pruned. Renormalises."""
    if not hyps:
        return []
    if depth <= 0:
        best = max(hyps, key=lambda h: h.log_weight)
        return normalise_hypotheses([best])
    if any(len(h.ancestors) < depth for h in hyps):
        return normalise_hypotheses(list(hyps))
    groups: dict[Hashable, list[Hypothesis]] = {}
    for h in hyps:
        groups.setdefault(h.ancestors[-depth], []).append(h)
    mass = {a: logsumexp([h.log_weight for h in g]) for a, g in groups.items()}
    keep = max(mass, key=lambda a: mass[a])
    return normalise_hypotheses(groups[keep])


def prune_children(hyps: list[Hypothesis], depth: int, min_ratio: float) -> list[Hypothesis]:
    """``ratio_prune(n_scan_prune(normalise_hypotheses(hyps), depth), min_ratio)`` with the
    same floats and order, without the work that cannot change them: a list that is already
    sorted best first stays so when one finite total is subtracted from every log weight
    (rounding is monotone), so the later normalisations do not sort again, and an N-scan
    step whose hypotheses all share the ancestor ``depth`` generations back keeps them all
    without summing its mass."""
    if not hyps:
        return []
    hyps = normalise_hypotheses(hyps)
    if depth <= 0:
        hyps = _renormalise([max(hyps, key=_weight)])
    elif any(len(h.ancestors) < depth for h in hyps):
        hyps = _renormalise(hyps)
    else:
        groups: dict[Hashable, list[Hypothesis]] = {}
        for h in hyps:
            groups.setdefault(h.ancestors[-depth], []).append(h)
        if len(groups) == 1:
            hyps = _renormalise(hyps)
        else:
            mass = {a: logsumexp([h.log_weight for h in g]) for a, g in groups.items()}
            keep = max(mass, key=lambda a: mass[a])
            hyps = _renormalise(groups[keep])  # a sublist keeps the order
    best = max(h.log_weight for h in hyps)
    floor = best + math.log(min_ratio) if min_ratio > 0 else -math.inf
    return _renormalise([h for h in hyps if h.log_weight >= floor])


def _weight(h: Hypothesis) -> float:
    return h.log_weight


def _renormalise(hyps: list[Hypothesis]) -> list[Hypothesis]:
    """:func:`normalise_hypotheses` of a list sorted best first."""
    if not hyps:
        return hyps
    total = logsumexp([h.log_weight for h in hyps])
    if not math.isfinite(total):  # (NaN weights after; sort as normalise_hypotheses does)
        return normalise_hypotheses(hyps)
    for h in hyps:
        h.log_weight -= total
    return hyps


def cap(hyps: list[Hypothesis], k: int) -> list[Hypothesis]:
    """The ``k`` best hypotheses, renormalised."""
    hyps.sort(key=lambda h: -h.log_weight)
    return normalise_hypotheses(hyps[:k])
