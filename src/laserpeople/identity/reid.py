"""Re-identification of people after crossings by the colour of their clothes (002 Sec. 2).

:class:`ColourReidentifier` is a pipeline stage after any tracker:
``update(tracks, frame) -> Tracks`` returns the same tracks with each person track's id
replaced by a persistent *identity*. It works on the tracker's output only, so it serves
the CSA, the leg MHT or a group tracker alike:

- While a person walks alone (no other person track within ``clean_distance``), its colour
  measurements (hue histograms of the frame's :class:`~laserpeople.frame.AppearanceObservation`
  s, matched to tracks by position) are learnt with the online mean and covariance of 002
  eqs. 1-5.
- A *crossing* starts when person tracks come closer than ``interaction_distance``, or a
  ``group`` track (a CSA cluster) holds them; learning stops for everyone involved (002:
  "as soon as the tracking algorithm detects a crossing, the algorithm stops to learn"),
  and the stage remembers which identities take part. A track that a tracker starts
  afresh near a crossing in progress, or near where an identity was lost, joins it as a
  candidate.
- The crossing ends when no group holds its tracks any more and they are pairwise farther
  apart than ``separation_distance`` (002 split condition 2). From then on the colour
  log-likelihoods (eq. 6, in log space) of every clean observation of every candidate track
  are summed per identity (eq. 7), and once there are as many tracks as identities with
  ``min_observations`` each (or ``max_wait`` after the end) the identities are re-assigned
  by the Hungarian algorithm maximising eq. 8.

Until then every track keeps the identity it had (a new track gets a free identity of its
crossing, or a fresh one).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from types import MappingProxyType

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.frame import Frame, FrameField
from laserpeople.identity.appearance import (
    AppearanceParams,
    OnlineGaussian,
    assign_identities,
    assignment_margin,
    log_likelihoods,
    measurement,
)
from laserpeople.lazy_scipy import linear_sum_assignment
from laserpeople.tracks import Track, Tracks

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class ReidParams:
    """Parameters of colour re-identification (002 Sec. 2)."""

    config_section = "reid"
    # 002 re-assigns after the crossing and stops learning only when the tracker sees one
    paper_preset = MappingProxyType({"early": False, "crowded_views": False})

    interaction_distance: float = param(
        1.2,
        "assumption: where the CSA's gates (about 0.5 m around each person) start to share points",
        "person tracks closer than this are crossing",
        "m",
    )
    separation_distance: float = param(
        3.0,
        "002 Sec. 2, split condition 2 (300 cm)",
        "a crossing ends when its tracks are pairwise farther apart than this",
        "m",
    )
    clean_distance: float = param(
        1.0,
        "assumption: a nearer person can leak into the camera region",
        "an observation is used only when no other person track is this close",
        "m",
    )
    observation_gate: float = param(
        0.6,
        "assumption",
        "largest distance between an observation and the track it is matched to",
        "m",
    )
    min_observations: int = param(
        3,
        "assumption (002 sums eq. 7 over k1..k2 without a number)",
        "clean observations per track before the identities of a crossing are re-assigned",
    )
    max_wait: float = param(
        3.0,
        "assumption",
        "after the crossing ends, re-assign at the latest after this even with fewer observations",
        "s",
    )
    rejoin_distance: float = param(
        2.0,
        "assumption",
        "a new track this close to a crossing or to a lost identity's last position is a "
        "candidate for its identities",
        "m",
    )
    lost_memory: float = param(
        5.0, "assumption", "how long a lost identity may be taken up again", "s"
    )
    early: bool = param(
        True,
        "extension of 002 (which re-assigns once the crossing ends, split condition 2; "
        "false restores it): crossing-3 seed 7, docs/csa.md",
        "also re-assign while a crossing goes on, as soon as each of its tracks has "
        "min_observations clean observations since it was last near another person",
    )
    decision_margin: float = param(
        10.0,
        "extension of 002 (a sequential likelihood-ratio test on eq. 7): crossing-3 seeds "
        "100-104, docs/csa.md",
        "with early: the identities of a crossing's tracks that have clean observations are "
        "re-assigned once the best assignment's summed log-likelihood beats the second best "
        "by this much (a likelihood ratio of e^margin)",
        "log-likelihood",
    )
    crowded_views: bool = param(
        True,
        "extension of 002 (which stops learning when the tracker detects a crossing; false "
        "restores it): crossing-3 seeds 7, 10-11, docs/csa.md",
        "an observation with another person seen by the camera within clean_distance is "
        "not clean either (the tracker may have lost that person)",
    )
    appearance: AppearanceParams = param(  # noqa: RUF009 (a frozen default instance)
        AppearanceParams(), "nested table appearance.*", "colour measurements"
    )

    def __post_init__(self) -> None:
        for name in (
            "interaction_distance",
            "separation_distance",
            "clean_distance",
            "observation_gate",
            "rejoin_distance",
            "lost_memory",
        ):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be positive")
        if self.min_observations < 1 or self.max_wait < 0:
            raise ValueError("min_observations must be >= 1 and max_wait >= 0")


@dataclass
class _Crossing:
    identities: set[int]
    tracks: set[int]
    centre: FloatArray
    ended_at: float | None = None
    loglik: dict[int, dict[int, float]] = field(default_factory=dict)  # track -> id -> sum
    n_obs: dict[int, int] = field(default_factory=dict)


@dataclass(frozen=True)
class Reassignment:
    """One re-assignment after a crossing (for inspection and tests).

    Attributes:
        stamp: Time [s].
        identities: The identities of the crossing.
        assignment: Track id -> identity given.
    """

    stamp: float
    identities: tuple[int, ...]
    assignment: dict[int, int]


class ColourReidentifier:
    """Re-identifies people after crossings from colour observations (002 Sec. 2).

    Attributes:
        models: Identity -> its learnt colour Gaussian (002 eqs. 1-5).
        reassignments: Every re-assignment so far.
    """

    consumes: frozenset[FrameField] = frozenset({"appearance"})

    def __init__(self, params: ReidParams | None = None) -> None:
        self.params = params or ReidParams()
        self.models: dict[int, OnlineGaussian] = {}
        self.reassignments: list[Reassignment] = []
        self._identity: dict[int, int] = {}  # track id -> identity
        self._crossings: list[_Crossing] = []
        self._lost: dict[int, tuple[FloatArray, float]] = {}  # identity -> (position, stamp)
        self._last_pos: dict[int, FloatArray] = {}  # track id -> position
        self._absent: dict[int, float] = {}  # track id -> when it vanished
        self._next = 0

    # ------------------------------------------------------------------
    def _fresh(self) -> int:
        ident = self._next
        self._next += 1
        self.models[ident] = OnlineGaussian(self.params.appearance.bins)
        return ident

    def update(self, tracks: Tracks, frame: Frame) -> Tracks:
        """Map the person tracks of ``tracks`` to identities, learning and re-assigning
        with ``frame.appearance``."""
        p = self.params
        stamp = tracks.stamp
        persons = tracks.of_kind("person")
        groups = tracks.of_kind("group")
        ids = [t.track_id for t in persons]
        pos = np.array([t.position for t in persons]).reshape(-1, 2)
        grouped = {m for g in groups for m in g.members}
        self._forget(set(ids) | grouped, stamp)
        self._adopt_new(persons, stamp)
        d = np.linalg.norm(pos[:, None] - pos[None], axis=-1) + np.diag(np.full(len(ids), np.inf))
        clean = (d >= p.clean_distance).all(axis=1) if ids else np.zeros(0, dtype=bool)
        self._start_crossings(ids, pos, d, groups)
        obs, crowded = self._match_observations(pos, frame)
        if p.crowded_views:
            clean &= ~crowded
        in_crossing = {t for c in self._crossings for t in c.tracks}
        for k, tid in enumerate(ids):
            y = obs[k]
            if p.early and (not clean[k] or tid in grouped):
                self._forget_evidence(tid)  # near another: it may have swapped since
            if y is None or not clean[k] or tid in grouped:
                continue
            if tid in in_crossing:
                self._accumulate(tid, y)
            else:
                self.models[self._identity[tid]].add(y)
        self._finish_crossings(ids, pos, grouped, stamp)
        for tid, xy in zip(ids, pos, strict=True):
            self._last_pos[tid] = xy
        return self._relabel(tracks)

    # ------------------------------------------------------------------
    def _forget(self, here: set[int], stamp: float) -> None:
        """Tracks that vanished leave their identity lost (unless a crossing holds it); a
        track that comes back keeps its identity unless another track took it meanwhile;
        tracks gone for longer than ``lost_memory`` are forgotten."""
        held = {i for c in self._crossings for i in c.identities}
        memory = self.params.lost_memory
        present_ids = {self._identity[t] for t in here if t in self._identity}
        for tid in list(self._identity):
            ident = self._identity[tid]
            if tid in here:
                if self._absent.pop(tid, None) is not None:
                    taken = any(
                        self._identity[o] == ident for o in here if o != tid and o in self._identity
                    )
                    if taken:
                        self._identity[tid] = self._fresh()
                    self._lost.pop(ident, None)
                continue
            if tid not in self._absent:
                self._absent[tid] = stamp
                if tid in self._last_pos and ident not in held and ident not in present_ids:
                    self._lost[ident] = (self._last_pos[tid], stamp)
            elif stamp - self._absent[tid] > memory:
                del self._identity[tid], self._absent[tid]
                self._last_pos.pop(tid, None)
                for c in self._crossings:
                    c.tracks.discard(tid)
        for ident in [i for i, (_, t) in self._lost.items() if stamp - t > memory]:
            del self._lost[ident]

    def _adopt_new(self, persons: tuple[Track, ...], stamp: float) -> None:
        """Give new tracks an identity: a free one of a crossing or of a lost person nearby
        (and make them candidates of that crossing), else a fresh one."""
        p = self.params
        used = {self._identity[t.track_id] for t in persons if t.track_id in self._identity}
        for t in persons:
            if t.track_id in self._identity:
                continue
            near = [c for c in self._crossings if self._near(c, t.position, persons)]
            if near:
                c = near[0]
            else:
                lost = [
                    i
                    for i, (xy, _) in self._lost.items()
                    if i not in used and np.linalg.norm(xy - t.position) < p.rejoin_distance
                ]
                if lost:
                    c = _Crossing({lost[0]}, set(), t.position.copy(), ended_at=stamp)
                    self._crossings.append(c)
                else:
                    ident = self._fresh()
                    self._identity[t.track_id] = ident
                    used.add(ident)
                    continue
            free = sorted(i for i in c.identities if i not in used)
            ident = free[0] if free else self._fresh()
            self._lost.pop(ident, None)
            c.identities.add(ident)
            c.tracks.add(t.track_id)
            self._identity[t.track_id] = ident
            used.add(ident)

    def _near(self, c: _Crossing, xy: FloatArray, persons: tuple[Track, ...]) -> bool:
        """Whether a new track at ``xy`` may be one of the people of crossing ``c``: within
        the rejoin distance of its centre or of where one of its tracks vanished, or, while
        it has fewer tracks than people, within the separation distance of the centre of
        its tracks' latest positions (its people spread at most that far before it ends)."""
        p = self.params
        if np.linalg.norm(c.centre - xy) < p.rejoin_distance:
            return True
        absent = [self._last_pos[t] for t in c.tracks if t in self._absent and t in self._last_pos]
        if any(np.linalg.norm(a - xy) < p.rejoin_distance for a in absent):
            return True
        present = [t.position for t in persons if t.track_id in c.tracks]
        if len(present) >= len(c.identities) or not present + absent:
            return False
        centre = np.mean(present + absent, axis=0)
        return bool(np.linalg.norm(centre - xy) < max(p.rejoin_distance, p.separation_distance))

    def _start_crossings(
        self, ids: list[int], pos: FloatArray, d: FloatArray, groups: tuple[Track, ...]
    ) -> None:
        """Open (or grow) crossings of tracks closer than the interaction distance or held
        by one group track."""
        links: list[set[int]] = []
        close = np.argwhere(np.triu(d < self.params.interaction_distance, 1))
        links.extend({ids[a], ids[b]} for a, b in close)
        links.extend(
            {m for m in g.members if m in self._identity} for g in groups if len(g.members) > 1
        )
        index = {tid: k for k, tid in enumerate(ids)}
        for link in links:
            if len(link) < 2:
                continue
            joined = [c for c in self._crossings if c.tracks & link]
            tracks = set(link).union(*[c.tracks for c in joined])
            identities = {self._identity[t] for t in link}.union(*[c.identities for c in joined])
            xy = [pos[index[t]] if t in index else self._last_pos[t] for t in tracks]
            centre = np.mean(xy, axis=0)
            for c in joined:
                self._crossings.remove(c)
            merged = _Crossing(identities, tracks, centre)
            for c in joined:
                for tid, row in c.loglik.items():
                    merged.loglik.setdefault(tid, {}).update(row)
            self._crossings.append(merged)

    def _match_observations(
        self, pos: FloatArray, frame: Frame
    ) -> tuple[list[FloatArray | None], NDArray[np.bool_]]:
        """The colour measurement of each track (None where no observation matches), and
        whether the observation matched to it has another person seen by the camera within
        ``clean_distance`` (someone the tracker may not track at that moment)."""
        p = self.params
        out: list[FloatArray | None] = [None] * pos.shape[0]
        crowded = np.zeros(pos.shape[0], dtype=bool)
        seen = np.array([o.position for o in frame.appearance]).reshape(-1, 2)
        views = [(k, measurement(o.hues, p.appearance)) for k, o in enumerate(frame.appearance)]
        views = [(k, y) for k, y in views if y is not None]
        if not views or not pos.size:
            return out, crowded
        vxy = seen[[k for k, _ in views]]
        dist = np.linalg.norm(pos[:, None] - vxy[None], axis=-1)
        cost = np.where(dist <= p.observation_gate, dist, 1e6)
        rows, cols = linear_sum_assignment(cost)
        for r, c in zip(rows, cols, strict=True):
            if dist[r, c] <= p.observation_gate:
                k, y = views[int(c)]
                out[int(r)] = y
                others = np.delete(seen, k, axis=0)
                near = np.linalg.norm(others - seen[k], axis=1) < p.clean_distance
                crowded[int(r)] = bool(near.any())
        return out, crowded

    def _forget_evidence(self, tid: int) -> None:
        """Drop the colour evidence of track ``tid`` in its crossings."""
        for c in self._crossings:
            c.loglik.pop(tid, None)
            c.n_obs.pop(tid, None)

    def _accumulate(self, tid: int, y: FloatArray) -> None:
        """Add one clean observation of a crossing's track to eq. 7 (after the crossing, or
        with ``early`` whenever the track is clean)."""
        for c in self._crossings:
            if tid not in c.tracks or (c.ended_at is None and not self.params.early):
                continue
            idents = sorted(i for i in c.identities if self.models[i].k >= 2)
            if not idents:
                continue
            fl = self.params.appearance.covariance_floor
            ll = log_likelihoods(
                y[None],
                np.array([self.models[i].mean for i in idents]),
                np.array([self.models[i].covariance for i in idents]),
                fl,
            )[:, 0]
            row = c.loglik.setdefault(tid, {})
            for i, v in zip(idents, ll, strict=True):
                row[i] = row.get(i, 0.0) + float(v)
            c.n_obs[tid] = c.n_obs.get(tid, 0) + 1

    def _finish_crossings(
        self, ids: list[int], pos: FloatArray, grouped: set[int], stamp: float
    ) -> None:
        """Detect the end of each crossing; re-assign its identities once observed."""
        p = self.params
        index = {tid: k for k, tid in enumerate(ids)}
        for c in list(self._crossings):
            present = [t for t in c.tracks if t in index]
            if p.early and len(c.identities) >= 2:
                self._decide_early(c, present, stamp)
            if c.tracks & grouped or not present:
                c.ended_at = None
                continue
            xy = pos[[index[t] for t in present]]
            c.centre = xy.mean(axis=0)
            dd = np.linalg.norm(xy[:, None] - xy[None], axis=-1)
            apart = bool((dd[np.triu_indices(len(present), 1)] > p.separation_distance).all())
            if not apart:
                c.ended_at = None
                continue
            if c.ended_at is None:
                c.ended_at = stamp
                continue
            enough = all(c.n_obs.get(t, 0) >= p.min_observations for t in present)
            complete = len(present) >= len(c.identities)
            if (enough and complete) or stamp - c.ended_at >= p.max_wait:
                self._reassign(c, present, stamp)
                self._crossings.remove(c)

    def _decide_early(self, c: _Crossing, present: list[int], stamp: float) -> None:
        """Re-assign while the crossing goes on: the tracks with clean observations since
        they were last near someone take the identities of the best assignment (002 eq. 8
        over them) once it beats the second best by ``decision_margin``; a track without
        such observations whose identity was given away takes one left over, if any (else,
        should it come back, it gets a new one, see :meth:`_forget`). The evidence is
        kept (it speaks of the track, whatever identity it holds): the decision is taken
        again with each new observation; nothing is recorded when no identity changes."""
        ready = [t for t in present if c.n_obs.get(t, 0) > 0]
        idents = sorted(i for i in c.identities if self.models[i].k >= 2)
        if not ready or len(ready) > len(idents):
            return
        cost = np.array([[-c.loglik.get(t, {}).get(i, 0.0) for t in ready] for i in idents])
        rows, cols, margin = assignment_margin(cost)
        if margin < self.params.decision_margin:
            return
        given = {ready[int(j)]: idents[int(i)] for i, j in zip(rows, cols, strict=True)}
        left = [i for i in idents if i not in given.values()]
        for tid in sorted(c.tracks - set(ready)):
            if self._identity.get(tid) in given.values() and left:
                given[tid] = left.pop(0)
        if all(self._identity.get(t) == i for t, i in given.items()):
            return
        self._identity.update(given)
        self.reassignments.append(Reassignment(stamp, tuple(idents), dict(given)))

    def _reassign(self, c: _Crossing, present: list[int], stamp: float) -> None:
        """Hungarian re-assignment of a crossing's identities to its tracks once the
        crossing ended (002 eq. 8)."""
        idents = sorted(c.identities)
        cost = np.zeros((len(idents), len(present)))
        for j, tid in enumerate(present):
            row = c.loglik.get(tid, {})
            for i, ident in enumerate(idents):
                cost[i, j] = -row.get(ident, 0.0)
        rows, cols = assign_identities(cost)
        given = {present[int(j)]: idents[int(i)] for i, j in zip(rows, cols, strict=True)}
        taken = set(given.values())
        for tid in present:
            if tid not in given:  # more tracks than identities: a new person
                cur = self._identity[tid]
                given[tid] = cur if cur not in taken else self._fresh()
                taken.add(given[tid])
        # identities outside this crossing held by its tracks stay with nobody else
        self._identity.update(given)
        for ident in idents:
            if ident not in taken:
                where = [
                    self._last_pos[t]
                    for t in c.tracks
                    if self._identity.get(t) == ident and t in self._last_pos
                ]
                self._lost[ident] = (where[0] if where else c.centre, stamp)
        self.reassignments.append(Reassignment(stamp, tuple(idents), dict(given)))

    def _relabel(self, tracks: Tracks) -> Tracks:
        out: list[Track] = []
        seen: set[int] = set()
        for t in tracks:
            if t.kind == "person":
                ident = self._identity[t.track_id]
                if ident in seen:  # two tracks on one identity: the second gets a new one
                    ident = self._fresh()
                    self._identity[t.track_id] = ident
                seen.add(ident)
                out.append(replace(t, track_id=ident))
            elif t.kind == "group":
                members = tuple(self._identity.get(m, m) for m in t.members)
                out.append(replace(t, members=members))
            else:
                out.append(t)
        return replace(tracks, tracks=tuple(out))
