"""Births of the feet tracker for person-sized objects no filter claims (a departure from
004, whose filters start only at a step's merge -> split sequence of the feet, Fig. 1).

In a party walking abreast (people 0.75 m apart) at 10-20 Hz, a person often shows one
leg only (the other hidden behind it), and the clusters of neighbours link to each other,
so no step sequence of their own is seen; the step events that are seen fall within the
birth exclusion of a neighbour's filter and refresh it. Such a person is a foreground
object of a person's size on which no filter stands. :class:`UnclaimedDetector` follows
such objects from scan to scan and reports the ones no filter has claimed for a while.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering import cluster_covariances, single_linkage
from laserpeople.clustering.trees import nearest
from laserpeople.lazy_scipy import cKDTree
from laserpeople.tracking.particle.objects import largest_eigenvalue, two_feet

if TYPE_CHECKING:
    from laserpeople.tracking.particle.feet import FeetParams


def claimed_objects(
    points: NDArray[np.float64],
    labels: NDArray[np.int64],
    feet: NDArray[np.float64],
    distance: float,
) -> NDArray[np.bool_]:
    """(K,) True for the objects (``labels`` (N,) of ``points`` (N, 2), K = max label + 1)
    with a point within ``distance`` [m] of one of the filters' estimated feet ``feet``
    (F, 2, 2) [m]."""
    n = int(labels.max()) + 1 if len(labels) else 0
    if n == 0 or len(feet) == 0:
        return np.zeros(n, dtype=bool)
    d, _ = nearest(points, feet.reshape(-1, 2))
    near = np.bincount(labels, weights=(d <= distance).astype(np.float64), minlength=n)
    return np.asarray(near > 0, dtype=bool)


class UnclaimedDetector:
    """Person-sized objects that no filter has claimed for ``claim_time``.

    An object is the single linkage of the birth points at ``link_distance`` with at least
    ``blob_leg_points`` points (a leg: the other may be hidden behind it) and a largest
    covariance eigenvalue of at most ``still_eigenvalue`` (the still detector's bound on
    a person's size); it is unclaimed when none of
    its points lies within ``claim_distance`` of a filter's estimated foot. An unclaimed
    object is the same as the previous scan's nearest unclaimed object whose centre lies
    within ``claim_distance`` + ``claim_speed`` x the time between the scans; once it has
    been unclaimed for ``claim_time`` without a break and its centre has moved
    ``claim_move`` from where it was first seen (a walker: what stands is the still
    detector's, and clutter the background has not learned does not walk), it is
    reported, as the two halves of its points along its major axis (the two legs).
    With ``first_scan_births`` the objects of the first scan are reported at once.
    """

    def __init__(self, params: FeetParams) -> None:
        self.params = params
        self._centres = np.empty((0, 2))
        self._origins = np.empty((0, 2))
        self._since = np.empty(0)
        self._stamp: float | None = None

    def detections(
        self,
        points: NDArray[np.float64],
        stamp: float,
        feet: NDArray[np.float64],
        labels: NDArray[np.int64] | None = None,
    ) -> list[NDArray[np.float64]]:
        """The feet (2, 2) [m] of every object of ``points`` (N, 2) (``labels`` (N,) at
        ``link_distance`` if known) that no filter's estimated foot (``feet`` (F, 2, 2))
        has claimed for ``claim_time`` [s] by ``stamp`` and that moved ``claim_move``
        [m]."""
        p = self.params
        first = self._stamp is None
        dt = 0.0 if self._stamp is None else stamp - self._stamp
        self._stamp = stamp
        if p.claim_distance <= 0.0 or len(points) == 0:
            self._centres, self._origins = np.empty((0, 2)), np.empty((0, 2))
            self._since = np.empty(0)
            return []
        if labels is None:
            labels = single_linkage(points, p.link_distance)
        n = int(labels.max()) + 1
        mean, cov, count = cluster_covariances(points, labels, n)
        sized = (count >= p.blob_leg_points) & (largest_eigenvalue(cov) <= p.still_eigenvalue)
        free = sized & ~claimed_objects(points, labels, feet, p.claim_distance)
        ok = np.flatnonzero(free)
        centres, since = mean[ok], np.full(ok.size, stamp)
        origins = centres.copy()
        if len(self._centres) and ok.size:
            reach = p.claim_distance + p.claim_speed * dt
            d, j = cKDTree(self._centres).query(centres, k=1, distance_upper_bound=reach)
            kept = np.isfinite(d)
            since[kept] = self._since[j[kept]]
            origins[kept] = self._origins[j[kept]]
        self._centres, self._origins, self._since = centres, origins, since
        moved = np.hypot(*(centres - origins).T) >= p.claim_move
        ready = ok if first and p.first_scan_births else ok[(stamp - since >= p.claim_time) & moved]
        return [two_feet(points[labels == k], mean[k], cov[k]) for k in ready]
