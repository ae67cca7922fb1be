"""Speed of the particle-filter trackers of 004: scans per second for 5 people with 500
particles per filter (issue 14).

The 004 scene "5 pers." (``people-5``: five people in two rows on line (a), 50 Hz
LMS151) is simulated once; the frames of two lasers (feet height for the feet tracker,
upper-body height for the upper-body tracker) are fused and background-subtracted
before timing, so only ``update`` is timed. Reported per tracker: the median time of one
``update`` (CPU time, so that other jobs on the machine do not count) over the frames
in which 5 or more filters are alive, as scans/s (median and
5th-95th percentile), and the mean rate over the whole run::

    nice -n 10 .venv/bin/python benchmarks/bench_particle.py [--seed 100] [--particles 500]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from laserpeople.background.beam_histogram import BeamHistogramBackground
from laserpeople.evaluation.schenk_scenes import lasers_of, simulate_scene
from laserpeople.frame import FrameTracker
from laserpeople.tracking.particle.feet import FeetParams, FeetTracker
from laserpeople.tracking.particle.frames import fused_frames
from laserpeople.tracking.particle.upper_body import UpperBodyParams, UpperBodyTracker


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=100)
    ap.add_argument("--particles", type=int, default=500)
    args = ap.parse_args()
    rec, empty = simulate_scene("people-5", args.seed)
    trackers: dict[str, tuple[str, FrameTracker]] = {
        "feet-pf": ("feet", FeetTracker(FeetParams(particles=args.particles))),
        "upper-body-pf": ("torso", UpperBodyTracker(UpperBodyParams(particles=args.particles))),
    }
    print(f"people-5 seed {args.seed}, {args.particles} particles per filter, 50 Hz")
    for name, (height, tracker) in trackers.items():
        sensors = lasers_of(rec, height)
        bg = BeamHistogramBackground().learn_scans(s for s in empty.scans if s.sensor in sensors)
        frames = fused_frames(rec.scans, sensors, bg)
        times, alive = [], []
        for frame in frames:
            t0 = time.process_time()
            tracker.update(frame)
            times.append(time.process_time() - t0)
            alive.append(len(tracker.bank))  # type: ignore[attr-defined]
        t, n = np.array(times), np.array(alive)
        busy = t[n >= 5]
        p5, med, p95 = np.percentile(busy, [95, 50, 5]) if busy.size else (np.nan,) * 3
        print(
            f"{name}: {1.0 / med:.0f} scans/s median ({1.0 / p5:.0f}-{1.0 / p95:.0f}, "
            f"5th-95th pct of time) over {busy.size} frames with >= 5 filters "
            f"(median {np.median(n[n >= 5]) if busy.size else 0:.0f} filters); "
            f"{len(t) / t.sum():.0f} scans/s mean over all {len(t)} frames"
        )


if __name__ == "__main__":
    main()
