"""KD-trees of point sets kept for their next use: a particle-filter tracker asks for a
tree of the same points several times per scan (the step detector, the filters' support,
the points near their feet, the blobs) and of the previous scan's points once more (the
step detector's overlap), and building one costs more than looking it up.

:func:`kdtree` returns a :class:`scipy.spatial.cKDTree` of a copy of the points, the same
tree for the same points (the same float64 values, bit for bit, in the same order) while it
is among the :data:`KEPT` last ones asked for in this thread (each thread keeps its own, so
that trackers in threads do not share a cache). :func:`nearest` finds each point's nearest
of a few others (the filters' feet or centres) and :func:`close_pairs` the pairs of a few
points within a distance (two filters on one person) without a tree.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering.compiled import extension
from laserpeople.lazy_scipy import cKDTree

KEPT = 4
"""Trees kept per thread: this scan's point sets and the previous scan's."""

CLOSE_POINTS = 200
"""Most points :func:`close_pairs` compares pair by pair (compiled): the filters of a
scan; beyond, a KD-tree finds the pairs."""

NEAREST_PAIRS = 100_000
"""Most query-reference pairs :func:`nearest` compares one by one (compiled); beyond, a
KD-tree finds the nearest."""

_local = threading.local()


def kdtree(points: NDArray[np.floating]) -> Any:
    """A ``cKDTree`` (default leaf size) of ``points`` (N, 2) [m], built on a copy of them
    (a later change of ``points`` does not reach it), kept for the next call with the same
    points (see the module doc)."""
    pts = np.ascontiguousarray(points, dtype=np.float64)
    key = (pts.shape, pts.tobytes())
    cache: OrderedDict[tuple[tuple[int, ...], bytes], Any] | None = getattr(_local, "trees", None)
    if cache is None:
        cache = _local.trees = OrderedDict()
    tree = cache.get(key)
    if tree is not None:
        cache.move_to_end(key)
        return tree
    tree = cKDTree(pts.copy())
    cache[key] = tree
    if len(cache) > KEPT:
        cache.popitem(last=False)
    return tree


def nearest(
    queries: NDArray[np.floating], refs: NDArray[np.floating]
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Each query's (N, 2) distance (N,) [m] to its nearest point of ``refs`` (M, 2), M >= 1,
    and that point's index (N,): compiled where built, by comparing every pair (up to
    :data:`NEAREST_PAIRS`; the first of equally near points), else :func:`nearest_python`.
    The same distances (the square root of dx^2 + dy^2, as the KD-tree computes them)."""
    ext = extension()
    q = np.ascontiguousarray(queries, dtype=np.float64).reshape(-1, 2)
    r = np.ascontiguousarray(refs, dtype=np.float64).reshape(-1, 2)
    if ext is not None and len(r) > 0 and len(q) * len(r) <= NEAREST_PAIRS:
        j = np.empty(len(q), dtype=np.int64)
        d = np.empty(len(q))
        if ext.nearest_points(q, r, j, d) is not NotImplemented:
            return d, j
    return nearest_python(q, r)


def nearest_python(
    queries: NDArray[np.floating], refs: NDArray[np.floating]
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """:func:`nearest` by a KD-tree of ``refs`` (:func:`kdtree`): the compiled one's
    reference."""
    d, j = kdtree(refs).query(queries, k=1)
    return np.asarray(d, dtype=np.float64), np.asarray(j, dtype=np.int64)


def close_pairs(points: NDArray[np.floating], radius: float) -> NDArray[np.int64]:
    """The pairs (K, 2) of indices i < j of ``points`` (N, 2) [m] within ``radius`` [m] of
    each other, in no particular order: compiled where built, by comparing every pair (up
    to :data:`CLOSE_POINTS` points), else :func:`close_pairs_python`: the same pairs."""
    ext = extension()
    pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
    n = len(pts)
    if ext is not None and n <= CLOSE_POINTS:
        out = np.empty((max(n * (n - 1) // 2, 0), 2), dtype=np.int64)
        k = ext.close_pairs(pts, float(radius), out)
        if k is not NotImplemented:
            return out[:k]
    return close_pairs_python(pts, radius)


def close_pairs_python(points: NDArray[np.floating], radius: float) -> NDArray[np.int64]:
    """:func:`close_pairs` by a KD-tree's ``query_pairs``: the compiled one's reference."""
    pairs = cKDTree(np.asarray(points, dtype=np.float64).reshape(-1, 2)).query_pairs(
        radius, output_type="ndarray"
    )
    return np.asarray(pairs, dtype=np.int64).reshape(-1, 2)


def clear() -> None:
    """Forget the trees this thread keeps."""
    getattr(_local, "trees", OrderedDict()).clear()


__all__ = [
    "CLOSE_POINTS",
    "KEPT",
    "NEAREST_PAIRS",
    "clear",
    "close_pairs",
    "close_pairs_python",
    "kdtree",
    "nearest",
    "nearest_python",
]
