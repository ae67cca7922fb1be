"""CPU per scan of the default leg MHT against Stone Soup's GNN on the same scenes (issue 10).

Both trackers get the same prepared scenes (simulated, then the shipped AdaBoost detector):
ours as ``benchmarks/people_suite.py`` feeds it (people ``tracks``, re-identification, the
static world model ``auto`` learned inside the timed update), GNN as ``benchmarks/peers.py``
feeds it (legs paired into people inside the timed step). Process CPU time per scan, the
lowest of ``--rounds`` rounds per scene (the machine is shared: run the two trackers back
to back and compare ratios). Default scenes: the randomised tuning seeds 0-3 and
narrow-corridor / crossing-3 seed 1 (never the held-back seeds 100-119).

    PYTHONPATH=src .venv/bin/python benchmarks/cost_vs_gnn.py [--tracker ours|gnn|both]
        [--seeds 0-3] [--named-seeds 1] [--seconds 30] [--rounds 1]

``--other SRC`` times ours against another version of the code (its ``src/``) instead of
GNN, in one process (as ``bench_track_ab.py``): each version prepares the scenes and builds
its tracker, the two are updated alternately, scan by scan (the order within a pair
alternating between rounds), and the script prints each version's median and mean process
CPU per scan, their ratios, and the scans whose reported tracks differ.

    PYTHONPATH=src .venv/bin/python benchmarks/cost_vs_gnn.py --other /tmp/old/src
        [--seeds 2] [--named-seeds 1] [--rounds 3]
"""

from __future__ import annotations

import argparse
import importlib
import re
import shutil
import sys
import tempfile
import time
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.evaluation.suite import PreparedScene, SuiteScene, frames_for, prepare
from laserpeople.tracking.frames import in_frame, tracking_frame
from peers import StoneSoupParams, StoneSoupTracker, pair_legs
from people_suite import make_factory, parse_seeds


def ours_ms(prepared: PreparedScene) -> float:
    """CPU ms per scan of the default leg MHT with its static world model."""
    tracker = make_factory("leg-mht", None, "auto")()
    frames = frames_for(prepared, frozenset(tracker.consumes))
    t0 = time.process_time()
    for frame in frames:
        tracker.update(frame)
    return 1e3 * (time.process_time() - t0) / max(len(frames), 1)


def gnn_ms(prepared: PreparedScene) -> float:
    """CPU ms per scan of Stone Soup's GNN, legs paired into people as in peers.py."""
    tracker = StoneSoupTracker("gnn", StoneSoupParams())
    cpu = 0.0
    for dets in prepared.detections:
        t0 = time.process_time()
        d = in_frame(dets, tracking_frame(dets))
        tracker.step(pair_legs(d.positions), d.stamp)
        cpu += time.process_time() - t0
    return 1e3 * cpu / max(len(prepared.detections), 1)


OTHER = "laserpeople_ab"
"""Package name of the other version (``--other``)."""


def load_other(src: Path, into: Path) -> ModuleType:
    """The package ``src/laserpeople`` copied to ``into`` as ``laserpeople_ab``, its imports
    of itself renamed (not its file-format names such as ``laserpeople-leg-model``)."""
    target = into / OTHER
    shutil.copytree(src / "laserpeople", target)
    pattern = re.compile(r"\blaserpeople\b(?!-)")
    for path in target.rglob("*.py"):
        path.write_text(pattern.sub(OTHER, path.read_text()))
    sys.path.insert(0, str(into))
    return importlib.import_module(OTHER)


def ours_in(package: str, scene: Any) -> tuple[Any, list[Any]]:
    """The default leg MHT with its static world model ``auto`` (as ``make_factory``) and
    the frames of ``scene`` (a ``(family, scenario, seed, seconds)`` tuple), both made by
    ``package``."""
    suite = importlib.import_module(f"{package}.evaluation.suite")
    det = importlib.import_module(f"{package}.detection.detector")
    registry = importlib.import_module(f"{package}.tracking.registry")
    static = importlib.import_module(f"{package}.pipeline.static_people")
    prepared = suite.prepare(
        suite.SuiteScene(*scene), det.AdaBoostLegDetector.default(det.LegDetectorParams())
    )
    entry = registry.get("leg-mht")
    tracker = entry.factory(entry.params_cls())
    if static.uses_static_model(tracker):
        model = static.people_static_model("auto")
        tracker.use_static_model(model)
        if model is not None:
            tracker = static.StaticFed(tracker, model)
    return tracker, suite.frames_for(prepared, frozenset(tracker.consumes))


def _rows(tracks: Any) -> list[tuple[Any, ...]]:
    return [(t.track_id, t.kind, t.members, t.position.tobytes()) for t in tracks]


def against_other(scenes: list[Any], rounds: int) -> None:
    """Time this version against ``laserpeople_ab`` scan by scan (module docstring)."""
    print(f"{'scene':24s} {'this':>8s} {'other':>8s}  median ms/scan (CPU)  this/other")
    for scene in scenes:
        for r in range(rounds):
            this, this_frames = ours_in("laserpeople", scene)
            other, other_frames = ours_in(OTHER, scene)
            cpu: dict[str, list[float]] = {"this": [], "other": []}
            differ = 0
            for a, b in zip(this_frames, other_frames, strict=True):
                pair = [("this", this, a), ("other", other, b)]
                if r % 2:
                    pair.reverse()
                out = {}
                for name, tracker, frame in pair:
                    t0 = time.process_time()
                    out[name] = tracker.update(frame)
                    cpu[name].append(time.process_time() - t0)
                differ += _rows(out["this"]) != _rows(out["other"])
            med = {k: 1e3 * float(np.median(v)) for k, v in cpu.items()}
            mean = {k: 1e3 * float(np.mean(v)) for k, v in cpu.items()}
            label = f"{scene[1]} {scene[2]} r{r + 1}"
            print(
                f"{label:24s} {med['this']:8.3f} {med['other']:8.3f}  "
                f"{med['this'] / med['other']:.3f} (mean {mean['this']:.3f} / "
                f"{mean['other']:.3f} = {mean['this'] / mean['other']:.3f}); scans with "
                f"different tracks: {differ}",
                flush=True,
            )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--tracker", choices=("ours", "gnn", "both"), default="both")
    ap.add_argument("--seeds", default="0-3", help="randomised seeds (tuning: 0-49)")
    ap.add_argument("--named-seeds", default="1", help="seeds of narrow-corridor, crossing-3")
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--rounds", type=int, default=1)
    ap.add_argument("--other", type=Path, default=None, help="another version's src/ (A/B)")
    args = ap.parse_args()
    seeds = parse_seeds(args.seeds)
    if args.other is not None:
        ab: list[tuple[str, str, int, float | None]] = [
            ("randomised", "randomised", s, args.seconds) for s in seeds
        ]
        for name in ("narrow-corridor", "crossing-3"):
            ab += [(name, name, s, None) for s in parse_seeds(args.named_seeds)]
        with tempfile.TemporaryDirectory() as tmp:
            load_other(args.other, Path(tmp))
            against_other(ab, args.rounds)
        return
    scenes = [SuiteScene("randomised", "randomised", s, args.seconds) for s in seeds]
    for name in ("narrow-corridor", "crossing-3"):
        scenes += [SuiteScene(name, name, s) for s in parse_seeds(args.named_seeds)]
    detector = AdaBoostLegDetector.default(LegDetectorParams())
    prepared = [prepare(s, detector) for s in scenes]
    runs = {"ours": ours_ms, "gnn": gnn_ms}
    names = list(runs) if args.tracker == "both" else [args.tracker]
    print(f"{'scene':24s} " + " ".join(f"{n:>8s}" for n in names) + "  ms/scan (CPU)")
    for p in prepared:
        best = {n: min(runs[n](p) for _ in range(args.rounds)) for n in names}
        label = f"{p.scene.scenario} {p.scene.seed}"
        ratio = f"  ours/gnn {best['ours'] / best['gnn']:.1f}x" if len(names) == 2 else ""
        print(f"{label:24s} " + " ".join(f"{best[n]:8.2f}" for n in names) + ratio, flush=True)


if __name__ == "__main__":
    main()
