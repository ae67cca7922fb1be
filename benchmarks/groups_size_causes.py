"""Why the group tracker's size is wrong on the randomised group scenes: every reported
group-frame with points (as ``groups_random.py`` scores the size: the true size is the
number of people among the group's points this scan) by what went wrong in its count.

The count is made again from the group's points with the tracker's own counting
(:func:`laserpeople.tracking.groups.observations.blob_people`: the people each blob at
d_hs stands for and the pairs of one person's two leg blobs), and each wrong rounded size
is put in the first class that holds:

- *filter*: the count is right, the filtered size (eqs. 28-31) is not;
- *run together*: a blob holds two or more people and counts fewer;
- *legs of two people paired*: two blobs of different people are paired as one person's
  legs;
- *one person's legs unpaired*: a person is in two blobs that are not paired;
- *one person counted as two*: a blob of one person counts two or more;
- *other*.

It also gives the wrong sizes by laser height and true size.

    PYTHONPATH=src python benchmarks/groups_size_causes.py [--seeds 0-19] [--seconds 40]
        [--set NAME=VALUE ...] [--jobs 2]
"""

from __future__ import annotations

import argparse
from collections import Counter
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from groups_random import parse_seeds, seen_members  # type: ignore[import-not-found]
from groups_table import _with  # type: ignore[import-not-found]
from laserpeople.clustering import single_linkage
from laserpeople.config import load_config
from laserpeople.evaluation.groups import frames_from_scans
from laserpeople.pipeline.background import at_torso_height
from laserpeople.sim.scenarios import build_scene, run_scenario
from laserpeople.tracking.groups import GroupMHTTracker, GroupTrackerParams
from laserpeople.tracking.groups.observations import blob_people
from laserpeople.tracking.groups.tracker import beam_spacing

CLASSES = (
    "right",
    "filter",
    "run together",
    "legs of two people paired",
    "one person's legs unpaired",
    "one person counted as two",
    "other",
)


def cause(who: np.ndarray, blob: np.ndarray, people: np.ndarray, pairs: np.ndarray) -> str:
    """The class of a wrong count: ``who`` (N,) the person of each point (-1: none),
    ``blob`` (N,) its blob 0..B-1, ``people`` (B,) and ``pairs`` (K, 2) as
    :func:`blob_people` gives them."""
    persons = [set(who[blob == b][who[blob == b] >= 0].tolist()) for b in range(people.size)]
    if any(len(p) >= 2 and people[b] < len(p) for b, p in enumerate(persons)):
        return "run together"
    if any(persons[a] != persons[b] and persons[a] and persons[b] for a, b in pairs):
        return "legs of two people paired"
    paired = {int(b) for b in pairs.ravel()}
    for person in {p for ps in persons for p in ps}:
        mine = [b for b, p in enumerate(persons) if person in p]
        if len(mine) >= 2 and any(b not in paired for b in mine):
            return "one person's legs unpaired"
    if any(len(p) == 1 and people[b] >= 2 for b, p in enumerate(persons)):
        return "one person counted as two"
    return "other"


def run_seed(seed: int, seconds: float, params: GroupTrackerParams) -> tuple[str, Counter]:
    """One scene: its laser height and the (class, true size) counts of its group-frames."""
    scanner = build_scene("random-groups", seconds=seconds, seed=seed).notes["scanner"]
    level = str(scanner["level"])
    sim = run_scenario("random-groups", seconds=seconds, seed=seed)
    tracker = GroupMHTTracker(params)
    tracker.use_torso_height(at_torso_height(float(scanner["height_m"])))
    counting = tracker.counting
    out: Counter[tuple[str, int]] = Counter()
    for lf in frames_from_scans(sim.scans):
        tracker.update(lf.frame)
        assert lf.frame.points is not None
        for g in tracker.last_groups:
            mine, n_true = seen_members(g.members, lf)
            if mine.size == 0:
                continue
            who = lf.true_person[mine]
            pts = lf.frame.points.points[mine]
            blob = single_linkage(pts, params.blob_distance)
            one = np.zeros(int(blob.max()) + 1, dtype=np.int64)
            spacing = beam_spacing(lf.frame, mine) if params.size_count == "resolved" else None
            people, pairs = blob_people(pts, blob, one, counting, spacing)
            count = float(people.sum()) - len(pairs)
            if round(g.size) == n_true:
                kind = "right"
            elif round(count) == n_true:
                kind = "filter"
            else:
                kind = cause(who, blob, people, pairs)
            out[(kind, min(n_true, 5))] += 1
    return level, out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seeds", default="0-19", help="tune on 0-19; 100-119 are held back")
    ap.add_argument("--seconds", type=float, default=40.0)
    ap.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE")
    ap.add_argument("--jobs", type=int, default=1, help="scenes run in parallel")
    args = ap.parse_args()
    params = _with(load_config(GroupTrackerParams, None, None), args.set)
    if params.size_count == "blobs":
        ap.error("the classes are those of size_count legs or resolved")
    seeds = parse_seeds(args.seeds)
    by_level: dict[str, Counter[tuple[str, int]]] = {"feet": Counter(), "torso": Counter()}
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        for level, counts in pool.map(
            run_seed, seeds, [args.seconds] * len(seeds), [params] * len(seeds)
        ):
            by_level[level].update(counts)
    total = sum(sum(c.values()) for c in by_level.values())
    print(f"parameters changed: {args.set or 'none'}; seeds {args.seconds:g} s each: {args.seeds}")
    print(f"{total} reported group-frames with points\n")
    print("| class | " + " | ".join(f"{level}" for level in by_level) + " | all |")
    print("|---|---|---|---|")
    for kind in CLASSES:
        shares = [sum(n for (k, _), n in c.items() if k == kind) / total for c in by_level.values()]
        print(
            f"| {kind} | "
            + " | ".join(f"{100 * s:.1f} %" for s in shares)
            + f" | {100 * sum(shares):.1f} % |"
        )
    print("\nwrong sizes by true size (share of all group-frames; wrong share of the row)\n")
    print("| laser | true size | group-frames | wrong (of all) | of row |")
    print("|---|---|---|---|---|")
    for level, c in by_level.items():
        for size in range(1, 6):
            row = sum(n for (_, s), n in c.items() if s == size)
            bad = sum(n for (k, s), n in c.items() if s == size and k != "right")
            if row:
                label = str(size) if size < 5 else "5+"
                share, of_row = 100 * bad / total, 100 * bad / row
                print(f"| {level} | {label} | {row} | {share:.1f} % | {of_row:.0f} % |")


if __name__ == "__main__":
    main()
