"""Where the default tracker's CPU goes per scan outside the leg MHT's step.

Runs the default tracker as ``people_suite.py`` and ``cost_vs_gnn.py`` run it (leg MHT,
people ``tracks``, the static world model ``auto`` fed from each frame) on each scene with
the parts around the MHT step wrapped in timers, and prints per scan: the process CPU of
the whole update, then the time inside each part (a part nested in another one is listed
below it, indented; its time is part of its parent's). The timers add about a microsecond
per call of their own; compare parts within a run.

    PYTHONPATH=src .venv/bin/python benchmarks/bench_around_mht.py
        [--scenes randomised:0 randomised:2 crossing-3:1] [--seconds 30] [--repeat 3]
"""

from __future__ import annotations

import argparse
import sys
import time
from collections import defaultdict
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

import laserpeople.background.occupancy as occupancy
import laserpeople.background.still_cast as still_cast
import laserpeople.pipeline.preprocess as preprocess
import laserpeople.pipeline.static_people as static_people
import laserpeople.tracking.legs as legs
import laserpeople.tracking.mht.core as core
import laserpeople.tracking.person_tracks as person_tracks
import laserpeople.tracking.point_model as point_model
from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.evaluation.suite import SuiteScene, frames_for, prepare
from people_suite import make_factory

PARTS: list[tuple[Any, str, str]] = [
    (preprocess.Fuse, "__call__", "points of the frame (Fuse)"),
    (static_people.PeopleStaticModel, "__call__", "static world model: learning"),
    (occupancy.OccupancyGrid, "_cast_still", "  free-space casting (still laser)"),
    (still_cast.StillCast, "cast", "    StillCast.cast"),
    (static_people.PeopleStaticModel, "static_time", "static world model: static_time"),
    (legs.LegMHTTracker, "_measurements", "leg measurements (incl. on_furniture)"),
    (person_tracks.PersonTracker, "on_furniture", "  on_furniture"),
    (core.MHT, "step", "MHT step"),
    (point_model.KalmanPointModel, "predict", "  point model predict"),
    (point_model.KalmanPointModel, "score", "  point model score"),
    (point_model.KalmanPointModel, "update", "  point model update"),
    (legs.LegMHTTracker, "_people_as_tracks", "people as tracks"),
    (legs, "leg_observations", "  leg observations"),
    (person_tracks.PersonTracker, "update", "  PersonTracker.update"),
]
"""(owner, attribute, label) of the parts timed."""


def timed(seconds: dict[str, float], label: str, fn: Callable[..., Any]) -> Callable[..., Any]:
    """``fn`` adding its process CPU time to ``seconds[label]``."""

    def wrapper(*args: Any, **kwargs: Any) -> Any:
        t0 = time.process_time()
        try:
            return fn(*args, **kwargs)
        finally:
            seconds[label] += time.process_time() - t0

    return wrapper


def run(prepared: Any) -> tuple[int, float, dict[str, float]]:
    """Scans, process CPU ms per scan of the whole update and ms per scan in each part."""
    tracker = make_factory("leg-mht", None, "auto")()
    frames = frames_for(prepared, frozenset(tracker.consumes))
    spent: dict[str, float] = defaultdict(float)
    saved = [(owner, name, owner.__dict__[name]) for owner, name, _ in PARTS]
    try:
        for owner, name, label in PARTS:
            setattr(owner, name, timed(spent, label, getattr(owner, name)))
        t0 = time.process_time()
        for frame in frames:
            tracker.update(frame)
        cpu = time.process_time() - t0
    finally:
        for owner, name, fn in saved:
            setattr(owner, name, fn)
    n = max(len(frames), 1)
    return len(frames), 1e3 * cpu / n, {k: 1e3 * v / n for k, v in spent.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument(
        "--scenes",
        nargs="+",
        default=["randomised:0", "randomised:2", "crossing-3:1"],
        help="SCENARIO:SEED",
    )
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--repeat", type=int, default=3, help="runs per scene (the fastest kept)")
    args = ap.parse_args()
    detector = AdaBoostLegDetector.default(LegDetectorParams())
    for text in args.scenes:
        scenario, seed = text.split(":")
        seconds = args.seconds if scenario == "randomised" else None
        scene = (
            SuiteScene(scenario, scenario, int(seed), seconds)
            if seconds is not None
            else SuiteScene(scenario, scenario, int(seed))
        )
        prepared = prepare(scene, detector)
        runs = [run(prepared) for _ in range(args.repeat)]
        scans, cpu, parts = min(runs, key=lambda r: r[1])
        print(f"{text}: {scans} scans, {cpu:.3f} ms CPU per scan (the whole update)")
        for _, _, label in PARTS:
            print(f"  {label:<44s} {parts.get(label, 0.0):7.3f} ms per scan")
        outside = cpu - parts.get("MHT step", 0.0)
        print(f"  {'all but the MHT step':<44s} {outside:7.3f} ms per scan", flush=True)


if __name__ == "__main__":
    main()
