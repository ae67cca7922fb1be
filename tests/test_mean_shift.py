"""Mean-shift clustering against a brute-force implementation."""

from __future__ import annotations

import importlib

import numpy as np
import pytest

from laserpeople.clustering import cluster_covariances, mean_shift

ms_module = importlib.import_module("laserpeople.clustering.mean_shift")


def brute_force(points: np.ndarray, h: float, tol: float, max_iter: int) -> np.ndarray:
    """Every point's mode by the textbook loop: shift to the mean of the points within h."""
    modes = []
    for x in points:
        m = x.copy()
        for _ in range(max_iter):
            near = points[np.hypot(*(points - m).T) <= h]
            new = near.mean(axis=0)
            done = np.hypot(*(new - m)) <= tol
            m = new
            if done:
                break
        modes.append(m)
    return np.array(modes)


def chained(modes: np.ndarray, radius: float) -> np.ndarray:
    """Cluster label (N,) of each mode: modes closer than ``radius`` chained together."""
    d = np.hypot(*(modes[:, None] - modes[None, :]).transpose(2, 0, 1)) <= radius
    reach = d.copy()
    for _ in range(len(modes)):
        nxt = (reach.astype(int) @ d.astype(int)) > 0
        if np.array_equal(nxt, reach):
            break
        reach = nxt
    return np.unique(reach, axis=0, return_inverse=True)[1].ravel()


def same_partition(a: np.ndarray, b: np.ndarray) -> bool:
    return bool(np.array_equal(a[:, None] == a[None, :], b[:, None] == b[None, :]))


@pytest.mark.parametrize("dense", [True, False])
@pytest.mark.parametrize("seed", range(4))
def test_modes_and_clusters_equal_brute_force(
    seed: int, dense: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    if not dense:  # force the KD-tree path
        monkeypatch.setattr(ms_module, "DENSE_LIMIT", 0)
    rng = np.random.default_rng(seed)
    centres = rng.uniform(0, 6, (5, 2))
    pts = np.concatenate([c + rng.normal(0, 0.06, (int(rng.integers(3, 30)), 2)) for c in centres])
    h = 0.25
    res = mean_shift(pts, h, tol=1e-6, max_iter=200)
    modes = brute_force(pts, h, 1e-6, 200)
    # the clusters: modes closer than h/2 chained together
    assert same_partition(res.labels, chained(modes, h / 2))
    for k in range(res.n_clusters):
        assert res.centres[k] == pytest.approx(modes[res.labels == k].mean(axis=0), abs=1e-5)


@pytest.mark.parametrize("seed", [4, 6, 13])
def test_clusters_whose_modes_lie_near_the_merge_radius(seed: int) -> None:
    """Feet-sized clusters 0.6-1.2 bandwidths apart along a line: some modes end between
    h/2 and h/1.5 apart, so the partition tells the merge radius h/2 from a near miss."""
    h = 0.25
    rng = np.random.default_rng(seed)
    steps = rng.uniform(0.6 * h, 1.2 * h, (6, 1))
    centres = np.cumsum(steps, axis=0) * np.array([[1.0, 0.0]]) + rng.normal(0, 0.03, (6, 2))
    pts = np.concatenate([c + rng.normal(0, 0.03, (int(rng.integers(3, 15)), 2)) for c in centres])
    modes = brute_force(pts, h, 1e-6, 200)
    expect = chained(modes, h / 2)
    assert not same_partition(expect, chained(modes, h / 1.5))  # the test can tell
    assert same_partition(mean_shift(pts, h, tol=1e-6, max_iter=200).labels, expect)


def test_two_feet_merge_or_split_with_the_bandwidth() -> None:
    rng = np.random.default_rng(3)
    foot = rng.normal(0, 0.02, (8, 2))
    pts = np.vstack([foot, foot + np.array([0.3, 0.0])])
    assert mean_shift(pts, 0.1).n_clusters == 2
    assert mean_shift(pts, 0.5).n_clusters == 1


def test_labels_numbered_by_first_point_and_empty_input() -> None:
    pts = np.array([[5.0, 5.0], [0.0, 0.0], [5.01, 5.0], [0.01, 0.0]])
    assert mean_shift(pts, 0.1).labels.tolist() == [0, 1, 0, 1]
    empty = mean_shift(np.empty((0, 2)), 0.1)
    assert empty.n_clusters == 0 and empty.labels.size == 0
    with pytest.raises(ValueError):
        mean_shift(pts, 0.0)


def test_cluster_covariances_equal_numpy() -> None:
    rng = np.random.default_rng(0)
    pts = rng.normal(size=(40, 2))
    labels = rng.integers(0, 3, 40)
    mean, cov, cnt = cluster_covariances(pts, labels, 3)
    for k in range(3):
        sel = pts[labels == k]
        assert cnt[k] == len(sel)
        assert mean[k] == pytest.approx(sel.mean(axis=0))
        assert cov[k] == pytest.approx(np.cov(sel.T, bias=True))


def test_duplicate_points_and_shared_positions_give_the_brute_force_modes() -> None:
    """Estimates at one position are shifted once (the distinct-position step): with many
    duplicated points the clusters and centres still equal the textbook loop's."""
    rng = np.random.default_rng(7)
    base = np.concatenate([c + rng.normal(0, 0.05, (12, 2)) for c in ((0, 0), (1, 0), (1.2, 0.1))])
    pts = np.concatenate([base, base[::2], base[::3]])  # exact duplicates
    res = mean_shift(pts, 0.2, tol=1e-9, max_iter=300)
    modes = brute_force(pts, 0.2, 1e-9, 300)
    for k in range(res.n_clusters):
        assert res.centres[k] == pytest.approx(modes[res.labels == k].mean(axis=0), abs=1e-9)
    # duplicates share their label
    n = len(base)
    assert np.array_equal(res.labels[n : n + len(base[::2])], res.labels[:n][::2])


def test_components_equal_scipy_connected_components() -> None:
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    from laserpeople.clustering.single_linkage import components

    rng = np.random.default_rng(1)
    for _ in range(50):
        n = int(rng.integers(1, 300))
        pts = rng.uniform(0, rng.uniform(0.5, 8.0), (n, 2))
        pairs = cKDTree(pts).query_pairs(0.2, output_type="ndarray")
        graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
        _, expect = connected_components(graph, directed=False)
        got = components(n, pairs)
        assert same_partition(got, expect)
        # each node's label is the smallest index of its component
        for c in np.unique(got):
            assert c == np.flatnonzero(got == c).min()
