"""Mean-shift clustering of 2D points with a flat kernel (004 Sec. 2, after Comaniciu & Meer).

Every point starts a mode estimate; each iteration moves every estimate to the mean of the
data points within ``bandwidth`` of it, until no estimate moves more than ``tol``. Estimates
that end within ``merge_radius`` (default ``bandwidth / 2``) of each other, directly or in a
chain, form one cluster. Neighbour search uses scipy's KD-tree; the shift of all estimates is
one sparse product per iteration (no loop over points).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

DENSE_LIMIT = 600
"""Up to this many points the neighbour sums use a dense distance mask, above it the
KD-tree (the same result; the dense form is faster for the few hundred foreground points
of a frame)."""


@dataclass(frozen=True, eq=False)
class MeanShiftResult:
    """Clusters of N points.

    Attributes:
        labels: (N,) int64 cluster index per point, 0..C-1, numbered by first point.
        centres: (C, 2) [m] the mode of each cluster (mean of its members' converged
            estimates).
        iterations: Iterations run.
    """

    labels: NDArray[np.int64]
    centres: NDArray[np.float64]
    iterations: int

    @property
    def n_clusters(self) -> int:
        """Number of clusters C."""
        return int(self.centres.shape[0])


def mean_shift(
    points: NDArray[np.floating],
    bandwidth: float,
    *,
    merge_radius: float | None = None,
    tol: float = 1e-3,
    max_iter: int = 50,
) -> MeanShiftResult:
    """Cluster ``points`` (N, 2) [m] by flat-kernel mean shift of radius ``bandwidth`` [m].

    Returns labels (N,) and cluster modes. Empty input gives no clusters.
    """
    if not bandwidth > 0.0:
        raise ValueError(f"bandwidth must be positive, got {bandwidth}")
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    n = len(pts)
    if n == 0:
        return MeanShiftResult(np.empty(0, np.int64), np.empty((0, 2)), 0)
    tree = cKDTree(pts) if n > DENSE_LIMIT else None
    modes = pts.copy()
    moving = np.ones(n, dtype=bool)
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007 - iteration count is returned
        idx = np.flatnonzero(moving)
        if n <= DENSE_LIMIT:  # small sets: one dense (M, N) mask product is fastest
            diff = modes[idx, None, :] - pts[None, :, :]
            inside = (np.einsum("mnc,mnc->mn", diff, diff) <= bandwidth * bandwidth).astype(
                np.float64
            )
            count = inside.sum(axis=1)
            sx, sy = (inside @ pts).T
        else:
            assert tree is not None
            pairs = cKDTree(modes[idx]).sparse_distance_matrix(
                tree, bandwidth, output_type="ndarray"
            )
            rows, cols = pairs["i"], pairs["j"]  # zero distances are kept as entries
            count = np.bincount(rows, minlength=idx.size).astype(np.float64)
            sx = np.bincount(rows, weights=pts[cols, 0], minlength=idx.size)
            sy = np.bincount(rows, weights=pts[cols, 1], minlength=idx.size)
        has = count > 0
        new = modes[idx].copy()
        new[has, 0] = sx[has] / count[has]
        new[has, 1] = sy[has] / count[has]
        shift = np.hypot(*(new - modes[idx]).T)
        modes[idx] = new
        moving[idx[shift <= tol]] = False
        if not moving.any():
            break
    radius = bandwidth / 2.0 if merge_radius is None else merge_radius
    pairs_ij = cKDTree(modes).query_pairs(radius, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs_ij)), (pairs_ij[:, 0], pairs_ij[:, 1])), shape=(n, n))
    _, comp = connected_components(graph, directed=False)
    # renumber by first occurrence so labels are stable
    _, first, inverse = np.unique(comp, return_index=True, return_inverse=True)
    order = np.argsort(np.argsort(first))
    labels = order[inverse].astype(np.int64)
    c = int(labels.max()) + 1
    cnt = np.bincount(labels, minlength=c).astype(np.float64)
    centres = np.column_stack(
        [np.bincount(labels, weights=modes[:, k], minlength=c) / cnt for k in (0, 1)]
    )
    return MeanShiftResult(labels, centres, it)


def cluster_covariances(
    points: NDArray[np.floating], labels: NDArray[np.int64], n_clusters: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """Per cluster: mean (C, 2), covariance (C, 2, 2) [m^2] and size (C,), vectorised."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    cnt = np.bincount(labels, minlength=n_clusters)
    safe = np.maximum(cnt, 1).astype(np.float64)
    mean = np.column_stack(
        [np.bincount(labels, weights=pts[:, k], minlength=n_clusters) / safe for k in (0, 1)]
    )
    d = pts - mean[labels]
    cov = np.empty((n_clusters, 2, 2))
    for a in (0, 1):
        for b in (0, 1):
            cov[:, a, b] = (
                np.bincount(labels, weights=d[:, a] * d[:, b], minlength=n_clusters) / safe
            )
    return mean, cov, cnt.astype(np.int64)


__all__ = ["MeanShiftResult", "cluster_covariances", "mean_shift"]
