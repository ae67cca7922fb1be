"""People on real unlabelled recordings: how many person ids, and how long people are
reported on things that never move.

For each recording (one topic, the shipped AdaBoost detector, the leg MHT in the world frame
when the bag has poses): person ids; *walker ids*, those whose track spans at least
``--walk`` metres (the extent of its positions); person-track-seconds; and
*static seconds*, the person-track-seconds of ids whose positions stay within
``--walk`` metres for their whole life (a person track that never moves sits on furniture,
a wall or a standing person; on these recordings people walk through).

    PYTHONPATH=src .venv/bin/python benchmarks/real_people.py [--policies arras tracks
        tracks-noreid]
        [--static-model] [--bags demo mir]
"""

from __future__ import annotations

import argparse
import os
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from laserpeople.detection.detector import AdaBoostLegDetector
from laserpeople.io import open_recording
from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams
from laserpeople.tracks import Tracks

ROOT = Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "../shared/data"))
BAGS = {
    "demo": (
        ROOT / "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag",
        "/scan",
    ),
    "mir": (
        ROOT / "mir/rosbags/mir_data/legs-test-split-2022-11-21-15-51-02-topic-split.bag",
        None,
    ),
}


@dataclass(frozen=True)
class RealCount:
    """Counts of one recording and policy."""

    ids: int
    walker_ids: int
    person_seconds: float
    static_seconds: float
    ms: float


def count(tracks: list[Tracks], walk: float) -> RealCount:
    """Person ids, walkers, person-track-seconds and static seconds (see module doc)."""
    positions: dict[int, list[np.ndarray]] = {}
    seconds: dict[int, float] = {}
    for k in range(1, len(tracks)):
        dt = tracks[k].stamp - tracks[k - 1].stamp
        for t in tracks[k].of_kind("person"):
            positions.setdefault(t.track_id, []).append(t.position)
            seconds[t.track_id] = seconds.get(t.track_id, 0.0) + dt
    walkers = 0
    static = 0.0
    for pid, pts in positions.items():
        arr = np.stack(pts)
        extent = float(np.max(np.linalg.norm(arr - arr.mean(axis=0), axis=1))) * 2.0
        if extent >= walk:
            walkers += 1
        else:
            static += seconds[pid]
    return RealCount(len(positions), walkers, sum(seconds.values()), static, 0.0)


def run(bag: Path, topic: str | None, policy: str, static_model: bool, walk: float) -> RealCount:
    """Track one recording with ``policy`` and count."""
    rec = open_recording(bag)
    name = topic or rec.topics()[0].name
    params = replace(LegTrackerParams(), people_policy=policy.removesuffix("-noreid"))
    if policy.endswith("-noreid"):  # the tracks policy without re-identification
        people = params.people
        params = replace(params, people=replace(people, reid=replace(people.reid, enabled=False)))
    model = None
    if static_model:
        from laserpeople.background.occupancy import OccupancyGrid, frame_from_scan

        model = OccupancyGrid()
    tracker = LegMHTTracker(params, static_model=model)
    detector = AdaBoostLegDetector.default()
    out: list[Tracks] = []
    spent = 0.0
    try:
        for scan in rec.scans([name]):
            dets = detector.detect(scan)
            t0 = time.perf_counter()
            if model is not None:
                model(frame_from_scan(scan, "world" if scan.pose is not None else "sensor"))
            out.append(tracker.update(dets))
            spent += time.perf_counter() - t0
    finally:
        rec.close()
    c = count(out, walk)
    return replace(c, ms=1e3 * spent / max(len(out), 1))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bags", nargs="+", default=list(BAGS))
    ap.add_argument("--policies", nargs="+", default=["arras", "tracks"])
    ap.add_argument("--static-model", action="store_true")
    ap.add_argument("--walk", type=float, default=1.0, help="m")
    args = ap.parse_args()
    print("bag   policy  static  ids  walkers  person-s  static-s  ms/scan")
    for key in args.bags:
        bag, topic = BAGS[key]
        for policy in args.policies:
            c = run(bag, topic, policy, args.static_model, args.walk)
            print(
                f"{key:5s} {policy:7s} {args.static_model!s:6s} {c.ids:4d} {c.walker_ids:8d} "
                f"{c.person_seconds:9.1f} {c.static_seconds:9.1f} {c.ms:8.2f}",
                flush=True,
            )


if __name__ == "__main__":
    main()
