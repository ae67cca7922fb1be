"""Walker velocities for the group observations (extension of 000 Sec. 4.1).

000 links two foreground points into one observation whenever they are closer than d_P,
so a person passing a standing group, or two parties walking past each other, are one
observation for as long as they are within d_P, and the tracker can only keep them apart
through its models (000 Fig. 18). In a crowded hall that fails: a wrong merge wins within
a few scans and cannot be undone while the parties stay close (docs/groups.md, "Why the
tracker does not beat memory-less clustering"). People who walk together move together.

This module tracks the walkers of the scene - the human-sized blobs at d_hs, with the two
leg blobs of one person paired as in :func:`~.observations.count_people` - with a
constant-velocity Kalman filter each and one-to-one nearest-neighbour association, and
cuts the d_P links between the points of two walkers that move apart (:func:`moving_apart`:
one stands while the other walks past, or they head more than 90 degrees apart) for
``apart_scans`` scans in a row. A walker whose velocity is not known yet (younger than
``min_scans``) keeps all of its links, so new people are clustered as by 000.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.lazy_scipy import linear_sum_assignment
from laserpeople.tracking import kalman
from laserpeople.tracking.groups.observations import blob_shapes, leg_pairs

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]


@dataclass(frozen=True)
class WalkerSettings:
    """How walkers are tracked and when their links are cut.

    Attributes:
        on: Whether links are cut at all (False: 000's clustering).
        standing_speed: A walker slower than this stands [m/s].
        walking_speed: A walker faster than this walks [m/s] (see :func:`moving_apart`).
        gate: Largest distance from a walker's predicted place to a detection it takes [m].
        accel_psd: White-acceleration power spectral density of a walker [m^2/s^3].
        measurement_std: Position noise of a walker detection (the midpoint of its leg
            blobs, or one blob) [m].
        init_velocity_std: Velocity std of a new walker [m/s].
        min_scans: Detections a walker needs before its velocity is used.
        apart_scans: Scans in a row two linked walkers must move apart before their
            links are cut.
        max_unseen: A walker not seen for longer than this is dropped [s].
        pair_distance: Largest distance between one person's two leg blobs [m].
        leg_radius: Largest radius of a blob that can be one leg [m].
    """

    on: bool = False
    standing_speed: float = 0.3
    walking_speed: float = 0.8
    gate: float = 0.6
    accel_psd: float = 0.2
    measurement_std: float = 0.3
    init_velocity_std: float = 1.0
    min_scans: int = 10
    apart_scans: int = 3
    max_unseen: float = 0.5
    pair_distance: float = 0.7
    leg_radius: float = 0.12

    def __post_init__(self) -> None:
        if not 0.0 < self.standing_speed <= self.walking_speed:
            raise ValueError("walkers need 0 < standing_speed <= walking_speed")
        positive = (
            self.gate,
            self.accel_psd,
            self.measurement_std,
            self.init_velocity_std,
            self.pair_distance,
            self.leg_radius,
        )
        if min(positive) <= 0.0:
            raise ValueError(
                "walker gate, accel_psd, measurement_std, init_velocity_std, pair_distance "
                "and leg_radius must be positive"
            )
        if self.min_scans < 1 or self.apart_scans < 1 or self.max_unseen < 0.0:
            raise ValueError("walker min_scans and apart_scans must be >= 1, max_unseen >= 0")


def walker_detections(
    points: FloatArray, blobs: IntArray, pair_distance: float, leg_radius: float
) -> tuple[FloatArray, IntArray]:
    """Walker detections of one scan: ``points`` (N, 2) [m] with blob labels ``blobs``
    (N,) 0..B-1. Two leg-sized blobs (radius at most ``leg_radius``) that are each other's
    nearest leg blob and closer than ``pair_distance`` are one walker at their midpoint;
    every other blob is a walker at its centre. Returns the places (W, 2) and the walker
    (B,) of every blob."""
    n_blobs = int(blobs.max()) + 1 if blobs.size else 0
    if n_blobs == 0:
        return np.empty((0, 2)), np.empty(0, dtype=np.int64)
    centre, radius = blob_shapes(points, blobs, n_blobs)
    leg, partner = leg_pairs(centre, radius, leg_radius, pair_distance)
    walker = np.arange(n_blobs)
    paired = partner >= 0
    # the pair's walker is the smaller blob label of the two
    walker[leg[paired]] = np.minimum(leg[paired], partner[paired])
    used, walker = np.unique(walker, return_inverse=True)
    counts = np.bincount(walker, minlength=used.size)
    places = (
        np.column_stack(
            [
                np.bincount(walker, centre[:, 0], used.size),
                np.bincount(walker, centre[:, 1], used.size),
            ]
        )
        / counts[:, None]
    )
    return places, walker.astype(np.int64)


class WalkerTracker:
    """Walkers of the scene, tracked scan to scan (see the module doc).

    Attributes:
        means: (T, 4) state (x, y, vx, vy) [m, m/s] of every walker.
        covs: (T, 4, 4) covariances.
        hits: (T,) detections taken by every walker.
        seen: (T,) time [s] every walker was last detected.
    """

    def __init__(self, settings: WalkerSettings | None = None) -> None:
        self.settings = settings if settings is not None else WalkerSettings()
        self.means = np.empty((0, 4))
        self.covs = np.empty((0, 4, 4))
        self.hits = np.empty(0, dtype=np.int64)
        self.seen = np.empty(0)
        self.ids = np.empty(0, dtype=np.int64)
        self.stamp: float | None = None
        self._next_id = 0
        # (walker id, walker id) -> consecutive scans the two moved apart while linked
        self._apart_for: dict[tuple[int, int], int] = {}

    def __len__(self) -> int:
        return int(self.hits.size)

    def update(self, places: FloatArray, stamp: float) -> tuple[FloatArray, BoolArray, IntArray]:
        """Take the walker detections ``places`` (W, 2) [m] of the scan at ``stamp`` [s];
        returns the velocity (W, 2) [m/s] of the walker each detection went to, whether
        it is known (W,) (the walker has at least ``min_scans`` detections) and its id
        (W,)."""
        s = self.settings
        dt = 0.0 if self.stamp is None else max(0.0, stamp - self.stamp)
        self.stamp = stamp
        if len(self) and dt > 0.0:
            self.means, self.covs = kalman.predict(
                self.means, self.covs, np.full(len(self), dt), s.accel_psd
            )
        w = places.shape[0]
        track_of = np.full(w, -1, dtype=np.int64)
        if len(self) and w:
            d = np.hypot(
                self.means[:, None, 0] - places[None, :, 0],
                self.means[:, None, 1] - places[None, :, 1],
            )
            cost = np.where(d < s.gate, d, 1e6)
            rows, cols = linear_sum_assignment(cost)
            ok = cost[rows, cols] < s.gate
            rows, cols = rows[ok], cols[ok]
            if rows.size:
                r = np.broadcast_to(np.eye(2) * s.measurement_std**2, (rows.size, 2, 2))
                self.means[rows], self.covs[rows] = kalman.update_batch(
                    self.means[rows], self.covs[rows], places[cols], r
                )
                self.hits[rows] += 1
                self.seen[rows] = stamp
                track_of[cols] = rows
        new = np.nonzero(track_of < 0)[0]
        if new.size:
            r = np.broadcast_to(np.eye(2) * s.measurement_std**2, (new.size, 2, 2))
            m, c = kalman.initiate_batch(places[new], np.array(r), s.init_velocity_std)
            track_of[new] = np.arange(len(self), len(self) + new.size)
            self.means = np.concatenate([self.means, m])
            self.covs = np.concatenate([self.covs, c])
            self.hits = np.concatenate([self.hits, np.ones(new.size, dtype=np.int64)])
            self.seen = np.concatenate([self.seen, np.full(new.size, stamp)])
            fresh = np.arange(self._next_id, self._next_id + new.size, dtype=np.int64)
            self.ids = np.concatenate([self.ids, fresh])
            self._next_id += new.size
        velocity = self.means[track_of, 2:4]
        known = self.hits[track_of] >= s.min_scans
        ids = self.ids[track_of]
        alive = stamp - self.seen <= s.max_unseen
        if not alive.all():
            self.means, self.covs = self.means[alive], self.covs[alive]
            self.hits, self.seen, self.ids = self.hits[alive], self.seen[alive], self.ids[alive]
        return velocity, known, ids

    def coherent_links(
        self, points: FloatArray, blobs: IntArray, links: IntArray, stamp: float
    ) -> BoolArray:
        """Track the walkers of a scan (``points`` (N, 2) [m], blob labels ``blobs`` (N,)
        0..B-1) and tell which point ``links`` (E, 2) join walkers that move alike (E,)."""
        s = self.settings
        if points.shape[0] == 0:
            self.update(np.empty((0, 2)), stamp)
            return np.ones(len(links), dtype=bool)
        places, walker_of_blob = walker_detections(points, blobs, s.pair_distance, s.leg_radius)
        velocity, known, ids = self.update(places, stamp)
        wa = walker_of_blob[blobs[links[:, 0]]]
        wb = walker_of_blob[blobs[links[:, 1]]]
        apart = moving_apart(velocity[wa], velocity[wb], s.standing_speed, s.walking_speed)
        apart &= known[wa] & known[wb]
        # a pair of walkers is cut once it has moved apart for apart_scans scans in a row
        lo, hi = np.minimum(ids[wa], ids[wb]), np.maximum(ids[wa], ids[wb])
        pairs, first, link_pair = np.unique(
            np.column_stack([lo, hi]), axis=0, return_index=True, return_inverse=True
        )
        streaks: dict[tuple[int, int], int] = {}
        cut = np.zeros(len(pairs), dtype=bool)
        for k in np.nonzero(apart[first])[0].tolist():
            pair = (int(pairs[k, 0]), int(pairs[k, 1]))
            streaks[pair] = self._apart_for.get(pair, 0) + 1
            cut[k] = streaks[pair] >= s.apart_scans
        self._apart_for = streaks
        return ~cut[link_pair.reshape(-1)]


def moving_apart(
    va: FloatArray, vb: FloatArray, standing_speed: float, walking_speed: float
) -> BoolArray:
    """Which pairs of walkers with velocities ``va`` (E, 2) and ``vb`` (E, 2) [m/s] do not
    move as one (E,): one stands (slower than ``standing_speed``) while the other walks
    (faster than ``walking_speed``), or both move (faster than ``standing_speed``) in
    directions more than 90 degrees apart. Walkers heading the same way are never cut: a
    party walking together differs only by the noise of its members' estimates."""
    sa = np.hypot(va[:, 0], va[:, 1])
    sb = np.hypot(vb[:, 0], vb[:, 1])
    slow, fast = np.minimum(sa, sb), np.maximum(sa, sb)
    passing = (slow < standing_speed) & (fast > walking_speed)
    crossing = (slow >= standing_speed) & (np.einsum("ij,ij->i", va, vb) < 0.0)
    return passing | crossing
