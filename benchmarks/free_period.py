"""The occupancy grid's ``free_period`` option on real recordings: what casting free space
less often changes in the people tracks, and what it saves.

For each recording (as ``real_people.py`` runs it: the pipeline, the shipped AdaBoost
detector, the leg MHT's default people with the static world model ``auto``) and each
``--periods`` value (0 = the default, casting in every frame): person ids, walker ids,
person-track-seconds, static seconds, gaps (``real_people.count``), the process CPU per
frame of the whole pipeline, and the frames whose tracks differ from those of period 0
(ids, kinds, members and positions bit for bit).

With ``--scenes`` it runs instead the default tracker as ``cost_vs_gnn.py`` runs it on
suite scenes, once with period 0 and once with each other period, the two updated
alternately scan by scan in one process (the machine is shared): the median and mean
process CPU per scan of each, their ratio, and the scans whose tracks differ.

    PYTHONPATH=src .venv/bin/python benchmarks/free_period.py [--periods 0 0.5 1 2]
        [--bags demo mir corridor] [--scenes randomised:0 randomised:2 ...]
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from laserpeople.background.occupancy import OccupancyParams
from laserpeople.detection.detector import AdaBoostLegDetector
from laserpeople.pipeline import build
from laserpeople.pipeline.background import StaticWorldParams
from laserpeople.tracking import registry
from laserpeople.tracks import Tracks
from real_people import BAGS, count, track_all


def run(key: str, period: float) -> tuple[list[Tracks], float]:
    """Every frame's tracks of one recording with ``free_period`` = ``period``, and the CPU
    [ms] per frame."""
    bag, topics, mounts = BAGS[key]
    static = StaticWorldParams(occupancy=OccupancyParams(free_period=period))
    pipe = build(
        bag,
        tracker=registry.get("leg-mht").make(None),
        topics=topics,
        mounts=mounts,
        detector=AdaBoostLegDetector.default(),
        background="auto",
        static_world=static,
    )
    return track_all(pipe)


def same(a: Tracks, b: Tracks) -> bool:
    """The same tracks (ids, kinds, members, positions bit for bit)."""
    if len(a.tracks) != len(b.tracks):
        return False
    return all(
        s.track_id == t.track_id
        and s.kind == t.kind
        and s.members == t.members
        and np.array_equal(s.position, t.position)
        for s, t in zip(a.tracks, b.tracks, strict=True)
    )


def scene_tracker(period: float) -> object:
    """The default frame tracker with its static world model ``auto`` (as
    ``people_suite.make_factory`` makes it), the grid's ``free_period`` = ``period``."""
    from laserpeople.pipeline.static_people import StaticFed, people_static_model

    tracker = registry.get("leg-mht").make(None)
    static = StaticWorldParams(occupancy=OccupancyParams(free_period=period))
    model = people_static_model("auto", static=static)
    assert model is not None
    return StaticFed(tracker, model)


def main_scenes(scenes: list[str], periods: list[float]) -> None:
    """The ``--scenes`` table (module docstring)."""
    from laserpeople.detection.detector import LegDetectorParams
    from laserpeople.evaluation.suite import SuiteScene, frames_for, prepare

    detector = AdaBoostLegDetector.default(LegDetectorParams())
    print("scene               period  ms/scan median (period 0)  ratio  mean ratio  differ")
    for text in scenes:
        scenario, seed = text.split(":")
        scene = (  # (as cost_vs_gnn.py: 30 s of the randomised family, named scenes whole)
            SuiteScene(scenario, scenario, int(seed), 30.0)
            if scenario == "randomised"
            else SuiteScene(scenario, scenario, int(seed))
        )
        prepared = prepare(scene, detector)
        for period in [q for q in periods if q > 0]:
            pair = [scene_tracker(0.0), scene_tracker(period)]
            frames = frames_for(prepared, frozenset(pair[0].consumes))  # type: ignore[attr-defined]
            cpu: list[list[float]] = [[], []]
            differ = 0
            for k, frame in enumerate(frames):
                out = []
                for i in (0, 1) if k % 2 == 0 else (1, 0):
                    t0 = time.process_time()
                    out.append((i, pair[i].update(frame)))  # type: ignore[attr-defined]
                    cpu[i].append(time.process_time() - t0)
                a, b = (t for _, t in sorted(out, key=lambda x: x[0]))
                differ += not same(a, b)
            med = [1e3 * float(np.median(c)) for c in cpu]
            mean = [1e3 * float(np.mean(c)) for c in cpu]
            print(
                f"{text:18s} {period:6.2f}  {med[1]:6.3f} ({med[0]:6.3f})         "
                f"{med[1] / med[0]:5.3f}  {mean[1] / mean[0]:10.3f}  {differ:5d}/{len(frames)}",
                flush=True,
            )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bags", nargs="+", default=["demo", "mir", "corridor"], choices=list(BAGS))
    ap.add_argument("--periods", nargs="+", type=float, default=[0.0, 0.5, 1.0, 2.0])
    ap.add_argument("--walk", type=float, default=1.0, help="m")
    ap.add_argument("--scenes", nargs="+", default=None, help="suite scenes SCENARIO:SEED")
    args = ap.parse_args()
    if args.scenes:
        main_scenes(args.scenes, args.periods)
        return
    print("bag      period  ids  walkers  person-s  walker-s  static-s  gaps  ms/frame  differ")
    for key in args.bags:
        base: list[Tracks] | None = None
        for period in args.periods:
            out, ms = run(key, period)
            if base is None:
                base = out
            differ = sum(not same(a, b) for a, b in zip(base, out, strict=True))
            c = replace(count(out, args.walk), ms=ms)
            print(
                f"{key:8s} {period:6.2f} {c.ids:4d} {c.walker_ids:8d} {c.person_seconds:9.1f} "
                f"{c.walker_seconds:9.1f} {c.static_seconds:9.1f} {c.gaps:5d} {c.ms:9.2f} "
                f"{differ:5d}/{len(out)}",
                flush=True,
            )


if __name__ == "__main__":
    main()
