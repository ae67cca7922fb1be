"""Long runs and crowded scans stay bounded (issue 16): tracks unseen for longer than their
label probabilities allow are deleted (mht/expiry.py), and the work per scan is capped
(``max_cluster_size``, ``max_assignment_solves``) with the degraded scans counted."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams
from laserpeople.tracking.mht.core import MHTParams
from laserpeople.tracking.mht.expiry import (
    drop_nodes,
    expired,
    log_existence_odds,
    max_misses,
)
from laserpeople.tracking.mht.hypothesis import Cluster, Hypothesis
from laserpeople.tracking.mht.probability import LabelProbabilities
from laserpeople.tracking.mht.tracktree import TrackNode
from laserpeople.tracks import Detections

APPROVED = LabelProbabilities(0.2, 0.79, 0.01)  # 000 Table 10
FREE = LabelProbabilities(0.3, 0.63, 0.07)
HALF_STANCE = np.array([0.0, 0.12])  # legs 0.24 m apart


def _dets(stamp: float, k: int, xy: np.ndarray) -> Detections:
    xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
    m = xy.shape[0]
    return Detections(stamp, k, xy, np.tile(np.eye(2) * 0.01, (m, 1, 1)), np.full(m, 0.9))


# ------------------------------------------------------------------ the deletion odds


def _odds_by_sum(p: LabelProbabilities, m: int) -> float:
    """Independent computation: still there (occluded m times) against deleted at scan k
    for every k = 1..m (occluded k-1 times, then deleted)."""
    alive = p.p_occ**m
    deleted = sum(p.p_occ ** (k - 1) * p.p_del for k in range(1, m + 1))
    return alive / deleted


@pytest.mark.parametrize("p", [APPROVED, FREE])
@pytest.mark.parametrize("m", [1, 2, 5, 13, 43, 200])
def test_existence_odds_match_the_sum_over_deletion_scans(p: LabelProbabilities, m: int) -> None:
    got = log_existence_odds(np.array([m]), p.log()[None, :])[0]
    assert got == pytest.approx(math.log(_odds_by_sum(p, m)), rel=1e-9, abs=1e-9)


def test_existence_odds_by_hand() -> None:
    # approved, one miss: 0.79 / 0.01 = 79; 13 misses: 0.79^13 * 0.21 / (0.01 (1 - 0.79^13))
    lp = np.tile(APPROVED.log(), (2, 1))
    odds = np.exp(log_existence_odds(np.array([1, 13]), lp))
    assert odds[0] == pytest.approx(79.0)
    assert odds[1] == pytest.approx(0.0466823 * 0.21 / (0.01 * (1 - 0.0466823)), rel=1e-5)
    assert odds[1] == pytest.approx(1.0283, abs=1e-3)  # deletion becomes the likelier at 14
    assert np.isinf(log_existence_odds(np.array([0]), lp[:1])[0])  # just detected


def test_max_misses_of_000_table_10() -> None:
    assert max_misses(APPROVED.p_occ, APPROVED.p_del, 1e-3) == 43
    assert max_misses(FREE.p_occ, FREE.p_del, 1e-3) == 19
    assert max_misses(APPROVED.p_occ, APPROVED.p_del, 0.0) == math.inf
    # the first m whose odds fall below the ratio
    for p in (APPROVED, FREE):
        m = int(max_misses(p.p_occ, p.p_del, 1e-3))
        assert _odds_by_sum(p, m) < 1e-3 <= _odds_by_sum(p, m - 1)


def _node(node_id: int, family: int, misses: int = 0) -> TrackNode:
    return TrackNode(node_id, family, -1, np.zeros(4), np.eye(4), 0.0, "occluded", misses=misses)


def test_expired_and_drop_nodes_merge_equal_hypotheses() -> None:
    a, b, b_old = _node(1, 0), _node(2, 1, misses=50), _node(3, 1, misses=2)
    lp = np.tile(APPROVED.log(), (2, 1))
    assert expired([b, b_old], lp, math.log(1e-3)) == {2}
    # {a, b}: 0.5, {a}: 0.3, {a, b_old}: 0.2 -> without b: {a}: 0.8, {a, b_old}: 0.2
    hyps = [
        Hypothesis(math.log(0.5), (a, b), ("p",)),
        Hypothesis(math.log(0.3), (a,), ("q",)),
        Hypothesis(math.log(0.2), (a, b_old), ("r",)),
    ]
    out = drop_nodes(Cluster(frozenset({0, 1}), hyps), {2})
    assert out is not None
    assert [h.key() for h in out.hypotheses] == [(1,), (1, 3)]
    assert np.exp([h.log_weight for h in out.hypotheses]) == pytest.approx([0.8, 0.2])
    assert out.hypotheses[0].ancestors == ("p",)  # the more probable one's history
    assert drop_nodes(Cluster(frozenset({1}), [Hypothesis(0.0, (b,))]), {2}) is None


# ------------------------------------------------------------------ trackers


def _walk_then_vanish(params: LegTrackerParams, unseen_scans: int) -> LegMHTTracker:
    """Two legs walk 3 s along +x at 10 Hz, then nothing is detected."""
    tracker = LegMHTTracker(params)
    for k in range(30):
        x = 1.0 + 0.1 * k
        tracker.update(_dets(0.1 * k, k, [[x, 0.1], [x, -0.1]]))
    for k in range(30, 30 + unseen_scans):
        tracker.update(_dets(0.1 * k, k, np.empty((0, 2))))
    return tracker


@pytest.mark.parametrize("policy", ["arras", "tracks"])
def test_legs_of_a_person_who_left_are_deleted(policy: str) -> None:
    params = LegTrackerParams(people_policy=policy)
    tracker = _walk_then_vanish(params, 60)
    assert tracker.state_counts()["families"] == 0
    assert tracker.state_counts()["hypotheses"] == 0


def test_approved_leg_lives_exactly_its_allowed_misses() -> None:
    params = LegTrackerParams(adaptive=False, nonadaptive_class="approved", people_policy="arras")
    limit = int(max_misses(APPROVED.p_occ, APPROVED.p_del, params.mht.existence_ratio))
    assert _walk_then_vanish(params, limit - 1).state_counts()["families"] == 2
    assert _walk_then_vanish(params, limit).state_counts()["families"] == 0


def test_without_expiry_n_scan_pruning_keeps_approved_legs_for_ever() -> None:
    """The defect of issue 16: N-scan-back pruning cuts off the deletion branches."""
    mht = dataclasses.replace(MHTParams(), existence_ratio=0.0)
    params = LegTrackerParams(people_policy="arras", mht=mht)
    tracker = _walk_then_vanish(params, 600)
    assert tracker.state_counts()["families"] == 2


@pytest.mark.slow
@pytest.mark.parametrize("policy", ["arras", "tracks"])
def test_state_bounded_by_what_is_in_view_over_many_crowds(policy: str) -> None:
    """Crowds of 4 people walk through the view and leave, one after the other, for 12
    crowds: nothing is left after the last one and the state never grows with the number
    of crowds seen."""
    tracker = LegMHTTracker(LegTrackerParams(people_policy=policy))
    rng = np.random.default_rng(3)
    k = 0
    after: list[dict[str, int]] = []
    for _crowd in range(12):
        start = rng.uniform([1.0, -3.0], [2.0, 3.0], size=(4, 2))
        for step in range(40):  # 4 s walking in view
            x = start + np.array([0.08 * step, 0.0])
            legs = np.concatenate([x + HALF_STANCE, x - HALF_STANCE])
            tracker.update(_dets(0.1 * k, k, legs))
            k += 1
        for _ in range(60):  # 6 s with nobody in view
            tracker.update(_dets(0.1 * k, k, np.empty((0, 2))))
            k += 1
        after.append(tracker.state_counts())
    assert after[-1]["families"] == 0 and after[-1]["hypotheses"] == 0
    assert max(a["persons"] for a in after) <= 8
    assert len(tracker.leg_ids_reported) >= 12 * 8 // 2  # counted, not stored
    assert len(tracker.leg_ids_reported._live) <= 8


# ------------------------------------------------------------------ bounded work per scan


crowd = st.tuples(
    st.integers(100, 500),  # detections per scan
    st.floats(1.0, 20.0),  # side of the square they fall in [m]
    st.integers(0, 2**32 - 1),
)


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scans=st.lists(crowd, min_size=2, max_size=3))
def test_hundreds_of_detections_per_scan_bounded_work(
    scans: list[tuple[int, float, int]],
) -> None:
    params = LegTrackerParams(mht=MHTParams(max_cluster_size=120, max_assignment_solves=300))
    tracker = LegMHTTracker(params)
    k_best = params.mht_params().k
    degraded = 0
    for k, (n, side, seed) in enumerate(scans):
        xy = np.random.default_rng(seed).uniform(0.0, side, size=(n, 2))
        tracker.update(_dets(0.1 * k, k, xy))
        s = tracker.last_stats
        assert s is not None
        assert s.max_cluster_hypotheses <= k_best
        assert s.n_hypotheses <= k_best * s.n_clusters
        # every cluster: at most the budget, plus the solve that finds its first child
        assert s.max_cluster_solves <= params.mht.max_assignment_solves + 1
        assert s.largest_cluster <= n + s.n_families + k_best * n  # tracks + measurements
        assert s.n_families <= n + sum(m for m, _, _ in scans[:k])
        degraded += s.degraded_clusters > 0
    assert tracker.guard.degraded_scans == degraded
    if degraded:
        assert "degraded" in tracker.guard.summary()


def test_a_dense_scan_of_500_is_degraded_and_said() -> None:
    tracker = LegMHTTracker(LegTrackerParams())
    rng = np.random.default_rng(0)
    largest = []
    for k in range(3):
        tracker.update(_dets(0.1 * k, k, rng.uniform(0.0, 10.0, size=(500, 2))))
        s = tracker.last_stats
        assert s is not None and s.max_cluster_solves <= 1  # degraded: one matching
        largest.append(s.largest_cluster)
    assert max(largest) > tracker.params.mht.max_cluster_size
    assert tracker.guard.degraded_scans == sum(x > 200 for x in largest) >= 1
    assert "scans degraded" in tracker.guard.summary()


def test_expiry_odds_table_expires_the_same_nodes() -> None:
    """``ExpiryOdds`` (odds remembered per label probabilities and misses) expires the
    same nodes as :func:`expired` over random node sets of two classes, scan after scan,
    also when its table is emptied for being full."""
    from laserpeople.tracking.mht.expiry import ExpiryOdds

    free = LabelProbabilities(0.3, 0.63, 0.07).log()
    approved = LabelProbabilities(0.2, 0.79, 0.01).log()
    rng = np.random.default_rng(5)
    for limit in (4096, 8):
        table = ExpiryOdds(limit)
        for _ in range(200):
            n = int(rng.integers(1, 12))
            nodes = [
                TrackNode(
                    node_id=i, family=i, parent_id=-1, mean=np.zeros(4), cov=np.eye(4),
                    stamp=0.0, label="occluded", misses=int(rng.integers(0, 60)),
                )
                for i in range(n)
            ]  # fmt: skip
            lp = np.array([free if rng.random() < 0.5 else approved for _ in range(n)])
            for ratio in (1e-3, 1e-2):
                want = expired(nodes, lp, math.log(ratio))
                assert table.expired(nodes, lp, math.log(ratio)) == want
            assert len(table) <= max(limit, 11)  # (one call may bring up to 11)
