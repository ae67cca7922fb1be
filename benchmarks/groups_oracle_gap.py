"""Where the group tracker misses true groups that 000's clustering of the true people gets:
each true group-frame matched by the oracle of ``groups_truth_bound.py`` (the true people by
single linkage of their legs at d_P, links between people moving 0.5 m/s or more apart cut)
and missed by the tracker, by what the tracker did in that scan; and the other way round.

Both are scored by CLEAR MOT as ``groups_random.py`` scores the tracker (gate 1 m, the
identity carried over from the last frame), each with its own matching. What the tracker
did with a group the oracle gets and it misses:

- *unseen, coasted > 1 m off*: no point of the group in this scan, a coasted report (no
  points) within 2 m of its centre, none within 1 m;
- *unseen, nothing reported near*: no point of it in this scan and no report within 2 m
  (coasting ended or never began: hidden or out of view for longer than ``coast_time``);
- *unseen, track near taken*: no point of it, a report within 1 m matched to another group;
- *seen, in no reported group*: its points are in no reported group (a group not
  confirmed yet, or its points in no track of the best hypothesis);
- *over-split*: its points in two or more reported groups;
- *joined, track on the other party*: its points in a reported group that also holds
  another true group's points, the group's position within 1 m of it but matched to the
  other party;
- *joined, centre > 1 m off*: the same, the position more than 1 m from it;
- *own, centre > 1 m off*: in one reported group holding no other true group, more than
  1 m from its centre (a track that lags, a split half at its parent's prediction);
- *own, track taken*: the same within 1 m, the track matched to another true group.

The *joined* ones are also counted by whether the two parties' points lie in one cluster
at d_P, whether they move alike or pass (``near_and_alike``), and which event made the
holder; and by where the id the party was last matched to is now (the holder's, coasted,
on another group, no longer reported). The *unseen, nothing reported near* ones by how long
the group has been unseen and whether the tracker still remembers its last id for
coasting. Also the id switches of both and, per seed, the runs of scans where the extra
misses pile up (to look at with ``laserpeople view``).

    PYTHONPATH=src python benchmarks/groups_oracle_gap.py [--seeds 0-19] [--seconds 40]
        [--set NAME=VALUE ...] [--jobs 2]
"""

from __future__ import annotations

import argparse
from collections import Counter
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from groups_random import parse_seeds  # type: ignore[import-not-found]
from groups_table import _with  # type: ignore[import-not-found]
from groups_truth_bound import as_tracks, clustering_000  # type: ignore[import-not-found]
from laserpeople.clustering import single_linkage
from laserpeople.config import load_config
from laserpeople.evaluation.clear_mot import ClearMot
from laserpeople.evaluation.groups import (
    ALONE_ID,
    GROUP_GATE,
    LabelledFrame,
    frames_from_scans,
    group_truth,
    near_and_alike,
)
from laserpeople.evaluation.params import EvaluationParams
from laserpeople.pipeline.background import at_torso_height
from laserpeople.sim.scenarios import build_scene, run_scenario
from laserpeople.tracking.groups import GroupMHTTracker, GroupTrackerParams
from laserpeople.tracks import Track, Tracks
from laserpeople.truth import TruthFrame

NEAR = 2.0
"""A coasted report within this of a missed unseen group's centre counts as coasting for it [m]."""
WALKING = 0.3
"""Mean speed of a group's members above which it walks [m/s]."""


def matched(mot: ClearMot) -> dict[int, int]:
    """Truth id -> track id of the pairs ``mot`` made in the frame it last accumulated."""
    return dict(mot.last_pairs)


def switched(before: dict[int, int], now: dict[int, int]) -> set[int]:
    """Truth ids matched now to another track than their last match."""
    return {oid for oid, tid in now.items() if oid in before and before[oid] != tid}


def speed_bucket(seconds: float, edges: tuple[float, float]) -> str:
    """``seconds`` as ``< a s``, ``a-b s`` or ``>= b s`` for ``edges`` (a, b)."""
    a, b = edges
    return f"< {a:g} s" if seconds < a else f"{a:g}-{b:g} s" if seconds < b else f">= {b:g} s"


class Scene:
    """The counts of one scene, frame by frame (see the module doc)."""

    def __init__(self, tracker: GroupMHTTracker, d_p: float) -> None:
        self.tracker = tracker
        self.d_p = d_p
        self.causes: Counter[str] = Counter()
        self.motion: Counter[str] = Counter()  # "cause | walk" / "cause | stand"
        self.joined: Counter[str] = Counter()
        self.ids_state: Counter[str] = Counter()
        self.unseen: Counter[str] = Counter()
        self.per_scan: Counter[int] = Counter()
        self.switches: Counter[str] = Counter()
        self.only_tracker = 0
        self.n_truth = 0
        self.last_t: dict[int, int] = {}  # truth id -> track id of its last tracker match
        self.last_o: dict[int, int] = {}
        self.hit_at: dict[int, float] = {}  # truth id -> time [s] of its last tracker match
        self.seen_at: dict[int, float] = {}  # truth id -> time [s] its points were last seen

    def frame(
        self,
        lf: LabelledFrame,
        frame: TruthFrame,
        reported: Tracks,
        mots: tuple[ClearMot, ClearMot],
    ) -> None:
        """Score one frame of the tracker's ``reported`` groups and the oracle's."""
        true = group_truth(frame)
        mots[0].accumulate(true, reported)
        mots[1].accumulate(true, as_tracks(frame, clustering_000(frame, self.d_p)))
        hit_t, hit_o = matched(mots[0]), matched(mots[1])
        self.switches["tracker"] += len(switched(self.last_t, hit_t))
        self.switches["oracle"] += len(switched(self.last_o, hit_o))
        before = dict(self.last_t)
        self.last_t.update(hit_t)
        self.last_o.update(hit_o)
        stamp = lf.frame.stamp
        self.n_truth += len(true)
        self.only_tracker += sum(1 for oid in hit_t if oid not in hit_o)
        fg = np.asarray(lf.frame.foreground)
        points = lf.frame.points
        assert points is not None
        est = self.tracker.point_labels(len(points))
        # point labels are families; the first reports are ``last_groups`` in order (coasted
        # vanished ones follow)
        groups = self.tracker.last_groups
        holders = {g.family: (g, t) for g, t in zip(groups, reported.tracks, strict=False)}
        coasted = reported.tracks[len(groups) :]
        taken = set(hit_t.values())
        cluster = np.full(fg.size, -1, dtype=np.int64)
        cluster[fg] = single_linkage(points.points[fg], self.d_p)
        for (g, people), oid, centre in zip(
            frame.groups().items(), true.person_ids.tolist(), true.positions, strict=True
        ):
            assert oid == (g if g >= 0 else ALONE_ID - g - 1)
            mine = np.isin(lf.true_person, people) & fg
            if mine.any():
                self.seen_at[oid] = stamp
            if oid in hit_t:
                self.hit_at[oid] = stamp
            if oid in hit_t or oid not in hit_o:
                continue
            d_coast = [float(np.hypot(*(t.position - centre))) for t in coasted]
            if not mine.any():
                within = [
                    t for t in reported.tracks if np.hypot(*(t.position - centre)) <= GROUP_GATE
                ]
                if any(t.track_id in taken for t in within):
                    cause = "unseen, track near taken"
                elif d_coast and min(d_coast) <= NEAR:
                    cause = "unseen, coasted > 1 m off"
                else:
                    cause = "unseen, nothing reported near"
                    self.unseen[self._unseen_state(oid, stamp)] += 1
            else:
                labels = np.unique(est[mine])
                labels = labels[labels >= 0]
                if labels.size == 0:
                    cause = "seen, in no reported group"
                elif labels.size > 1:
                    cause = "over-split"
                else:
                    g_est, holder = holders[int(labels[0])]
                    off = float(np.hypot(*(holder.position - centre))) > GROUP_GATE
                    other = (est == labels[0]) & fg & ~mine
                    if not other.any():
                        cause = "own, centre > 1 m off" if off else "own, track taken"
                    else:
                        cause = "joined, " + (
                            "centre > 1 m off" if off else "track on the other party"
                        )
                        one = np.intersect1d(cluster[mine], cluster[other]).size > 0
                        how = self._motion(frame, people, lf.true_person[other])
                        self.joined[
                            f"{'one cluster' if one else 'two clusters'}, {how}, "
                            f"holder made by {g_est.event or 'neither'}"
                        ] += 1
                        state = self._id_state(before.get(oid), holder, reported, coasted, centre)
                        age = speed_bucket(stamp - self.hit_at.get(oid, -1e9), (1.0, 3.0))
                        self.ids_state[f"{state} | last matched {age} ago"] += 1
            self.causes[cause] += 1
            rows = np.isin(frame.person_ids, people)
            speed = float(np.hypot(*frame.velocities[rows].mean(axis=0)))
            self.motion[f"{cause} | {'walk' if speed > WALKING else 'stand'}"] += 1
            self.per_scan[lf.frame.index] += 1

    def _unseen_state(self, oid: int, stamp: float) -> str:
        """How long an unseen group has been unseen, and whether its last id is remembered
        by the tracker's coasting (remembered: not coasted now because it had been reported
        for less time than it has been gone, or past ``coast_time``)."""
        since = speed_bucket(stamp - self.seen_at.get(oid, -1e9), (1.0, 2.0))
        prev = self.last_t.get(oid)
        if prev is None:
            return f"unseen {since} | never matched"
        if prev in self.tracker.coasting:
            return f"unseen {since} | last id remembered, not coasted"
        return f"unseen {since} | last id forgotten"

    def _motion(self, frame: TruthFrame, people: list[int], others: np.ndarray) -> str:
        """``alike``, ``passing`` or ``apart``: a leg of ``people`` within d_P of a leg of
        the true people ``others`` (point labels, -1 none) moving alike, differently, or
        none within d_P."""
        rows_m = np.flatnonzero(np.isin(frame.person_ids, people))
        rows_o = np.flatnonzero(np.isin(frame.person_ids, others[others >= 0]))
        near, alike = near_and_alike(frame, rows_m, rows_o, self.d_p)
        return "alike" if np.any(near & alike) else "passing" if near.any() else "apart"

    def _id_state(
        self,
        prev: int | None,
        holder: Track,
        reported: Tracks,
        coasted: tuple[Track, ...],
        centre: np.ndarray,
    ) -> str:
        """Where the last id ``prev`` a joined party was matched to is now."""
        if prev is None:
            return "never matched before"
        if prev == holder.track_id:
            return "its last id is the holder's"
        now = {t.track_id: t for t in reported.tracks}.get(prev)
        if now is not None:
            far = "> 1 m off" if np.hypot(*(now.position - centre)) > GROUP_GATE else "taken"
            return f"its last id {'coasted' if now in coasted else 'reported with points'}, {far}"
        if prev in self.tracker.coasting:
            return "its last id not reported, remembered (reported shorter than gone)"
        return "its last id not reported, its coasting ended"


def run_seed(seed: int, seconds: float, params: GroupTrackerParams) -> dict[str, object]:
    """One scene: the tracker's misses of groups the oracle gets, by cause; the reverse."""
    sim = run_scenario("random-groups", seconds=seconds, seed=seed)
    height = build_scene("random-groups", seconds=seconds, seed=seed).notes["scanner"]
    tracker = GroupMHTTracker(params)
    tracker.use_torso_height(at_torso_height(float(height["height_m"])))
    truth_of = {f.scan_index: f for f in sim.truth}
    ep = EvaluationParams(gate=GROUP_GATE, kind="group")
    mots = (ClearMot(ep, keep_frames=False), ClearMot(ep, keep_frames=False))
    scene = Scene(tracker, params.cluster_distance)
    for lf in frames_from_scans(sim.scans):
        reported = tracker.update(lf.frame)
        frame = truth_of.get(lf.frame.index)
        if frame is not None and len(frame):
            scene.frame(lf, frame, reported, mots)
    return {
        "causes": scene.causes,
        "motion": scene.motion,
        "joined": scene.joined,
        "ids_state": scene.ids_state,
        "unseen": scene.unseen,
        "only_tracker": scene.only_tracker,
        "switches": scene.switches,
        "truth": scene.n_truth,
        "tracker": mots[0].result(),
        "oracle": mots[1].result(),
        "per_scan": scene.per_scan,
    }


def worst_runs(per_scan: Counter[int], scans: int = 3) -> str:
    """The ``scans`` longest runs of consecutive scans with extra misses, as first-last."""
    idx = sorted(per_scan)
    runs: list[tuple[int, int, int]] = []  # (misses, first, last)
    for k in idx:
        if runs and k == runs[-1][2] + 1:
            runs[-1] = (runs[-1][0] + per_scan[k], runs[-1][1], k)
        else:
            runs.append((per_scan[k], k, k))
    runs.sort(reverse=True)
    return ", ".join(f"scans {a}-{b} ({n})" for n, a, b in runs[:scans])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seeds", default="0-19", help="tune on 0-19; 100-119 are held back")
    ap.add_argument("--seconds", type=float, default=40.0)
    ap.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE")
    ap.add_argument("--jobs", type=int, default=1)
    args = ap.parse_args()
    params = _with(load_config(GroupTrackerParams, None, None), args.set)
    seeds = parse_seeds(args.seeds)
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        jobs = [pool.submit(run_seed, s, args.seconds, params) for s in seeds]
        out = [j.result() for j in jobs]
    causes: Counter[str] = sum((r["causes"] for r in out), Counter())  # type: ignore[misc]
    motion: Counter[str] = sum((r["motion"] for r in out), Counter())  # type: ignore[misc]
    switches: Counter[str] = sum((r["switches"] for r in out), Counter())  # type: ignore[misc]
    truth = sum(int(r["truth"]) for r in out)  # type: ignore[call-overload]
    extra = sum(causes.values())
    reverse = sum(int(r["only_tracker"]) for r in out)  # type: ignore[call-overload]
    for seed, r in zip(seeds, out, strict=True):
        t, o = r["tracker"], r["oracle"]
        n = sum(r["causes"].values())  # type: ignore[attr-defined]
        print(
            f"seed {seed}: tracker {t.mota:.3f} (miss {t.misses}), oracle {o.mota:.3f} "  # type: ignore[attr-defined]
            f"(miss {o.misses}); oracle gets, tracker misses {n}; worst: "  # type: ignore[attr-defined]
            f"{worst_runs(r['per_scan'])}"  # type: ignore[arg-type]
        )
    print(
        f"\nseeds {args.seeds}, {args.seconds:g} s: {truth} true group-frames; the oracle gets "
        f"and the tracker misses {extra} ({100 * extra / truth:.1f} %), the tracker gets and "
        f"the oracle misses {reverse} ({100 * reverse / truth:.1f} %); id switches tracker "
        f"{switches['tracker']}, oracle {switches['oracle']}\n"
    )
    print("| the tracker | group-frames | of the extra misses | walking | standing |")
    print("|---|---|---|---|---|")
    for cause, n in causes.most_common():
        walk, stand = motion[f"{cause} | walk"], motion[f"{cause} | stand"]
        print(f"| {cause} | {n} | {100 * n / extra:.1f} % | {walk} | {stand} |")
    joined: Counter[str] = sum((r["joined"] for r in out), Counter())  # type: ignore[misc]
    print("\n| joined: the two parties' points, their motion, the holder | group-frames |")
    print("|---|---|")
    for key, n in joined.most_common():
        print(f"| {key} | {n} |")
    unseen: Counter[str] = sum((r["unseen"] for r in out), Counter())  # type: ignore[misc]
    print("\n| unseen, nothing reported near: unseen for, its last id | group-frames |")
    print("|---|---|")
    for key, n in unseen.most_common():
        print(f"| {key} | {n} |")
    ids_state: Counter[str] = sum((r["ids_state"] for r in out), Counter())  # type: ignore[misc]
    print("\n| joined: the party's last matched id now | group-frames |")
    print("|---|---|")
    for key, n in ids_state.most_common():
        print(f"| {key} | {n} |")


if __name__ == "__main__":
    main()
