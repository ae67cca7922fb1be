"""Mean-shift clustering of 2D points with a flat kernel (004 Sec. 2, after Comaniciu & Meer).

Every point starts a mode estimate; each iteration moves every estimate to the mean of the
data points within ``bandwidth`` of it, until no estimate moves more than ``tol`` (an
estimate that moved at most ``tol`` stops). Estimates at one position are shifted once. Estimates
that end within ``merge_radius`` (default ``bandwidth / 2``) of each other, directly or in a
chain, form one cluster. Neighbour search uses scipy's KD-tree; the shift of all estimates is
one sparse product per iteration (no loop over points).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering.compiled import extension
from laserpeople.clustering.single_linkage import components
from laserpeople.lazy_scipy import cKDTree

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


def _distinct(
    xy: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The distinct rows (U, 2) of ``xy`` (M, 2) and each row's index (M,) among them
    (a 1-D unique of x + iy, much cheaper than ``np.unique(axis=0)``)."""
    key, inverse = np.unique(xy[:, 0] + 1j * xy[:, 1], return_inverse=True)
    return np.column_stack([key.real, key.imag]), inverse.reshape(-1).astype(np.int64)


def _shift(
    modes: NDArray[np.float64],
    pts: NDArray[np.float64],
    tree: cKDTree | None,
    bandwidth: float,
) -> NDArray[np.float64]:
    """One flat-kernel step: every mode (M, 2) moved to the mean of the points of ``pts``
    (N, 2) within ``bandwidth`` of it (a mode without any stays)."""
    m = len(modes)
    if tree is None:  # small sets: a dense (M, N) distance mask
        dx = np.subtract.outer(modes[:, 0], pts[:, 0])
        dy = np.subtract.outer(modes[:, 1], pts[:, 1])
        # per coordinate, not einsum over a (M, N, 2) array: the same sums, 10x faster
        rows, cols = np.nonzero(dx * dx + dy * dy <= bandwidth * bandwidth)
    else:
        pairs = cKDTree(modes).sparse_distance_matrix(tree, bandwidth, output_type="ndarray")
        rows, cols = pairs["i"], pairs["j"]  # zero distances are kept as entries
    # sums by bincount, not a matrix product: BLAS threads cost more than they save here
    count = np.bincount(rows, minlength=m).astype(np.float64)
    sx = np.bincount(rows, weights=pts[cols, 0], minlength=m)
    sy = np.bincount(rows, weights=pts[cols, 1], minlength=m)
    has = count > 0
    new = modes.copy()
    new[has, 0] = sx[has] / count[has]
    new[has, 1] = sy[has] / count[has]
    return new


def _components(modes: NDArray[np.float64], radius: float) -> NDArray[np.int64]:
    """Connected components (U,) of the graph linking modes (U, 2) within ``radius``, as
    any labels (renumbered by the caller)."""
    return components(len(modes), cKDTree(modes).query_pairs(radius, output_type="ndarray"))


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

    Estimates that sit at exactly the same position have the same future under the flat
    kernel, so each iteration shifts only the distinct positions of the estimates still
    moving (after one step most points of a foot or torso share one or two), which gives
    the same modes as shifting every estimate.
    """
    if not bandwidth > 0.0:
        raise ValueError(f"bandwidth must be positive, got {bandwidth}")
    ext = extension()
    pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
    n = len(pts)
    if ext is not None and 0 < n <= DENSE_LIMIT:
        radius = merge_distance(bandwidth, merge_radius)
        labels = np.empty(n, dtype=np.int64)
        centres = np.empty((n, 2))
        done = ext.mean_shift_dense(
            pts, float(bandwidth), float(tol), int(max_iter), float(radius), labels, centres
        )
        if done is not NotImplemented:
            c, it = done
            return MeanShiftResult(labels, centres[:c], it)
    return mean_shift_python(pts, bandwidth, merge_radius=merge_radius, tol=tol, max_iter=max_iter)


def merge_distance(bandwidth: float, merge_radius: float | None) -> float:
    """Modes closer than this [m] are one cluster: ``merge_radius``, or half the bandwidth
    (004 Sec. 3)."""
    return bandwidth / 2.0 if merge_radius is None else merge_radius


def mean_shift_python(
    points: NDArray[np.floating],
    bandwidth: float,
    *,
    merge_radius: float | None = None,
    tol: float = 1e-3,
    max_iter: int = 50,
) -> MeanShiftResult:
    """:func:`mean_shift` in numpy (the KD-tree's pairs for the first step, the distinct
    estimates' shifts by a dense mask or the KD-tree): the reference of the compiled
    version, which shifts every distinct estimate over the dense kernel up to
    :data:`DENSE_LIMIT` points (the same modes within rounding: the first step's sums
    add the same points in another order)."""
    if not bandwidth > 0.0:
        raise ValueError(f"bandwidth must be positive, got {bandwidth}")
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    n = len(pts)
    if n == 0:
        return MeanShiftResult(np.empty(0, np.int64), np.empty((0, 2)), 0)
    everything = cKDTree(pts)
    tree = everything if n > DENSE_LIMIT else None
    # first step of every estimate (each at its own point): the neighbour pairs of the
    # points within the bandwidth, found once by the KD-tree (the costliest step)
    ij = everything.query_pairs(bandwidth, output_type="ndarray")
    own = np.arange(n)
    rows = np.concatenate([ij[:, 0], ij[:, 1], own])
    cols = np.concatenate([ij[:, 1], ij[:, 0], own])
    count = np.bincount(rows, minlength=n).astype(np.float64)
    modes = np.column_stack(
        [np.bincount(rows, weights=pts[cols, k], minlength=n) / count for k in (0, 1)]
    )
    still = np.hypot(*(modes - pts).T) > tol
    members = np.flatnonzero(still)
    # distinct positions of the moving estimates and, per moving point, its position's row
    reps, owner = _distinct(modes[still])
    it = 1
    while members.size and it < max_iter:
        it += 1
        new = _shift(reps, pts, tree, bandwidth)
        shift = np.hypot(*(new - reps).T)
        modes[members] = new[owner]
        still = shift > tol
        if not still.any():
            break
        moving = still[owner]
        members, owner = members[moving], owner[moving]
        reps, inverse = _distinct(new[still])
        owner = inverse[np.cumsum(still)[owner] - 1]
    radius = merge_distance(bandwidth, merge_radius)
    distinct, where = _distinct(modes)
    comp = _components(distinct, radius)[where]
    # renumber by first occurrence so labels are stable
    _, first, inverse = np.unique(comp, return_index=True, return_inverse=True)
    order = np.argsort(np.argsort(first))
    labels = order[inverse.reshape(-1)].astype(np.int64)
    c = int(labels.max()) + 1
    cnt = np.bincount(labels, minlength=c).astype(np.float64)
    centres = np.column_stack(
        [np.bincount(labels, weights=modes[:, k], minlength=c) / cnt for k in (0, 1)]
    )
    return MeanShiftResult(labels, centres, it)


def cluster_covariances(
    points: NDArray[np.floating], labels: NDArray[np.int64], n_clusters: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """Per cluster: mean (C, 2), covariance (C, 2, 2) [m^2] (divided by the size) and size
    (C,) of ``points`` (N, 2) [m] with ``labels`` (N,) in 0..C-1; an empty cluster has mean
    and covariance 0. Compiled where built (the same sums in the same order as
    :func:`cluster_covariances_python`, its reference)."""
    ext = extension()
    if ext is not None:
        pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
        lab = np.ascontiguousarray(labels, dtype=np.int64)
        if lab.shape == (pts.shape[0],):
            mean = np.empty((n_clusters, 2))
            cov = np.empty((n_clusters, 2, 2))
            cnt = np.empty(n_clusters, dtype=np.int64)
            if ext.cluster_stats(pts, lab, mean, cov, cnt) is not NotImplemented:
                return mean, cov, cnt
    return cluster_covariances_python(points, labels, n_clusters)


def cluster_covariances_python(
    points: NDArray[np.floating], labels: NDArray[np.int64], n_clusters: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """:func:`cluster_covariances` in numpy (bincount sums): the compiled one's reference."""
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


__all__ = [
    "MeanShiftResult",
    "cluster_covariances",
    "cluster_covariances_python",
    "mean_shift",
    "mean_shift_python",
]
