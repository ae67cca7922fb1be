"""The occupancy grid's ``free_period`` option on real recordings: what casting free space
less often changes in the people tracks, and what it saves.

For each recording (as ``real_people.py`` runs it: the pipeline, the shipped AdaBoost
detector, the leg MHT's default people with the static world model ``auto``) and each
``--periods`` value (0 = the default, casting in every frame): person ids, walker ids,
person-track-seconds, static seconds, gaps (``real_people.count``), the process CPU per
frame of the whole pipeline, and the frames whose tracks differ from those of period 0
(ids, kinds, members and positions bit for bit).

    PYTHONPATH=src .venv/bin/python benchmarks/free_period.py [--periods 0 0.5 1 2]
        [--bags demo mir corridor]
"""

from __future__ import annotations

import argparse
import sys
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bags", nargs="+", default=["demo", "mir", "corridor"], choices=list(BAGS))
    ap.add_argument("--periods", nargs="+", type=float, default=[0.0, 0.5, 1.0, 2.0])
    ap.add_argument("--walk", type=float, default=1.0, help="m")
    args = ap.parse_args()
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
