"""The group tracker of 000 Sec. 4: a multi-model MHT over groups of people.

Each frame: the foreground points are clustered by single linkage (d_P) into observations
with their number of human-sized blobs (Sec. 4.1); the MHT core predicts the group tracks,
the branch generator spawns the continue/split/merge models of every parent hypothesis with
re-predicted tracks and re-clustered observations (Secs. 4.3-4.4), and the core lists the k
best children over all models and parents with the hypothesis probability of eqs. 33-37,
prunes (ratio, N-scan-back) and updates the matched groups (eqs. 28-31).

Reported are the groups of the best hypothesis that are confirmed (in it for
``confirm_scans`` consecutive scans, :mod:`.confirm`; 1 reports every group, as 000) and,
with a static world model, not on a static place. A group first reported where a
reported group vanished takes its id (``id_memory``, :mod:`.handover`).

The people-only mode (:meth:`GroupTrackerParams.people_only`) inhibits splits and merges
and clusters with a small d_P, the comparison tracker of 000 Fig. 17 (right).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from laserpeople.background import StaticWorldModel
from laserpeople.errors import LaserPeopleError
from laserpeople.frame import Frame, FrameField
from laserpeople.scan import visible_area
from laserpeople.tracking.groups.coast import CoastedReports
from laserpeople.tracking.groups.confirm import Candidate, Confirmation
from laserpeople.tracking.groups.handover import IdHandover
from laserpeople.tracking.groups.interaction import (
    GroupBranches,
    GroupLabelModel,
)
from laserpeople.tracking.groups.labels import format_labels, sort_labels
from laserpeople.tracking.groups.model import GroupModel, group_payload
from laserpeople.tracking.groups.observations import GroupObservations, SizeCounting
from laserpeople.tracking.groups.occlusion import FrameShadows
from laserpeople.tracking.groups.params import GroupTrackerParams
from laserpeople.tracking.mht.core import MHT, StepStats
from laserpeople.tracking.mht.tracktree import TrackNode
from laserpeople.tracks import Track, Tracks

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


LABEL_MEMO = 4096
"""Label sets whose displayed and formatted forms a tracker remembers at most (then it
forgets all); below that, :meth:`GroupMHTTracker.forget_gone` keeps only the label sets of
tracks alive in some hypothesis."""
FORGET_EVERY = 64
"""Scans between two rounds of :meth:`GroupMHTTracker.forget_gone` (what it keeps of gone
tracks in between is at most this many scans' worth)."""
EVENTS_KEPT = 1024
"""Splits and merges :attr:`GroupMHTTracker.events` keeps at least (the latest; at most
twice as many, all are counted in :attr:`GroupMHTTracker.event_counts`): the 20-people
hall records about 75 per 1,000 scans, some 65,000 in a robot's day at 10 scans/s."""
GROUP_MIN_RATIO = 3e-3
"""Ratio pruning of group hypotheses where ``mht.min_ratio`` is unset: drop a hypothesis
below 0.3 % of its cluster's best (000 Sec. 4.5.2 names ratio pruning without a value; the
generic :data:`~laserpeople.tracking.mht.core.MIN_RATIO` is 1e-3). Chosen
for speed (issue 12: under 5 ms at 20 people) on entrance-hall seeds 0 and 1 (60 s, d_P
1.3 m: clustering error 0.2417, group size and events the same for 1e-3, 2e-3 and 3e-3;
5e-3 0.2413, 1e-2 0.2445); held out (seeds 2-4, 5-7) and on the real demo bag see
docs/groups.md "Settings", ratio pruning."""
GROUP_N_SCAN = 3
"""N-scan-back depth of group hypotheses where ``mht.n_scan`` is unset (000's scan-back depth
of eight, :data:`~laserpeople.tracking.mht.core.N_SCAN`, under ``--preset paper``): a merge
of two groups passing each other that lost in its scan no longer stays among the
hypotheses to win a few scans later. Measured with ``model_prior`` normalised on held-back
random-groups seeds 100-119 and the real recordings (docs/groups.md, "Eq. 32 normalised and
N-scan-back 3")."""


@dataclass(frozen=True, eq=False)
class GroupEstimate:
    """One reported group of the best hypothesis after a frame.

    Attributes:
        family: The track's family (unique over the run; a split or merge starts new ones).
            Not always the id it is reported with: reported ids may be handed over or
            reused (``reuse_ids``, ``id_memory``); the ``Tracks`` the update returns list
            these groups first, in this order.
        labels: Its label set.
        mean: State (5,): x, y [m], vx, vy [m/s], n [people].
        cov: Covariance (5, 5).
        members: Frame point indices (K,) of the observation it was matched with this frame
            (empty when occluded).
        contour: Contour (K, 2) [m], absolute.
        event: "split" or "merge" when a model made this track's family, else "".
    """

    family: int
    labels: tuple[str, ...]
    mean: FloatArray
    cov: FloatArray
    members: IntArray
    contour: FloatArray
    event: str

    @property
    def size(self) -> float:
        """Estimated number of people n."""
        return float(self.mean[4])


@dataclass(frozen=True)
class GroupEvent:
    """A split or merge in the reported (best) hypothesis, recorded when a group it made
    is first reported (a split once, though it makes two groups).

    Attributes:
        stamp: Time of that report [s].
        kind: "split" or "merge".
        labels: Labels of the group it made (of a split: the first half reported).
    """

    stamp: float
    kind: str
    labels: tuple[str, ...]


class GroupMHTTracker:
    """Group tracker: ``update(frame) -> Tracks`` with ``kind="group"`` tracks carrying the
    size (rounded n), the labels and the contour (absolute) (see the module doc)."""

    consumes: frozenset[FrameField] = frozenset({"points", "foreground"})

    def __init__(self, params: GroupTrackerParams | None = None) -> None:
        self.params = params if params is not None else GroupTrackerParams()
        p = self.params
        self.model = GroupModel(p.model_settings())
        self.label_model = GroupLabelModel(
            p.p_m,
            p.p_o,
            p.p_t,
            p.p_n,
            p.p_f,
            p.observation_area or 1.0,
            (p.p_m_shadowed, p.p_o_shadowed, p.p_t_shadowed) if p.shadow_occlusion else None,
            p.shadow_margin,
            p.shadow_hits,
        )
        self.mht: MHT[GroupObservations] = MHT(
            p.mht.with_defaults(min_ratio=GROUP_MIN_RATIO, n_scan=GROUP_N_SCAN),
            self.model,
            self.label_model,
        )
        self.branches = GroupBranches(
            self.model, self.mht.tree, p.interaction_settings(), self.name
        )
        self.mht.branches = self.branches
        # root family -> reported number (roots of live tracks only, see forget_gone)
        self._roots: dict[int, str] = {}
        self._numbered = 0  # root families numbered so far
        self._shown: dict[tuple[str, ...], tuple[str, ...]] = {}  # labels -> display_labels
        self._formatted: dict[tuple[str, ...], str] = {}  # display labels -> format_labels
        self._reported: set[int] = set()  # live families reported (their event recorded)
        self.events: list[GroupEvent] = []
        """The latest splits and merges of the reported hypothesis, oldest first (all of
        them up to :data:`EVENTS_KEPT`; at most twice that many are kept)."""
        self.event_counts: dict[str, int] = {"split": 0, "merge": 0}
        """Splits and merges recorded since the start (all of them, unlike ``events``)."""
        # (kind, split stem or merged labels) -> frame it was last reported in
        self._event_at: dict[tuple[str, tuple[str, ...]], int] = {}
        self.last_stats: StepStats | None = None
        self.last_groups: list[GroupEstimate] = []
        self.last_observations = GroupObservations.empty()
        self._counting = p.counting()
        self.static_model: StaticWorldModel | None = None
        """Asked how long a group's place has been static (the pipeline sets it when
        ``static_groups`` is false; None: every group is reported)."""
        self.wide_points_left_out = 0
        """Foreground points left out of the observations as parts of blobs wider than
        ``max_blob_size``, summed over the frames."""
        self.static_groups_hidden = 0
        """Group-scans not reported because the group sat on a static place, never walked."""
        self.confirmation = Confirmation(p.confirm_settings())
        """Which groups of the best hypothesis are confirmed (``confirm_scans``)."""
        self._scans = 0
        # family -> (time [s], position) of its last walk, or of when it was first tracked
        self._anchors: dict[int, tuple[float, FloatArray]] = {}
        self._walked_at: dict[str, float] = {}  # internal label -> time [s] of its last walk
        self._ids: dict[tuple[str, ...], int] = {}  # internal labels -> id reported for them
        self._last_at: dict[int, FloatArray] = {}  # reported id -> its last position [m]
        self.handover = IdHandover(p.id_memory if p.reuse_ids else 0.0, p.id_gate)
        """Vanished reported ids handed to the groups taking their place (``id_memory``)."""
        self._taken_over: set[int] = set()  # coasting families a new group replaced
        self.coasting = CoastedReports(p.coast_time, p.merged_coast_time)
        """The last reports of vanished groups, reported at their predictions (``coast_time``)."""

    @property
    def counting(self) -> SizeCounting:
        """How the people of an observation are counted (the parameters' counting, at
        torso height without pairs: :meth:`use_torso_height`)."""
        return self._counting

    def use_torso_height(self, torso: bool) -> None:
        """Whether the recording states the laser at torso height (the pipeline tells it,
        :func:`~laserpeople.pipeline.background.set_laser_height`): there, unless
        ``torso_pairs``, the people of a cluster are counted without pairing blobs as legs
        (:class:`~laserpeople.tracking.groups.observations.SizeCounting`)."""
        counting = replace(self.params.counting(), torso=torso and not self.params.torso_pairs)
        self._counting = counting
        self.branches.s = replace(self.branches.s, counting=counting)

    @property
    def wants_static_model(self) -> bool:
        """True when groups on static places are hidden (``static_groups`` false)."""
        return not self.params.static_groups

    static_model_off = "group_tracker.static_groups = true"
    """Why no static world model is wanted, when it is not (for the user)."""

    def use_static_model(self, model: StaticWorldModel | None) -> None:
        """Ask ``model`` how long a group's place has been static (None: none)."""
        self.static_model = model

    def name(self, node: TrackNode) -> tuple[str, ...]:
        """The internal label set of ``node``: a new group is named by its family until it
        is reported (labels made from it by splits keep that root)."""
        labels = group_payload(node).labels
        return labels if labels else (str(node.family),)

    def display_labels(self, labels: tuple[str, ...]) -> tuple[str, ...]:
        """Labels as reported: each root family is numbered 0, 1, ... in the order the
        groups are first reported (000's naming: ``0`` -> ``0-0``, ``0-1`` on a split)."""
        shown = self._shown.get(labels)
        if shown is not None:  # its roots are numbered already; numbers never change
            return shown
        out = []
        for label in labels:
            root, _, rest = label.partition("-")
            number = self._roots.get(int(root))
            if number is None:
                number = self._roots[int(root)] = str(self._numbered)
                self._numbered += 1
            out.append(f"{number}-{rest}" if rest else number)
        if len(self._shown) >= LABEL_MEMO:
            self._shown.clear()
        shown = self._shown[labels] = sort_labels(out)
        return shown

    def observe(self, frame: Frame) -> GroupObservations:
        """The observation clusters of a frame's foreground points (Sec. 4.1)."""
        if frame.points is None or frame.foreground is None:
            raise LaserPeopleError(
                "the group tracker needs the frame's points and foreground mask",
                scan=frame.index,
                hint="run the preprocessing stage (points, background subtraction) first",
            )
        fg = np.asarray(frame.foreground, dtype=bool)
        if fg.shape != (len(frame.points),):
            raise LaserPeopleError(
                f"foreground mask of {fg.size} values for {len(frame.points)} points",
                scan=frame.index,
                hint="the mask must have one value per point of frame.points",
            )
        idx = np.nonzero(fg)[0].astype(np.int64)
        pts = frame.points.points[idx]
        finite = np.isfinite(pts).all(axis=1)
        if not finite.all():
            pts, idx = pts[finite], idx[finite]
        p = self.params
        spacing = beam_spacing(frame, idx) if p.size_count == "resolved" else None
        obs = GroupObservations.from_points(
            pts, idx, p.cluster_distance, p.blob_distance, self._counting, p.max_blob_size, spacing
        )
        self.wide_points_left_out += len(pts) - len(obs.points)
        return obs

    @staticmethod
    def _visible_area(frame: Frame) -> float:
        """V of eqs. 36-37 for ``observation_area`` 0: the area [m^2] the frame's lasers saw
        (the sum over its scans)."""
        area = sum(visible_area(scan) for scan in frame.scans)
        if not area > 0.0:
            raise LaserPeopleError(
                "the group tracker's observation_area 0 needs the area the lasers saw, and "
                f"this frame has {len(frame.scans)} scans with no valid return",
                scan=frame.index,
                hint="set [group_tracker] observation_area to the field of view in m^2",
            )
        return area

    def update(self, frame: Frame) -> Tracks:
        """Track one frame."""
        obs = self.observe(frame)
        self.last_observations = obs
        if self.params.observation_area == 0.0:
            self.label_model.area = self._visible_area(frame)
        if self.params.shadow_occlusion:
            self.label_model.shadows = FrameShadows.from_frame(frame)
            self.label_model.stamp = frame.stamp
        self.branches.begin_scan(obs, frame.stamp)
        self.model.scan = obs
        self.last_stats = self.mht.step(obs, frame.stamp)
        best, probs = self.mht.best_nodes()
        groups: list[GroupEstimate] = []
        tracks: list[Track] = []
        nodes = self._confirmed(best, frame.stamp)
        ids = self._reported_ids(nodes, frame.stamp)
        for node, track_id in zip(nodes, ids, strict=True):
            payload = group_payload(node)
            labels = self.display_labels(self.name(node))
            contour = payload.contour + node.mean[:2]
            members = payload.members  # empty when occluded (coasted)
            groups.append(
                GroupEstimate(
                    node.family, labels, node.mean, node.cov, members, contour, payload.event
                )
            )
            if node.family not in self._reported:
                self._reported.add(node.family)
                if payload.event:
                    self._record(GroupEvent(frame.stamp, payload.event, labels), frame.index)
            tracks.append(
                Track(
                    track_id=track_id,
                    kind="group",
                    position=node.mean[:2],
                    velocity=node.mean[2:4],
                    covariance=node.cov[:2, :2],
                    size=max(1, round(float(node.mean[4]))),
                    labels=self._format(labels),
                    score=probs.get(node.family, 1.0),
                    contour=contour,
                )
            )
        self.last_groups = groups
        if self.coasting.memory > 0.0:
            shown = {node.family for node in nodes}
            hidden = {self._ids.get(self.name(n), n.family) for n in best if n.family not in shown}
            coasted = self.coasting.coasted(
                frame.stamp,
                set(ids) | hidden,
                self._seen_gone(frame),
                self._among(frame, groups),
            )
            self.coasting.record(frame.stamp, tracks)
            tracks += coasted
        self._reported.intersection_update(self.mht.tree.nodes_by_family)
        if self._scans % FORGET_EVERY == 0:
            self.forget_gone(frame.index)
        return Tracks(frame.stamp, frame.index, tuple(tracks), frame.frame, frame.sensor_pose)

    def _among(self, frame: Frame, groups: list[GroupEstimate]) -> Callable[[Track], bool]:
        """Whether a coasted group is among the points of the groups reported in ``frame``
        (``merged_coast_time``): a point of its predicted contour (its position, without a
        contour) within ``blob_distance`` of one of their points."""
        assert frame.points is not None
        seen = [g.members for g in groups if g.members.size]
        points = frame.points.points[np.concatenate(seen)] if seen else np.empty((0, 2))
        reach = self.params.blob_distance

        def among(track: Track) -> bool:
            if not len(points):
                return False
            mine = track.contour if len(track.contour) else track.position[None, :]
            d2 = np.sum((mine[:, None, :] - points[None, :, :]) ** 2, axis=2)
            return bool(d2.min() <= reach * reach)

        return among

    def _seen_gone(self, frame: Frame) -> Callable[[Track], bool] | None:
        """Whether ``frame``'s scans saw past every point of a coasted group's predicted
        contour (or its position, without a contour) by more than ``shadow_margin``; None
        when the scans' poses are unknown."""
        shadows = self.label_model.shadows
        if not self.params.shadow_occlusion:
            shadows = FrameShadows.from_frame(frame)
        if shadows is None:
            return None
        margin = self.params.shadow_margin
        seen = shadows

        def gone(track: Track) -> bool:
            points = track.contour if len(track.contour) else track.position[None, :]
            return seen.seen_empty(points, margin)

        return gone

    def _reported_ids(self, nodes: list[TrackNode], stamp: float) -> list[int]:
        """The id each of ``nodes`` is reported with: its family, or with ``reuse_ids`` the
        id of the group reported before with the same internal labels (a split group whose
        parts merged back: ``0`` -> ``0-0``, ``0-1`` -> ``0``), unless another node of this
        scan has that id; the two halves of a split keep their ids by position
        (:meth:`_follow_halves`); a group whose labels were never reported may take the
        id of a group that vanished near it (``id_memory``, :mod:`.handover`)."""
        if not self.params.reuse_ids:
            return [node.family for node in nodes]
        keys = [self.name(node) for node in nodes]
        out: list[int] = []
        taken: set[int] = set()
        # a node that keeps its own id first, so that a merged-back group never takes it
        for node, key in zip(nodes, keys, strict=True):
            if self._ids.get(key, node.family) == node.family:
                taken.add(node.family)
        fresh: list[int] = []  # nodes whose labels were never reported
        for k, (node, key) in enumerate(zip(nodes, keys, strict=True)):
            track_id = self._ids.get(key)
            if track_id is None:
                if len(self._ids) >= LABEL_MEMO:  # a bound for pathological runs only
                    self._ids = {x: self._ids[x] for x in keys if x in self._ids}
                track_id = self._ids[key] = node.family
                fresh.append(k)
            elif track_id != node.family and track_id in taken:
                track_id = node.family
            taken.add(track_id)
            out.append(track_id)
        handed = self.handover.hand_over(stamp, [nodes[k].mean[:2] for k in fresh], set(out))
        inherited: set[int] = set()  # nodes that took a vanished group's id
        for k, track_id in zip(fresh, handed, strict=True):
            if track_id is not None:
                out[k] = self._ids[keys[k]] = track_id
                inherited.add(k)
        self._follow_halves(nodes, keys, out, inherited)
        self._last_at.update((i, node.mean[:2]) for i, node in zip(out, nodes, strict=True))
        self.handover.record(stamp, out, [node.mean for node in nodes])
        return out

    def _follow_halves(
        self,
        nodes: list[TrackNode],
        keys: list[tuple[str, ...]],
        ids: list[int],
        handed: set[int],
    ) -> None:
        """Give the two halves of one split (labels ``X-0`` and ``X-1``, both reported this
        scan) their ids by where those ids were last reported (in place in ``ids``, and in
        the labels -> id memory for later scans).

        The halves of a split start as two copies of one prediction (000 Sec. 4.2.3), so the
        hypotheses that give observation A to ``X-0`` and B to ``X-1`` or the other way round
        are equally likely; which one is best flips with the next scans' data, and so would
        the ids, at every split and again when the halves split anew after merging back.
        Each id stays with the half nearer to where it was last seen; a half whose id has not
        been reported yet keeps its own."""
        pairs: dict[tuple[str, ...], list[int]] = {}
        for i, key in enumerate(keys):
            ends = {label.rpartition("-")[2] for label in key}
            if len(ends) == 1 and all("-" in label for label in key):
                stem = tuple(label.rpartition("-")[0] for label in key)
                pairs.setdefault(stem, [-1, -1])[int(ends.pop()) & 1] = i
        for a, b in pairs.values():
            if a < 0 or b < 0 or a in handed or b in handed:
                continue
            at_a, at_b = self._last_at.get(ids[a]), self._last_at.get(ids[b])
            if at_a is None or at_b is None:
                continue
            pa, pb = nodes[a].mean[:2], nodes[b].mean[:2]
            kept = math.dist(pa, at_a) ** 2 + math.dist(pb, at_b) ** 2
            swapped = math.dist(pa, at_b) ** 2 + math.dist(pb, at_a) ** 2
            if swapped < kept:
                ids[a], ids[b] = ids[b], ids[a]
                self._ids[keys[a]], self._ids[keys[b]] = ids[a], ids[b]

    @property
    def unconfirmed_groups_withheld(self) -> int:
        """Group-scans not reported because their group was not confirmed yet
        (``confirm_scans``; groups hidden on static places are not counted here)."""
        return self.confirmation.withheld

    def _confirmed(self, nodes: list[TrackNode], stamp: float) -> list[TrackNode]:
        """The groups of the best hypothesis ``nodes`` that are reported: not on a static
        place (:meth:`_off_static_places`, when a static world model is set) and
        confirmed (:mod:`.confirm`; every group counts as present, hidden or not)."""
        shown = nodes if self.static_model is None else self._off_static_places(nodes, stamp)
        visible = {node.family for node in shown}
        candidates = [
            Candidate(n.family, group_payload(n).event, self.name(n), n.family in visible)
            for n in nodes
        ]
        if self.handover.memory > 0.0:
            for node, c in zip(nodes, candidates, strict=True):
                new = not c.event and not self.confirmation.is_confirmed(c.family)
                if new and self.handover.near_vanished(stamp, node.mean[:2]):
                    self.confirmation.confirm(c.family)
            candidates = self._take_over_coasting(nodes, candidates)
        self._scans += 1
        keep = self.confirmation.select(self._scans, candidates)
        return [node for node, k in zip(nodes, keep, strict=True) if k]

    def _take_over_coasting(
        self, nodes: list[TrackNode], candidates: list[Candidate]
    ) -> list[Candidate]:
        """A new group seen within ``take_over_distance`` of a reported group that is coasting
        (unseen this scan) takes its place: the new group is confirmed at once and the
        coasting one is not reported any more (its id goes to the new one, :mod:`.handover`);
        the candidates with those hidden."""
        gate = self.params.take_over_distance
        coasting = [
            k
            for k, (n, c) in enumerate(zip(nodes, candidates, strict=True))
            if c.visible
            and self.confirmation.is_confirmed(c.family)
            and group_payload(n).members.size == 0
            and c.family not in self._taken_over
        ]
        for node, c in zip(nodes, candidates, strict=True):
            if c.event or self.confirmation.is_confirmed(c.family):
                continue
            if group_payload(node).members.size == 0 or not coasting:
                continue
            d = [math.dist(node.mean[:2], nodes[k].mean[:2]) for k in coasting]
            nearest = int(np.argmin(d))
            if d[nearest] <= gate:
                self.confirmation.confirm(c.family)
                self._taken_over.add(nodes[coasting.pop(nearest)].family)
                if not coasting:
                    break
        if not self._taken_over:
            return candidates
        gone = self._taken_over
        return [replace(c, visible=False) if c.family in gone else c for c in candidates]

    def _off_static_places(self, nodes: list[TrackNode], stamp: float) -> list[TrackNode]:
        """``nodes`` without the groups on static places (counted in
        :attr:`static_groups_hidden`).

        A group *walks* when it is ``min_travel`` from where it last walked (or was first
        tracked); the walk of a group of one label is that label's last walk (a merged
        group's centroid also moves as members come and go). Of a group's labels, and the
        labels they came from by splits (:meth:`_walks`), the latest last walk tells
        whether someone in it walked lately, the earliest since when it has stood. A group
        is hidden when nobody in it walked within ``static_time`` and at least
        ``static_share`` of its contour lies on places static for longer than
        ``static_time`` and longer than it has stood there (plus ``arrival_slack``). A
        group that walked in and stands is therefore kept, and so is the half of a group
        that holds something static (a person who walked past it, then on) until
        ``static_time`` after the person's last walk."""
        assert self.static_model is not None
        p = self.params
        anchors: dict[int, tuple[float, FloatArray]] = {}
        asked: list[tuple[TrackNode, float]] = []
        for node in nodes:
            position = node.mean[:2]
            anchor = anchors[node.family] = self._anchors.get(node.family, (stamp, position))
            labels = self.name(node)
            if math.dist(position, anchor[1]) >= p.min_travel:
                anchors[node.family] = (stamp, position)
                if len(labels) == 1:
                    self._walked_at[labels[0]] = stamp
            earliest, latest = self._walks(labels)
            if stamp - latest >= p.static_time:
                stood = stamp - earliest + p.arrival_slack if earliest > -math.inf else 0.0
                asked.append((node, max(p.static_time, stood)))
        self._anchors = anchors
        contours = [group_payload(node).contour + node.mean[:2] for node, _ in asked]
        if not contours:
            return nodes
        static = self.static_model.static_time(np.concatenate(contours))
        hidden: set[int] = set()
        end = 0
        for (node, limit), contour in zip(asked, contours, strict=True):
            end += len(contour)
            on_static = np.count_nonzero(static[end - len(contour) : end] > limit)
            if len(contour) and on_static >= p.static_share * len(contour):
                hidden.add(node.family)
        self.static_groups_hidden += len(hidden)
        return [node for node in nodes if node.family not in hidden]

    def forget_gone(self, index: int) -> None:
        """Forget what only tracks gone from every hypothesis could ask (called every
        :data:`FORGET_EVERY` scans; ``index`` is the frame index of now): reported families,
        numbers of roots no live track's labels hold, last walks of labels and reported ids
        of label sets that are neither a live track's nor stems of one, the label memos of
        sets no live track carries (pure functions of the set and the root numbers, computed
        again if needed) and the events recorded more than N-scan-back frames ago. Family
        ids are never reused, and the labels of every future track are its new family or
        come from the labels of tracks alive now (a split appends ``-0``/``-1``, a merge
        unites two sets and prunes ``X-0``, ``X-1`` to their stem ``X``), so the output is
        the same as with everything kept; the memory is bounded by the live tracks instead
        of growing with the length of the run."""
        live = [n for nodes in self.mht.tree.nodes_by_family.values() for n in nodes]
        names = {self.name(node) for node in live}
        labels = {label for name in names for label in name}
        roots = {int(label.partition("-")[0]) for label in labels}
        self._roots = {r: k for r, k in self._roots.items() if r in roots}
        self._shown = {k: v for k, v in self._shown.items() if k in names}
        shown = set(self._shown.values())
        self._formatted = {k: v for k, v in self._formatted.items() if k in shown}
        self.confirmation.prune(self.mht.tree.nodes_by_family, {str(r) for r in roots})
        self._taken_over.intersection_update(self.mht.tree.nodes_by_family)
        self.branches.forget_gone(names)
        stems = {stem for label in labels for stem in _stems(label)}
        if self._walked_at:  # a label's walk counts for the labels split from it
            self._walked_at = {k: t for k, t in self._walked_at.items() if k in stems}
        # a label set comes back only from its live parts merging back
        self._ids = {k: i for k, i in self._ids.items() if all(x in stems for x in k)}
        kept = set(self._ids.values())
        self._last_at = {i: at for i, at in self._last_at.items() if i in kept}
        n_scan = self.mht.params.depth
        self._event_at = {k: i for k, i in self._event_at.items() if 0 <= index - i <= n_scan}

    def state_counts(self) -> dict[str, int]:
        """Sizes of what the tracker keeps from scan to scan (for soak runs and tests):
        live track nodes and families, hypotheses, and the bookkeeping
        :meth:`forget_gone` bounds."""
        stats = self.last_stats
        return {
            "nodes": self.mht.tree.n_nodes,
            "families": self.mht.tree.n_families,
            "hypotheses": 0 if stats is None else stats.n_hypotheses,
            "reported": len(self._reported),
            "roots": len(self._roots),
            "shown": len(self._shown),
            "formatted": len(self._formatted),
            "event_at": len(self._event_at),
            "events": len(self.events),
            "walked_at": len(self._walked_at),
            "reported_ids": len(self._ids),
            "last_positions": len(self._last_at),
            "anchors": len(self._anchors),
            "taken_over": len(self._taken_over),
            "handover": len(self.handover),
            "coasting": len(self.coasting),
            "merged_labels": self.branches.memo_size,
            **self.confirmation.sizes(),
        }

    def _walks(self, labels: tuple[str, ...]) -> tuple[float, float]:
        """(earliest, latest) over ``labels`` of a label's last walk [s]: its own or that
        of a label it came from by splits (its stems, ``3-0-1`` -> ``3-0``, ``3``); labels
        that never walked are left out, and both are -inf when none walked."""
        walks = []
        for label in labels:
            last = max(self._walked_at.get(stem, -math.inf) for stem in _stems(label))
            if last > -math.inf:
                walks.append(last)
        return (min(walks), max(walks)) if walks else (-math.inf, -math.inf)

    def _format(self, labels: tuple[str, ...]) -> str:
        """:func:`format_labels`, remembered."""
        text = self._formatted.get(labels)
        if text is None:
            if len(self._formatted) >= LABEL_MEMO:
                self._formatted.clear()
            text = self._formatted[labels] = format_labels(labels)
        return text

    def _record(self, event: GroupEvent, index: int = -1) -> None:
        """Append ``event`` unless it is the second half of a split already recorded at
        this stamp (the halves X-0 and X-1 of one split share the stem X), or a split of
        the same stem (a merge of the same labels) recorded at most N-scan-back scans
        before (frame ``index``): the reported hypothesis changed its mind about the scan
        of one event."""
        key = (event.kind, event.labels)
        if event.kind == "split":
            stem = tuple(label.rsplit("-", 1)[0] for label in event.labels)
            for e in reversed(self.events):
                if e.stamp != event.stamp:
                    break
                if e.kind == "split" and tuple(x.rsplit("-", 1)[0] for x in e.labels) == stem:
                    return
            key = ("split", stem)
        last = self._event_at.get(key)
        self._event_at[key] = index
        if last is not None and 0 <= index - last <= self.mht.params.depth:
            return
        self.events.append(event)
        if len(self.events) > 2 * EVENTS_KEPT:
            del self.events[:-EVENTS_KEPT]
        self.event_counts[event.kind] = self.event_counts.get(event.kind, 0) + 1

    def point_labels(self, n_points: int) -> IntArray:
        """Group (track family) of each of the last frame's ``n_points`` points, -1 outside
        every reported group observed this frame (for the clustering error, 000 Sec. 4.6.1;
        the points of a group not reported yet are in none)."""
        out = np.full(n_points, -1, dtype=np.int64)
        for g in self.last_groups:
            out[g.members] = g.family
        return out

    @property
    def n_hypotheses(self) -> int:
        """Hypotheses after the last frame, summed over clusters."""
        return 0 if self.last_stats is None else self.last_stats.n_hypotheses


def beam_spacing(frame: Frame, idx: IntArray) -> FloatArray | None:
    """Beam spacing [m] (range x angular step of its scan) at the frame points ``idx``
    (K,); None when the frame does not carry the scans its points came from."""
    assert frame.points is not None
    points = frame.points
    scans = {scan.sensor: scan for scan in frame.scans}
    out = np.empty(idx.size)
    sensor = points.sensor_ids[idx]
    beams = points.beams[idx]
    for s in np.unique(sensor):
        scan = scans.get(points.sensors[int(s)])
        if scan is None:
            return None
        here = sensor == s
        out[here] = scan.ranges[beams[here]] * abs(scan.angle_increment)
    return out


def _stems(label: str) -> list[str]:
    """``label`` and the labels it came from by splits: ``3-0-1`` -> ``3-0-1``, ``3-0``,
    ``3``."""
    parts = label.split("-")
    return ["-".join(parts[:k]) for k in range(len(parts), 0, -1)]


__all__ = [
    "GroupEstimate",
    "GroupEvent",
    "GroupMHTTracker",
    "GroupTrackerParams",
]
