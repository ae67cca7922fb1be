"""The feet tracker (004 Sec. 2.1, ``track --tracker feet-pf``) on the randomised group
scenes (``random-groups``) whose one laser is at feet height: 004's adapted MOTP (eqs.
10-11), MOTA and recall per seed, and their means split by still or moving sensor and by
scanner resolution (fine: below 0.6 deg; coarse: 0.6-1 deg).

Each scene runs through the commands a user types (``simulate``, ``track``, ``evaluate
--json``), so the static world model is the one ``track --background`` chooses. Scenes at
torso height are skipped (``upper-body-pf`` is for them). **Seeds 100-119 are held back:
never tune on them**; tune on 0-19.

    PYTHONPATH=src .venv/bin/python benchmarks/feet_random.py [--seeds 0-19] [--seconds 10]
        [--config params.toml] [--preset paper] [--background auto] [--jobs 2]
        [--keep DIR] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from pathlib import Path

from groups_random import parse_seeds  # type: ignore[import-not-found]
from laserpeople.sim.scenarios import build_scene

COARSE_DEG = 0.6
"""Scanners this coarse or coarser count as coarse [deg]."""


def _cli() -> list[str]:
    return [sys.executable, "-m", "laserpeople.cli"]


def run_seed(seed: int, seconds: float, workdir: Path, extra: list[str]) -> dict[str, object]:
    """Simulate, track and score one scene; its notes and the scores."""
    npz = workdir / f"g{seed}.npz"
    csv = workdir / f"g{seed}.csv"
    simulate = ["simulate", "random-groups", "--seed", str(seed), "-s", f"{seconds:g}"]
    subprocess.run(
        [*_cli(), *simulate, "-o", str(npz)],
        check=True,
        capture_output=True,
    )
    track = subprocess.run(
        [*_cli(), "track", str(npz), "--tracker", "feet-pf", "-o", str(csv), *extra],
        check=True,
        capture_output=True,
        text=True,
    )
    ev = subprocess.run(
        [*_cli(), "evaluate", str(csv), "--truth", str(npz), "--json"],
        check=True,
        capture_output=True,
        text=True,
    )
    scores = json.loads(ev.stdout)
    model = [
        line for line in (track.stdout + track.stderr).splitlines() if "static world model:" in line
    ]
    return {
        "seed": seed,
        "motp_schenk": scores["motp_schenk"],
        "mota": scores["mota"],
        "recall": scores["recall"],
        "idf1": scores["idf1"],
        "model": model[0].strip() if model else "",
    }


def feet_scene_parser(description: str | None) -> argparse.ArgumentParser:
    """The options of the scripts that study feet-pf on the random-groups scenes at feet
    height: seeds, scene length, a config, where recordings and tracks are kept, jobs."""
    ap = argparse.ArgumentParser(
        description=description, formatter_class=argparse.RawTextHelpFormatter
    )
    ap.add_argument("--seeds", default="0-19", help="tune on 0-19; held back: 100-119")
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--config", default=None, help="TOML passed to track --config")
    ap.add_argument("--keep", default=None, help="recordings and tracks here (reused)")
    ap.add_argument("--jobs", type=int, default=1, help="scenes tracked in parallel")
    return ap


@contextmanager
def tracked_feet_scenes(args: argparse.Namespace) -> Iterator[dict[int, tuple[bool, Path]]]:
    """The random-groups scenes of ``args.seeds`` whose laser is at feet height, each
    simulated and tracked by feet-pf (reused from ``args.keep`` where there): seed ->
    (whether the robot moves, the path of ``g{seed}`` without suffix: ``.npz`` the
    recording, ``.csv`` the tracks). Without ``--keep`` the files go when the block ends."""
    extra = ["--config", args.config] if args.config else []
    scenes = {}
    for seed in parse_seeds(args.seeds):
        notes = build_scene("random-groups", seconds=args.seconds, seed=seed).notes
        if notes["scanner"]["level"] == "feet":
            scenes[seed] = bool(notes["moving_robot"])
    with tempfile.TemporaryDirectory() as tmp:
        workdir = Path(args.keep) if args.keep else Path(tmp)
        workdir.mkdir(parents=True, exist_ok=True)
        missing = [s for s in scenes if not (workdir / f"g{s}.csv").exists()]
        with ThreadPoolExecutor(max_workers=args.jobs) as pool:
            list(pool.map(lambda s: run_seed(s, args.seconds, workdir, extra), missing))
        yield {seed: (moving, workdir / f"g{seed}") for seed, moving in scenes.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seeds", default="0-19", help="tune on 0-19; held back: 100-119")
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--config", default=None, help="TOML passed to track --config")
    ap.add_argument("--preset", default=None, help="passed to track --preset")
    ap.add_argument("--background", default=None, help="passed to track --background")
    ap.add_argument("--jobs", type=int, default=1, help="scenes run in parallel")
    ap.add_argument("--keep", default=None, help="keep the recordings and tracks here")
    ap.add_argument("--json", default=None, help="write the per-seed rows here")
    args = ap.parse_args()
    extra: list[str] = []
    for flag in ("config", "preset", "background"):
        value = getattr(args, flag)
        if value is not None:
            extra += [f"--{flag}", value]
    scenes = {}
    for seed in parse_seeds(args.seeds):
        notes = build_scene("random-groups", seconds=args.seconds, seed=seed).notes
        if notes["scanner"]["level"] == "feet":
            scenes[seed] = notes
    os.environ.setdefault("PYTHONPATH", str(Path(__file__).resolve().parents[1] / "src"))
    with tempfile.TemporaryDirectory() as tmp:
        workdir = Path(args.keep) if args.keep else Path(tmp)
        workdir.mkdir(parents=True, exist_ok=True)
        with ThreadPoolExecutor(max_workers=args.jobs) as pool:
            jobs = {s: pool.submit(run_seed, s, args.seconds, workdir, extra) for s in scenes}
            rows = []
            for seed, job in jobs.items():
                row = job.result()
                notes = scenes[seed]
                row["resolution_deg"] = notes["scanner"]["resolution_deg"]
                row["rate_hz"] = notes["scanner"]["rate_hz"]
                row["moving"] = bool(notes["moving_robot"])
                rows.append(row)
                print(
                    f"seed {seed} ({row['resolution_deg']:.2f} deg, {row['rate_hz']:g} Hz, "
                    f"{'moving' if row['moving'] else 'still'}): adapted MOTP "
                    f"{row['motp_schenk']:.3f}, MOTA {row['mota']:.3f}, recall "
                    f"{row['recall']:.3f}, IDF1 {row['idf1']:.3f}; {row['model']}",
                    flush=True,
                )
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))

    def mean(key: str, group: list[dict[str, object]]) -> float:
        values = [float(r[key]) for r in group]  # type: ignore[arg-type]
        return sum(values) / len(values) if values else math.nan

    groups = {
        "all": rows,
        "still": [r for r in rows if not r["moving"]],
        "moving": [r for r in rows if r["moving"]],
        f"fine (< {COARSE_DEG} deg)": [r for r in rows if r["resolution_deg"] < COARSE_DEG],  # type: ignore[operator]
        f"coarse (>= {COARSE_DEG} deg)": [r for r in rows if r["resolution_deg"] >= COARSE_DEG],  # type: ignore[operator]
    }
    print(f"\nfeet-pf on random-groups at feet height, seeds {args.seeds}, {args.seconds:g} s each")
    print("| scenes | runs | adapted MOTP | MOTA | recall | IDF1 |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, group in groups.items():
        if group:
            print(
                f"| {name} | {len(group)} | {mean('motp_schenk', group):.3f} | "
                f"{mean('mota', group):.3f} | {mean('recall', group):.3f} | "
                f"{mean('idf1', group):.3f} |"
            )


if __name__ == "__main__":
    main()
