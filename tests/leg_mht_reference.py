"""The leg MHT's output on simulated scenes, as flat arrays, for the regression test that
keeps the leg tracker's results unchanged when the MHT core changes.

    PYTHONPATH=src python tests/leg_mht_reference.py   # rewrites tests/data/leg_mht_reference.npz

Only rewrite the reference when a change to the leg tracker's results is intended.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracking.legs import LegTrackerParams

REFERENCE = Path(__file__).parent / "data" / "leg_mht_reference.npz"
SCENES = (("demo", 10.0, 0), ("narrow-corridor", 20.0, 1))
KINDS = {"leg": 0, "person": 1}


def run_scene(
    name: str, seconds: float, seed: int, params: LegTrackerParams | None = None
) -> dict[str, NDArray[np.float64]]:
    """Track the scene's ground-truth leg detections; one row per reported track:
    (scan, kind, id, x, y, vx, vy, score, first member, hypotheses). ``params``: the
    recorded setting (people policy ``arras``) unless given."""
    from laserpeople.sim.scenarios import run_scenario
    from laserpeople.tracking import synthetic as syn
    from laserpeople.tracking.legs import LegMHTTracker

    result = run_scenario(name, seconds=seconds, seed=seed)
    dets = syn.detections_from_sim(result.scans, result.truth, clutter_probability=0.9)
    tracker = LegMHTTracker(params or LegTrackerParams(people_policy="arras"))  # as recorded
    rows = []
    for d in dets:
        out = tracker.update(d)
        for t in out:
            rows.append(
                (
                    d.scan_index,
                    KINDS[t.kind],
                    t.track_id,
                    *t.position,
                    *t.velocity,
                    t.score,
                    t.members[0] if t.members else -1,
                    tracker.n_hypotheses,
                )
            )
    return {f"{name}_{seed}": np.asarray(rows, dtype=np.float64).reshape(-1, 10)}


def compute() -> dict[str, NDArray[np.float64]]:
    """All scenes' rows."""
    out: dict[str, NDArray[np.float64]] = {}
    for name, seconds, seed in SCENES:
        out.update(run_scene(name, seconds, seed))
    return out


if __name__ == "__main__":
    REFERENCE.parent.mkdir(exist_ok=True)
    np.savez_compressed(REFERENCE, **compute())
    print(f"wrote {REFERENCE}")
