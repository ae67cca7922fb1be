"""The model level of the group tracker (000 Secs. 4.3-4.5): which split / merge /
continue models branch off a parent hypothesis, the re-prediction of the tracks each model
postulates, the re-clustering of the observations per model, and the label probabilities.

Model generation (Sec. 4.4) is data-driven and binary: a track may split into two only when
two observations fall in its gate (and both halves must then be matched); two tracks may
merge only when one observation falls in both gates; a track takes part in at most one
event per scan. A model is a set of such events with no track in two of them; its prior
P(M | parent) is eq. 32, charged, as in 000's recursion (eq. 35), in every scan for the
model chosen in that scan. How eq. 32 becomes P(M | parent) is a setting
(``model_prior``, :meth:`GroupBranches._model_priors`): printed as is (``"literal"``) it
charges p_C to every continued track, so two tracks that share an observation pay p_C^2
every scan against p_C for the track made by merging them; with p_C only for tracks that
have a choice (``"choice"``) the merged track pays nothing and the pair p_C^2 every scan;
``"normalised"`` divides eq. 32 by its sum over the parent's models, so that the models
of a parent share probability one and continuing two tracks costs only what eq. 27 gives
their merge (docs/groups.md).

Re-clustering (Sec. 4.3): an observation in the gate of more than one of a model's tracks
(not merged by the model) is divided among them by the nearest-track rule: each point goes
to the track with the nearest predicted contour point. The two halves of a split share
their parent's contour and count as one track here (the split itself divides the
observations between them). The model then brings its own partition of the observations
to the MHT core (:class:`~laserpeople.tracking.mht.protocols.BranchObservations`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Collection, Hashable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering import single_linkage
from laserpeople.tracking.groups.labels import merge_labels, split_labels
from laserpeople.tracking.groups.model import (
    GroupModel,
    GroupPayload,
    group_distance_sq,
    group_payload,
    merge_log_likelihood,
    merge_state,
    node_prediction,
    split_state,
    trail_velocity,
    with_trail_velocity,
)
from laserpeople.tracking.groups.observations import GroupObservations, SizeCounting
from laserpeople.tracking.groups.occlusion import FrameShadows
from laserpeople.tracking.mht.protocols import Branch, BranchObservations
from laserpeople.tracking.mht.tracktree import BY_FAMILY, DETECTED, TrackNode, TrackTree

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

MERGED_LABELS_MEMO = 4096
"""Label-set pairs whose merged labels are remembered across scans at most (then all
forgotten); below that, :meth:`GroupBranches.forget_gone` keeps only the pairs of live
label sets."""
MAX_EVENTS = 12
"""Default of :attr:`InteractionSettings.max_events` (the tracker's ``max_events``)."""


@dataclass(frozen=True)
class InteractionSettings:
    """Group formation probabilities and limits (000 Sec. 4.4, 4.6).

    Attributes:
        p_c, p_s, p_g: Priors of continuation, split and merge.
        d_p: Clustering distance d_P [m] (eq. 25).
        d_hs: Blob distance d_hs [m] (re-clustered observations count their blobs).
        split_merge: False for the people-only tracker (continuation only).
        join_observations: Also offer each model with the observations that only one
            continued track gates joined into one (extension).
        max_models: Most models per parent (the likeliest by eq. 32).
        max_events: Candidate events per parent kept for model enumeration (the
            likeliest; at most 2^max_events models are enumerated).
        prune_labels: Relabel a set holding both halves ``X-0``, ``X-1`` of a split ``X``
            when a merge unites them (000 Sec. 4.2.4's optional pruning).
        c0: Initial covariance C_0 (5, 5) (split tracks restart from it).
        recluster_blobs: Re-cluster by blobs instead of points (extension).
        counting: How re-clustered parts count their people (000's blob count if None).
        model_prior: How eq. 32 becomes P(M | parent): "normalised", "choice" or
            "literal" (see :meth:`GroupBranches._model_priors`).
        trail_window: Seconds of observed centroids whose slope is the velocity of eqs.
            25-27 (0: the Kalman filter's, 000; see :meth:`GroupBranches.merge_motion`).
        centroid_std: Std of an observed centroid [m] (the trail velocity's variance).
    """

    p_c: float
    p_s: float
    p_g: float
    d_p: float
    d_hs: float
    split_merge: bool
    max_models: int
    join_observations: bool
    c0: FloatArray
    model_prior: str = "normalised"
    merge_likelihood: str = "density"
    max_events: int = MAX_EVENTS
    prune_labels: bool = True
    recluster_blobs: bool = False
    counting: SizeCounting | None = None
    trail_window: float = 0.0
    centroid_std: float = 0.1


@dataclass(frozen=True, eq=False)
class Event:
    """A candidate split (one track, ``kind`` "split") or merge (two tracks, "merge") and
    its log prior ratio to
    continuing them (p_S / p_C, or p_G N_ij / p_C^2)."""

    kind: str
    tracks: tuple[TrackNode, ...]
    log_ratio: float
    merge_loglik: float = 0.0


def enumerate_models(
    events: Sequence[Event], limit: int, max_events: int = MAX_EVENTS
) -> list[tuple[Event, ...]]:
    """Sets of events no track takes part in twice, the ``limit`` likeliest (by the sum of
    log ratios; the empty set, all continue, is always first among equals), of the
    ``max_events`` likeliest events."""
    ranked = sorted(events, key=lambda e: -e.log_ratio)[:max_events]
    found: list[tuple[float, int, tuple[Event, ...]]] = []

    def rec(k: int, used: frozenset[int], chosen: tuple[Event, ...], score: float) -> None:
        if k == len(ranked):
            found.append((score, len(found), chosen))
            return
        e = ranked[k]
        ids = {t.node_id for t in e.tracks}
        if not ids & used:
            rec(k + 1, used | ids, (*chosen, e), score + e.log_ratio)
        rec(k + 1, used, chosen, score)

    rec(0, frozenset(), (), 0.0)
    found.sort(key=lambda f: (-f[0], len(f[2]), f[1]))
    return [f[2] for f in found[:limit]]


class GroupBranches:
    """The :class:`~laserpeople.tracking.mht.protocols.BranchGenerator` of the group
    tracker. Call :meth:`begin_scan` with the scan's observations before each MHT step.

    Args:
        model: The group track model (gates of re-predicted tracks, Q, C_0).
        tree: The MHT's track tree (ids of the tracks the models make).
        settings: Probabilities and limits.
        name: The label set of a track (names a new group when first needed).
    """

    def __init__(
        self,
        model: GroupModel,
        tree: TrackTree,
        settings: InteractionSettings,
        name: Callable[[TrackNode], tuple[str, ...]],
    ) -> None:
        self.model = model
        self.tree = tree
        self.s = settings
        self.name = name
        self.obs = GroupObservations.empty()
        self._log_pc = math.log(settings.p_c)
        self._log_ps = math.log(settings.p_s)
        self._log_pg = math.log(settings.p_g)
        self._split: dict[int, tuple[TrackNode, TrackNode]] = {}
        self._merged: dict[tuple[int, int], TrackNode] = {}
        self._merge_ll: dict[tuple[int, int], float] = {}
        self._gates: dict[int, BoolArray] = {}
        self._partitions: dict[tuple[Hashable, ...], BranchObservations] = {}
        self._divided: dict[tuple[int, tuple[int, ...]], list[_Piece] | None] = {}
        self._half_of: dict[int, int] = {}  # node id of a split half -> its parent's
        self._rows: dict[int, tuple[BoolArray, int]] = {}  # node id -> gate row, its bits
        self._pending: list[TrackNode] = []  # tracks made and not gated yet
        self._merged_labels: dict[tuple[tuple[str, ...], tuple[str, ...]], tuple[str, ...]] = {}
        self.stamp = math.nan
        self.models_generated = 0

    @property
    def memo_size(self) -> int:
        """Label-set pairs whose merged labels are remembered."""
        return len(self._merged_labels)

    def forget_gone(self, names: Collection[tuple[str, ...]]) -> None:
        """Forget the merged labels of pairs of which a set is not in ``names`` (the label
        sets of the tracks alive in some hypothesis); a pure function of the two sets,
        computed again should such a pair meet again."""
        self._merged_labels = {
            k: v for k, v in self._merged_labels.items() if k[0] in names and k[1] in names
        }

    def begin_scan(self, obs: GroupObservations, stamp: float = math.nan) -> None:
        """Set this scan's observations (and its time [s]) and
        forget the last scan's re-predicted tracks."""
        self.obs = obs
        self.stamp = stamp
        self._split.clear()
        self._merged.clear()
        self._merge_ll.clear()
        self._gates.clear()
        self._partitions.clear()
        self._divided.clear()
        self._half_of.clear()
        self._rows.clear()
        self._pending.clear()

    # ------------------------------------------------------------------ models

    def branches(
        self,
        tracks: tuple[TrackNode, ...],
        gate_row: Callable[[TrackNode], BoolArray],
        meas_idx: NDArray[np.intp],
    ) -> list[Branch]:
        """One branch per model of a parent with ``tracks`` (see the module doc)."""
        known = self._rows  # a node belongs to one cluster of the scan: one row each
        gates: dict[int, BoolArray] = {}
        masks: list[int] = []
        for t in tracks:
            got = known.get(t.node_id)
            if got is None:
                row = gate_row(t)
                got = known[t.node_id] = (row, _bits(row))
            gates[t.node_id] = got[0]
            masks.append(got[1])
        events: list[Event] = []
        if self.s.split_merge and meas_idx.size:
            wide, shared = _gate_events(masks)  # most parents have neither
            if wide:
                for t, mask in zip(tracks, masks, strict=True):
                    if mask.bit_count() >= 2:  # two observations in the gate
                        events.append(Event("split", (t,), self._log_ps - self._log_pc))
            if shared:
                for a in range(len(tracks)):
                    for b in range(a + 1, len(tracks)):
                        if masks[a] & masks[b]:  # one observation in both gates
                            ta, tb = tracks[a], tracks[b]
                            ll = self._merge_loglik(ta, tb)
                            ratio = self._log_pg + ll - 2.0 * self._log_pc
                            events.append(Event("merge", (ta, tb), ratio, ll))
        if not events and self.s.split_merge and not self.s.join_observations:
            # the common case: one model, all continue; no observation is in two gates
            # (that would be a merge event), so nothing is re-clustered
            prior = 0.0 if self.s.model_prior != "literal" else len(tracks) * self._log_pc
            self.models_generated += 1
            return [Branch(prior, tuple(sorted(tracks, key=BY_FAMILY)), 0, None)]
        models = enumerate_models(events, self.s.max_models, self.s.max_events)
        priors = self._model_priors(tracks, events, models)
        out: list[Branch] = []
        mkey = meas_idx.tobytes()
        # every model's tracks first (the tracks splits and merges make are gated together)
        reconfigured = [self._repredict(tracks, chosen) for chosen in models]
        for chosen, prior, new_tracks in zip(models, priors, reconfigured, strict=True):
            obs = self._recluster(new_tracks, chosen, gates, meas_idx, mkey=mkey)
            out.append(Branch(prior, new_tracks, len(out), obs))
            if self.s.join_observations:
                obs = self._recluster(new_tracks, chosen, gates, meas_idx, join=True, mkey=mkey)
                if obs is not None:
                    out.append(Branch(prior, new_tracks, len(out), obs))
        self.models_generated += len(out)
        return out

    def _model_priors(
        self,
        tracks: tuple[TrackNode, ...],
        events: Sequence[Event],
        models: Sequence[tuple[Event, ...]],
    ) -> list[float]:
        """log P(M | parent) of each model (eq. 32, read as ``self.s.model_prior`` says):

        * ``"normalised"``: eq. 32 divided by its sum over the parent's models, so that
          P(M | parent) is a distribution over the models the data allow (eq. 35 needs
          one); a parent whose tracks have no choice has one model of probability 1;
        * ``"choice"``: p_C only for tracks some event could involve, not normalised;
        * ``"literal"``: eq. 32 as printed, p_C for every continued track.
        """
        ratios = [sum(e.log_ratio for e in chosen) for chosen in models]
        if self.s.model_prior == "normalised":
            total = float(np.logaddexp.reduce(ratios)) if ratios else 0.0
            return [r - total for r in ratios]
        if self.s.model_prior == "choice":
            involved = {t.node_id for e in events for t in e.tracks}
            return [len(involved) * self._log_pc + r for r in ratios]
        return [len(tracks) * self._log_pc + r for r in ratios]

    def _merge_loglik(self, a: TrackNode, b: TrackNode) -> float:
        """log N_ij of the pair (eqs. 25-27), once per scan."""
        key = (a.node_id, b.node_id)
        if key not in self._merge_ll:
            pa, pb = group_payload(a), group_payload(b)
            ma, ca = self.merge_motion(a)
            mb, cb = self.merge_motion(b)
            d2 = group_distance_sq(pa.contour, ma, ca, pb.contour, mb, cb, self.s.d_p)
            if self.s.merge_likelihood == "density":
                self._merge_ll[key] = merge_log_likelihood(d2, ca, cb)
            else:  # the compatibility exp(-d^2 / 2), at most 1
                self._merge_ll[key] = -0.5 * d2
        return self._merge_ll[key]

    def merge_motion(self, node: TrackNode) -> tuple[FloatArray, FloatArray]:
        """The predicted state (5,) and covariance (5, 5) of ``node`` that eqs. 25-27
        compare: the Kalman filter's (000), or with ``trail_window`` set and a trail
        spanning half of it, with the velocity from the trail (:func:`trail_velocity`)."""
        mean, cov = node_prediction(node)
        if self.s.trail_window <= 0.0:
            return mean, cov
        got = trail_velocity(
            group_payload(node).trail, 0.5 * self.s.trail_window, self.s.centroid_std
        )
        return (mean, cov) if got is None else with_trail_velocity(mean, cov, *got)

    # ------------------------------------------------------------------ re-prediction

    def _repredict(
        self, tracks: tuple[TrackNode, ...], chosen: tuple[Event, ...]
    ) -> tuple[TrackNode, ...]:
        """The tracks of a model: the parent's, with split tracks replaced by their halves
        and merging pairs by their merged track (made once per scan and shared)."""
        gone: set[int] = set()
        made: list[TrackNode] = []
        for e in chosen:
            gone.update(t.node_id for t in e.tracks)
            if e.kind == "split":
                made.extend(self.split(e.tracks[0]))
            else:
                made.append(self.merge(e.tracks[0], e.tracks[1]))
        kept = [t for t in tracks if t.node_id not in gone]
        return tuple(sorted((*kept, *made), key=BY_FAMILY))

    def split(self, node: TrackNode) -> tuple[TrackNode, TrackNode]:
        """The two predicted tracks ``node`` splits into (000 Sec. 4.2.3): copies of its
        prediction with n/2 people each, C_0, its contour, labels X-0 and X-1."""
        if node.node_id not in self._split:
            mean, _ = node_prediction(node)
            pm, pc = split_state(mean, self.s.c0)
            old = group_payload(node)
            halves = []
            for labels in split_labels(self.name(node)):
                payload = GroupPayload(old.contour, labels, must_match=True, event="split")
                halves.append(self._made(node, pm, pc, payload))
            self._split[node.node_id] = (halves[0], halves[1])
            for half in halves:
                self._half_of[half.node_id] = node.node_id
        return self._split[node.node_id]

    def merge(self, a: TrackNode, b: TrackNode) -> TrackNode:
        """The predicted track of ``a`` and ``b`` merged (eqs. 17-18): contour the union,
        labels the union (pruned)."""
        key = (a.node_id, b.node_id)
        if key not in self._merged:
            pa, pb = group_payload(a), group_payload(b)
            ma, ca = node_prediction(a)
            mb, cb = node_prediction(b)
            na, nb = max(len(pa.contour), 1), max(len(pb.contour), 1)
            pm, pc = merge_state(ma, ca, na, mb, cb, nb)
            points = np.concatenate([pa.contour + ma[:2], pb.contour + mb[:2]])
            names = (self.name(a), self.name(b))
            labels = self._merged_labels.get(names)
            if labels is None:  # a pure function of the two sets, remembered over scans
                if len(self._merged_labels) >= MERGED_LABELS_MEMO:
                    self._merged_labels.clear()
                labels = self._merged_labels[names] = merge_labels(
                    *names, prune=self.s.prune_labels
                )
            payload = GroupPayload(
                points - pm[:2],
                labels,
                must_match=True,
                event="merge",
            )
            self._merged[key] = self._made(a, pm, pc, payload)
        return self._merged[key]

    def _made(
        self, parent: TrackNode, mean: FloatArray, cov: FloatArray, payload: GroupPayload
    ) -> TrackNode:
        node = TrackNode(
            node_id=self.tree.new_node_id(),
            family=self.tree.new_family(),
            parent_id=parent.node_id,
            mean=mean,
            cov=cov,
            stamp=parent.stamp,
            label=DETECTED,
            hits=parent.hits,
            age=parent.age,
            payload=payload,
            detected_stamp=parent.detected_stamp,
        )
        node.pred_mean, node.pred_cov = mean, cov
        self._pending.append(node)
        return node

    # ------------------------------------------------------------------ re-clustering

    def _gate(
        self, node: TrackNode, gates: dict[int, BoolArray], meas_idx: NDArray[np.intp]
    ) -> BoolArray:
        row = gates.get(node.node_id)
        if row is not None:
            return row
        if node.node_id not in self._gates:
            # with every track made since the last gating, each scored as if alone
            pending = [n for n in self._pending if n.node_id not in self._gates]
            self._pending.clear()
            if all(n.node_id != node.node_id for n in pending):
                pending.append(node)
            self.model.score_apart(pending, self.obs)
            for n in pending:
                self._gates[n.node_id] = self.model.score([n], self.obs)[0][0]
        return self._gates[node.node_id][meas_idx]

    def _gate_bits(
        self, node: TrackNode, gates: dict[int, BoolArray], meas_idx: NDArray[np.intp]
    ) -> int:
        """:meth:`_gate` as the bits of an int (bit i: observation ``meas_idx[i]``)."""
        got = self._rows.get(node.node_id)
        if got is None:
            row = self._gate(node, gates, meas_idx)
            got = self._rows[node.node_id] = (row, _bits(row))
        return got[1]

    def _recluster(
        self,
        tracks: tuple[TrackNode, ...],
        chosen: tuple[Event, ...],
        gates: dict[int, BoolArray],
        meas_idx: NDArray[np.intp],
        join: bool = False,
        mkey: bytes | None = None,
    ) -> BranchObservations | None:
        """The model's partition of the cluster's observations, or None when it is the
        cluster's own: an observation in the gates of two of its tracks is divided among
        them (Sec. 4.3); with ``join``, the observations in the gate of one continued
        track and of no other track are joined into one (the extension, see the module
        doc). The division of an observation among given tracks and the partition made
        of a given list of parts are computed once per scan and shared by the models of
        all parents."""
        if meas_idx.size == 0 or not tracks:
            return None
        # units: a split's two halves are one; every other track is its own
        halves = self._half_of
        units: dict[int, list[TrackNode]] = {}
        for t in tracks:
            units.setdefault(halves.get(t.node_id, t.node_id), []).append(t)
        unit_list = list(units.values())
        if not join:  # is any observation in the gates of two units?
            seen = twice = 0
            for unit in unit_list:
                mask = 0
                for t in unit:
                    mask |= self._gate_bits(t, gates, meas_idx)
                twice |= seen & mask
                seen |= mask
            if not twice:
                return None
        unit_gate = np.empty((len(unit_list), meas_idx.size), dtype=bool)
        for u, unit in enumerate(unit_list):
            unit_gate[u] = self._gate(unit[0], gates, meas_idx)
            for t in unit[1:]:
                unit_gate[u] |= self._gate(t, gates, meas_idx)
        n_gating = unit_gate.sum(axis=0)
        shared_idx = np.nonzero(n_gating >= 2)[0]
        joined: dict[int, list[int]] = {}  # first local index -> local indices joined
        if join:
            for u, unit in enumerate(unit_list):
                if len(unit) > 1:
                    continue  # split halves take their observations one each
                mine = np.nonzero(unit_gate[u] & (n_gating == 1))[0].tolist()
                if len(mine) >= 2:
                    joined[mine[0]] = mine
            if not joined:
                return None
        elif shared_idx.size == 0:
            return None
        shared = set(shared_idx.tolist())
        skip = {i for group in joined.values() for i in group[1:]}
        js = meas_idx.tolist()
        keys: list[Hashable] = []
        # per item: its scan observation, and its pieces (divided) or members (joined)
        plan: list[tuple[int, list[_Piece] | None, list[int] | None]] = []
        changed = False
        for i, j in enumerate(js):
            if i in skip:
                continue
            if i in joined:
                together = [js[x] for x in joined[i]]
                keys.append(("joined", *together))
                plan.append((j, None, together))
                changed = True
                continue
            if i in shared:
                near = [unit_list[u] for u in np.nonzero(unit_gate[:, i])[0].tolist()]
                pieces = self._divide(j, near)
                if pieces is not None:
                    changed = True
                    keys.extend(p[4] for p in pieces)
                    plan.append((j, pieces, None))
                    continue
            keys.append(j)
            plan.append((j, None, None))
        if not changed:
            return None
        key = tuple(keys)
        found = self._partitions.get(key)
        if found is not None:
            return found
        parts: list[tuple[FloatArray, IntArray]] = []
        rows: list[IntArray] = []
        shares: list[float] = []
        origin: list[int] = []
        offsets = self.obs.offsets
        for j, divided, members in plan:
            if divided is None and members is None:
                parts.append((self.obs.cluster(j), self.obs.cluster_members(j)))
                rows.append(np.arange(offsets[j], offsets[j + 1], dtype=np.int64))
                shares.append(1.0)
                origin.append(j)
            elif divided is not None:  # the pieces of a divided observation
                for pts, mem, own, share, _ in divided:
                    parts.append((pts, mem))
                    rows.append(own)
                    shares.append(share)
                    origin.append(j)
            elif members is not None:  # observations joined into one
                parts.append(
                    (
                        np.concatenate([self.obs.cluster(x) for x in members]),
                        np.concatenate([self.obs.cluster_members(x) for x in members]),
                    )
                )
                rows.append(
                    np.concatenate([np.arange(offsets[x], offsets[x + 1]) for x in members]).astype(
                        np.int64
                    )
                )
                shares.append(float(len(members)))
                origin.append(j)
        made = BranchObservations(
            GroupObservations.from_parts(
                parts,
                self.s.d_hs,
                shares,
                rows,
                self.s.counting,
                None if self.obs.blobs is None else self.obs.blobs[np.concatenate(rows)],
                None if self.obs.spacing is None else self.obs.spacing[np.concatenate(rows)],
            ),
            key,
            tuple(origin),
        )
        self._partitions[key] = made
        return made

    def _divide(self, j: int, near: list[list[TrackNode]]) -> list[_Piece] | None:
        """The pieces of scan observation ``j`` divided among the units ``near`` by the
        nearest-track rule (Sec. 4.3), or None when every point goes to one unit; once
        per scan for each observation and list of units."""
        key = (j, tuple(unit[0].node_id for unit in near))
        if key in self._divided:
            return self._divided[key]
        pts, mem = self.obs.cluster(j), self.obs.cluster_members(j)
        first = int(self.obs.offsets[j])
        own = np.arange(first, first + len(mem), dtype=np.int64)
        owner = _nearest_unit(pts, near)
        if self.s.recluster_blobs:
            if self.obs.blobs is None:
                blobs = single_linkage(pts, self.s.d_hs)
            else:
                blobs = np.unique(self.obs.blobs[own], return_inverse=True)[1]
            owner = _blob_majority(owner, blobs.astype(np.int64))
        counts = np.bincount(owner)
        labels = np.flatnonzero(counts)  # the units given points, ascending
        pieces: list[_Piece] | None = None
        if labels.size >= 2:
            pieces = []
            for u, k in zip(labels.tolist(), counts[labels].tolist(), strict=True):
                sel = owner == u
                mine = mem[sel]
                pieces.append((pts[sel], mine, own[sel], float(k) / len(mem), (j, mine.tobytes())))
        self._divided[key] = pieces
        return pieces


def _gate_events(masks: Sequence[int]) -> tuple[bool, bool]:
    """Whether some gate (bits of an int, one per observation) holds two observations
    (a split may be), and whether some observation is in two gates (a merge may be:
    the gates' bits overlap exactly when their counts add up to more than their
    union's)."""
    union = counted = most = 0
    for mask in masks:
        union |= mask
        bits = mask.bit_count()
        counted += bits
        most = max(most, bits)
    return most >= 2, counted > union.bit_count()


def _bits(row: BoolArray) -> int:
    """A boolean row (m,) as an int with bit i set where ``row[i]``."""
    if row.size > 64:
        return int.from_bytes(np.packbits(row, bitorder="little").tobytes(), "little")
    out = 0
    for i, x in enumerate(row.tolist()):  # a few items: faster than numpy's packbits
        if x:
            out |= 1 << i
    return out


_Piece = tuple[FloatArray, IntArray, IntArray, float, Hashable]
"""A piece of a divided observation: points (K, 2), frame point indices (K,), rows in the
scan's observations (K,), share of the observation, key."""


def _blob_majority(owner: IntArray, blobs: IntArray) -> IntArray:
    """Each point's owner (K,) replaced by the owner most of its blob's points have
    (``blobs`` (K,) labels 0..B-1; ties to the lower owner index)."""
    n_units = int(owner.max()) + 1
    votes = np.zeros((int(blobs.max()) + 1, n_units), dtype=np.int64)
    np.add.at(votes, (blobs, owner), 1)
    return np.asarray(np.argmax(votes, axis=1)[blobs], dtype=np.int64)


def _nearest_unit(points: FloatArray, units: Sequence[Sequence[TrackNode]]) -> IntArray:
    """Index into ``units`` (K,) of the unit whose predicted contour point is nearest to
    each point (Euclidean; the nearest-neighbour rule of 000 Sec. 4.3; a tie goes to the
    first unit). One matrix of squared distances from every point to every unit's
    contour points, its minima per unit, and the unit of the least."""
    contours = []
    for unit in units:
        node = unit[0]
        mean, _ = node_prediction(node)
        contour = group_payload(node).contour + mean[:2]
        contours.append(contour if contour.shape[0] else mean[None, :2])
    sizes = np.array([c.shape[0] for c in contours], dtype=np.int64)
    cols = np.concatenate(contours)
    dx = np.subtract.outer(points[:, 0], cols[:, 0])
    dy = np.subtract.outer(points[:, 1], cols[:, 1])
    d = np.multiply(dx, dx, out=dx)
    d += np.multiply(dy, dy, out=dy)
    per_unit = np.minimum.reduceat(d, np.cumsum(sizes) - sizes, axis=1)  # (K, U)
    return np.asarray(np.argmin(per_unit, axis=1), dtype=np.int64)


class GroupLabelModel:
    """Assignment probabilities of 000 eqs. 36-37: matched p_M, occluded p_O, obsolete p_T
    for tracks; new and false alarm for observations. Eq. 36 gives them as p_N = lambda_N V
    and p_F = lambda_F V, eq. 37 a likelihood 1/V each: their product leaves the rates
    lambda = p / V [1/m^2], against the likelihoods N_i of matched observations (eq. 24,
    a density in 1/m^2), as the leg tracker's lambda_new and lambda_fal. ``area`` is V
    [m^2]; the tracker sets it per scan when the observation area is the lasers' view. A
    split or merged track of this scan must be matched (000 Sec. 4.4).

    With ``shadowed`` probabilities (p_M, p_O, p_T) and a scan's :attr:`shadows` set, a
    track detected in at least ``shadow_hits`` scans whose predicted contour lies wholly
    in the shadow of closer returns takes those instead (000 Sec. 3.3.1's adaptive
    occlusion probabilities, :mod:`.occlusion`)."""

    def __init__(
        self,
        p_m: float,
        p_o: float,
        p_t: float,
        p_n: float,
        p_f: float,
        area: float = 1.0,
        shadowed: tuple[float, float, float] | None = None,
        shadow_margin: float = 0.0,
        shadow_hits: int = 1,
    ) -> None:
        self._lp = np.log(np.array([p_m, p_o, p_t]))
        self._must = np.array([math.log(p_m), -np.inf, -np.inf])
        self._log_p_new = math.log(p_n)
        self._log_p_fal = math.log(p_f)
        self.area = area
        """V of eqs. 36-37 [m^2]."""
        self._shadow_lp = None if shadowed is None else np.log(np.array(shadowed))
        self._margin = shadow_margin
        self._hits = shadow_hits
        self._shadows: FrameShadows | None = None
        self._in_shadow: dict[int, bool] = {}  # node id -> shadowed, this scan
        self.stamp = -math.inf
        """Time [s] of the scan being tracked: a node of an earlier scan is tested at its
        prediction, one of this scan at its state."""

    @property
    def shadows(self) -> FrameShadows | None:
        """What the lasers of the scan being tracked saw (None: no track is shadowed)."""
        return self._shadows

    @shadows.setter
    def shadows(self, value: FrameShadows | None) -> None:
        self._shadows = value
        self._in_shadow.clear()

    def track_log_probs(self, nodes: Sequence[TrackNode]) -> FloatArray:
        """(T, 3) log p of matched/occluded/obsolete per track."""
        must = np.array([group_payload(n).must_match for n in nodes], dtype=bool)
        out = np.where(must[:, None], self._must[None, :], self._lp[None, :])
        if self._shadow_lp is not None and self._shadows is not None:
            rows = [i for i, n in enumerate(nodes) if not must[i] and n.hits >= self._hits]
            self._test([nodes[i] for i in rows])
            hidden = [i for i in rows if self._in_shadow[nodes[i].node_id]]
            out[hidden] = self._shadow_lp
        return out

    def in_shadow(self, node: TrackNode) -> bool:
        """True when every point of ``node``'s contour, at its predicted position (its
        own for a node of this scan), lies behind a closer return of this scan."""
        if self._shadows is None:
            return False
        self._test([node])
        return self._in_shadow[node.node_id]

    def _test(self, nodes: Sequence[TrackNode]) -> None:
        """Test the contours of those of ``nodes`` not tested this scan (one batch)."""
        assert self._shadows is not None
        todo = [n for n in nodes if n.node_id not in self._in_shadow]
        if not todo:
            return
        parts = []
        for node in todo:
            at = node.mean if node.stamp >= self.stamp or node.pred_mean is None else node.pred_mean
            contour = group_payload(node).contour
            parts.append(contour + at[:2] if len(contour) else at[None, :2])
        counts = np.array([len(x) for x in parts])
        flags = self._shadows.shadowed_sets(np.concatenate(parts), counts, self._margin)
        self._in_shadow.update(zip((n.node_id for n in todo), flags.tolist(), strict=True))

    def measurement_log_rates(
        self, measurements: GroupObservations
    ) -> tuple[FloatArray, FloatArray]:
        """log lambda_N = log(p_N / V) and log lambda_F = log(p_F / V) (M,) for every
        observation."""
        m = len(measurements)
        log_v = math.log(self.area)
        return np.full(m, self._log_p_new - log_v), np.full(m, self._log_p_fal - log_v)
