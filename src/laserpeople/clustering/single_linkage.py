"""Single-linkage clustering of 2D points with a distance threshold (000 Sec. 4.1).

Two points belong to the same cluster when a chain of points links them in which every
step is shorter than the threshold ``d_P``: the connected components of the graph whose
edges join points closer than ``d_P``. The pairs are found with a KD-tree
(``scipy.spatial.cKDTree.query_pairs``, O(n log n) for points of bounded density) and the
components by vectorised label propagation (:func:`components`), so no distance matrix is
ever built.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering.compiled import extension
from laserpeople.config import param
from laserpeople.lazy_scipy import cKDTree


@dataclass(frozen=True)
class SingleLinkageParams:
    """Parameters of single-linkage point clustering."""

    config_section = "clustering"

    distance: float = param(
        1.3,
        "000 Sec. 5.1, Fig. 17 (least clustering error at d_P = 1.3 m)",
        "points closer than this are linked into one cluster (d_P)",
        "m",
    )
    min_points: int = param(
        1, "assumption", "clusters with fewer points get label -1 (none)", "points"
    )

    def __post_init__(self) -> None:
        if not self.distance > 0:
            raise ValueError("clustering distance must be positive")
        if self.min_points < 1:
            raise ValueError("min_points must be at least 1")


def components(n: int, pairs: NDArray[np.integer]) -> NDArray[np.int64]:
    """Connected components of the graph on ``n`` nodes with the edges ``pairs`` (E, 2):
    per node (n,) the smallest node index of its component. Label propagation along the
    edges with pointer jumping, vectorised (a few rounds for the short chains of scan
    points; no sparse-matrix set-up, which costs more than the search for ~100 points)."""
    label = np.arange(n, dtype=np.int64)
    if len(pairs) == 0:
        return label
    a = np.asarray(pairs[:, 0], dtype=np.int64)
    b = np.asarray(pairs[:, 1], dtype=np.int64)
    while True:
        low = np.minimum(label[a], label[b])
        nxt = label.copy()
        np.minimum.at(nxt, a, low)
        np.minimum.at(nxt, b, low)
        while True:  # jump: every node to its label's label until they agree
            jumped = nxt[nxt]
            if np.array_equal(jumped, nxt):
                break
            nxt = jumped
        if np.array_equal(nxt, label):
            return label
        label = nxt


def single_linkage(
    points: NDArray[np.floating],
    distance: float,
    mask: NDArray[np.bool_] | None = None,
    min_points: int = 1,
) -> NDArray[np.int64]:
    """Cluster labels of ``points`` (N, 2) [m] under single linkage with threshold
    ``distance`` [m] (strictly closer points are linked).

    Only points where ``mask`` is True (all when None) are clustered; the others, and
    members of clusters with fewer than ``min_points`` points, get label -1. Labels are
    0..K-1, numbered by each cluster's first point in input order (deterministic).

    Returns:
        (N,) int64 labels.

    Raises:
        ValueError: ``distance`` is not a positive number.

    The compiled version runs where it is built (:mod:`~laserpeople.clustering.compiled`;
    a sweep along x over the points sorted by x, linked by union-find), else
    :func:`single_linkage_python`: the same labels.
    """
    if not distance > 0:
        raise ValueError(f"single-linkage distance must be positive, got {distance}")
    ext = extension()
    if ext is None:
        return single_linkage_python(points, distance, mask, min_points)
    pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
    labels = np.empty(pts.shape[0], dtype=np.int64)
    chosen = None if mask is None else np.ascontiguousarray(mask, dtype=bool)
    ext.single_linkage_labels(pts, chosen, float(distance), int(min_points), labels)
    return labels


def single_linkage_python(
    points: NDArray[np.floating],
    distance: float,
    mask: NDArray[np.bool_] | None = None,
    min_points: int = 1,
) -> NDArray[np.int64]:
    """:func:`single_linkage` in numpy (the KD-tree's pairs, label propagation): the
    reference of the compiled version."""
    if not distance > 0:
        raise ValueError(f"single-linkage distance must be positive, got {distance}")
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    n = pts.shape[0]
    labels = np.full(n, -1, dtype=np.int64)
    chosen = np.ones(n, dtype=bool) if mask is None else np.asarray(mask, dtype=bool).copy()
    chosen &= np.isfinite(pts).all(axis=1)
    idx = np.flatnonzero(chosen)
    if idx.size == 0:
        return labels
    sub = pts[idx]
    # query_pairs links pairs with d <= r; shrink r by one ulp so that d == distance is not linked
    pairs = cKDTree(sub).query_pairs(np.nextafter(distance, 0.0), output_type="ndarray")
    comp = components(idx.size, pairs)
    # renumber by first appearance and drop small clusters
    _, first, inverse, counts = np.unique(
        comp, return_index=True, return_inverse=True, return_counts=True
    )
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    keep = counts >= min_points
    new_id = np.full(order.size, -1, dtype=np.int64)
    kept_ranks = rank[keep]
    new_id[keep] = np.argsort(np.argsort(kept_ranks, kind="stable"), kind="stable")
    labels[idx] = new_id[inverse.reshape(-1)]
    return labels


__all__ = ["SingleLinkageParams", "components", "single_linkage", "single_linkage_python"]
