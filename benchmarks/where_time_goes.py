"""Where the whole loop's CPU goes per scan, part by part: the hall scenes of
``bench_scaling.py`` and the real demo bag, tracked as ``laserpeople track`` does.

Each recording is read into memory and run through the pipeline of ``bench_scaling.py``
(leg detection, the default leg MHT with its people layer, the static world model ``auto``)
with the parts wrapped in process-CPU timers (``bench_track_parts.timed``). Printed per
scene: the CPU per scan of the whole loop, then per part its CPU per scan and its share of
the loop. Parts nest (indented under the part that calls them); "the rest" of a part is
what its listed children leave. The timers add a little of their own (about a microsecond
per call); compare parts within a run. ``--profile N`` also prints the N functions with
the most self time (cProfile by process CPU time, which inflates Python calls about
twofold against numpy work: read it for which functions, not how much).

    PYTHONPATH=src .venv/bin/python benchmarks/where_time_goes.py [--people 4 20]
        [--seconds 8] [--no-demo] [--cache DIR] [--profile 25]
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

import laserpeople.detection.detector as detector
import laserpeople.detection.features as features
import laserpeople.tracking.legs as legs
import laserpeople.tracking.mht.core as core
import laserpeople.tracking.mht.listing as listing
import laserpeople.tracking.person_tracks as person_tracks
import laserpeople.tracking.point_model as point_model
from bench_scaling import DEMO_BAG, add_scene_arguments, hall_paths, pipeline
from bench_track_parts import timed

LEG_DETECTION = "leg detection in blocks: segments, features, legs"
PARTS: list[tuple[Any, str, str, int]] = [
    # (detect_many: the blocks of frames read ahead; detect: a scan not read ahead)
    (detector.AdaBoostLegDetector, "detect_many", LEG_DETECTION, 0),
    (features, "_compute", "features of the segments", 1),
    (features, "_compute_compiled", "features of the segments (the C extension)", 1),
    (detector.AdaBoostLegDetector, "detect", "leg detection scan by scan", 0),
    (legs.LegMHTTracker, "update", "leg tracker (MHT, people layer, glue)", 0),
    (core.MHT, "step", "MHT step", 1),
    (point_model.KalmanPointModel, "predict", "Kalman prediction of the live nodes", 2),
    (point_model.KalmanPointModel, "score", "gating and likelihoods", 2),
    (core.MHT, "_branch_lone", "clusters of one track per parent", 2),
    (core.MHT, "_branch", "clusters of the general path", 2),
    (core.MHT, "_k_best", "k best children (costs, listing, Murty)", 3),
    (core, "list_children", "listing by branch and bound", 4),
    (listing, "COMPILED_K_BEST", "compiled costs and listing (the C extension)", 4),
    (core, "k_best_children", "Murty's method", 4),
    (core.MHT, "_assemble", "children's hypotheses, normalising, pruning", 3),
    (listing, "COMPILED_ASSEMBLE_PLAIN", "children's hypotheses (the C extension)", 3),
    (core.MHT, "_fill_deferred", "Kalman updates and births of kept children", 2),
    (core.MHT, "_expire", "expiry of unseen tracks", 2),
    (person_tracks.PersonTracker, "update", "people layer (person tracks)", 1),
]
"""(owner, attribute, label, depth) of the parts timed; each is listed under the part of
the next lower depth above it."""


def run(path: Path, background: str) -> tuple[int, float, dict[str, float]]:
    """Scans, process CPU s of the whole loop and CPU s per part, one pass over ``path``."""
    spent: dict[str, float] = defaultdict(float)
    saved = [(owner, name, getattr(owner, name)) for owner, name, _, _ in PARTS]
    steps = pipeline("laserpeople", path, background)
    try:
        for owner, name, label, _ in PARTS:
            if getattr(owner, name) is not None:  # (None: the C extension is not built)
                setattr(owner, name, timed(spent, label, getattr(owner, name), time.process_time))
        t0 = time.process_time()
        scans = sum(1 for _ in steps)
        cpu = time.process_time() - t0
    finally:
        for owner, name, fn in saved:
            setattr(owner, name, fn)
    return scans, cpu, spent


def report(name: str, scans: int, cpu: float, spent: dict[str, float]) -> None:
    """Print one scene's table (see the module doc)."""
    ms = 1e3 * cpu / scans
    print(f"\n{name}: {scans} scans, {ms:.3f} ms CPU per scan ({scans / cpu:.0f} scans/s)")
    print(f"  {'part':<58s} {'ms/scan':>8s} {'share':>6s}")
    # (the parts of depth 0: leg detection both ways and the leg tracker)
    top = sum(spent[label] for _, _, label, depth in PARTS if depth == 0)
    for i, (_, _, label, depth) in enumerate(PARTS):
        v = spent[label]
        print(f"  {'  ' * depth + label:<58s} {1e3 * v / scans:8.3f} {100 * v / cpu:5.1f}%")
        children = _children(PARTS, i)
        if children:
            own = v - sum(spent[PARTS[c][2]] for c in children)
            pad = "  " * (depth + 1)
            print(
                f"  {pad + '(outside the parts below)':<58s} {1e3 * own / scans:8.3f} "
                f"{100 * own / cpu:5.1f}%"
            )
    other = cpu - top
    print(
        f"  {'point set, static world model, pipeline (the rest)':<58s} "
        f"{1e3 * other / scans:8.3f} {100 * other / cpu:5.1f}%"
    )


def _children(parts: list[tuple[Any, str, str, int]], i: int) -> list[int]:
    """Indices of the direct children of part ``i`` in ``parts``."""
    depth = parts[i][3]
    out = []
    for k in range(i + 1, len(parts)):
        if parts[k][3] <= depth:
            break
        if parts[k][3] == depth + 1:
            out.append(k)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    add_scene_arguments(ap, [4, 20])
    ap.add_argument("--profile", type=int, default=0, help="also the N top functions")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        paths = hall_paths(args.people, args.seconds, args.cache or Path(tmp))
        scenes = [(f"hall, {n} people", p) for n, p in zip(args.people, paths, strict=True)]
        bag = args.data / DEMO_BAG
        if not args.no_demo:
            if bag.exists():
                scenes.append(("real demo bag", bag))
            else:
                print(f"no demo bag at {bag}: left out (--data names the shared data)")
        for name, path in scenes:
            report(name, *run(path, args.background))
            if args.profile:
                prof = cProfile.Profile(time.process_time)
                steps = pipeline("laserpeople", path, args.background)
                prof.runcall(lambda s=steps: sum(1 for _ in s))
                pstats.Stats(prof).sort_stats("tottime").print_stats(args.profile)


if __name__ == "__main__":
    main()
