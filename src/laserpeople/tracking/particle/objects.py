"""Which foreground points belong to objects small enough to be (part of) a person.

004 bounds the size of what its trackers follow only through the mean-shift bandwidth
(Sec. 2.2), which cuts a 1 m baggage cart into person-sized clusters, one filter each.
Here the foreground points are linked into connected objects (single linkage); an object
whose covariance has a largest eigenvalue above a bound is no person (nor a person's
feet), and the particle trackers neither start filters on its points nor count them as a
filter's support.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering import cluster_covariances, single_linkage


def largest_eigenvalue(cov: NDArray[np.float64]) -> NDArray[np.float64]:
    """Largest eigenvalue of symmetric 2x2 matrices (C, 2, 2), in closed form."""
    a, b, d = cov[:, 0, 0], cov[:, 0, 1], cov[:, 1, 1]
    return np.asarray((a + d) / 2 + np.sqrt(((a - d) / 2) ** 2 + b * b), dtype=np.float64)


def small_objects(
    points: NDArray[np.float64], link_distance: float, max_eigenvalue: float
) -> NDArray[np.bool_]:
    """(N,) True for the points of ``points`` (N, 2) [m] whose object (single linkage at
    ``link_distance`` [m]) has a largest covariance eigenvalue of at most
    ``max_eigenvalue`` [m^2]; all True when ``max_eigenvalue`` is 0 (no bound)."""
    if max_eigenvalue <= 0.0 or len(points) == 0:
        return np.ones(len(points), dtype=bool)
    labels = single_linkage(points, link_distance)
    n = int(labels.max()) + 1
    _, cov, _ = cluster_covariances(points, labels, n)
    return np.asarray(largest_eigenvalue(cov)[labels] <= max_eigenvalue, dtype=bool)


__all__ = ["largest_eigenvalue", "small_objects"]
