"""Observations of the group tracker (000 Sec. 4.1): clusters of foreground points.

The foreground points of one scan are grouped by single linkage with the distance d_P; each
cluster Z_i is one observation. Its size observation n_hs(Z_i) counts the people in it:

* ``"blobs"`` (000 Sec. 4.1, Fig. 12): the number of human-sized clusters found by
  re-clustering its points with d_hs < d_P;
* ``"legs"``: the same blobs, then two blobs that are each other's nearest blob
  in the cluster, closer than a stride (``pair_distance``) and both leg-sized (radius at
  most ``leg_radius``) are one person's two legs. At 30 cm a walker's legs are up to 0.76 m
  apart (99th percentile in the simulator), so d_hs = 0.3 m counts a walker as two people
  whenever the gap between the legs exceeds 0.3 m.
* ``"resolved"``: what the laser resolves at that range. As ``"legs"``, but a blob wider
  than a leg is not always one person: its points cover an arc of their beam spacings
  (range x angular step, so each point weighs what one beam covers at its range: the
  expected beams per leg there are ``leg_width`` / spacing), it holds
  ``L = round(arc / leg_width)`` legs (at least one) and stands for ``floor(L / 2 + 1/2)``
  people (two legs side by side or a torso: one; the legs of two people run together:
  two). A blob wider than a person (``2 x radius`` above ``person_width``) holds at least
  ``ceil(2 radius / person_width)`` people, whatever its arc (the people behind the
  nearest show slivers). A leg-sized blob whose arc covers ``pair_arc`` or more holds both
  legs of a person (far away or at low resolution two legs side by side give a blob of a
  leg's radius) and is not paired. The one-leg blobs are paired by a maximum matching (the
  most pairs closer than ``pair_distance``, each blob in one pair at most): the fewest
  people whose two legs lie within a stride, where mutual nearest neighbours miss the
  pairs of people walking in file with strides as long as their spacing. A wide blob that
  its arc counts as two people (three legs) but no wider than a person, whose points (in
  scan order) are nowhere more than ``surface_gap`` apart, is one continuous surface: one
  person (a torso at 1 m; the legs of two people leave a gap between them).

The stride is ambiguous: a walker's legs may be 0.7 m apart and two neighbours' legs 0.55
m. With a ``stride_range`` (near, far) the count is also made with the pairs closer than
``near`` only (the most people the scan may show, ``n_high``) and with those closer than
``far`` (the fewest, ``n_low``); the tracker reads the size a group's track predicts
within that range (:func:`size_reading`; the low end only for walking groups), so a count
that flickers between two readings of one scan keeps the group's size.

With ``torso`` (a laser at torso height, as the recording states it) no two blobs are
paired: each is a body, not a leg, and two neighbours' torsos closer than a stride are two
people.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering import single_linkage
from laserpeople.clustering.single_linkage import components

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


def within_size(points: FloatArray, blobs: IntArray, max_size: float) -> NDArray[np.bool_]:
    """Mask (N,) of the ``points`` (N, 2) [m] whose blob spans at most ``max_size`` [m]
    (the diagonal of its bounding box); ``blobs`` (N,) labels them 0..B-1, every label
    used (as :func:`component_labels` numbers them)."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if pts.shape[0] == 0:
        return np.ones(0, dtype=bool)
    labels = np.asarray(blobs, dtype=np.int64)
    counts = np.bincount(labels)
    starts = np.cumsum(counts) - counts
    ordered = pts[np.argsort(labels, kind="stable")]
    extent = np.maximum.reduceat(ordered, starts) - np.minimum.reduceat(ordered, starts)
    wide = np.einsum("bk,bk->b", extent, extent) > max_size * max_size
    return ~wide[labels]


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
        blobs: (P,) blob (d_hs) of each point, labels unique over the set.
        spacing: (P,) beam spacing at each point's range [m] (range x angular step), for
            ``"resolved"`` counting; None when not known.
        n_range: (M, 2) the fewest and the most people each cluster may hold as its
            blobs are paired with strides of ``SizeCounting.stride_range`` (``n_hs`` lies
            within); None when no range is counted.
    """

    points: FloatArray
    offsets: IntArray
    members: IntArray
    centroids: FloatArray
    n_hs: FloatArray
    share: FloatArray
    source: IntArray | None = None
    blobs: IntArray | None = None
    spacing: FloatArray | None = None
    n_range: FloatArray | None = None

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
        owner = self.point_cluster
        dist = np.hypot(*(self.points - self.centroids[owner]).T)
        out = np.zeros(m)
        np.maximum.at(out, owner, dist)
        return out

    @cached_property
    def point_cluster(self) -> IntArray:
        """Cluster (P,) of each point (one array, read only by convention)."""
        return np.repeat(np.arange(len(self)), self.sizes)

    @cached_property
    def sizes(self) -> IntArray:
        """Points per cluster (M,) (one array, read only by convention)."""
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
        cls,
        points: FloatArray,
        members: IntArray,
        d_p: float,
        d_hs: float,
        counting: SizeCounting | None = None,
        max_blob_size: float = 0.0,
        spacing: FloatArray | None = None,
    ) -> GroupObservations:
        """Cluster ``points`` (N, 2) [m] with single linkage at ``d_p`` [m] and count the
        people in each cluster from its blobs at ``d_hs`` [m] (``counting``, paper's blob
        count when None); ``members`` (N,) are their indices in the frame and ``spacing``
        (N,) the beam spacing at each point's range [m] (``"resolved"`` counting). With
        ``max_blob_size`` > 0 [m] the points of blobs wider than it are left out (the
        clusters are then made again from the rest; the blobs are those of one linkage)."""
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        idx = np.asarray(members, dtype=np.int64).reshape(-1)
        gap = None if spacing is None else np.asarray(spacing, dtype=np.float64).reshape(-1)
        finite = np.isfinite(pts).all(axis=1)
        if not finite.all():
            pts, idx = pts[finite], idx[finite]
            gap = None if gap is None else gap[finite]
        d_blob = min(d_hs, d_p)
        pairs, length = close_pairs(pts, max(d_p, d_blob))
        fine = component_labels(pts.shape[0], pairs[length < d_blob])
        if max_blob_size > 0.0 and pts.shape[0]:
            keep = within_size(pts, fine, max_blob_size)
            if not keep.all():
                # the pairs among the points kept are theirs: no second search
                new_index = np.cumsum(keep) - 1
                inside = keep[pairs[:, 0]] & keep[pairs[:, 1]]
                pairs, length = new_index[pairs[inside]], length[inside]
                pts, idx = pts[keep], idx[keep]
                gap = None if gap is None else gap[keep]
                fine = component_labels(pts.shape[0], pairs[length < d_blob])
        links = pairs[length < d_p]
        if pts.shape[0] == 0:
            return cls.empty()
        labels = component_labels(pts.shape[0], links)
        return cls._from_labels(pts, idx, labels, fine, counting, spacing=gap)

    @classmethod
    def from_parts(
        cls,
        parts: Sequence[tuple[FloatArray, IntArray]],
        d_hs: float,
        share: Sequence[float] | None = None,
        source: Sequence[IntArray] | None = None,
        counting: SizeCounting | None = None,
        blobs: IntArray | None = None,
        spacing: FloatArray | None = None,
    ) -> GroupObservations:
        """Observations made of given point sets ``(points (K, 2), members (K,))`` (e.g. the
        parts of a re-clustered observation, Sec. 4.3, with their ``share`` of it); blobs
        found at ``d_hs``, or given as ``blobs`` (the blob label of every point of the
        concatenated parts, e.g. the scan's, so no part is clustered again); ``source``
        gives each part's rows in the scan's set; ``spacing`` the beam spacing [m] of
        every point of the concatenated parts."""
        if not parts:
            return cls.empty()
        pts = np.concatenate([p for p, _ in parts]).reshape(-1, 2)
        idx = np.concatenate([m for _, m in parts]).astype(np.int64)
        sizes = [len(m) for _, m in parts]
        labels = np.repeat(np.arange(len(parts), dtype=np.int64), sizes)
        if blobs is not None:
            # a blob cut by a part boundary counts once on each side
            span = int(np.max(blobs)) + 1
            fine = labels * span + np.asarray(blobs, dtype=np.int64)
        else:
            fine_parts: list[IntArray] = []
            base = 0
            for p, m in parts:  # blob labels, unique over the parts
                fine_parts.append(single_linkage(p, d_hs) + base)
                base += len(m)
            fine = np.concatenate(fine_parts)
        out = cls._from_labels(pts, idx, labels, fine, counting, ordered=True, spacing=spacing)
        changes: dict[str, IntArray | FloatArray] = {}
        if share is not None:
            changes["share"] = np.asarray(share, dtype=np.float64).reshape(len(parts))
        if source is not None:
            changes["source"] = np.concatenate(source).astype(np.int64)
        return replace(out, **changes) if changes else out  # type: ignore[arg-type]

    @classmethod
    def _from_labels(
        cls,
        pts: FloatArray,
        idx: IntArray,
        labels: IntArray,
        fine: IntArray,
        counting: SizeCounting | None = None,
        ordered: bool = False,
        spacing: FloatArray | None = None,
    ) -> GroupObservations:
        """The observations of points ``pts`` (N, 2) with frame indices ``idx`` (N,),
        cluster labels ``labels`` (N,) 0..M-1, blob labels ``fine`` (N,) and beam spacings
        ``spacing`` (N,) [m] or None; the points are put cluster after cluster (in their
        order within each), which they are already when ``ordered`` (labels
        non-decreasing: the sort is skipped)."""
        if not ordered:
            order = np.argsort(labels, kind="stable")
            pts, idx, labels, fine = pts[order], idx[order], labels[order], fine[order]
            spacing = None if spacing is None else spacing[order]
        m = int(labels.max()) + 1
        counts = np.bincount(labels, minlength=m)
        offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        centroids = (
            np.column_stack([np.bincount(labels, pts[:, 0], m), np.bincount(labels, pts[:, 1], m)])
            / np.maximum(counts, 1)[:, None]
        )
        n_hs, n_range = count_people(pts, labels, fine, m, counting, spacing)
        return cls(
            pts, offsets, idx, centroids, n_hs, np.ones(m),
            blobs=fine, spacing=spacing, n_range=n_range,
        )  # fmt: skip


def close_pairs(points: FloatArray, distance: float) -> tuple[IntArray, FloatArray]:
    """Pairs (E, 2) of finite ``points`` (N, 2) [m] closer than ``distance`` [m] (one
    KD-tree query) and their lengths (E,) [m]."""
    from scipy.spatial import cKDTree

    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if not distance > 0:
        raise ValueError(f"single-linkage distances must be positive, got {distance}")
    if pts.shape[0] == 0:
        return np.empty((0, 2), dtype=np.int64), np.empty(0)
    pairs = cKDTree(pts).query_pairs(distance, output_type="ndarray").astype(np.int64)
    a, b = pairs[:, 0], pairs[:, 1]
    x, y = pts[:, 0], pts[:, 1]
    return pairs, np.hypot(x[a] - x[b], y[a] - y[b])  # gathers of one coordinate: faster


def component_labels(n: int, links: IntArray) -> IntArray:
    """Single-linkage labels (n,) of ``n`` points joined by ``links`` (E, 2), numbered by
    each cluster's first point (as :func:`laserpeople.clustering.single_linkage`)."""
    root = components(n, links)
    index = np.arange(n)
    rank = np.cumsum(root == index) - 1  # each component's smallest index is its root
    return rank[root].astype(np.int64)


@dataclass(frozen=True)
class SizeCounting:
    """How the people in a cluster are counted from its blobs (see the module doc).

    Attributes:
        method: "blobs" (000: one person per blob at d_hs) or "legs" (pairs of leg blobs
            are one person).
        pair_distance: Largest distance between the centres of one person's two leg
            blobs [m].
        leg_radius: Largest radius of a blob that can be one leg [m] (wider blobs are a
            person or more already and are not paired).
        leg_width: Arc a leg covers [m] ("resolved").
        person_width: Widest a person is at the laser's height [m] ("resolved": a blob
            twice whose radius is wider holds ``ceil(2 radius / person_width)`` people at
            least; 0: not used).
        pair_arc: Arc from which a leg-sized blob holds two legs and is not paired [m]
            ("resolved"; 0: every leg-sized blob may be paired).
        surface_gap: Largest gap between scan neighbours of a blob that is one
            continuous surface [m] ("resolved": such a blob of three legs' arc, no wider
            than ``person_width``, is one person; 0: not used).
        torso: The laser is at torso height: no two blobs are paired as one person's legs
            ("legs" and "resolved"; each blob is counted alone).
        stride_range: (near, far) [m]: the count's range pairs the legs closer than
            ``near`` (most people) and closer than ``far`` (fewest people); (0, 0): no
            range, the count alone.
    """

    method: str = "legs"
    pair_distance: float = 0.7
    leg_radius: float = 0.12
    leg_width: float = 0.18
    person_width: float = 0.0
    pair_arc: float = 0.0
    surface_gap: float = 0.0
    torso: bool = False
    stride_range: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        if self.method not in ("blobs", "legs", "resolved"):
            raise ValueError("size counting method must be 'blobs', 'legs' or 'resolved'")
        if min(self.pair_distance, self.leg_radius, self.leg_width) <= 0.0:
            raise ValueError("pair_distance, leg_radius and leg_width must be positive")
        if min(self.person_width, self.pair_arc, self.surface_gap) < 0.0:
            raise ValueError(
                "person_width, pair_arc and surface_gap must not be negative (0: not used)"
            )
        near, far = self.stride_range
        if self.ranged and not 0.0 < near <= self.pair_distance <= far < np.inf:
            raise ValueError(
                "stride_range must be (0, 0) or (near, far) with 0 < near <= pair_distance "
                "<= far, finite"
            )

    @property
    def ranged(self) -> bool:
        """Whether a range of counts is made (``stride_range`` not (0, 0))."""
        return self.stride_range != (0.0, 0.0) and self.method != "blobs"


def count_people(
    pts: FloatArray,
    labels: IntArray,
    fine: IntArray,
    m: int,
    counting: SizeCounting | None = None,
    spacing: FloatArray | None = None,
) -> tuple[FloatArray, FloatArray | None]:
    """People (M,) in each of ``m`` clusters, and (None without a range) the fewest and the
    most people (M, 2) each may hold: ``labels`` (N,) the cluster and ``fine`` (N,) the blob
    of each point ``pts`` (N, 2) [m] (blob labels unique over clusters).

    "blobs": the number of distinct blobs per cluster (000 Sec. 4.1). "legs": that number
    minus the pairs of leg-sized blobs of one cluster that are mutual nearest neighbours
    closer than ``pair_distance``. "resolved": as "legs", but a blob wider than a leg counts
    the people its arc and its width hold (:func:`resolved_people`; ``spacing`` (N,) the
    beam spacing at each point [m]), and the one-leg blobs narrower in arc than
    ``pair_arc`` are paired by a maximum matching (:func:`blob_people`). The range, when
    ``counting.ranged``: the counts with the one-leg blobs paired within
    ``stride_range[1]`` and within ``stride_range[0]`` [m] (the blobs are described once,
    only their pairing is made for each stride)."""
    if pts.shape[0] == 0:
        return np.zeros(m), None
    if fine.min() >= 0 and np.bincount(fine).all():  # labels 0..B-1: np.unique's inverse
        blob = fine
    else:
        _, blob = np.unique(fine, return_inverse=True)
    n_blobs = int(blob.max()) + 1
    blob_cluster = np.zeros(n_blobs, dtype=np.int64)
    blob_cluster[blob] = labels
    if counting is None or counting.method == "blobs":
        out: FloatArray = np.bincount(blob_cluster, minlength=m).astype(np.float64)
        return out, None
    strides = (counting.pair_distance, *(counting.stride_range if counting.ranged else ()))
    people, pairings = blob_pairings(pts, blob, blob_cluster, counting, spacing, strides)
    alone = np.bincount(blob_cluster, people, m).astype(np.float64)
    counts = []
    for pairs in pairings:
        n = alone.copy()
        # a pair of one person's two leg blobs counts one person, not two
        np.subtract.at(n, blob_cluster[pairs[:, 0]], 1.0)
        counts.append(n)
    if len(counts) == 1:
        return counts[0], None
    n_hs, high, low = counts  # paired within pair_distance, the near and the far stride
    return n_hs, np.column_stack([low, high])


def size_reading(
    predicted: FloatArray,
    n_hs: FloatArray,
    n_range: FloatArray | None,
    fresh: NDArray[np.bool_],
    stride_speed: float,
) -> FloatArray:
    """The size observation (T,) [people] the Kalman update reads for tracks with the
    ``predicted`` states (T, 5) (x, y, vx, vy, n): the predicted size within the range
    (T, 2) of counts of its cluster (the nearer end when outside), where the range's low
    end is the count ``n_hs`` (T,) for a track predicted slower than ``stride_speed``
    [m/s] (only walkers take strides beyond ``pair_distance``); the count itself for the
    ``fresh`` (T,) tracks (made by a split or merge this scan: their size n/2 or a sum was
    never seen) and for every track without a range."""
    if n_range is None:
        return n_hs
    walking = np.hypot(predicted[:, 2], predicted[:, 3]) >= stride_speed
    low = np.where(walking, n_range[:, 0], n_hs)
    return np.where(fresh, n_hs, np.clip(predicted[:, 4], low, n_range[:, 1]))


def blob_people(
    pts: FloatArray,
    blob: IntArray,
    blob_cluster: IntArray,
    counting: SizeCounting,
    spacing: FloatArray | None = None,
) -> tuple[FloatArray, IntArray]:
    """What "legs" and "resolved" counting see in the blobs: the people (B,) each blob
    stands for alone and the pairs (K, 2) of blobs that are one person's two legs (each
    pair counts one person less). ``blob`` (N,) is the label 0..B-1 of each point ``pts``
    (N, 2) [m], every label used, ``blob_cluster`` (B,) the cluster of each blob and
    ``spacing`` (N,) the beam spacing at each point [m] or None. With ``counting.torso``
    there are no pairs."""
    people, (pairs,) = blob_pairings(
        pts, blob, blob_cluster, counting, spacing, (counting.pair_distance,)
    )
    return people, pairs


def blob_pairings(
    pts: FloatArray,
    blob: IntArray,
    blob_cluster: IntArray,
    counting: SizeCounting,
    spacing: FloatArray | None,
    strides: Sequence[float],
) -> tuple[FloatArray, list[IntArray]]:
    """:func:`blob_people` with the leg blobs paired within each of ``strides`` [m] in
    turn (``counting.pair_distance`` replaced): the people (B,) each blob stands for alone
    and one array of pairs (K, 2) per stride."""
    n_blobs = blob_cluster.size
    centre, radius = blob_shapes(pts, blob, n_blobs)
    people = np.ones(n_blobs)
    pairable = (radius <= counting.leg_radius) & (not counting.torso)
    if counting.method == "resolved":
        people = resolved_people(blob, radius, counting, spacing)
        if spacing is not None and counting.surface_gap > 0.0:
            surface = continuous_surfaces(pts, blob, radius, counting, spacing)
            people[surface] = 1.0
        if spacing is not None and counting.pair_arc > 0.0:
            arc = np.bincount(blob, np.asarray(spacing, dtype=np.float64), n_blobs)
            pairable &= arc < counting.pair_arc
        legs = np.nonzero(pairable)[0]
        return people, [
            legs[matched_legs(centre[legs], stride, blob_cluster[legs])] for stride in strides
        ]
    out = []
    for stride in strides:
        leg, partner = leg_pairs(
            centre, np.where(pairable, radius, np.inf), counting.leg_radius, stride,
            blob_cluster,
        )  # fmt: skip
        first = (partner >= 0) & (leg < partner)  # each mutual pair once
        out.append(np.column_stack([leg[first], partner[first]]).astype(np.int64))
    return people, out


def resolved_people(
    blob: IntArray, radius: FloatArray, counting: SizeCounting, spacing: FloatArray | None
) -> FloatArray:
    """People (B,) each blob stands for under ``"resolved"`` counting (module doc), before
    the pairs of one-leg blobs are taken off: ``blob`` (N,) the label 0..B-1 of each point,
    ``radius`` (B,) each blob's radius [m], ``spacing`` (N,) the beam spacing at each
    point [m] (None: unknown, every blob is one person, as ``"legs"``)."""
    n_blobs = radius.size
    people = np.ones(n_blobs)
    if spacing is None:
        return people
    arc = np.bincount(blob, np.asarray(spacing, dtype=np.float64), n_blobs)
    legs = np.maximum(1.0, np.round(arc / counting.leg_width))
    wide = radius > counting.leg_radius
    people[wide] = np.floor(legs[wide] / 2.0 + 0.5)
    if counting.person_width > 0.0:
        across = np.ceil(2.0 * radius[wide] / counting.person_width - 1e-9)
        people[wide] = np.maximum(people[wide], across)
    return people


def continuous_surfaces(
    pts: FloatArray,
    blob: IntArray,
    radius: FloatArray,
    counting: SizeCounting,
    spacing: FloatArray,
) -> NDArray[np.bool_]:
    """Mask (B,) of the blobs that are one continuous surface under ``"resolved"``
    counting: wider than a leg (``radius`` (B,) [m] above ``leg_radius``), no wider than
    ``person_width`` (twice the radius), of three legs' arc (``round(arc / leg_width)``
    = 3, the arc the sum of ``spacing`` (N,) [m]) and with no two consecutive points of
    the blob (``pts`` (N, 2) [m] in scan order, ``blob`` (N,) their labels 0..B-1) more
    than ``surface_gap`` [m] apart. A blob that wraps round the end of a scan shows a
    gap and is left as it is."""
    n_blobs = radius.size
    arc = np.bincount(blob, np.asarray(spacing, dtype=np.float64), n_blobs)
    gap = np.zeros(n_blobs)
    same = blob[1:] == blob[:-1]
    step = np.hypot(*np.diff(pts, axis=0).T)
    np.maximum.at(gap, blob[1:][same], step[same])
    starts = np.bincount(blob[np.r_[True, ~same]], minlength=n_blobs)
    contiguous = starts == 1
    legs = np.round(arc / counting.leg_width)
    return (
        (radius > counting.leg_radius)
        & (2.0 * radius <= counting.person_width)
        & (legs == 3.0)
        & contiguous
        & (gap <= counting.surface_gap)
    )


def blob_shapes(pts: FloatArray, blob: IntArray, n_blobs: int) -> tuple[FloatArray, FloatArray]:
    """Centre (B, 2) [m] and radius (B,) [m] (largest distance of a point from the centre)
    of each of ``n_blobs`` blobs, ``blob`` (N,) the label 0..B-1 of each point ``pts``
    (N, 2), every label used."""
    size = np.bincount(blob, minlength=n_blobs)
    centre = (
        np.column_stack(
            [np.bincount(blob, pts[:, 0], n_blobs), np.bincount(blob, pts[:, 1], n_blobs)]
        )
        / size[:, None]
    )
    radius = np.zeros(n_blobs)
    np.maximum.at(radius, blob, np.hypot(*(pts - centre[blob]).T))
    return centre, radius


def leg_pairs(
    centre: FloatArray,
    radius: FloatArray,
    leg_radius: float,
    pair_distance: float,
    cluster: IntArray | None = None,
) -> tuple[IntArray, IntArray]:
    """One person's two legs among blobs with ``centre`` (B, 2) and ``radius`` (B,) [m]:
    blobs of radius at most ``leg_radius`` that are each other's nearest such blob (within
    the same ``cluster`` (B,) label, any when None) and closer than ``pair_distance`` [m].
    Returns the leg-sized blobs (L,) and each one's partner blob (L,), -1 if unpaired."""
    leg = np.nonzero(radius <= leg_radius)[0]
    partner = np.full(leg.size, -1, dtype=np.int64)
    if leg.size < 2:
        return leg, partner
    c = centre[leg]
    dist = np.hypot(c[:, None, 0] - c[None, :, 0], c[:, None, 1] - c[None, :, 1])
    if cluster is not None:
        same = cluster[leg][:, None] == cluster[leg][None, :]
        dist = np.where(same, dist, np.inf)
    np.fill_diagonal(dist, np.inf)
    nearest = np.argmin(dist, axis=1)
    k = np.arange(leg.size)
    paired = (dist[k, nearest] < pair_distance) & (nearest[nearest] == k)
    partner[paired] = leg[nearest[paired]]
    return leg, partner


MATCHING_EXACT = 12
"""Largest set of linked one-leg blobs matched exactly (a search over the subsets); larger
sets (crowds standing within a stride of each other) are paired greedily, closest first."""


def matched_legs(centre: FloatArray, pair_distance: float, cluster: IntArray) -> IntArray:
    """Pairs (K, 2) of rows of ``centre`` (L, 2) [m], the one-leg blobs, that are one
    person's two legs: a maximum matching of the blobs of one ``cluster`` (L,) closer than
    ``pair_distance`` [m] (the most pairs, and of those the least summed distance), each
    blob in one pair at most. Sets of linked blobs larger than :data:`MATCHING_EXACT` are
    paired closest first."""
    n = centre.shape[0]
    none = np.empty((0, 2), dtype=np.int64)
    if n < 2:
        return none
    dist = np.hypot(
        centre[:, None, 0] - centre[None, :, 0], centre[:, None, 1] - centre[None, :, 1]
    )
    link = (dist < pair_distance) & (cluster[:, None] == cluster[None, :])
    np.fill_diagonal(link, False)
    a, b = np.nonzero(np.triu(link))
    if a.size == 0:
        return none
    part = component_labels(n, np.column_stack([a, b]).astype(np.int64))
    out: list[tuple[int, int]] = []
    for k in np.unique(part[a]):
        rows = np.flatnonzero(part == k)
        if rows.size == 2:
            out.append((int(rows[0]), int(rows[1])))
        elif rows.size <= MATCHING_EXACT:
            out += [
                (int(rows[i]), int(rows[j]))
                for i, j in _best_matching(dist[np.ix_(rows, rows)], link[np.ix_(rows, rows)])
            ]
        else:
            out += _closest_first(dist, link, rows)
    return np.asarray(out, dtype=np.int64).reshape(-1, 2)


def _best_matching(dist: FloatArray, link: NDArray[np.bool_]) -> list[tuple[int, int]]:
    """Maximum matching of the graph ``link`` (n, n) (the most pairs, then the least summed
    ``dist``), by a search over the unmatched vertices (n at most :data:`MATCHING_EXACT`)."""
    n = dist.shape[0]
    neighbours = [np.flatnonzero(link[v]).tolist() for v in range(n)]
    memo: dict[int, tuple[int, float, tuple[tuple[int, int], ...]]] = {}

    def best(done: int) -> tuple[int, float, tuple[tuple[int, int], ...]]:
        if done in memo:
            return memo[done]
        v = next((i for i in range(n) if not done >> i & 1), -1)
        if v < 0:
            return 0, 0.0, ()
        top = best(done | 1 << v)  # v in no pair
        for u in neighbours[v]:
            if not done >> u & 1:
                count, length, pairs = best(done | 1 << v | 1 << u)
                if (count + 1, -(length + dist[v, u])) > (top[0], -top[1]):
                    top = (count + 1, length + float(dist[v, u]), ((v, u), *pairs))
        memo[done] = top
        return top

    return list(best(0)[2])


def _closest_first(
    dist: FloatArray, link: NDArray[np.bool_], rows: IntArray
) -> list[tuple[int, int]]:
    """Pairs of ``rows`` linked in ``link``, closest first, each row in one pair at most."""
    sub = np.where(link[np.ix_(rows, rows)], dist[np.ix_(rows, rows)], np.inf)
    i, j = np.nonzero(np.triu(np.isfinite(sub)))
    taken = np.zeros(rows.size, dtype=bool)
    out: list[tuple[int, int]] = []
    for e in np.argsort(sub[i, j], kind="stable"):
        if not (taken[i[e]] or taken[j[e]]):
            taken[i[e]] = taken[j[e]] = True
            out.append((int(rows[i[e]]), int(rows[j[e]])))
    return out
