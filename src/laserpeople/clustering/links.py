"""Links between the clusters of two point sets: a cluster of one set is linked to a
cluster of the other when a point of the one lies within a distance of a point of the other
(004 Fig. 1: the feet clusters of consecutive scans, compared by their overlap)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering.compiled import extension
from laserpeople.clustering.trees import kdtree

MAX_KEYS = 1 << 20
"""Most cluster pairs (C x W) the compiled links mark in a table of their own; beyond, the
reference runs (its cost grows with the pairs of points instead)."""


def cluster_links(
    points: NDArray[np.floating],
    labels: NDArray[np.int64],
    old: NDArray[np.floating],
    old_labels: NDArray[np.int64],
    reach: float,
) -> NDArray[np.int64]:
    """The distinct links ``label * W + old_label`` (ascending; W = ``old_labels.max() +
    1``) of every pair of a point of ``points`` (N, 2) [m] (cluster ``labels`` (N,), 0..C-1)
    and a point of ``old`` (M, 2) (cluster ``old_labels`` (M,), non-empty) within
    ``reach`` [m]. Compiled where built (a sweep along x), else
    :func:`cluster_links_python`: the same links."""
    ext = extension()
    if ext is not None and len(points) and len(old):
        pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
        prev = np.ascontiguousarray(old, dtype=np.float64).reshape(-1, 2)
        lab = np.ascontiguousarray(labels, dtype=np.int64)
        old_lab = np.ascontiguousarray(old_labels, dtype=np.int64)
        width = int(old_lab.max()) + 1
        size = (int(lab.max()) + 1) * width
        if 0 < size <= MAX_KEYS:
            out = np.empty(size, dtype=np.int64)
            k = ext.cluster_links(pts, lab, prev, old_lab, float(reach), width, out)
            if k is not NotImplemented:
                return out[:k]
    return cluster_links_python(points, labels, old, old_labels, reach)


def cluster_links_python(
    points: NDArray[np.floating],
    labels: NDArray[np.int64],
    old: NDArray[np.floating],
    old_labels: NDArray[np.int64],
    reach: float,
) -> NDArray[np.int64]:
    """:func:`cluster_links` by the KD-trees' pairs within ``reach`` and a 1-D unique of
    their keys: the compiled one's reference."""
    near = kdtree(points).sparse_distance_matrix(kdtree(old), reach, output_type="ndarray")
    width = int(old_labels.max()) + 1
    return np.unique(labels[near["i"]] * width + old_labels[near["j"]]).astype(np.int64)


__all__ = ["cluster_links", "cluster_links_python"]
