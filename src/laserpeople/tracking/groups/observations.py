"""Observations of the group tracker (000 Sec. 4.1): clusters of foreground points.

The foreground points of one scan are grouped by single linkage with the distance d_P; each
cluster Z_i is one observation. Its size observation n_hs(Z_i) is the number of
human-sized clusters found by re-clustering its points with d_hs < d_P (Fig. 12).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering import single_linkage

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True, eq=False)
class GroupObservations:
    """The observation clusters of one scan, M clusters over P points.

    Attributes:
        points: (P, 2) [m], cluster after cluster.
        offsets: (M + 1,) start of each cluster in ``points``.
        members: (P,) index of each point in the frame's point set (for evaluation).
        centroids: (M, 2) [m] mean point of each cluster (eq. 16).
        n_hs: (M,) number of human-sized blobs of each cluster (Sec. 4.1).
        share: (M,) share of the scan's observation each cluster is (1; for the parts of
            a re-clustered observation their share of its points).
        source: (P,) row of each point in the scan's observation set this one was made
            from, or None for the scan's own set.
    """

    points: FloatArray
    offsets: IntArray
    members: IntArray
    centroids: FloatArray
    n_hs: FloatArray
    share: FloatArray
    source: IntArray | None = None

    def __len__(self) -> int:
        return int(self.offsets.size - 1)

    def cluster(self, i: int) -> FloatArray:
        """Points (K_i, 2) of cluster ``i``."""
        return self.points[self.offsets[i] : self.offsets[i + 1]]

    def cluster_members(self, i: int) -> IntArray:
        """Frame point indices (K_i,) of cluster ``i``."""
        return self.members[self.offsets[i] : self.offsets[i + 1]]

    @cached_property
    def radii(self) -> FloatArray:
        """Largest distance (M,) [m] of a cluster's points from its centroid."""
        m = len(self)
        if m == 0:
            return np.empty(0)
        owner = np.repeat(np.arange(m), self.sizes)
        dist = np.hypot(*(self.points - self.centroids[owner]).T)
        out = np.zeros(m)
        np.maximum.at(out, owner, dist)
        return out

    @property
    def sizes(self) -> IntArray:
        """Points per cluster (M,)."""
        return np.diff(self.offsets)

    @classmethod
    def empty(cls) -> GroupObservations:
        """No observations."""
        return cls(
            np.empty((0, 2)),
            np.zeros(1, dtype=np.int64),
            np.empty(0, dtype=np.int64),
            np.empty((0, 2)),
            np.empty(0),
            np.empty(0),
        )

    @classmethod
    def from_points(
        cls, points: FloatArray, members: IntArray, d_p: float, d_hs: float
    ) -> GroupObservations:
        """Cluster ``points`` (N, 2) [m] with single linkage at ``d_p`` [m] and count the
        blobs at ``d_hs`` [m]; ``members`` (N,) are their indices in the frame."""
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        idx = np.asarray(members, dtype=np.int64).reshape(-1)
        if pts.shape[0] == 0:
            return cls.empty()
        labels = single_linkage(pts, d_p)
        fine = single_linkage(pts, d_hs) if d_hs < d_p else labels
        return cls._from_labels(pts, idx, labels, fine)

    @classmethod
    def from_parts(
        cls,
        parts: Sequence[tuple[FloatArray, IntArray]],
        d_hs: float,
        share: Sequence[float] | None = None,
        source: Sequence[IntArray] | None = None,
    ) -> GroupObservations:
        """Observations made of given point sets ``(points (K, 2), members (K,))`` (e.g. the
        parts of a re-clustered observation, Sec. 4.3, with their ``share`` of it); blobs
        counted at ``d_hs``; ``source`` gives each part's rows in the scan's set."""
        if not parts:
            return cls.empty()
        pts = np.concatenate([p for p, _ in parts]).reshape(-1, 2)
        idx = np.concatenate([m for _, m in parts]).astype(np.int64)
        labels = np.repeat(np.arange(len(parts), dtype=np.int64), [len(m) for _, m in parts])
        fine_parts: list[IntArray] = []
        base = 0
        for p, m in parts:  # blob labels, unique over the parts
            fine_parts.append(single_linkage(p, d_hs) + base)
            base += len(m)
        fine = np.concatenate(fine_parts)
        out = cls._from_labels(pts, idx, labels, fine)  # keeps the order of the parts
        if share is not None:
            out = replace(out, share=np.asarray(share, dtype=np.float64).reshape(len(parts)))
        if source is not None:
            out = replace(out, source=np.concatenate(source).astype(np.int64))
        return out

    @classmethod
    def _from_labels(
        cls, pts: FloatArray, idx: IntArray, labels: IntArray, fine: IntArray
    ) -> GroupObservations:
        order = np.argsort(labels, kind="stable")
        pts, idx, labels, fine = pts[order], idx[order], labels[order], fine[order]
        m = int(labels.max()) + 1
        counts = np.bincount(labels, minlength=m)
        offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        centroids = (
            np.column_stack([np.bincount(labels, pts[:, 0], m), np.bincount(labels, pts[:, 1], m)])
            / np.maximum(counts, 1)[:, None]
        )
        # blobs per cluster: distinct (cluster, fine label) pairs
        pairs = np.unique(labels * (int(fine.max()) + 1) + fine)
        n_hs = np.bincount(pairs // (int(fine.max()) + 1), minlength=m).astype(np.float64)
        return cls(pts, offsets, idx, centroids, n_hs, np.ones(m))
