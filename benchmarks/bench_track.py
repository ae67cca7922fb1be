"""Cycle time of the leg MHT tracker: median ms per scan for 4 and for 20 walking people.

Synthetic leg detections (stance/swing gait, mutual occlusion, random misses, clutter) at
the scan rate given; the tracker's parameters are the defaults (k and N stated in the
output). Median wall time per scan, and the median process CPU time (the figure to compare
on a shared machine, where wall time includes waiting for a core). The paper needed 44.5 ms
per cycle for 4 people (000 Sec. 3.4.3); the goal here is under 2 ms.

    .venv/bin/python benchmarks/bench_track.py [--seconds 30] [--rate 37.5] [--tracker leg-mht]

With ``--scenes`` it instead runs the demo scene and the simulated scenes of 000 Sec. 3.4
(figure-eight,
turn-on-stance-leg, narrow-corridor; detections from the ground truth with ray-cast
occlusion, or with ``--detector adaboost`` from the shipped leg detector) in the adaptive and
both non-adaptive modes, and prints created tracks (Fig. 8), hypotheses (Fig. 9), person
MOTA/IDF1 and the median cycle time:

    .venv/bin/python benchmarks/bench_track.py --scenes [--seed 0] [--detector adaboost]
"""

from __future__ import annotations

import argparse
import math
import time
from typing import Any

import numpy as np

from laserpeople.tracking import registry
from laserpeople.tracking import synthetic as syn


def crowd(n_people: int, seed: int, synthetic: Any = syn) -> list[Any]:
    """People walking back and forth across an 8 m x 8 m area in front of the sensor, as
    paths of the module ``synthetic`` (``laserpeople.tracking.synthetic`` or another
    version's copy of it, for ``bench_track_ab.py``)."""
    rng = np.random.default_rng(seed)
    paths: list[Any] = []
    for _ in range(n_people):
        start = (float(rng.uniform(1.5, 8.0)), float(rng.uniform(-4.0, 4.0)))
        heading = float(rng.uniform(-math.pi, math.pi))
        speed = float(rng.uniform(0.6, 1.3))
        paths.append(
            synthetic.line_path(start, (speed * math.cos(heading) * 0.3, speed * math.sin(heading)))
        )
    return paths


def crowd_scene(n_people: int, seconds: float, rate: float, synthetic: Any = syn) -> Any:
    """The benchmark's scene of ``n_people`` walkers (seeded by their number) with clutter,
    built by the module ``synthetic`` (see :func:`crowd`)."""
    sensor = synthetic.SensorModel(false_alarms_per_scan=0.5, box=(0.5, -6.0, 10.0, 6.0))
    paths = crowd(n_people, seed=n_people, synthetic=synthetic)
    return synthetic.make_scene(paths, seconds, rate=rate, sensor=sensor)


def bench(n_people: int, seconds: float, rate: float, tracker_name: str) -> dict[str, float]:
    scene = crowd_scene(n_people, seconds, rate)
    entry = registry.get(tracker_name)
    params = entry.params_cls()
    # the registry hands out frame trackers; time the leg tracker inside the adapter
    tracker = getattr(entry.factory(params), "tracker", None) or entry.factory(params)
    times = []
    cpu = []
    hyps = []
    for d in scene.detections:
        t0, c0 = time.perf_counter(), time.process_time()
        tracker.update(d)
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
        hyps.append(getattr(tracker, "n_hypotheses", 0))
    ms = np.array(times) * 1e3
    return {
        "median_ms": float(np.median(ms)),
        "cpu_median_ms": 1e3 * float(np.median(cpu)),
        "p95_ms": float(np.percentile(ms, 95)),
        "mean_hypotheses": float(np.mean(hyps)),
        "mean_detections": float(np.mean([len(d) for d in scene.detections])),
    }


SCENES = (
    ("demo", None),
    ("figure-eight", 30.0),
    ("turn-on-stance-leg", 20.0),
    ("narrow-corridor", 40.0),
)


def scenes(seed: int, detector: str) -> None:
    """The 000 Sec. 3.4 experiments on simulated scenes, adaptive vs non-adaptive."""
    from laserpeople.evaluation import evaluate
    from laserpeople.sim.scenarios import run_scenario
    from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams

    modes = {
        "adaptive": LegTrackerParams(),
        "non-adaptive (free)": LegTrackerParams(adaptive=False),
        "non-adaptive (approved)": LegTrackerParams(adaptive=False, nonadaptive_class="approved"),
    }
    for name, seconds in SCENES:
        result = run_scenario(name, seconds=seconds, seed=seed)
        if detector == "truth":
            dets = syn.detections_from_sim(result.scans, result.truth, clutter_probability=0.9)
        else:
            from laserpeople.detection.detector import AdaBoostLegDetector

            det = AdaBoostLegDetector.default()
            first = result.scans[0].sensor
            dets = [det.detect(s) for s in result.scans if s.sensor == first]
        print(f"{name} (seed {seed}, {len(dets)} scans, detections: {detector})")
        for label, params in modes.items():
            tracker = LegMHTTracker(params)
            outs, hyps, times = [], [], []
            for d in dets:
                t0 = time.perf_counter()
                outs.append(tracker.update(d))
                times.append(time.perf_counter() - t0)
                hyps.append(tracker.n_hypotheses)
            summary = evaluate(result.truth, outs).result().summary()
            print(
                f"  {label:24s} leg tracks created {len(tracker.leg_ids_reported):3d}, "
                f"persons created {tracker.people.persons_created:3d}, hypotheses mean "
                f"{np.mean(hyps):5.1f} max {max(hyps):3d}, MOTA {summary['mota']:.3f}, "
                f"MOTP {summary['motp_m'] or float('nan'):.3f} m, IDF1 {summary['idf1']:.3f}, "
                f"{1e3 * np.median(times):.2f} ms/scan"
            )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--rate", type=float, default=37.5, help="scan rate [Hz]")
    ap.add_argument("--tracker", default="leg-mht")
    ap.add_argument("--people", type=int, nargs="+", default=[4, 20])
    ap.add_argument("--scenes", action="store_true", help="run the 000 Sec. 3.4 scenes")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--detector", choices=("truth", "adaboost"), default="truth")
    args = ap.parse_args()
    if args.scenes:
        scenes(args.seed, args.detector)
        return
    entry = registry.get(args.tracker)
    params = entry.params_cls()
    mht = params.mht_params() if hasattr(params, "mht_params") else getattr(params, "mht", None)
    if mht is not None:
        print(f"{args.tracker}: k = {mht.k}, N-scan = {mht.depth}, ratio = {mht.ratio}")
    for n in args.people:
        r = bench(n, args.seconds, args.rate, args.tracker)
        print(
            f"{n:3d} people @ {args.rate:g} Hz: median {r['median_ms']:.2f} ms/scan "
            f"(process CPU {r['cpu_median_ms']:.2f}), "
            f"p95 {r['p95_ms']:.2f} ms, mean hypotheses {r['mean_hypotheses']:.1f}, "
            f"mean detections {r['mean_detections']:.1f}"
        )


if __name__ == "__main__":
    main()
