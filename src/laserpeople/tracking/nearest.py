"""Global-nearest-neighbour (GNN) Kalman tracker: the cheap baseline.

Each scan, predicted tracks and detections are paired by the minimum total squared
Mahalanobis distance within the gate (Hungarian); unpaired detections start tracks, tracks
missed for more than ``max_misses`` scans are deleted; a track is reported once it has been
detected ``min_hits`` times. People are built from its leg tracks by the same person model as
the MHT tracker (000 Sec. 3.3), without feedback into the leg tracking.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.scan import CoordinateFrame
from laserpeople.tracking import kalman
from laserpeople.tracking.assignment import solve
from laserpeople.tracking.frames import in_frame, tracking_frame
from laserpeople.tracking.guard import InputGuard
from laserpeople.tracking.kalman import KalmanParams
from laserpeople.tracking.people import LegState, PersonFuser, PersonParams
from laserpeople.tracking.seen_ids import SeenIds
from laserpeople.tracks import Detections, Track, Tracks

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class NearestNeighbourParams:
    """Parameters of the GNN baseline tracker."""

    config_section = "nn_tracker"

    max_misses: int = param(
        5, "assumption (about p_occ|F^n = p_del|F with 000 Table 10)", "delete after", "scans"
    )
    min_hits: int = param(2, "assumption", "detections before a track is reported", "scans")
    kalman: KalmanParams = param(  # noqa: RUF009 (a frozen default instance)
        KalmanParams(), "nested table kalman.*", "leg motion model"
    )
    person: PersonParams = param(  # noqa: RUF009 (a frozen default instance)
        PersonParams(), "nested table person.*", "people from leg pairs"
    )

    def __post_init__(self) -> None:
        if self.max_misses < 0 or self.min_hits < 1:
            raise ValueError("max_misses must be >= 0 and min_hits >= 1")


@dataclass(eq=False)
class _Tracks:
    ids: list[int] = field(default_factory=list)
    means: FloatArray = field(default_factory=lambda: np.empty((0, 4)))
    covs: FloatArray = field(default_factory=lambda: np.empty((0, 4, 4)))
    hits: list[int] = field(default_factory=list)
    misses: list[int] = field(default_factory=list)


class NearestNeighbourTracker:
    """GNN leg tracker with person fusion: ``update(detections) -> Tracks``."""

    def __init__(self, params: NearestNeighbourParams | None = None) -> None:
        self.params = params if params is not None else NearestNeighbourParams()
        self.people = PersonFuser(self.params.person)
        self._t = _Tracks()
        self._ids = itertools.count()
        self._stamp: float | None = None
        self.frame: CoordinateFrame | None = None
        self.leg_ids_reported = SeenIds()
        """Distinct leg ids reported since the start (``len``), in bounded memory."""
        self.guard = InputGuard()
        """Counts of hostile input (repeated/backward stamps, non-finite values)."""
        self.dropped_detections = 0

    def _positions(self, detections: Detections) -> tuple[FloatArray, FloatArray]:
        if self.frame is None:
            self.frame = tracking_frame(detections)
        detections = in_frame(detections, self.frame)
        r = kalman.measurement_covariances(
            detections.covariances, self.params.kalman.measurement_std
        )
        return detections.positions, r

    def update(self, detections: Detections) -> Tracks:
        """Track one scan's detections (checked by :class:`InputGuard` first)."""
        detections = self.guard.check(detections)
        self.dropped_detections = self.guard.dropped_detections
        kp = self.params.kalman
        z, r = self._positions(detections)
        t = self._t
        n = len(t.ids)
        if n:
            dt = np.full(n, 0.0 if self._stamp is None else detections.stamp - self._stamp)
            t.means, t.covs = kalman.predict(
                t.means, t.covs, np.clip(dt, 0.0, kp.max_dt), kp.accel_psd
            )
        self._stamp = detections.stamp
        matched_t = np.full(n, -1)
        matched_z = np.zeros(len(z), dtype=bool)
        if n and len(z):
            d2, _ = kalman.mahalanobis_and_loglik(t.means, t.covs, z, r)
            ok = (d2 <= kp.gate) & (kalman.euclidean_sq(t.means, z) <= kp.max_gate_distance**2)
            # every track may stay unmatched at the cost of the gate
            cost = np.hstack([np.where(ok, d2, np.inf), np.full((n, n), np.inf)])
            cost[np.arange(n), len(z) + np.arange(n)] = kp.gate
            sol = solve(cost)
            if sol is not None:
                for i, j in zip(sol.rows.tolist(), sol.cols.tolist(), strict=True):
                    if j < len(z) and ok[i, j]:
                        matched_t[i] = j
                        matched_z[j] = True
        for i in range(n):
            j = int(matched_t[i])
            if j >= 0:
                t.means[i], t.covs[i] = kalman.update(t.means[i], t.covs[i], z[j], r[j])
                t.hits[i] += 1
                t.misses[i] = 0
            else:
                t.misses[i] += 1
        keep = [i for i in range(n) if t.misses[i] <= self.params.max_misses]
        t.ids = [t.ids[i] for i in keep]
        t.hits = [t.hits[i] for i in keep]
        t.misses = [t.misses[i] for i in keep]
        t.means, t.covs = t.means[keep], t.covs[keep]
        new = np.flatnonzero(~matched_z)
        if new.size:
            inits = [kalman.initiate(z[j], r[j], kp.init_velocity_std) for j in new]
            t.means = np.vstack([t.means, np.stack([m for m, _ in inits])])
            t.covs = np.concatenate([t.covs, np.stack([c for _, c in inits])])
            t.ids.extend(next(self._ids) for _ in new)
            t.hits.extend([1] * new.size)
            t.misses.extend([0] * new.size)
        legs = {
            tid: LegState(tid, t.means[i], t.covs[i])
            for i, tid in enumerate(t.ids)
            if t.hits[i] >= self.params.min_hits
        }
        self.leg_ids_reported.prune(t.ids)
        self.leg_ids_reported.add(legs)
        persons = self.people.update(legs, detections.stamp)
        leg_tracks = [
            Track(tid, "leg", s.mean[:2], s.mean[2:4], s.cov[:2, :2]) for tid, s in legs.items()
        ]
        assert self.frame is not None
        return Tracks(
            detections.stamp,
            detections.scan_index,
            tuple(leg_tracks + persons),
            self.frame,
            detections.sensor_pose,
        )
