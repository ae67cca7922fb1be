"""The MHT core: normalisation per generation, pruning, clustering, shared track tree."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pytest

from laserpeople.tracking.kalman import KalmanParams
from laserpeople.tracking.mht import listing
from laserpeople.tracking.mht.core import MHT, MHTParams, product, project
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
    assert enumerate_children([0.0], [[0, 1]], np.zeros((2, 3)), np.zeros((2, 3)), np.zeros(3),
                              np.zeros(3), 5, 9.0, limit=10, budget=0) is None  # fmt: skip
    many = 11  # more measurements than are ever listed: Murty's turn
    assert enumerate_children([0.0], [[]], np.zeros((0, many)), np.zeros((0, 3)),
                              np.zeros(many), np.zeros(many), 5, 9.0) is None  # fmt: skip


def test_listing_costs_from_the_scan_tables_are_those_of_the_cluster_arrays(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The listing's costs as the core takes them from the scan's tables (per cluster the
    detection costs, the label costs as plain floats made once per scan) are those of the
    cluster's arrays, entry by entry (the same table entries, negated: compared exactly),
    on clusters of two close targets with misses and clutter; and the tracker keeps the
    same hypotheses when the arrays' costs are listed instead."""
    from laserpeople.tracking.mht.listing import plain_costs

    checked = 0
    original = MHT._plain_costs

    def from_arrays(self: MHT[PointMeasurements], rows: list[int], meas_idx: np.ndarray) -> tuple:
        log_new, log_fal = self._log_rates
        return plain_costs(
            self._cost_live[np.ix_(rows, meas_idx)],
            self._lp_live[rows],
            log_new[meas_idx],
            log_fal[meas_idx],
        )

    def spy(self: MHT[PointMeasurements], rows: list[int], meas_idx: np.ndarray) -> tuple:
        nonlocal checked
        got = original(self, rows, meas_idx)
        assert got == from_arrays(self, rows, meas_idx)
        checked += len(rows) > 1 and len(meas_idx) > 0
        return got

    monkeypatch.setattr(MHT, "_plain_costs", spy)
    monkeypatch.setattr(listing, "COMPILED_K_BEST", None)  # (the Python path's costs)
    tables = make_mht()
    counts = run_targets(tables, 60)
    assert checked >= 20  # clusters of several tracks and measurements were compared
    monkeypatch.setattr(MHT, "_plain_costs", from_arrays)
    arrays = make_mht()
    assert run_targets(arrays, 60) == counts

    def state(m: MHT[PointMeasurements]) -> list[tuple]:
        return [
            (h.log_weight, [(t.family, t.node_id, t.mean.tolist()) for t in h.tracks])
            for c in m.clusters
            for h in c.hypotheses
        ]

    assert state(tables) == state(arrays)


def test_clusters_over_the_limit_are_listed_within_the_budget_as_murty_lists_them() -> None:
    """A crowded cluster (eight to eleven tracks, five to eight measurements, several
    parents: 10^8 children and more, far over the listing limit) is listed within the
    budget of steps, with Murty's children (same parents, labels and costs within
    rounding); out of steps (a budget of 1), or with no budget, it goes to Murty (None)."""
    from laserpeople.tracking.mht.listing import LISTING_LIMIT, children_bound
    from laserpeople.tracking.mht.listing import enumerate_children as listed
    from laserpeople.tracking.mht.matrix import build_matrix, k_best_children

    rng = np.random.default_rng(35)
    over = listed_ok = 0
    for trial in range(40):
        n_nodes, m = int(rng.integers(8, 12)), int(rng.integers(5, 9))
        lp = np.log(np.clip(rng.dirichlet([8.0, 1.0, 1.0], size=n_nodes), 1e-6, None))
        tm = rng.uniform(-4.0, 4.0, size=(n_nodes, m))
        tm[rng.random((n_nodes, m)) < 0.5] = np.inf
        log_new = np.log(rng.uniform(1e-3, 1e-2, size=m))
        log_fal = np.log(rng.uniform(1e-3, 1e-2, size=m))
        rows = [sorted(rng.choice(n_nodes, size=n_nodes - 1, replace=False)) for _ in range(4)]
        priors = sorted(rng.uniform(0.0, 2.0, size=len(rows)).tolist())
        n_labels = [2 + int(np.isfinite(r).sum()) for r in tm]
        if children_bound(rows, n_labels, m) <= LISTING_LIMIT:
            continue
        over += 1
        args = (priors, rows, tm, lp, log_new, log_fal, 5, 4.6)
        assert listed(*args, budget=0) is None and listed(*args, budget=1) is None
        fast = listed(*args)
        if fast is None:  # (out of steps: Murty's turn)
            continue
        listed_ok += 1
        base = build_matrix(tm, lp, log_new, log_fal)
        slow = k_best_children(priors, [base.subset(list(r)) for r in rows], 5, 4.6)
        np.testing.assert_allclose([c for *_, c in fast], [c for *_, c in slow], atol=1e-12)
        assert [(pi, dec.track_label, dec.track_measurement, dec.measurement_label)
                for pi, dec, _ in fast] == [
            (pi, dec.track_label, dec.track_measurement, dec.measurement_label)
            for pi, dec, _ in slow
        ], trial  # fmt: skip
    assert over >= 30 and listed_ok >= over // 2, (over, listed_ok)


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


def test_the_listing_budget_counts_every_track_and_measurement_labelled() -> None:
    """Steps counted by hand (``limit=0``: every cluster is over the limit; no shortcut).

    - One measurement, no track (new -ln 0.01 = 4.605, false alarm -ln 0.02 = 3.912):
      the first measurement step, then one per label: 3 steps. A budget of 3 lists both
      children, 2 gives up (None: Murty's turn).
    - Two tracks without measurements (occluded -ln 0.3, obsolete -ln 0.2 each): track 0
      once, track 1 once per label of track 0: 3 steps, four children 2.408, 2.813,
      2.813, 3.219. A budget of 3 lists them, 2 gives up.
    - Under the listing limit no budget applies: a budget of 1 lists all four."""
    from laserpeople.tracking.mht.listing import enumerate_children as listed

    ln, lf = np.log([0.01]), np.log([0.02])
    one = ([0.0], [[]], np.zeros((0, 1)), np.zeros((0, 3)), ln, lf, 5, 9.0)
    assert listed(*one, limit=0, shortcut=False, budget=2) is None
    got = listed(*one, limit=0, shortcut=False, budget=3)
    assert got is not None
    np.testing.assert_allclose([c for *_, c in got], [-math.log(0.02), -math.log(0.01)])
    lp = np.log(np.tile([0.5, 0.3, 0.2], (2, 1)))
    two = ([0.0], [[0, 1]], np.zeros((2, 0)), lp, np.zeros(0), np.zeros(0), 5, 9.0)
    assert listed(*two, limit=0, shortcut=False, budget=2) is None
    a, b = -math.log(0.3), -math.log(0.2)
    for kw in ({"limit": 0, "budget": 3}, {"budget": 1}):
        got = listed(*two, shortcut=False, **kw)
        assert got is not None, kw
        np.testing.assert_allclose([c for *_, c in got], [2 * a, a + b, a + b, 2 * b])


class PlaceLabels(FixedLabels):
    """FixedLabels whose new-track and false-alarm rates grow with a measurement's x
    (every measurement its own rates); keeps the positions it was last asked about."""

    def __init__(self) -> None:
        self.x = np.empty(0)

    def measurement_log_rates(self, m: PointMeasurements) -> tuple[np.ndarray, np.ndarray]:
        self.x = np.asarray(m.positions, float)[:, 0]
        return math.log(0.001) + 0.2 * self.x, math.log(0.003) + 0.1 * self.x


def test_listing_costs_are_each_clusters_own_measurements_rates(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """With a rate per measurement (PlaceLabels), the listing's new-track and false-alarm
    costs taken from the scan's tables are those of the cluster's own measurements: for
    every cluster, -(log rate) of each of its measurements, from the labels by hand."""
    labels = PlaceLabels()
    later = 0
    original = MHT._plain_costs

    def spy(self: MHT[PointMeasurements], rows: list[int], meas_idx: np.ndarray) -> tuple:
        nonlocal later
        got = original(self, rows, meas_idx)
        x = labels.x[meas_idx]
        assert got[3] == pytest.approx((-(math.log(0.001) + 0.2 * x)).tolist(), abs=1e-12)
        assert got[4] == pytest.approx((-(math.log(0.003) + 0.1 * x)).tolist(), abs=1e-12)
        later += int(meas_idx.size > 0 and meas_idx[0] > 0)
        return got

    monkeypatch.setattr(MHT, "_plain_costs", spy)
    monkeypatch.setattr(listing, "COMPILED_K_BEST", None)  # (the Python path's costs)
    mht = MHT(MHTParams(), KalmanPointModel(KalmanParams()), labels)  # type: ignore[arg-type]
    run_targets(mht, 60)
    assert later >= 4  # clusters whose measurements do not start the scan's list


def test_settled_links_go_and_the_others_stay() -> None:
    """``MHT._drop_settled_links`` by hand: a link goes when either family's cluster has a
    single hypothesis, when one of its families has no cluster any more, or when both
    clusters are N-scan pruned (every hypothesis N ancestors deep) and the link is at
    least N + 1 generations old; every other link stays, in its order."""
    from laserpeople.tracking.legs import LegMHTTracker
    from laserpeople.tracking.mht.hypothesis import Cluster

    mht = LegMHTTracker().mht
    n = mht.params.depth
    deep, shallow = tuple(range(n)), tuple(range(n - 1))

    def cluster(families: set[int], hyps: int, ancestors: tuple[int, ...]) -> Cluster:
        return Cluster(frozenset(families), [Hypothesis(-1.0, (), ancestors) for _ in range(hyps)])

    single = cluster({1}, 1, deep)  # one hypothesis: nothing uncertain
    pruned_a, pruned_b = cluster({2, 5}, 2, deep), cluster({3}, 3, deep)
    young = cluster({4}, 2, shallow)  # formed lately: not N-scan pruned yet
    mht.clusters = [single, pruned_a, pruned_b, young]
    mht.generation = 20
    settled_before = mht.generation - 1 - n  # links made then or earlier are settled
    mht.links = {
        (1, 2): mht.generation - 1,  # goes: family 1's cluster is single
        (2, 3): settled_before,  # goes: both pruned, old enough
        (3, 5): settled_before + 1,  # stays: too recent
        (2, 4): settled_before - 3,  # stays: family 4's cluster is not pruned
        (3, 9): settled_before + 1,  # goes: family 9 has no cluster
        (5, 3): settled_before - 1,  # goes: both pruned, old enough
        (4, 5): mht.generation - 1,  # stays
    }
    cluster_of = {f: c for c in mht.clusters for f in c.families}
    mht._drop_settled_links(cluster_of)
    assert list(mht.links.items()) == [
        ((3, 5), settled_before + 1),
        ((2, 4), settled_before - 3),
        ((4, 5), mht.generation - 1),
    ]
    mht._drop_settled_links(cluster_of)  # (what stays is not settled: the same again)
    assert list(mht.links) == [(3, 5), (2, 4), (4, 5)]
    mht.links = {}
    mht._drop_settled_links(cluster_of)
    assert mht.links == {}
