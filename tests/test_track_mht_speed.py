"""The speed shortcuts of the MHT core give exactly what the general code gives."""

from __future__ import annotations

import numpy as np
import pytest

# two code paths giving the same bits may hold on one CPU only: CI runs these again on
# another CPU path (.ci/run)
pytestmark = pytest.mark.regression


def _random_single_cluster(rng: np.random.Generator, ties: bool) -> tuple:
    """A cluster of at most one track per parent and at most one measurement."""
    n_nodes = int(rng.integers(0, 4))
    m = int(rng.integers(0, 2))
    if ties:  # few distinct values: many equal costs, to check the order of ties
        lp = -rng.choice([0.5, 1.0, 2.0, np.inf], size=(n_nodes, 3), p=[0.3, 0.3, 0.3, 0.1])
        tm = rng.choice([0.5, 1.0, 1.5, np.inf], size=(n_nodes, m))
        log_new = -rng.choice([0.5, 1.0, np.inf], size=m)
        log_fal = -rng.choice([0.5, 1.0, np.inf], size=m)
    else:
        lp = np.log(np.clip(rng.dirichlet(np.ones(3), size=n_nodes), 1e-6, None))
        tm = rng.uniform(-3.0, 6.0, size=(n_nodes, m))
        tm[rng.random((n_nodes, m)) < 0.3] = np.inf
        log_new = np.log(rng.uniform(1e-4, 1e-2, size=m))
        log_fal = np.log(rng.uniform(1e-4, 1e-2, size=m))
    n_parents = int(rng.integers(1, 6))
    rows = [
        [int(rng.integers(0, n_nodes))] if n_nodes and rng.random() < 0.8 else []
        for _ in range(n_parents)
    ]
    if ties:
        priors = list(rng.choice([0.0, 0.5, 1.0, np.inf], size=n_parents))
    else:
        priors = list(rng.uniform(0.0, 3.0, size=n_parents))
    k, gap = int(rng.integers(1, 12)), float(rng.uniform(0.5, 12.0))
    return priors, rows, tm, lp, log_new, log_fal, k, gap


def test_single_track_shortcut_lists_the_same_children_as_the_full_listing() -> None:
    """Clusters of at most one track per parent and one measurement (random costs, and
    costs with many ties, infinite labels and parents): the closed-form listing gives the
    same children as the branch and bound, in the same order, with the same floats."""
    from laserpeople.tracking.mht.listing import enumerate_children

    rng = np.random.default_rng(10)
    listed = 0
    for trial in range(3000):
        args = _random_single_cluster(rng, ties=trial % 2 == 1)
        full = enumerate_children(*args, shortcut=False)
        short = enumerate_children(*args, shortcut=True)
        assert full is not None and short is not None
        assert len(full) == len(short), trial
        for (pa, da, ca), (pb, db, cb) in zip(full, short, strict=True):
            assert (pa, ca) == (pb, cb), trial
            assert da.track_label == db.track_label, trial
            assert da.track_measurement == db.track_measurement, trial
            assert da.measurement_label == db.measurement_label, trial
            assert da.cost == db.cost, trial
        listed += len(full)
    assert listed > 3000  # the clusters had children to compare


def _state(tracker: object) -> list:
    """Every cluster's hypotheses: weights, ancestry length and the tracks' full content."""
    mht = tracker.mht  # type: ignore[attr-defined]
    return [
        [
            (
                h.log_weight,
                len(h.ancestors),
                [
                    (t.node_id, t.family, t.label, t.measurement, t.hits, t.misses, t.loglik,
                     t.mean.tobytes(), t.cov.tobytes())
                    for t in h.tracks
                ],
            )
            for h in c.hypotheses
        ]
        for c in mht.clusters
    ]  # fmt: skip


@pytest.mark.parametrize("policy", ["tracks", "arras"])
def test_lone_cluster_shortcut_gives_the_same_hypotheses_every_scan(
    policy: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Six walkers with clutter and misses: the leg MHT with the shortcuts (lone clusters,
    the obvious detected child, closed-form listing) holds exactly the hypotheses (weights,
    node ids, states) of the one without, after every scan, and reports the same tracks;
    under both people policies (ratio pruning 1e-2 and 1e-3)."""
    from laserpeople.tracking import synthetic as syn
    from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams
    from laserpeople.tracking.mht.core import MHT

    obvious = {"taken": 0, "declined": 0}
    original = MHT._branch_obvious

    def counted(self, *args, **kwargs):  # type: ignore[no-untyped-def]
        out = original(self, *args, **kwargs)
        obvious["taken" if out is not None else "declined"] += 1
        return out

    monkeypatch.setattr(MHT, "_branch_obvious", counted)

    scene = syn.walkers_scene(5, 1.0)
    params = LegTrackerParams(people_policy=policy)
    fast, slow = LegMHTTracker(params), LegMHTTracker(params)
    slow.mht.shortcuts = False
    lone = 0
    for d in scene.detections:
        out_fast, out_slow = fast.update(d), slow.update(d)
        assert _state(fast) == _state(slow), d.scan_index
        assert [(t.track_id, t.kind, t.position.tobytes(), t.score) for t in out_fast] == [
            (t.track_id, t.kind, t.position.tobytes(), t.score) for t in out_slow
        ]
        lone += sum(len(c.families) == 1 for c in fast.mht.clusters)
    assert lone > 100  # the shortcut was taken
    assert obvious["taken"] > 1000 and obvious["declined"] > 0  # both ways, and compared


@pytest.mark.parametrize("policy", ["tracks", "arras"])
def test_deferred_child_states_give_the_same_hypotheses_every_scan(policy: str) -> None:
    """Six walkers with clutter and misses: the plain MHT that makes its children's states
    at the end of the step, for the kept children only, holds exactly the hypotheses
    (weights, node and family ids, states bit for bit) of the one that updates every gated
    pair before branching, after every scan, and reports the same tracks; the states of
    pruned children are never made."""
    from laserpeople.tracking import synthetic as syn
    from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams

    scene = syn.walkers_scene(11, 1.5)
    params = LegTrackerParams(people_policy=policy)
    deferred, eager = LegMHTTracker(params), LegMHTTracker(params)
    eager.mht.deferred_states = False
    skipped = 0
    for d in scene.detections:
        out_d, out_e = deferred.update(d), eager.update(d)
        assert _state(deferred) == _state(eager), d.scan_index
        assert [(t.track_id, t.kind, t.position.tobytes(), t.score) for t in out_d] == [
            (t.track_id, t.kind, t.position.tobytes(), t.score) for t in out_e
        ]
        skipped += len(eager.mht._updates) - len(deferred.mht._deferred)
    assert deferred.mht._defer and not eager.mht._defer
    assert skipped > 100  # pairs whose update the deferred MHT never computed


def test_kalman_update_batch_gives_each_state_the_same_floats_in_any_batch() -> None:
    """What makes the deferred child states exact: a state's Kalman update is the same bit
    for bit whatever else its batch holds (any subset, any order, the plain-float path of
    a few states and the array path)."""
    from laserpeople.tracking import kalman

    rng = np.random.default_rng(4)
    for _ in range(400):
        n = int(rng.integers(1, 90))
        a = rng.normal(size=(n, 4, 4)) * rng.uniform(0.01, 3.0)
        covs = a @ a.transpose(0, 2, 1) + np.eye(4) * rng.uniform(1e-4, 1.0)
        means = rng.normal(size=(n, 4)) * 5.0
        z = rng.normal(size=(n, 2)) * 5.0
        b = rng.normal(size=(n, 2, 2)) * 0.1
        r = b @ b.transpose(0, 2, 1) + np.eye(2) * 1e-3
        all_means, all_covs = kalman.update_batch(means, covs, z, r)
        sub = rng.permutation(rng.choice(n, size=int(rng.integers(1, n + 1)), replace=False))
        sub_means, sub_covs = kalman.update_batch(means[sub], covs[sub], z[sub], r[sub])
        assert all_means[sub].tobytes() == sub_means.tobytes()
        assert all_covs[sub].tobytes() == sub_covs.tobytes()


def test_track_node_fields_in_the_order_the_core_passes_them() -> None:
    """The MHT core makes track nodes with positional fields (a third of the cost of
    keywords): their order is pinned here."""
    from dataclasses import fields

    from laserpeople.tracking.mht.tracktree import TrackNode

    assert [f.name for f in fields(TrackNode)] == [
        "node_id", "family", "parent_id", "mean", "cov", "stamp", "label", "measurement",
        "hits", "misses", "age", "loglik", "payload", "pred_mean", "pred_cov", "children",
        "detected_stamp",
    ]  # fmt: skip


def test_predictions_kept_in_the_batch_give_the_same_hypotheses_every_scan() -> None:
    """Six walkers with clutter and misses: the leg MHT whose point model keeps its
    predictions in the batch (the leg tracker's, ``node_predictions`` false) holds exactly
    the hypotheses (weights, node and family ids, states bit for bit) of one whose model
    sets every node's ``pred_mean`` and ``pred_cov``, after every scan, and reports the same
    tracks; its nodes' own predictions stay unset, the other's are the batch's rows."""
    from laserpeople.tracking import synthetic as syn
    from laserpeople.tracking.legs import LegMHTTracker

    scene = syn.walkers_scene(11, 1.5)
    batch, views = LegMHTTracker(), LegMHTTracker()
    assert not batch.mht.model.node_predictions  # type: ignore[attr-defined]
    views.mht.model.node_predictions = True  # type: ignore[attr-defined]
    for d in scene.detections:
        out_b, out_v = batch.update(d), views.update(d)
        assert _state(batch) == _state(views), d.scan_index
        assert [(t.track_id, t.kind, t.position.tobytes(), t.score) for t in out_b] == [
            (t.track_id, t.kind, t.position.tobytes(), t.score) for t in out_v
        ]
    # the last step's predicted nodes; those the step dropped keep what predict set on them
    done_b = batch.mht.model._predicted[0]  # type: ignore[attr-defined]
    done_v = views.mht.model._predicted[0]  # type: ignore[attr-defined]
    assert len(done_b) == len(done_v) > 10
    assert all(n.pred_mean is None and n.pred_cov is None for n in done_b)
    kept = [(b, v) for b, v in zip(done_b, done_v, strict=True) if v.pred_mean is not None]
    assert kept
    for b, v in kept:
        mean, cov = batch.mht.model._pred(b)  # type: ignore[attr-defined]
        assert mean.tobytes() == v.pred_mean.tobytes() and cov.tobytes() == v.pred_cov.tobytes()


def test_one_step_prediction_and_coasting_in_one_stacked_product_are_the_two_products() -> None:
    """The predicted and coasted covariances formed as one stacked product
    ``[F, F_c] P [F, F_c]^T + Q`` are the two products ``F P F^T + Q`` and
    ``F_c P F_c^T + Q`` with the transition and coasting matrices built here from their
    definitions, within 1e-12 relative (the same products on one machine; a CPU whose BLAS
    takes another kernel for the stacked shape may differ in the last bit; a swapped pair
    or transpose, or a dropped Q, differs by far more)."""
    from laserpeople.tracking import kalman

    rng = np.random.default_rng(8)
    for _ in range(300):
        t = int(rng.integers(1, 60))
        means = rng.normal(scale=[5.0, 5.0, 1.0, 1.0], size=(t, 4))
        a = rng.normal(size=(t, 4, 4)) * rng.uniform(0.01, 3.0)
        covs = a @ a.transpose(0, 2, 1) + np.eye(4) * rng.uniform(1e-4, 1.0)
        d = float(rng.choice([1.0 / 40.0, 0.1, 0.7]) + abs(rng.normal(scale=1e-3)))
        psd, tau = float(rng.uniform(0.1, 40.0)), float(rng.uniform(0.2, 5.0))
        f = np.array([[1.0, 0, d, 0], [0, 1.0, 0, d], [0, 0, 1.0, 0], [0, 0, 0, 1.0]])
        pp, pv, vv = psd * d**3 / 3.0, psd * (d * d) / 2.0, psd * d
        q = np.array([[pp, 0, pv, 0], [0, pp, 0, pv], [pv, 0, vv, 0], [0, pv, 0, vv]])
        k = float(np.exp(np.array([-d / tau]))[0])
        g = tau * (1.0 - k)
        fc = np.array([[1.0, 0, g, 0], [0, 1.0, 0, g], [0, 0, k, 0], [0, 0, 0, k]])
        kalman._STEP_MATRICES.clear()
        _, pc, cm, cc = kalman._one_step_predict_and_coast(means, covs, d, psd, tau)
        tol = {"rtol": 1e-12, "atol": 1e-15}
        np.testing.assert_allclose(pc, f @ covs @ f.T + q, **tol)
        np.testing.assert_allclose(cc, fc @ covs @ fc.T + q, **tol)
        np.testing.assert_allclose(cm, np.einsum("ij,tj->ti", fc, means), **tol)
        assert pc.shape == cc.shape == (t, 4, 4)
    kalman._STEP_MATRICES.clear()
