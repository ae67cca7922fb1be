"""Cycle time of the Cluster Sorting Algorithm (002): median ms per frame for 3 and 10
people, and of the colour re-identification stage on top of it.

3 people: the ``crossing-3`` scenes (all six permutations, seed 0). 10 people: people
walking between random waypoints of an 8 m x 6 m area in front of the two back-to-back
lasers of 002's robot (they meet, form clusters and split again). Frames hold the raw
foreground points of both lasers (the simulator's per-beam labels) and the simulated
camera's colour observations.

    PYTHONPATH=src .venv/bin/python benchmarks/bench_csa.py [--seconds 20] [--seed 0]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from laserpeople.frame import Frame
from laserpeople.identity.reid import ColourReidentifier
from laserpeople.scan import Pose2D
from laserpeople.sim.camera import SimulatedCamera, simulated_frames
from laserpeople.sim.motion import Route
from laserpeople.sim.people import random_person
from laserpeople.sim.scenarios import run_scenario
from laserpeople.sim.sensors import SensorSpec
from laserpeople.sim.simulator import Scene, simulate
from laserpeople.sim.world import World, room
from laserpeople.tracking.csa import ClusterSortingTracker


def crowd_scene(n_people: int, seconds: float, seed: int) -> Scene:
    """``n_people`` walking between random waypoints in front of two back-to-back lasers."""
    rng = np.random.default_rng([seed, n_people])
    routes = []
    for _ in range(n_people):
        x, y = rng.uniform(-4.0, 4.0), rng.uniform(1.0, 7.0)
        r = Route(float(x), float(y), float(rng.uniform(-math.pi, math.pi)))
        speed = float(rng.uniform(0.6, 1.2))
        while r.end_time < seconds:
            r.walk_to(float(rng.uniform(-4.0, 4.0)), float(rng.uniform(1.0, 7.0)), speed=speed)
        routes.append(r)
    people = [random_person(rng, i, routes[i]) for i in range(n_people)]
    sensors = [
        SensorSpec("front", "sick-lms200", 0.35, Pose2D(0.0, 0.0, math.pi / 2), rate_hz=10.0),
        SensorSpec(
            "rear", "sick-lms200", 0.35, Pose2D(0.0, 0.0, -math.pi / 2), rate_hz=10.0, phase=0.05
        ),
    ]
    return Scene(World(room(-6.0, -3.0, 6.0, 9.0)), people, sensors)


def time_frames(frames: list[Frame]) -> tuple[list[float], list[float]]:
    """ms per frame of the CSA alone and of the colour stage after it."""
    csa = ClusterSortingTracker()
    reid = ColourReidentifier()
    t_csa, t_reid = [], []
    for f in frames:
        t0 = time.perf_counter()
        tracks = csa.update(f)
        t1 = time.perf_counter()
        reid.update(tracks, f)
        t2 = time.perf_counter()
        t_csa.append(1e3 * (t1 - t0))
        t_reid.append(1e3 * (t2 - t1))
    return t_csa, t_reid


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    rows = []
    csa3: list[float] = []
    reid3: list[float] = []
    points3: list[int] = []
    for k in range(6):
        result = run_scenario(f"crossing-3-p{k}", seed=args.seed)
        frames = simulated_frames(result, SimulatedCamera(seed=args.seed))
        a, b = time_frames(frames)
        csa3 += a
        reid3 += b
        points3 += [int(np.count_nonzero(f.foreground)) for f in frames]
    rows.append(("3 (crossing-3, 6 permutations)", csa3, reid3, points3))
    result = simulate(crowd_scene(10, args.seconds, args.seed), args.seconds, seed=args.seed)
    frames = simulated_frames(result, SimulatedCamera(seed=args.seed))
    a, b = time_frames(frames)
    rows.append(
        ("10 (random walkers)", a, b, [int(np.count_nonzero(f.foreground)) for f in frames])
    )
    print(
        "| people | frames | foreground points (mean) | CSA ms/frame median (p95) | "
        "+ colour re-id ms/frame median |"
    )
    print("|---|---|---|---|---|")
    for label, tc, tr, pts in rows:
        print(
            f"| {label} | {len(tc)} | {np.mean(pts):.0f} | {np.median(tc):.2f} "
            f"({np.percentile(tc, 95):.2f}) | {np.median(tr):.2f} |"
        )


if __name__ == "__main__":
    main()
