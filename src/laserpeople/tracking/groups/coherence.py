"""Motion coherence of a group over several scans (an extension of 000 Sec. 4.3).

000's observation likelihood (eqs. 19-24) compares an observation with the track's
contour of the last scan, moved by one scan of the predicted velocity. A group track's
contour is replaced by its observation every scan, so two parties walking past each other
at 1 m/s differ by 0.1 m per scan, below the point noise: a track made by merging them
explains their shared observation as well as the two tracks do, and wrong merges win
(docs/groups.md). This module adds a data term that sees a group move as one over
``lag`` seconds:

* every group track keeps the points it observed over the last ``lag`` seconds (its
  *history*, snapshots every ``step`` seconds; a merged track the union of its parents'
  snapshots taken at the same scans, split halves start without one);
* an observation (or a part of a re-clustered one, share w) matched to the track is
  compared with the oldest snapshot moved by the track's predicted velocity over the
  snapshot's age tau: d is the root mean square, over the observation's points z_l, of
  the Euclidean distance to the nearest moved snapshot point,

      d^2 = mean_l min_j |z_l - (p_j + v tau)|^2,

* and the track's data likelihood gains the factor

      log c = -1/2 w max(0, d^2 / sigma^2 - 2),

  zero while the points deviate from a rigid motion by no more than a point spread sigma
  per axis (2 = the mean of a chi-square with two degrees of freedom), a penalty
  quadratic in d beyond it. A group that moves as one keeps d near its gait and occlusion
  jitter; a merged track of parties moving at velocities v_a, v_b has its parts off by
  about w_b |v_a - v_b| tau and w_a |v_a - v_b| tau from where the merged velocity puts
  them, while the two separate tracks, each with its own velocity, are not.

The term is off (000's likelihood) when ``lag`` is 0.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracking.groups.model import (
    GroupModel,
    GroupModelSettings,
    GroupPayload,
    Snapshot,
    group_payload,
    with_payload,
)
from laserpeople.tracking.groups.observations import GroupObservations
from laserpeople.tracking.mht.tracktree import TrackNode

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

History = tuple[Snapshot, ...]


@dataclass(frozen=True)
class CoherenceSettings:
    """The motion-coherence term (see the module doc).

    Attributes:
        lag: Longest age of the snapshot compared with [s]; 0 switches the term off.
        min_age: Youngest snapshot age that is compared [s] (younger: no term).
        step: Least time between two snapshots kept [s].
        sigma: Point spread of a group that moves as one, per axis [m].
        align: Translation-only ICP steps that refine the shift v tau to the rigid
            translation that best aligns the snapshot with the observation (0: the
            track's velocity alone).
        both_ways: Average d^2 over both directions: also the moved snapshot's points
            to their nearest observed point (a part that left the group shows).
        merged_only: Only tracks made by a merge, while their reference snapshot is from
            before it (the union of the parents' points): what a merge must explain; a
            track whose members start to leave is then not penalised before it can split.
    """

    lag: float
    min_age: float
    step: float
    sigma: float
    align: int = 0
    both_ways: bool = False
    merged_only: bool = False

    @property
    def enabled(self) -> bool:
        """Whether the term is on."""
        return self.lag > 0.0


def push_snapshot(
    history: History, stamp: float, points: FloatArray, lag: float, step: float
) -> History:
    """``history`` with the snapshot (``stamp`` [s], absolute ``points`` (K, 2) [m])
    appended when it is the first in its slot of ``step`` seconds (slots on a common time
    grid, so tracks observed at the same scans keep snapshots of the same scans), and the
    snapshots older than ``lag`` before ``stamp`` dropped (the newest is always kept)."""
    out = list(history)
    if not out or math.floor(stamp / step + 1e-9) != math.floor(out[-1][0] / step + 1e-9):
        out.append((float(stamp), np.asarray(points, dtype=np.float64).reshape(-1, 2)))
    while len(out) > 1 and stamp - out[0][0] > lag + 1e-9:
        out.pop(0)
    return tuple(out)


def reference_snapshot(history: History, stamp: float, min_age: float) -> Snapshot | None:
    """The oldest snapshot of ``history`` when it is at least ``min_age`` [s] before
    ``stamp``, else None."""
    if not history or stamp - history[0][0] < min_age - 1e-9:
        return None
    return history[0]


def merge_histories(a: History, b: History, tolerance: float) -> History:
    """The history of two merging tracks: for every snapshot of ``a``, the union of its
    points with those of the snapshot of ``b`` taken within ``tolerance`` [s] of it (a
    snapshot only one of them has would show half of the merged group and is dropped)."""
    out = []
    for stamp, points in a:
        near = [q for t, q in b if abs(t - stamp) <= tolerance + 1e-9]
        if near:
            out.append((stamp, np.concatenate([points, near[0]])))
    return tuple(out)


def coherence_distance_sq(points: FloatArray, past: FloatArray, shift: FloatArray) -> float:
    """d^2 [m^2]: mean over ``points`` (K, 2) of the squared distance to the nearest point
    of ``past`` (J, 2) moved by ``shift`` (2,) [m]."""
    diff = np.asarray(points)[:, None, :] - (np.asarray(past) + shift)[None, :, :]
    return float(np.einsum("ijk,ijk->ij", diff, diff).min(axis=1).mean())


def aligned_distance_sq(
    past: FloatArray, points: FloatArray, shift: FloatArray, steps: int, both_ways: bool = False
) -> float:
    """d^2 of :func:`coherence_distance_sq` of ``points`` (K, 2) to the ``past`` points
    (J, 2) [m], after ``steps`` translation-only ICP steps from ``shift`` (2,) [m] (each:
    the shift becomes the mean offset of the points from their nearest past points); with
    ``both_ways`` the mean of it and of the same from the moved past points to the points.

    The squared distances of every point to every past point, one (K, J) matrix per step
    (a group's few dozen points: cheaper than building and querying a KD-tree); the
    moved past points' nearest points are the matrix's column minima. A step whose
    nearest points are those of the step before ends the alignment (the shift would not
    change again; the result is that of all ``steps``)."""
    pts = np.asarray(points, dtype=np.float64)
    ref = np.asarray(past, dtype=np.float64)
    sx, sy = float(shift[0]), float(shift[1])
    zx, zy, px, py = pts[:, 0], pts[:, 1], ref[:, 0], ref[:, 1]
    last: NDArray[np.intp] | None = None
    for step in range(steps + 1):
        dx = np.subtract.outer(zx - sx, px)
        dy = np.subtract.outer(zy - sy, py)
        d = np.multiply(dx, dx, out=dx)
        d += np.multiply(dy, dy, out=dy)
        if step == steps:
            break
        k = d.argmin(axis=1)
        if last is not None and np.array_equal(k, last):
            # the same nearest points as the step before, so the same shift as this
            # step's: every further step repeats this one (the same numbers)
            break
        last = k
        sx = float((zx - px[k]).sum()) / zx.size  # the mean offset
        sy = float((zy - py[k]).sum()) / zy.size
    d_sq = float(d.min(axis=1).sum()) / zx.size
    if both_ways:
        d_sq = 0.5 * (d_sq + float(d.min(axis=0).sum()) / px.size)
    return d_sq


def coherence_log_likelihood(d_sq: float, sigma: float, share: float = 1.0) -> float:
    """log c = -1/2 w max(0, d^2 / sigma^2 - 2) (module doc)."""
    return -0.5 * share * max(0.0, d_sq / sigma**2 - 2.0)


class CoherentGroupModel(GroupModel):
    """:class:`~laserpeople.tracking.groups.model.GroupModel` whose tracks keep their
    history and whose data likelihood has the coherence factor (module doc)."""

    def __init__(self, settings: GroupModelSettings, coherence: CoherenceSettings) -> None:
        super().__init__(settings)
        self.coherence = coherence
        self._refs: dict[int, tuple[FloatArray, FloatArray] | None] = {}
        self._terms: dict[tuple[int, int], FloatArray] = {}
        # (node id, frame point indices of a cluster) -> d^2 of the node's snapshot and
        # those points, this scan (a cluster recurs in the observations of many models)
        self._d_sq: dict[tuple[int, bytes], float] = {}

    def predict(self, nodes: Sequence[TrackNode], stamp: float) -> None:
        """Predict (see the base class) and forget the last scan's coherence terms."""
        super().predict(nodes, stamp)
        self._refs.clear()
        self._terms.clear()
        self._d_sq.clear()
        self._stamp = stamp

    def score(
        self, nodes: Sequence[TrackNode], measurements: GroupObservations
    ) -> tuple[BoolArray, FloatArray]:
        """Gate and log N_i (eq. 24) plus log c of every gated (node, cluster) (T, M)."""
        gated, loglik = super().score(nodes, measurements)
        if not self.coherence.enabled:
            return gated, loglik
        loglik = loglik.copy()  # the base model may hand out rows of its cache
        for a, node in enumerate(nodes):
            if not gated[a].any():
                continue
            key = (node.node_id, id(measurements))
            term = self._terms.get(key)
            if term is None:
                term = self._term_row(node, measurements, gated[a])
                self._terms[key] = term
            loglik[a] += term
        return gated, loglik

    def _reference(self, node: TrackNode) -> tuple[FloatArray, FloatArray] | None:
        """The node's reference snapshot (J, 2) [m] and its shift v tau (2,), once per scan."""
        if node.node_id not in self._refs:
            payload = group_payload(node)
            ref = reference_snapshot(payload.history, self._stamp, self.coherence.min_age)
            if ref is not None and self.coherence.merged_only:
                # NaN (never merged) compares False: no term
                ref = ref if ref[0] <= payload.merged_stamp + 1e-9 else None
            if ref is None or node.pred_mean is None or ref[1].shape[0] == 0:
                self._refs[node.node_id] = None
            else:
                shift = node.pred_mean[2:4] * (self._stamp - ref[0])
                self._refs[node.node_id] = (ref[1], shift)
        return self._refs[node.node_id]

    def _term_row(self, node: TrackNode, obs: GroupObservations, gated: BoolArray) -> FloatArray:
        """log c (M,) of the node against every gated cluster (0 elsewhere)."""
        row = np.zeros(len(obs))
        ref = self._reference(node)
        if ref is None:
            return row
        past, shift = ref
        sigma = self.coherence.sigma
        known = self._d_sq
        for j in np.flatnonzero(gated).tolist():
            # the frame's points, in order, are named by their indices: a cluster met
            # again in another observation set (a part a model left whole) is not
            # aligned again
            key = (node.node_id, obs.cluster_members(j).tobytes())
            d_sq = known.get(key)
            if d_sq is None:
                d_sq = known[key] = aligned_distance_sq(
                    past, obs.cluster(j), shift, self.coherence.align, self.coherence.both_ways
                )
            row[j] = coherence_log_likelihood(d_sq, sigma, float(obs.share[j]))
        return row

    def coherence_term(self, node: TrackNode, measurements: GroupObservations, j: int) -> float:
        """log c of ``node`` against cluster ``j`` of ``measurements`` (0 when the term is
        off, the node has no reference snapshot or does not gate ``j``)."""
        if not self.coherence.enabled:
            return 0.0
        self.score([node], measurements)
        term = self._terms.get((node.node_id, id(measurements)))
        return 0.0 if term is None else float(term[j])

    def update(
        self,
        nodes: Sequence[TrackNode],
        measurements: GroupObservations,
        js: Sequence[int],
        stamp: float,
    ) -> list[tuple[FloatArray, FloatArray, Any]]:
        """Kalman update (base class); the observation joins the track's history."""
        out = super().update(nodes, measurements, js, stamp)
        if not self.coherence.enabled:
            return out
        c = self.coherence
        made = []
        for node, j, (mean, cov, payload) in zip(nodes, js, out, strict=True):
            history = push_snapshot(
                group_payload(node).history, stamp, measurements.cluster(j), c.lag, c.step
            )
            merged = group_payload(node).merged_stamp
            made.append((mean, cov, with_payload(payload, history=history, merged_stamp=merged)))
        return made

    def coast(self, node: TrackNode, stamp: float) -> tuple[FloatArray, FloatArray, Any]:
        """The prediction; the history is kept."""
        mean, cov, payload = super().coast(node, stamp)
        if self.coherence.enabled:
            old = group_payload(node)
            payload = with_payload(payload, history=old.history, merged_stamp=old.merged_stamp)
        return mean, cov, payload

    def initiate(
        self, measurements: GroupObservations, js: Sequence[int], stamp: float
    ) -> list[tuple[FloatArray, FloatArray, Any]]:
        """New groups (eq. 16) with their first snapshot."""
        out = super().initiate(measurements, js, stamp)
        if not self.coherence.enabled:
            return out
        return [
            (mean, cov, with_payload(payload, history=((float(stamp), measurements.cluster(j)),)))
            for j, (mean, cov, payload) in zip(js, out, strict=True)
        ]


__all__ = [
    "CoherenceSettings",
    "CoherentGroupModel",
    "GroupPayload",
    "coherence_distance_sq",
    "coherence_log_likelihood",
    "merge_histories",
    "push_snapshot",
    "reference_snapshot",
]
