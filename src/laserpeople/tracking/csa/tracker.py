"""The CSA tracker (002 Sec. 2): single targets by the KFA, clusters by the VBA, merges,
splits, births and what is reported (the package's docstring gives the whole)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from laserpeople.background import StaticWorldModel
from laserpeople.frame import Frame, FrameField
from laserpeople.lazy_scipy import linear_sum_assignment
from laserpeople.tracking import kalman
from laserpeople.tracking.csa.clusters import (
    fragment_origins,
    gate_components,
    leader_clusters,
    on_a_wall,
    person_groups,
    split_ready,
)
from laserpeople.tracking.csa.leg_people import LegPeople, missed_legs, unheld_people
from laserpeople.tracking.csa.params import CSAParams
from laserpeople.tracking.csa.viterbi import (
    Estimates,
    coast_people,
    gate_loglik,
    per_person_scores,
    viterbi_step,
)
from laserpeople.tracking.robot_motion import MotionWatch
from laserpeople.tracks import Track, Tracks

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass
class _Single:
    pid: int
    mean: FloatArray
    cov: FloatArray
    last_seen: float
    spawned_by: int = -1  # the cluster it was started next to (a fragment of its people?)
    born: float = -math.inf  # when it was started from unselected points
    hits: int = 0  # scans in a row with selected measurements (see confirm_scans)
    before: tuple[FloatArray, FloatArray, float] | None = None
    """jump_back: the state (4,), covariance (4, 4) and last-seen time [s] the target had
    before it last jumped (see :meth:`ClusterSortingTracker._jumped`), predicted to its
    last scan."""
    seen_since: float | None = None
    """Since when [s] the target had selected measurements in every scan up to
    ``last_seen`` (None: since ``last_seen``)."""

    def __post_init__(self) -> None:
        if self.seen_since is None:
            self.seen_since = self.last_seen


@dataclass
class _Cluster:
    cid: int
    members: tuple[int, ...]
    means: FloatArray
    covs: FloatArray
    scores: FloatArray
    origin: IntArray  # person each estimate's Viterbi path started from
    last_seen: float
    shown: dict[int, FloatArray] = field(default_factory=dict)  # person -> last shown at
    motion: dict[int, tuple[FloatArray, float]] = field(default_factory=dict)  # velocity, stamp
    born_pid: int = 0  # single targets with a larger id were started after this cluster
    labels: IntArray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    """Sub-cluster of each estimate (leader clustering at subcluster_distance), computed
    once per scan in :meth:`ClusterSortingTracker.update`, after the VBA step."""
    uncounted: list[tuple[FloatArray, float]] = field(default_factory=list)
    """Where (2,) [m] and since when [s] the cluster shows a person-sized group nobody
    holds (count_people)."""
    continued: dict[int, float] = field(default_factory=dict)
    """Person -> when [s] a measurement last continued one of its Viterbi paths
    (coast_people)."""


@dataclass(frozen=True)
class CSAEvent:
    """A merge or split, for inspection and tests.

    Attributes:
        stamp: Time [s].
        kind: "merge person+person", "merge person+cluster", "merge cluster+cluster",
            "split", "split apart" (``members``: the people who left), "adopt orphan" or
            "count people" (``members``: the people added).
        members: The people of the cluster after a merge / before a split.
    """

    stamp: float
    kind: str
    members: tuple[int, ...]


@dataclass
class _State:
    singles: dict[int, _Single] = field(default_factory=dict)
    clusters: dict[int, _Cluster] = field(default_factory=dict)
    next_pid: int = 0
    next_cid: int = 0


class ClusterSortingTracker:
    """The CSA as a :class:`~laserpeople.frame.FrameTracker` on raw foreground points.

    Attributes:
        events: Every merge and split so far (:class:`CSAEvent`).
    """

    consumes: frozenset[FrameField] = frozenset({"points", "foreground"})
    wants_torso_runs = True
    """At torso height its foreground keeps torso-shaped runs too (``[leg_foreground]
    torso_blobs``, :func:`~laserpeople.pipeline.leg_foreground.wants_torso_runs`)."""

    def __init__(self, params: CSAParams | None = None) -> None:
        self.params = params or CSAParams()
        self.learns_behind_people = self.params.background_people
        """Whether the pipeline's per-beam histogram leaves out the people standing while
        it learns (:func:`~laserpeople.pipeline.leg_foreground.learns_behind_people`)."""
        self._s = _State()
        self._last: float | None = None
        self.events: list[CSAEvent] = []
        self._motion = MotionWatch()
        self._moving = False
        """Whether the laser of this world-frame run has moved (see ``moving_travel``)."""
        self._posed = False
        """Whether this is a world-frame run with the laser's poses (see ``moving_travel``)."""
        self._scan_points = np.empty((0, 2))
        self._unwalked: dict[int, tuple[FloatArray, float]] = {}
        """Person -> where (2,) [m] and when [s] its travel is measured from (where it was
        started, moved on every ``moving_window``), while it has not walked
        ``moving_travel`` from there (world-frame runs with poses)."""
        self._stamp = 0.0
        self._people: LegPeople | None = LegPeople() if self.params.moving_people else None
        """The leg MHT's people (``moving_people``), run on the frames with poses and legs
        once the laser has moved (before, only their last seconds are held)."""
        if self._people is not None:
            self.consumes = self.consumes | {"legs"}
        self.at_torso_height = False
        """Whether the recording states the laser at torso height
        (:meth:`use_torso_height`): people are counted into clusters after
        ``torso_count_seconds`` instead of ``count_seconds``."""

    def use_people_static_model(self, model: StaticWorldModel | None) -> None:
        """The static world model the leg MHT's people of ``moving_people`` ask (the
        pipeline feeds it each frame; None: none). Nothing to do without the setting."""
        if self._people is not None:
            self._people.use_static_model(model)

    def use_torso_height(self, torso: bool) -> None:
        """Whether the recording states the laser at torso height (the pipeline tells it,
        :func:`~laserpeople.pipeline.background.set_laser_height`)."""
        self.at_torso_height = torso

    # ------------------------------------------------------------------ helpers
    def _new_single(self, pos: FloatArray, stamp: float) -> None:
        p = self.params
        pid = self._s.next_pid
        self._s.next_pid += 1
        spawned_by = -1
        reach = p.init_distance + p.max_gate_distance
        for c in self._s.clusters.values():
            if np.min(np.linalg.norm(c.means[:, :2] - pos, axis=1)) < reach:
                spawned_by = c.cid
                break
        self._s.singles[pid] = _Single(
            pid, np.r_[pos, 0.0, 0.0], self._init_cov(), stamp, spawned_by, stamp, 1
        )
        self._started(pid, pos)

    def _init_cov(self) -> FloatArray:
        """Covariance (4, 4) of a new single target."""
        p = self.params
        v = p.init_velocity_std**2
        return np.diag([p.mean_std**2, p.mean_std**2, v, v])

    def _points(self, frame: Frame) -> FloatArray:
        if frame.points is None or frame.foreground is None:
            from laserpeople.errors import LaserPeopleError

            raise LaserPeopleError(
                "the CSA needs the frame's points and foreground mask",
                scan=frame.index,
                hint="run the preprocess stage before the csa tracker",
            )
        return frame.points.points[np.asarray(frame.foreground, dtype=bool)]

    # ------------------------------------------------------------------ update
    def update(self, frame: Frame) -> Tracks:
        """Process one frame's foreground points; return the tracks after it."""
        p = self.params
        z = self._points(frame)
        assert frame.points is not None
        self._scan_points = np.asarray(frame.points.points, dtype=np.float64)
        stamp = frame.stamp
        self._stamp = float(stamp)
        if frame.frame == "world":
            self._moving = self._motion(frame.sensor_pose)
            self._posed = frame.sensor_pose is not None
        world = self._posed and frame.frame == "world" and frame.legs is not None
        people = self._people if world else None
        if people is not None and not self._moving:
            people.hold(frame)  # nothing of it is used before the laser moves
        elif people is not None:
            people.update(frame)
            # the legs the leg MHT holds and the foreground lacks
            z = np.vstack([z, missed_legs(z, people.legs)])
        dt = 0.0 if self._last is None else min(max(stamp - self._last, 0.0), p.max_dt)
        prev = self._last
        self._last = stamp
        point_var = p.point_std**2
        gate2 = p.gate
        s = self._s

        singles = list(s.singles.values())
        clusters = list(s.clusters.values())
        # predict every single target and every cluster estimate
        if singles:
            sm, sc = kalman.predict(
                np.array([t.mean for t in singles]),
                np.array([t.cov for t in singles]),
                np.full(len(singles), dt),
                p.person_accel_psd,
            )
        else:
            sm, sc = np.empty((0, 4)), np.empty((0, 4, 4))
        cpred = [
            kalman.predict(c.means, c.covs, np.full(len(c.means), dt), p.point_accel_psd)
            for c in clusters
        ]
        # validation gates of every object over the measurements
        cap = p.max_gate_distance
        gates = np.zeros((len(singles) + len(clusters), z.shape[0]), dtype=bool)
        if singles and z.size:
            gates[: len(singles)] = gate_loglik(sm, sc, z, point_var, gate2, cap)[0]
        for k, (cm, cc) in enumerate(cpred):
            if z.size and cm.size:
                g = gate_loglik(cm, cc, z, point_var, gate2, cap)[0]
                gates[len(singles) + k] = g.any(axis=0)
        comps = gate_components(gates)
        selected_any = gates.any(axis=0)
        free = np.asarray(~selected_any, dtype=bool)  # no object selects (jump_back takes some)

        new_singles: dict[int, _Single] = {}
        new_clusters: dict[int, _Cluster] = {}
        for comp in comps:
            objs_s = [i for i in comp if i < len(singles)]
            if len(comp) == 1 and objs_s:
                i = objs_s[0]
                t = singles[i]
                sel = gates[i]
                before = self._before(t, dt)
                if sel.any():  # KFA: the mean of the selected measurements
                    centre = z[sel].mean(axis=0)
                    mean, cov = kalman.update(sm[i], sc[i], centre, np.eye(2) * p.mean_std**2)
                    unseen = prev is not None and t.last_seen < prev
                    jumped = self._jumped(t, sm[i], centre, unseen)
                    new_singles[t.pid] = _Single(
                        t.pid,
                        mean,
                        cov,
                        stamp,
                        t.spawned_by,
                        t.born,
                        t.hits + 1,
                        (sm[i], sc[i], t.last_seen) if jumped else None,
                        stamp if unseen else t.seen_since,
                    )
                    self._walked(t.pid, centre)
                elif (
                    before is not None
                    and (back := self._jump_back(before, z, free)).sum() >= p.min_points
                ):
                    free &= ~back  # the target goes back to its state before the jump
                    centre = z[back].mean(axis=0)
                    mean, cov = kalman.update(
                        before[0], before[1], centre, np.eye(2) * p.mean_std**2
                    )
                    new_singles[t.pid] = _Single(
                        t.pid, mean, cov, stamp, t.spawned_by, t.born, t.hits + 1, None, stamp
                    )
                    self._walked(t.pid, centre)
                elif stamp - t.last_seen <= p.max_unseen + p.lost_keep:
                    # a miss before confirmation starts the count again
                    hits = t.hits if t.hits >= p.confirm_scans else 0
                    new_singles[t.pid] = _Single(
                        t.pid,
                        sm[i],
                        sc[i],
                        t.last_seen,
                        t.spawned_by,
                        t.born,
                        hits,
                        before,
                        t.seen_since,
                    )
                continue
            cl = self._vba(comp, singles, sm, sc, clusters, cpred, z, stamp, point_var)
            if cl is None:
                continue
            cl.labels = leader_clusters(cl.means[:, :2], p.subcluster_distance)
            if p.adopt_orphans:
                self._orphans_claim(cl)
            if p.cut_free:
                self._cut_free(cl, stamp, new_singles)
            if p.count_people:
                self._count_people(cl, stamp)
            done = self._maybe_split(cl, stamp, new_singles)
            if not done and p.split_apart:
                done = self._split_apart(cl, stamp, new_singles)
            if not done:
                new_clusters[cl.cid] = cl
        if p.adopt_orphans:
            self._adopt_orphans(new_singles, new_clusters, stamp)
        if p.adopt_escaped:
            self._adopt_escaped(new_singles, new_clusters, stamp)
        s.singles = new_singles
        s.clusters = new_clusters
        if self._unwalked:  # forget the people deleted
            alive = set(new_singles).union(*(c.members for c in new_clusters.values()))
            self._unwalked = {k: v for k, v in self._unwalked.items() if k in alive}
        if people is not None and self._moving:
            self._people_births(people.people, stamp)
        else:
            self._initiate(z[free], stamp)
        return self._report(frame)

    def _jumped(self, t: _Single, pred: FloatArray, centre: FloatArray, unseen: bool) -> bool:
        """``jump_back``: whether single target ``t``, predicted to ``pred`` (4,), jumps by
        taking selected measurements with mean ``centre`` (2,) [m] after a scan without any
        (``unseen``): farther than ``init_distance`` from its prediction, having had
        selected measurements in every scan for at least ``jump_back_seen`` [s] before the
        gap (a person tracked steadily, not a flickering blob)."""
        p = self.params
        if not (p.jump_back and unseen):
            return False
        assert t.seen_since is not None
        steady = t.last_seen - t.seen_since >= p.jump_back_seen
        return steady and float(np.hypot(*(centre - pred[:2]))) > p.init_distance

    def _before(self, t: _Single, dt: float) -> tuple[FloatArray, FloatArray, float] | None:
        """``jump_back``: the state of single target ``t`` before its last jump, predicted
        by ``dt`` [s], or None (none kept, or last seen more than ``max_unseen`` ago)."""
        if t.before is None or self._stamp - t.before[2] > self.params.max_unseen:
            return None
        mean, cov = kalman.predict(
            t.before[0][None], t.before[1][None], np.array([dt]), self.params.person_accel_psd
        )
        return mean[0], cov[0], t.before[2]

    def _jump_back(
        self, before: tuple[FloatArray, FloatArray, float], z: FloatArray, free: NDArray[np.bool_]
    ) -> NDArray[np.bool_]:
        """``jump_back``: which measurements ``z`` (M, 2) [m] among the ``free`` ones (M,)
        lie inside the gate of the state ``before`` (see :meth:`_before`)."""
        p = self.params
        inside = gate_loglik(
            before[0][None], before[1][None], z, p.point_std**2, p.gate, p.max_gate_distance
        )[0][0]
        return np.asarray(inside & free, dtype=bool)

    def _people_births(self, people: FloatArray, stamp: float) -> None:
        """``moving_people``: a single target for each of the leg MHT's ``people`` (P, 2)
        [m] that no object holds (:func:`~laserpeople.tracking.csa.leg_people.unheld_people`),
        reported at once (the MHT confirmed it, on a place not static for long)."""
        s = self._s
        objects = [t.mean[:2] for t in s.singles.values()]
        objects += [c.means[:, :2] for c in s.clusters.values()]
        held = np.vstack(objects) if objects else np.empty((0, 2))
        for xy in unheld_people(people, held):
            pid = s.next_pid
            self._new_single(xy, stamp)
            self._unwalked.pop(pid, None)
            s.singles[pid].hits = self.params.confirm_scans

    def _confirmed(self, t: _Single) -> bool:
        """Whether single target ``t`` is reported (see ``confirm_scans``)."""
        if not self._shown_walker(t.pid):
            return False
        return t.born == -math.inf or t.hits >= self.params.confirm_scans

    def _started(self, pid: int, xy: FloatArray) -> None:
        """Remember where person ``pid`` was started at (2,) [m] in a world-frame run with
        poses, until it walked ``moving_travel`` from there (see :meth:`_walked`)."""
        if self._posed and self.params.moving_travel > 0:
            self._unwalked[pid] = (np.array(xy, dtype=np.float64), self._stamp)

    def _walked(self, pid: int, xy: FloatArray) -> None:
        """Person ``pid`` was seen at ``xy`` (2,) [m]: once that lies ``moving_travel``
        from where it was started (or, after ``moving_window``, from where it was then),
        it has walked, for good."""
        held = self._unwalked.get(pid)
        if held is None:
            return
        start, since = held
        if float(np.hypot(*(xy - start))) < self.params.moving_travel:
            window = self.params.moving_window
            if window > 0 and self._stamp - since >= window:  # too slow: measure anew
                self._unwalked[pid] = (np.array(xy, dtype=np.float64), self._stamp)
            return
        wall = self.params.moving_wall
        if wall > 0 and on_a_wall(xy, self._scan_points, wall):
            return  # sliding along a wall as the laser's view moves
        del self._unwalked[pid]

    def _adopted(self, target: int, person: int, last: FloatArray | None = None) -> None:
        """Person ``person``, last estimated at ``last`` (2,) [m] (None: unknown), is
        continued by the single target ``target`` (adopt_orphans, adopt_escaped): when that
        target has not walked ``moving_travel``, neither has the person, from where the
        target was started. On a moving laser new targets start on furniture all over the
        scene; one that took a walked person's identity was reported at once, wherever it
        stood. A target started within ``moving_adopt_near`` of where a person who walked
        was last estimated is that person found again: it keeps having walked."""
        start = self._unwalked.pop(target, None)
        if start is None:
            return
        near = self.params.moving_adopt_near
        gap = math.inf if last is None else float(np.hypot(*(start[0] - last)))
        if person not in self._unwalked and near > 0 and gap <= near:
            return  # the person found again next to where it was lost
        self._unwalked[person] = start

    def _shown_walker(self, pid: int) -> bool:
        """Whether person ``pid`` may be reported under ``moving_travel``: the laser has not
        moved, or the person walked since it was started from unselected points (as a
        single target, a person of a cluster, or a target split from one)."""
        return not (self._moving and pid in self._unwalked)

    def _shown_unseen(self, t: _Single, stamp: float) -> bool:
        """Whether single target ``t``, unseen since ``t.last_seen``, is still reported at
        ``stamp`` [s] (see ``moving_unseen``; never once unseen for ``max_unseen``, while
        ``lost_keep`` keeps it)."""
        limit = self.params.moving_unseen
        if stamp - t.last_seen > self.params.max_unseen:
            return False
        return not (self._moving and limit > 0 and stamp - t.last_seen > limit)

    def _vba(
        self,
        comp: list[int],
        singles: list[_Single],
        sm: FloatArray,
        sc: FloatArray,
        clusters: list[_Cluster],
        cpred: list[tuple[FloatArray, FloatArray]],
        z: FloatArray,
        stamp: float,
        point_var: float,
    ) -> _Cluster | None:
        """Run the VBA on a cluster, merging the objects of ``comp`` first."""
        p = self.params
        ns = len(singles)
        objs_s = [i for i in comp if i < ns]
        objs_c = [i - ns for i in comp if i >= ns]
        means = [sm[objs_s]] + [cpred[k][0] for k in objs_c]
        covs = [sc[objs_s]] + [cpred[k][1] for k in objs_c]
        scores = [np.zeros(len(objs_s))] + [
            clusters[k].scores - clusters[k].scores.max() for k in objs_c
        ]
        origin = [np.array([singles[i].pid for i in objs_s], dtype=np.int64)] + [
            clusters[k].origin for k in objs_c
        ]
        # with the fragment rule (extension of 002), a target started next to one of
        # these clusters and merging back into it is a fragment of the cluster's people
        cids = {clusters[k].cid for k in objs_c} if p.fragment_rule else set()
        joining = {singles[i].pid for i in objs_s if singles[i].spawned_by not in cids}
        if p.fragment_rule:
            # a target younger than fragment_age is not yet a person: merging, it is a
            # fragment of the others (of the oldest of the young, when all are young)
            young = {singles[i].pid for i in objs_s if stamp - singles[i].born < p.fragment_age}
            older = (joining - young) | {m for k in objs_c for m in clusters[k].members}
            joining -= young
            if not older and young:
                joining = {min(young)}
        members = tuple(sorted(joining.union(*[clusters[k].members for k in objs_c])))
        last_seen = max(
            [singles[i].last_seen for i in objs_s] + [clusters[k].last_seen for k in objs_c]
        )
        if len(comp) > 1:
            kind = (
                "merge person+person"
                if not objs_c
                else "merge cluster+cluster"
                if len(objs_c) > 1
                else "merge person+cluster"
            )
            self.events.append(CSAEvent(stamp, kind, members))
        shown = {singles[i].pid: sm[i, :2] for i in objs_s}
        motion = {singles[i].pid: (sm[i, 2:], stamp) for i in objs_s}
        continued = {singles[i].pid: singles[i].last_seen for i in objs_s}
        for k in objs_c:
            shown.update(clusters[k].shown)
            motion.update(clusters[k].motion)
            continued.update(clusters[k].continued)
        born = min([clusters[k].born_pid for k in objs_c], default=self._s.next_pid)
        since = [u for k in objs_c for u in clusters[k].uncounted]
        if objs_c:
            cid = clusters[objs_c[0]].cid
        else:
            cid = self._s.next_cid
            self._s.next_cid += 1
        all_means = np.concatenate(means)
        all_covs = np.concatenate(covs)
        all_scores = np.concatenate(scores)
        all_origin = fragment_origins(np.concatenate(origin), members, shown)
        if p.person_scores:
            all_scores = per_person_scores(all_scores, all_origin)
        step = viterbi_step(
            all_means,
            all_covs,
            all_scores,
            z,
            point_var,
            p.gate,
            p.max_gate_distance,
            all_origin if p.person_mixture else None,
        )
        if step.predecessor.size == 0:  # nothing seen: coast every estimate
            if stamp - last_seen > p.max_unseen + p.lost_keep:
                return None
            return _Cluster(
                cid,
                members,
                all_means,
                all_covs,
                all_scores,
                all_origin,
                last_seen,
                shown,
                motion,
                born,
                uncounted=since,
                continued=continued,
            )
        kept: Estimates = (step.means, step.covs, step.scores, all_origin[step.predecessor])
        if p.coast_people:
            kept = coast_people(
                kept,
                (all_means, all_covs, all_scores, all_origin),
                continued,
                (stamp, last_seen),
                p.max_unseen,
            )
        return _Cluster(
            cid,
            members,
            *kept,
            stamp,
            shown,
            motion,
            born,
            uncounted=since,
            continued=continued,
        )

    def _maybe_split(self, cl: _Cluster, stamp: float, out: dict[int, _Single]) -> bool:
        """Split ``cl`` into single targets when 002's conditions 1 and 2 hold."""
        ok, labels = split_ready(cl.means[:, :2], len(cl.members), self.params, cl.labels)
        if not ok:
            return False
        ids = self._subcluster_ids(cl, labels)
        for sub, pid in enumerate(ids):
            sel = labels == sub
            out[pid] = _Single(pid, cl.means[sel].mean(axis=0), self._init_cov(), stamp)
        self.events.append(CSAEvent(stamp, "split", cl.members))
        return True

    def _split_apart(self, cl: _Cluster, stamp: float, out: dict[int, _Single]) -> bool:
        """Let every person of ``cl`` that is apart leave it (``split_apart``): its main
        sub-cluster (``cl.labels``) holds no other person's main paths and its centroid
        lies farther than ``separation_distance`` from every other sub-cluster's centroid
        (002 condition 2 for that person alone). Its estimates become the single target
        written to ``out`` with its identity (at their mean, as 002's split starts its
        targets), the others stay; when every sub-cluster is apart, nobody leaves (002's
        split, or ``adopt_escaped`` for a cluster short of sub-clusters, decides). Returns
        True when the cluster is left with one person and became a single target itself
        (the cluster is gone), else False."""
        p = self.params
        labels = cl.labels
        n_sub = int(labels.max()) + 1 if labels.size else 0
        if n_sub < 2:
            return False
        cents = np.array([cl.means[labels == k, :2].mean(axis=0) for k in range(n_sub)])
        d = np.linalg.norm(cents[:, None] - cents[None], axis=-1)
        np.fill_diagonal(d, np.inf)
        mains: dict[int, list[int]] = {}
        for m in cl.members:
            own = cl.origin == m
            if own.any():
                k = int(np.argmax(np.bincount(labels[own], minlength=n_sub)))
                mains.setdefault(k, []).append(m)
        leaving = [
            (k, ms[0])
            for k, ms in mains.items()
            if len(ms) == 1 and d[k].min() > p.separation_distance
        ]
        if not leaving or len(leaving) == n_sub:  # all apart: 002's split (or none) decides
            return False
        keep = np.ones(labels.size, dtype=bool)
        for k, m in leaving:
            sel = labels == k
            keep &= ~sel
            out[m] = _Single(m, cl.means[sel].mean(axis=0), self._init_cov(), cl.last_seen)
        gone = tuple(m for _, m in leaving)
        self.events.append(CSAEvent(stamp, "split apart", gone))
        cl.members = tuple(m for m in cl.members if m not in gone)
        cl.means, cl.covs, cl.scores = cl.means[keep], cl.covs[keep], cl.scores[keep]
        cl.origin = cl.origin[keep]
        cl.labels = leader_clusters(cl.means[:, :2], p.subcluster_distance)
        if len(cl.members) != 1:
            return False
        m = cl.members[0]
        out[m] = _Single(m, cl.means.mean(axis=0), self._init_cov(), cl.last_seen)
        return True

    @staticmethod
    def _subcluster_ids(cl: _Cluster, labels: IntArray) -> list[int]:
        """The person for each sub-cluster (see :meth:`_assign_members`)."""
        n_sub = int(labels.max()) + 1
        cents = np.array([cl.means[labels == k, :2].mean(axis=0) for k in range(n_sub)])
        return ClusterSortingTracker._assign_members(cl, cents, labels)

    @staticmethod
    def _assign_members(cl: _Cluster, positions: FloatArray, labels: IntArray) -> list[int]:
        """The person for each of K positions (K, 2) of a cluster, one-to-one by the
        Hungarian algorithm: nearest to where each person was last shown (as a single target
        or a sub-cluster of this cluster), or, when some person was never shown, the one
        most estimates' Viterbi paths started from (``labels`` (E,) gives each estimate's
        position, -1 for none). An extension of 002, which leaves identities after a split
        to colour."""
        n = len(cl.members)
        k = positions.shape[0]
        if all(m in cl.shown for m in cl.members):
            prev = np.array([cl.shown[m] for m in cl.members])
            cost = np.linalg.norm(positions[:, None] - prev[None], axis=-1)
        else:
            index = {m: c for c, m in enumerate(cl.members)}
            cost = np.zeros((k, n))
            for lab, org in zip(labels, cl.origin, strict=True):
                if lab >= 0 and int(org) in index:
                    cost[lab, index[int(org)]] -= 1.0
        rows, cols = linear_sum_assignment(cost)
        ids = [-1] * k
        for r_, c_ in zip(rows, cols, strict=True):
            ids[int(r_)] = cl.members[int(c_)]
        return ids

    def _adopt_escaped(
        self, singles: dict[int, _Single], clusters: dict[int, _Cluster], stamp: float
    ) -> None:
        """Extension of 002 (its Sec. 4 names the failure: a person who walks away in the
        shadow of the others is lost by the VBA and found again as a new target). When a
        cluster shows k sub-clusters fewer than it holds people and exactly k targets were
        started since it formed, the sub-clusters and those targets are its people: if
        they are all pairwise separated (002 condition 2) the cluster splits, and the new
        targets take the remaining identities."""
        p = self.params
        in_clusters = {m for c in clusters.values() for m in c.members}
        for cl in list(clusters.values()):
            labels = cl.labels
            n_sub = int(labels.max()) + 1
            missing = len(cl.members) - n_sub
            if missing <= 0:
                continue
            new = [t for t in singles.values() if t.pid >= cl.born_pid and t.pid not in in_clusters]
            if len(new) != missing:
                continue
            cents = np.array([cl.means[labels == k, :2].mean(axis=0) for k in range(n_sub)])
            pos = np.concatenate([cents, np.array([t.mean[:2] for t in new])])
            d = np.linalg.norm(pos[:, None] - pos[None], axis=-1)
            if not (d[np.triu_indices(len(pos), 1)] > p.separation_distance).all():
                continue
            ids = self._assign_members(cl, pos, labels)
            for sub in range(n_sub):
                mean = cl.means[labels == sub].mean(axis=0)
                singles[ids[sub]] = _Single(ids[sub], mean, self._init_cov(), stamp)
            for t, pid in zip(new, ids[n_sub:], strict=True):
                del singles[t.pid]
                singles[pid] = _Single(pid, t.mean, t.cov, t.last_seen)
                self._adopted(t.pid, pid, cl.shown.get(pid))
            del clusters[cl.cid]
            self.events.append(CSAEvent(stamp, "split", cl.members))

    @staticmethod
    def _main_subclusters(cl: _Cluster) -> set[int]:
        """The sub-clusters of ``cl`` (``cl.labels``) that hold most of some person's
        Viterbi paths (each person's *main* sub-cluster)."""
        n_sub = int(cl.labels.max()) + 1
        return {
            int(np.argmax(np.bincount(cl.labels[cl.origin == m], minlength=n_sub)))
            for m in {int(o) for o in cl.origin}
        }

    def _cut_free(self, cl: _Cluster, stamp: float, out: dict[int, _Single]) -> None:
        """Cut off every sub-cluster of ``cl`` (leader clustering at
        ``subcluster_distance``) that holds none of its people's main paths and lies
        farther than ``subcluster_distance`` from every estimate of the sub-clusters that
        do (a person's legs are never that far apart): with at least ``min_points``
        estimates it becomes a new single target started next to the cluster, at the mean
        of those estimates, written to ``out``; fewer are dropped (see ``cut_free``).
        Called after the orphans' claim, so a person of the cluster who lost its paths
        takes such a sub-cluster first."""
        p = self.params
        if cl.labels.size == 0:
            return
        main = self._main_subclusters(cl)
        n_sub = int(cl.labels.max()) + 1
        held = cl.means[np.isin(cl.labels, list(main)), :2]
        keep = np.ones(cl.labels.size, dtype=bool)
        for k in range(n_sub):
            sel = cl.labels == k
            if k in main:
                continue
            gap = np.linalg.norm(cl.means[sel, None, :2] - held[None], axis=-1).min()
            if gap <= p.subcluster_distance:  # leader clustering cut a person's legs apart
                continue
            keep &= ~sel
            if int(sel.sum()) < p.min_points:  # too few to start a target: dropped
                continue
            pid = self._s.next_pid
            self._s.next_pid += 1
            mean = cl.means[sel].mean(axis=0)
            out[pid] = _Single(pid, mean, self._init_cov(), stamp, cl.cid, stamp, 1)
        if keep.all():
            return
        cl.means, cl.covs, cl.scores = cl.means[keep], cl.covs[keep], cl.scores[keep]
        cl.origin = cl.origin[keep]
        cl.labels = leader_clusters(cl.means[:, :2], p.subcluster_distance)

    def _count_people(self, cl: _Cluster, stamp: float) -> None:
        """Give ``cl`` a new person for every person-sized group of its estimates
        (:func:`person_groups` at ``person_width``) with at least ``count_points``
        estimates that holds no person's main paths (the group holding most of them) and
        whose centre lies farther than ``leg_gap`` from the main group of every person
        whose paths it holds (so it is not that person's other leg), once a group
        so was seen within ``person_width`` of the same place for ``count_seconds``
        (``torso_count_seconds`` at torso height; see ``count_people``): the group's paths
        continue as the new person's."""
        p = self.params
        wait = p.torso_count_seconds if self.at_torso_height else p.count_seconds
        if cl.means.shape[0] < p.count_points:
            cl.uncounted = []
            return
        xy = cl.means[:, :2]
        groups = person_groups(xy, p.person_width)
        n_groups = int(groups.max()) + 1
        cents = np.array([xy[groups == g].mean(axis=0) for g in range(n_groups)])
        main = {
            m: int(np.argmax(np.bincount(groups[cl.origin == m], minlength=n_groups)))
            for m in {int(o) for o in cl.origin}
        }
        sizes = np.bincount(groups, minlength=n_groups)
        seen: list[tuple[FloatArray, float]] = []
        added = []
        origin = cl.origin.copy()
        for g in range(n_groups):
            if sizes[g] < p.count_points:
                continue
            owners = {int(o) for o in cl.origin[groups == g]}
            gap = min(float(np.hypot(*(cents[g] - cents[main[m]]))) for m in owners)
            # (a person's own main group lies at 0: never counted)
            if gap <= p.leg_gap:  # may be an owner's other leg
                continue
            since = min(
                (t for c, t in cl.uncounted if np.hypot(*(c - cents[g])) <= p.person_width),
                default=stamp,
            )
            if stamp - since < wait:
                seen.append((cents[g], since))
                continue
            pid = self._s.next_pid
            self._s.next_pid += 1
            sel = groups == g
            origin[sel] = pid
            cl.shown[pid] = cents[g]
            cl.motion[pid] = (cl.means[sel, 2:].mean(axis=0), stamp)
            added.append(pid)
        cl.uncounted = seen
        if added:
            cl.origin = origin
            cl.members = tuple(sorted((*cl.members, *added)))
            self.events.append(CSAEvent(stamp, "count people", tuple(added)))

    def _orphans_claim(self, cl: _Cluster) -> None:
        """Orphans of cluster ``cl`` (people none of whose Viterbi paths survive) take the
        sub-clusters (leader clustering at ``subcluster_distance``) that are no person's
        main sub-cluster (the one holding most of its paths), nearest first to where the
        orphan was last estimated (Hungarian, within ``separation_distance``); the paths of
        a claimed sub-cluster continue as the orphan's. Another person's paths that took a
        second person's points (people who passed within a leg's width) are given back
        once the two are ``subcluster_distance`` apart."""
        p = self.params
        own = {int(o) for o in cl.origin}
        orphans = [m for m in cl.members if m not in own and m in cl.shown]
        if not orphans:
            return
        labels = cl.labels
        n_sub = int(labels.max()) + 1
        main = self._main_subclusters(cl)
        free = [k for k in range(n_sub) if k not in main]
        if not free:
            return
        cents = np.array([cl.means[labels == k, :2].mean(axis=0) for k in free])
        prev = np.array([cl.shown[m] for m in orphans])
        d = np.linalg.norm(prev[:, None] - cents[None], axis=-1)
        rows, cols = linear_sum_assignment(np.where(d < p.separation_distance, d, 1e6))
        origin = cl.origin.copy()
        for r, c in zip(rows, cols, strict=True):
            if d[r, c] < p.separation_distance:
                origin[labels == free[int(c)]] = orphans[int(r)]
        cl.origin = origin

    def _adopt_orphans(
        self, singles: dict[int, _Single], clusters: dict[int, _Cluster], stamp: float
    ) -> None:
        """A person of a cluster none of whose Viterbi paths survive (an *orphan*: its
        points fell outside every gate, or another person's paths took them) is the target
        started next to the cluster since it formed: the nearest such target within
        ``separation_distance`` of where the orphan was last estimated takes its identity
        (Hungarian on distance) and the orphan leaves the cluster; a cluster left with one
        person becomes a single target again. An extension of 002 (whose VBA keeps a
        cluster's people until the split conditions hold)."""
        p = self.params
        in_clusters = {m for c in clusters.values() for m in c.members}
        for cl in list(clusters.values()):
            own = {int(o) for o in cl.origin}
            orphans = [m for m in cl.members if m not in own and m in cl.shown]
            new = [
                t
                for t in singles.values()
                if t.pid >= cl.born_pid and t.pid not in in_clusters and t.spawned_by == cl.cid
            ]
            if not orphans or not new:
                continue
            prev = np.array([cl.shown[m] for m in orphans])
            pos = np.array([t.mean[:2] for t in new])
            d = np.linalg.norm(prev[:, None] - pos[None], axis=-1)
            rows, cols = linear_sum_assignment(np.where(d < p.separation_distance, d, 1e6))
            taken = []
            for r, c in zip(rows, cols, strict=True):
                if d[r, c] >= p.separation_distance:
                    continue
                m, t = orphans[int(r)], new[int(c)]
                del singles[t.pid]
                singles[m] = _Single(m, t.mean, t.cov, t.last_seen)
                self._adopted(t.pid, m, cl.shown[m])
                taken.append(m)
            if not taken:
                continue
            self.events.append(CSAEvent(stamp, "adopt orphan", tuple(taken)))
            cl.members = tuple(m for m in cl.members if m not in taken)
            if len(cl.members) == 1:
                m = cl.members[0]
                singles[m] = _Single(m, cl.means.mean(axis=0), self._init_cov(), stamp)
                del clusters[cl.cid]

    def _initiate(self, free: FloatArray, stamp: float) -> None:
        if free.shape[0] < self.params.min_points:
            return
        labels = leader_clusters(free, self.params.init_distance)
        counts = np.bincount(labels)
        for k in np.flatnonzero(counts >= self.params.min_points):
            self._new_single(free[labels == k].mean(axis=0), stamp)

    def member_estimates(self, cl: _Cluster, stamp: float) -> dict[int, tuple[FloatArray, ...]]:
        """Where each person of cluster ``cl`` is: person -> (position (2,) [m], velocity
        (2,) [m/s], covariance (2, 2) [m^2]).

        002 keeps every person's identity through a cluster: each estimate of the VBA
        continues a Viterbi path that started at one person (``origin``). A person's
        position is the mean of its estimates (its legs); when its estimates lie in several
        sub-clusters (leader clustering at ``subcluster_distance``), those of the
        sub-cluster holding most of them. A person none of whose paths survived (another's
        took them over) is moved from where it was last estimated by its last velocity for
        up to ``member_coast``, then held, and gets a covariance of one gate.
        Updates the cluster's memory of where and how each person was last seen."""
        p = self.params
        labels = cl.labels
        out: dict[int, tuple[FloatArray, ...]] = {}
        for m in cl.members:
            own = cl.origin == m
            if own.any():
                counts = np.bincount(labels[own])
                sel = own & (labels == int(np.argmax(counts)))
                pos = cl.means[sel, :2]
                vel = cl.means[sel, 2:].mean(axis=0)
                cov = np.cov(pos.T) if pos.shape[0] > 1 else np.zeros((2, 2))
                cov = cov + np.eye(2) * p.mean_std**2
                xy = pos.mean(axis=0)
                self._walked(m, xy)
                cl.shown[m] = xy
                # a person coasting (coast_people) was last moved when last continued
                since = cl.continued.get(m, stamp) if p.coast_people else stamp
                cl.motion[m] = (vel, since)
                out[m] = (xy, vel, cov)
                continue
            if m not in cl.shown:  # never seen in this cluster's memory: its centre
                xy = cl.means[:, :2].mean(axis=0)
                out[m] = (xy, np.zeros(2), np.eye(2) * p.max_gate_distance**2)
                continue
            vel, since = cl.motion.get(m, (np.zeros(2), stamp))
            if stamp - since > p.max_unseen:  # lost inside the cluster: not reported
                continue
            coast = min(max(stamp - since, 0.0), p.member_coast)
            out[m] = (
                cl.shown[m] + vel * coast,
                vel if stamp - since < p.member_coast else np.zeros(2),
                np.eye(2) * p.max_gate_distance**2,
            )
        return out

    def _report(self, frame: Frame) -> Tracks:
        p = self.params
        out: list[Track] = []
        for t in self._s.singles.values():
            if self._confirmed(t) and self._shown_unseen(t, frame.stamp):
                out.append(Track(t.pid, "person", t.mean[:2], t.mean[2:], t.cov[:2, :2]))
        for c in self._s.clusters.values():
            if frame.stamp - c.last_seen > p.max_unseen:  # kept by lost_keep: not reported
                continue
            for pid, (xy, vel, cov) in self.member_estimates(c, frame.stamp).items():
                if not self._shown_walker(pid):
                    continue
                out.append(Track(pid, "person", xy, vel, cov, score=0.5))
            if not p.group_rows:
                continue
            pos = c.means[:, :2]
            cov = np.cov(pos.T) if pos.shape[0] > 1 else np.eye(2) * p.point_std**2
            out.append(
                Track(
                    c.cid,
                    "group",
                    pos.mean(axis=0),
                    c.means[:, 2:].mean(axis=0),
                    cov + np.eye(2) * 1e-6,
                    size=len(c.members),
                    members=c.members,
                )
            )
        frame_name = frame.points.frame if frame.points is not None else frame.frame
        return Tracks(frame.stamp, frame.index, tuple(out), frame_name, frame.sensor_pose)

    @property
    def clusters(self) -> dict[int, tuple[int, ...]]:
        """Cluster id -> the people it holds (the memory of who merged)."""
        return {c.cid: c.members for c in self._s.clusters.values()}
