"""The tracks CSVs that `laserpeople track` wrote before the pipeline (commit 943d2b9) on
the simulated demo scene and on the real demo bag, kept as the regression reference of
tests/test_pipeline.py (compared with tests/tolerant.py, so that it holds on every CPU).

    PYTHONPATH=src LASERPEOPLE_SHARED_DATA=/work/shared/data \
        python tests/pipeline_reference.py   # rewrites tests/data/pipeline_*.csv.gz

Only rewrite the references when a change to the leg tracker's results is intended (the
bag's is written only when the shared data are there).
"""

from __future__ import annotations

import gzip
import os
import sys
import tempfile
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

DATA = Path(__file__).parent / "data"
DEMO_SCENE = DATA / "pipeline_demo_scene_tracks.csv.gz"
"""The simulated demo (seed 0), all 161 scans, through `track` with ``--people-policy
arras`` as a user runs it."""
DEMO_BAG = "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag"
REAL_BAG = DATA / "pipeline_demo_bag_tracks.csv.gz"
"""The real demo bag's first :data:`BAG_SCANS` scans (people policy ``arras``)."""
BAG_SCANS = 200
COLUMNS = 13
"""The columns compared: those of the CSV before the pipeline added ``topic``."""
KINDS = {"leg": 0, "person": 1, "group": 2}


def demo_scene_csv(workdir: Path) -> Path:
    """Run `laserpeople track` on the simulated demo as a user does; the CSV's path."""
    from typer.testing import CliRunner

    from laserpeople.cli import app
    from laserpeople.sim import run_scenario

    rec = workdir / "demo.npz"
    run_scenario("demo", seed=0).write(rec)
    out = workdir / "demo-tracks.csv"
    args = ["--quiet", "track", str(rec), "-o", str(out), "--people-policy", "arras"]
    result = CliRunner().invoke(app, args)
    if result.exit_code != 0:
        raise RuntimeError(result.output)
    return out


def demo_bag_csv(root: Path, workdir: Path) -> Path:
    """Track the real demo bag's first :data:`BAG_SCANS` scans; the CSV's path."""
    from laserpeople.pipeline import build
    from laserpeople.tracking.legs import LegTrackerParams

    out = workdir / "bag-tracks.csv"
    arras = LegTrackerParams(people_policy="arras")  # the policy the reference run used
    build(root / DEMO_BAG, params=arras, outputs=[out], max_frames=BAG_SCANS).run()
    return out


def old_format(text: str, max_scan: int) -> str:
    """The CSV's first :data:`COLUMNS` columns, rows of scans below ``max_scan``."""
    lines = [ln for ln in text.splitlines() if ln and not ln.startswith("#")]
    keep = [",".join(lines[0].split(",")[:COLUMNS])]
    keep += [",".join(r.split(",")[:COLUMNS]) for r in lines[1:] if int(r.split(",")[0]) < max_scan]
    return "\n".join(keep) + "\n"


def read_reference(path: Path) -> str:
    """A reference CSV's text."""
    return gzip.decompress(path.read_bytes()).decode()


def track_rows(text: str) -> dict[str, NDArray]:  # type: ignore[type-arg]
    """A tracks CSV's rows as arrays: ``keys`` (N, 2) scan and kind code, ``ids`` (N,)
    and ``values`` (N, 6) x, y, vx, vy (as written, 4 decimals) and the logarithms of
    cov_xx and cov_yy (written with 6 significant digits)."""
    lines = [ln.split(",") for ln in text.splitlines()[1:] if ln]
    if not lines:
        empty = np.empty((0, 6))
        return {"keys": np.empty((0, 2)), "ids": np.empty(0), "values": empty}
    keys = np.array([[float(r[0]), KINDS[r[3]]] for r in lines])
    ids = np.array([r[2] for r in lines])
    raw = np.array([[float(v) for v in (*r[4:9], r[10])] for r in lines])
    values = np.column_stack([raw[:, :4], np.log(np.maximum(raw[:, 4:], 1e-300))])
    return {"keys": keys, "ids": ids, "values": values}


def _write(path: Path, text: str) -> None:
    path.write_bytes(gzip.compress(text.encode(), mtime=0))
    print(f"wrote {path}")


if __name__ == "__main__":
    DATA.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        _write(DEMO_SCENE, old_format(demo_scene_csv(Path(tmp)).read_text(), 10**9))
        root = Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "/work/shared/data"))
        if (root / DEMO_BAG).is_file():
            _write(REAL_BAG, old_format(demo_bag_csv(root, Path(tmp)).read_text(), BAG_SCANS))
        else:
            print(f"demo bag not found under {root}: its reference not written", file=sys.stderr)
