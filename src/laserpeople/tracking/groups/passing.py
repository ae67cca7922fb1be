"""People who pass each other are not a group: links cut before the clustering.

000 Sec. 4.1 clusters a scan's foreground points by single linkage at d_P (1.3 m), so a
person who walks past a group within d_P is one observation with it, and the tracker must
explain that observation by a merge or by re-clustering it (Sec. 4.3). This extension cuts
the links between the points of two tracked groups that move differently before the
clustering: each blob (single linkage at d_hs) is attributed to the group of the last
scan's best hypothesis whose contour, moved by the group's velocity to this scan, is
nearest to the blob's points (a blob takes the group most of its points are nearest to),
if that contour point lies within ``pass_distance``; a link (two points closer than d_P)
between blobs of two groups whose velocities differ by more than ``pass_speed`` is cut
(they walk past each other, not together). Links to blobs attributed to no group (new
people, or too far from every prediction) are kept, as are links within one group's
points: a group that splits is not cut by this rule, and people who meet and walk on
together are linked again once their velocities agree.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]


@dataclass(frozen=True)
class MovingGroup:
    """A group of the last scan as this rule sees it.

    Attributes:
        contour: (K, 2) [m] absolute contour points at ``stamp`` (K may be 0: the
            position alone stands for the group).
        position: (2,) [m] the group's position at ``stamp``.
        velocity: (2,) [m/s] the group's velocity.
        stamp: time [s] of the estimate.
    """

    contour: FloatArray
    position: FloatArray
    velocity: FloatArray
    stamp: float

    def points_at(self, stamp: float) -> FloatArray:
        """Contour points (K, 2) [m] moved at constant velocity to ``stamp`` [s] (the
        position (1, 2) when the contour is empty)."""
        shift = self.velocity * (stamp - self.stamp)
        pts = self.contour if self.contour.shape[0] else self.position[None, :]
        return np.asarray(pts + shift, dtype=np.float64)


@dataclass(frozen=True)
class PassingRule:
    """The link cut of this module for one scan.

    Attributes:
        groups: the groups of the last scan's best hypothesis.
        stamp: time [s] of the scan being clustered.
        pass_distance: farthest a blob may be from a group's predicted contour to be
            attributed to it [m] (0: the rule is off).
        pass_speed: least difference of two groups' velocities [m/s] (norm of the
            difference vector) that cuts the links between their blobs.
    """

    groups: Sequence[MovingGroup]
    stamp: float
    pass_distance: float
    pass_speed: float

    @property
    def active(self) -> bool:
        """Whether the rule can cut anything (on, and two groups to tell apart)."""
        return self.pass_distance > 0.0 and len(self.groups) >= 2

    def owners(self, points: FloatArray, blobs: IntArray) -> IntArray:
        """Group index (N,) of each of ``points`` (N, 2) [m], -1 for none: the blob's
        (``blobs`` (N,) labels 0..B-1) majority of its points' nearest groups, kept when
        the blob's nearest point to that group's predicted contour is within
        ``pass_distance``."""
        return attribute_blobs(
            points, blobs, [g.points_at(self.stamp) for g in self.groups], self.pass_distance
        )

    def keep(self, points: FloatArray, blobs: IntArray, links: IntArray) -> BoolArray:
        """Mask (E,) of the ``links`` (E, 2) (point index pairs into ``points`` (N, 2) [m],
        blob labels ``blobs`` (N,)) that are kept."""
        n_links = links.shape[0]
        if not self.active or n_links == 0:
            return np.ones(n_links, dtype=bool)
        owner = self.owners(points, blobs)
        velocities = np.array([g.velocity for g in self.groups], dtype=np.float64).reshape(-1, 2)
        return keep_links(links, owner, velocities, self.pass_speed)


def attribute_blobs(
    points: FloatArray, blobs: IntArray, contours: Sequence[FloatArray], pass_distance: float
) -> IntArray:
    """Index into ``contours`` (N,) of the group each point's blob belongs to, -1 for none.

    Each point votes for the contour (each (K_g, 2) [m], K_g >= 1) with the nearest point;
    its blob (``blobs`` (N,) labels 0..B-1) takes the group most of its points voted for
    (ties to the lower index) if some point of the blob lies within ``pass_distance`` [m]
    of that group's contour."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    n = pts.shape[0]
    if n == 0 or not contours:
        return np.full(n, -1, dtype=np.int64)
    sizes = np.array([c.shape[0] for c in contours], dtype=np.int64)
    if (sizes < 1).any():
        raise ValueError("every group needs at least one contour point")
    cols = np.concatenate(contours).reshape(-1, 2)
    d2 = np.square(pts[:, None, 0] - cols[None, :, 0]) + np.square(
        pts[:, None, 1] - cols[None, :, 1]
    )
    per_group = np.minimum.reduceat(d2, np.cumsum(sizes) - sizes, axis=1)  # (N, G)
    nearest = np.argmin(per_group, axis=1)
    labels = np.asarray(blobs, dtype=np.int64).reshape(n)
    n_blobs = int(labels.max()) + 1
    votes = np.zeros((n_blobs, len(contours)), dtype=np.int64)
    np.add.at(votes, (labels, nearest), 1)
    blob_group = np.argmax(votes, axis=1)
    # the blob's closest approach to the group it takes
    closest = np.full(n_blobs, np.inf)
    np.minimum.at(closest, labels, per_group[np.arange(n), blob_group[labels]])
    blob_owner = np.where(closest < pass_distance * pass_distance, blob_group, -1)
    return np.asarray(blob_owner[labels], dtype=np.int64)


def keep_links(
    links: IntArray, owner: IntArray, velocities: FloatArray, pass_speed: float
) -> BoolArray:
    """Mask (E,) of the ``links`` (E, 2) kept: a link is cut when both its points belong
    to groups (``owner`` (N,), -1 none), different ones, whose ``velocities`` (G, 2)
    [m/s] differ by more than ``pass_speed`` [m/s]."""
    a, b = owner[links[:, 0]], owner[links[:, 1]]
    both = (a >= 0) & (b >= 0) & (a != b)
    cut = np.zeros(links.shape[0], dtype=bool)
    if both.any():
        dv = velocities[a[both]] - velocities[b[both]]
        cut[both] = np.hypot(dv[:, 0], dv[:, 1]) > pass_speed
    return ~cut
