"""CPU per scan of the default leg MHT against Stone Soup's GNN on the same scenes (issue 10).

Both trackers get the same prepared scenes (simulated, then the shipped AdaBoost detector):
ours as ``benchmarks/people_suite.py`` feeds it (people ``tracks``, re-identification, the
static world model ``auto`` learned inside the timed update), GNN as ``benchmarks/peers.py``
feeds it (legs paired into people inside the timed step). Process CPU time per scan, the
lowest of ``--rounds`` rounds per scene (the machine is shared: run the two trackers back
to back and compare ratios). Default scenes: the randomised tuning seeds 0-3 and
narrow-corridor / crossing-3 seed 1 (never the held-back seeds 100-119).

    PYTHONPATH=src .venv/bin/python benchmarks/cost_vs_gnn.py [--tracker ours|gnn|both]
        [--seeds 0-3] [--named-seeds 1] [--seconds 30] [--rounds 1] [--config A.toml ...]

``--config`` (repeatable) times ours with each TOML too, in the same process, a column each
after the defaults (e.g. other ``[leg_tracker.mht]`` settings).

For an A/B of ours against another version of the code (its ``src/``) on these scenes,
scan by scan in one process, use ``benchmarks/bench_track_ab.py --other SRC --scenes ...``.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.evaluation.suite import PreparedScene, SuiteScene, frames_for, prepare
from laserpeople.tracking.frames import in_frame, tracking_frame
from peers import StoneSoupParams, StoneSoupTracker, pair_legs
from people_suite import make_factory, parse_seeds


def ours_ms(prepared: PreparedScene, config: Path | None = None) -> float:
    """CPU ms per scan of the leg MHT with its static world model (``config``: a TOML whose
    sections it reads; None: the defaults)."""
    tracker = make_factory("leg-mht", config, "auto")()
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--tracker", choices=("ours", "gnn", "both"), default="both")
    ap.add_argument("--seeds", default="0-3", help="randomised seeds (tuning: 0-49)")
    ap.add_argument("--named-seeds", default="1", help="seeds of narrow-corridor, crossing-3")
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--rounds", type=int, default=1)
    ap.add_argument(
        "--config",
        type=Path,
        action="append",
        default=[],
        help="also time ours with this TOML (repeatable; a column each after the defaults)",
    )
    args = ap.parse_args()
    seeds = parse_seeds(args.seeds)
    scenes = [SuiteScene("randomised", "randomised", s, args.seconds) for s in seeds]
    for name in ("narrow-corridor", "crossing-3"):
        scenes += [SuiteScene(name, name, s) for s in parse_seeds(args.named_seeds)]
    detector = AdaBoostLegDetector.default(LegDetectorParams())
    prepared = [prepare(s, detector) for s in scenes]
    runs: dict[str, Callable[[PreparedScene], float]] = {}
    if args.tracker != "gnn":
        runs["ours"] = ours_ms
        runs.update({c.stem: partial(ours_ms, config=c) for c in args.config})
    if args.tracker != "ours":
        runs["gnn"] = gnn_ms
    print(f"{'scene':24s} " + " ".join(f"{n:>8s}" for n in runs) + "  ms/scan (CPU)")
    for p in prepared:
        best = {n: min(run(p) for _ in range(args.rounds)) for n, run in runs.items()}
        label = f"{p.scene.scenario} {p.scene.seed}"
        ratios = ""
        if "gnn" in best and len(best) > 1:
            ratios = "  " + " ".join(
                f"{n}/gnn {ms / best['gnn']:.2f}x" for n, ms in best.items() if n != "gnn"
            )
        print(f"{label:24s} " + " ".join(f"{ms:8.2f}" for ms in best.values()) + ratios, flush=True)


if __name__ == "__main__":
    main()
