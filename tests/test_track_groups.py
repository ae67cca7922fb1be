"""The group tracker (000 Sec. 4): every equation against hand-computed values, label
naming on split/merge, and scripted scenes run through the tracker."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from laserpeople.clustering import single_linkage
from laserpeople.evaluation.clustering import ClusteringError, GroupSizeError, group_size_errors
from laserpeople.frame import Frame
from laserpeople.scan import PointSet
from laserpeople.tracking.groups import GroupMHTTracker, GroupObservations, GroupTrackerParams
from laserpeople.tracking.groups.interaction import Event, GroupLabelModel, enumerate_models
from laserpeople.tracking.groups.labels import (
    format_labels,
    merge_labels,
    prune_labels,
    split_labels,
)
from laserpeople.tracking.groups.model import (
    GroupModel,
    GroupPayload,
    group_distance_sq,
    merge_log_likelihood,
    merge_state,
    split_state,
)
from laserpeople.tracking.groups.observations import (
    SizeCounting,
    close_pairs,
    component_labels,
    count_people,
)
from laserpeople.tracking.mht.tracktree import TrackNode
from test_paper_groups import ref_hausdorff, ref_log_n

# ---------------------------------------------------------------- observations (Sec. 4.1)


def _brute_single_linkage(points: np.ndarray, d: float) -> np.ndarray:
    n = len(points)
    adj = np.linalg.norm(points[:, None] - points[None], axis=2) <= d
    labels = -np.ones(n, dtype=int)
    k = 0
    for s in range(n):
        if labels[s] >= 0:
            continue
        stack = [s]
        labels[s] = k
        while stack:
            i = stack.pop()
            for j in np.nonzero(adj[i] & (labels < 0))[0]:
                labels[j] = k
                stack.append(j)
        k += 1
    return labels


def test_single_linkage_matches_all_pairs_reference() -> None:
    rng = np.random.default_rng(0)
    for _ in range(100):
        n = int(rng.integers(0, 60))
        pts = rng.uniform(0, 6, (n, 2))
        d = float(rng.uniform(0.2, 1.5))
        np.testing.assert_array_equal(single_linkage(pts, d), _brute_single_linkage(pts, d))


def test_single_linkage_chains_links_and_numbers_by_first_point() -> None:
    pts = np.array([[0, 0], [5, 0], [1, 0], [5.5, 0], [2.0, 0], [3.2, 0]])
    # points exactly d_P apart are not linked ("closer than"), so a chain 1 m apart needs more
    np.testing.assert_array_equal(single_linkage(pts, 1.05), [0, 1, 0, 1, 0, 2])
    np.testing.assert_array_equal(single_linkage(pts, 1.0), [0, 1, 2, 1, 3, 4])
    with pytest.raises(ValueError):
        single_linkage(pts, 0.0)


def legs(centre: tuple[float, float], n: int = 4) -> np.ndarray:
    """Points of one person: two legs 0.3 m apart, ``n`` points on each (radius 0.06 m)."""
    out = []
    for dx in (-0.15, 0.15):
        ang = np.linspace(-1.0, 1.0, n)
        out.append(
            np.column_stack([centre[0] + dx + 0.06 * np.sin(ang), centre[1] - 0.06 * np.cos(ang)])
        )
    return np.concatenate(out)


def _levels(pts: np.ndarray, coarse: float, fine: float) -> tuple[np.ndarray, np.ndarray]:
    pairs, length = close_pairs(pts, coarse)
    n = len(pts)
    return component_labels(n, pairs[length < coarse]), component_labels(n, pairs[length < fine])


def test_close_pairs_give_single_linkage_at_each_distance() -> None:
    """Both levels from one KD-tree query give the labels of two single_linkage calls
    (numbered by first point), including points exactly d apart (not linked)."""
    rng = np.random.default_rng(3)
    for n in (1, 2, 17, 150):
        pts = rng.uniform(0.0, 6.0, (n, 2))
        coarse, fine = _levels(pts, 1.3, 0.3)
        np.testing.assert_array_equal(coarse, single_linkage(pts, 1.3))
        np.testing.assert_array_equal(fine, single_linkage(pts, 0.3))
    grid = np.array([[0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [3.0, 0.0]])
    coarse, fine = _levels(grid, 2.0, 0.5)
    # 0.5 m and 2.0 m apart exactly: not linked at 0.5 and 2.0 (strictly closer)
    assert coarse.tolist() == [0, 0, 0, 1] and fine.tolist() == [0, 1, 2, 3]
    np.testing.assert_array_equal(coarse, single_linkage(grid, 2.0))
    with pytest.raises(ValueError, match="positive"):
        close_pairs(grid, 0.0)


def test_observations_count_human_sized_blobs_fig12() -> None:
    """Fig. 12: four people within d_P of each other are one cluster of four blobs (the
    legs of one person are within d_hs); a pair 2.6 m away is a second cluster, and, as
    in Fig. 12 (right), counts as one blob because the two stand closer than d_hs."""
    people = [(0.0, 0.0), (0.8, 0.0), (1.6, 0.0), (2.4, 0.0), (5.0, 0.0), (5.7, 0.0)]
    pts = np.concatenate([legs(p) for p in people])
    obs = GroupObservations.from_points(pts, np.arange(len(pts)), 1.3, 0.3)
    assert len(obs) == 2
    np.testing.assert_array_equal(obs.n_hs, [4.0, 1.0])
    np.testing.assert_array_equal(obs.sizes, [32, 16])
    np.testing.assert_allclose(obs.centroids[0], [1.2, pts[:32, 1].mean()])
    np.testing.assert_array_equal(np.sort(obs.cluster_members(1)), np.arange(32, 48))


def _leg(x: float, y: float, n: int = 5, r: float = 0.06) -> np.ndarray:
    """``n`` points on the front half of a leg of radius ``r`` [m] centred at (x, y)."""
    ang = np.linspace(-1.2, 1.2, n)
    return np.column_stack([x + r * np.sin(ang), y - r * np.cos(ang)])


def test_leg_counting_pairs_one_walkers_legs() -> None:
    """A walker mid-stride (legs 0.5 m apart) is two blobs at d_hs = 0.3 m (000) but one
    person when mutual-nearest leg blobs within 0.7 m are paired; two such walkers 0.75 m
    apart side by side are 4 blobs and 2 people (each leg's nearest is its own other leg:
    0.5 m against 0.75 m)."""
    legs_count = SizeCounting("legs", pair_distance=0.7, leg_radius=0.12)
    one = np.concatenate([_leg(0.0, 0.25), _leg(0.0, -0.25)])
    obs = GroupObservations.from_points(one, np.arange(len(one)), 1.3, 0.3)
    assert obs.n_hs.tolist() == [2.0]
    obs = GroupObservations.from_points(one, np.arange(len(one)), 1.3, 0.3, legs_count)
    assert obs.n_hs.tolist() == [1.0]
    two = np.concatenate([one, one + np.array([0.75, 0.0])])
    assert GroupObservations.from_points(two, np.arange(20), 1.3, 0.3).n_hs.tolist() == [4.0]
    got = GroupObservations.from_points(two, np.arange(20), 1.3, 0.3, legs_count).n_hs
    assert got.tolist() == [2.0]


def test_leg_counting_leaves_wide_blobs_and_other_clusters_alone() -> None:
    """A person with the legs together is one blob wider than a leg (radius > 0.12 m): it
    is not paired with the single visible leg of a neighbour 0.5 m away (2 people). Two
    single legs 0.6 m apart in different clusters (d_P 0.4 m) are one person each."""
    legs_count = SizeCounting("legs", pair_distance=0.7, leg_radius=0.12)
    wide = np.concatenate([_leg(-0.09, 0.0), _leg(0.09, 0.0)])  # one blob, radius ~0.15
    pts = np.concatenate([wide, _leg(0.6, 0.0)])
    obs = GroupObservations.from_points(pts, np.arange(15), 1.3, 0.3, legs_count)
    assert obs.n_hs.tolist() == [2.0]
    apart = np.concatenate([_leg(0.0, 0.0), _leg(0.6, 0.0)])
    obs = GroupObservations.from_points(apart, np.arange(10), 0.4, 0.3, legs_count)
    assert obs.n_hs.tolist() == [1.0, 1.0]
    # count_people itself: clusters 0 and 1, blobs 0..3; blobs 0 and 1 are a leg pair
    labels = np.array([0] * 5 + [0] * 5 + [1] * 5 + [1] * 5)
    fine = np.repeat(np.arange(4), 5)
    four = np.concatenate([_leg(0, 0), _leg(0, 0.4), _leg(5, 0), _leg(5, 2.0)])
    np.testing.assert_array_equal(count_people(four, labels, fine, 2, legs_count)[0], [1.0, 2.0])
    np.testing.assert_array_equal(count_people(four, labels, fine, 2, None)[0], [2.0, 2.0])


def test_reclustered_parts_take_the_scans_blobs() -> None:
    """Parts of a re-clustered observation count their people from the scan's blob labels
    (no second single linkage): a blob cut by the part boundary counts on both sides."""
    pts = np.concatenate([_leg(0.0, 0.0), _leg(0.0, 0.45), _leg(0.8, 0.0)])
    scan = GroupObservations.from_points(pts, np.arange(15), 1.3, 0.3)
    assert scan.blobs is not None and np.unique(scan.blobs).size == 3
    cut = [(scan.points[:7], scan.members[:7]), (scan.points[7:], scan.members[7:])]
    parts = GroupObservations.from_parts(cut, 0.3, blobs=scan.blobs)
    # the first part holds blob 0 and two points of blob 1; the second the rest of blob 1
    # and blob 2
    np.testing.assert_array_equal(parts.n_hs, [2.0, 2.0])
    again = GroupObservations.from_parts(cut, 0.3)  # clustered again: the same here
    np.testing.assert_array_equal(again.n_hs, parts.n_hs)


# ---------------------------------------------------------------- equations of Sec. 4.2


def test_eq17_18_merge_state() -> None:
    mi = np.array([0.0, 0.0, 1.0, 0.0, 2.0])
    mj = np.array([4.0, 0.0, 0.0, 1.0, 3.0])
    ci = np.diag([1.0, 1.0, 1.0, 1.0, 0.5])
    cj = np.diag([2.0, 2.0, 2.0, 2.0, 0.25])
    mean, cov = merge_state(mi, ci, 1, mj, cj, 3)  # w_i = 1/4, w_j = 3/4
    np.testing.assert_allclose(mean, [3.0, 0.0, 0.25, 0.75, 5.0])
    expected = (1 / 16) * 1.0 + (9 / 16) * 2.0
    np.testing.assert_allclose(np.diag(cov), [expected] * 4 + [0.75])
    assert cov[0, 4] == 0.0


def test_split_state_halves_the_size_and_restarts_the_covariance() -> None:
    c0 = np.eye(5) * 0.3
    mean, cov = split_state(np.array([1.0, 2.0, 0.5, 0.0, 3.0]), c0)
    np.testing.assert_allclose(mean, [1.0, 2.0, 0.5, 0.0, 1.5])
    np.testing.assert_allclose(cov, c0)


def test_eq25_27_group_to_group_distance_and_likelihood() -> None:
    ci = cj = np.eye(5) * 0.5  # C_i + C_j = I
    mi = np.array([0.0, 0.0, 1.0, 0.0, 1.0])
    mj = np.array([2.0, 0.0, 0.0, 0.0, 1.0])
    one = np.zeros((1, 2))
    # dx = (-2, 0) shortened by d_P = 1.3 -> (-0.7, 0); dv = (1, 0): d^2 = 0.49 + 1
    d2 = group_distance_sq(one, mi, ci, one, mj, cj, 1.3)
    assert d2 == pytest.approx(1.49)
    # within d_P the position part is zero; the closest pair of contour points counts
    two = np.array([[0.0, 0.0], [1.5, 0.0]])
    assert group_distance_sq(two, mi, ci, one, mj, cj, 1.3) == pytest.approx(1.0)
    expected = math.log(math.exp(-0.5 * 1.49) / ((2 * math.pi) ** 2 * 1.0))
    assert merge_log_likelihood(1.49, ci, cj) == pytest.approx(expected)


# ---------------------------------------------------------------- labels


def test_label_naming_on_split_and_merge() -> None:
    assert split_labels(("0",)) == (("0-0",), ("0-1",))
    assert split_labels(("1-0", "2")) == (("1-0-0", "2-0"), ("1-0-1", "2-1"))
    assert merge_labels(("0-0",), ("0-1",)) == ("0",)  # the split undone
    assert merge_labels(("0-0",), ("0-1",), prune=False) == ("0-0", "0-1")
    assert merge_labels(("1-0",), ("2",)) == ("1-0", "2")
    assert prune_labels(("0-0-0", "0-0-1", "0-1")) == ("0",)
    assert format_labels(("10", "2", "1-1")) == "1-1|2|10"


def _prune_by_restarting(labels: set[str]) -> tuple[str, ...]:
    """000's pruning written plainly: replace the first pair X-0, X-1 in natural order by
    X and start again from the first label, until no pair is left."""
    out = set(labels)
    while True:
        for label in sorted(out, key=lambda x: [int(p) for p in x.split("-")]):
            stem, sep, last = label.rpartition("-")
            if sep and last in "01" and {f"{stem}-0", f"{stem}-1"} <= out:
                out -= {f"{stem}-0", f"{stem}-1"}
                out.add(stem)
                break
        else:
            return tuple(sorted(out, key=lambda x: [int(p) for p in x.split("-")]))


def test_label_pruning_equals_restarting_from_the_first_label() -> None:
    # nested and overlapping sets (X with X-0, X-0-0 ...), where the order of the
    # replacements decides the result: {0-0, 0-1, 0-0-0, 0-0-1} -> {0, 0-0}
    assert prune_labels({"0-0", "0-1", "0-0-0", "0-0-1"}) == ("0", "0-0")
    rng = np.random.default_rng(5)
    for _ in range(3000):
        labels = {
            "-".join(map(str, [rng.integers(3), *rng.integers(2, size=rng.integers(5))]))
            for _ in range(int(rng.integers(1, 25)))
        }
        assert prune_labels(labels) == _prune_by_restarting(labels), labels


def test_model_enumeration_is_binary_and_disjoint() -> None:
    def node(i: int) -> TrackNode:
        return TrackNode(i, i, -1, np.zeros(5), np.eye(5), 0.0, "new")

    a, b, c = node(0), node(1), node(2)
    events = [
        Event("split", (a,), -1.0),
        Event("merge", (a, b), -0.5),
        Event("merge", (b, c), -2.0),
        Event("split", (c,), -1.0),
    ]
    models = enumerate_models(events, 100)
    assert models[0] == ()  # all continue: the likeliest when every event costs
    for m in models:
        ids = [t.node_id for e in m for t in e.tracks]
        assert len(ids) == len(set(ids))  # no track in two events
    # {split a, split c}, {merge ab, split c}, {split a, merge bc} are among them
    kinds = {tuple(sorted((e.kind, tuple(t.node_id for t in e.tracks)) for e in m)) for m in models}
    assert (("merge", (0, 1)), ("split", (2,))) in kinds
    assert (("merge", (1, 2)), ("split", (0,))) in kinds
    assert len(models) == 1 + 4 + 3  # empty, singles, the three disjoint pairs
    assert len(enumerate_models(events, 3)) == 3


# ---------------------------------------------------------------- the model and the MHT


def _model(params: GroupTrackerParams | None = None) -> GroupModel:
    return GroupModel((params or GroupTrackerParams()).model_settings())


def test_score_is_eq19_24_with_the_predicted_contour() -> None:
    """The vectorised gate/likelihood equals eqs. 19-24 computed point by point."""
    params = GroupTrackerParams()
    model = _model(params)
    rng = np.random.default_rng(1)
    contour = rng.normal(0, 0.3, (12, 2))
    node = TrackNode(0, 0, -1, np.array([1.0, 1.0, 0.5, 0.0, 2.0]), np.eye(5) * 0.05, 0.0, "new",
                     payload=GroupPayload(contour))  # fmt: skip
    model.predict([node], 0.1)
    near = contour + np.array([1.05, 1.0]) + rng.normal(0, 0.05, contour.shape)
    far = rng.normal([4.0, 1.0], 0.2, (6, 2))
    beside = rng.normal([1.5, 2.2], 0.2, (5, 2))
    pts = np.concatenate([near, far, beside])
    obs = GroupObservations.from_points(pts, np.arange(len(pts)), 0.9, 0.3)
    gated, ll = model.score([node], obs)
    assert node.pred_mean is not None and node.pred_cov is not None
    s = node.pred_cov[:2, :2] + np.eye(2) * params.point_std**2  # eq. 23
    for i in range(len(obs)):
        d = ref_hausdorff(obs.cluster(i), contour + node.pred_mean[:2], s)
        inside = d**2 <= params.model_settings().gate_sq
        assert gated[0, i] == inside
        if inside:
            assert ll[0, i] == pytest.approx(ref_log_n(d, s))
    assert gated[0].any() and not gated[0].all()


def test_batched_score_of_many_tracks_is_eq19_24_per_track() -> None:
    """Scoring several tracks against the scan in one pass gives, for each, eqs. 19-24
    computed point by point (gate and log N_i), including an empty contour (the track's
    position stands in for it) and tracks near several clusters."""
    params = GroupTrackerParams()
    model = _model(params)
    rng = np.random.default_rng(4)
    pts = np.concatenate(
        [rng.normal(c, 0.15, (8, 2)) for c in ([0.0, 0.0], [1.2, 0.3], [3.0, 0.0], [3.6, 1.2])]
    )
    obs = GroupObservations.from_points(pts, np.arange(len(pts)), 0.9, 0.3)
    nodes = []
    for i, (centre, k) in enumerate((([0.0, 0.0], 9), ([1.2, 0.3], 4), ([3.2, 0.5], 0))):
        contour = rng.normal(0.0, 0.15, (k, 2))
        mean = np.array([*centre, 0.2 * i, 0.0, 2.0])
        cov = np.eye(5) * (0.02 + 0.03 * i)
        nodes.append(TrackNode(i, i, -1, mean, cov, 0.0, "new", payload=GroupPayload(contour)))
    model.predict(nodes, 0.1)
    gated, ll = model.score(nodes, obs)
    gate_sq = params.model_settings().gate_sq
    for a, node in enumerate(nodes):
        assert node.pred_mean is not None and node.pred_cov is not None
        contour = node.payload.contour + node.pred_mean[:2]
        if contour.shape[0] == 0:
            contour = node.pred_mean[None, :2]
        s = node.pred_cov[:2, :2] + np.eye(2) * params.point_std**2  # eq. 23
        for i in range(len(obs)):
            d = ref_hausdorff(obs.cluster(i), contour, s)
            assert gated[a, i] == (d**2 <= gate_sq)
            if gated[a, i]:
                assert ll[a, i] == pytest.approx(ref_log_n(d, s))
    assert gated.sum() >= 3


def test_hypothesis_probabilities_eq33_37() -> None:
    """One isolated group and one observation: the children are matched (p_M N),
    occluded or obsolete with the observation a false alarm or new track (p_O, p_T times
    p_F, p_N), normalised; no model choice, so no p_C (Sec. 4.4)."""
    p = GroupTrackerParams()
    tracker = GroupMHTTracker(replace(p, mht=replace(p.mht, n_scan=0)))  # one parent
    pts = legs((2.0, 0.0))
    for k in range(5):
        tracker.mht.params = replace(p.mht, n_scan=0) if k == 4 else p.mht
        tracker.update(_frame(pts, k, 0.1 * k))
    tracker.mht.params = replace(p.mht, min_ratio=1e-9)
    node = tracker.mht.best_tracks()[0]
    moved = pts + np.array([0.02, 0.0])
    obs = GroupObservations.from_points(
        moved, np.arange(len(moved)), p.cluster_distance, p.blob_distance
    )
    tracker.model.predict([node], 0.5)
    _, ll = tracker.model.score([node], obs)
    n_i = math.exp(ll[0, 0])
    before = dict(
        zip([h.key() for h in tracker.mht.clusters[0].hypotheses], range(10), strict=False)
    )
    assert len(before) == 1  # a single parent
    tracker.update(_frame(moved, 5, 0.5))
    got = sorted(math.exp(h.log_weight) for c in tracker.mht.clusters for h in c.hypotheses)
    raw = np.array([p.p_m * n_i, p.p_o * p.p_f, p.p_o * p.p_n, p.p_t * p.p_f, p.p_t * p.p_n])
    np.testing.assert_allclose(got, np.sort(raw / raw.sum()), rtol=1e-9)


def test_label_model_split_tracks_must_match() -> None:
    lm = GroupLabelModel(0.79, 0.19, 0.02, 0.02, 0.06)
    free = TrackNode(
        0, 0, -1, np.zeros(5), np.eye(5), 0.0, "new", payload=GroupPayload(np.zeros((1, 2)))
    )
    must = TrackNode(1, 1, -1, np.zeros(5), np.eye(5), 0.0, "new",
                     payload=GroupPayload(np.zeros((1, 2)), must_match=True))  # fmt: skip
    lp = lm.track_log_probs([free, must])
    np.testing.assert_allclose(np.exp(lp[0]), [0.79, 0.19, 0.02])
    assert np.exp(lp[1, 0]) == pytest.approx(0.79) and np.isneginf(lp[1, 1:]).all()
    new, fal = lm.measurement_log_rates(GroupObservations.empty())
    assert new.size == fal.size == 0


# ---------------------------------------------------------------- scripted scenes


def _frame(points: np.ndarray, index: int, stamp: float) -> Frame:
    n = len(points)
    ps = PointSet(
        stamp, points, np.zeros(n, dtype=np.int64), np.arange(n), frame="world", index=index
    )
    return Frame(index=index, stamp=stamp, scans=(), topic="sim", frame="world", points=ps,
                 foreground=np.ones(n, dtype=bool))  # fmt: skip


# The scripted label histories hold for the defaults (not for 000's group tracker exactly,
# the paper preset of docs/papers.md: it splits the group of the scripted sequence and
# does not merge it back, see there).
SETTINGS = pytest.mark.parametrize("params", [GroupTrackerParams()], ids=["default"])


def _run(people_at, steps: int, dt: float = 0.1, params: GroupTrackerParams | None = None):  # type: ignore[no-untyped-def]
    """Track hand-made frames; ``people_at(k)`` -> list of (x, y, true group)."""
    tracker = GroupMHTTracker(params)
    tracked, memoryless = ClusteringError(), ClusteringError()
    history = []
    for k in range(steps):
        people = people_at(k)
        pts = np.concatenate([legs((x, y)) for x, y, _ in people])
        truth = np.repeat([g for _, _, g in people], len(legs((0, 0))))
        out = tracker.update(_frame(pts, k, k * dt))
        history.append(out)
        tracked.accumulate_labels(truth, tracker.point_labels(len(pts)))
        d_p = tracker.params.cluster_distance
        memoryless.accumulate_labels(truth, single_linkage(pts, d_p))
    return tracker, history, tracked.result(), memoryless.result()


@SETTINGS
def test_split_and_merge_labels_on_a_scripted_sequence(params: GroupTrackerParams) -> None:
    """Three people stand together (group 0); two walk away (0-0 and 0-1 after the split),
    come back and rejoin: the merge undoes the split (label 0 again)."""

    def people_at(k: int) -> list[tuple[float, float, int]]:
        if k < 20:
            y = 0.0
        elif k < 45:
            y = 0.12 * (k - 20)  # 1.2 m/s away
        elif k < 70:
            y = 0.12 * (70 - k)
        else:
            y = 0.0
        return [(3.0, 0.0, 0), (3.8, y, 0), (4.6, y, 0)]

    tracker, history, _, _ = _run(people_at, 130, params=params)
    first = history[10].of_kind("group")
    assert [t.labels for t in first] == ["0"]
    assert first[0].size == 3
    labels_seen = {t.labels for out in history for t in out.of_kind("group")}
    assert {"0-0", "0-1"} <= labels_seen
    last = history[-1].of_kind("group")
    assert [t.labels for t in last] == ["0"]
    kinds = [e.kind for e in tracker.events]
    assert "split" in kinds and "merge" in kinds
    assert kinds.index("split") < kinds.index("merge")
    # the rejoined group is the group of before the split (its labels say so): same id
    assert last[0].track_id == first[0].track_id
    # the half nearer the group's centroid (3.8 m) takes its id (id_memory): the pair
    # leaving (4.2 m), not the person staying at 3.0 m, who gets a new id
    halves = [t for out in history[25:45] for t in out.of_kind("group") if t.labels != "0"]
    staying = {t.track_id for t in halves if abs(t.position[1]) < 0.3}
    leaving = {t.track_id for t in halves if t.position[1] > 1.0}
    assert leaving == {first[0].track_id}
    assert staying and first[0].track_id not in staying


def test_reports_list_the_best_hypothesis_groups_first_under_their_reported_ids() -> None:
    """``last_groups`` are the update's first reports, in order (what the group benchmarks
    and the point labels rely on); a rejoined group is reported under its old id while
    its own family, the one ``point_labels`` gives its points, is new."""

    def people_at(k: int) -> list[tuple[float, float, int]]:
        y = 0.0 if k < 20 or k >= 70 else 0.12 * min(k - 20, 70 - k)
        return [(3.0, 0.0, 0), (3.8, y, 0), (4.6, y, 0)]

    tracker = GroupMHTTracker(GroupTrackerParams())
    renamed = 0
    for k in range(130):
        pts = np.concatenate([legs((x, y)) for x, y, _ in people_at(k)])
        out = tracker.update(_frame(pts, k, 0.1 * k))
        groups = tracker.last_groups
        assert len(out.tracks) >= len(groups)
        for g, t in zip(groups, out.tracks, strict=False):
            np.testing.assert_allclose(t.position, g.mean[:2], atol=1e-12)
            labels = tracker.point_labels(len(pts))
            assert set(labels[g.members].tolist()) <= {g.family}
            renamed += t.track_id != g.family
    assert renamed >= 50  # a split half under the group's id, then the rejoined group


def test_without_reuse_ids_a_rejoined_group_gets_a_new_id() -> None:
    """``reuse_ids = false``: every track is reported with its own id, so the group of
    three that split and rejoined (the scripted sequence above) ends with a new id."""

    def people_at(k: int) -> list[tuple[float, float, int]]:
        y = 0.0 if k < 20 or k >= 70 else 0.12 * min(k - 20, 70 - k)
        return [(3.0, 0.0, 0), (3.8, y, 0), (4.6, y, 0)]

    _, history, _, _ = _run(people_at, 130, params=GroupTrackerParams(reuse_ids=False))
    first, last = history[10].of_kind("group"), history[-1].of_kind("group")
    assert [t.labels for t in first] == [t.labels for t in last] == ["0"]
    assert last[0].track_id != first[0].track_id
    split_ids = {t.track_id for out in history for t in out.of_kind("group") if t.labels != "0"}
    assert first[0].track_id not in split_ids  # 000: a split half is a new track


@SETTINGS
def test_a_group_of_three_leaving_one_by_one_splits_twice(params: GroupTrackerParams) -> None:
    """Three people stand together (group 0); one walks off south, half a second later
    another north. Splits are binary (000 Sec. 4.4): the history is two splits, the labels
    end as a binary tree under 0 (0-0, 0-1-0, 0-1-1 or 0-0-0, 0-0-1, 0-1), one per person,
    and nothing merges. (When both leave in the same scan, the third cluster is a new
    group: no track's gate holds two clusters any more; docs/groups.md.)"""

    def people_at(k: int) -> list[tuple[float, float, int]]:
        south = 0.12 * max(0, k - 20)
        north = 0.12 * max(0, k - 25)
        return [(3.0, -south, 0), (3.8, 0.0, 0), (4.6, north, 0)]

    tracker, history, _, _ = _run(people_at, 60, params=params)
    assert [t.labels for t in history[10].of_kind("group")] == ["0"]
    last = sorted(t.labels for t in history[-1].of_kind("group"))
    assert last in (["0-0", "0-1-0", "0-1-1"], ["0-0-0", "0-0-1", "0-1"])
    assert sorted(t.size for t in history[-1].of_kind("group")) == [1, 1, 1]
    assert [e.kind for e in tracker.events] == ["split", "split"]


@SETTINGS
def test_two_groups_meeting_merge_their_labels(params: GroupTrackerParams) -> None:
    """Two separate groups walk together and stand: one group labelled 0|1 of size 4."""

    def people_at(k: int) -> list[tuple[float, float, int]]:
        gap = max(0.8, 4.0 - 0.1 * k)
        return [(2.0, 0.0, 0), (2.8, 0.0, 0), (2.8 + gap, 0.0, 1), (3.6 + gap, 0.0, 1)]

    tracker, history, _, _ = _run(people_at, 80, params=params)
    start = history[5].of_kind("group")
    assert sorted(t.labels for t in start) == ["0", "1"]
    last = history[-1].of_kind("group")
    assert [t.labels for t in last] == ["0|1"]
    assert last[0].size == 4
    assert [e.kind for e in tracker.events] == ["merge"]


@SETTINGS
def test_fig18_tracker_keeps_a_passing_person_apart(params: GroupTrackerParams) -> None:
    """Fig. 18: one person walks through a pair walking the other way. Memory-less single
    linkage joins them while they pass; the tracker continues both tracks and
    re-clusters the shared observation by nearest track, keeping the groups apart."""

    def people_at(k: int) -> list[tuple[float, float, int]]:
        pair_x = 1.0 + 0.12 * k
        lone_x = 9.0 - 0.12 * k
        return [(pair_x, 0.0, 0), (pair_x, 0.9, 0), (lone_x, 0.45, 1)]

    _, history, tracked, memoryless = _run(people_at, 70, params=params)
    assert memoryless.under_segmented >= 10  # they do come within d_P of each other
    assert tracked.error <= 0.5 * memoryless.error
    ids = {t.track_id for out in history[20:] for t in out.of_kind("group")}
    assert len(ids) == 2  # the same two tracks throughout, no merge


def test_people_only_mode_never_splits_or_merges() -> None:
    def people_at(k: int) -> list[tuple[float, float, int]]:
        y = 0.0 if k < 10 else min(0.12 * (k - 10), 2.0)
        return [(3.0, 0.0, 0), (3.7, y, 0)]

    tracker, _, _, _ = _run(people_at, 40, params=GroupTrackerParams.people_only())
    assert tracker.events == []
    assert tracker.params.cluster_distance == 0.5 and not tracker.params.split_merge


# ---------------------------------------------------------------- group-size error (Sec. 4.6.3)


def test_group_size_error() -> None:
    true_person = np.array([0, 0, 1, 1, 2, -1, 3])
    estimated = np.array([5, 5, 5, 5, 6, 6, -1])
    err = group_size_errors(true_person, estimated, {5: 2.4, 6: 2.0, 7: 3.0})
    np.testing.assert_allclose(err, [0.4, 1.0])  # group 7 holds no point
    acc = GroupSizeError()
    acc.accumulate(true_person, estimated, {5: 2.4, 6: 2.0})
    r = acc.result()
    assert r.mean_error == pytest.approx(0.7)
    assert r.exact_share == pytest.approx(0.5)  # 2.4 rounds to 2: exact; 2 vs 1 is not
    assert r.within_one_share == pytest.approx(1.0)
    assert r.count == 2


@pytest.mark.parametrize("share_parts", [True, False])
def test_score_of_reclustered_parts_reuses_the_scan_distances(share_parts: bool) -> None:
    """Parts of a scan cluster (a model's re-clustered observations) score as eqs. 19-24
    on the parts' own points, also when computed from the scan's distance matrix; each
    part counts as its share of one matched observation (``share_parts``, the default)
    or as a matched observation of its own (000)."""
    params = GroupTrackerParams(share_parts=share_parts)
    model = _model(params)
    rng = np.random.default_rng(4)
    contour = rng.normal(0, 0.3, (10, 2))
    node = TrackNode(0, 0, -1, np.array([1.0, 1.0, 0.0, 0.0, 2.0]), np.eye(5) * 0.05, 0.0, "new",
                     payload=GroupPayload(contour))  # fmt: skip
    model.predict([node], 0.1)
    pts = np.concatenate([contour + 1.0, rng.normal([2.0, 1.0], 0.1, (6, 2))])
    scan = GroupObservations.from_points(pts, np.arange(len(pts)), 1.3, 0.3)
    model.scan = scan
    assert len(scan) == 1
    rows = np.arange(len(scan.points))
    left = scan.points[:, 0] < 1.5
    parts = [(scan.points[left], scan.members[left]), (scan.points[~left], scan.members[~left])]
    obs = GroupObservations.from_parts(parts, 0.3, [0.5, 0.5], [rows[left], rows[~left]])
    model.score([node], scan)  # fills the per-node distances of the scan
    gated, ll = model.score([node], obs)
    assert node.pred_mean is not None and node.pred_cov is not None
    s = node.pred_cov[:2, :2] + np.eye(2) * params.point_std**2  # eq. 23
    log_pm = math.log(params.p_m)
    for i in range(2):
        d = ref_hausdorff(obs.cluster(i), contour + node.pred_mean[:2], s)
        assert gated[0, i] == (d**2 <= params.model_settings().gate_sq)
        if gated[0, i]:
            w = 0.5 if share_parts else 1.0
            expected = w * (log_pm + ref_log_n(d, s)) - log_pm
            assert ll[0, i] == pytest.approx(expected)
    assert gated[0].any()


def test_joining_observations_keeps_a_group_through_a_gap() -> None:
    """The middle one of three people in a row is unseen for four scans, leaving a gap
    wider than d_P: 000's models split the group; with the joining extension it
    continues whole."""

    def people_at(k: int) -> list[tuple[float, float, int]]:
        row = [(3.0, 0.0, 0), (3.9, 0.0, 0), (4.8, 0.0, 0)]
        return [row[0], row[2]] if 30 <= k < 34 else row

    # 000's setting: with the motion coherence (the default) the snapshot of three
    # people against the two seen makes a split the better model during the gap
    plain, _, _, _ = _run(people_at, 60, params=GroupTrackerParams())
    joined, history, result, memoryless = _run(
        people_at, 60, params=GroupTrackerParams(join_observations=True)
    )
    assert "split" in [e.kind for e in plain.events]
    assert joined.events == []
    assert {t.labels for out in history for t in out.of_kind("group")} == {"0"}
    assert result.over_segmented == 0 < memoryless.over_segmented


def test_empty_frames_and_missing_fields() -> None:
    from laserpeople.errors import LaserPeopleError

    tracker = GroupMHTTracker()
    pts = legs((2.0, 0.0))
    for k in range(3):
        tracker.update(_frame(pts, k, 0.1 * k))
    empty = _frame(np.empty((0, 2)), 3, 0.3)
    out = tracker.update(empty)  # the group is occluded, still reported
    assert [t.labels for t in out.of_kind("group")] == ["0"]
    assert tracker.point_labels(0).size == 0
    bare = Frame(index=4, stamp=0.4, scans=(), topic="sim")
    with pytest.raises(LaserPeopleError, match="points and foreground"):
        tracker.update(bare)
    wrong = replace(_frame(pts, 5, 0.5), foreground=np.ones(3, dtype=bool))
    with pytest.raises(LaserPeopleError, match="foreground mask"):
        tracker.update(wrong)


def _half(family: int, label: str, x: float) -> TrackNode:
    mean = np.array([x, 0.0, 0.0, 0.0, 1.0])
    payload = GroupPayload(np.zeros((1, 2)), (label,), event="split")
    return TrackNode(family, family, -1, mean, np.eye(5), 0.0, "detected", payload=payload)


def test_the_halves_of_a_split_keep_their_ids_by_position() -> None:
    """The two halves of a split are equally likely either way round, so the best
    hypothesis may give the left person ``3-0`` in one scan and ``3-1`` in the next: the
    ids stay with the people (nearest to where each id was last reported), also when the
    halves split anew after merging back; a half first seen keeps its own id."""
    tracker = GroupMHTTracker(GroupTrackerParams(id_memory=0.0))  # ids by labels
    assert tracker._reported_ids([_half(10, "3-0", 0.0), _half(11, "3-1", 2.0)], 0.1) == [10, 11]
    # the other hypothesis wins: family 10 (3-0) now holds the right person
    assert tracker._reported_ids([_half(10, "3-0", 2.1), _half(11, "3-1", 0.1)], 0.2) == [11, 10]
    assert tracker._reported_ids([_half(11, "3-1", 0.2), _half(10, "3-0", 2.2)], 0.3) == [10, 11]
    # merged back and split again with new families: the ids by position, not by label
    assert tracker._reported_ids([_half(20, "3-0", 2.3), _half(21, "3-1", 0.3)], 0.4) == [11, 10]
    # a half of another split whose sibling is not reported: its own id
    assert tracker._reported_ids([_half(30, "5-1", 0.35)], 0.5) == [30]
    # 000's naming (reuse_ids false): every track its family
    plain = GroupMHTTracker(GroupTrackerParams(reuse_ids=False))
    assert plain._reported_ids([_half(10, "3-0", 0.0), _half(11, "3-1", 2.0)], 0.6) == [10, 11]
    assert plain._reported_ids([_half(10, "3-0", 2.1), _half(11, "3-1", 0.1)], 0.7) == [10, 11]


def test_a_half_seen_alone_after_the_halves_swapped_keeps_its_persons_id() -> None:
    """After the halves of split 3 swapped ids by position (``3-0`` reported as 11 on the
    right, ``3-1`` as 10 on the left), the right half is missed: the left half alone,
    ``3-1`` at 0.2 m, is reported as 10, the id its person had (the swap is remembered for
    the labels, not only made by position while both halves are seen), and the right half
    back alone as 11."""
    tracker = GroupMHTTracker(GroupTrackerParams(id_memory=0.0))  # ids by labels
    assert tracker._reported_ids([_half(10, "3-0", 0.0), _half(11, "3-1", 2.0)], 0.8) == [10, 11]
    assert tracker._reported_ids([_half(10, "3-0", 2.1), _half(11, "3-1", 0.1)], 0.9) == [11, 10]
    assert tracker._reported_ids([_half(11, "3-1", 0.2)], 1.0) == [10]
    assert tracker._reported_ids([_half(10, "3-0", 2.2)], 1.1) == [11]


def test_a_new_half_takes_the_id_that_vanished_beside_it() -> None:
    """The split's halves 10 and 11 vanish and a half of another split is first reported
    0.35 m from where 10 was: it takes id 10 (``id_memory``); with ``id_gate`` 0.3 m, or
    without the handover, its own."""
    for params, expected in (
        (GroupTrackerParams(), 10),
        (GroupTrackerParams(id_gate=0.3), 30),
        (GroupTrackerParams(id_memory=0.0), 30),
    ):
        tracker = GroupMHTTracker(params)
        assert tracker._reported_ids([_half(10, "3-0", 0.0), _half(11, "3-1", 2.0)], 0.1) == [
            10,
            11,
        ]
        assert tracker._reported_ids([_half(30, "5-1", 0.35)], 0.2) == [expected]
