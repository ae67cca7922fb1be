"""Soak test: up to 1,000,000 simulated scans streamed through detection and a tracker, with
the tracker's state, its cycle time and the process memory sampled along the way.

The stream is made of simulated scenes of ``--seconds`` each played back to back with time
running on (scene ``k`` has the seed ``--seed + k`` and its stamps shifted by ``k`` scene
lengths), so a new crowd walks in every scene while the tracker keeps running: the scenes
change over time (default: the 60-s entrance hall of 000 Sec. 4.6, up to 20 people in
groups that meet, split and leave). Scans are simulated one scene at a time (constant
memory), run through the leg detector or the foreground stages the tracker consumes
(:func:`laserpeople.pipeline.observe_stages_for`) and the tracker (``--tracker``, any
registered one; default ``leg-mht``).

Every ``--every`` scans one row is printed: scans done, people in view (ground truth, mean
over the window), the tracker's state (leg MHT: live leg families, track nodes,
hypotheses, stored person tracks of its people layer; other trackers: the sizes their
``state_counts()`` gives, if any), the tracker's cycle time (mean and 95th percentile [ms]
over the window, CPU time of the process, so that other programs on a loaded machine do
not count; the wall time of the tracker and of the whole scan with simulation and
detection follow) and the process memory (RSS [MB], or the traced Python heap with
``--tracemalloc``, which slows the run down 2-3x). At the end: per quantity its peak and
its least-squares slope per 100,000 scans over the samples (flat is the goal; the slope
says how much it would grow over the next 100k scans), also written as JSON with ``--json``.

    PYTHONPATH=src .venv/bin/python benchmarks/soak.py --scans 10000 --every 500
    PYTHONPATH=src .venv/bin/python benchmarks/soak.py --scans 1000000 --every 10000 \
        --json soak.json        # the full run (hours, see README)
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time
import tracemalloc
from collections.abc import Iterator
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from laserpeople.frame import Frame
from laserpeople.pipeline import FrameChooser, Pipeline, laser_frames, observe_stages_for
from laserpeople.scan import Scan
from laserpeople.sim import run_scenario
from laserpeople.tracking import registry


def scene_stream(
    scenario: str, seconds: float, seed: int, scans: int, people: list[int]
) -> Iterator[Scan]:
    """``scans`` scans of back-to-back scenes (see the module doc); ``people`` receives the
    number of true people in view at each scan (appended as the scans are yielded)."""
    done = 0
    k = 0
    while done < scans:
        result = run_scenario(scenario, seconds=seconds, seed=seed + k)
        first = result.scans[0].sensor
        truth = {t.scan_index: len(t.positions) for t in result.truth}
        shift = k * seconds
        for scan in result.scans:
            if scan.sensor != first or scan.stamp >= seconds:  # the next scene starts there
                continue
            people.append(truth.get(scan.index, 0))
            yield replace(scan, stamp=scan.stamp + shift, index=done)
            done += 1
            if done >= scans:
                return
        k += 1


def state_counts(tracker: Any) -> dict[str, int]:
    """Sizes of the tracker's state: its own ``state_counts()`` (behind an adapter too)."""
    inner = getattr(tracker, "tracker", tracker)
    counts = getattr(inner, "state_counts", None)
    return dict(counts()) if callable(counts) else {}


class CpuTimed:
    """A frame tracker that records the CPU time [s] of each ``update`` (the process's,
    so that other programs on a loaded machine do not count, as they do in wall time)."""

    def __init__(self, tracker: Any) -> None:
        self.tracker = tracker
        self.consumes = tracker.consumes
        self.seconds = 0.0

    def update(self, frame: Frame) -> Any:
        """The wrapped tracker's update, timed."""
        t0 = time.process_time()
        out = self.tracker.update(frame)
        self.seconds = time.process_time() - t0
        return out


def memory_mb(traced: bool) -> float:
    """Traced Python heap or resident set size [MB]."""
    if traced:
        return tracemalloc.get_traced_memory()[0] / 1e6
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 1e6


@dataclass
class Soak:
    """Samples of one soak run: one row per window."""

    rows: list[dict[str, float]] = field(default_factory=list)

    def slope_per_100k(self, key: str) -> float:
        """Least-squares slope of ``key`` over the scans done, per 100,000 scans."""
        x = np.array([r["scans"] for r in self.rows], dtype=np.float64)
        y = np.array([r[key] for r in self.rows], dtype=np.float64)
        if x.size < 2 or np.ptp(x) == 0:
            return math.nan
        return float(np.polyfit(x, y, 1)[0] * 1e5)

    def peak(self, key: str) -> float:
        """Largest sample of ``key``."""
        return max(r[key] for r in self.rows)


def run(args: argparse.Namespace) -> Soak:
    entry = registry.get(args.tracker)
    params = entry.params_cls()
    if args.tracker == "leg-mht":
        if args.people_policy is not None:
            params = replace(params, people_policy=args.people_policy)
        if args.existence_ratio is not None:
            params = replace(params, mht=replace(params.mht, existence_ratio=args.existence_ratio))
    tracked = entry.make(params)
    tracker = CpuTimed(tracked)
    preprocess, observe = observe_stages_for(entry.consumes, None)
    people: list[int] = []
    scans = scene_stream(args.scenario, args.seconds, args.seed, args.scans, people)
    source: Iterator[Frame] = FrameChooser("world")(laser_frames(scans))
    pipe = Pipeline(source, preprocess=preprocess, observe=observe, tracker=tracker)
    soak = Soak()
    if args.tracemalloc:
        tracemalloc.start()
    window_ms: list[float] = []
    window_wall: list[float] = []
    t_window = time.perf_counter()
    header = False
    for n, step in enumerate(pipe, start=1):
        window_ms.append(1e3 * tracker.seconds)
        window_wall.append(1e3 * step.track_seconds)
        if n % args.every and n != args.scans:
            continue
        ms = np.array(window_ms)
        in_view = people[n - len(window_ms) : n]
        row: dict[str, float] = {
            "scans": n,
            "in_view": float(np.mean(in_view)) if in_view else 0.0,
            **state_counts(tracked),
            "track_ms": float(ms.mean()),
            "track_p95_ms": float(np.percentile(ms, 95)),
            "track_wall_ms": float(np.mean(window_wall)),
            "scan_wall_ms": 1e3 * (time.perf_counter() - t_window) / len(window_ms),
            "memory_mb": memory_mb(args.tracemalloc),
        }
        soak.rows.append(row)
        if not header:
            print("  ".join(f"{k:>12}" for k in row))
            header = True
        print(
            "  ".join(f"{v:12.1f}" if isinstance(v, float) else f"{v:12d}" for v in row.values()),
            flush=True,
        )
        window_ms = []
        window_wall = []
        t_window = time.perf_counter()
    return soak


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scans", type=int, default=10_000, help="scans to stream (up to 1e6)")
    ap.add_argument("--every", type=int, default=500, help="scans per sample")
    ap.add_argument("--tracker", default="leg-mht", help="any registered tracker")
    ap.add_argument("--scenario", default="entrance-hall")
    ap.add_argument("--seconds", type=float, default=60.0, help="length of each scene [s]")
    ap.add_argument("--seed", type=int, default=0, help="seed of the first scene")
    ap.add_argument("--people-policy", default=None, help="leg-mht: arras or tracks")
    ap.add_argument(
        "--existence-ratio", type=float, default=None, help="leg-mht: mht.existence_ratio"
    )
    ap.add_argument("--tracemalloc", action="store_true", help="trace the Python heap")
    ap.add_argument("--json", default=None, help="write the samples and summary here")
    args = ap.parse_args()
    if not 1 <= args.scans <= 1_000_000:
        ap.error("--scans must be in 1..1,000,000")
    if args.every < 1:
        ap.error("--every must be at least 1")
    t0 = time.perf_counter()
    soak = run(args)
    minutes = (time.perf_counter() - t0) / 60.0
    keys = [k for k in soak.rows[0] if k != "scans"]
    print(f"\n{args.tracker} on {args.scans} scans of {args.scenario} ({minutes:.1f} min):")
    print(f"{'':>14}{'peak':>12}{'slope/100k':>12}")
    summary = {}
    for k in keys:
        summary[k] = {"peak": soak.peak(k), "slope_per_100k": soak.slope_per_100k(k)}
        print(f"{k:>14}{soak.peak(k):12.2f}{soak.slope_per_100k(k):12.2f}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"args": vars(args), "rows": soak.rows, "summary": summary}, fh, indent=1)


if __name__ == "__main__":
    main()
