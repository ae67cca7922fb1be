"""Person tracks on static places, hidden for trackers that have no static world of their own.

The leg MHT's people (policy ``tracks``) and the group tracker ask a static world model
themselves. The other person trackers (``nn``, ``csa``, ``feet-pf``, ``upper-body-pf``)
report whatever their observations hold, and on real recordings that includes things that
never move: an object put down after the per-beam background was learned, the end of a
wall at the edge of the range, a chair's legs. :class:`StaticTrackFilter` is an identify
stage behind such a tracker that asks the people's occupancy grid
(:class:`~laserpeople.pipeline.static_people.PeopleStaticModel`) and leaves out of the
output the person tracks that a user would call furniture, with the people layer's rule
(``tracking/person_tracks.py``) applied to reported tracks. A track's place is the
frame's points within ``radius`` of its position (the legs or body it was made from; its
centre can lie between two chair posts, on free space), and the place's static time is
the one that ``static_share`` of those points reach (the centre's when no point is near):

- a track *travels* only while its place is not static (static for at most
  ``static_time``): hopping between the posts of a chair or railing is not walking;
- a track that has not travelled ``min_travel`` from where it was first reported is
  hidden while its place has been static for longer than ``static_time``;
- either only once tracks have stood on that static place for ``stand_time``, one id
  after another with gaps of at most ``place_gap`` (a tracker may give the same thing a
  new id every few seconds): people who stand in a crowd for a few seconds, on places the
  grid first saw when they stood there, are not hidden;
- a track that has travelled is hidden only when it stands (slower than ``min_speed``) on
  a place that was static ``arrival_slack`` longer than it has stood there (a track that
  slid onto furniture it passed); a person who walks in and stands keeps its track.

The tracker itself is not changed (its tracks go on, hidden rows come back when the rule
no longer holds); the stage counts the person-scans it hid and ``laserpeople track``
prints the count. ``static_tracks.hide = false`` reports every track, as the papers do.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from laserpeople.background import StaticWorldModel
from laserpeople.config import param
from laserpeople.frame import Frame, FrameField
from laserpeople.tracks import Tracks

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class StaticTrackParams:
    """When a person track of a tracker without its own static world is left out."""

    config_section = "static_tracks"

    hide: bool = param(
        True,
        "measured on the real demo, MiR and corridor bags (docs/people-benchmarks.md); "
        "false is the papers' behaviour (002, 004: every track)",
        "leave out of the output the person tracks of nn, csa, feet-pf and upper-body-pf "
        "that stand on static places (counted and reported by laserpeople track)",
    )
    static_time: float = param(
        10.0,
        "as people.static_time",
        "a track on a place static for longer is hidden unless it has walked (see arrival_slack)",
        "s",
    )
    min_travel: float = param(
        0.5,
        "as people.min_travel (leg_tracker's distance travelled to initiate a person)",
        "distance from where a track was first reported, off static places, that is a walk",
        "m",
    )
    arrival_slack: float = param(
        2.0,
        "as people.arrival_slack",
        "a track that walked and stands is hidden only on places static this much longer "
        "than it has stood there",
        "s",
    )
    min_speed: float = param(0.1, "as people.min_speed", "a track slower than this stands", "m/s")
    radius: float = param(
        0.35,
        "assumption: a person's legs are within about 0.3 m of its centre",
        "the frame's points this close to a track are its place",
        "m",
    )
    static_share: float = param(
        0.75,
        "as group_tracker.static_share: a person beside a wall has about half of the points "
        "near it on the wall",
        "a place is static for as long as this share of its points are",
    )
    stand_time: float = param(
        10.0,
        "measured (docs/people-benchmarks.md): people standing 4-10 s in a meeting in the "
        "simulated entrance hall",
        "a track is hidden only once tracks have stood on its static place this long",
        "s",
    )
    place_gap: float = param(
        2.0,
        "assumption: a tracker that loses a thing gives it a new id within a second or two",
        "tracks on a static place follow each other when the next one is there within this "
        "many seconds of the last (within radius of it)",
        "s",
    )
    forget_after: float = param(
        60.0,
        "assumption: longer than the trackers' own coasting and re-identification gaps",
        "what the stage knows of a track id unseen this long is forgotten (bounded memory)",
        "s",
    )

    def __post_init__(self) -> None:
        values = (
            self.static_time,
            self.min_travel,
            self.arrival_slack,
            self.min_speed,
            self.radius,
            self.stand_time,
            self.place_gap,
        )
        if min(values) < 0.0 or not all(math.isfinite(v) for v in values):
            raise ValueError(
                "static_time, min_travel, arrival_slack, min_speed, radius, stand_time and "
                "place_gap must be finite and not negative"
            )
        if not 0.0 < self.static_share <= 1.0:
            raise ValueError("static_share must be in (0, 1]")
        if not self.forget_after > 0.0:
            raise ValueError("forget_after must be positive")


@dataclass
class _Seen:
    """What the stage knows of one person track id."""

    born: tuple[float, float]
    travelled: float
    arrived: tuple[float, float, float]  # time [s], x, y [m] of the last walk's end
    last: float  # time [s] last reported by the tracker


@dataclass
class _Place:
    """A static place where tracks stand, one after another."""

    x: float
    y: float
    since: float  # time [s] the first of them stood there
    last: float  # time [s] one stood there last


class StaticTrackFilter:
    """An identify stage that leaves out person tracks on static places (module docstring).

    Args:
        model: The static world model asked how long places have been static (the
            people's occupancy grid, learned by its preprocess stage).
        params: The rule's parameters (None: defaults).

    Attributes:
        hidden: Person-scans left out so far.
        hidden_ids: Track ids left out in at least one scan.
    """

    consumes: frozenset[FrameField] = frozenset()

    def __init__(self, model: StaticWorldModel, params: StaticTrackParams | None = None) -> None:
        self.model = model
        self.params = params if params is not None else StaticTrackParams()
        self.hidden = 0
        self.hidden_ids: set[int] = set()
        self._seen: dict[int, _Seen] = {}
        self._places: list[_Place] = []

    def update(self, tracks: Tracks, frame: Frame) -> Tracks:
        """``tracks`` without the person tracks that stand on static places."""
        p = self.params
        people = [t for t in tracks.tracks if t.kind == "person"]
        now = tracks.stamp
        self._forget(now)
        if not people:
            return tracks
        static = self._static_times(np.array([t.position for t in people]), frame)
        hide: set[int] = set()
        for t, s in zip(people, static, strict=True):
            x, y = (float(v) for v in t.position)
            seen = self._seen.get(t.track_id)
            if seen is None:
                seen = self._seen[t.track_id] = _Seen((x, y), 0.0, (now, x, y), now)
            seen.last = now
            if math.hypot(x - seen.arrived[1], y - seen.arrived[2]) >= p.min_travel:
                seen.arrived = (now, x, y)
            if s <= p.static_time:
                seen.travelled = max(seen.travelled, math.hypot(x - seen.born[0], y - seen.born[1]))
                continue
            if now - self._stood_at(x, y, now) < p.stand_time:
                continue
            standing = math.hypot(*(float(v) for v in t.velocity)) < p.min_speed
            if seen.travelled < p.min_travel or (
                standing and s > now - seen.arrived[0] + p.arrival_slack
            ):
                hide.add(t.track_id)
        if not hide:
            return tracks
        self.hidden += len(hide)
        self.hidden_ids |= hide
        kept = tuple(t for t in tracks.tracks if t.kind != "person" or t.track_id not in hide)
        return replace(tracks, tracks=kept)

    def _static_times(self, centres: FloatArray, frame: Frame | None) -> list[float]:
        """Per track centre (M, 2): the static time [s] reached by ``static_share`` of the
        frame's points within ``radius`` (the centre's own without such points)."""
        p = self.params
        points = np.zeros((0, 2))
        if frame is not None and frame.points is not None:
            points = frame.points.points
        d = points[None, :, :] - centres[:, None, :]
        near = np.einsum("mnk,mnk->mn", d, d) <= p.radius**2
        used = np.flatnonzero(near.any(axis=0))
        asked = np.concatenate([centres, points[used]]) if len(used) else centres
        times = np.asarray(self.model.static_time(asked), dtype=np.float64)
        out = times[: len(centres)].tolist()
        of_point = dict(zip(used.tolist(), times[len(centres) :].tolist(), strict=True))
        for i, row in enumerate(near):
            mine = sorted((of_point[j] for j in np.flatnonzero(row).tolist()), reverse=True)
            if mine:  # the time that at least static_share of the points have been static
                out[i] = mine[math.ceil(p.static_share * len(mine)) - 1]
        return out

    def _stood_at(self, x: float, y: float, now: float) -> float:
        """Since when [s] tracks have stood on the static place at (x, y) [m]."""
        p = self.params
        near = [q for q in self._places if math.hypot(q.x - x, q.y - y) <= p.radius]
        place = min(near, key=lambda q: q.since) if near else None
        if place is None:
            place = _Place(x, y, now, now)
            self._places.append(place)
        place.x, place.y, place.last = x, y, now
        return place.since

    def _forget(self, now: float) -> None:
        horizon = now - self.params.forget_after
        if any(s.last < horizon for s in self._seen.values()):
            self._seen = {k: s for k, s in self._seen.items() if s.last >= horizon}
        gap = now - self.params.place_gap
        self._places = [q for q in self._places if q.last >= gap]


__all__ = ["StaticTrackFilter", "StaticTrackParams"]
