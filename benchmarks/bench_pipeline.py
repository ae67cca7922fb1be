"""Overhead of the pipeline: the same detect -> track -> write loop, bare and as a Pipeline.

Both variants run over the same scans held in memory (reading is the same code in both
and only adds noise), with a fresh AdaBoost detector and a fresh tracker per run, and
write the tracks CSV to a temporary file; both files must hold the same rows. Runs
alternate bare / pipeline ``--repeat`` times and are timed in process CPU time (other
processes on a shared machine do not count); the minimum per variant is compared. The
goal: pipeline overhead under 5 % of the bare loop's time per scan.

A second figure isolates the pipeline's own cost per frame: the same pipeline with a
detector and a tracker that do nothing (frames, stage calls, the build-time check, the
CSV sink with no rows).

    .venv/bin/python benchmarks/bench_pipeline.py [--scans 400] [--repeat 5] [--tracker nn]
"""

from __future__ import annotations

import argparse
import itertools
import os
import tempfile
import time
from pathlib import Path

from laserpeople.detection.detector import AdaBoostLegDetector
from laserpeople.frame import Frame, FrameField
from laserpeople.io import open_recording
from laserpeople.io.tracks_csv import TracksCsvWriter
from laserpeople.pipeline import DetectLegs, FrameChooser, Pipeline, TracksCsvSink, laser_frames
from laserpeople.scan import Scan
from laserpeople.tracking import registry
from laserpeople.tracks import Detections, Tracks

REAL_BAG = "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag"


def bare(scans: list[Scan], tracker_name: str, out: Path) -> float:
    """The loop as the commands ran it before the pipeline; seconds."""
    entry = registry.get(tracker_name)
    tracker = entry.make().tracker  # type: ignore[attr-defined]
    detector = AdaBoostLegDetector.default()
    t0 = time.process_time()
    writer: TracksCsvWriter | None = None
    for scan in scans:
        tracks = tracker.update(detector.detect(scan))
        if writer is None:
            writer = TracksCsvWriter(out, frame=tracks.frame)
        writer.write(tracks)
    if writer is not None:
        writer.close()
    return time.process_time() - t0


def pipeline(scans: list[Scan], tracker_name: str, out: Path) -> float:
    """The same through :class:`laserpeople.pipeline.Pipeline`; seconds."""
    entry = registry.get(tracker_name)
    tracker = entry.make()
    detector = AdaBoostLegDetector.default()
    t0 = time.process_time()
    Pipeline(
        FrameChooser()(laser_frames(scans)),
        observe=[DetectLegs(detector)],
        tracker=tracker,
        sinks=[TracksCsvSink(out)],
    ).run()
    return time.process_time() - t0


class _NoDetector:
    def detect(self, scan: Scan) -> Detections:
        return Detections.empty(scan.stamp, scan.index, "sensor", scan.pose)


class _NoTracker:
    consumes: frozenset[FrameField] = frozenset({"legs"})

    def update(self, frame: Frame) -> Tracks:
        return Tracks(frame.stamp, frame.index, (), frame.frame)


def own_cost(scans: list[Scan], out: Path, repeat: int) -> float:
    """The pipeline's own time per frame [s] (do-nothing detector and tracker)."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.process_time()
        Pipeline(
            FrameChooser()(laser_frames(scans)),
            observe=[DetectLegs(_NoDetector())],
            tracker=_NoTracker(),
            sinks=[TracksCsvSink(out)],
        ).run()
        best = min(best, time.process_time() - t0)
    return best / len(scans)


def load(name: str, n: int) -> list[Scan]:
    if name == "demo":
        from laserpeople.sim import run_scenario

        scans = list(run_scenario("demo", seed=0).scans)
        first = scans[0].sensor
        return [s for s in scans if s.sensor == first][:n]
    data = Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "../shared/data"))
    rec = open_recording(data / REAL_BAG)
    try:
        return list(itertools.islice(rec.scans(), n))
    finally:
        rec.close()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scans", type=int, default=400)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--tracker", action="append")
    ap.add_argument("--source", action="append", choices=("demo", "real"))
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        a, b = Path(tmp) / "a.csv", Path(tmp) / "b.csv"
        for source in args.source or ["demo", "real"]:
            scans = load(source, args.scans)
            for name in args.tracker or ["leg-mht", "nn"]:
                times: dict[str, list[float]] = {"bare": [], "pipeline": []}
                for _ in range(args.repeat):
                    times["bare"].append(bare(scans, name, a))
                    times["pipeline"].append(pipeline(scans, name, b))
                if a.read_text().splitlines()[0] != ",".join(
                    b.read_text().splitlines()[0].split(",")[:13]
                ):
                    raise SystemExit("the two variants wrote different headers")
                t_bare, t_pipe = min(times["bare"]), min(times["pipeline"])
                n = len(scans)
                own = own_cost(scans, b, args.repeat)
                print(
                    f"{source:5s} {name:8s} {n} scans: bare {1e3 * t_bare / n:.3f} ms/scan, "
                    f"pipeline {1e3 * t_pipe / n:.3f} ms/scan, overhead "
                    f"{1e6 * (t_pipe - t_bare) / n:+.1f} us/scan "
                    f"({100 * (t_pipe - t_bare) / t_bare:+.1f} %); pipeline's own cost "
                    f"{1e6 * own:.1f} us/frame = {100 * own * n / t_bare:.2f} % of bare"
                )


if __name__ == "__main__":
    main()
