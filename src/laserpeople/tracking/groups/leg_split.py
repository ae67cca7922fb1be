"""Points split between tracked walkers (extension of 000 Sec. 4.1; docs/groups.md
"Walkers", "Third round").

The walkers of :mod:`.walkers` are unions of whole blobs at d_hs = 0.3 m, so a blob that
holds legs of two people who pass within 0.3 m of each other is one walker with one
velocity, and its d_P links weld the two people's groups for that scan, whatever the
velocities (the ceiling study of docs/groups.md: blobs at 0.3 m given the true velocity of
their main person reach 0.184 against 0.097 for the true partition into people, seed 0,
30 s).

Here the tracked walkers take the points instead. Every scan:

1. **Atoms**: the points are cut into small segments by single linkage at
   ``segment_distance`` (about one leg, or part of one).
2. **Claims**: every walker's points of its last scan are moved by its velocity to now;
   each point votes for the walker of its nearest moved point within ``point_gate``, and
   each segment goes to the walker most of its points vote for (:func:`claim_segments`).
   A segment no point of which is that close goes to the nearest predicted walker centre
   within ``centre_gate``. So two people whose legs touch keep their own legs: the
   segments follow the walkers, not the blobs.
3. **Release**: a walker keeps one person of what it took - its blobs at
   ``release_distance``, two leg-sized ones that are each other's nearest within
   ``pair_distance`` counted as one person - the one nearest its prediction; the rest is
   unclaimed (:func:`release_extras`: a walker born from a blob that held two people would
   keep both).
4. **New walkers**: the segments no walker claims are grouped as in :mod:`.walkers`
   (blobs at d_hs, two leg blobs that are each other's nearest within ``pair_distance``
   are one walker) and start walkers.
5. **Measurement**: a walker's place is the mean of the centres of its own blobs at d_hs
   (its points only: two legs, or one blob), with the std ``lone_std`` when it is one
   leg-sized blob (the other leg hidden: off by up to half a stride).

The links between the points of two walkers are then cut by the rule of :mod:`.walkers`
(:func:`~.walkers.moving_apart`), or when their velocities differ by more than
``max_velocity_difference``, for ``apart_scans`` scans in a row, now also inside a blob at
d_hs. On the held-out simulated hall this gives 0.214 against 0.220 for the walkers of
:mod:`.walkers`, but it loses on every real recording (one person's legs taken by two
walkers), so it is off by default (docs/groups.md "Third round").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from laserpeople.tracking import kalman
from laserpeople.tracking.groups.observations import blob_shapes, component_labels, leg_pairs
from laserpeople.tracking.groups.walkers import WalkerSettings, moving_apart, walker_detections

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]


@dataclass(frozen=True)
class SplitSettings:
    """How the points are split between the walkers.

    Attributes:
        segment_distance: Single-linkage distance of the atoms the walkers take [m].
        point_gate: A point votes for the walker of its nearest moved last-scan point
            if that is closer than this [m].
        centre_gate: A segment no point of which votes goes to the nearest predicted
            walker centre closer than this [m].
        lone_std: Position noise of a walker seen as one leg-sized blob [m].
        release_distance: Single-linkage distance of the blobs a walker's points are
            counted in as people when it keeps one person (0: no release) [m].
        max_velocity_difference: Cut the links of two walkers whose velocities differ by
            more than this (0: :func:`~.walkers.moving_apart`) [m/s].
    """

    segment_distance: float = 0.1
    point_gate: float = 0.25
    centre_gate: float = 0.5
    lone_std: float = 0.6
    release_distance: float = 0.15
    max_velocity_difference: float = 0.0

    def __post_init__(self) -> None:
        if min(self.segment_distance, self.point_gate, self.centre_gate, self.lone_std) <= 0:
            raise ValueError(
                "walker split segment_distance, point_gate, centre_gate and lone_std must be "
                "positive"
            )
        if self.release_distance < 0.0 or self.max_velocity_difference < 0.0:
            raise ValueError(
                "walker split release_distance and max_velocity_difference must not be negative"
            )


def claim_segments(
    points: FloatArray,
    segments: IntArray,
    previous: FloatArray,
    previous_owner: IntArray,
    centres: FloatArray,
    point_gate: float,
    centre_gate: float,
) -> IntArray:
    """The walker (S,) of each of the S segments (labels ``segments`` (N,) 0..S-1 of the
    ``points`` (N, 2) [m]), -1 for none: each point votes for ``previous_owner`` (M,) of its
    nearest ``previous`` point (M, 2) [m] (the walkers' last points, moved to now) within
    ``point_gate`` [m]; a segment goes to the walker with most votes (ties: the lower
    walker); a segment without votes goes to the nearest of the walker ``centres`` (T, 2)
    [m] within ``centre_gate`` [m]."""
    n_seg = int(segments.max()) + 1 if segments.size else 0
    owner = np.full(n_seg, -1, dtype=np.int64)
    n_walkers = centres.shape[0]
    if n_seg == 0 or n_walkers == 0:
        return owner
    if previous.shape[0]:
        dist, nearest = cKDTree(previous).query(points, distance_upper_bound=point_gate)
        voted = np.isfinite(dist)
        if voted.any():
            votes = np.bincount(
                segments[voted] * n_walkers + previous_owner[nearest[voted]],
                minlength=n_seg * n_walkers,
            ).reshape(n_seg, n_walkers)
            has = votes.max(axis=1) > 0
            owner[has] = np.argmax(votes[has], axis=1)
    rest = np.nonzero(owner < 0)[0]
    if rest.size:
        centre, _ = blob_shapes(points, segments, n_seg)
        d = np.hypot(
            centre[rest, None, 0] - centres[None, :, 0], centre[rest, None, 1] - centres[None, :, 1]
        )
        best = np.argmin(d, axis=1)
        near = d[np.arange(rest.size), best] < centre_gate
        owner[rest[near]] = best[near]
    return owner


def release_extras(
    points: FloatArray,
    owner: IntArray,
    blob_links: IntArray,
    centres: FloatArray,
    pair_distance: float,
    leg_radius: float,
) -> IntArray:
    """``owner`` (N,) with the points a walker cannot hold set to -1: a walker's own points
    (``owner`` the walker row, -1 none) linked by ``blob_links`` (E, 2) (pairs closer than
    d_hs) make its blobs; two leg-sized blobs (radius at most ``leg_radius`` [m]) that are
    each other's nearest within ``pair_distance`` [m] are one person, any other blob is
    one; a walker keeps the person nearest its predicted centre (``centres`` (T, 2) [m])
    and releases the others' points (a walker that took two people, e.g. born from one
    blob that held both)."""
    out = owner.copy()
    mine = np.nonzero(owner >= 0)[0]
    if mine.size == 0:
        return out
    index = np.full(owner.size, -1, dtype=np.int64)
    index[mine] = np.arange(mine.size)
    same = (owner[blob_links[:, 0]] == owner[blob_links[:, 1]]) & (owner[blob_links[:, 0]] >= 0)
    blob = component_labels(mine.size, index[blob_links[same]])
    n_blobs = int(blob.max()) + 1
    walker_of_blob = np.zeros(n_blobs, dtype=np.int64)
    walker_of_blob[blob] = owner[mine]
    if np.bincount(walker_of_blob).max() < 2:
        return out
    centre, radius = blob_shapes(points[mine], blob, n_blobs)
    leg, partner = leg_pairs(centre, radius, leg_radius, pair_distance, walker_of_blob)
    person = np.arange(n_blobs)
    paired = partner >= 0
    person[leg[paired]] = np.minimum(leg[paired], partner[paired])
    n_person = n_blobs
    place = (
        np.column_stack(
            [
                np.bincount(person, centre[:, 0], n_person),
                np.bincount(person, centre[:, 1], n_person),
            ]
        )
        / np.maximum(np.bincount(person, minlength=n_person), 1)[:, None]
    )
    walker_of_person = np.full(n_person, -1, dtype=np.int64)
    walker_of_person[person] = walker_of_blob
    used = np.nonzero(walker_of_person >= 0)[0]
    w = walker_of_person[used]
    d = np.hypot(*(place[used] - centres[w]).T)
    order = np.lexsort((d, w))
    first = np.ones(order.size, dtype=bool)
    first[1:] = w[order][1:] != w[order][:-1]
    kept = np.zeros(n_person, dtype=bool)
    kept[used[order[first]]] = True
    out[mine[~kept[person[blob]]]] = -1
    return out


def walker_places(
    points: FloatArray, owner: IntArray, blob_links: IntArray, n_walkers: int, leg_radius: float
) -> tuple[FloatArray, BoolArray, BoolArray]:
    """Place of each of ``n_walkers`` walkers from its points: ``owner`` (N,) the walker of
    every point of ``points`` (N, 2) [m], ``blob_links`` (E, 2) the point pairs closer than
    d_hs. A walker's blobs are its own points linked by them; its place (W, 2) [m] is the
    mean of its blobs' centres. Returns the places, whether each walker has points (W,) and
    whether it is one leg-sized blob (W,) (radius at most ``leg_radius`` [m])."""
    places = np.zeros((n_walkers, 2))
    seen = np.zeros(n_walkers, dtype=bool)
    lone = np.zeros(n_walkers, dtype=bool)
    if points.shape[0] == 0:
        return places, seen, lone
    same = owner[blob_links[:, 0]] == owner[blob_links[:, 1]]
    blob = component_labels(points.shape[0], blob_links[same])
    n_blobs = int(blob.max()) + 1
    centre, radius = blob_shapes(points, blob, n_blobs)
    walker_of_blob = np.zeros(n_blobs, dtype=np.int64)
    walker_of_blob[blob] = owner
    blobs_per = np.bincount(walker_of_blob, minlength=n_walkers)
    seen = blobs_per > 0
    sums = np.column_stack(
        [
            np.bincount(walker_of_blob, centre[:, 0], n_walkers),
            np.bincount(walker_of_blob, centre[:, 1], n_walkers),
        ]
    )
    places[seen] = sums[seen] / blobs_per[seen, None]
    small = np.bincount(walker_of_blob, radius <= leg_radius, n_walkers) > 0
    lone = (blobs_per == 1) & small
    return places, seen, lone


class SplitWalkerTracker:
    """Walkers that take the points of the scan (see the module doc).

    Attributes:
        means: (T, 4) state (x, y, vx, vy) [m, m/s] of every walker.
        covs: (T, 4, 4) covariances.
        hits: (T,) scans in which every walker had points.
        seen: (T,) time [s] every walker last had points.
        ids: (T,) id of every walker.
        last_owner: The walker id of every point of the last scan (for diagnostics).
    """

    def __init__(self, settings: WalkerSettings, split: SplitSettings | None = None) -> None:
        self.settings = settings
        self.split = split if split is not None else SplitSettings()
        self.means = np.empty((0, 4))
        self.covs = np.empty((0, 4, 4))
        self.hits = np.empty(0, dtype=np.int64)
        self.seen = np.empty(0)
        self.ids = np.empty(0, dtype=np.int64)
        self.stamp: float | None = None
        self._next_id = 0
        self._points = np.empty((0, 2))  # every walker's last points
        self._owner = np.empty(0, dtype=np.int64)  # their walker (row)
        self._at = np.empty(0)  # their time [s]
        self._apart_for: dict[tuple[int, int], int] = {}
        self.last_owner = np.empty(0, dtype=np.int64)

    def __len__(self) -> int:
        return int(self.hits.size)

    def assign(
        self, points: FloatArray, links: IntArray, length: FloatArray, d_hs: float, stamp: float
    ) -> IntArray:
        """Track the walkers over one scan: ``points`` (N, 2) [m], ``links`` (E, 2) the point
        pairs closer than d_P with their ``length`` (E,) [m]; returns the walker row (N,) of
        every point (every point has one: unclaimed points start walkers)."""
        s, sp = self.settings, self.split
        dt = 0.0 if self.stamp is None else max(0.0, stamp - self.stamp)
        self.stamp = stamp
        if len(self) and dt > 0.0:
            self.means, self.covs = kalman.predict(
                self.means, self.covs, np.full(len(self), dt), s.accel_psd
            )
        self._drop_lost(stamp)
        n = points.shape[0]
        segments = component_labels(n, links[length < sp.segment_distance])
        moved = self._points + self.means[self._owner, 2:4] * (stamp - self._at)[:, None]
        owner_of_segment = claim_segments(
            points,
            segments,
            moved,
            self._owner,
            self.means[:, :2],
            sp.point_gate,
            sp.centre_gate,
        )
        owner = owner_of_segment[segments] if n else np.empty(0, dtype=np.int64)
        blob_links = links[length < d_hs]
        if sp.release_distance > 0.0:
            owner = release_extras(
                points,
                owner,
                links[length < sp.release_distance],
                self.means[:, :2],
                s.pair_distance,
                s.leg_radius,
            )
        free = np.nonzero(owner < 0)[0]
        if free.size:
            inside = (owner[blob_links[:, 0]] < 0) & (owner[blob_links[:, 1]] < 0)
            index = np.full(n, -1, dtype=np.int64)
            index[free] = np.arange(free.size)
            free_blobs = component_labels(free.size, index[blob_links[inside]])
            _, walker = walker_detections(points[free], free_blobs, s.pair_distance, s.leg_radius)
            owner[free] = len(self) + walker[free_blobs]
            self._start(int(walker.max()) + 1, stamp)
        places, has, lone = walker_places(points, owner, blob_links, len(self), s.leg_radius)
        rows = np.nonzero(has)[0]
        fresh = rows[self.hits[rows] == 0]
        old = rows[self.hits[rows] > 0]
        std = np.where(lone, sp.lone_std, s.measurement_std)
        if old.size:
            r = np.eye(2)[None, :, :] * (std[old] ** 2)[:, None, None]
            self.means[old], self.covs[old] = kalman.update_batch(
                self.means[old], self.covs[old], places[old], r
            )
        if fresh.size:
            r = np.eye(2)[None, :, :] * (std[fresh] ** 2)[:, None, None]
            self.means[fresh], self.covs[fresh] = kalman.initiate_batch(
                places[fresh], r, s.init_velocity_std
            )
        self.hits[rows] += 1
        self.seen[rows] = stamp
        # the walkers' points for the next scan: this scan's, else their last ones
        kept = ~has[self._owner]
        self._points = np.concatenate([self._points[kept], points])
        self._owner = np.concatenate([self._owner[kept], owner])
        self._at = np.concatenate([self._at[kept], np.full(n, stamp)])
        self.last_owner = self.ids[owner]
        return owner

    def _start(self, count: int, stamp: float) -> None:
        """Append ``count`` walkers without a state yet (set at their first place)."""
        self.means = np.concatenate([self.means, np.zeros((count, 4))])
        self.covs = np.concatenate([self.covs, np.zeros((count, 4, 4))])
        self.hits = np.concatenate([self.hits, np.zeros(count, dtype=np.int64)])
        self.seen = np.concatenate([self.seen, np.full(count, stamp)])
        fresh = np.arange(self._next_id, self._next_id + count, dtype=np.int64)
        self.ids = np.concatenate([self.ids, fresh])
        self._next_id += count

    def _drop_lost(self, stamp: float) -> None:
        alive = stamp - self.seen <= self.settings.max_unseen
        if alive.all():
            return
        row = np.cumsum(alive) - 1
        self.means, self.covs = self.means[alive], self.covs[alive]
        self.hits, self.seen, self.ids = self.hits[alive], self.seen[alive], self.ids[alive]
        keep = alive[self._owner]
        self._points, self._at = self._points[keep], self._at[keep]
        self._owner = row[self._owner[keep]]

    def coherent_links(
        self,
        points: FloatArray,
        blobs: IntArray,
        links: IntArray,
        stamp: float,
        d_hs: float | None = None,
    ) -> BoolArray:
        """Split the ``points`` (N, 2) [m] of a scan between the walkers and tell which
        point ``links`` (E, 2) join walkers that move alike (E,); the walkers' blobs are
        their own points at ``d_hs`` [m] (0.3 m when None; ``blobs``, the scan's blobs, are
        not used)."""
        del blobs
        d_hs = 0.3 if d_hs is None else d_hs
        s, sp = self.settings, self.split
        length = (
            np.hypot(*(points[links[:, 0]] - points[links[:, 1]]).T)
            if len(links)
            else (np.empty(0))
        )
        owner = self.assign(points, links, length, d_hs, stamp)
        if len(links) == 0:
            self._apart_for = {}
            return np.ones(0, dtype=bool)
        wa, wb = owner[links[:, 0]], owner[links[:, 1]]
        known = self.hits >= s.min_scans
        velocity = self.means[:, 2:4]
        apart = (wa != wb) & known[wa] & known[wb]
        if sp.max_velocity_difference > 0.0:
            dv = velocity[wa] - velocity[wb]
            apart &= np.einsum("ij,ij->i", dv, dv) > sp.max_velocity_difference**2
        else:
            apart &= moving_apart(velocity[wa], velocity[wb], s.standing_speed, s.walking_speed)
        # a pair of walkers is cut once it has moved apart for apart_scans scans in a row
        # (apart is the same for every link of a pair: only those links are looked at)
        keep = np.ones(len(links), dtype=bool)
        streaks: dict[tuple[int, int], int] = {}
        on = np.nonzero(apart)[0]
        if on.size:
            a_id, b_id = self.ids[wa[on]], self.ids[wb[on]]
            span = int(self.ids.max()) + 1
            key = np.minimum(a_id, b_id) * span + np.maximum(a_id, b_id)
            pair_keys, link_pair = np.unique(key, return_inverse=True)
            cut = np.zeros(pair_keys.size, dtype=bool)
            for k, code in enumerate(pair_keys.tolist()):
                pair = (code // span, code % span)
                streaks[pair] = self._apart_for.get(pair, 0) + 1
                cut[k] = streaks[pair] >= s.apart_scans
            keep[on] = ~cut[link_pair.reshape(-1)]
        self._apart_for = streaks
        return keep
