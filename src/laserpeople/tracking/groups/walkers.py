"""Walker velocities for the group observations (extension of 000 Sec. 4.1).

000 links two foreground points into one observation whenever they are closer than d_P,
so a person passing a standing group, or two parties walking past each other, are one
observation for as long as they are within d_P, and the tracker can only keep them apart
through its models (000 Fig. 18). In a crowded hall that fails: a wrong merge wins within
a few scans and cannot be undone while the parties stay close (docs/groups.md, "Why the
tracker does not beat memory-less clustering"). People who walk together move together.

This module tracks the walkers of the scene - a person's leg blobs, or one wider blob -
and cuts the d_P links between the points of two walkers that do not move alike. A walker
whose velocity is not known (younger than ``min_scans``, or whose places do not lie on a
line) keeps all of its links, so such people are clustered as by 000.

Blobs: single linkage at ``blob_distance`` (0: the observations' blobs at d_hs). At 0.15 m
the legs of two people who touch are two blobs; at d_hs = 0.3 m they are one, and one
walker with one velocity.

Detections (``association``):

* ``"pairs"``: two leg-sized blobs that are each other's nearest and closer than
  ``pair_distance`` are one walker at their midpoint (as the size count); every other blob
  is a walker; walkers are matched one to one to the nearest detection (Hungarian).
* ``"tracks"``: the walkers choose their blobs. Every walker has two slots; a blob may go
  to either (the second slot only takes a leg-sized blob), and one Hungarian assignment
  over all slots and the blobs within ``gate`` of the predicted places decides, so in a
  crowd a walker keeps its own legs rather than whichever leg is its mutual nearest. Blobs
  no walker takes are paired as in ``"pairs"`` and start walkers. A walker is predicted on
  the line of its window velocity (``line_prediction``) once that spans half a window,
  else by its Kalman filter.

The walker's place is the midpoint of its two legs, the centre of a wider blob, or a lone
leg (one leg hidden), which is off by up to half a stride and is given the std
``lone_std`` instead of ``measurement_std``.

Velocities (``velocity``): the Kalman filter's (constant velocity), or (``"window"``) the
weighted least-squares slope of the walker's places over the last ``window`` seconds
(weights 1 / std^2). The midpoint of the legs stands still while both feet are planted
and moves while one foot swings, so it oscillates once per step (0.5 s at 1.2 m/s in the
simulator's gait); a slope over two to three steps averages that out, which a Kalman
filter quick enough to follow a walker does not. A window velocity is known only if the
places lie within ``max_residual`` (weighted RMS) of their line: a walker whose track
jumped to another person mostly does not.

Cut (``cut``): ``"stand_walk"`` - one stands (under ``standing_speed``) while the other
walks (over ``walking_speed``), or both move in directions more than 90 degrees apart
(:func:`moving_apart`); ``"difference"`` - their velocities differ by more than
``max_velocity_difference`` (:func:`velocity_apart`, the rule of the ceiling with true
velocities); ``"passing"`` - both: they differ by more than ``max_velocity_difference``
while one stands (under ``standing_speed``) or they head apart (:func:`passing`). Each
must hold for ``apart_scans`` scans in a row. Session 13's walkers were ``"pairs"``, ``"kalman"``,
``"stand_walk"`` over 3 scans with the blobs at d_hs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment

from laserpeople.tracking import kalman
from laserpeople.tracking.groups.observations import blob_shapes, component_labels, leg_pairs

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

ASSOCIATIONS = ("pairs", "tracks")
VELOCITIES = ("kalman", "window")
CUTS = ("stand_walk", "difference", "passing")

PAIR, WIDE, LONE = 0, 1, 2
"""Kinds of walker detection: two leg blobs, one wider blob, one leg-sized blob alone."""

HISTORY = 128
"""Places kept per walker for the window velocity (128 scans: a 1.2 s window at up to
100 Hz; at faster scan rates the window is shorter than ``window``)."""


@dataclass(frozen=True)
class WalkerSettings:
    """How walkers are tracked and when their links are cut.

    Attributes:
        on: Whether links are cut at all (False: 000's clustering).
        standing_speed: A walker slower than this stands [m/s].
        walking_speed: A walker faster than this walks [m/s] (see :func:`moving_apart`).
        gate: Largest distance from a walker's predicted place to a detection (a blob,
            with ``"tracks"``) it takes [m].
        accel_psd: White-acceleration power spectral density of a walker [m^2/s^3].
        measurement_std: Position noise of a walker detection (the midpoint of its leg
            blobs, or one wider blob) [m].
        lone_std: Position noise of a walker seen as one leg-sized blob [m].
        init_velocity_std: Velocity std of a new walker [m/s].
        min_scans: Detections a walker needs before its velocity is used.
        apart_scans: Scans in a row two linked walkers must move apart before their
            links are cut.
        max_unseen: A walker not seen for longer than this is dropped [s].
        pair_distance: Largest distance between one person's two leg blobs [m].
        leg_radius: Largest radius of a blob that can be one leg [m].
        association: ``"pairs"`` or ``"tracks"`` (module doc).
        velocity: ``"kalman"`` or ``"window"`` (module doc).
        window: Length of the window velocity's fit [s].
        cut: ``"stand_walk"``, ``"difference"`` or ``"passing"`` (module doc).
        max_velocity_difference: Walkers whose velocities differ by more than this move
            apart (``cut = "difference"`` or ``"passing"``) [m/s].
        max_residual: A window velocity is known only if the walker's places are within
            this weighted RMS distance of the fitted line [m] (a walker whose track
            jumped to another person mid-window mostly is not).
        blob_distance: Single-linkage distance of the walkers' own blobs [m] (0: the
            observations' blobs at d_hs). Finer blobs split the legs of two people that
            touch, which one blob at d_hs welds.
        line_prediction: ``"tracks"``: a walker whose window spans at least half of
            ``window`` is predicted on its window's line rather than by its Kalman
            filter (which a lone stance leg holds back).
    """

    on: bool = False
    standing_speed: float = 0.3
    walking_speed: float = 0.8
    gate: float = 0.6
    accel_psd: float = 0.2
    measurement_std: float = 0.3
    lone_std: float = 1.0
    init_velocity_std: float = 1.0
    min_scans: int = 10
    apart_scans: int = 2
    max_unseen: float = 0.5
    pair_distance: float = 0.7
    leg_radius: float = 0.12
    association: str = "tracks"
    velocity: str = "window"
    window: float = 1.2
    cut: str = "passing"
    max_velocity_difference: float = 0.6
    max_residual: float = 0.1
    blob_distance: float = 0.15
    line_prediction: bool = True

    def __post_init__(self) -> None:
        if not 0.0 < self.standing_speed <= self.walking_speed:
            raise ValueError("walkers need 0 < standing_speed <= walking_speed")
        positive = (
            self.gate,
            self.accel_psd,
            self.measurement_std,
            self.lone_std,
            self.init_velocity_std,
            self.pair_distance,
            self.leg_radius,
            self.window,
            self.max_velocity_difference,
            self.max_residual,
        )
        if min(positive) <= 0.0:
            raise ValueError(
                "walker gate, accel_psd, measurement_std, lone_std, init_velocity_std, "
                "pair_distance, leg_radius, window, max_velocity_difference and max_residual "
                "must be positive"
            )
        if self.min_scans < 1 or self.apart_scans < 1 or self.max_unseen < 0.0:
            raise ValueError("walker min_scans and apart_scans must be >= 1, max_unseen >= 0")
        if self.blob_distance < 0.0:
            raise ValueError("walker blob_distance must not be negative")
        for name, value, allowed in (
            ("association", self.association, ASSOCIATIONS),
            ("velocity", self.velocity, VELOCITIES),
            ("cut", self.cut, CUTS),
        ):
            if value not in allowed:
                raise ValueError(f"walker {name} must be one of {allowed}, got {value!r}")


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
    places, walker, _ = paired_detections(centre, radius, pair_distance, leg_radius)
    return places, walker


def paired_detections(
    centre: FloatArray, radius: FloatArray, pair_distance: float, leg_radius: float
) -> tuple[FloatArray, IntArray, IntArray]:
    """:func:`walker_detections` from the blobs' ``centre`` (B, 2) and ``radius`` (B,) [m]:
    the places (W, 2), the walker (B,) of every blob and the kind (W,) of every walker
    (:data:`PAIR`, :data:`WIDE` or :data:`LONE`)."""
    n_blobs = radius.size
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
    kind = np.where(counts == 2, PAIR, np.where(radius[used] <= leg_radius, LONE, WIDE))
    return places, walker.astype(np.int64), kind.astype(np.int64)


def assign_blobs(
    predicted: FloatArray,
    centre: FloatArray,
    is_leg: BoolArray,
    gate: float,
    pair_distance: float,
) -> tuple[IntArray, IntArray]:
    """Track-guided detections: walkers predicted at ``predicted`` (T, 2) [m] choose among
    blobs at ``centre`` (B, 2) [m] (``is_leg`` (B,): leg-sized). Each walker has two slots;
    the first takes any blob within ``gate``, the second a leg-sized one within ``gate``;
    one Hungarian assignment minimises the summed distances.
    A walker keeps two blobs only if both are legs closer than ``pair_distance`` to each
    other (else the farther is released). Returns the walker (B,) of every blob (-1: none)
    and the number of blobs (T,) every walker took."""
    t, b = predicted.shape[0], centre.shape[0]
    owner = np.full(b, -1, dtype=np.int64)
    taken = np.zeros(t, dtype=np.int64)
    if t == 0 or b == 0:
        return owner, taken
    d = np.hypot(
        predicted[:, None, 0] - centre[None, :, 0], predicted[:, None, 1] - centre[None, :, 1]
    )
    near = d < gate
    big = 1e6
    first = np.where(near, d, big)
    second = np.where(near & is_leg[None, :], d, big)
    rows, cols = linear_sum_assignment(np.concatenate([first, second]))
    cost = np.concatenate([first, second])[rows, cols]
    ok = cost < big
    rows, cols = rows[ok], cols[ok]
    walker = rows % t
    owner[cols] = walker
    # a walker with two blobs: both legs, and within a stride of each other
    twice = np.nonzero(np.bincount(walker, minlength=t) == 2)[0]
    for w in twice.tolist():
        mine = cols[walker == w]
        a, c = int(mine[0]), int(mine[1])
        gap = float(np.hypot(*(centre[a] - centre[c])))
        if not (is_leg[a] and is_leg[c] and gap < pair_distance):
            owner[c if d[w, c] > d[w, a] else a] = -1
    taken = np.bincount(owner[owner >= 0], minlength=t).astype(np.int64)
    return owner, taken


def window_velocity(
    stamps: FloatArray, places: FloatArray, weights: FloatArray, now: float, window: float
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Weighted least-squares line through a walker's places over the last ``window``
    seconds before ``now``: ``stamps`` (T, K) [s], ``places`` (T, K, 2) [m], ``weights``
    (T, K) (0: no place). Returns the slopes (T, 2) [m/s] (0 where fewer than two distinct
    times), the line's place (T, 2) [m] at ``now``, the time span (T,) [s] of the places
    used and the weighted RMS distance (T,) [m] of the places from the line."""
    w = np.where(now - stamps <= window + 1e-9, weights, 0.0)
    tau = np.where(w > 0.0, stamps - now, 0.0)
    s = w.sum(axis=1)
    st = (w * tau).sum(axis=1)
    stt = (w * tau * tau).sum(axis=1)
    sx = np.einsum("tk,tkc->tc", w, places)
    stx = np.einsum("tk,tkc->tc", w * tau, places)
    den = s * stt - st * st
    ok = den > 1e-12
    v = np.zeros((stamps.shape[0], 2))
    v[ok] = (s[ok, None] * stx[ok] - st[ok, None] * sx[ok]) / den[ok, None]
    safe = np.maximum(s, 1e-12)
    a = (sx - v * st[:, None]) / safe[:, None]
    r = places - a[:, None, :] - v[:, None, :] * tau[:, :, None]
    rms = np.sqrt(np.einsum("tk,tkc->t", w, r * r) / safe)
    oldest = np.where(w > 0.0, tau, 0.0).min(axis=1)
    return v, a, -oldest, rms


class WalkerTracker:
    """Walkers of the scene, tracked scan to scan (see the module doc).

    Attributes:
        means: (T, 4) state (x, y, vx, vy) [m, m/s] of every walker.
        covs: (T, 4, 4) covariances.
        hits: (T,) detections taken by every walker.
        seen: (T,) time [s] every walker was last detected.
        ids: (T,) id of every walker.
        last_kind: (T,) kind of the last scan's detection of every walker (-1: none).
        last_scan: see :meth:`coherent_links`.
    """

    def __init__(self, settings: WalkerSettings | None = None) -> None:
        self.settings = settings if settings is not None else WalkerSettings()
        self.means = np.empty((0, 4))
        self.covs = np.empty((0, 4, 4))
        self.hits = np.empty(0, dtype=np.int64)
        self.seen = np.empty(0)
        self.ids = np.empty(0, dtype=np.int64)
        self.last_kind = np.empty(0, dtype=np.int64)
        self.stamp: float | None = None
        self._next_id = 0
        self._scan = 0
        # window of places: stamps (T, K), places (T, K, 2), weights (T, K)
        self._t = np.empty((0, HISTORY))
        self._xy = np.empty((0, HISTORY, 2))
        self._w = np.empty((0, HISTORY))
        # (walker id, walker id) -> consecutive scans the two moved apart while linked
        self._apart_for: dict[tuple[int, int], int] = {}
        self.last_scan: tuple[IntArray, FloatArray, BoolArray, IntArray] | None = None
        """The last scan's walker of every point, and every walker's velocity, whether it
        is known and its id (for diagnostics; None before the first scan with points)."""

    def __len__(self) -> int:
        return int(self.hits.size)

    def _predict(self, stamp: float) -> None:
        s = self.settings
        dt = 0.0 if self.stamp is None else max(0.0, stamp - self.stamp)
        self.stamp = stamp
        if len(self) and dt > 0.0:
            self.means, self.covs = kalman.predict(
                self.means, self.covs, np.full(len(self), dt), s.accel_psd
            )

    def _measure(
        self, rows: IntArray, places: FloatArray, kinds: IntArray, stamp: float, w: int
    ) -> IntArray:
        """Update walkers ``rows`` with ``places`` (of ``kinds``), start walkers for the
        ``w`` - len(rows) places after them; returns the walker of each of the ``w``
        places (rows first)."""
        s = self.settings
        std = np.where(kinds == LONE, s.lone_std, s.measurement_std)
        r = np.eye(2)[None, :, :] * (std**2)[:, None, None]
        n_old = rows.size
        if n_old:
            self.means[rows], self.covs[rows] = kalman.update_batch(
                self.means[rows], self.covs[rows], places[:n_old], r[:n_old]
            )
            self.hits[rows] += 1
            self.seen[rows] = stamp
        new = w - n_old
        slot = self._scan % HISTORY
        self._w[:, slot] = 0.0
        if new:
            m, c = kalman.initiate_batch(places[n_old:], r[n_old:], s.init_velocity_std)
            self.means = np.concatenate([self.means, m])
            self.covs = np.concatenate([self.covs, c])
            self.hits = np.concatenate([self.hits, np.ones(new, dtype=np.int64)])
            self.seen = np.concatenate([self.seen, np.full(new, stamp)])
            fresh = np.arange(self._next_id, self._next_id + new, dtype=np.int64)
            self.ids = np.concatenate([self.ids, fresh])
            self._next_id += new
            self._t = np.concatenate([self._t, np.zeros((new, HISTORY))])
            self._xy = np.concatenate([self._xy, np.zeros((new, HISTORY, 2))])
            self._w = np.concatenate([self._w, np.zeros((new, HISTORY))])
            self.last_kind = np.concatenate([self.last_kind, np.full(new, -1, dtype=np.int64)])
        out = np.concatenate([rows, np.arange(len(self) - new, len(self))]).astype(np.int64)
        self.last_kind[:] = -1
        self.last_kind[out] = kinds
        self._t[out, slot] = stamp
        self._xy[out, slot] = places
        self._w[out, slot] = (s.measurement_std / std) ** 2
        self._scan += 1
        return out

    def _velocities(self, stamp: float) -> tuple[FloatArray, BoolArray]:
        s = self.settings
        known = self.hits >= s.min_scans
        if s.velocity == "kalman":
            return self.means[:, 2:4].copy(), known
        v, _, _, rms = window_velocity(self._t, self._xy, self._w, stamp, s.window)
        known &= rms <= s.max_residual
        return v, known

    def _drop_lost(self, stamp: float) -> None:
        alive = stamp - self.seen <= self.settings.max_unseen
        if not alive.all():
            self.means, self.covs = self.means[alive], self.covs[alive]
            self.hits, self.seen, self.ids = self.hits[alive], self.seen[alive], self.ids[alive]
            self.last_kind = self.last_kind[alive]
            self._t, self._xy, self._w = self._t[alive], self._xy[alive], self._w[alive]

    def update(
        self, places: FloatArray, stamp: float, kinds: IntArray | None = None
    ) -> tuple[FloatArray, BoolArray, IntArray]:
        """Take the walker detections ``places`` (W, 2) [m] (of ``kinds`` (W,), all
        :data:`PAIR` when None) of the scan at ``stamp`` [s], matched one to one to the
        nearest predicted walker within ``gate``; returns the velocity (W, 2) [m/s] of the
        walker each detection went to, whether it is known (W,) (the walker has at least
        ``min_scans`` detections) and its id (W,)."""
        s = self.settings
        self._predict(stamp)
        w = places.shape[0]
        kinds = np.full(w, PAIR, dtype=np.int64) if kinds is None else kinds
        track_of = np.full(w, -1, dtype=np.int64)
        rows = np.empty(0, dtype=np.int64)
        cols = np.empty(0, dtype=np.int64)
        if len(self) and w:
            d = np.hypot(
                self.means[:, None, 0] - places[None, :, 0],
                self.means[:, None, 1] - places[None, :, 1],
            )
            cost = np.where(d < s.gate, d, 1e6)
            rows, cols = linear_sum_assignment(cost)
            ok = cost[rows, cols] < s.gate
            rows, cols = rows[ok].astype(np.int64), cols[ok].astype(np.int64)
        new = np.setdiff1d(np.arange(w), cols)
        order = np.concatenate([cols, new])
        track_of[order] = self._measure(rows, places[order], kinds[order], stamp, w)
        velocity, known = self._velocities(stamp)
        out = velocity[track_of], known[track_of], self.ids[track_of]
        self._drop_lost(stamp)
        return out

    def update_blobs(
        self, centre: FloatArray, radius: FloatArray, stamp: float
    ) -> tuple[IntArray, FloatArray, BoolArray, IntArray]:
        """Take the blobs (``centre`` (B, 2), ``radius`` (B,) [m]) of the scan at
        ``stamp`` [s]; returns the walker (B,) of every blob and each walker's velocity
        (W, 2) [m/s], whether it is known (W,) and its id (W,), W walkers this scan."""
        s = self.settings
        if s.association == "pairs":
            places, walker, kinds = paired_detections(centre, radius, s.pair_distance, s.leg_radius)
            velocity, known, ids = self.update(places, stamp, kinds)
            return walker, velocity, known, ids
        self._predict(stamp)
        is_leg = radius <= s.leg_radius
        predicted = self.means[:, :2]
        if s.line_prediction and len(self):
            _, line, span, _ = window_velocity(self._t, self._xy, self._w, stamp, s.window)
            predicted = np.where((span >= 0.5 * s.window)[:, None], line, predicted)
        owner, taken = assign_blobs(predicted, centre, is_leg, s.gate, s.pair_distance)
        rows = np.nonzero(taken > 0)[0].astype(np.int64)
        n_rows = rows.size
        # the place and kind of each walker that took blobs
        sums = np.zeros((len(self), 2))
        mine = owner >= 0
        np.add.at(sums, owner[mine], centre[mine])
        places = sums[rows] / taken[rows, None]
        one_leg = np.zeros(len(self), dtype=bool)
        one_leg[owner[mine & is_leg]] = True
        kinds = np.where(taken[rows] == 2, PAIR, np.where(one_leg[rows], LONE, WIDE))
        # blobs no walker took start walkers, paired as in "pairs"
        free = np.nonzero(~mine)[0]
        new_places, new_walker, new_kinds = paired_detections(
            centre[free], radius[free], s.pair_distance, s.leg_radius
        )
        all_places = np.concatenate([places, new_places])
        all_kinds = np.concatenate([kinds, new_kinds]).astype(np.int64)
        track_of = self._measure(rows, all_places, all_kinds, stamp, all_places.shape[0])
        # walkers of this scan: 0..n_rows-1 the old ones that took blobs, then the new
        local = np.full(len(self), -1, dtype=np.int64)
        local[rows] = np.arange(n_rows)
        walker = np.empty(centre.shape[0], dtype=np.int64)
        walker[mine] = local[owner[mine]]
        walker[free] = n_rows + new_walker
        velocity, known = self._velocities(stamp)
        out = walker, velocity[track_of], known[track_of], self.ids[track_of]
        self._drop_lost(stamp)
        return out

    def coherent_links(
        self, points: FloatArray, blobs: IntArray, links: IntArray, stamp: float
    ) -> BoolArray:
        """Track the walkers of a scan (``points`` (N, 2) [m], blob labels ``blobs`` (N,)
        0..B-1) and tell which point ``links`` (E, 2) join walkers that move alike (E,)."""
        s = self.settings
        if points.shape[0] == 0:
            self.update(np.empty((0, 2)), stamp)
            return np.ones(len(links), dtype=bool)
        if s.blob_distance > 0.0:
            a, b = links[:, 0], links[:, 1]
            length = np.hypot(points[a, 0] - points[b, 0], points[a, 1] - points[b, 1])
            blobs = component_labels(points.shape[0], links[length < s.blob_distance])
        n_blobs = int(blobs.max()) + 1
        centre, radius = blob_shapes(points, blobs, n_blobs)
        walker_of_blob, velocity, known, ids = self.update_blobs(centre, radius, stamp)
        self.last_scan = (walker_of_blob[blobs], velocity, known, ids)
        wa = walker_of_blob[blobs[links[:, 0]]]
        wb = walker_of_blob[blobs[links[:, 1]]]
        if s.cut == "difference":
            apart = velocity_apart(velocity[wa], velocity[wb], s.max_velocity_difference)
        elif s.cut == "passing":
            apart = passing(velocity[wa], velocity[wb], s.standing_speed, s.max_velocity_difference)
        else:
            apart = moving_apart(velocity[wa], velocity[wb], s.standing_speed, s.walking_speed)
        apart &= known[wa] & known[wb] & (wa != wb)
        # a pair of walkers is cut once it has moved apart for apart_scans scans in a row
        streaks: dict[tuple[int, int], int] = {}
        lo, hi = np.minimum(ids[wa], ids[wb]), np.maximum(ids[wa], ids[wb])
        for a, b, now in set(zip(lo.tolist(), hi.tolist(), apart.tolist(), strict=True)):
            if now:
                streaks[a, b] = self._apart_for.get((a, b), 0) + 1
        self._apart_for = streaks
        if not streaks:
            return np.ones(len(links), dtype=bool)
        pairs = zip(lo.tolist(), hi.tolist(), strict=True)
        cut = [streaks.get(pair, 0) >= s.apart_scans for pair in pairs]
        return ~np.asarray(cut, dtype=bool)


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


def velocity_apart(va: FloatArray, vb: FloatArray, max_difference: float) -> BoolArray:
    """Which pairs of walkers with velocities ``va`` (E, 2) and ``vb`` (E, 2) [m/s] differ
    by more than ``max_difference`` [m/s] (E,)."""
    return np.hypot(va[:, 0] - vb[:, 0], va[:, 1] - vb[:, 1]) > max_difference


def passing(
    va: FloatArray, vb: FloatArray, standing_speed: float, max_difference: float
) -> BoolArray:
    """Which pairs of walkers with velocities ``va`` (E, 2) and ``vb`` (E, 2) [m/s] pass
    each other (E,): their velocities differ by more than ``max_difference`` [m/s] while
    one stands (slower than ``standing_speed`` [m/s]) or both move in directions more than
    90 degrees apart. Walkers heading the same way are not cut, however their speeds
    differ: on the real recordings those are mostly one party's noisy estimates."""
    apart = velocity_apart(va, vb, max_difference)
    return apart & moving_apart(va, vb, standing_speed, standing_speed)
