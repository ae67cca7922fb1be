"""Do simulated legs look like real ones? Per-segment statistics side by side.

Real: the labelled legs of leg_tracker's ``positive_*_extracted.bag`` (``/training_scan``
paired one to one with ``/leg_cluster_positions``, laser frame; 768 beams over 270 deg,
0.352 deg apart). Simulated: people walking and standing 1-4 m from a scanner with the
same angular resolution (Hokuyo URG-04LX geometry).

Both are segmented with the same jump-distance rule (a new segment where neighbouring
valid points are more than ``JUMP`` apart) and a segment whose centre lies within
``MATCH`` of a labelled leg is that leg. Printed per range bin: number of legs, median
and quartiles of the segment width (first to last point) and of the points per leg.

Run:  .venv/bin/python benchmarks/sim_vs_real.py [--sigma 0.01] [--seconds 120]
"""

from __future__ import annotations

import argparse
import itertools
import math
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.scan import Pose2D
from laserpeople.sim import Scene, simulate
from laserpeople.sim.motion import Route
from laserpeople.sim.people import BodyParams, random_person
from laserpeople.sim.sensors import SensorSpec
from laserpeople.sim.world import World, room

DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "leg_tracker" / "rosbags"
BAGS = "training_scans_res=0.33/positive_*_extracted.bag"
JUMP = 0.13  # m, leg_tracker's default cluster distance
MATCH = 0.1  # m, "a segment whose centre is within ~0.1 m of a label is a leg"
BINS = np.array([1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0])

Stats = list[tuple[float, float, int]]  # (range of the segment centre, width, points)


def segment(points: NDArray[np.float64]) -> list[NDArray[np.float64]]:
    """Split the valid points (K, 2) of a scan, in beam order, at jumps > JUMP."""
    if len(points) == 0:
        return []
    gaps = np.linalg.norm(np.diff(points, axis=0), axis=1) > JUMP
    return np.split(points, np.flatnonzero(gaps) + 1)


def leg_stats(points: NDArray[np.float64], legs: NDArray[np.float64]) -> Stats:
    """Statistics of the segments matched to the leg positions ``legs`` (L, 2)."""
    segs = segment(points)
    if not segs or len(legs) == 0:
        return []
    centres = np.array([s.mean(axis=0) for s in segs])
    out: Stats = []
    for leg in legs:
        d = np.linalg.norm(centres - leg, axis=1)
        j = int(np.argmin(d))
        if d[j] <= MATCH:
            s = segs[j]
            out.append((float(np.hypot(*centres[j])), float(np.linalg.norm(s[-1] - s[0])), len(s)))
    return out


def real_stats() -> Stats:
    """Leg statistics of the real labelled scans."""
    from rosbags.highlevel import AnyReader

    out: Stats = []
    for bag in sorted(DATA.glob(BAGS)):
        scans, labels = [], []
        with AnyReader([bag]) as reader:
            conns = [
                c
                for c in reader.connections
                if c.topic in ("/training_scan", "/leg_cluster_positions")
            ]
            for conn, _t, raw in reader.messages(connections=conns):
                msg: Any = reader.deserialize(raw, conn.msgtype)
                if conn.topic == "/training_scan":
                    r = np.asarray(msg.ranges, dtype=np.float64)
                    a = msg.angle_min + np.arange(r.size) * msg.angle_increment
                    ok = np.isfinite(r) & (r > msg.range_min) & (r < msg.range_max)
                    scans.append(np.column_stack([r * np.cos(a), r * np.sin(a)])[ok])
                else:
                    labels.append(
                        np.array([[p.position.x, p.position.y] for p in msg.poses]).reshape(-1, 2)
                    )
        if len(scans) != len(labels):
            raise SystemExit(f"{bag}: {len(scans)} scans but {len(labels)} label sets")
        for pts, legs in zip(scans, labels, strict=True):
            out.extend(leg_stats(pts, legs))
    return out


def sim_scene(rng: np.random.Generator, seconds: float, sigma: float, body: BodyParams) -> Scene:
    """People walking (and now and then standing) 1-4.5 m in front of a URG-04LX-like scanner."""
    world = World(room(-6.0, -6.0, 6.0, 6.0))
    people = []
    for i in range(5):
        x0, y0 = rng.uniform([-3.0, 0.8], [3.0, 4.5])
        route = Route(float(x0), float(y0), 0.0)
        while route.end_time < seconds:
            target = rng.uniform([-3.5, 0.8], [3.5, 4.5])
            route.walk_to(float(target[0]), float(target[1]), float(rng.uniform(0.5, 1.4)))
            if rng.random() < 0.3:
                route.wait(float(rng.uniform(0.5, 3.0)))
        people.append(random_person(rng, i, route, params=body))
    # the laser faces +y; 7.5 Hz like the real recordings
    sensor = SensorSpec(
        "laser", "hokuyo-urg-04lx", 0.25, Pose2D(0.0, 0.0, math.pi / 2), rate_hz=7.5, sigma=sigma
    )
    return Scene(world, people, [sensor])


def sim_stats(seconds: float, sigma: float, body: BodyParams, seed: int = 0) -> Stats:
    """Leg statistics of a simulated recording, legs labelled from the ground truth."""
    rng = np.random.default_rng(seed)
    result = simulate(sim_scene(rng, seconds, sigma, body), seconds, seed=seed)
    out: Stats = []
    for scan, frame in zip(result.scans, result.truth, strict=True):
        pts, _ = scan.valid_points("sensor")
        assert scan.pose is not None
        legs = scan.pose.inverse_transform_points(frame.leg_positions.reshape(-1, 2))
        out.extend(leg_stats(pts, legs))
    return out


def table(name: str, stats: Stats) -> list[str]:
    """Rows: range bin, legs, width median [q1-q3] (cm), points median [q1-q3]."""
    arr = np.array(stats, dtype=np.float64).reshape(-1, 3)
    rows = []
    for lo, hi in itertools.pairwise(BINS):
        sel = arr[(arr[:, 0] >= lo) & (arr[:, 0] < hi)]
        if len(sel) == 0:
            rows.append(f"{name:5s} {lo:3.1f}-{hi:3.1f} m  {0:5d}")
            continue
        w = np.percentile(sel[:, 1] * 100, [25, 50, 75])
        n = np.percentile(sel[:, 2], [25, 50, 75])
        rows.append(
            f"{name:5s} {lo:3.1f}-{hi:3.1f} m  {len(sel):5d}  "
            f"{w[1]:5.1f} [{w[0]:4.1f}-{w[2]:4.1f}]  {n[1]:5.1f} [{n[0]:4.1f}-{n[2]:4.1f}]"
        )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sigma", type=float, default=None, help="simulated range noise [m]")
    parser.add_argument("--seconds", type=float, default=160.0, help="simulated length [s]")
    parser.add_argument("--leg-radius", type=float, nargs=2, default=None, help="min max [m]")
    parser.add_argument("--hip", type=float, nargs=2, default=None, help="min max [m]")
    args = parser.parse_args()
    body = BodyParams()
    if args.leg_radius:
        body = replace(body, leg_radius_min=args.leg_radius[0], leg_radius_max=args.leg_radius[1])
    if args.hip:
        body = replace(body, hip_half_width_min=args.hip[0], hip_half_width_max=args.hip[1])
    sigma = args.sigma if args.sigma is not None else 0.01
    real = real_stats()
    sim = sim_stats(args.seconds, sigma, body)
    print(
        f"jump distance {JUMP} m, match radius {MATCH} m; simulated leg radius "
        f"{body.leg_radius_min}-{body.leg_radius_max} m, range noise {sigma} m"
    )
    print("data  range      legs  width cm: median [q1-q3]  points: median [q1-q3]")
    for r_row, s_row in zip(table("real", real), table("sim", sim), strict=True):
        print(r_row)
        print(s_row)
    r_arr, s_arr = np.array(real), np.array(sim)
    for name, arr in (("real", r_arr), ("sim", s_arr)):
        sel = arr[(arr[:, 0] >= 1.0) & (arr[:, 0] < 4.0)]
        print(
            f"{name:5s} 1-4 m: {len(sel)} legs, width median {np.median(sel[:, 1]) * 100:.1f} cm, "
            f"points median {np.median(sel[:, 2]):.1f}"
        )


if __name__ == "__main__":
    main()
