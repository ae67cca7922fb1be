"""Leg traces: the velocity of every small segment of the scan (extension of 000 Sec. 4.1;
docs/groups.md "Walkers", "Third round").

The ceiling study of the walkers (docs/groups.md) shows that the d_P links can only be cut
well between parts that hold one person's points: one stray point of another group in a
part welds the two groups for that scan. Walkers (a person's two legs, tracked) take a
neighbour's leg now and then in a crowd (about 1 % of the points); segments at 0.1 m (a
leg, or part of one) hold two people's points far less often (0.2-0.3 %). A leg moves in
steps (standing, then swinging at two to three times the walker's speed), but over one
gait cycle (about 1 s) it moves as far as its walker. So:

1. **Segments**: single linkage of the points at ``segment_distance``.
2. **Traces**: every segment is matched one to one (Hungarian, within ``gate``) to a trace
   of the last scans, predicted by the trace's velocity; unmatched segments start traces,
   a trace unseen for longer than ``max_unseen`` ends.
3. **Velocity**: a trace's displacement over the last ``window`` seconds, known once its
   history spans at least ``min_span``.
4. **Cut**: a d_P link between two segments whose known velocities differ by more than
   ``max_velocity_difference`` is cut. A segment whose velocity is not known keeps its
   links, so new legs are clustered as by 000.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment

from laserpeople.tracking.groups.observations import blob_shapes, component_labels

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

HISTORY = 32
"""Places kept per trace (32 scans: a 1 s window at up to 30 Hz)."""


@dataclass(frozen=True)
class TraceSettings:
    """How legs are traced and when their links are cut.

    Attributes:
        segment_distance: Single-linkage distance of the segments [m].
        gate: Largest distance from a trace's predicted place to its segment [m].
        window: Time over which a trace's displacement gives its velocity [s].
        min_span: A trace's velocity is known once its history spans this long [s].
        max_unseen: A trace unseen for longer than this ends [s].
        max_velocity_difference: Links between segments whose velocities differ by more
            than this are cut [m/s].
    """

    segment_distance: float = 0.1
    gate: float = 0.3
    window: float = 1.0
    min_span: float = 0.8
    max_unseen: float = 0.3
    max_velocity_difference: float = 0.6

    def __post_init__(self) -> None:
        positive = (
            self.segment_distance,
            self.gate,
            self.window,
            self.min_span,
            self.max_velocity_difference,
        )
        if min(positive) <= 0.0 or self.max_unseen < 0.0 or self.min_span > self.window:
            raise ValueError(
                "leg traces need positive segment_distance, gate, window, min_span <= window "
                "and max_velocity_difference, and max_unseen >= 0"
            )


def window_velocity(
    stamps: FloatArray, places: FloatArray, now: float, window: float
) -> tuple[FloatArray, FloatArray]:
    """Displacement velocity of every trace: ``stamps`` (T, K) [s] (NaN: empty slot) and
    ``places`` (T, K, 2) [m] of its history; the velocity (T, 2) [m/s] from its oldest place
    within ``window`` [s] before ``now`` to its newest, and the time span (T,) [s] between
    them (0: fewer than two places)."""
    t = stamps.shape[0]
    if t == 0:
        return np.empty((0, 2)), np.empty(0)
    inside = np.isfinite(stamps) & (now - stamps <= window + 1e-9)
    big = np.where(inside, stamps, np.inf)
    small = np.where(inside, stamps, -np.inf)
    oldest, newest = np.argmin(big, axis=1), np.argmax(small, axis=1)
    rows = np.arange(t)
    span = np.where(inside.any(axis=1), stamps[rows, newest] - stamps[rows, oldest], 0.0)
    span = np.nan_to_num(span)
    move = places[rows, newest] - places[rows, oldest]
    velocity = np.zeros((t, 2))
    ok = span > 0.0
    velocity[ok] = move[ok] / span[ok, None]
    return velocity, span


class LegTracer:
    """Traces of the scan's segments (see the module doc).

    Attributes:
        ids: (T,) id of every trace.
        velocity: (T, 2) [m/s] displacement velocity of every trace.
        span: (T,) [s] time its velocity was measured over.
        last_trace: trace row of every segment of the last scan.
    """

    def __init__(self, settings: TraceSettings | None = None) -> None:
        self.settings = settings if settings is not None else TraceSettings()
        self.ids = np.empty(0, dtype=np.int64)
        self.velocity = np.empty((0, 2))
        self.span = np.empty(0)
        self._place = np.empty((0, 2))  # last place
        self._seen = np.empty(0)  # last time seen [s]
        self._stamps = np.empty((0, HISTORY))
        self._places = np.empty((0, HISTORY, 2))
        self._scan = 0
        self._next_id = 0
        self.last_trace = np.empty(0, dtype=np.int64)

    def __len__(self) -> int:
        return int(self.ids.size)

    def step(self, centres: FloatArray, stamp: float) -> IntArray:
        """Match the segments at ``centres`` (S, 2) [m] of the scan at ``stamp`` [s] to the
        traces; returns the trace row (S,) of every segment (new traces for the rest)."""
        s = self.settings
        alive = stamp - self._seen <= s.max_unseen + 1e-9
        if not alive.all():
            self._keep(alive)
        n = centres.shape[0]
        trace = np.full(n, -1, dtype=np.int64)
        if len(self) and n:
            predicted = self._place + self.velocity * (stamp - self._seen)[:, None]
            d = np.hypot(
                predicted[:, None, 0] - centres[None, :, 0],
                predicted[:, None, 1] - centres[None, :, 1],
            )
            cost = np.where(d < s.gate, d, 1e6)
            rows, cols = linear_sum_assignment(cost)
            ok = cost[rows, cols] < s.gate
            trace[cols[ok]] = rows[ok]
        new = np.nonzero(trace < 0)[0]
        if new.size:
            trace[new] = np.arange(len(self), len(self) + new.size)
            self.ids = np.concatenate(
                [self.ids, np.arange(self._next_id, self._next_id + new.size, dtype=np.int64)]
            )
            self._next_id += new.size
            self.velocity = np.concatenate([self.velocity, np.zeros((new.size, 2))])
            self.span = np.concatenate([self.span, np.zeros(new.size)])
            self._place = np.concatenate([self._place, centres[new]])
            self._seen = np.concatenate([self._seen, np.full(new.size, stamp)])
            self._stamps = np.concatenate([self._stamps, np.full((new.size, HISTORY), np.nan)])
            self._places = np.concatenate([self._places, np.zeros((new.size, HISTORY, 2))])
        slot = self._scan % HISTORY
        self._scan += 1
        self._stamps[:, slot] = np.nan
        self._stamps[trace, slot] = stamp
        self._places[trace, slot] = centres
        self._place[trace] = centres
        self._seen[trace] = stamp
        self.velocity, self.span = window_velocity(self._stamps, self._places, stamp, s.window)
        self.last_trace = trace
        return trace

    def _keep(self, alive: BoolArray) -> None:
        self.ids, self.velocity, self.span = self.ids[alive], self.velocity[alive], self.span[alive]
        self._place, self._seen = self._place[alive], self._seen[alive]
        self._stamps, self._places = self._stamps[alive], self._places[alive]

    def coherent_links(
        self,
        points: FloatArray,
        blobs: IntArray,
        links: IntArray,
        stamp: float,
        d_hs: float | None = None,
    ) -> BoolArray:
        """Trace the segments of a scan (``points`` (N, 2) [m]) and tell which point
        ``links`` (E, 2) join segments that move alike (E,) (``blobs`` and ``d_hs`` are not
        used: the segments are the tracer's own)."""
        del blobs, d_hs
        s = self.settings
        n = points.shape[0]
        if n == 0:
            self.step(np.empty((0, 2)), stamp)
            return np.ones(len(links), dtype=bool)
        a, b = links[:, 0], links[:, 1]
        length = np.hypot(points[a, 0] - points[b, 0], points[a, 1] - points[b, 1])
        segments = component_labels(n, links[length < s.segment_distance])
        n_seg = int(segments.max()) + 1
        centres, _ = blob_shapes(points, segments, n_seg)
        trace = self.step(centres, stamp)
        known = self.span[trace] >= s.min_span - 1e-9
        velocity = self.velocity[trace]
        sa, sb = segments[a], segments[b]
        dv = velocity[sa] - velocity[sb]
        apart = (
            known[sa] & known[sb] & (np.einsum("ij,ij->i", dv, dv) > s.max_velocity_difference**2)
        )
        return ~apart
