"""What the randomised group scenes at feet height (``random-groups``, as
``feet_random.py``) allow: 004's adapted MOTP (eqs. 10-11) of oracles that know where the
people are, and of the other trackers, on the same recordings and scored the same way
(``evaluate --json``, ``motp_schenk``).

Oracles (a track exactly on the person's true position, with the person's id, and nothing
else; written as a tracks CSV and scored by ``evaluate``):

- *shown*: in every scan in which the laser shows the person: at least one laser return
  within ``--shown`` 0.15 m of the centre of one of their legs (legs have radii of
  0.05-0.09 m);
- *coasting 1 s*: also up to ``--coast`` 1 s after the person was last shown (a tracker
  that keeps a track through short occlusions, as feet-pf's ``miss_time`` does, but knows
  where the person went);
- *from first shown*: from the first scan in which the person is shown to the end (a
  tracker that never loses anyone once seen).

Trackers (``--trackers``): any registered tracker through ``track --tracker T`` (``default``:
``track`` without ``--tracker``), and ``stonesoup-gnn`` (``benchmarks/peers.py``'s Stone
Soup GNN on leg pairs of the shipped AdaBoost detector; needs the ``peers`` extra), and
``feet-pf`` with one input from the truth (``oracle-foreground``, ``oracle-foreground-added``,
``oracle-foreground-cut``, ``oracle-births``; ``feet_oracle_inputs.py``): which part limits.

    PYTHONPATH=src python benchmarks/feet_ceiling.py [--seeds 100-119] [--seconds 10]
        [--trackers feet-pf default csa stonesoup-gnn] [--keep DIR] [--json out.json]

**Seeds 100-119 are held back**: measure there, never tune there.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

sys.path.insert(0, str(Path(__file__).resolve().parent))

from feet_oracle_inputs import MODES, track_with_oracle  # type: ignore[import-not-found]
from feet_random import COARSE_DEG  # type: ignore[import-not-found]
from groups_random import parse_seeds  # type: ignore[import-not-found]
from laserpeople.io import open_recording
from laserpeople.io.tracks_csv import HEADER
from laserpeople.sim.scenarios import build_scene

SHOWN = 0.15
"""A laser return this close to a leg centre shows the person [m]."""
COAST = 1.0
"""The coasting oracle keeps a person's track this long after they were last shown [s]."""
ORACLES = ("shown", "coasting", "from first shown")
STILL_ROW = (0, 0, 0.01, 0, 0.01, 1, "")
"""An oracle track row's velocity, covariance [m^2], size and labels columns."""


def _cli() -> list[str]:
    return [sys.executable, "-m", "laserpeople.cli"]


def shown_people(
    points: NDArray[np.float64], legs: NDArray[np.float64], reach: float = SHOWN
) -> NDArray[np.bool_]:
    """Which people (P,) the returns ``points`` (N, 2) show: at least one within ``reach``
    [m] of either leg centre of ``legs`` (P, 2, 2); all in one frame."""
    if len(points) == 0 or len(legs) == 0:
        return np.zeros(len(legs), dtype=bool)
    d = np.linalg.norm(points[None, None, :, :] - legs[:, :, None, :], axis=-1)
    return np.asarray((d <= reach).any(axis=(1, 2)), dtype=bool)


def oracle_rows(
    shown: list[tuple[int, float, NDArray[np.int64], NDArray[np.float64], NDArray[np.bool_]]],
    oracle: str,
    coast: float = COAST,
) -> list[tuple[Any, ...]]:
    """Tracks CSV rows of ``oracle`` from per scan (scan index, stamp, person ids, true
    positions (P, 2), shown mask (P,))."""
    last: dict[int, float] = {}
    rows: list[tuple[Any, ...]] = []
    for scan, stamp, ids, xy, mask in shown:
        for pid, p, s in zip(ids.tolist(), xy, mask.tolist(), strict=True):
            if s:
                last[pid] = stamp
            seen = last.get(pid)
            keep = (
                s
                if oracle == "shown"
                else seen is not None and (oracle != "coasting" or stamp - seen <= coast)
            )
            if keep:
                xy_text = (f"{p[0]:.4f}", f"{p[1]:.4f}")
                rows.append((scan, f"{stamp:.6f}", pid, "person", *xy_text, *STILL_ROW))
    return rows


def scene_shown(
    npz: Path,
) -> list[tuple[int, float, NDArray[np.int64], NDArray[np.float64], NDArray[np.bool_]]]:
    """Per scan of the first sensor: index, stamp, person ids, true positions, shown mask."""
    with open_recording(npz) as rec:
        truth = {t.scan_index: t for t in rec.truth()}
        first = None
        out = []
        for scan in rec.scans():
            first = first or scan.sensor
            if scan.sensor != first or scan.index not in truth:
                continue
            t = truth[scan.index]
            pts, _ = scan.valid_points("world" if scan.pose is not None else "sensor")
            out.append(
                (
                    scan.index,
                    scan.stamp,
                    t.person_ids,
                    t.positions,
                    shown_people(np.asarray(pts, dtype=np.float64), t.leg_positions),
                )
            )
    return out


def evaluate(tracks: Path, npz: Path) -> dict[str, float]:
    """``evaluate --json`` of a tracks CSV against the recording's truth; all 0 when the
    CSV holds no person track (``evaluate`` refuses to score it)."""
    ev = subprocess.run(
        [*_cli(), "evaluate", str(tracks), "--truth", str(npz), "--json"],
        capture_output=True,
        text=True,
    )
    if ev.returncode != 0:
        if "no person tracks" in ev.stderr + ev.stdout:
            return dict.fromkeys(("motp_schenk", "mota", "recall", "idf1"), 0.0)
        raise RuntimeError(f"evaluate {tracks}: {ev.stderr.strip()}")
    scores = json.loads(ev.stdout)
    return {k: float(scores[k]) for k in ("motp_schenk", "mota", "recall", "idf1")}


def run_tracker(name: str, seed: int, npz: Path, workdir: Path, seconds: float) -> Path:
    """Track the recording with ``name``; the tracks CSV."""
    out = workdir / f"g{seed}-{name}.csv"
    if name == "stonesoup-gnn":
        from laserpeople.config import load_config
        from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
        from laserpeople.evaluation.suite import SuiteScene, prepare
        from peers import StoneSoupParams, peer_tracks  # type: ignore[import-not-found]

        detector = AdaBoostLegDetector.default(load_config(LegDetectorParams, None))
        prepared = prepare(SuiteScene("feet", "random-groups", seed, seconds), detector)
        peer_tracks(prepared, "gnn", StoneSoupParams(), workdir)
        (workdir / f"random-groups-{seed}-gnn.csv").replace(out)
        return out
    if name in MODES:
        return track_with_oracle(npz, out, name)
    tracker = [] if name == "default" else ["--tracker", name]
    subprocess.run(
        [*_cli(), "track", str(npz), *tracker, "-o", str(out)], check=True, capture_output=True
    )
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seeds", default="100-119", help="held back: 100-119; tuning: 0-19")
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--trackers", nargs="*", default=["feet-pf", "default", "csa"])
    ap.add_argument("--shown", type=float, default=SHOWN, help="[m]")
    ap.add_argument("--coast", type=float, default=COAST, help="[s]")
    ap.add_argument("--keep", default=None, help="recordings and tracks here (reused)")
    ap.add_argument("--json", default=None, help="write the per-seed rows here")
    args = ap.parse_args()
    columns = [*ORACLES, *args.trackers]
    rows: list[dict[str, Any]] = []
    with tempfile.TemporaryDirectory() as tmp:
        workdir = Path(args.keep) if args.keep else Path(tmp)
        workdir.mkdir(parents=True, exist_ok=True)
        for seed in parse_seeds(args.seeds):
            notes = build_scene("random-groups", seconds=args.seconds, seed=seed).notes
            if notes["scanner"]["level"] != "feet":
                continue
            npz = workdir / f"g{seed}.npz"
            if not npz.exists():
                sim = ["simulate", "random-groups", "--seed", str(seed), "-s", f"{args.seconds:g}"]
                subprocess.run([*_cli(), *sim, "-o", str(npz)], check=True, capture_output=True)
            shown = scene_shown(npz)
            row: dict[str, Any] = {
                "seed": seed,
                "moving": bool(notes["moving_robot"]),
                "resolution_deg": notes["scanner"]["resolution_deg"],
                "person_scans": int(sum(len(s[2]) for s in shown)),
                "shown_share": float(
                    sum(int(s[4].sum()) for s in shown) / max(1, sum(len(s[2]) for s in shown))
                ),
            }
            for oracle in ORACLES:
                path = workdir / f"g{seed}-oracle-{oracle.replace(' ', '_')}.csv"
                with open(path, "w", newline="", encoding="utf-8") as fh:
                    w = csv.writer(fh, lineterminator="\n")
                    w.writerow(HEADER)
                    w.writerows(oracle_rows(shown, oracle, args.coast))
                row[oracle] = evaluate(path, npz)
            for name in args.trackers:
                row[name] = evaluate(run_tracker(name, seed, npz, workdir, args.seconds), npz)
            rows.append(row)
            print(
                f"seed {seed} ({'moving' if row['moving'] else 'still'}, "
                f"{row['resolution_deg']:.2f} deg): shown {row['shown_share']:.2f}; "
                + ", ".join(f"{c} {row[c]['motp_schenk']:.3f}" for c in columns),
                flush=True,
            )
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    groups = {
        "all": rows,
        "still": [r for r in rows if not r["moving"]],
        "moving": [r for r in rows if r["moving"]],
        f"< {COARSE_DEG} deg": [r for r in rows if r["resolution_deg"] < COARSE_DEG],
        f">= {COARSE_DEG} deg": [r for r in rows if r["resolution_deg"] >= COARSE_DEG],
    }
    print(f"\nadapted MOTP (eqs. 10-11) on random-groups at feet height, seeds {args.seeds}")
    print("| scenes | shown | " + " | ".join(columns) + " |")
    print("|---|---:|" + "---:|" * len(columns))
    for name, group in groups.items():
        if not group:
            continue
        means = [np.mean([r[c]["motp_schenk"] for r in group]) for c in columns]
        share = np.mean([r["shown_share"] for r in group])
        print(
            f"| {name} ({len(group)}) | {share:.2f} | "
            + " | ".join("nan" if math.isnan(m) else f"{m:.3f}" for m in means)
            + " |"
        )


if __name__ == "__main__":
    main()
