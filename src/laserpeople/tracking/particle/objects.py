"""Which foreground points belong to objects small enough to be (part of) a person.

004 bounds the size of what its trackers follow only through the mean-shift bandwidth
(Sec. 2.2), which cuts a 1 m baggage cart into person-sized clusters, one filter each.
Here the foreground points are linked into connected objects (single linkage); an object
whose covariance has a largest eigenvalue above a bound is no person (nor a person's
feet), and the particle trackers neither start filters on its points nor count them as a
filter's support; :class:`ObjectMemory` keeps the pieces such an object breaks into
from starting filters for a while.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering import cluster_covariances, single_linkage
from laserpeople.lazy_scipy import cKDTree


def largest_eigenvalue(cov: NDArray[np.float64]) -> NDArray[np.float64]:
    """Largest eigenvalue of symmetric 2x2 matrices (C, 2, 2), in closed form."""
    a, b, d = cov[:, 0, 0], cov[:, 0, 1], cov[:, 1, 1]
    return np.asarray((a + d) / 2 + np.sqrt(((a - d) / 2) ** 2 + b * b), dtype=np.float64)


def small_objects(
    points: NDArray[np.float64],
    link_distance: float,
    max_eigenvalue: float,
    labels: NDArray[np.int64] | None = None,
) -> NDArray[np.bool_]:
    """(N,) True for the points of ``points`` (N, 2) [m] whose object (single linkage at
    ``link_distance`` [m]; ``labels`` (N,) if already known) has a largest covariance
    eigenvalue of at most ``max_eigenvalue`` [m^2]; all True when ``max_eigenvalue`` is 0
    (no bound)."""
    if max_eigenvalue <= 0.0 or len(points) == 0:
        return np.ones(len(points), dtype=bool)
    eig = object_eigenvalues(points, link_distance, labels)
    return np.asarray(eig <= max_eigenvalue, dtype=bool)


def object_eigenvalues(
    points: NDArray[np.float64], link_distance: float, labels: NDArray[np.int64] | None = None
) -> NDArray[np.float64]:
    """(N,) the largest covariance eigenvalue [m^2] of the object (single linkage at
    ``link_distance`` [m]; ``labels`` (N,) if already known) each point of ``points``
    (N, 2) [m] belongs to."""
    if len(points) == 0:
        return np.empty(0)
    if labels is None:
        labels = single_linkage(points, link_distance)
    n = int(labels.max()) + 1
    _, cov, _ = cluster_covariances(points, labels, n)
    return np.asarray(largest_eigenvalue(cov)[labels], dtype=np.float64)


def kept_labels(
    points: NDArray[np.float64],
    labels: NDArray[np.int64],
    keep: NDArray[np.bool_],
    link_distance: float,
) -> NDArray[np.int64]:
    """The single-linkage labels (M,) at ``link_distance`` [m] of ``points[keep]``, given
    the ``labels`` (N,) of all ``points`` (N, 2) [m] at that distance, without clustering
    them again: dropping whole objects splits no other, so an object kept whole keeps its
    points together, and only the kept points of objects kept in part are linked again
    (among themselves: points of different objects are at least ``link_distance`` apart).
    Numbered 0..K-1 by each object's first point, as :func:`single_linkage` numbers them,
    so the result equals ``single_linkage(points[keep], link_distance)``."""
    keep = np.asarray(keep, dtype=bool)
    sub = labels[keep]
    if sub.size == 0:
        return np.empty(0, dtype=np.int64)
    n = int(labels.max()) + 1
    partial = np.bincount(sub, minlength=n) != np.bincount(labels, minlength=n)
    if partial[sub].any():
        # kept pieces of a split object: link them again, apart from every other object
        part = partial[sub]
        again = single_linkage(points[keep][part], link_distance)
        sub = sub.copy()
        sub[part] = n + again
    _, first, inverse = np.unique(sub, return_index=True, return_inverse=True)
    rank = np.empty(first.size, dtype=np.int64)
    rank[np.argsort(first, kind="stable")] = np.arange(first.size)
    return np.asarray(rank[inverse.reshape(-1)], dtype=np.int64)


class ObjectMemory:
    """Remembers where too-big objects were, so that the pieces a big object breaks into
    (a baggage cart seen at a grazing angle, or cut in two by the person in front of it)
    start no filter while they are still small.

    A point is *remembered* when its object is too big in this scan, or when it lies
    within ``reach`` [m] (at 50 Hz; scaled up with the time between scans) of a point
    remembered in the previous scan whose object was last seen too big at most
    ``duration`` [s] ago. The age is inherited from the nearest such point, so a chain of
    pieces ends ``duration`` after the object was last seen whole. ``duration`` 0 remembers
    nothing beyond the scan itself.
    """

    def __init__(self, reach: float, duration: float) -> None:
        self.reach = reach
        self.duration = duration
        self._points = np.empty((0, 2))
        self._seen = np.empty(0)
        self._stamp: float | None = None

    def update(
        self, points: NDArray[np.float64], big: NDArray[np.bool_], stamp: float
    ) -> NDArray[np.bool_]:
        """(N,) True for the points of ``points`` (N, 2) [m] that are part of a big object
        now (``big`` (N,)) or were remembered as one (see the class)."""
        seen = np.where(big, stamp, -np.inf)
        dt = 0.02 if self._stamp is None else stamp - self._stamp
        self._stamp = stamp
        if self.duration > 0.0 and len(self._points) and len(points):
            reach = self.reach * max(1.0, dt / 0.02)
            d, j = cKDTree(self._points).query(points, k=1, distance_upper_bound=reach)
            near = np.isfinite(d)
            seen[near] = np.maximum(seen[near], self._seen[j[near]])
        remembered = stamp - seen <= self.duration
        self._points = np.asarray(points[remembered], dtype=np.float64).reshape(-1, 2)
        self._seen = seen[remembered]
        return np.asarray(remembered, dtype=bool)


def two_feet(
    points: NDArray[np.float64], centre: NDArray[np.float64], cov: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Two feet (2, 2) [m] of an object of ``points`` (N, 2): the centres of its points
    either side of ``centre`` along the major axis of ``cov`` (2, 2); a side without
    points at 0.1 m from the centre."""
    _, vecs = np.linalg.eigh(cov)
    u = vecs[:, -1]
    side = (points - centre) @ u
    feet = np.empty((2, 2))
    for i, mask in enumerate((side < 0.0, side >= 0.0)):
        feet[i] = points[mask].mean(axis=0) if mask.any() else centre + (0.1 if i else -0.1) * u
    return feet


__all__ = [
    "ObjectMemory",
    "kept_labels",
    "largest_eigenvalue",
    "object_eigenvalues",
    "small_objects",
    "two_feet",
]
