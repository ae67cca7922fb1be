"""Where the group tracker loses group MOTA on the randomised group scenes: every true
group-frame left unmatched (a miss) by what the tracker did with its points and by what the
group was doing; every unmatched reported group (a false positive) by what it holds; and
the reported group sizes that are wrong (rounded, as ``groups_random.py``'s exact share) by
the true size (the people among the group's points) and the range of its points' mean from
the scanner.

Matching per frame as CLEAR MOT's step 2 (Hungarian, gate 1 m, without the identity
carried over from the last frame, so the counts differ slightly from ``groups_random.py``).

What the tracker did with a missed group's points:

- *merged*: they are in a reported group with points of another true group;
- *over-split*: they are in two or more reported groups;
- *unreported*: seen, but in no reported group (not confirmed yet, or hidden);
- *unseen*: no point of it in this scan (occluded, out of view; the truth keeps a person
  for 2 s after the scanner last hit them); also counted by where its people are: every
  one outside the scan's field of view, every one outside it or beyond the scan's
  ``range_max``, or else in view (hidden behind closer returns), and whether a reported
  group lies within the gate of its centre;
- *offset*: in one reported group of its own, more than 1 m from its centre.

A *merged* miss is also counted by the reported group holding its points: made by a
merge, by a split (a half), or by neither (a track that took both groups' points), and
whether that group was first reported less than 1 s before. A *merged* miss of a group
walking past another is also counted by whether one cluster at d_P of the scan's
foreground held both groups' points (then no split of 000 can part them: a split needs
two observations) and by how long the group and the people of the other true group in the
holder had walked (speed above 0.3 m/s without a break).

What the group was doing: walking or standing (mean speed of its members above or below
0.3 m/s), and whether a leg of another true group is within d_P of one of its legs while
moving differently (*passing*: velocities at least ``PROXEMIC_SPEED`` apart: crossing
parties, parties leaving each other, someone walking past a standing group) or alike
(*alike*: standing side by side, meeting, walking together; the proxemic truth of
``groups_random.py`` joins these), or neither (*apart*).

    PYTHONPATH=src python benchmarks/groups_misses.py [--seeds 0-9] [--seconds 40]
        [--set NAME=VALUE ...]
"""

from __future__ import annotations

import argparse
from collections import Counter

import numpy as np
from scipy.optimize import linear_sum_assignment

from groups_random import parse_seeds, seen_members  # type: ignore[import-not-found]
from groups_table import _with  # type: ignore[import-not-found]
from laserpeople.clustering import single_linkage
from laserpeople.config import load_config
from laserpeople.evaluation.groups import (
    GROUP_GATE,
    LabelledFrame,
    frames_from_scans,
    group_truth,
    near_and_alike,
)
from laserpeople.pipeline.background import at_torso_height
from laserpeople.sim.scenarios import build_scene, run_scenario
from laserpeople.tracking.groups import GroupMHTTracker, GroupTrackerParams
from laserpeople.tracking.groups.occlusion import FrameShadows
from laserpeople.truth import TruthFrame

WALKING = 0.3
"""Mean speed of a group's members above which it walks [m/s]."""
RANGES = (3.0, 6.0)
"""Range bins of the size table [m]: below 3, 3 to 6, 6 and more."""


def context(frame: TruthFrame, people: np.ndarray, d_p: float) -> str:
    """``walk``/``stand`` and ``passing``/``alike``/``apart`` of the true group ``people``."""
    mine = np.isin(frame.person_ids, people)
    speed = float(np.hypot(*frame.velocities[mine].mean(axis=0)))
    motion = "walk" if speed > WALKING else "stand"
    if mine.all():
        return f"{motion}, apart"
    near, alike = near_and_alike(frame, np.flatnonzero(mine), np.flatnonzero(~mine), d_p)
    if np.any(near & alike):
        return f"{motion}, alike"
    return f"{motion}, passing" if near.any() else f"{motion}, apart"


def size_key(n_true: int, distance: float) -> tuple[str, str]:
    """Row of the size table: the true size (``5+`` for five or more) and the range bin."""
    size = str(n_true) if n_true < 5 else "5+"
    if distance < RANGES[0]:
        return size, f"< {RANGES[0]:g} m"
    if distance < RANGES[1]:
        return size, f"{RANGES[0]:g}-{RANGES[1]:g} m"
    return size, f">= {RANGES[1]:g} m"


def unseen_where(lf: LabelledFrame, people_xy: np.ndarray) -> str:
    """Why the scan of ``lf`` shows none of the people at ``people_xy`` (P, 2) [m]:
    ``outside the field of view`` (every one of them), ``beyond range_max`` (every one
    outside the field of view or beyond the range), else ``in view (hidden)``."""
    shadows = FrameShadows.from_frame(lf.frame)
    if shadows is None:
        return "in view (hidden)"
    outside = np.ones(len(people_xy), dtype=bool)
    away = np.ones(len(people_xy), dtype=bool)
    for view, scan in zip(shadows.views, lf.frame.scans, strict=True):
        covered, _ = view.hidden(people_xy, 0.0)
        far = np.hypot(*(people_xy - view.origin).T) > scan.range_max
        outside &= ~covered
        away &= ~covered | far
    if outside.all():
        return "outside the field of view"
    return "beyond range_max" if away.all() else "in view (hidden)"


def walked(since: dict[int, float], people: np.ndarray, stamp: float) -> str:
    """How long the least-walked of ``people`` has walked: ``standing``, ``< 1 s`` or
    ``>= 1 s`` (``since``: person id -> stamp [s] their walk began; absent: standing), or
    ``no person`` when ``people`` is empty."""
    if people.size == 0:
        return "no person"
    if any(int(p) not in since for p in people):
        return "standing"
    return "< 1 s" if min(stamp - since[int(p)] for p in people) < 1.0 else ">= 1 s"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seeds", default="0-9", help="tune on 0-9; 100-119 are held back")
    ap.add_argument("--seconds", type=float, default=40.0)
    ap.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE")
    args = ap.parse_args()
    params = _with(load_config(GroupTrackerParams, None, None), args.set)
    misses: Counter[tuple[str, str]] = Counter()
    false: Counter[str] = Counter()
    sizes: Counter[tuple[str, str]] = Counter()
    wrong: Counter[tuple[str, str, str]] = Counter()  # size, range, "too few"/"too many"
    holders: Counter[tuple[str, bool]] = Counter()  # event that made it, reported < 1 s
    passing: Counter[tuple[bool, str, str]] = Counter()  # one cluster, walked, other walked
    unseen: Counter[tuple[str, bool]] = Counter()  # where, a report within the gate
    n_truth = 0
    for seed in parse_seeds(args.seeds):
        sim = run_scenario("random-groups", seconds=args.seconds, seed=seed)
        truth_of = {f.scan_index: f for f in sim.truth}
        tracker = GroupMHTTracker(params)
        height = build_scene("random-groups", seconds=args.seconds, seed=seed).notes["scanner"]
        tracker.use_torso_height(at_torso_height(float(height["height_m"])))
        first_reported: dict[int, float] = {}  # group id -> stamp [s]
        since: dict[int, float] = {}  # person id -> stamp [s] their walk began
        for lf in frames_from_scans(sim.scans):
            reported = tracker.update(lf.frame)
            for g in tracker.last_groups:
                first_reported.setdefault(g.family, lf.frame.stamp)
            frame = truth_of.get(lf.frame.index)
            if frame is None:
                continue
            speeds = np.hypot(*frame.velocities.T)
            for pid, v in zip(frame.person_ids.tolist(), speeds.tolist(), strict=True):
                if v <= WALKING:
                    since.pop(pid, None)
                else:
                    since.setdefault(pid, lf.frame.stamp)
            true = group_truth(frame)
            groups = list(frame.groups().values())
            n_truth += len(groups)
            tracks = np.array([t.position for t in reported.tracks]).reshape(-1, 2)
            hit_g: set[int] = set()
            hit_t: set[int] = set()
            if len(groups) and len(tracks):
                d = np.linalg.norm(true.positions[:, None] - tracks[None], axis=2)
                cost = np.where(d <= GROUP_GATE, d, 1e6)
                rows, cols = linear_sum_assignment(cost)
                ok = cost[rows, cols] < 1e6
                hit_g, hit_t = set(rows[ok].tolist()), set(cols[ok].tolist())
            fg = np.asarray(lf.frame.foreground)
            assert lf.frame.points is not None
            fg_idx = np.flatnonzero(fg)
            cluster = np.full(fg.size, -1, dtype=np.int64)
            cluster[fg_idx] = single_linkage(
                lf.frame.points.points[fg_idx], params.cluster_distance
            )
            pose = lf.frame.sensor_pose
            origin = np.array([pose.x, pose.y]) if pose is not None else np.zeros(2)
            for g in tracker.last_groups:
                seen, n_true = seen_members(g.members, lf)
                if seen.size == 0:
                    continue
                centre = lf.frame.points.points[seen].mean(axis=0)
                key = size_key(n_true, float(np.hypot(*(centre - origin))))
                sizes[key] += 1
                n_est = round(g.size)
                if n_est != n_true:
                    wrong[(*key, "too few" if n_est < n_true else "too many")] += 1
            est = tracker.point_labels(len(lf.frame.points))
            for k, people in enumerate(groups):
                if k in hit_g:
                    continue
                mine = np.isin(lf.true_person, people) & fg
                labels = np.unique(est[mine])
                labels = labels[labels >= 0]
                if not mine.any():
                    cause = "unseen"
                    xy = frame.positions[np.isin(frame.person_ids, people)]
                    near = bool(len(tracks)) and bool(
                        np.hypot(*(tracks - xy.mean(axis=0)).T).min() <= GROUP_GATE
                    )
                    unseen[(unseen_where(lf, xy), near)] += 1
                elif labels.size == 0:
                    cause = "unreported"
                elif labels.size > 1:
                    cause = "over-split"
                elif np.any((est == labels[0]) & fg & ~mine):
                    cause = "merged"
                    holder = int(labels[0])
                    young = lf.frame.stamp - first_reported[holder] < 1.0
                    event = next(g.event for g in tracker.last_groups if g.family == holder)
                    holders[(event or "neither", young)] += 1
                else:
                    cause = "offset"
                ctx = context(frame, people, params.cluster_distance)
                if cause == "merged" and ctx == "walk, passing":
                    other = (est == labels[0]) & fg & ~mine
                    one = np.intersect1d(cluster[mine], cluster[other]).size > 0
                    who = np.unique(lf.true_person[other])
                    passing[
                        (
                            one,
                            walked(since, np.asarray(people), lf.frame.stamp),
                            walked(since, who[who >= 0], lf.frame.stamp),
                        )
                    ] += 1
                misses[(cause, ctx)] += 1
            # the first reports are ``last_groups`` in order; coasted vanished ones follow
            shown = tracker.last_groups
            for k in range(len(reported.tracks)):
                if k in hit_t:
                    continue
                g = shown[k] if k < len(shown) else None
                if g is None or g.members.size == 0:
                    false["coasting (no points this scan)"] += 1
                    continue
                who = lf.true_person[g.members]
                kinds = np.unique(lf.true_group[g.members][who >= 0])
                what = ("no person", "part of one true group", "two or more true groups")
                false[what[min(kinds.size, 2)]] += 1
        print(f"seed {seed} done", flush=True)
    print(f"\n{sum(misses.values())} misses of {n_truth} true group-frames (seeds {args.seeds})\n")
    print("| tracker did | group was | share of true group-frames |")
    print("|---|---|---|")
    for (cause, ctx), n in misses.most_common():
        if n / n_truth >= 0.005:
            print(f"| {cause} | {ctx} | {100 * n / n_truth:.1f} % |")
    by_cause: Counter[str] = Counter()
    by_ctx: Counter[str] = Counter()
    for (cause, ctx), n in misses.items():
        by_cause[cause] += n
        by_ctx[ctx.split(", ")[1]] += n
    print("\nby cause: " + ", ".join(f"{c} {100 * n / n_truth:.1f} %" for c, n in by_cause.items()))
    print("by context: " + ", ".join(f"{c} {100 * n / n_truth:.1f} %" for c, n in by_ctx.items()))
    print(
        "unseen by where its people are: "
        + ", ".join(
            f"{where}{', a report within the gate' if near else ''} {100 * n / n_truth:.1f} %"
            for (where, near), n in unseen.most_common()
        )
    )
    print("false positives: " + ", ".join(f"{c} {n}" for c, n in false.most_common()))
    print(
        "merged misses by the group holding them: "
        + ", ".join(
            f"{event} {100 * (holders[(event, True)] + holders[(event, False)]) / n_truth:.1f} %"
            f" ({100 * holders[(event, True)] / n_truth:.1f} % reported < 1 s)"
            for event in ("merge", "split", "neither")
        )
    )
    n_passing = max(sum(passing.values()), 1)
    print(
        f"\nmerged while walking past a group that moves differently: {sum(passing.values())} "
        "group-frames; in one cluster at d_P with the other group's points "
        f"{100 * sum(n for k, n in passing.items() if k[0]) / n_passing:.0f} %"
    )
    print("| the group had walked | the other group's people had walked | share |")
    print("|---|---|---|")
    by_walk: Counter[tuple[str, str]] = Counter()
    for (_, mine_walked, other_walked), n in passing.items():
        by_walk[(mine_walked, other_walked)] += n
    for (mine_walked, other_walked), n in by_walk.most_common():
        print(f"| {mine_walked} | {other_walked} | {100 * n / n_passing:.0f} % |")
    n_sizes = max(sum(sizes.values()), 1)
    print(
        f"\nwrong sizes: {sum(wrong.values())} of {n_sizes} reported group-frames with points "
        f"({100 * sum(wrong.values()) / n_sizes:.1f} %)\n"
    )
    print("| true size | range | group-frames | wrong (of all) | too few | too many | of row |")
    print("|---|---|---|---|---|---|---|")
    for key in sorted(sizes):
        few, many = wrong[(*key, "too few")], wrong[(*key, "too many")]
        print(
            f"| {key[0]} | {key[1]} | {sizes[key]} | {100 * (few + many) / n_sizes:.1f} % | "
            f"{100 * few / n_sizes:.1f} % | {100 * many / n_sizes:.1f} % | "
            f"{100 * (few + many) / sizes[key]:.0f} % |"
        )


if __name__ == "__main__":
    main()
