"""The clustering of 2D points compiled (``single_linkage_labels``, ``mean_shift_dense``,
``cluster_stats``, ``cluster_links`` and ``nearest_points`` of the MHT's C extension)
against the numpy references on random scenes of feet-sized blobs: the same labels, links
and nearest points where no distance lies within a last bit of a threshold or a tie (mean
shift's clusters in all but 1 % of scenes), cluster modes within 1e-12 m, cluster means
and covariances within 1e-15 (relative to the points' scale), nearest distances within
1e-15 relative."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.typing import NDArray

from laserpeople.clustering import compiled
from laserpeople.clustering.links import cluster_links, cluster_links_python
from laserpeople.clustering.mean_shift import (
    DENSE_LIMIT,
    cluster_covariances,
    cluster_covariances_python,
    mean_shift,
    mean_shift_python,
)
from laserpeople.clustering.single_linkage import single_linkage, single_linkage_python
from laserpeople.clustering.trees import close_pairs, close_pairs_python, nearest, nearest_python

MODE_TOL = 1e-12  # m: the first step's sums add the same points in another order
STATS_TOL = 1e-15  # relative: the same sums in the same order, up to a last-bit difference
MAX_OTHER_CLUSTERINGS = 10  # of 1000 mean shift scenes (see its test)
NEAR_TIE = 1e-12  # relative: two centres this close to a point may be ranked either way


@pytest.fixture(autouse=True)
def _built() -> None:
    if compiled.extension() is None:
        pytest.skip("the C extension is not built, or stale")


def _blobs(rng: np.random.Generator, n: int) -> NDArray[np.float64]:
    """n points round 1-8 centres within 3 m of the origin, spread 0.02-0.3 m."""
    k = int(rng.integers(1, 9))
    centres = rng.uniform(-3.0, 3.0, (k, 2))
    spread = rng.uniform(0.02, 0.3)
    out: NDArray[np.float64] = centres[rng.integers(0, k, n)] + rng.normal(0.0, spread, (n, 2))
    return out


def _near_threshold(pts: NDArray[np.float64], d: float) -> bool:
    """Whether a pair of points lies within 1e-9 of the distance d (where the two ways of
    computing a distance may decide a link differently)."""
    ok = pts[np.isfinite(pts).all(axis=1)]
    diff = ok[:, None, :] - ok[None, :, :]
    dist = np.sqrt((diff**2).sum(axis=-1))
    return bool((np.abs(dist - d) < 1e-9).any())


def test_single_linkage_labels_are_the_references() -> None:
    """1500 random scenes with masks, points that are not finite and min_points 1-4."""
    rng = np.random.default_rng(350)
    for _ in range(1500):
        n = int(rng.integers(0, 250))
        pts = _blobs(rng, n)
        if n and rng.random() < 0.3:
            pts[rng.integers(0, n, 3)] = [np.nan, np.inf]
        d = float(rng.uniform(0.03, 0.6))
        if _near_threshold(pts, d):
            continue
        mask = rng.random(n) < 0.8 if rng.random() < 0.5 else None
        k = int(rng.integers(1, 5))
        np.testing.assert_array_equal(
            single_linkage(pts, d, mask, k), single_linkage_python(pts, d, mask, k)
        )


def test_single_linkage_links_strictly_closer_points() -> None:
    """Points exactly ``distance`` apart are not linked, a float closer they are."""
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [5.0, 5.0], [5.0, 5.5]])
    assert single_linkage(pts, 1.0).tolist() == [0, 1, 2, 2]
    assert single_linkage(pts, np.nextafter(1.0, 2.0)).tolist() == [0, 0, 1, 1]
    assert single_linkage(pts, 1.0, min_points=2).tolist() == [-1, -1, 0, 0]
    mask = np.array([True, True, False, True])
    assert single_linkage(pts, 1.0, mask).tolist() == [0, 1, -1, 2]


def test_mean_shift_is_the_reference() -> None:
    """1000 random scenes of up to DENSE_LIMIT points: the same clusters (labels) in all but
    at most MAX_OTHER_CLUSTERINGS scenes, and in those that agree the modes within MODE_TOL
    and the iterations within one. The two add a kernel's points in another order, so an
    estimate or a mode within a last bit of the bandwidth, the merge radius or the
    tolerance may be decided either way on some CPU; a wrong compiled path differs in most
    scenes (0 of 1000 differ here). Above DENSE_LIMIT the reference itself runs."""
    rng = np.random.default_rng(351)
    other = 0
    for _ in range(1000):
        pts = _blobs(rng, int(rng.integers(1, 300)))
        bw = float(rng.uniform(0.05, 0.5))
        radius = None if rng.random() < 0.7 else float(rng.uniform(0.01, 0.3))
        got = mean_shift(pts, bw, merge_radius=radius)
        want = mean_shift_python(pts, bw, merge_radius=radius)
        if not np.array_equal(got.labels, want.labels):
            other += 1
            continue
        assert abs(got.iterations - want.iterations) <= 1
        np.testing.assert_allclose(got.centres, want.centres, rtol=0.0, atol=MODE_TOL)
    assert other <= MAX_OTHER_CLUSTERINGS
    big = _blobs(rng, DENSE_LIMIT + 50)
    got, want = mean_shift(big, 0.2), mean_shift_python(big, 0.2)  # the same numpy code
    np.testing.assert_allclose(got.centres, want.centres, rtol=0.0, atol=MODE_TOL)
    assert got.labels.tolist() == want.labels.tolist()


def test_mean_shift_by_hand() -> None:
    """Two feet 0.5 m apart and one lone point: three clusters at their means; a point
    that is not finite leaves the call to the reference (which refuses it as before)."""
    pts = np.array([[0.0, 0.0], [0.02, 0.0], [0.5, 0.0], [0.52, 0.02], [3.0, 3.0]])
    r = mean_shift(pts, 0.1)
    assert r.labels.tolist() == [0, 0, 1, 1, 2]
    np.testing.assert_allclose(r.centres, [[0.01, 0.0], [0.51, 0.01], [3.0, 3.0]], atol=1e-15)
    bad = pts.copy()
    bad[2, 0] = np.nan
    try:
        want: object = mean_shift_python(bad, 0.1).labels.tolist()
    except ValueError as exc:
        want = type(exc)
    try:
        got: object = mean_shift(bad, 0.1).labels.tolist()
    except ValueError as exc:
        got = type(exc)
    assert got == want


def test_cluster_statistics_are_the_references() -> None:
    """1000 random labellings (empty clusters among them): the same sizes, means and
    covariances within STATS_TOL of the points' scale."""
    rng = np.random.default_rng(352)
    for _ in range(1000):
        n = int(rng.integers(0, 200))
        pts = _blobs(rng, n) + rng.uniform(-20.0, 20.0, 2)
        c = int(rng.integers(1, 12))
        labels = rng.integers(0, c, n).astype(np.int64)
        got = cluster_covariances(pts, labels, c)
        want = cluster_covariances_python(pts, labels, c)
        np.testing.assert_array_equal(got[2], want[2])
        scale = max(1.0, float(np.abs(pts).max(initial=0.0)))
        np.testing.assert_allclose(got[0], want[0], rtol=0.0, atol=STATS_TOL * scale)
        np.testing.assert_allclose(got[1], want[1], rtol=0.0, atol=STATS_TOL * scale**2)


def test_cluster_statistics_refuse_labels_outside() -> None:
    """A label outside 0..C-1 is left to the reference, which refuses it."""
    pts = np.zeros((3, 2))
    with pytest.raises(ValueError):
        cluster_covariances(pts, np.array([0, -1, 1]), 2)
    with pytest.raises(ValueError):
        cluster_covariances_python(pts, np.array([0, -1, 1]), 2)


def test_cluster_links_are_the_references() -> None:
    """1000 random pairs of scans (the second a moved copy of the first, or another
    scene), each clustered by mean shift: the same links."""
    rng = np.random.default_rng(353)
    for _ in range(1000):
        old = _blobs(rng, int(rng.integers(1, 200)))
        new = (
            old + rng.normal(0.0, 0.05, old.shape)
            if rng.random() < 0.5
            else _blobs(rng, int(rng.integers(1, 200)))
        )
        reach = float(rng.uniform(0.05, 0.6))
        cross = np.sqrt(((new[:, None, :] - old[None, :, :]) ** 2).sum(axis=-1))
        if (np.abs(cross - reach) < 1e-9).any():
            continue
        labels, old_labels = mean_shift(new, 0.2).labels, mean_shift(old, 0.2).labels
        np.testing.assert_array_equal(
            cluster_links(new, labels, old, old_labels, reach),
            cluster_links_python(new, labels, old, old_labels, reach),
        )


def test_cluster_links_by_hand() -> None:
    """Clusters 0 and 1 of the new points near old cluster 1, new cluster 2 near old 0;
    points exactly the reach apart are linked."""
    new = np.array([[0.0, 0.0], [0.3, 0.0], [5.0, 0.0]])
    old = np.array([[5.0, 0.5], [0.15, 0.0]])
    got = cluster_links(new, np.array([0, 1, 2]), old, np.array([0, 1]), 0.5)
    assert got.tolist() == [0 * 2 + 1, 1 * 2 + 1, 2 * 2 + 0]


def test_nearest_points_are_the_references() -> None:
    """1000 random scenes of points and a few filters' centres: the same nearest centre,
    its distance within 1e-15 relative."""
    rng = np.random.default_rng(354)
    for _ in range(1000):
        pts = _blobs(rng, int(rng.integers(0, 300)))
        centres = rng.uniform(-3.0, 3.0, (int(rng.integers(1, 20)), 2))
        got, want = nearest(pts, centres), nearest_python(pts, centres)
        np.testing.assert_allclose(got[0], want[0], rtol=1e-15, atol=0.0)
        # the index where no other centre is within a last bit as near (computed here)
        dist = np.sort(np.hypot(*(pts[:, None, :] - centres[None, :, :]).transpose(2, 0, 1)))
        clear = (
            dist[:, 1] - dist[:, 0] > NEAR_TIE * np.maximum(dist[:, 0], 1.0)
            if len(centres) > 1
            else np.ones(len(pts), dtype=bool)
        )
        assert got[1][clear].tolist() == want[1][clear].tolist()


def test_nearest_by_hand() -> None:
    """The nearest of three centres and its distance; the first of two equally near."""
    d, j = nearest(np.array([[0.0, 0.0], [3.0, 4.0]]), np.array([[1.0, 0.0], [3.0, 3.0]]))
    assert j.tolist() == [0, 1]
    np.testing.assert_allclose(d, [1.0, 1.0], rtol=1e-15)
    d, j = nearest(np.array([[0.0, 0.0]]), np.array([[0.0, 1.0], [1.0, 0.0]]))
    assert j.tolist() == [0]


def test_close_pairs_are_the_references() -> None:
    """1000 random sets of up to 40 filters' positions: the same pairs (in any order)."""
    rng = np.random.default_rng(355)
    for _ in range(1000):
        pts = rng.uniform(-3.0, 3.0, (int(rng.integers(0, 40)), 2))
        radius = float(rng.uniform(0.05, 1.5))
        if _near_threshold(pts, radius):
            continue
        got, want = close_pairs(pts, radius), close_pairs_python(pts, radius)
        assert sorted(map(tuple, got.tolist())) == sorted(map(tuple, want.tolist()))


def test_close_pairs_by_hand() -> None:
    """Points exactly the radius apart are a pair; none of fewer than two points."""
    pts = np.array([[0.0, 0.0], [0.5, 0.0], [2.0, 0.0], [0.0, 0.25]])
    assert sorted(map(tuple, close_pairs(pts, 0.5).tolist())) == [(0, 1), (0, 3)]
    assert close_pairs(pts[:1], 0.5).shape == (0, 2)
    assert close_pairs(np.empty((0, 2)), 0.5).shape == (0, 2)
