"""The geometry of the CSA's objects: which objects merge (002's shared gates), a cluster's
sub-clusters and split conditions (002's leader clustering), person-sized groups of
points, walls, and whose paths a fragment's are."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering.single_linkage import components
from laserpeople.tracking.csa.params import CSAParams

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


def leader_clusters(positions: FloatArray, distance: float) -> IntArray:
    """Sub-cluster label (N,) of each position (N, 2) by 002's procedure: the first
    unassigned position opens a sub-cluster, every unassigned position closer than
    ``distance`` to it joins; repeat until all are assigned."""
    pts = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
    labels = np.full(pts.shape[0], -1, dtype=np.int64)
    k = 0
    while True:
        free = np.flatnonzero(labels < 0)
        if free.size == 0:
            return labels
        first = pts[free[0]]
        near = np.linalg.norm(pts[free] - first, axis=1) < distance
        labels[free[near]] = k
        k += 1


def split_ready(
    positions: FloatArray, n_people: int, params: CSAParams, labels: IntArray | None = None
) -> tuple[bool, IntArray]:
    """002's split conditions 1 and 2 for a cluster of ``n_people`` with estimates at
    ``positions`` (E, 2); returns (split?, sub-cluster label per estimate). ``labels``:
    the estimates' sub-clusters when already computed (:func:`leader_clusters` at
    ``subcluster_distance``)."""
    if labels is None:
        labels = leader_clusters(positions, params.subcluster_distance)
    n_sub = int(labels.max()) + 1 if labels.size else 0
    if n_sub != n_people:
        return False, labels
    centroids = np.array([positions[labels == s].mean(axis=0) for s in range(n_sub)])
    d = np.linalg.norm(centroids[:, None] - centroids[None], axis=-1)
    iu = np.triu_indices(n_sub, 1)
    separated = int((d[iu] > params.separation_distance).sum())
    return separated == n_sub * (n_sub - 1) // 2, labels


def person_groups(positions: FloatArray, width: float) -> IntArray:
    """Person-sized groups of positions (N, 2) [m] by complete linkage: the two groups
    whose farthest pair of positions is closest are joined while that distance is at most
    ``width`` [m], so every group fits within ``width`` (two legs of a person, a torso)
    and people standing side by side are apart. Returns a group label (N,) per position,
    0 .. K-1 in the order of each group's first position."""
    pts = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
    n = pts.shape[0]
    d = np.hypot(*(pts[:, None] - pts[None]).transpose(2, 0, 1))
    np.fill_diagonal(d, np.inf)
    label = np.arange(n)
    while n > 1:
        i, j = np.unravel_index(int(np.argmin(d)), d.shape)
        if not d[i, j] <= width:
            break
        i, j = min(i, j), max(i, j)
        d[i] = np.maximum(d[i], d[j])  # complete linkage: the farthest pair
        d[:, i] = d[i]
        d[i, i] = np.inf
        d[j] = np.inf
        d[:, j] = np.inf
        label[label == j] = i
    # every group is labelled by its first position: numbered in that order
    return np.unique(label, return_inverse=True)[1].astype(np.int64).reshape(-1)


def gate_components(gates: NDArray[np.bool_]) -> list[list[int]]:
    """The objects that merge (002 Sec. 2: objects whose validation gates share a
    measurement): groups of the rows of ``gates`` (O, M) connected by sharing at least one
    measurement, each sorted, in the order of their first object."""
    n = gates.shape[0]
    g = gates.astype(np.float64)
    shared = (g @ g.T) > 0  # share at least one measurement
    label = components(n, np.argwhere(np.triu(shared, 1)))
    out: dict[int, list[int]] = {}
    for i, k in enumerate(label.tolist()):
        out.setdefault(k, []).append(i)
    return list(out.values())


WALL_TOLERANCE = 0.05
"""Points within this distance [m] of a line lie on it (``on_a_wall``): a wall's returns
scatter a few centimetres about it, a leg's arc bulges 0.07 m from its chord."""
WALL_OWN = 0.35
"""The points within this distance [m] of a target are its own (``on_a_wall``; the
``[leg_foreground] radius`` that keeps them)."""


def on_a_wall(xy: FloatArray, points: FloatArray, length: float) -> bool:
    """Whether a target at ``xy`` (2,) [m] sits on a wall of the scan's ``points`` (N, 2)
    [m]: its own points (those within :data:`WALL_OWN`, at least 3) lie on a straight line
    (RMS distance from their principal axis at most :data:`WALL_TOLERANCE`), and the
    points within ``length`` [m] of it that lie on that line span at least ``length``.
    A person's legs are two arcs, and their line does not continue beyond them."""
    d = np.linalg.norm(points - xy, axis=1)
    own = points[d <= WALL_OWN]
    if own.shape[0] < 3:
        return False
    centre = own.mean(axis=0)
    _, _, vt = np.linalg.svd(own - centre, full_matrices=False)
    if math.sqrt(float(np.mean(((own - centre) @ vt[1]) ** 2))) > WALL_TOLERANCE:
        return False
    near = points[d <= length] - centre
    along = near[np.abs(near @ vt[1]) <= WALL_TOLERANCE] @ vt[0]
    return bool(along.max() - along.min() >= length)


def fragment_origins(
    origin: IntArray, members: tuple[int, ...], shown: dict[int, FloatArray]
) -> IntArray:
    """``origin`` (E,) with every path that started at a target which is not one of the
    cluster's ``members`` (a fragment, see ``fragment_rule``) given to the member last
    shown nearest to that target (``shown``: person -> position (2,)); unchanged where no
    member was shown."""
    known = [m for m in members if m in shown]
    stray = sorted({int(o) for o in origin} - set(members))
    if not known or not stray:
        return origin
    out = origin.copy()
    ref = np.array([shown[m] for m in known])
    for o in stray:
        if o in shown:
            out[origin == o] = known[int(np.argmin(np.linalg.norm(ref - shown[o], axis=1)))]
    return out
