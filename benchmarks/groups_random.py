"""The group tracker (000 Sec. 4) on the randomised group scenes (``random-groups``): group
MOTA (CLEAR MOT of the reported groups against the true groups, people alone are groups
of one, gate 1 m; a person is in the truth when the scanner saw them within 2 s),
group-size error (000 Sec. 4.6.3: mean error, exact share) and the clustering error, per
seed and pooled. The proxemic MOTA scores the same tracks against the true groups as 000's
definition sees them (groups within d_P that move alike joined,
:func:`laserpeople.evaluation.groups.proxemic_truth`).

Frames come straight from the simulator (foreground = the beams on people), as
``benchmarks/groups_table.py``. **Seeds 100-119 are held back: never tune on them**; tune
on 0-9.

    PYTHONPATH=src python benchmarks/groups_random.py [--seeds 100-119] [--seconds 40]
        [--preset paper] [--set NAME=VALUE ...] [--jobs 2]
"""

from __future__ import annotations

import argparse
import math
from concurrent.futures import ProcessPoolExecutor

import numpy as np
from numpy.typing import NDArray

from groups_table import _with  # type: ignore[import-not-found]
from laserpeople.config import load_config
from laserpeople.evaluation.clear_mot import ClearMotResult
from laserpeople.evaluation.groups import GroupRunResult, LabelledFrame, run_groups
from laserpeople.sim.scenarios import build_scene, run_scenario
from laserpeople.tracking.groups import GroupTrackerParams


def parse_seeds(text: str) -> list[int]:
    """``"100-119"`` or ``"1,2,5"`` -> the seeds."""
    out: list[int] = []
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        out += list(range(int(lo), int(hi) + 1)) if hi else [int(lo)]
    return out


def seen_members(members: NDArray[np.int64], lf: LabelledFrame) -> tuple[NDArray[np.int64], int]:
    """Of a reported group's point indices ``members``, those the frame's foreground holds,
    and how many true people they belong to."""
    seen = members[np.asarray(lf.frame.foreground)[members]]
    who = lf.true_person[seen]
    return seen, int(np.unique(who[who >= 0]).size)


def _mota(mots: list[ClearMotResult]) -> float:
    """MOTA pooled over runs (by group-frames)."""
    truth = sum(m.num_truth for m in mots)
    wrong = sum(m.misses + m.false_positives + m.id_switches for m in mots)
    return 1.0 - wrong / truth if truth else math.nan


def pooled(runs: list[GroupRunResult]) -> dict[str, float]:
    """Group MOTA (against the scene's groups and against the proxemic truth), size mean
    error and exact share pooled over runs (by group-frames)."""
    count = sum(r.size.count for r in runs)

    def wmean(values: list[float]) -> float:
        pairs = [(v, r.size.count) for v, r in zip(values, runs, strict=True) if r.size.count]
        return sum(v * c for v, c in pairs) / count if count else math.nan

    return {
        "mota": _mota([r.group_mot for r in runs]),
        "proxemic": _mota([r.proxemic_mot for r in runs]),
        "size_error": wmean([r.size.mean_error for r in runs]),
        "exact": wmean([r.size.exact_share for r in runs]),
    }


def _run_seed(seed: int, seconds: float, params: GroupTrackerParams) -> tuple[dict, GroupRunResult]:
    """One scene: its notes and the tracker's scores."""
    notes = build_scene("random-groups", seconds=seconds, seed=seed).notes
    sim = run_scenario("random-groups", seconds=seconds, seed=seed)
    height = float(notes["scanner"]["height_m"])
    return notes, run_groups(sim.scans, params, truth=sim.truth, laser_height=height)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seeds", default="100-119", help="held back: 100-119; tune on 0-9")
    ap.add_argument("--seconds", type=float, default=40.0)
    ap.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE")
    ap.add_argument("--jobs", type=int, default=1, help="scenes run in parallel")
    ap.add_argument("--preset", default=None, help="paper: 000's group tracker (docs/papers.md)")
    args = ap.parse_args()
    params = _with(load_config(GroupTrackerParams, None, args.preset), args.set)
    print(f"preset {args.preset}; parameters changed: {args.set or 'none'}")
    runs: list[GroupRunResult] = []
    by_level: dict[str, list[GroupRunResult]] = {"feet": [], "torso": []}
    seeds = parse_seeds(args.seeds)
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        jobs = [pool.submit(_run_seed, seed, args.seconds, params) for seed in seeds]
        for seed, job in zip(seeds, jobs, strict=True):
            notes, r = job.result()
            runs.append(r)
            by_level[notes["scanner"]["level"]].append(r)
            m, x = r.group_mot, r.proxemic_mot
            print(
                f"seed {seed} ({notes['scanner']['level']}, "
                f"{notes['scanner']['resolution_deg']:.2f} deg, "
                f"{'moving' if notes['moving_robot'] else 'still'}, {notes['people']} people): "
                f"group MOTA {m.mota:.3f} (miss {m.misses}, fp {m.false_positives}, ids "
                f"{m.id_switches} of {m.num_truth}), proxemic {x.mota:.3f} (miss {x.misses}, fp "
                f"{x.false_positives}, ids {x.id_switches} of {x.num_truth}); "
                f"size error {r.size.mean_error:.2f}, exact "
                f"{100 * r.size.exact_share:.1f} %; clustering error {r.clustering.error:.3f}",
                flush=True,
            )
    print(f"\nrandom-groups, seeds {args.seeds}, {args.seconds:g} s each (pooled)\n")
    print("| scenes | group MOTA | proxemic MOTA | size exact | size mean error [people] |")
    print("|---|---|---|---|---|")
    for name, group in (("all", runs), *by_level.items()):
        if group:
            p = pooled(group)
            print(
                f"| {name} ({len(group)}) | {p['mota']:.3f} | {p['proxemic']:.3f} | "
                f"{100 * p['exact']:.1f} % | "
                f"{p['size_error']:.2f} |"
            )


if __name__ == "__main__":
    main()
