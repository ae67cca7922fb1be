"""The group tracker's fast paths against the per-equation reference: the one-pass score
of many tracks (dense distances, segment reductions, blocks) is eqs. 19-24 computed per
track and cluster with the reach pre-gate; the same for a model's re-clustered parts, for
the root-mean-square variant, and whatever the block size."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from laserpeople.tracking.groups import GroupObservations, GroupTrackerParams
from laserpeople.tracking.groups import model as model_mod
from laserpeople.tracking.groups.model import GroupModel, GroupPayload
from laserpeople.tracking.mht.tracktree import TrackNode
from test_paper_groups import ref_log_n


def _distances(z: np.ndarray, contour: np.ndarray, s: np.ndarray) -> np.ndarray:
    """D(z_l - p_j, S) (eq. 21) of every observed point to every contour point (K_z, K_p)."""
    v = z[:, None, :] - contour[None, :, :]
    return np.sqrt(np.einsum("ijk,kl,ijl->ij", v, np.linalg.inv(s), v))


# two code paths giving the same bits may hold on one CPU only: CI runs these again on
# another CPU path (.ci/run)
pytestmark = pytest.mark.regression


def _scene(seed: int) -> tuple[list[TrackNode], GroupObservations]:
    """Tracks (some with empty contours, some far from every cluster) and a scan."""
    rng = np.random.default_rng(seed)
    centres = rng.uniform(-4.0, 4.0, (6, 2))
    pts = np.concatenate([rng.normal(c, 0.25, (int(rng.integers(3, 14)), 2)) for c in centres])
    obs = GroupObservations.from_points(pts, np.arange(len(pts)), 0.6, 0.3)
    nodes = []
    for i in range(9):
        centre = centres[i % 6] + rng.normal(0.0, 0.4, 2) if i < 8 else np.array([30.0, 0.0])
        k = 0 if i % 4 == 3 else int(rng.integers(1, 12))
        contour = rng.normal(0.0, 0.25, (k, 2))
        mean = np.array([*centre, rng.normal(0, 0.3), rng.normal(0, 0.3), 2.0])
        cov = np.diag(rng.uniform(0.01, 0.4, 5))
        nodes.append(TrackNode(i, i, -1, mean, cov, 0.0, "new", payload=GroupPayload(contour)))
    return nodes, obs


def _reference(
    model: GroupModel, nodes: list[TrackNode], obs: GroupObservations, scan: GroupObservations
) -> tuple[np.ndarray, np.ndarray]:
    """Gate and log-likelihood per (track, cluster) from eqs. 19-24 (one cluster and one
    track at a time), with the reach pre-gate on the clusters of ``scan`` the points of
    each cluster came from."""
    st = model.s
    gated = np.zeros((len(nodes), len(obs)), dtype=bool)
    loglik = np.full((len(nodes), len(obs)), -np.inf)
    source = obs.source if obs.source is not None else np.arange(len(obs.points))
    scan_cluster = np.repeat(np.arange(len(scan)), scan.sizes)
    for a, node in enumerate(nodes):
        assert node.pred_mean is not None and node.pred_cov is not None
        pos = node.pred_mean[:2]
        contour = node.payload.contour + pos
        if contour.shape[0] == 0:
            contour = pos[None, :]
        s = node.pred_cov[:2, :2] + model.s.r_point  # eq. 23
        lam = float(np.linalg.eigvalsh(s).max())
        reach = min(st.max_gap, math.sqrt(st.gate_sq * lam))
        r_t = float(np.max(np.hypot(*(contour - pos).T)))
        for i in range(len(obs)):
            rows = source[obs.offsets[i] : obs.offsets[i + 1]]
            near = all(
                math.hypot(*(scan.centroids[c] - pos)) - scan.radii[c] - r_t <= reach
                for c in np.unique(scan_cluster[rows])
            )
            if not near:
                continue
            d2 = _distances(obs.cluster(i), contour, s)
            if st.rms:
                d = min(
                    math.sqrt(np.mean(d2.min(axis=1) ** 2)), math.sqrt(np.mean(d2.min(axis=0) ** 2))
                )
            else:  # eqs. 19-20
                d = min(float(np.mean(d2.min(axis=1))), float(np.mean(d2.min(axis=0))))
            if d**2 <= st.gate_sq:
                gated[a, i] = True
                w = obs.share[i]
                ll = ref_log_n(d, s)
                loglik[a, i] = w * (st.log_p_match + ll) - st.log_p_match
    return gated, loglik


def _check(model: GroupModel, nodes: list[TrackNode], obs: GroupObservations, scan) -> None:  # type: ignore[no-untyped-def]
    ref_g, ref_ll = _reference(model, nodes, obs, scan)
    gated, loglik = model.score(nodes, obs)
    np.testing.assert_array_equal(gated, ref_g)
    np.testing.assert_allclose(loglik[gated], ref_ll[ref_g], rtol=0, atol=1e-9)
    assert np.all(np.isneginf(loglik[~gated]))


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
@pytest.mark.parametrize("rms", [False, True])
def test_one_pass_score_equals_eq19_24_per_track(seed: int, rms: bool) -> None:
    params = replace(GroupTrackerParams(), hausdorff="rms" if rms else "mean")
    nodes, obs = _scene(seed)
    model = GroupModel(params.model_settings())
    model.predict(nodes, 0.2)
    model.scan = obs
    _check(model, nodes, obs, obs)
    assert model.score(nodes, obs)[0].sum() >= 3


@pytest.mark.parametrize("seed", [0, 1])
def test_one_pass_score_with_a_short_reach_cap(seed: int) -> None:
    """``max_gap`` below the gate's reach cuts pairs (the cap is not exact): the fast path
    cuts the same pairs."""
    settings = replace(GroupTrackerParams().model_settings(), max_gap=0.3)
    nodes, obs = _scene(seed)
    model = GroupModel(settings)
    model.predict(nodes, 0.5)
    model.scan = obs
    _check(model, nodes, obs, obs)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_one_pass_score_of_reclustered_parts(seed: int) -> None:
    """A model's parts (each cluster cut in two, one pair of clusters joined) score as
    eqs. 19-24 on their own points, with the reach of the scan clusters they came from."""
    nodes, scan = _scene(seed)
    model = GroupModel(GroupTrackerParams().model_settings())
    model.predict(nodes, 0.2)
    model.scan = scan
    parts, rows, shares = [], [], []
    for i in range(1, len(scan)):
        own = np.arange(scan.offsets[i], scan.offsets[i + 1])
        left = scan.points[own, 0] < scan.centroids[i, 0]
        for sel in (left, ~left):
            if sel.any():
                parts.append((scan.points[own[sel]], scan.members[own[sel]]))
                rows.append(own[sel])
                shares.append(float(sel.sum()) / own.size)
    joined = np.concatenate([np.arange(scan.offsets[0], scan.offsets[2])])
    parts.append((scan.points[joined], scan.members[joined]))
    rows.append(joined)
    shares.append(2.0)
    obs = GroupObservations.from_parts(
        parts, 0.3, shares, rows, None, scan.blobs[np.concatenate(rows)]
    )
    _check(model, nodes, obs, scan)


def test_score_in_blocks_equals_one_block(monkeypatch: pytest.MonkeyPatch) -> None:
    """Scoring in blocks of tracks (large scans) gives the same numbers as one block."""
    nodes, obs = _scene(5)
    settings = GroupTrackerParams().model_settings()
    whole = GroupModel(settings)
    whole.predict(nodes, 0.2)
    g1, l1 = whole.score(nodes, obs)
    monkeypatch.setattr(model_mod, "SCORE_BLOCK", 40)
    blocks = GroupModel(settings)
    blocks.predict(nodes, 0.2)
    g2, l2 = blocks.score(nodes, obs)
    np.testing.assert_array_equal(g1, g2)
    np.testing.assert_array_equal(l1, l2)


def test_remembered_rows_are_returned_for_any_order_of_tracks() -> None:
    """Rows remembered from an earlier call are the ones a new call in another order
    returns (the MHT core asks for subsets of the live tracks)."""
    nodes, obs = _scene(6)
    model = GroupModel(GroupTrackerParams().model_settings())
    model.predict(nodes, 0.2)
    g, ll = model.score(nodes, obs)
    order = [4, 0, 7, 2]
    g2, ll2 = model.score([nodes[i] for i in order], obs)
    np.testing.assert_array_equal(g2, g[order])
    np.testing.assert_array_equal(ll2, ll[order])


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("rms", [False, True])
def test_score_of_one_track_alone_equals_eq19_24(seed: int, rms: bool) -> None:
    """A track scored alone gives eqs. 19-24, and the same numbers
    as the same track scored with others by :meth:`GroupModel.score_apart`."""
    params = replace(GroupTrackerParams(), hausdorff="rms" if rms else "mean")
    nodes, obs = _scene(seed)
    alone = GroupModel(params.model_settings())
    alone.predict(nodes, 0.2)
    for node in nodes:
        _check(alone, [node], obs, obs)
    together = GroupModel(params.model_settings())
    together.predict(nodes, 0.2)
    together.score_apart(nodes, obs)
    g1, l1 = alone.score(nodes, obs)
    g2, l2 = together.score(nodes, obs)
    np.testing.assert_array_equal(g1, g2)
    np.testing.assert_array_equal(l1, l2)


def test_split_halves_scored_apart_equal_each_half_alone() -> None:
    """The two halves of a split (same prediction and contour) are scored once by
    :meth:`GroupModel.score_apart`; each half's rows are what scoring it alone gives."""
    nodes, obs = _scene(4)
    params = GroupTrackerParams()
    model = GroupModel(params.model_settings())
    model.predict(nodes, 0.2)
    mean, cov = model_mod.split_state(nodes[1].pred_mean, params.c0())
    halves = []
    for i, labels in enumerate((("0-0",), ("0-1",))):
        half = TrackNode(100 + i, 100 + i, 1, mean, cov, 0.2, "detected",
                         payload=GroupPayload(nodes[1].payload.contour, labels))  # fmt: skip
        half.pred_mean, half.pred_cov = mean, cov
        halves.append(half)
    model.score_apart([*halves, nodes[2]], obs)
    g, ll = model.score([*halves, nodes[2]], obs)
    for row, node in enumerate([*halves, nodes[2]]):
        alone = GroupModel(params.model_settings())
        alone.predict([n for n in nodes if n is not nodes[1]], 0.2)
        node_alone = TrackNode(200, 200, 1, node.mean, node.cov, 0.2, "detected",
                               payload=node.payload)  # fmt: skip
        node_alone.pred_mean, node_alone.pred_cov = node.pred_mean, node.pred_cov
        g1, l1 = alone.score([node_alone], obs)
        np.testing.assert_array_equal(g[row], g1[0])
        np.testing.assert_array_equal(ll[row], l1[0])


def test_nearest_unit_equals_a_plain_loop_over_units() -> None:
    """Re-clustering by nearest predicted contour point (Sec. 4.3) in one matrix equals
    the rule applied unit by unit (the first unit wins a tie; an empty contour counts as
    the track's position)."""
    from laserpeople.tracking.groups.interaction import _nearest_unit

    nodes, obs = _scene(5)
    model = GroupModel(GroupTrackerParams().model_settings())
    model.predict(nodes, 0.2)
    units = [[n] for n in nodes[:8]]
    owner = _nearest_unit(obs.points, units)
    for k, p in enumerate(obs.points):
        best, want = math.inf, 0
        for u, (node,) in enumerate(units):
            c = node.payload.contour + node.pred_mean[:2]
            if c.shape[0] == 0:
                c = node.pred_mean[None, :2]
            d = float(np.min(np.sum((c - p) ** 2, axis=1)))
            if d < best:
                best, want = d, u
        assert owner[k] == want
    # a tie: two units with the same contour, the point goes to the first
    twin = [[nodes[0]], [nodes[0]]]
    assert (_nearest_unit(obs.points, twin) == 0).all()


def test_row_block_min_equals_minimum_reduceat_along_rows() -> None:
    """The per-cluster minima of the score (one ``min`` per block of rows) are
    ``np.minimum.reduceat`` along the rows, bit for bit, for one or many blocks."""
    rng = np.random.default_rng(11)
    for _ in range(300):
        n, k = int(rng.integers(1, 60)), int(rng.integers(1, 40))
        q = rng.normal(0.0, 10.0 ** rng.uniform(-3, 3), (n, k))
        n_cuts = min(n - 1, int(rng.integers(0, 6)))
        cuts = np.sort(rng.choice(np.arange(1, max(n, 2)), size=n_cuts, replace=False))
        starts = np.concatenate([[0], cuts]).astype(np.int64)
        lengths = np.diff(np.append(starts, n))
        got = model_mod._row_block_min(q, starts, lengths)
        np.testing.assert_array_equal(got, np.minimum.reduceat(q, starts, axis=0))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_initial_states_in_one_batch_equal_eq16_per_cluster(seed: int) -> None:
    """New groups made in one batch have the states, covariances, contours and members of
    eq. 16 cluster by cluster."""
    _, obs = _scene(seed)
    model = GroupModel(GroupTrackerParams().model_settings())
    js = list(range(len(obs)))[::-1][: max(2, len(obs) - 1)]
    made = model.initiate(obs, js, 0.0)
    assert len(made) == len(js)
    for j, (mean, cov, payload) in zip(js, made, strict=True):
        centroid = obs.cluster(j).mean(axis=0)
        np.testing.assert_allclose(mean, [*centroid, 0.0, 0.0, obs.n_hs[j]], rtol=1e-12)
        np.testing.assert_allclose(cov, model.s.c0, rtol=1e-12)  # eq. 16's initial covariance
        np.testing.assert_allclose(payload.contour, obs.cluster(j) - centroid, atol=1e-12)
        np.testing.assert_array_equal(payload.members, obs.cluster_members(j))
        assert payload.labels == () and not payload.must_match and payload.event == ""


@pytest.mark.parametrize("method", ["blobs", "legs"])
def test_people_count_of_dense_blob_labels_equals_relabelled_ones(method: str) -> None:
    """The blob count takes labels 0..B-1 as they are (no ``np.unique``): the same counts
    as for the same blobs under labels with gaps (which go through ``np.unique``)."""
    from laserpeople.tracking.groups.observations import SizeCounting, count_people

    rng = np.random.default_rng(3)
    counting = SizeCounting(method)
    for _ in range(100):
        n = int(rng.integers(1, 80))
        pts = rng.uniform(-3.0, 3.0, (n, 2))
        m = int(rng.integers(1, 6))
        labels = np.sort(rng.integers(0, m, n))
        m = int(labels.max()) + 1
        blobs = labels * 10 + rng.integers(0, 4, n)  # blobs inside clusters
        _, dense = np.unique(blobs, return_inverse=True)
        dense = dense.astype(np.int64)
        gappy = dense * 3 + 5
        got = count_people(pts, labels, dense, m, counting)[0]
        np.testing.assert_array_equal(got, count_people(pts, labels, gappy, m, counting)[0])


def test_gate_bits_equal_packbits() -> None:
    """A gate row as the bits of an int: the short loop equals numpy's packbits, for
    short rows and for rows longer than 64."""
    from laserpeople.tracking.groups.interaction import _bits

    rng = np.random.default_rng(5)
    for m in [0, 1, 2, 5, 17, 63, 64, 65, 130]:
        for _ in range(20):
            row = rng.random(m) < 0.3
            want = int.from_bytes(np.packbits(row, bitorder="little").tobytes(), "little")
            assert _bits(row) == want


def test_predictions_gathered_from_predict_equal_the_nodes_own() -> None:
    """Predictions taken as rows of :meth:`GroupModel.predict`'s arrays equal the nodes'
    ``pred_mean`` / ``pred_cov`` stacked, in any order and for a node predicted elsewhere
    (a model's split half); a remembered single row comes back as the computed one."""
    nodes, obs = _scene(6)
    model = GroupModel(GroupTrackerParams().model_settings())
    model.predict(nodes, 0.3)
    order = [nodes[i] for i in (4, 0, 7, 2, 2)]
    means, covs = model._predictions(order)
    np.testing.assert_array_equal(means, np.stack([n.pred_mean for n in order]))
    np.testing.assert_array_equal(covs, np.stack([n.pred_cov for n in order]))
    other = TrackNode(500, 500, 1, nodes[1].mean, nodes[1].cov, 0.3, "detected",
                      payload=nodes[1].payload)  # fmt: skip
    other.pred_mean, other.pred_cov = nodes[1].pred_mean * 0.5, nodes[1].pred_cov
    means, _ = model._predictions([nodes[3], other])
    np.testing.assert_array_equal(means, np.stack([nodes[3].pred_mean, other.pred_mean]))
    g_all, ll_all = model.score(nodes, obs)
    for i, node in enumerate(nodes):
        g1, ll1 = model.score([node], obs)
        np.testing.assert_array_equal(g1, g_all[i : i + 1])
        np.testing.assert_array_equal(ll1, ll_all[i : i + 1])


def _group_distance_sq_reference(ci, mi, cvi, cj, mj, cvj, d_p):  # type: ignore[no-untyped-def]
    """Eqs. 25-26 as written before the in-place version: pairs as rows, the shortening
    by two ``where``s, the quadratic form by einsum over (pairs, 4)."""
    pi = ci + mi[:2]
    pj = cj + mj[:2]
    delta = (pi[:, None, :] - pj[None, :, :]).reshape(-1, 2)
    length = np.hypot(delta[:, 0], delta[:, 1])
    scale = np.where(length > d_p, 1.0 - d_p / np.where(length > 0, length, 1.0), 0.0)
    star = np.empty((delta.shape[0], 4))
    star[:, :2] = delta * scale[:, None]
    star[:, 2:] = mi[2:4] - mj[2:4]
    sol = np.linalg.solve(cvi[:4, :4] + cvj[:4, :4], star.T)
    return float(np.min(np.einsum("ij,ji->i", star, sol)))


def test_group_distance_in_place_equals_eq25_26_bit_for_bit() -> None:
    """The in-place d_min^2 (one (4, pairs) array, the shortening as 1 - d_P / max(|dx|,
    d_P)) is the number the pairs-as-rows version gives, to the bit, also for point
    pairs exactly d_P apart, within d_P and at the same place."""
    rng = np.random.default_rng(12)
    for trial in range(400):
        ki, kj = rng.integers(1, 40, 2)
        ci = rng.normal(0.0, 0.6, (ki, 2))
        cj = rng.normal(0.0, 0.6, (kj, 2))
        if trial % 5 == 0:  # a pair exactly d_P apart and a pair at one place
            cj[0] = ci[0] + np.array([1.3, 0.0])
            cj[-1] = ci[-1]
        mi = np.array([*rng.normal(0, 1, 2), *rng.normal(0, 0.8, 2), 2.0])
        mj = np.array([*rng.normal(0, 1, 2), *rng.normal(0, 0.8, 2), 1.0])
        a = rng.normal(size=(5, 5))
        b = rng.normal(size=(5, 5))
        cvi = a @ a.T * 0.05 + np.eye(5) * 0.01
        cvj = b @ b.T * 0.05 + np.eye(5) * 0.01
        got = model_mod.group_distance_sq(ci, mi, cvi, cj, mj, cvj, 1.3)
        assert got == _group_distance_sq_reference(ci, mi, cvi, cj, mj, cvj, 1.3)


def test_observations_of_ordered_parts_skip_the_sort_with_the_same_arrays() -> None:
    """``_from_labels(..., ordered=True)`` (labels already non-decreasing, as from_parts
    makes them) equals the sorting path."""
    rng = np.random.default_rng(3)
    sizes = rng.integers(1, 9, 6)
    labels = np.repeat(np.arange(6), sizes)
    pts = rng.normal(0.0, 1.0, (labels.size, 2))
    idx = rng.permutation(labels.size).astype(np.int64)
    fine = np.arange(labels.size, dtype=np.int64) // 2
    counting = GroupTrackerParams().counting()
    a = GroupObservations._from_labels(pts, idx, labels, fine, counting)
    b = GroupObservations._from_labels(pts, idx, labels, fine, counting, ordered=True)
    for name in ("points", "offsets", "members", "centroids", "n_hs", "share", "blobs"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


def test_gate_event_pretest_equals_the_split_and_merge_loops() -> None:
    """The pre-test of :meth:`GroupBranches.branches` (some gate with two observations;
    some observation in two gates) says what its loops over tracks and pairs find."""
    from laserpeople.tracking.groups.interaction import _gate_events

    rng = np.random.default_rng(8)
    for _ in range(3000):
        masks = [int(x) for x in rng.integers(0, 2 ** int(rng.integers(1, 9)), rng.integers(0, 7))]
        wide = any(m.bit_count() >= 2 for m in masks)
        shared = any(
            masks[a] & masks[b] for a in range(len(masks)) for b in range(a + 1, len(masks))
        )
        assert _gate_events(masks) == (wide, shared)
