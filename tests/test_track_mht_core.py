"""The MHT core: normalisation per generation, pruning, clustering, shared track tree."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pytest

from laserpeople.tracking.kalman import KalmanParams
from laserpeople.tracking.mht.core import MHT, MHTParams, StepStats, product, project
from laserpeople.tracking.mht.hypothesis import (
    Hypothesis,
    cap,
    n_scan_prune,
    normalise_hypotheses,
    ratio_prune,
)
from laserpeople.tracking.mht.tracktree import TrackNode
from laserpeople.tracking.point_model import KalmanPointModel, PointMeasurements


class FixedLabels:
    """Free-track probabilities of 000 Table 10 for every track."""

    def track_log_probs(self, nodes: Sequence[TrackNode]) -> np.ndarray:
        return np.tile(np.log([0.3, 0.63, 0.07]), (len(nodes), 1))

    def measurement_log_rates(self, m: PointMeasurements) -> tuple[np.ndarray, np.ndarray]:
        return np.full(len(m), math.log(0.001)), np.full(len(m), math.log(0.003))


def meas(points: np.ndarray, std: float = 0.03) -> PointMeasurements:
    pts = np.asarray(points, float).reshape(-1, 2)
    return PointMeasurements(pts, np.tile(np.eye(2) * std**2, (len(pts), 1, 1)))


def make_mht(**kw: float) -> MHT[PointMeasurements]:
    return MHT(MHTParams(**kw), KalmanPointModel(KalmanParams()), FixedLabels())  # type: ignore[arg-type]


def run_targets(mht: MHT[PointMeasurements], steps: int, seed: int = 0) -> list[int]:
    """Three targets (two close together), misses and clutter; returns hypothesis counts."""
    rng = np.random.default_rng(seed)
    counts = []
    for k in range(steps):
        t = 0.1 * k
        pts = np.array([[1 + 0.5 * t, 0.0], [1 + 0.5 * t, 0.3], [4.0, -2 + 0.3 * t]])
        pts = pts[rng.random(3) > 0.15] + rng.normal(0, 0.02, (0, 2)).sum()
        if rng.random() < 0.3:
            pts = np.vstack([pts, rng.uniform(0, 5, (1, 2))])
        mht.step(meas(pts), t)
        counts.append(sum(len(c.hypotheses) for c in mht.clusters))
    return counts


def test_probabilities_normalised_per_cluster_and_generation() -> None:
    mht = make_mht()
    rng = np.random.default_rng(1)
    for k in range(60):
        t = 0.1 * k
        pts = np.array([[1 + 0.5 * t, 0.0], [1 + 0.5 * t, 0.3]]) + rng.normal(0, 0.02, (2, 2))
        pts = pts[rng.random(2) > 0.2]
        mht.step(meas(pts), t)
        for c in mht.clusters:
            total = sum(math.exp(h.log_weight) for h in c.hypotheses)
            assert total == pytest.approx(1.0, abs=1e-9)
            w = [h.log_weight for h in c.hypotheses]
            assert w == sorted(w, reverse=True)
            assert len(c.hypotheses) <= mht.params.k


def test_tracks_follow_targets_and_ids_are_stable() -> None:
    mht = make_mht()
    families = []
    for k in range(50):
        t = 0.1 * k
        pts = np.array([[1 + 0.5 * t, 0.0], [1.0, 2.0 + 0.4 * t]])
        mht.step(meas(pts), t)
        best = mht.best_tracks()
        families.append(tuple(n.family for n in best))
    assert len(set(families[5:])) == 1 and len(families[-1]) == 2
    pos = np.array([n.mean[:2] for n in mht.best_tracks()])
    want = np.array([[1 + 0.5 * 4.9, 0.0], [1.0, 2.0 + 0.4 * 4.9]])
    np.testing.assert_allclose(np.sort(pos, axis=0), np.sort(want, axis=0), atol=0.05)
    vel = np.array([n.mean[2:] for n in mht.best_tracks()])
    np.testing.assert_allclose(
        np.sort(vel, axis=0), np.sort([[0.5, 0], [0, 0.4]], axis=0), atol=0.1
    )


def test_independent_targets_form_separate_clusters() -> None:
    mht = make_mht()
    for k in range(20):
        t = 0.1 * k
        mht.step(meas(np.array([[1 + 0.3 * t, 0.0], [1.0, 5.0], [6.0, -3.0]])), t)
    assert len(mht.clusters) == 3
    assert all(len(c.families) == 1 for c in mht.clusters)


def test_track_tree_shares_nodes_and_memory_is_bounded() -> None:
    mht = make_mht()
    counts = run_targets(mht, 300)
    assert max(counts) <= 3 * mht.params.k
    # every node is stored once: no two live nodes of a family derive from the same parent
    # with the same measurement
    seen: set[tuple[int, int, int]] = set()
    for nodes in mht.tree.nodes_by_family.values():
        for n in nodes:
            key = (n.family, n.parent_id, n.measurement)
            assert key not in seen
            seen.add(key)
    live_ids = {id(t) for c in mht.clusters for h in c.hypotheses for t in h.tracks}
    assert len(live_ids) == mht.tree.n_nodes
    assert mht.tree.n_nodes < 200
    assert len(mht.links) < 100


def _h(w: float, anc: tuple[int, ...]) -> Hypothesis:
    return Hypothesis(math.log(w), (), anc)


def test_n_scan_keeps_the_branch_with_most_mass() -> None:
    # ancestor 1 has the single best leaf (0.40) but ancestor 2 has more mass (0.55)
    def hyps() -> list[Hypothesis]:  # fresh objects: pruning renormalises in place
        return [_h(0.40, (1, 10)), _h(0.05, (1, 11)), _h(0.30, (2, 12)), _h(0.25, (2, 13))]

    kept = n_scan_prune(hyps(), 2)
    assert {h.ancestors for h in kept} == {(2, 12), (2, 13)}
    assert sum(math.exp(h.log_weight) for h in kept) == pytest.approx(1.0)
    assert math.exp(kept[0].log_weight) == pytest.approx(0.30 / 0.55)
    # depth 1 groups by the parent
    kept1 = n_scan_prune(hyps(), 1)
    assert len(kept1) == 1 and kept1[0].ancestors == (1, 10)
    # short histories are not pruned
    assert len(n_scan_prune([_h(0.5, (1,)), _h(0.5, (2,))], 2)) == 2
    # depth 0 keeps the best leaf
    assert n_scan_prune(hyps(), 0)[0].ancestors == (1, 10)


def test_ratio_prune_keeps_best() -> None:
    def hyps() -> list[Hypothesis]:
        return [_h(0.5, ()), _h(0.3, ()), _h(0.0004, ()), _h(0.1996, ())]

    kept = ratio_prune(hyps(), 1e-3)
    assert len(kept) == 3
    assert math.exp(kept[0].log_weight) == pytest.approx(0.5 / 0.9996)
    assert len(ratio_prune(hyps(), 0.7)) == 1
    assert len(cap(hyps(), 2)) == 2


def test_pruning_inside_mht_keeps_the_best_branch() -> None:
    """With N-scan depth 1 only children of one parent survive each step, and the reported
    tracks equal those of the highest-mass branch (here, the true targets)."""
    mht = make_mht(n_scan=1)
    run_targets(mht, 80, seed=3)
    for c in mht.clusters:
        parents = {h.ancestors[-1] for h in c.hypotheses if h.ancestors}
        assert len(parents) <= 1


def test_product_and_projection() -> None:
    node = lambda f: TrackNode(f * 10, f, -1, np.zeros(4), np.eye(4), 0.0, "new")  # noqa: E731
    a = normalise_hypotheses(
        [Hypothesis(math.log(0.6), (node(1),), (1,)), Hypothesis(math.log(0.4), (), (2,))]
    )
    b = normalise_hypotheses(
        [Hypothesis(math.log(0.9), (node(2),), (3,)), Hypothesis(math.log(0.1), (), (4,))]
    )
    joint = product([a, b], k=10)
    assert len(joint) == 4
    assert math.exp(joint[0].log_weight) == pytest.approx(0.54)
    assert joint[0].ancestors == ((1, 3),)
    back = project(joint, frozenset({1}))
    probs = sorted(math.exp(h.log_weight) for h in back)
    np.testing.assert_allclose(probs, [0.4, 0.6])
    assert len(product([a, b], k=2)) == 2


class SplitModels:
    """A toy interaction model (the group tracker's split, 000 Sec. 4.4): a parent track may
    continue (p_C) or split into two new tracks that must both be matched (p_S)."""

    def __init__(self, mht: MHT[PointMeasurements], p_split: float) -> None:
        self.mht = mht
        self.p_split = p_split
        self.must_match: set[int] = set()

    def branches(self, tracks, gate_row, meas_idx):  # type: ignore[no-untyped-def]
        from laserpeople.tracking.mht.protocols import Branch

        out = [Branch(math.log(1 - self.p_split), tracks, 0)]
        for t in tracks:
            if gate_row(t).sum() >= 2:  # data-driven: two measurements in its gate
                halves = []
                for _ in range(2):
                    node = TrackNode(
                        self.mht.tree.new_node_id(), self.mht.tree.new_family(), t.node_id,
                        t.mean, t.cov, t.stamp, "detected",
                    )  # fmt: skip
                    node.pred_mean, node.pred_cov = t.pred_mean, t.pred_cov
                    self.must_match.add(node.node_id)
                    halves.append(node)
                rest = tuple(x for x in tracks if x is not t)
                split = tuple(sorted((*rest, *halves), key=lambda n: n.family))
                out.append(Branch(math.log(self.p_split), split, 1))
        return out


class SplitLabels(FixedLabels):
    def __init__(self, models: SplitModels) -> None:
        self.models = models

    def track_log_probs(self, nodes: Sequence[TrackNode]) -> np.ndarray:
        lp = super().track_log_probs(nodes)
        for i, n in enumerate(nodes):
            if n.node_id in self.models.must_match:
                lp[i, 1:] = -np.inf  # a split track cannot be occluded or deleted
        return lp


def test_model_branches_for_split_hypotheses() -> None:
    """The hook the group tracker uses: branches with re-predicted tracks and a model prior;
    children of all models of all parents compete in one k-best list."""
    mht: MHT[PointMeasurements] = MHT(MHTParams(), KalmanPointModel(KalmanParams()), FixedLabels())
    models = SplitModels(mht, p_split=0.2)
    mht.branches = models
    mht.labels = SplitLabels(models)
    for k in range(5):
        mht.step(meas(np.array([[2.0, 0.0]])), 0.1 * k)
    assert len(mht.best_tracks()) == 1
    original = mht.best_tracks()[0].family
    # the target splits into two, 0.3 m apart
    for k in range(5, 12):
        mht.step(meas(np.array([[2.0, -0.15], [2.0, 0.15]])), 0.1 * k)
        for c in mht.clusters:
            assert sum(math.exp(h.log_weight) for h in c.hypotheses) == pytest.approx(1.0)
    assert len(mht.clusters) == 1  # the split families stay with the family they replaced
    best = mht.clusters[0].best()
    assert len(best.tracks) == 2
    assert all(t.family != original for t in best.tracks)  # the split, not continuation
    ys = sorted(float(t.mean[1]) for t in best.tracks)
    np.testing.assert_allclose(ys, [-0.15, 0.15], atol=0.03)


def test_enumerated_children_match_k_best_children() -> None:
    """Listing by branch and bound gives the same children (parents, labels, costs) as
    multi-parent Murty on the same assignment problems, with and without measurements and
    gates, from one track and measurement to six tracks, five measurements and four
    parents (where the cuts matter)."""
    from laserpeople.tracking.mht.listing import enumerate_children
    from laserpeople.tracking.mht.matrix import build_matrix, k_best_children

    rng = np.random.default_rng(3)
    for trial in range(300):
        big = trial >= 60
        n_nodes = int(rng.integers(0, 7 if big else 4))
        m = int(rng.integers(0, 6 if big else 3))
        lp = np.log(np.clip(rng.dirichlet(np.ones(3), size=n_nodes), 1e-6, None))
        tm = rng.uniform(-3.0, 6.0, size=(n_nodes, m))
        tm[rng.random((n_nodes, m)) < 0.3] = np.inf
        log_new = np.log(rng.uniform(1e-4, 1e-2, size=m))
        log_fal = np.log(rng.uniform(1e-4, 1e-2, size=m))
        rows = [
            sorted(rng.choice(n_nodes, size=int(rng.integers(0, n_nodes + 1)), replace=False))
            for _ in range(int(rng.integers(1, 5 if big else 4)))
        ]
        priors = list(rng.uniform(0.0, 3.0, size=len(rows)))
        k, gap = int(rng.integers(1, 25)), float(rng.uniform(1.0, 12.0))
        fast = enumerate_children(priors, rows, tm, lp, log_new, log_fal, k, gap, limit=10**9)
        base = build_matrix(tm, lp, log_new, log_fal)
        slow = k_best_children(priors, [base.subset(list(r)) for r in rows], k, gap)
        assert fast is not None, trial
        np.testing.assert_allclose([c for *_, c in fast], [c for *_, c in slow])

        def key(sol: tuple) -> tuple:
            pi, dec, cost = sol
            return (round(cost, 9), pi, tuple(dec.track_label), tuple(dec.track_measurement),
                    tuple(dec.measurement_label))  # fmt: skip

        assert sorted(map(key, fast)) == sorted(map(key, slow)), trial
    assert enumerate_children([0.0], [[0, 1]], np.zeros((2, 3)), np.zeros((2, 3)),
                              np.zeros(3), np.zeros(3), 5, 9.0, limit=10) is None  # fmt: skip
    many = 11  # more measurements than are ever listed: Murty's turn
    assert enumerate_children([0.0], [[]], np.zeros((0, many)), np.zeros((0, 3)),
                              np.zeros(many), np.zeros(many), 5, 9.0) is None  # fmt: skip


def test_listing_with_many_equal_costs_matches_murty_costs() -> None:
    """Seven tracks all gating seven measurements at the same cost: about 10^9 children
    (far above the default listing limit, lifted here), thousands of them tied; the cuts
    drop ties beyond the k-th, and the costs listed are Murty's."""
    from laserpeople.tracking.mht.listing import enumerate_children
    from laserpeople.tracking.mht.matrix import build_matrix, k_best_children

    n = m = 7
    tm = np.ones((n, m))
    lp = np.log(np.tile([0.5, 0.3, 0.2], (n, 1)))
    log_new, log_fal = np.log(np.full(m, 0.01)), np.log(np.full(m, 0.02))
    rows = [list(range(n)), list(range(n))]
    fast = enumerate_children([0.0, 0.5], rows, tm, lp, log_new, log_fal, 20, 10.0, limit=10**12)
    slow = k_best_children([0.0, 0.5], [build_matrix(tm, lp, log_new, log_fal)] * 2, 20, 10.0)
    assert fast is not None and len(fast) == 20
    np.testing.assert_allclose([c for *_, c in fast], [c for *_, c in slow])
    # every child is a valid labelling: detected tracks use distinct measurements
    for _, dec, _ in fast:
        used = [j for j in dec.track_measurement if j >= 0]
        assert len(used) == len(set(used))


def test_ambiguous_cluster_rule_hand_computed() -> None:
    """``MHTParams.is_ambiguous`` and ``k_wide`` (the adaptive k): best parent below 0.5
    and a parent with at least 6 tracks; ``max(k, k_ambiguous)`` children."""
    p = MHTParams(k_best=5, k_ambiguous=8, ambiguous_below=0.5, ambiguous_tracks=6)
    assert p.k_wide == 8
    assert p.is_ambiguous(math.log(0.49), 6)
    assert not p.is_ambiguous(math.log(0.51), 6)  # one hypothesis dominates
    assert not p.is_ambiguous(math.log(0.49), 5)  # too few legs
    assert not MHTParams(ambiguous_below=0.0).is_ambiguous(-50.0, 10)
    assert MHTParams(k_best=5, k_ambiguous=3).k_wide == 5  # never fewer than k
    assert MHTParams(k_best=5).k_wide == 5  # unset: off
    assert MHTParams().with_defaults(k_ambiguous=8).k_ambiguous == 8
    assert MHTParams(k_ambiguous=0).with_defaults(k_ambiguous=8).k_ambiguous == 0
    with pytest.raises(ValueError, match="k_ambiguous"):
        MHTParams(k_ambiguous=-1)
    with pytest.raises(ValueError, match="ambiguous_below"):
        MHTParams(ambiguous_below=1.5)
    with pytest.raises(ValueError, match="ambiguous_n_scan"):
        MHTParams(ambiguous_n_scan=-1)
    q = MHTParams(n_scan=4, ambiguous_n_scan=6)
    assert (q.depth, q.depth_wide, q.depth_kept, q.adaptive) == (4, 6, 6, True)
    assert MHTParams(n_scan=4, ambiguous_n_scan=3).depth_wide == 4  # never shallower
    assert not MHTParams(k_best=5, n_scan=4).adaptive


def test_cluster_k_from_parents() -> None:
    """k 5 / N 4, k_ambiguous 8, ambiguous_n_scan 6. Parents 0.45 / 0.35 / 0.2 with 6 tracks
    each: ambiguous, (8, 6); 0.7 / 0.3: (5, 4); 0.45 / 0.55 with 4 tracks: (5, 4); the
    ancestors kept: 6 whatever the cluster."""
    node = lambda f: TrackNode(f * 10, f, -1, np.zeros(4), np.eye(4), 0.0, "new")  # noqa: E731
    six = tuple(node(f) for f in range(1, 7))
    mht = make_mht(k_best=5, n_scan=4, k_ambiguous=8, ambiguous_n_scan=6)
    hyps = [Hypothesis(math.log(w), six) for w in (0.45, 0.35, 0.2)]
    assert mht._cluster_k(hyps) == (8, 6)
    assert mht._cluster_k([Hypothesis(math.log(w), six) for w in (0.7, 0.3)]) == (5, 4)
    assert mht._cluster_k([Hypothesis(math.log(w), six[:4]) for w in (0.45, 0.55)]) == (5, 4)
    assert mht.params.depth_kept == 6
    parent = Hypothesis(0.0, six, tuple(range(10)), hypothesis_id=99)
    assert mht._history(parent) == (5, 6, 7, 8, 9, 99)
    only_k = make_mht(k_best=5, n_scan=4, k_ambiguous=8)
    assert only_k._cluster_k(hyps) == (8, 4)
    assert make_mht(k_best=5, n_scan=4)._cluster_k(hyps) == (5, 4)  # off


def test_ambiguous_cluster_prunes_deeper() -> None:
    """N-scan with depth 1 keeps one branch of the previous scan; an ambiguous cluster with
    ambiguous_n_scan 3 keeps children of both (hand-made: four children 0.25 of six tracks,
    two from each of the parents 10 and 11, which share their older ancestors): parents
    0.4 / 0.3 / 0.3 are ambiguous (4 kept), 0.6 / 0.4 are not (2 kept)."""
    from laserpeople.tracking.mht.hypothesis import prune_children

    node = lambda f: TrackNode(f * 10, f, -1, np.zeros(4), np.eye(4), 0.0, "new")  # noqa: E731
    six = tuple(node(f) for f in range(1, 7))
    children = [
        Hypothesis(math.log(0.25), six, (1, 2, a)) for a in (10, 10, 11, 11)
    ]  # two children of each of the parents 10 and 11
    assert len(prune_children(list(children), 1, 1e-3)) == 2
    assert len(prune_children(list(children), 3, 1e-3)) == 4
    mht = make_mht(k_best=5, n_scan=1, k_ambiguous=8, ambiguous_n_scan=3)
    for weights, kept in (((0.4, 0.3, 0.3), 4), ((0.6, 0.4), 2)):
        parents = [Hypothesis(math.log(w), six) for w in weights]
        mht._k, mht._depth = mht._cluster_k(parents)
        fresh = [Hypothesis(h.log_weight, h.tracks, h.ancestors) for h in children]
        assert len(mht._prune_children({(i,): h for i, h in enumerate(fresh)})) == kept


def test_ambiguous_clusters_branch_more_children() -> None:
    """Two close targets and clutter: with k 2 no cluster holds more than 2 hypotheses;
    with k_ambiguous 6 for clusters whose best is below 0.9 and that hold 2 tracks, some
    do (and none more than 6); with the rule off (ambiguous_below 0) it is k 2 again."""
    counts = []
    for kw in (
        {"k_best": 2},
        {"k_best": 2, "k_ambiguous": 6, "ambiguous_below": 0.9, "ambiguous_tracks": 2},
        {"k_best": 2, "k_ambiguous": 6, "ambiguous_below": 0.0, "ambiguous_tracks": 2},
    ):
        mht = make_mht(**kw)
        most = [0]
        step = mht.step

        def recording(m: PointMeasurements, t: float, step=step, most=most, mht=mht) -> StepStats:
            stats = step(m, t)
            most[0] = max(most[0], stats.max_cluster_hypotheses)
            return stats

        mht.step = recording  # type: ignore[method-assign]
        run_targets(mht, 40)
        counts.append(most[0])
    assert counts[0] <= 2
    assert 2 < counts[1] <= 6
    assert counts[2] <= 2
