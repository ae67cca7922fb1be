"""Re-identification of people lost for long by their leg widths, after any point tracker.

The leg MHT keeps the identity of a person who leaves the view and comes back
(:mod:`laserpeople.tracking.reidentify`); trackers of raw points (``csa``, ``feet-pf``,
``upper-body-pf``) give such a person a new id. :class:`LegWidthReidentifier` is an
identify stage after them: ``update(tracks, frame) -> Tracks`` returns the tracks with the
ids of returning people rewritten to their old ones, by the leg MHT's own model:

- **Widths.** Each scan of the frame is cut into segments by the jump distance
  (:class:`~laserpeople.segmentation.JumpDistanceSegmenter`). A segment of at least
  ``min_points`` points, ``min_width`` to ``max_width`` wide (one leg, not a part of one,
  two legs or a wall), not cut by something in front of it (:func:`occluded`) and
  whose mean point lies within ``leg_distance`` of exactly one person track adds its
  :func:`~laserpeople.tracking.reidentify.leg_width` to that track's
  :class:`~laserpeople.tracking.reidentify.Signature`.
- **Ends.** A track id absent from the tracker's output for longer than ``lost_after``
  becomes a :class:`~laserpeople.tracking.reidentify.DormantIdentity` (kept when it has
  ``rules.min_samples`` widths, for ``rules.max_dormant``). An id that comes back while
  its identity is dormant takes it back.
- **New ids.** A track id seen for the first time is reported as it is; once
  :meth:`~laserpeople.tracking.reidentify.Reidentifier.ready` (``rules.min_samples``
  widths or ``rules.decide_time``), it is matched to the dormant identities
  (:meth:`~laserpeople.tracking.reidentify.Reidentifier.give_back`: the signature test,
  the motion gate, the Hungarian assignment and ``rules.min_posterior``), and when given
  one its output id is the identity's from then on (one id change in the output).

Ids are the tracker's own unless given back; the ``members`` of group tracks are rewritten
alike. An id whose identity was given to another track and that then comes back gets an id
from :data:`FRESH_IDS` on (the tracker's ids never reach them).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.frame import Frame, FrameField
from laserpeople.segmentation import JumpDistanceParams, JumpDistanceSegmenter, SegmentTable
from laserpeople.tracking.reidentify import (
    Candidate,
    DormantIdentity,
    Reidentifier,
    ReidentifyParams,
    Signature,
    leg_width,
)
from laserpeople.tracks import Track, Tracks

FloatArray = NDArray[np.float64]

FRESH_IDS = 1_000_000_000
"""First output id given to a track whose own id was given to another (see the module
docstring)."""


@dataclass(frozen=True)
class LegReidParams:
    """Re-identification by leg widths after the trackers of raw points (``[csa]``,
    ``[feet_pf]``, ``[upper_body_pf]`` ``leg_reid``)."""

    config_section = "leg_reid"

    leg_distance: float = param(
        0.5,
        "assumption: a person's legs lie within ~0.3 m of its centre, plus the lag of a "
        "point tracker's estimate",
        "a segment whose mean point is this close to one person track (and no other) is "
        "one of its legs",
        "m",
    )
    jump_distance: float = param(
        0.1,
        "as the leg detector's segmentation ([jump_distance] threshold, the neko7055 rule)",
        "a new segment starts where neighbouring points are at least this far apart",
        "m",
    )
    min_points: int = param(
        3,
        "assumption: a width from 2 beams is mostly the beam step",
        "points a segment needs to give a width",
    )
    min_width: float = param(
        0.1,
        "measured (docs/trackers.md, the real followed-person recording): 5 % of the "
        "followed person's whole, "
        "unoccluded segments lie below 0.113 m, the median at 0.147 m; narrower ones are a "
        "leg seen in part (0.08 kept them and no returning person was recognised)",
        "narrowest segment taken as one leg",
        "m",
    )
    max_width: float = param(
        0.25,
        "assumption: one leg's width on the real person-following recording 0.11-0.20 m; "
        "wider segments are two legs together or a leg against a wall",
        "widest segment taken as one leg",
        "m",
    )
    lost_after: float = param(
        1.0,
        "assumption: a point tracker leaves a person out of a few scans while it coasts",
        "a track id absent from the output this long has ended (becomes a dormant identity)",
        "s",
    )
    rules: ReidentifyParams = param(  # noqa: RUF009 (a frozen default instance)
        ReidentifyParams(min_samples=100, decide_time=8.0),
        "the leg MHT's re-identification (tracking/reidentify.py); min_samples 100: the "
        "widths of raw segments near a point track scatter more than those of detected "
        "legs; decide_time 8 s: a point track gains ~12 widths/s (the dev recording's "
        "followed person: 1048 in 899 scans), 100 in ~8 s",
        "when and how a new id is matched to a dormant identity ([leg_reid.rules])",
    )

    def __post_init__(self) -> None:
        for name in ("leg_distance", "jump_distance", "min_width", "max_width"):
            if not (math.isfinite(getattr(self, name)) and getattr(self, name) > 0):
                raise ValueError(f"{name} must be positive and finite")
        if self.min_points < 2 or self.lost_after < 0 or self.min_width > self.max_width:
            raise ValueError("need min_points >= 2, lost_after >= 0, min_width <= max_width")


@dataclass
class _Id:
    """What the stage knows of one of the tracker's ids.

    Attributes:
        output: The id it is reported with.
        born: First time it was reported [s].
        last_seen: Last time it was reported [s].
        position: Its last position (2,) [m].
        signature: Its leg widths (with its identity's, once given one back).
        seen_before: Time its identity was tracked before it [s].
        pending: New and not yet matched to the dormant identities.
        ended: Absent for longer than ``lost_after``.
    """

    output: int
    born: float
    last_seen: float
    position: FloatArray
    signature: Signature
    seen_before: float = 0.0
    pending: bool = True
    ended: bool = False


class LegWidthReidentifier:
    """Gives people who come back their old ids by their leg widths (module docstring).

    Args:
        params: Parameters (None: defaults).

    Attributes:
        reid: The dormant identities and their matching (the leg MHT's model).
    """

    consumes: frozenset[FrameField] = frozenset({"scans"})

    def __init__(self, params: LegReidParams | None = None) -> None:
        self.params = params if params is not None else LegReidParams()
        self.reid = Reidentifier(self.params.rules)
        self._segmenter = JumpDistanceSegmenter(
            JumpDistanceParams(threshold=self.params.jump_distance)
        )
        self._ids: dict[int, _Id] = {}
        self._next_fresh = FRESH_IDS

    def update(self, tracks: Tracks, frame: Frame) -> Tracks:
        """``tracks`` with the ids of returning people rewritten, learning leg widths from
        ``frame.scans``."""
        stamp = tracks.stamp
        persons = tracks.of_kind("person")
        for t in persons:
            self._see(t, stamp)
        if persons:
            for tid, width in self.widths(persons, frame):
                self._ids[tid].signature.add(width)
        self._end_lost(stamp)
        self._match(stamp)
        return self._relabel(tracks)

    def widths(self, persons: tuple[Track, ...], frame: Frame) -> list[tuple[int, float]]:
        """``(track id, leg width [m])`` of every segment of ``frame``'s scans taken as a leg
        of one of ``persons`` (module docstring)."""
        p = self.params
        pos = np.array([t.position for t in persons]).reshape(-1, 2)
        out: list[tuple[int, float]] = []
        for scan in frame.scans:
            if frame.frame == "world" and scan.pose is None:
                continue  # (the points' place in the tracks' frame is unknown)
            table = self._segmenter(scan)
            if len(table) == 0:
                continue
            sizes = table.sizes
            centres = table.centres()
            if frame.frame == "world" and scan.pose is not None:
                centres = scan.pose.transform_points(centres)
            near = np.linalg.norm(centres[:, None, :] - pos[None, :, :], axis=-1) <= p.leg_distance
            count = near.sum(axis=1)
            whole = (count == 1) & (sizes >= p.min_points) & ~occluded(table)
            for k in np.flatnonzero(whole).tolist():
                width = leg_width(_segment_points(table, k))
                if p.min_width <= width <= p.max_width:
                    out.append((persons[int(np.argmax(near[k]))].track_id, width))
        return out

    def _see(self, t: Track, stamp: float) -> None:
        """Note that the tracker reports ``t`` at ``stamp`` [s]."""
        state = self._ids.get(t.track_id)
        if state is None:
            self._ids[t.track_id] = _Id(
                t.track_id,
                stamp,
                stamp,
                t.position.copy(),
                Signature(),
                pending=self.params.rules.enabled,
            )
            return
        if state.ended:  # back after lost_after: its identity if nobody took it
            if self.reid.dormant.pop(state.output, None) is None and self._given(state.output):
                state.output = self._next_fresh
                self._next_fresh += 1
            state.ended = False
        state.last_seen = stamp
        state.position = t.position.copy()

    def _given(self, output: int) -> bool:
        """Whether another live id is reported as ``output``."""
        return any(s.output == output and not s.ended for s in self._ids.values())

    def _end_lost(self, stamp: float) -> None:
        """Make ids absent for longer than ``lost_after`` dormant identities."""
        for state in self._ids.values():
            if state.ended or stamp - state.last_seen <= self.params.lost_after:
                continue
            state.ended = True
            state.pending = False
            seen = state.seen_before + state.last_seen - state.born
            self.reid.remember(
                DormantIdentity(
                    state.output, state.position.copy(), state.last_seen, state.signature, seen
                )
            )
        self.reid.forget_old(stamp)
        forgotten = self.params.rules.max_dormant
        for tid in [k for k, s in self._ids.items() if s.ended and stamp - s.last_seen > forgotten]:
            del self._ids[tid]

    def _match(self, stamp: float) -> None:
        """Match the new ids that are ready to the dormant identities."""
        ready = {
            tid: s
            for tid, s in self._ids.items()
            if s.pending and not s.ended and self.reid.ready(s.signature, s.born, stamp)
        }
        if not ready:
            return
        given = self.reid.give_back(
            [
                Candidate(tid, s.position.copy(), stamp, s.signature, s.born)
                for tid, s in ready.items()
            ]
        )
        for tid, s in ready.items():
            s.pending = False
            d = given.get(tid)
            if d is not None:
                s.output = d.identity
                s.signature = d.signature.merged(s.signature)
                s.seen_before = d.seen_for

    def _relabel(self, tracks: Tracks) -> Tracks:
        """``tracks`` with each person id (and group member) as reported."""
        ids = self._ids
        if all(s.output == tid for tid, s in ids.items()):
            return tracks
        out: list[Track] = []
        for t in tracks:
            if t.kind == "person":
                out.append(replace(t, track_id=ids[t.track_id].output))
            elif t.kind == "group" and t.members:
                members = tuple(ids[m].output if m in ids else m for m in t.members)
                out.append(replace(t, members=members))
            else:
                out.append(t)
        return replace(tracks, tracks=tuple(out))


def occluded(table: SegmentTable) -> NDArray[np.bool_]:
    """Whether each segment (M,) of ``table`` may be cut by something in front of it: the
    valid point of the beam just before its first (or just after its last) is nearer to the
    laser than that end (the leg goes on behind it, so its width would be too small)."""
    m = len(table)
    if m == 0:
        return np.zeros(0, dtype=bool)
    rng = np.hypot(table.points[:, 0], table.points[:, 1])
    beams = table.beams
    first = table.offsets[:-1]
    last = table.offsets[1:] - 1
    out = np.zeros(m, dtype=bool)
    before = first[1:]  # (a segment's first point has the previous segment's last before it)
    adjacent = beams[before - 1] == beams[before] - 1
    out[1:] |= adjacent & (rng[before - 1] < rng[before])
    after = last[:-1]
    adjacent = beams[after + 1] == beams[after] + 1
    out[:-1] |= adjacent & (rng[after + 1] < rng[after])
    return out


def _segment_points(table: SegmentTable, k: int) -> FloatArray:
    """The sensor-frame points (n, 2) [m] of segment ``k`` of ``table``, in scan order."""
    return np.asarray(table.points[table.offsets[k] : table.offsets[k + 1]], dtype=np.float64)


__all__ = ["FRESH_IDS", "LegReidParams", "LegWidthReidentifier", "occluded"]
