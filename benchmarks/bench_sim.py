"""Speed of the simulator: scans per second for 720 beams and 10 walking people.

Target (issue 3): >= 1000 scans/s on one core for the per-scan work (ray casting against
every leg, wall and piece of clutter, noise, beam labels, building the Scan). Also
reported: the end-to-end rate of ``simulate`` including motion planning and truth.

Run:  .venv/bin/python benchmarks/bench_sim.py
"""

from __future__ import annotations

import statistics
import time

import numpy as np

from laserpeople.scan import Pose2D
from laserpeople.sim import Scene, simulate
from laserpeople.sim.motion import Route
from laserpeople.sim.people import plan_person, random_person
from laserpeople.sim.sensors import LASER_MODELS, LaserModel, SensorSpec
from laserpeople.sim.simulator import _dynamic_shapes, render_scan, scan_times
from laserpeople.sim.world import World, chair, pillar, room, round_bin, table

BENCH_MODEL = LaserModel(
    "bench-720", 359.5, 0.5, 40.0, 0.05, 30.0, 0.01, 0.0, 0.001, "720 beams over 359.5 deg"
)


def bench_scene(n_people: int = 10, seed: int = 0) -> Scene:
    """A 12 x 10 m room with clutter and ``n_people`` walking criss-cross."""
    rng = np.random.default_rng(seed)
    objs = [*room(0.0, 0.0, 12.0, 10.0), pillar(3.0, 7.0), round_bin(9.0, 2.0)]
    objs += [*table(9.0, 8.0), *chair(8.0, 7.0), *chair(2.0, 2.0)]
    people = []
    for i in range(n_people):
        pts = rng.uniform([1.0, 1.0], [11.0, 9.0], size=(6, 2))
        route = Route(float(pts[0, 0]), float(pts[0, 1]), 0.0).walk_path(
            pts[1:], float(rng.uniform(0.8, 1.4))
        )
        people.append(random_person(rng, i, route))
    LASER_MODELS[BENCH_MODEL.name] = BENCH_MODEL
    sensor = SensorSpec("laser", BENCH_MODEL.name, 0.2, Pose2D(6.0, 5.0, 0.3))
    return Scene(World(objs), people, [sensor])


def per_scan_rate(scene: Scene, n_scans: int = 2000, repeats: int = 5) -> list[float]:
    """Scans/s of :func:`render_scan` alone (motion planned beforehand)."""
    duration = n_scans / 40.0
    planned = [plan_person(p, duration) for p in scene.people]
    spec = scene.sensors[0]
    times = scan_times(duration, 40.0, 0.0)[:n_scans]
    shapes = _dynamic_shapes(planned, times, spec.height, scene.world.n_objects)
    pose = np.array([spec.mount.x, spec.mount.y, spec.mount.theta])
    rates = []
    for _ in range(repeats):
        rng = np.random.default_rng(0)
        t0 = time.perf_counter()
        hits = 0
        for k in range(times.size):
            scan, _ = render_scan(spec, scene.world, shapes.at(k), pose, float(times[k]), k, rng)
            hits += int(np.count_nonzero(scan.labels.leg >= 0))  # type: ignore[union-attr]
        rates.append(times.size / (time.perf_counter() - t0))
    assert hits > 0
    return rates


def end_to_end_rate(scene: Scene, seconds: float = 25.0, repeats: int = 3) -> list[float]:
    """Scans/s of :func:`simulate` (planning, ray casting, truth)."""
    rates = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        result = simulate(scene, seconds, seed=0)
        rates.append(len(result.scans) / (time.perf_counter() - t0))
    return rates


def main() -> None:
    scene = bench_scene()
    n_beams = LASER_MODELS["bench-720"].n_beams
    r = per_scan_rate(scene)
    print(f"per-scan (ray cast + noise + labels), {n_beams} beams, 10 people + clutter:")
    print(
        f"  median {statistics.median(r):8.0f} scans/s  (runs: {', '.join(f'{x:.0f}' for x in r)})"
    )
    e = end_to_end_rate(scene)
    print("end-to-end simulate() incl. gait planning and ground truth:")
    print(
        f"  median {statistics.median(e):8.0f} scans/s  (runs: {', '.join(f'{x:.0f}' for x in e)})"
    )
    target = 1000.0
    verdict = "meets" if statistics.median(r) >= target else "MISSES"
    print(f"target >= {target:.0f} scans/s per scan: {verdict}")


if __name__ == "__main__":
    main()
