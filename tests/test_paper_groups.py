"""The group tracker's equations (000 Sec. 4) through the code the tracker runs.

Every reference here is computed in the test from the paper's formula (not by a function
of ``src``), on values that tell the formula from its near misses: non-diagonal
covariances, contours of unequal sizes, clusters just inside and outside the gate. The
tracker's own objects are used: :class:`GroupMHTTracker`'s model (prediction, gate and
likelihood, update, initiation), its branch generator (split and merge events, their
priors, the merged and split tracks, re-clustering) and its label model.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.stats import chi2

from laserpeople.tracking.groups import GroupMHTTracker, GroupObservations, GroupTrackerParams
from laserpeople.tracking.groups.interaction import Event, enumerate_models
from laserpeople.tracking.groups.model import GroupPayload
from laserpeople.tracking.mht.tracktree import TrackNode

RTOL = 1e-9
"""Relative tolerance of the comparisons with the hand computations (float64 sums in
another order)."""


def _spd(rng: np.random.Generator, scale: float) -> np.ndarray:
    """A random symmetric positive definite (5, 5) matrix with non-zero off-diagonals."""
    a = rng.normal(0.0, 1.0, (5, 5))
    return scale * (a @ a.T / 5.0 + 0.2 * np.eye(5))


def _node(
    tracker: GroupMHTTracker, mean: list[float], cov: np.ndarray, contour: np.ndarray
) -> TrackNode:
    tree = tracker.mht.tree
    return TrackNode(
        tree.new_node_id(),
        tree.new_family(),
        -1,
        np.array(mean, dtype=float),
        cov,
        0.0,
        "new",
        payload=GroupPayload(np.asarray(contour, dtype=float)),
    )


def _obs(points: np.ndarray, p: GroupTrackerParams) -> GroupObservations:
    pts = np.asarray(points, dtype=float)
    return GroupObservations.from_points(
        pts, np.arange(len(pts)), p.cluster_distance, p.blob_distance, p.counting()
    )


# ---------------------------------------------------------------- references (the paper)


def ref_predict(mean: np.ndarray, cov: np.ndarray, dt: float, p: GroupTrackerParams):
    """Sec. 4.2.3: x' = A x, C' = A C A^T + Q dt / period, Q = diag(eps^2)."""
    a = np.eye(5)
    a[0, 2] = a[1, 3] = dt
    q = np.diag([p.eps_pos**2, p.eps_pos**2, p.eps_vel**2, p.eps_vel**2, p.eps_n**2])
    return a @ mean, a @ cov @ a.T + q * dt / p.period


def ref_hausdorff(z: np.ndarray, contour: np.ndarray, s: np.ndarray) -> float:
    """Eqs. 19-22 point by point: D(v, S) = sqrt(v^T S^-1 v), the two directed averages
    of the nearest distances, their minimum."""
    s_inv = np.linalg.inv(s)
    d = np.empty((len(z), len(contour)))
    for i, zi in enumerate(z):
        for j, pj in enumerate(contour):
            v = zi - pj
            d[i, j] = math.sqrt(float(v @ s_inv @ v))
    z_to_p = float(np.mean(d.min(axis=1)))
    p_to_z = float(np.mean(d.min(axis=0)))
    return min(z_to_p, p_to_z)


def ref_log_n(d_hd: float, s: np.ndarray) -> float:
    """Eq. 24: log of exp(-d_HD^2 / 2) / (2 pi sqrt(det S))."""
    return -0.5 * d_hd**2 - math.log(2.0 * math.pi * math.sqrt(float(np.linalg.det(s))))


def ref_merge_log_n(
    ci: np.ndarray,
    mi: np.ndarray,
    pi: np.ndarray,
    cj: np.ndarray,
    mj: np.ndarray,
    pj: np.ndarray,
    d_p: float,
) -> float:
    """Eqs. 25-27: the least Mahalanobis distance over contour-point pairs of
    (dx shortened by d_P, dv) with C_i + C_j (4x4), and the normal density of it."""
    s = ci[:4, :4] + cj[:4, :4]
    s_inv = np.linalg.inv(s)
    best = math.inf
    for a in pi + mi[:2]:
        for b in pj + mj[:2]:
            dx = a - b
            norm = float(np.hypot(*dx))
            dx = np.zeros(2) if norm <= d_p else dx * (1.0 - d_p / norm)
            v = np.array([dx[0], dx[1], mi[2] - mj[2], mi[3] - mj[3]])
            best = min(best, float(v @ s_inv @ v))
    return -0.5 * best - math.log((2.0 * math.pi) ** 2 * math.sqrt(float(np.linalg.det(s))))


# ---------------------------------------------------------------- prediction, initiation


def test_prediction_is_constant_velocity_with_q_per_period() -> None:
    p = GroupTrackerParams()
    tracker = GroupMHTTracker(p)
    rng = np.random.default_rng(3)
    cov = _spd(rng, 0.05)
    node = _node(tracker, [1.0, 2.0, 0.8, -0.4, 2.0], cov, np.zeros((1, 2)))
    node.stamp = 0.1
    tracker.model.predict([node], 0.35)  # dt = 0.25 s, a quarter of the period
    mean, c = ref_predict(node.mean, cov, 0.25, p)
    np.testing.assert_allclose(node.pred_mean, mean, rtol=RTOL)
    np.testing.assert_allclose(node.pred_cov, c, rtol=RTOL, atol=1e-12)


def test_eq16_new_groups_take_the_cluster_size() -> None:
    p = GroupTrackerParams()
    tracker = GroupMHTTracker(p)
    # two people (four legs 0.2 m apart, pairs 0.5 m apart) and one person, far apart
    legs = [[0.0, 0.0], [0.0, 0.2], [0.5, 0.0], [0.5, 0.2], [5.0, 0.0], [5.0, 0.2]]
    pts = np.concatenate(
        [np.array(c) + np.array([[0.0, 0.0], [0.03, 0.0], [0.0, 0.03]]) for c in legs]
    )
    obs = _obs(pts, p)
    assert sorted(obs.n_hs.tolist()) == [1.0, 2.0]
    for js in ([0, 1], [0], [1]):  # several at once and one at a time
        made = tracker.model.initiate(obs, js, 0.0)
        for j, (mean, cov, payload) in zip(js, made, strict=True):
            centroid = obs.cluster(j).mean(axis=0)
            np.testing.assert_allclose(mean, [*centroid, 0.0, 0.0, obs.n_hs[j]], rtol=RTOL)
            np.testing.assert_allclose(cov, p.c0())
            np.testing.assert_allclose(payload.contour + centroid, obs.cluster(j), atol=1e-12)


# ---------------------------------------------------------------- gate and likelihood


def _scored_scene(p: GroupTrackerParams, n_nodes: int):
    """Tracks with non-diagonal predicted covariances near clusters at several distances,
    one just outside the gate on d_HD^2 but inside a gate on d_HD."""
    tracker = GroupMHTTracker(p)
    rng = np.random.default_rng(11)
    nodes = []
    for k in range(n_nodes):
        cov = _spd(rng, 0.04)
        cov[0, 1] = cov[1, 0] = 0.8 * math.sqrt(cov[0, 0] * cov[1, 1])  # strongly correlated
        contour = rng.normal(0.0, 0.25, (5 + 3 * k, 2))
        nodes.append(_node(tracker, [3.0 * k, 0.0, 0.3, 0.1, 2.0], cov, contour))
    tracker.model.predict(nodes, 0.1)
    pts = []
    for k, node in enumerate(nodes):
        base = node.payload.contour + node.pred_mean[:2]
        pts.append(base[:4] + rng.normal(0.0, 0.05, (4, 2)))  # close: gated
        pts.append(rng.normal([3.0 * k + 0.2, 1.1], 0.03, (3, 2)))  # beside the gate
    return tracker, nodes, _obs(np.concatenate(pts), p)


@pytest.mark.parametrize("n_nodes", [1, 3])
def test_eq19_24_gate_and_likelihood_with_a_correlated_covariance(n_nodes: int) -> None:
    p = GroupTrackerParams(cluster_distance=0.7)  # the clusters beside stay apart
    tracker, nodes, obs = _scored_scene(p, n_nodes)
    gated, ll = tracker.model.score(nodes, obs)
    gate_sq = chi2.ppf(p.gate_probability, 2)
    r = np.eye(2) * p.point_std**2
    between = 0
    for a, node in enumerate(nodes):
        s = node.pred_cov[:2, :2] + r  # eq. 23
        contour = node.payload.contour + node.pred_mean[:2]
        for i in range(len(obs)):
            d = ref_hausdorff(obs.cluster(i), contour, s)
            if d > 9.0:
                continue  # far away: the tracker need not score it
            between += math.sqrt(gate_sq) < d <= gate_sq
            assert gated[a, i] == (d**2 <= gate_sq), (a, i, d)
            if d**2 <= gate_sq:
                assert ll[a, i] == pytest.approx(ref_log_n(d, s), rel=1e-9)
    assert gated.sum() >= n_nodes
    assert between >= 1  # some cluster tells d^2 <= gate from d <= gate


# ---------------------------------------------------------------- update (eqs. 28-31)


def test_eq28_31_update_with_a_full_covariance() -> None:
    p = GroupTrackerParams()
    tracker = GroupMHTTracker(p)
    rng = np.random.default_rng(5)
    cov = _spd(rng, 0.03)
    node = _node(tracker, [0.0, 0.0, 0.5, 0.2, 1.0], cov, np.zeros((1, 2)))
    tracker.model.predict([node], 0.1)
    legs = [[0.2, 0.0], [0.2, 0.2], [0.7, 0.0], [0.7, 0.2]]  # two people
    pts = np.concatenate(
        [np.array(c) + np.array([[0.0, 0.0], [0.03, 0.0], [0.0, 0.03]]) for c in legs]
    )
    obs = _obs(pts, p)
    assert obs.n_hs[0] == 2.0
    ((mean, c, payload),) = tracker.model.update([node], obs, [0], 0.1)
    h = np.zeros((3, 5))
    h[0, 0] = h[1, 1] = h[2, 4] = 1.0
    r = np.diag([p.centroid_std**2, p.centroid_std**2, p.size_std**2])
    pm, pc = node.pred_mean, node.pred_cov
    z = np.array([*obs.cluster(0).mean(axis=0), 2.0])
    s = h @ pc @ h.T + r
    k = pc @ h.T @ np.linalg.inv(s)
    np.testing.assert_allclose(mean, pm + k @ (z - h @ pm), rtol=1e-9)
    np.testing.assert_allclose(c, pc - k @ h @ pc, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(payload.contour + mean[:2], obs.cluster(0), atol=1e-12)


# ---------------------------------------------------------------- merge and split (eqs. 17-18)


def test_eq17_18_merged_track_weights_by_contour_size_with_cross_covariances() -> None:
    p = GroupTrackerParams()
    tracker = GroupMHTTracker(p)
    rng = np.random.default_rng(7)
    ci, cj = _spd(rng, 0.05), _spd(rng, 0.08)
    a = _node(tracker, [0.0, 0.0, 1.0, 0.0, 2.0], ci, rng.normal(0, 0.2, (2, 2)))
    b = _node(tracker, [1.0, 0.5, 0.0, 1.0, 3.0], cj, rng.normal(0, 0.2, (6, 2)))
    tracker.model.predict([a, b], 0.1)
    tracker.branches.begin_scan(GroupObservations.empty(), 0.1)
    merged = tracker.branches.merge(a, b)
    wi, wj = 2 / 8, 6 / 8
    mi, mj, pci, pcj = a.pred_mean, b.pred_mean, a.pred_cov, b.pred_cov
    mean = np.r_[wi * mi[:4] + wj * mj[:4], mi[4] + mj[4]]
    cov = np.zeros((5, 5))
    cov[:4, :4] = wi**2 * pci[:4, :4] + wj**2 * pcj[:4, :4]
    # cov(w_i x_i + w_j x_j, n_i + n_j) of independent tracks
    cov[:4, 4] = cov[4, :4] = wi * pci[:4, 4] + wj * pcj[:4, 4]
    cov[4, 4] = pci[4, 4] + pcj[4, 4]
    np.testing.assert_allclose(merged.pred_mean, mean, rtol=RTOL)
    np.testing.assert_allclose(merged.pred_cov, cov, rtol=RTOL)
    assert abs(cov[0, 4]) > 1e-3  # the cross-covariance is not zero here
    contour = merged.payload.contour + merged.pred_mean[:2]
    expected = np.concatenate([a.payload.contour + mi[:2], b.payload.contour + mj[:2]])
    np.testing.assert_allclose(contour, expected, atol=1e-12)
    assert merged.payload.must_match


def test_split_halves_have_half_the_people_and_c0() -> None:
    p = GroupTrackerParams()
    tracker = GroupMHTTracker(p)
    rng = np.random.default_rng(8)
    a = _node(tracker, [0.0, 0.0, 1.0, 0.0, 3.0], _spd(rng, 0.05), np.zeros((3, 2)))
    tracker.model.predict([a], 0.1)
    tracker.branches.begin_scan(GroupObservations.empty(), 0.1)
    for half in tracker.branches.split(a):
        np.testing.assert_allclose(half.pred_mean, np.r_[a.pred_mean[:4], 1.5], rtol=RTOL)
        np.testing.assert_allclose(half.pred_cov, p.c0())
        assert half.payload.must_match


# ---------------------------------------------------------------- eq. 32 through the branches


def _branch_priors(p: GroupTrackerParams, scene: str):
    tracker = GroupMHTTracker(p)
    rng = np.random.default_rng(9)
    if scene == "merge":  # two tracks, one observation spanning both
        ca, cb = _spd(rng, 0.03), _spd(rng, 0.03)
        a = _node(tracker, [0.0, 0.0, 0.3, 0.0, 1.0], ca, np.array([[0.0, 0.0], [0.1, 0.1]]))
        b = _node(
            tracker, [1.0, 0.0, -0.2, 0.1, 1.0], cb, np.array([[0.0, 0.0], [-0.1, 0.1], [0.1, 0.0]])
        )
        nodes = [a, b]
        pts = np.array([[x, 0.05 * (i % 2)] for i, x in enumerate(np.linspace(0.0, 1.0, 11))])
    else:  # one track, two observations in its gate
        a = _node(tracker, [0.0, 0.0, 0.0, 0.0, 2.0], _spd(rng, 0.03),
                  np.array([[-0.8, 0.0], [-0.7, 0.1], [0.7, 0.0], [0.8, 0.1]]))  # fmt: skip
        nodes = [a]
        pts = np.array([[-0.8, 0.0], [-0.75, 0.1], [0.75, 0.0], [0.8, 0.1]])
    tracker.model.predict(nodes, 0.1)
    obs = _obs(pts, p)
    tracker.branches.begin_scan(obs, 0.1)
    tracker.model.scan = obs
    gated, _ = tracker.model.score(nodes, obs)
    rows = {n.node_id: gated[k] for k, n in enumerate(nodes)}
    out = tracker.branches.branches(
        tuple(nodes), lambda t: rows[t.node_id], np.arange(len(obs), dtype=np.intp)
    )
    return nodes, out


@pytest.mark.parametrize("model_prior", ["choice", "literal"])
def test_eq32_merge_prior_is_pg_nij_over_pc_squared(model_prior: str) -> None:
    p = GroupTrackerParams(model_prior=model_prior, merge_likelihood="density")
    (a, b), out = _branch_priors(p, "merge")
    by_size = {len(br.tracks): br.log_prior for br in out}
    assert set(by_size) == {1, 2}  # continue both, or merge
    log_nij = ref_merge_log_n(
        a.pred_cov, a.pred_mean, a.payload.contour, b.pred_cov, b.pred_mean, b.payload.contour,
        p.cluster_distance,
    )  # fmt: skip
    # eq. 32: p_C^2 for the continuation, p_G N_ij for the merge
    assert by_size[2] == pytest.approx(2 * math.log(p.p_c), rel=1e-12)
    assert by_size[1] == pytest.approx(math.log(p.p_g) + log_nij, rel=1e-9)


def test_eq32_merge_prior_with_the_compatibility() -> None:
    p = GroupTrackerParams(merge_likelihood="compatibility", model_prior="literal")
    (a, b), out = _branch_priors(p, "merge")
    by_size = {len(br.tracks): br.log_prior for br in out}
    s = a.pred_cov[:4, :4] + b.pred_cov[:4, :4]
    log_nij = ref_merge_log_n(
        a.pred_cov, a.pred_mean, a.payload.contour, b.pred_cov, b.pred_mean, b.payload.contour,
        p.cluster_distance,
    )  # fmt: skip
    d2 = -2.0 * (log_nij + math.log((2 * math.pi) ** 2 * math.sqrt(np.linalg.det(s))))
    assert by_size[1] == pytest.approx(math.log(p.p_g) - 0.5 * d2, rel=1e-9)


@pytest.mark.parametrize("model_prior", ["choice", "literal"])
def test_eq32_split_prior_is_ps(model_prior: str) -> None:
    p = GroupTrackerParams(model_prior=model_prior)
    _, out = _branch_priors(p, "split")
    by_size = {len(br.tracks): br.log_prior for br in out}
    assert set(by_size) == {1, 2}
    assert by_size[1] == pytest.approx(math.log(p.p_c), rel=1e-12)
    assert by_size[2] == pytest.approx(math.log(p.p_s), rel=1e-12)


def test_normalised_model_priors_are_eq32_over_their_sum() -> None:
    p = GroupTrackerParams(model_prior="normalised")
    _, out = _branch_priors(p, "split")
    by_size = {len(br.tracks): br.log_prior for br in out}
    total = p.p_c + p.p_s
    assert math.exp(by_size[1]) == pytest.approx(p.p_c / total, rel=1e-12)
    assert math.exp(by_size[2]) == pytest.approx(p.p_s / total, rel=1e-12)


def test_normalised_merge_priors_share_probability_one() -> None:
    # eq. 32 over its sum: continue both p_C^2 / (p_C^2 + p_G N_ij), merge p_G N_ij / (...);
    # the unnormalised readings charge the continuation p_C^2 in every scan whatever N_ij
    p = GroupTrackerParams(model_prior="normalised", merge_likelihood="density")
    (a, b), out = _branch_priors(p, "merge")
    by_size = {len(br.tracks): br.log_prior for br in out}
    log_nij = ref_merge_log_n(
        a.pred_cov, a.pred_mean, a.payload.contour, b.pred_cov, b.pred_mean, b.payload.contour,
        p.cluster_distance,
    )  # fmt: skip
    merge = p.p_g * math.exp(log_nij)
    total = p.p_c**2 + merge
    assert math.exp(by_size[2]) == pytest.approx(p.p_c**2 / total, rel=1e-9)
    assert math.exp(by_size[1]) == pytest.approx(merge / total, rel=1e-9)
    assert math.exp(by_size[1]) + math.exp(by_size[2]) == pytest.approx(1.0, rel=1e-12)


def test_the_likeliest_models_come_first() -> None:
    def node(i: int) -> TrackNode:
        return TrackNode(i, i, -1, np.zeros(5), np.eye(5), 0.0, "new")

    e1 = Event("split", (node(0),), -0.5)
    e2 = Event("split", (node(1),), -1.0)
    e3 = Event("split", (node(2),), -3.0)
    models = enumerate_models([e3, e1, e2], 3)
    assert models == [(), (e1,), (e2,)]


def test_reclustering_gives_each_point_to_the_nearest_track() -> None:
    """Sec. 4.3: in the model where both tracks continue, the observation they share is
    divided by the nearest predicted contour point."""
    p = GroupTrackerParams()
    (a, b), out = _branch_priors(p, "merge")
    both = next(br for br in out if len(br.tracks) == 2)
    assert both.observations is not None
    parts = both.observations.measurements
    ca = a.payload.contour + a.pred_mean[:2]
    cb = b.payload.contour + b.pred_mean[:2]
    for k in range(len(parts)):
        pts = parts.cluster(k)
        da = np.min(np.linalg.norm(pts[:, None] - ca[None], axis=2), axis=1)
        db = np.min(np.linalg.norm(pts[:, None] - cb[None], axis=2), axis=1)
        assert np.all(da <= db) or np.all(db < da)
    assert len(parts) == 2


# ---------------------------------------------------------------- eqs. 36-37


def test_eq36_37_label_probabilities_and_rates_per_square_metre() -> None:
    p = GroupTrackerParams(observation_area=50.0)
    tracker = GroupMHTTracker(p)
    free = _node(tracker, [0.0] * 5, np.eye(5), np.zeros((1, 2)))
    must = _node(tracker, [0.0] * 5, np.eye(5), np.zeros((1, 2)))
    must.payload = replace(must.payload, must_match=True)
    lp = tracker.label_model.track_log_probs([free, must])
    np.testing.assert_allclose(np.exp(lp[0]), [p.p_m, p.p_o, p.p_t], rtol=1e-12)
    assert np.exp(lp[1, 0]) == pytest.approx(p.p_m) and np.isneginf(lp[1, 1:]).all()
    obs = _obs(np.array([[0.0, 0.0], [0.1, 0.0], [4.0, 0.0]]), p)
    new, fal = tracker.label_model.measurement_log_rates(obs)
    np.testing.assert_allclose(np.exp(new), p.p_n / 50.0, rtol=1e-12)  # lambda_N = p_N / V
    np.testing.assert_allclose(np.exp(fal), p.p_f / 50.0, rtol=1e-12)


def test_v_of_eqs_36_37_is_the_area_the_laser_saw() -> None:
    """``observation_area = 0``: V is the fan the laser saw, sum r_i^2 |dtheta| / 2 (a beam
    without a return at the range limit), set on every frame."""
    from laserpeople.frame import Frame
    from laserpeople.scan import PointSet, Scan

    ranges = np.array([2.0, 3.0, np.inf, 4.0])
    scan = Scan(0.0, -0.1, 0.05, ranges, range_max=5.0)
    xy, beams = scan.valid_points()
    ps = PointSet(0.0, xy, np.zeros(len(xy), dtype=np.int64), beams)
    frame = Frame(0, 0.0, (scan,), "laser", "sensor", None, ps, np.ones(len(xy), dtype=bool))
    tracker = GroupMHTTracker(GroupTrackerParams(observation_area=0.0))
    tracker.update(frame)
    expected = 0.5 * (4.0 + 9.0 + 25.0 + 16.0) * 0.05
    assert tracker.label_model.area == pytest.approx(expected, rel=1e-12)
    fixed = GroupMHTTracker(GroupTrackerParams(observation_area=30.0))
    fixed.update(frame)
    assert fixed.label_model.area == 30.0
