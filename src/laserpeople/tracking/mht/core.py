"""The MHT tracking cycle over clusters of interacting tracks (000 Sec. 3.2-3.3.2; Cox &
Hingorani 1996).

One :meth:`MHT.step` per scan:

1. predict every live track node once (the track tree shares nodes between hypotheses);
2. gate and score every node against every measurement (vectorised in the track model);
3. cluster: families and measurements that share a gate, or families that shared one in
   the last N scans, form a cluster; clusters that now share a measurement are merged
   (product of their hypotheses), clusters whose families no longer interact are split
   (marginal hypotheses per part; exact because N-scan pruning has fixed everything the
   parts ever shared, see :meth:`MHT._drop_settled_links`);
4. per cluster: the globally k best children over all parent hypotheses (and model
   branches), stopped early by the probability ratio: listed by branch and bound
   (:mod:`.listing`), or for very large clusters by multi-parent Murty on one assignment
   matrix per parent (:mod:`.matrix`);
5. normalise per cluster and generation, N-scan-back pruning, ratio pruning;
6. the plain MHT (one model per parent) makes the states of the children kept, in one
   batch (:meth:`MHT._fill_deferred`; with branch models they were made before step 4);
7. garbage-collect the track tree.

The reported state is the best hypothesis of every cluster (their product is the globally
best hypothesis because clusters are independent).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Hashable, Iterable, Sequence, Sized
from dataclasses import dataclass, replace
from typing import Any, Generic, TypeVar

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.tracking.mht import listing
from laserpeople.tracking.mht.expiry import ExpiryOdds, drop_nodes
from laserpeople.tracking.mht.hypothesis import (
    Cluster,
    Hypothesis,
    normalise_hypotheses,
    prune_children,
)
from laserpeople.tracking.mht.listing import (
    PlainCosts,
    list_children,
    plain_costs,
    single_children,
)
from laserpeople.tracking.mht.matrix import (
    AssignmentMatrix,
    LabelledAssignment,
    Work,
    build_matrix,
    k_best_children,
)
from laserpeople.tracking.mht.probability import (
    DELETED,
    DETECTED,
    OCCLUDED,
)
from laserpeople.tracking.mht.probability import NEW as NEW_LABEL
from laserpeople.tracking.mht.protocols import (
    Branch,
    BranchGenerator,
    BranchObservations,
    LabelModel,
    SingleModel,
    TrackModel,
)
from laserpeople.tracking.mht.tracktree import BY_FAMILY, NEW, TrackNode, TrackTree
from laserpeople.tracking.mht.tracktree import DETECTED as NODE_DETECTED
from laserpeople.tracking.mht.tracktree import OCCLUDED as NODE_OCCLUDED

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

Meas = TypeVar("Meas", bound=Sized)


MIN_RATIO = 1e-3
"""Ratio pruning's threshold where ``MHTParams.min_ratio`` is unset and the tracker sets
none: an assumption (000 Sec. 4.5.2 names ratio pruning without a value)."""

K_BEST = 20
"""Children per cluster and scan where ``MHTParams.k_best`` is unset and the tracker sets
none: an assumption (000 Sec. 4.6 averages its cycle times over k from 2 to 200)."""

N_SCAN = 8
"""N-scan-back depth where ``MHTParams.n_scan`` is unset and the tracker sets none: 000
Sec. 3.4.3 (a scan-back depth of eight)."""


@dataclass(frozen=True)
class MHTParams:
    """Branching and pruning of the hypothesis tree (000 Sec. 3.3.2)."""

    config_section = "mht"

    k_best: int | None = param(
        None,
        "unset: the tracker's default: K_BEST = 20 (assumption; 000 Sec. 4.6 averages k over "
        "2..200) for the group tracker and the leg tracker's people policy arras, 5 for its "
        "policy tracks (see LegTrackerParams.mht_params)",
        "k of Murty's k-best branching: children per cluster and scan, over all parents",
    )
    n_scan: int | None = param(
        None,
        "unset: the tracker's default: N_SCAN = 8 (000 Sec. 3.4.3, a scan-back depth of "
        "eight) for the leg tracker's people policy arras, 4 for its policy tracks (see "
        "LegTrackerParams.mht_params), GROUP_N_SCAN = 3 for the group tracker (its paper "
        "preset: 8; docs/groups.md)",
        "N of N-scan-back pruning",
    )
    min_ratio: float | None = param(
        None,
        "unset: the tracker's default: MIN_RATIO = 1e-3 (assumption; 000 Sec. 4.5.2 names "
        "ratio pruning without a value) for the leg tracker's people policy arras, 1e-2 for "
        "its policy tracks (see LegTrackerParams.mht_params), 3e-3 for the group "
        "tracker (GROUP_MIN_RATIO, docs/groups.md)",
        "drop hypotheses less probable than this times the best of their cluster",
    )
    max_cluster_size: int = param(
        200,
        "assumption: ~3x the largest cluster measured (72 items, simulated entrance hall; "
        "docs/speed.md)",
        "a cluster with more tracks plus measurements is degraded: only its best parent "
        "hypothesis is extended, by its best matching of tracks and measurements (one "
        "assignment problem) with the k best labellings of what it leaves unmatched",
    )
    max_assignment_solves: int = param(
        2000,
        "assumption: ~3x the most solves measured in one scan (640, simulated entrance hall; "
        "docs/speed.md)",
        "assignment problems (Murty subproblems) solved per cluster and scan at most; "
        "then the children found so far are kept and the cluster counts as degraded",
    )
    existence_ratio: float = param(
        1e-3,
        "000 eqs. 8-10 (the deletion mass N-scan-back pruning cuts off, see mht/expiry.py); "
        "value: MIN_RATIO, ratio pruning's. Issue 16: without it an approved leg that left "
        "the view was never deleted and state and cycle time grew without bound",
        "a track unseen for m scans is deleted from every hypothesis once the odds of it still "
        "existing under its label probabilities fall below this (0: never; 000 Table 10 "
        "free: 19 scans, approved: 43)",
    )

    def __post_init__(self) -> None:
        if self.k_best is not None and (isinstance(self.k_best, bool) or self.k_best < 1):
            raise ValueError("k_best must be at least 1")
        if self.n_scan is not None and (isinstance(self.n_scan, bool) or self.n_scan < 0):
            raise ValueError("n_scan must be >= 0")
        if self.min_ratio is not None and (
            isinstance(self.min_ratio, bool)
            or not isinstance(self.min_ratio, int | float)
            or not 0.0 <= self.min_ratio < 1.0
        ):
            raise ValueError("min_ratio must be a number in [0, 1)")
        if self.max_cluster_size < 1 or self.max_assignment_solves < 1:
            raise ValueError("max_cluster_size and max_assignment_solves must be at least 1")
        if not 0.0 <= self.existence_ratio < 1.0:
            raise ValueError("existence_ratio must be in [0, 1)")

    @property
    def ratio(self) -> float:
        """The ratio pruning threshold in use: ``min_ratio``, or :data:`MIN_RATIO` unset."""
        return MIN_RATIO if self.min_ratio is None else float(self.min_ratio)

    @property
    def k(self) -> int:
        """k of the k-best branching in use: ``k_best``, or :data:`K_BEST` unset."""
        return K_BEST if self.k_best is None else int(self.k_best)

    @property
    def depth(self) -> int:
        """N-scan-back depth in use: ``n_scan``, or :data:`N_SCAN` unset."""
        return N_SCAN if self.n_scan is None else int(self.n_scan)

    def with_defaults(
        self, min_ratio: float = MIN_RATIO, k_best: int = K_BEST, n_scan: int = N_SCAN
    ) -> MHTParams:
        """These parameters with each unset one of ``min_ratio``, ``k_best`` and ``n_scan``
        set to the given value (a tracker's own default); explicit values stay."""
        return replace(
            self,
            min_ratio=min_ratio if self.min_ratio is None else self.min_ratio,
            k_best=k_best if self.k_best is None else self.k_best,
            n_scan=n_scan if self.n_scan is None else self.n_scan,
        )


@dataclass(frozen=True)
class StepStats:
    """What one MHT step did.

    Attributes:
        n_clusters: Clusters after the step.
        n_hypotheses: Hypotheses summed over clusters (the work done).
        max_cluster_hypotheses: Hypotheses of the largest cluster.
        n_live_nodes: Track nodes referred to by some hypothesis.
        n_families: Live track families.
        families_created: Families created since the start (any hypothesis).
        assignment_solves: Assignment problems solved in the step (Murty subproblems).
        degraded_clusters: Clusters of the step over ``max_cluster_size`` or
            ``max_assignment_solves``, whose children were not all the k best.
        largest_cluster: Most tracks plus measurements of one cluster's problem.
        max_cluster_solves: Most assignment problems solved for one cluster.
    """

    n_clusters: int
    n_hypotheses: int
    max_cluster_hypotheses: int
    n_live_nodes: int
    n_families: int
    families_created: int
    assignment_solves: int = 0
    degraded_clusters: int = 0
    largest_cluster: int = 0
    max_cluster_solves: int = 0


def components(
    fam_meas: dict[int, set[int]], links: Iterable[tuple[int, int]], n_meas: int
) -> list[tuple[frozenset[int], list[int]]]:
    """Connected components of families (ints >= 0) and measurements ``0..n_meas-1``:
    a family is joined to the measurements in its gate (``fam_meas``) and to the families
    it is linked with (``links``, pairs of families in ``fam_meas``). Per component its
    families and its measurements (increasing); components in the order of their first
    family in ``fam_meas``, then those of measurements alone in measurement order.

    Runs the compiled one (:data:`~.listing.COMPILED_COMPONENTS`) where it is built, else
    (and for input it leaves to Python) :func:`components_python`, its reference: the same
    components, frozensets made in the same order."""
    if listing.COMPILED_COMPONENTS is not None:
        out = listing.COMPILED_COMPONENTS(fam_meas, links, n_meas)
        if out is not NotImplemented:
            return out
    return components_python(fam_meas, links, n_meas)


def components_python(
    fam_meas: dict[int, set[int]], links: Iterable[tuple[int, int]], n_meas: int
) -> list[tuple[frozenset[int], list[int]]]:
    """:func:`components` in Python (union-find over dicts)."""
    up: dict[int, int] = {f: f for f in fam_meas}  # union-find; measurement j is ~j (< 0)
    for j in range(n_meas):
        up[~j] = ~j

    def root(x: int) -> int:
        r = up[x]
        if r == x:
            return x
        while up[r] != r:
            r = up[r]
        while x != r:  # path compression
            up[x], x = r, up[x]
        return r

    for a, b in links:
        ra, rb = root(a), root(b)
        if ra != rb:
            up[rb] = ra
    for f, js in fam_meas.items():
        ra = root(f)  # stays a root: the others join it
        for j in js:
            rb = root(~j)
            if rb != ra:
                up[rb] = ra
    fams: dict[int, set[int]] = {}
    meas: dict[int, list[int]] = {}
    for f in fam_meas:
        fams.setdefault(root(f), set()).add(f)
    for j in range(n_meas):
        meas.setdefault(root(~j), []).append(j)
    roots = list(dict.fromkeys([*fams, *meas]))
    return [(frozenset(fams.get(r, ())), meas.get(r, [])) for r in roots]


def project(hyps: Sequence[Hypothesis], families: frozenset[int]) -> list[Hypothesis]:
    """Marginal hypotheses over a subset of families: equal projections are merged and
    their probabilities added; each keeps the history of its most probable member."""
    merged: dict[tuple[int, ...], Hypothesis] = {}
    for h in sorted(hyps, key=lambda h: -h.log_weight):
        tracks = tuple(t for t in h.tracks if t.family in families)
        key = tuple(t.node_id for t in tracks)
        if key in merged:
            m = merged[key]
            m.log_weight = float(np.logaddexp(m.log_weight, h.log_weight))
        else:
            merged[key] = Hypothesis(h.log_weight, tracks, h.ancestors)
    return normalise_hypotheses(list(merged.values()))


def _joint_ancestors(a: tuple[Hashable, ...], b: tuple[Hashable, ...]) -> tuple[Hashable, ...]:
    """Ancestry of a joint hypothesis: its ancestor g generations back is the pair of the
    parts' ancestors g generations back."""
    n = min(len(a), len(b))
    if n == 0:
        return ()
    return tuple(zip(a[-n:], b[-n:], strict=True))


def product(parts: Sequence[Sequence[Hypothesis]], k: int) -> list[Hypothesis]:
    """Joint hypotheses of independent clusters: the ``k`` most probable combinations."""
    acc = [(h.log_weight, h.tracks, h.ancestors) for h in parts[0]]
    for part in parts[1:]:
        combos = [
            (wa + b.log_weight, ta + b.tracks, _joint_ancestors(aa, b.ancestors))
            for wa, ta, aa in acc
            for b in part
        ]
        combos.sort(key=lambda c: -c[0])
        acc = combos[:k]
    return normalise_hypotheses(
        [Hypothesis(w, tuple(sorted(t, key=BY_FAMILY)), anc) for w, t, anc in acc]
    )


_DEFERRED: FloatArray = np.full(0, np.nan)
"""The state of a node whose state is made at the end of the step
(:meth:`MHT._fill_deferred`); it never leaves the step."""


def _max_gap(min_ratio: float) -> float:
    """The largest cost gap to the best child that ratio pruning keeps, ``-log min_ratio``."""
    return -math.log(min_ratio) if min_ratio > 0 else math.inf


def _detection_costs(gated: BoolArray, loglik: FloatArray, lp: FloatArray) -> FloatArray:
    """``-(log p_det + log N)`` (n, m) where gated, inf elsewhere (000 eq. 15 in -log):
    by the compiled one (:data:`~.listing.COMPILED_DETECTION_COSTS`, one call instead of
    four numpy calls on a few dozen pairs) where it is built and takes the arrays, else
    :func:`_detection_costs_python`, its reference (the same floats)."""
    compiled = listing.COMPILED_DETECTION_COSTS
    if compiled is not None:
        out = np.empty(gated.shape)
        try:
            compiled(gated, loglik, lp, out)
        except ValueError:  # (not C-contiguous, or not of the shapes expected)
            return _detection_costs_python(gated, loglik, lp)
        return out
    return _detection_costs_python(gated, loglik, lp)


def _detection_costs_python(gated: BoolArray, loglik: FloatArray, lp: FloatArray) -> FloatArray:
    """:func:`_detection_costs` in numpy."""
    return np.where(gated, -(lp[:, DETECTED, None] + loglik), np.inf)


class MHT(Generic[Meas]):
    """Multi-hypothesis tracker core, generic over the track model and label model.

    Args:
        params: Branching and pruning parameters.
        model: Track model (prediction, gating, update, initiation).
        labels: Label probabilities (detected/occluded/deleted, new/false alarm).
        branches: Model branches per parent (the plain MHT has one).
    """

    def __init__(
        self,
        params: MHTParams,
        model: TrackModel[Meas],
        labels: LabelModel[Meas],
        branches: BranchGenerator | None = None,
    ) -> None:
        self.params = params
        self.model = model
        self.labels = labels
        self.branches: BranchGenerator = branches if branches is not None else SingleModel()
        self.tree = TrackTree()
        self.clusters: list[Cluster] = []
        self.links: dict[tuple[int, int], int] = {}
        self.generation = 0
        self.stamp: float | None = None
        # this scan's child states, computed in one batch by _prepare_children
        self._updates: dict[tuple[int, Hashable], tuple[FloatArray, FloatArray, Any]] = {}
        self._initiated: dict[Hashable, tuple[FloatArray, FloatArray, Any]] = {}
        self._scan_initiated = False  # whether _initiated holds this scan's measurements
        # the plain MHT defers its children's states to one batch at the end of the step,
        # for the children some hypothesis kept (:meth:`_fill_deferred`): (child, parent
        # node, scan measurement) updated, (new node, scan measurement) initiated
        self._defer = False
        self._deferred: list[tuple[TrackNode, TrackNode, int]] = []
        self._deferred_births: list[tuple[TrackNode, int]] = []
        self._lp_live: FloatArray = np.empty((0, 3))  # label log-probs of the live nodes
        self._cost_live: FloatArray = np.empty((0, 0))  # their detection costs
        # the label costs as plain floats, made once per scan when a listing needs them
        # (:meth:`_plain_costs`): occluded and deleted costs per live node, new and
        # false-alarm costs per measurement (the first, detection costs, left empty)
        self._plain: PlainCosts = ([], [], [], [], [])
        self._plain_made = False
        self._log_rates: tuple[FloatArray, FloatArray] = (np.empty(0), np.empty(0))
        self._expiry = ExpiryOdds()  # existence odds by label probabilities and misses
        self._gap = _max_gap(params.ratio)  # ratio pruning's cost gap, set each step
        self._solves = 0  # this step's assignment problems solved
        self._degraded = 0  # this step's degraded clusters
        self._largest = 0  # this step's largest cluster problem (tracks + measurements)
        self._most_solves = 0  # this step's most assignment problems of one cluster
        self.deferred_states = True
        """Whether the plain MHT makes its children's states at the end of the step, for
        the children kept only (:meth:`_fill_deferred`); the same states as made per scan
        for every gated pair before branching (off only to test that)."""
        self.shortcuts = True
        """Whether clusters of one track and at most one measurement take the shortcuts
        (:meth:`_branch_lone`, :func:`~.listing.single_children`); they give the same
        hypotheses as the general path (off only to test that)."""

    # ------------------------------------------------------------------ public

    def best_tracks(self) -> list[TrackNode]:
        """Track nodes of the best hypothesis (best of every cluster), by family."""
        return self.best_nodes()[0]

    def best_probabilities(self) -> dict[int, float]:
        """Family -> probability of its cluster's best hypothesis."""
        return self.best_nodes()[1]

    def best_nodes(self) -> tuple[list[TrackNode], dict[int, float]]:
        """:meth:`best_tracks` and :meth:`best_probabilities` in one pass over the
        clusters (the probability of each cluster's best hypothesis computed once)."""
        out: list[TrackNode] = []
        probs: dict[int, float] = {}
        for c in self.clusters:
            best = c.hypotheses[0]  # (Cluster.best)
            p = math.exp(best.log_weight)
            for t in best.tracks:
                probs[t.family] = p
            out += best.tracks
        out.sort(key=BY_FAMILY)
        return out, probs

    def step(self, measurements: Meas, stamp: float) -> StepStats:
        """Process one scan's measurements taken at ``stamp`` [s]."""
        self._solves = self._degraded = self._largest = self._most_solves = 0
        self._gap = _max_gap(self.params.ratio)
        live = [n for nodes in self.tree.nodes_by_family.values() for n in nodes]
        if live:
            self.model.predict(live, stamp)
        n_meas = len(measurements)
        if live and n_meas:
            gated, loglik = self.model.score(live, measurements)
        else:
            gated = np.zeros((len(live), n_meas), dtype=bool)
            loglik = np.full((len(live), n_meas), -np.inf)
        row_of = {n.node_id: i for i, n in enumerate(live)}
        self._lp_live = self.labels.track_log_probs(live) if live else np.empty((0, 3))
        self._cost_live = _detection_costs(gated, loglik, self._lp_live)
        self._plain_made = False
        plain = type(self.branches) is SingleModel
        self._defer = plain and self.deferred_states
        self._prepare_children(live, gated, measurements, stamp)
        fam_meas = self._family_gates(live, gated)
        cluster_of = {f: c for c in self.clusters for f in c.families}
        self._drop_settled_links(cluster_of)
        parts = components(fam_meas, self.links, n_meas)
        log_new, log_fal = self.labels.measurement_log_rates(measurements)
        self._log_rates = (log_new, log_fal)
        new_clusters: list[Cluster] = []
        live_nodes: dict[int, TrackNode] = {}  # (the clusters' nodes by id)
        for fams, meas_idx in parts:
            parents = self._parents(fams, cluster_of)
            lone = None
            if (
                self.shortcuts
                and plain
                and len(meas_idx) <= 1
                and all(len(p.tracks) <= 1 for p in parents)
            ):
                lone = self._branch_lone(
                    parents, measurements, meas_idx, stamp, loglik, row_of, log_new, log_fal
                )
            children = lone if lone is not None else self._branch(
                parents, measurements, meas_idx, stamp, gated, loglik, row_of, log_new, log_fal
            )  # fmt: skip
            self._link(children, fams, fam_meas, meas_idx)
            # (the cluster's nodes, each once, by id: its families in the order of their
            # first node, and the scan's live nodes in the order of the clusters)
            nodes = {id(t): t for h in children for t in h.tracks}
            if nodes:
                families = frozenset([t.family for t in nodes.values()])
                new_clusters.append(Cluster(families, children))
                live_nodes.update(nodes)
        if self._defer:
            self._fill_deferred(measurements, stamp, live_nodes)
        self.clusters = self._expire(new_clusters, live_nodes.values())
        if self.clusters is not new_clusters:  # some nodes went
            live_nodes = {id(t): t for c in self.clusters for h in c.hypotheses for t in h.tracks}
        self.tree.collect(live_nodes.values())
        self.generation += 1
        self.stamp = stamp
        sizes = [len(c.hypotheses) for c in self.clusters]
        return StepStats(
            n_clusters=len(self.clusters),
            n_hypotheses=int(sum(sizes)),
            max_cluster_hypotheses=max(sizes, default=0),
            n_live_nodes=len(live_nodes),  # (tree.n_nodes: collect indexed each once)
            n_families=self.tree.n_families,
            families_created=self.tree.families_created,
            assignment_solves=self._solves,
            degraded_clusters=self._degraded,
            largest_cluster=self._largest,
            max_cluster_solves=self._most_solves,
        )

    def _expire(self, clusters: list[Cluster], nodes: Iterable[TrackNode]) -> list[Cluster]:
        """The clusters without the tracks unseen for longer than their label
        probabilities allow (:mod:`.expiry`); clusters left without a family go (the list
        ``clusters`` itself when nothing goes). ``nodes`` are the clusters' track nodes,
        each once, in the order of their first appearance."""
        ratio = self.params.existence_ratio
        if ratio <= 0:
            return clusters
        unseen = [t for t in nodes if t.misses]
        if not unseen:
            return clusters
        gone = self._expiry.expired(unseen, self.labels.track_log_probs(unseen), math.log(ratio))
        if not gone:
            return clusters
        out: list[Cluster] = []
        for c in clusters:
            if any(t.node_id in gone for h in c.hypotheses for t in h.tracks):
                kept = drop_nodes(c, gone)
                if kept is not None:
                    out.append(kept)
            else:
                out.append(c)
        return out

    # ------------------------------------------------------------------ clustering

    def _family_gates(self, live: list[TrackNode], gated: BoolArray) -> dict[int, set[int]]:
        """The measurements in the gate of some node of each family."""
        out: dict[int, set[int]] = {n.family: set() for n in live}
        rows, cols = np.nonzero(gated)
        for i, j in zip(rows.tolist(), cols.tolist(), strict=True):
            out[live[i].family].add(j)
        return out

    def _drop_settled_links(self, cluster_of: dict[int, Cluster]) -> None:
        """Forget links whose shared measurements are settled in every hypothesis
        (``cluster_of``: each family's cluster).

        A cluster with a single hypothesis has nothing uncertain: all its links go. Once
        N-scan pruning has acted (every hypothesis has N ancestors) all hypotheses share the
        ancestor N generations back, which fixes every assignment up to then; a link made at
        or before that generation cannot make the parts' hypotheses inconsistent any more.
        Each cluster's two questions are asked only for the clusters of linked families,
        and whether it is pruned only where the answer can matter.
        """
        if not self.links:
            return
        n = self.params.depth
        settled_before = self.generation - 1 - n
        pruned: dict[int, bool] = {}  # by id(cluster)

        def settled(c: Cluster) -> bool:
            got = pruned.get(id(c))
            if got is None:
                got = pruned[id(c)] = all(len(h.ancestors) >= n for h in c.hypotheses)
            return got

        keep: dict[tuple[int, int], int] = {}
        for (a, b), last in self.links.items():
            ca, cb = cluster_of.get(a), cluster_of.get(b)
            if ca is None or cb is None:
                continue  # a family died
            if len(ca.hypotheses) == 1 or len(cb.hypotheses) == 1:
                continue
            if last <= settled_before and settled(ca) and settled(cb):
                continue
            keep[(a, b)] = last
        self.links = keep

    def _parents(self, fams: frozenset[int], cluster_of: dict[int, Cluster]) -> list[Hypothesis]:
        if fams:  # (most clusters: one cluster of the last scan, the same families)
            c = cluster_of[next(iter(fams))]
            if c.families == fams:  # (the general path below gives its hypotheses)
                return c.hypotheses
        touching = list({id(c): c for f in fams for c in (cluster_of[f],)}.values())
        if not touching:
            return [Hypothesis(0.0, ())]
        parts: list[list[Hypothesis]] = []
        whole = len(touching) == 1
        for c in touching:
            if c.families <= fams:
                parts.append(c.hypotheses)
            else:
                parts.append(project(c.hypotheses, fams & c.families))
                whole = False
        if whole:
            return parts[0]
        return product(parts, self.params.k)

    def _link(
        self,
        children: list[Hypothesis],
        fams: frozenset[int],
        fam_meas: dict[int, set[int]],
        meas_idx: list[int],
    ) -> None:
        if not meas_idx or not fams:  # (families without measurements, or one measurement)
            return
        born = {t.measurement: t.family for h in children for t in h.tracks if t.label == NEW}
        if len(fams) + bool(born) < 2:  # no two families can share a measurement
            return
        links, generation = self.links, self.generation
        for j in meas_idx:
            sharing = [f for f in fams if j in fam_meas[f]]
            if j in born:
                sharing.append(born[j])
            if len(sharing) > 1:  # every pair (x, y), x < y, in the order of x then y
                sharing.sort()
                for pair in itertools.combinations(sharing, 2):
                    links[pair] = generation

    def _link_replaced(self, child: Sequence[TrackNode], parent: Sequence[TrackNode]) -> None:
        """Link families a child created other than from a new measurement (a model's split
        or merge tracks) with each other and with the parent's families they replaced, so
        the cluster stays whole until these alternatives are settled."""
        parent_fams = {t.family for t in parent}
        born = {t.family for t in child if t.family not in parent_fams and t.label != NEW}
        if not born:
            return
        child_fams = {t.family for t in child}
        group = sorted(born | (parent_fams - child_fams))
        for x in range(len(group)):
            for y in range(x + 1, len(group)):
                self.links[(group[x], group[y])] = self.generation

    # ------------------------------------------------------------------ branching

    def _branch(
        self,
        parents: list[Hypothesis],
        measurements: Meas,
        meas_list: list[int],
        stamp: float,
        gated: BoolArray,
        loglik: FloatArray,
        row_of: dict[int, int],
        log_new: FloatArray,
        log_fal: FloatArray,
    ) -> list[Hypothesis]:
        if type(self.branches) is SingleModel:
            return self._branch_plain(
                parents, measurements, meas_list, stamp, loglik, row_of, log_new, log_fal
            )
        meas_idx = np.asarray(meas_list, dtype=np.intp)
        # the branches (models) of every parent
        plans: list[tuple[Hypothesis, Branch]] = []

        def gate_row(node: TrackNode) -> BoolArray:
            return gated[row_of[node.node_id], meas_idx]

        for parent in parents:
            for b in self.branches.branches(parent.tracks, gate_row, meas_idx):
                plans.append((parent, b))
        # branches that see the same observations share one k-best problem; a model that
        # brings its own partition of the observations (re-clustering) gets its own
        partitions: dict[tuple[Hashable, ...] | None, list[int]] = {}
        for pi, (_, branch) in enumerate(plans):
            obs = branch.observations
            partitions.setdefault(None if obs is None else obs.keys, []).append(pi)
        max_gap = self._gap
        solutions: list[tuple[int, LabelledAssignment, float]] = []
        for members in partitions.values():
            found = self._k_best(
                [plans[pi][1].tracks for pi in members],
                [-(plans[pi][0].log_weight + plans[pi][1].log_prior) for pi in members],
                plans[members[0]][1].observations,
                measurements,
                meas_list,
                row_of,
                log_new,
                log_fal,
                max_gap,
            )
            solutions += [(members[pi], dec, total) for pi, dec, total in found]
        if len(partitions) > 1:  # the global k best of the partitions' k best
            solutions.sort(key=lambda sol: sol[2])
            best = solutions[0][2] if solutions else math.inf
            solutions = [sol for sol in solutions[: self.params.k] if sol[2] <= best + max_gap]

        # make the children nodes each (node, label) needs, once, in batches
        # per plan: ids, scan origins and measurement set of its branch's observations
        plan_items: list[tuple[Sequence[Hashable], Sequence[int], Any, bool]] = []
        for _, branch in plans:
            obs = branch.observations
            if obs is None:
                plan_items.append((meas_list, meas_list, measurements, False))
            else:
                plan_items.append((obs.keys, obs.origin, obs.measurements, True))

        to_update: dict[tuple[int, Hashable], tuple[TrackNode, Hashable, Any, int]] = {}
        born: dict[Hashable, tuple[Any, int, int]] = {}
        for pi, dec, _ in solutions:
            ids, origin, source, local = plan_items[pi]
            tlabels, tmeas = dec.track_label, dec.track_measurement
            for i, node in enumerate(plans[pi][1].tracks):
                if tlabels[i] == DETECTED:
                    jl = tmeas[i]
                    j = ids[jl]
                    key = (node.node_id, j)
                    if not local and key in to_update:  # the same entry again
                        continue
                    if j not in node.children:
                        to_update[key] = (node, j, source, jl if local else meas_list[jl])
            for a, lab in enumerate(dec.measurement_label):
                if lab == NEW_LABEL and ids[a] not in born:
                    born[ids[a]] = (source, a if local else meas_list[a], origin[a])
        self._make_detected_children(list(to_update.values()), measurements, stamp, loglik, row_of)
        new_nodes = self._new_nodes(born, measurements, stamp)

        return self._assemble(
            solutions,
            [p for p, _ in plans],
            [b.tracks for _, b in plans],
            [items[0] for items in plan_items],
            [b.model for _, b in plans],
            new_nodes,
            stamp,
            models=True,
        )

    def _branch_plain(
        self,
        parents: list[Hypothesis],
        measurements: Meas,
        meas_list: list[int],
        stamp: float,
        loglik: FloatArray,
        row_of: dict[int, int],
        log_new: FloatArray,
        log_fal: FloatArray,
    ) -> list[Hypothesis]:
        """:meth:`_branch` of the plain MHT (one branch per parent: its own tracks, prior
        1, the cluster's measurements ``meas_list``): the same children, nodes and ids in the
        same order, without the branch objects and their bookkeeping."""
        tracks_of = [p.tracks for p in parents]
        max_gap = self._gap
        solutions = self._k_best(
            tracks_of,
            [-(p.log_weight + 0.0) for p in parents],  # (+ the single branch's log prior)
            None,
            measurements,
            meas_list,
            row_of,
            log_new,
            log_fal,
            max_gap,
        )
        # make the children nodes each (node, label) needs, once, in batches
        plan, assemble = listing.COMPILED_PLAN_PLAIN, listing.COMPILED_ASSEMBLE_PLAIN
        planned = NotImplemented
        if plan is not None:  # (the same pairs and births, or NotImplemented)
            planned = plan(solutions, tracks_of, meas_list, measurements)
        if planned is NotImplemented:
            pairs, born = self._plan_plain(solutions, tracks_of, meas_list, measurements)
        else:
            pairs, born = planned
        new_nodes = self._make_plain(pairs, born, measurements, stamp, loglik, row_of)

        if assemble is not None and planned is not NotImplemented:
            children = assemble(
                solutions, parents, tracks_of, meas_list, new_nodes, self._occluded_child,
                stamp, Hypothesis, self.params.depth, np.logaddexp,
            )  # fmt: skip
            if children is not NotImplemented:  # (the children _assemble makes)
                return self._prune_children(children)
        n = len(parents)
        return self._assemble(
            solutions, parents, tracks_of, [meas_list] * n, [0] * n, new_nodes, stamp, models=False
        )

    def _make_plain(
        self,
        pairs: list[tuple[TrackNode, Hashable, Any, int]],
        born: dict[Hashable, tuple[Any, int, int]],
        measurements: Meas,
        stamp: float,
        loglik: FloatArray,
        row_of: dict[int, int],
    ) -> dict[Hashable, TrackNode]:
        """:meth:`_make_detected_children` of ``pairs``, then :meth:`_new_nodes` of
        ``born``: by the compiled one (:data:`~.listing.COMPILED_MAKE_PLAIN`) where the
        states are deferred, which makes the same nodes with the same ids in the same
        order, else (and for input it leaves to Python) by those two."""
        made = listing.COMPILED_MAKE_PLAIN
        if made is not None and self._defer:
            tree = self.tree
            new_nodes = made(
                pairs, born, loglik, row_of, TrackNode, tree.new_node_id, tree.new_family,
                stamp, _DEFERRED, NODE_DETECTED, NEW, self._deferred, self._deferred_births,
            )  # fmt: skip
            if new_nodes is not NotImplemented:
                return new_nodes
        self._make_detected_children(pairs, measurements, stamp, loglik, row_of)
        return self._new_nodes(born, measurements, stamp)

    @staticmethod
    def _plan_plain(
        solutions: list[tuple[int, LabelledAssignment, float]],
        tracks_of: list[tuple[TrackNode, ...]],
        meas_list: list[int],
        measurements: Meas,
    ) -> tuple[list[tuple[TrackNode, Hashable, Any, int]], dict[Hashable, tuple[Any, int, int]]]:
        """The children nodes the plain MHT's ``solutions`` need, each once, in the order
        they are first met: ``(node, j, measurements, j)`` per detected child not made yet
        (for :meth:`_make_detected_children`) and ``{j: (measurements, j, j)}`` per
        measurement labelled new (for :meth:`_new_nodes`); ``j`` a scan measurement."""
        to_update: dict[tuple[int, int], tuple[TrackNode, Hashable, Any, int]] = {}
        born: dict[Hashable, tuple[Any, int, int]] = {}
        for pi, dec, _ in solutions:
            tlabels, tmeas = dec.track_label, dec.track_measurement
            for i, node in enumerate(tracks_of[pi]):
                if tlabels[i] == DETECTED:
                    j = meas_list[tmeas[i]]
                    key = (node.node_id, j)
                    if key not in to_update and j not in node.children:
                        to_update[key] = (node, j, measurements, j)
            for a, lab in enumerate(dec.measurement_label):
                if lab == NEW_LABEL:
                    j = meas_list[a]
                    if j not in born:
                        born[j] = (measurements, j, j)
        return list(to_update.values()), born

    def _assemble(
        self,
        solutions: list[tuple[int, LabelledAssignment, float]],
        parents: Sequence[Hypothesis],
        tracks_of: Sequence[Sequence[TrackNode]],
        ids_of: Sequence[Sequence[Hashable]],
        model_of: Sequence[int],
        new_nodes: dict[Hashable, TrackNode],
        stamp: float,
        models: bool,
    ) -> list[Hypothesis]:
        """The pruned children of ``solutions`` ((plan, assignment, cost)): plan ``pi`` is
        parent ``parents[pi]`` with tracks ``tracks_of[pi]``, model ``model_of[pi]`` and
        the ids ``ids_of[pi]`` of the measurements its assignment indexes (children made
        beforehand). ``models``: branch models (the plain MHT's parents' tracks are sorted
        by family, and its children hold their parent's families)."""
        children: dict[tuple[int, ...], Hypothesis] = {}
        history: dict[int, tuple[Hashable, ...]] = {}  # per parent (most have several children)
        for pi, dec, total in solutions:
            parent = parents[pi]
            kept = history.get(id(parent))
            if kept is None:
                kept = history[id(parent)] = self._history(parent)
            ids = ids_of[pi]
            tracks: list[TrackNode] = []
            tlabels, tmeas = dec.track_label, dec.track_measurement
            for i, node in enumerate(tracks_of[pi]):
                label = tlabels[i]
                if label == DETECTED:
                    tracks.append(node.children[ids[tmeas[i]]])
                elif label == OCCLUDED:
                    child = node.children.get(-1)
                    tracks.append(child if child is not None else self._occluded_child(node, stamp))
            born_here = False
            for a, lab in enumerate(dec.measurement_label):
                if lab == NEW_LABEL:
                    tracks.append(new_nodes[ids[a]])
                    born_here = True
            if born_here or models:
                tracks.sort(key=BY_FAMILY)
            added = self._add_child(children, kept, tracks, total, model_of[pi])
            if added and models:
                self._link_replaced(tracks, parent.tracks)
        return self._prune_children(children)

    def _add_child(
        self,
        children: dict[tuple[int, ...], Hypothesis],
        history: tuple[Hashable, ...],
        tracks: list[TrackNode],
        total: float,
        model: int,
    ) -> bool:
        """Add the child hypothesis holding ``tracks`` at cost ``total`` of a parent whose
        :meth:`_history` is ``history``; when another child (of another model branch)
        already holds the same tracks, its weight gains this one's instead. Returns whether
        a new child was made."""
        key = tuple([t.node_id for t in tracks])
        if key in children:
            c = children[key]
            c.log_weight = float(np.logaddexp(c.log_weight, -total))
            return False
        children[key] = Hypothesis(-total, tuple(tracks), history, model=model)
        return True

    def _history(self, parent: Hypothesis) -> tuple[Hashable, ...]:
        """The ancestors of ``parent``'s children: its own and itself, the last N."""
        n_scan = self.params.depth
        ancestors = (*parent.ancestors, parent.hypothesis_id)
        return ancestors[-n_scan:] if n_scan else ()

    def _prune_children(self, children: dict[tuple[int, ...], Hypothesis]) -> list[Hypothesis]:
        """A cluster's children normalised, N-scan and ratio pruned (by the compiled
        :func:`~.hypothesis.prune_children` where it is built)."""
        if len(children) == 1:
            (only,) = children.values()
            if math.isfinite(only.log_weight):  # normalising and both prunings give log 1
                only.log_weight = 0.0
                return [only]
        hyps = list(children.values())
        compiled = listing.COMPILED_PRUNE
        if compiled is not None:  # (the same hypotheses and floats, or NotImplemented)
            out = compiled(hyps, self.params.depth, self.params.ratio)
            if out is not NotImplemented:
                return out
        return prune_children(hyps, self.params.depth, self.params.ratio)

    def _branch_lone(
        self,
        parents: list[Hypothesis],
        measurements: Meas,
        meas_idx: list[int],
        stamp: float,
        loglik: FloatArray,
        row_of: dict[int, int],
        log_new: FloatArray,
        log_fal: FloatArray,
    ) -> list[Hypothesis] | None:
        """:meth:`_branch` of a plain-MHT cluster whose parents hold at most one track (one
        family) and which has at most one measurement, most clusters (a leg and its own
        detection, or a leg unseen): the same children, hypotheses and node, family and
        hypothesis ids in the same order, from :func:`~.listing.single_children` on this
        scan's tables, without the general path's per-cluster arrays and objects. None
        (use :meth:`_branch`) for a cluster it does not cover: over ``max_cluster_size``, or
        with a node not scored this scan."""
        if len(parents) == 1 and len(meas_idx) == 1 and len(parents[0].tracks) == 1:
            obvious = self._branch_obvious(
                parents[0], measurements, meas_idx[0], stamp, loglik, row_of, log_new, log_fal
            )
            if obvious is not None:
                return obvious
        uniq: dict[int, int] = {}
        nodes_u: list[TrackNode] = []
        rows_of: list[list[int]] = []
        for parent in parents:
            if parent.tracks:
                t = parent.tracks[0]
                i = uniq.get(t.node_id)
                if i is None:
                    if t.node_id not in row_of:
                        return None
                    i = uniq[t.node_id] = len(nodes_u)
                    nodes_u.append(t)
                rows_of.append([i])
            else:
                rows_of.append([])
        m = len(meas_idx)
        size = len(nodes_u) + m
        if size > self.params.max_cluster_size:
            return None
        self._largest = max(self._largest, size)
        j = meas_idx[0] if m else -1
        cost_live, lp_live = self._cost_live, self._lp_live
        tm: list[float] = []
        c_occ: list[float] = []
        c_del: list[float] = []
        for t in nodes_u:
            row = row_of[t.node_id]
            tm.append(float(cost_live[row, j]) if m else math.inf)
            c_occ.append(-float(lp_live[row, OCCLUDED]))
            c_del.append(-float(lp_live[row, DELETED]))
        meas = (-float(log_new[j]), -float(log_fal[j])) if m else None
        priors = [-(p.log_weight + 0.0) for p in parents]  # the single branch's log prior is 0
        max_gap = self._gap
        solutions = single_children(priors, rows_of, tm, c_occ, c_del, meas, self.params.k, max_gap)
        # the nodes, in the order _branch makes them: detected children, new track, occluded
        to_update: list[tuple[TrackNode, Hashable, Any, int]] = []
        new_track = False
        for _, pi, tl, ml in solutions:
            if tl == DETECTED:
                node = parents[pi].tracks[0]
                if j not in node.children and all(node is not u[0] for u in to_update):
                    to_update.append((node, j, measurements, j))
            elif ml == NEW_LABEL:
                new_track = True
        self._make_detected_children(to_update, measurements, stamp, loglik, row_of)
        new_node = None
        if new_track:
            new_node = self._new_nodes({j: (measurements, j, j)}, measurements, stamp)[j]
        children: dict[tuple[int, ...], Hypothesis] = {}
        history: dict[int, tuple[Hashable, ...]] = {}
        for total, pi, tl, ml in solutions:
            parent = parents[pi]
            kept = history.get(pi)
            if kept is None:
                kept = history[pi] = self._history(parent)
            tracks: list[TrackNode] = []
            if tl == DETECTED:
                tracks.append(parent.tracks[0].children[j])
            elif tl == OCCLUDED:
                node = parent.tracks[0]
                child = node.children.get(-1)
                tracks.append(child if child is not None else self._occluded_child(node, stamp))
            if ml == NEW_LABEL:
                assert new_node is not None
                tracks.append(new_node)  # a new family: after the parent's
            self._add_child(children, kept, tracks, total, 0)
        return self._prune_children(children)

    def _branch_obvious(
        self,
        parent: Hypothesis,
        measurements: Meas,
        j: int,
        stamp: float,
        loglik: FloatArray,
        row_of: dict[int, int],
        log_new: FloatArray,
        log_fal: FloatArray,
    ) -> list[Hypothesis] | None:
        """:meth:`_branch_lone` of the commonest cluster, one parent hypothesis with one
        track and one measurement (a leg and its own detection), when its only child kept
        is the track detected with the measurement: every other child (occluded or deleted,
        the measurement new or a false alarm) costs more than that one plus the ratio gap.
        The costs are the floats :func:`~.listing.single_children` sums, so the child, its
        node and its ids are the same; None (take the listing) in any other case."""
        t = parent.tracks[0]
        row = row_of.get(t.node_id)
        if row is None or self.params.max_cluster_size < 2:
            return None
        tm = float(self._cost_live[row, j])
        prior = -(parent.log_weight + 0.0)
        detected = prior + tm
        if not (math.isfinite(detected) and math.isfinite(prior)):
            return None
        limit = detected + self._gap
        lp = self._lp_live
        c_new, c_fal = -float(log_new[j]), -float(log_fal[j])
        for c in (-float(lp[row, OCCLUDED]), -float(lp[row, DELETED])):
            cost = prior + c
            if not (cost + c_new > limit and cost + c_fal > limit):
                return None
        self._largest = max(self._largest, 2)
        child = t.children.get(j)
        if child is None:  # (its update is in this scan's batch: the measurement is gated)
            child = self._detected_child(t, j, j, float(loglik[row, j]), stamp)
        return [Hypothesis(0.0, (child,), self._history(parent))]

    def _k_best(
        self,
        tracks_of: list[tuple[TrackNode, ...]],
        priors: list[float],
        obs: BranchObservations | None,
        measurements: Meas,
        meas_list: list[int],
        row_of: dict[int, int],
        log_new: FloatArray,
        log_fal: FloatArray,
        max_gap: float,
    ) -> list[tuple[int, LabelledAssignment, float]]:
        """The k best children of parents (or branches) with tracks ``tracks_of`` and costs
        ``priors`` (-log weight, with the model prior) that all see the same observations
        (``obs``, or the cluster's measurements ``meas_list`` when None); parent indices of
        the result index ``tracks_of``."""
        compiled = listing.COMPILED_K_BEST
        if obs is None and compiled is not None:  # (the same children, or NotImplemented)
            _, occ_all, del_all, new_all, fal_all = self._scan_plain()
            out = compiled(
                tracks_of, priors, row_of, self._cost_live, meas_list, occ_all,
                del_all, new_all, fal_all, self.params.k, max_gap, self.shortcuts,
                self.params.max_cluster_size,
            )  # fmt: skip
            if out is not NotImplemented:
                solutions, size = out
                self._largest = max(self._largest, size)
                return solutions
        meas_idx = np.asarray(meas_list, dtype=np.intp)
        uniq: dict[int, int] = {}
        nodes_u: list[TrackNode] = []
        rows_of: list[list[int]] = []  # each parent's tracks as indices into nodes_u
        for tracks in tracks_of:
            rows = []
            for t in tracks:
                i = uniq.get(t.node_id)
                if i is None:
                    i = uniq[t.node_id] = len(nodes_u)
                    nodes_u.append(t)
                rows.append(i)
            rows_of.append(rows)
        # the costs: per node, once, of matching each measurement and of the unmatched
        # labels; as plain floats from the scan's tables when every node was scored this
        # scan (the commonest case), as arrays otherwise or when Murty's method needs them
        arrays: tuple[FloatArray, FloatArray, FloatArray, FloatArray] | None = None
        plain: PlainCosts | None = None
        if obs is None and all(t.node_id in row_of for t in nodes_u):
            plain = self._plain_costs([row_of[t.node_id] for t in nodes_u], meas_idx)
            n, m = len(nodes_u), meas_idx.size
        else:
            if obs is None:
                tm_cost, lp = self._costs(nodes_u, measurements, meas_idx, row_of)
                c_new, c_fal = log_new[meas_idx], log_fal[meas_idx]
            else:
                lp = self.labels.track_log_probs(nodes_u)
                m = len(obs.measurements)
                if nodes_u and m:
                    g_b, ll_b = self.model.score(nodes_u, obs.measurements)
                    tm_cost = _detection_costs(g_b, ll_b, lp)
                else:
                    tm_cost = np.full((len(nodes_u), m), np.inf)
                c_new, c_fal = self.labels.measurement_log_rates(obs.measurements)
            arrays = (tm_cost, lp, c_new, c_fal)
            n, m = tm_cost.shape
        k = self.params.k
        size = n + m
        self._largest = max(self._largest, size)
        degraded = size > self.params.max_cluster_size
        budget = self.params.max_assignment_solves
        members = list(range(len(tracks_of)))
        if degraded:  # the best parent's best matching and its label variants only
            best = min(range(len(members)), key=lambda i: priors[i])
            members, priors, budget = [members[best]], [priors[best]], 1
            rows_of = [rows_of[best]]
        solutions = None
        if not degraded:
            if plain is None:
                assert arrays is not None
                plain = plain_costs(*arrays)
            solutions = list_children(priors, rows_of, *plain, k, max_gap, shortcut=self.shortcuts)
        if solutions is None:
            if arrays is None:
                tm_cost, lp = self._costs(nodes_u, measurements, meas_idx, row_of)
                arrays = (tm_cost, lp, log_new[meas_idx], log_fal[meas_idx])
            base = build_matrix(*arrays)
            matrices: list[AssignmentMatrix] = [base.subset(r) for r in rows_of]
            work = Work(max_solves=budget)
            solutions = k_best_children(priors, matrices, k, max_gap, work=work)
            self._solves += work.solves
            self._most_solves = max(self._most_solves, work.solves)
            degraded = degraded or work.truncated
        self._degraded += int(degraded)
        if degraded:
            return [(members[pi], dec, total) for pi, dec, total in solutions]
        return solutions

    def _plain_costs(self, live_rows: list[int], meas_idx: NDArray[np.intp]) -> PlainCosts:
        """:func:`~.listing.list_children`'s costs of the live nodes at ``live_rows`` (rows
        of this scan's tables) for the measurements ``meas_idx``, the same floats as the
        arrays :meth:`_costs` takes from the tables: the detection costs taken out of the
        table per cluster, the label costs from the scan's label costs as plain floats
        (made once per scan, at the first cluster that needs them)."""
        _, occ_all, del_all, new_all, fal_all = self._scan_plain()
        js = meas_idx.tolist()
        return (
            self._cost_live.take(live_rows, axis=0).take(meas_idx, axis=1).tolist(),
            [occ_all[i] for i in live_rows],
            [del_all[i] for i in live_rows],
            [new_all[j] for j in js],
            [fal_all[j] for j in js],
        )

    def _scan_plain(self) -> PlainCosts:
        """This scan's label costs as plain floats (:func:`~.listing.plain_costs`, without
        detection costs), made at the first cluster that needs them."""
        if not self._plain_made:
            self._plain = plain_costs(np.empty((0, 0)), self._lp_live, *self._log_rates)
            self._plain_made = True
        return self._plain

    def _costs(
        self,
        nodes: Sequence[TrackNode],
        measurements: Meas,
        meas_idx: NDArray[np.intp],
        row_of: dict[int, int],
    ) -> tuple[FloatArray, FloatArray]:
        """Detection costs (n, m) ``-(log p_det + log N)`` (inf where not gated) of ``nodes``
        for the cluster's measurements, and their label log-probabilities (n, 3); taken from
        this scan's tables, except for nodes a branch generator made or re-predicted."""
        if all(t.node_id in row_of for t in nodes):
            live_rows = np.array([row_of[t.node_id] for t in nodes], dtype=np.intp)
            return self._cost_live[live_rows[:, None], meas_idx], self._lp_live[live_rows]
        lp = self.labels.track_log_probs(nodes)
        if meas_idx.size == 0:
            return np.zeros((len(nodes), 0)), lp
        # the live nodes from the tables, only the others are scored
        cost = np.empty((len(nodes), meas_idx.size))
        made = [i for i, t in enumerate(nodes) if t.node_id not in row_of]
        known = [i for i, t in enumerate(nodes) if t.node_id in row_of]
        if known:
            rows = [row_of[nodes[i].node_id] for i in known]
            cost[known] = self._cost_live[rows][:, meas_idx]
        g_m, ll_m = self.model.score([nodes[i] for i in made], measurements)
        cost[made] = _detection_costs(g_m[:, meas_idx], ll_m[:, meas_idx], lp[made])
        return cost, lp

    # ------------------------------------------------------------------ track tree

    def _prepare_children(
        self, live: list[TrackNode], gated: BoolArray, measurements: Meas, stamp: float
    ) -> None:
        """Compute, in one batch each, the update of every live node with every measurement
        it gates (and, at the first birth of the scan, a new track at every measurement:
        :meth:`_new_nodes`); the clusters then take what their children need (one batch per
        scan instead of one per cluster). The plain MHT defers them instead
        (:meth:`_fill_deferred`)."""
        self._updates = {}
        self._initiated = {}
        self._scan_initiated = False
        self._deferred = []
        self._deferred_births = []
        if self._defer:
            return
        rows, cols = np.nonzero(gated)
        nodes = [live[i] for i in rows.tolist()]
        js = cols.tolist()
        states = self.model.update(nodes, measurements, js, stamp) if nodes else []
        self._updates = {(n.node_id, j): st for n, j, st in zip(nodes, js, states, strict=True)}

    def _fill_deferred(
        self, measurements: Meas, stamp: float, live_nodes: dict[int, TrackNode]
    ) -> None:
        """The states of the plain MHT's children made this scan that some hypothesis
        kept (``live_nodes``, by ``id``): the Kalman updates in one batch, the new tracks
        in another. The others were pruned; their nodes are dropped with the tree's next
        collection, stateless. (The track model's batches give every item the same floats
        whatever the batch holds, so this gives the states the per-scan batch gave.)"""
        kept = [d for d in self._deferred if id(d[0]) in live_nodes]
        if kept:
            states = self.model.update(
                [d[1] for d in kept], measurements, [d[2] for d in kept], stamp
            )
            for (child, _, _), (mean, cov, payload) in zip(kept, states, strict=True):
                child.mean, child.cov, child.payload = mean, cov, payload
        born = [b for b in self._deferred_births if id(b[0]) in live_nodes]
        if born:
            states = self.model.initiate(measurements, [b[1] for b in born], stamp)
            for (node, _), (mean, cov, payload) in zip(born, states, strict=True):
                node.mean, node.cov, node.payload = mean, cov, payload
        self._deferred = []
        self._deferred_births = []

    def _make_detected_children(
        self,
        pairs: list[tuple[TrackNode, Hashable, Any, int]],
        measurements: Meas,
        stamp: float,
        loglik: FloatArray,
        row_of: dict[int, int],
    ) -> None:
        """Create (once) the child of each node updated with an observation: ``(node, id,
        measurement set, index in it)``, the id being the scan index or a model's key."""
        if not pairs:
            return
        if self._defer:  # (the plain MHT: scan measurements, states made at the end)
            for node, j, _, jl in pairs:
                self._detected_child(node, j, jl, float(loglik[row_of[node.node_id], jl]), stamp)
            return
        missing = [p for p in pairs if (p[0].node_id, p[1]) not in self._updates]
        by_source: dict[int, list[tuple[TrackNode, Hashable, Any, int]]] = {}
        for p in missing:  # nodes a branch generator made or re-predicted, own observations
            by_source.setdefault(id(p[2]), []).append(p)
        for group in by_source.values():
            states = self.model.update(
                [p[0] for p in group], group[0][2], [p[3] for p in group], stamp
            )
            self._updates.update(
                ((node.node_id, j), st) for (node, j, _, _), st in zip(group, states, strict=True)
            )
        for node, j, source, jl in pairs:
            row = row_of.get(node.node_id)
            own = source is not measurements
            self._detected_child(
                node,
                j,
                jl if not own else -1,
                float(loglik[row, jl]) if row is not None and not own else 0.0,
                stamp,
            )

    def _detected_child(
        self, node: TrackNode, j: Hashable, jl: int, loglik: float, stamp: float
    ) -> TrackNode:
        """The child of ``node`` updated with observation ``j`` (its update computed
        already, or, in the plain MHT, made at the end of the step by
        :meth:`_fill_deferred`), made and stored in ``node.children``; ``jl`` is its scan
        measurement (-1 for a model's own observation) and ``loglik`` its log-likelihood."""
        if self._defer:
            mean, cov, payload = _DEFERRED, _DEFERRED, None
        else:
            mean, cov, payload = self._updates[(node.node_id, j)]
        # (positional: the fields in their order, node_id to payload; a third of the cost
        # of passing them by keyword)
        child = node.children[j] = TrackNode(
            self.tree.new_node_id(),
            node.family,
            node.node_id,
            mean,
            cov,
            stamp,
            NODE_DETECTED,
            jl,  # measurement
            node.hits + 1,
            0,  # misses
            node.age + 1,
            loglik,
            payload,
        )
        if self._defer:
            self._deferred.append((child, node, jl))
        return child

    def _new_nodes(
        self, born: dict[Hashable, tuple[Any, int, int]], measurements: Meas, stamp: float
    ) -> dict[Hashable, TrackNode]:
        """One new track (a new family) per observation labelled *new* in some child;
        ``born`` maps its id to (measurement set, index in it, scan index of its origin).
        Scan measurements first in scan order, then a model's own observations."""
        if self._defer:  # (the plain MHT: scan measurements, states made at the end)
            return self._new_nodes_deferred(born, stamp)
        if born and not self._scan_initiated:  # the scan's batch, once (most scans: none)
            every = list(range(len(measurements)))
            states = self.model.initiate(measurements, every, stamp) if every else []
            self._initiated.update(zip(every, states, strict=True))
            self._scan_initiated = True
        scan_js = sorted(v[1] for v in born.values() if v[0] is measurements)
        scan: list[Hashable] = [*scan_js]
        own = [j for j, (src, _, _) in born.items() if src is not measurements]
        for j in own:
            if j not in self._initiated:
                src, jl, _ = born[j]
                self._initiated[j] = self.model.initiate(src, [jl], stamp)[0]
        out: dict[Hashable, TrackNode] = {}
        for j in [*scan, *own]:
            mean, cov, payload = self._initiated[j]
            out[j] = TrackNode(  # (positional, as in _detected_child)
                self.tree.new_node_id(),
                self.tree.new_family(),
                -1,  # parent_id
                mean,
                cov,
                stamp,
                NEW,
                born[j][2],  # measurement
                1,  # hits
                0,  # misses
                0,  # age
                0.0,  # loglik
                payload,
            )
        return out

    def _new_nodes_deferred(
        self, born: dict[Hashable, tuple[Any, int, int]], stamp: float
    ) -> dict[Hashable, TrackNode]:
        """:meth:`_new_nodes` of the plain MHT (every observation a scan measurement, its
        own id): the nodes in scan order, their states made by :meth:`_fill_deferred`."""
        out: dict[Hashable, TrackNode] = {}
        for jl in sorted(v[1] for v in born.values()):
            node = out[jl] = TrackNode(  # (positional, as in _detected_child)
                self.tree.new_node_id(),
                self.tree.new_family(),
                -1,  # parent_id
                _DEFERRED,
                _DEFERRED,
                stamp,
                NEW,
                born[jl][2],  # measurement
            )
            self._deferred_births.append((node, jl))
        return out

    def _occluded_child(self, node: TrackNode, stamp: float) -> TrackNode:
        child = node.children.get(-1)
        if child is None:
            mean, cov, payload = self.model.coast(node, stamp)
            child = TrackNode(  # (positional, as in _detected_child)
                self.tree.new_node_id(),
                node.family,
                node.node_id,
                mean,
                cov,
                stamp,
                NODE_OCCLUDED,
                -1,  # measurement
                node.hits,
                node.misses + 1,
                node.age + 1,
                0.0,  # loglik
                payload,
                None,  # pred_mean
                None,  # pred_cov
                {},  # children
                node.detected_stamp,
            )
            node.children[-1] = child
        return child
