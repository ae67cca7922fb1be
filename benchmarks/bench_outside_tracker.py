"""The parts of ``track``'s loop outside the tracker, this tree against another side by
side in one process: reading the recording, leg detection, the point set, the static world
model.

The other tree is imported as the package ``laserpeople_ab`` (``bench_track_ab.load_other``).
Per pass and recording, each tree (who goes first alternates) reads the recording (the
real demo bag: decoding its ROS 1 LaserScans; the simulated halls (4 people, or ``--people``) of
``bench_scaling.py``: an .npz), detects the legs of every scan (``detect``: segmentation,
the 14 features, AdaBoost, the detections) scan by scan and as ``track`` does (blocks of
frames at once where the tree reads ahead), puts every scan into a point set (``Fuse``)
and feeds the people's static world model (``PeopleStaticModel("auto")`` as ``track``
runs it). Printed per recording and part: the median process CPU per scan over the passes
of each tree and the ratio before/after, then whether the outputs agree: the largest
difference of the detections' positions and scores, leg counts, and of the static world
model's answers (``static_time`` at every detection of the last 50 scans).

    PYTHONPATH=src .venv/bin/python benchmarks/bench_outside_tracker.py --before OLD/src
        [--passes 5] [--halls /tmp/halls] [--people 4 20]
"""

from __future__ import annotations

import argparse
import importlib
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_detect_ab import add_recording_arguments, recordings
from bench_track_ab import PACKAGE, load_other

PARTS = (
    "read",
    "frames as track reads",
    "detect, scan by scan",
    "detect as track does",
    "point set",
    "static world model",
)
"""The parts timed; ``frames as track reads``: the recording read again as ``track`` does
(``RecordingFrames``: the scans' checks of empty beams, beam layouts, stamps and copies,
and their frames, with each scan's validity mask); ``detect as track does``: blocks of
the pipeline's ``LOOKAHEAD`` frames detected at once (``detect_many``) where the tree has
it, else scan by scan.
"as track runs them" adds up the parts but ``read`` (which ``frames as track reads``
holds) and ``detect, scan by scan``."""


def run_parts(package: str, path: Path) -> tuple[dict[str, float], dict[str, Any]]:
    """CPU seconds per scan of each part for ``package`` on ``path``, and its outputs."""
    io = importlib.import_module(f"{package}.io")
    detector = importlib.import_module(f"{package}.detection.detector")
    pipe = importlib.import_module(f"{package}.pipeline")
    static = importlib.import_module(f"{package}.pipeline.static_people")
    # (``track`` makes its tracker, which imports the MHT's listing and its C extension,
    # before the first frame: the frames' checks find the extension then)
    importlib.import_module(f"{package}.tracking.mht.listing")
    clock = time.process_time
    cpu: dict[str, float] = {}
    t0 = clock()
    rec = io.open_recording(path)
    try:
        scans = list(rec.scans())
    finally:
        rec.close()
    cpu["read"] = clock() - t0
    t0 = clock()
    rec = io.open_recording(path)
    source = pipe.RecordingFrames(rec, [rec.topics()[0].name])
    try:
        # (with each scan's validity mask, which leg detection reads next: a tree whose
        # checks computed it pays for it there, one that did not pays here)
        n_frames = sum(1 for frame in source if frame.scans[0].valid is not None)
    finally:
        rec.close()
    cpu["frames as track reads"] = clock() - t0
    assert n_frames == len(scans)
    det = detector.AdaBoostLegDetector.default()
    t0 = clock()
    dets = [det.detect(s) for s in scans]
    cpu["detect, scan by scan"] = clock() - t0
    ahead = getattr(importlib.import_module(f"{package}.pipeline.recording"), "LOOKAHEAD", 1)
    det = detector.AdaBoostLegDetector.default()
    t0 = clock()
    if ahead > 1:
        blocks = [det.detect_many(scans[i : i + ahead]) for i in range(0, len(scans), ahead)]
        in_blocks = [d for block in blocks for d in block]
    else:
        in_blocks = [det.detect(s) for s in scans]
    cpu["detect as track does"] = clock() - t0
    frames = list(pipe.FrameChooser()(pipe.laser_frames(scans)))
    fuse = pipe.Fuse()
    t0 = clock()
    frames = [fuse(f) for f in frames]
    cpu["point set"] = clock() - t0
    model = static.PeopleStaticModel("auto")
    model.fill_foreground = False
    answers = []
    t0 = clock()
    for k, f in enumerate(frames):
        model(f)
        if k >= len(frames) - 50:
            answers.append(model.static_time(dets[k].positions))
    cpu["static world model"] = clock() - t0 - model.query_cpu
    per_scan = {part: seconds / len(scans) for part, seconds in cpu.items()}
    return per_scan, {"dets": dets, "blocks": in_blocks, "answers": answers}


def largest(a: list[np.ndarray], b: list[np.ndarray]) -> float:
    """The largest absolute difference of paired arrays (inf when their shapes differ)."""
    worst = 0.0
    for x, y in zip(a, b, strict=True):
        if x.shape != y.shape:
            return float("inf")
        if x.size:
            worst = max(worst, float(np.max(np.abs(x - y))))
    return worst


def compare(name: str, path: Path, packages: list[str], passes: int) -> None:
    """Time and compare the packages' parts on the recording ``path``."""
    times: dict[str, dict[str, list[float]]] = {p: {part: [] for part in PARTS} for p in packages}
    outputs: dict[str, dict[str, Any]] = {}
    for k in range(passes):
        for p in packages if k % 2 == 0 else packages[::-1]:
            per_scan, outputs[p] = run_parts(p, path)
            for part, seconds in per_scan.items():
                times[p][part].append(seconds)
    before, after = packages
    print(f"\n{name}: {passes} passes, median CPU ms per scan")
    print(f"  {'part':24s} {'before':>8s} {'after':>8s} {'before/after':>13s}")
    total = {p: 0.0 for p in packages}
    for part in PARTS:
        b, a = (statistics.median(times[p][part]) for p in packages)
        if part not in ("read", "detect, scan by scan"):
            total[before] += b
            total[after] += a
        print(f"  {part:24s} {1e3 * b:8.3f} {1e3 * a:8.3f} {b / a:12.2f}x")
    b, a = total[before], total[after]
    print(f"  {'as track runs them':24s} {1e3 * b:8.3f} {1e3 * a:8.3f} {b / a:12.2f}x")
    x = outputs[before]["dets"]
    for label, key in (("scan by scan", "dets"), ("in blocks", "blocks")):
        y = outputs[after][key]
        legs = sum(len(d) for d in x), sum(len(d) for d in y)
        print(
            f"  detections {label}: {legs[0]} -> {legs[1]} legs; largest difference of "
            f"positions {largest([d.positions for d in x], [d.positions for d in y]):.2e} m, "
            f"of scores {largest([d.scores for d in x], [d.scores for d in y]):.2e}"
        )
    print(
        "  static world model's answers: largest difference "
        f"{largest(outputs[before]['answers'], outputs[after]['answers']):.2e} s"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--before", type=Path, required=True, help="the other tree's src/")
    ap.add_argument("--passes", type=int, default=5)
    add_recording_arguments(ap)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        load_other(args.before, Path(tmp))
        packages = [PACKAGE, "laserpeople"]
        for name, path in recordings(args, Path(tmp)):
            compare(name, path, packages, args.passes)


if __name__ == "__main__":
    main()
