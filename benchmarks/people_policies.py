"""People policies side by side on simulated scenes: ``arras`` (000 Sec. 3.3) vs ``tracks``
(people as tracks of their own), with the shipped AdaBoost leg detector on the simulated
scans (the first laser of each scene).

Besides the registered scenes, two with furniture only (no people), seen by a static
SICK LMS200-like laser for 30 s: ``furniture-office`` (the office of 000 Sec. 2.3.1 without its
two people) and ``furniture-chairs`` (eight 4-post chairs and two tables placed at random by
the seed in a 7 x 6 m room). There every person track is on a static object.

Per scene and seed: person MOTA, IDF1, ID switches, person ids created, and the
person-track-seconds more than ``--static-gate`` from every true person (on scenes with only
furniture this is the time people are reported on static objects).

    PYTHONPATH=src .venv/bin/python benchmarks/people_policies.py \
        --scenes demo:0-4 crossing-3:0-2 narrow-corridor:0-2 entrance-hall:0-2 [--static-model]
        [--model MODEL.json]
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from laserpeople.config import load_config
from laserpeople.detection.detector import AdaBoostLegDetector
from laserpeople.evaluation import evaluate
from laserpeople.sim import SimResult, run_scenario
from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams
from laserpeople.tracks import Tracks
from laserpeople.truth import TruthFrame


@dataclass(frozen=True)
class Row:
    """One scene, seed and policy."""

    scene: str
    seed: int
    policy: str
    mota: float
    idf1: float
    switches: int
    ids: int
    off_truth_s: float
    ms: float


def off_truth_seconds(tracks: list[Tracks], truth: list[TruthFrame], gate: float) -> float:
    """Person-track-seconds [s] farther than ``gate`` [m] from every true person."""
    total = 0.0
    for k in range(1, len(tracks)):
        dt = tracks[k].stamp - tracks[k - 1].stamp
        people = tracks[k].of_kind("person")
        if not people:
            continue
        pos = np.stack([t.position for t in people])
        tp = truth[k].positions if k < len(truth) else np.empty((0, 2))
        if len(tp) == 0:
            total += dt * len(people)
            continue
        d = np.min(np.linalg.norm(pos[:, None, :] - tp[None, :, :], axis=2), axis=1)
        total += dt * int(np.count_nonzero(d > gate))
    return total


def furniture_scene(name: str, seed: int) -> SimResult:
    """Simulate one of the furniture-only scenes (see the module docstring)."""
    from laserpeople.scan import Pose2D
    from laserpeople.sim.scenarios.arras import DETECTION_HEIGHT, _lms, office_world
    from laserpeople.sim.simulator import Scene, simulate
    from laserpeople.sim.world import World, chair, room, table

    if name == "furniture-office":
        objects = office_world()
    else:
        rng = np.random.default_rng([seed, 0xC4A1])
        objects = [*room(0.0, 0.0, 7.0, 6.0)]
        for _ in range(8):
            objects += chair(
                float(rng.uniform(0.8, 6.2)),
                float(rng.uniform(1.2, 5.2)),
                float(rng.uniform(0, 6.3)),
            )
        for _ in range(2):
            objects += table(float(rng.uniform(1.5, 5.5)), float(rng.uniform(2.0, 4.8)))
    sensor = _lms("laser", DETECTION_HEIGHT, Pose2D(3.5, 0.2, np.pi / 2))
    return simulate(Scene(World(objects), [], [sensor]), 30.0, seed=seed, name=name)


def run(
    scene: str,
    seed: int,
    policy: str,
    static_model: bool,
    gate: float,
    leg_model: str | None = None,
    base: LegTrackerParams | None = None,
) -> Row:
    """Simulate, detect (the shipped leg model, or a model file), track with
    ``policy``, score."""
    if scene.startswith("furniture-"):
        result = furniture_scene(scene, seed)
    else:
        result = run_scenario(scene, seed=seed)
    scans = list(result.scans)
    first = scans[0].sensor
    scans = [s for s in scans if s.sensor == first]
    truth = list(result.truth)
    detector = (
        AdaBoostLegDetector.default()
        if leg_model is None
        else AdaBoostLegDetector.from_file(leg_model)
    )
    params = replace(base if base is not None else LegTrackerParams(), people_policy=policy)
    model = None
    if static_model and policy == "tracks":
        from laserpeople.background.occupancy import OccupancyGrid, frame_from_scan

        model = OccupancyGrid()
    tracker = LegMHTTracker(params, static_model=model)
    outputs: list[Tracks] = []
    spent = 0.0
    for scan in scans:
        dets = detector.detect(scan)
        t0 = time.perf_counter()
        if model is not None:
            model(frame_from_scan(scan, "world" if scan.pose is not None else "sensor"))
        outputs.append(tracker.update(dets))
        spent += time.perf_counter() - t0
    summary = (
        evaluate(truth, outputs).result().summary() if any(len(t.positions) for t in truth) else {}
    )
    ids = len({t.track_id for o in outputs for t in o.of_kind("person")})
    return Row(
        scene,
        seed,
        policy,
        float(summary.get("mota") or 0.0),
        float(summary.get("idf1") or 0.0),
        int(summary.get("id_switches") or 0),
        ids,
        off_truth_seconds(outputs, truth, gate),
        1e3 * spent / max(len(scans), 1),
    )


def parse_scene(spec: str) -> tuple[str, list[int]]:
    """``name:0-4`` or ``name:1,3`` or ``name`` (seed 0)."""
    if ":" not in spec:
        return spec, [0]
    name, seeds = spec.split(":", 1)
    if "-" in seeds:
        a, b = seeds.split("-")
        return name, list(range(int(a), int(b) + 1))
    return name, [int(s) for s in seeds.split(",")]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", nargs="+", default=["demo:0-4"])
    ap.add_argument("--policies", nargs="+", default=["arras", "tracks"])
    ap.add_argument("--static-model", action="store_true", help="occupancy grid for tracks")
    ap.add_argument("--static-gate", type=float, default=1.0, help="m")
    ap.add_argument("--model", default=None, help="leg model file (default: the shipped model)")
    ap.add_argument("--config", type=Path, help="TOML whose [leg_tracker] the tracker reads")
    args = ap.parse_args()
    base = load_config(LegTrackerParams, args.config) if args.config else None
    print("scene              seed policy  MOTA   IDF1   IDsw  ids  off-truth[s]  ms/scan")
    means: dict[tuple[str, str], list[Row]] = {}
    for spec in args.scenes:
        name, seeds = parse_scene(spec)
        for seed in seeds:
            for policy in args.policies:
                r = run(name, seed, policy, args.static_model, args.static_gate, args.model, base)
                means.setdefault((name, policy), []).append(r)
                print(
                    f"{name:18s} {seed:4d} {policy:7s} {r.mota:6.3f} {r.idf1:6.3f} "
                    f"{r.switches:5d} {r.ids:4d} {r.off_truth_s:12.1f} {r.ms:8.2f}",
                    flush=True,
                )
    print("\nmeans")
    for (name, policy), rows in means.items():
        print(
            f"{name:18s} {policy:7s} MOTA {np.mean([r.mota for r in rows]):.3f} "
            f"IDF1 {np.mean([r.idf1 for r in rows]):.3f} "
            f"IDsw {np.mean([r.switches for r in rows]):.1f} "
            f"ids {np.mean([r.ids for r in rows]):.1f} "
            f"off-truth {np.mean([r.off_truth_s for r in rows]):.1f} s "
            f"ms {np.mean([r.ms for r in rows]):.2f}"
        )


if __name__ == "__main__":
    main()
