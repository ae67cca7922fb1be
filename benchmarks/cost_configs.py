"""CPU per scan of the leg MHT with several ``--config`` files against Stone Soup's GNN, in
one process on the tuning scenes (randomised 0-3, 30 s; narrow-corridor 1; crossing-3 1).

Each scene is prepared (simulated and leg-detected) once; GNN and every config then run
on it, twice each, and the faster run counts (process time per scan, leg detection
excluded). The first column of ours is the shipped defaults, then one per config file:

    PYTHONPATH=src python benchmarks/cost_configs.py A.toml B.toml
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from cost_vs_gnn import gnn_ms
from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.evaluation.suite import PreparedScene, SuiteScene, frames_for, prepare
from people_suite import make_factory


def ours_ms(prepared: PreparedScene, config: Path | None) -> float:
    """Process time per scan [ms] of the leg MHT read from ``config`` (None: defaults)."""
    tracker = make_factory("leg-mht", config, "auto")()
    frames = frames_for(prepared, frozenset(tracker.consumes))
    t0 = time.process_time()
    for frame in frames:
        tracker.update(frame)
    return 1e3 * (time.process_time() - t0) / max(len(frames), 1)


def main(argv: list[str]) -> None:
    configs: list[Path | None] = [None, *(Path(p) for p in argv)]
    detector = AdaBoostLegDetector.default(LegDetectorParams())
    scenes = [SuiteScene("randomised", "randomised", s, 30.0) for s in range(4)]
    scenes += [SuiteScene(n, n, 1) for n in ("narrow-corridor", "crossing-3")]
    print("scene: gnn | " + " ".join(str(c or "defaults") for c in configs))
    for scene in scenes:
        prepared = prepare(scene, detector)
        gnn = min(gnn_ms(prepared) for _ in range(2))
        row = [min(ours_ms(prepared, c) for _ in range(2)) for c in configs]
        cells = " ".join(f"{r:.2f} ({r / gnn:.2f}x)" for r in row)
        print(f"{scene.scenario} {scene.seed}: gnn {gnn:.2f} | {cells}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
