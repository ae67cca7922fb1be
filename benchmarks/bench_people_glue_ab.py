"""CPU of the leg tracker outside its MHT step (the people layer and the glue: the input
guard, the measurements, the leg observations, the person tracks, the tracks out) against
another version's, both in one process on the loop ``track`` runs.

Both trees run the pipeline of ``bench_scaling.py`` (leg detection, the default leg MHT,
the static world model ``auto``) over the same recordings, stepped alternately scan by scan
(who goes first: :func:`bench_scaling.goes_first`), with process-CPU timers
(``bench_track_parts.timed``) around ``LegMHTTracker.update`` and ``MHT.step`` of each
tree: the part is the first minus the second. Printed per recording and pass: each tree's
part in ms per scan and their ratio (other / this, above 1: this is faster), and the
median of the passes' ratios. The timers add about a microsecond per call of their own to
both trees.

    PYTHONPATH=src .venv/bin/python benchmarks/bench_people_glue_ab.py --before OTHER/src
        [--people 4 20] [--passes 3] [--no-demo] [--cache DIR]
"""

from __future__ import annotations

import argparse
import importlib
import itertools
import statistics
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_scaling import DEMO_BAG, add_scene_arguments, goes_first, hall_paths, pipeline
from bench_track_ab import load_other
from bench_track_parts import timed


def wrap(package: str, spent: dict[str, float]) -> list[tuple[Any, str, Any]]:
    """Put timers round the leg tracker's update and the MHT step of ``package``; returns
    what to put back."""
    legs = importlib.import_module(f"{package}.tracking.legs")
    core = importlib.import_module(f"{package}.tracking.mht.core")
    saved = []
    for owner, name in ((legs.LegMHTTracker, "update"), (core.MHT, "step")):
        saved.append((owner, name, owner.__dict__[name]))
        setattr(owner, name, timed(spent, name, getattr(owner, name), time.process_time))
    return saved


def one_pass(packages: list[str], path: Path, background: str) -> dict[str, float]:
    """ms per scan of the part of each package over one pass of ``path``."""
    spent: dict[str, dict[str, float]] = {p: defaultdict(float) for p in packages}
    saved = [s for p in packages for s in wrap(p, spent[p])]
    steps = {p: pipeline(p, path, background) for p in packages}
    scans = 0
    try:
        for scan in itertools.count():
            order = packages[::-1] if goes_first(scan) else packages
            ended = [next(steps[p], None) is None for p in order]
            if any(ended):
                break
            scans += 1
    finally:
        for owner, name, fn in saved:
            setattr(owner, name, fn)
    n = max(scans, 1)
    return {p: 1e3 * (spent[p]["update"] - spent[p]["step"]) / n for p in packages}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    add_scene_arguments(ap, [4, 20])
    ap.add_argument("--before", type=Path, required=True, help="the other source tree (its src/)")
    ap.add_argument("--passes", type=int, default=3)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        other = load_other(args.before, Path(tmp) / "other").__name__
        packages = ["laserpeople", other]
        paths = hall_paths(args.people, args.seconds, args.cache or Path(tmp))
        scenes = [(f"hall, {n} people", p) for n, p in zip(args.people, paths, strict=True)]
        bag = args.data / DEMO_BAG
        if not args.no_demo and bag.exists():
            scenes.append(("real demo bag", bag))
        for name, path in scenes:
            ratios = []
            for k in range(args.passes):
                ms = one_pass(packages, path, args.background)
                ratios.append(ms[other] / ms["laserpeople"])
                print(
                    f"{name}, pass {k + 1}: leg tracker outside the MHT step, other "
                    f"{ms[other]:.4f} this {ms['laserpeople']:.4f} ms/scan, other/this "
                    f"{ratios[-1]:.3f}",
                    flush=True,
                )
            print(f"{name}: other/this {statistics.median(ratios):.3f} (median of the passes)")


if __name__ == "__main__":
    main()
