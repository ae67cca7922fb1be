"""CPU of the group tracker's settings side by side (docs/groups.md "Walkers", "Third
round"): 000's setting, the walkers of session 13 and the walkers taking the points
(``GroupTrackerParams.split_walkers()``) track the same simulated entrance-hall frames in
one process, taking turns run by run, ``--repeats`` times; per scan the least CPU time of
the repeats, then the median by people in view. One process and turns keep the ratios
fair on a shared machine.

    PYTHONPATH=src python benchmarks/bench_groups_presets.py [--seeds 3 4] [--seconds 60]
        [--repeats 3]
"""

from __future__ import annotations

import argparse

import numpy as np

from bench_groups import hall_runs, time_frames
from laserpeople.tracking.groups import GroupTrackerParams

BINS = ((0, 4), (5, 9), (10, 14), (15, 20))
"""People in view per bin (both ends included)."""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[3, 4])
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    settings = {
        "000's setting": GroupTrackerParams.paper_likelihood(),
        "walkers": GroupTrackerParams(walkers=True),
        "walkers taking the points": GroupTrackerParams.split_walkers(),
    }
    runs = hall_runs("entrance-hall", args.seeds, args.seconds)
    people = np.concatenate([p for _, p in runs])
    ms: dict[str, list[np.ndarray]] = {name: [] for name in settings}
    for _ in range(args.repeats):
        for name, params in settings.items():
            ms[name].append(np.concatenate([time_frames(frames, params) for frames, _ in runs]))
    least = {name: np.min(np.stack(v), axis=0) for name, v in ms.items()}
    names = list(settings)
    print("| people in view | " + " | ".join(names) + " | taking the points / walkers | scans |")
    print("|---|" + "---|" * (len(names) + 2))
    for lo, hi in BINS:
        sel = (people >= lo) & (people <= hi)
        if not sel.any():
            continue
        med = {name: float(np.median(v[sel])) for name, v in least.items()}
        ratio = med["walkers taking the points"] / med["walkers"]
        cells = " | ".join(f"{med[n]:.2f}" for n in names)
        print(f"| {lo}-{hi} | {cells} | {ratio:.2f} | {int(sel.sum())} |")


if __name__ == "__main__":
    main()
