"""``laserpeople track`` as a whole process on real recordings, for one or two source trees
side by side: what a user's run costs (interpreter start, imports, reading, detection,
tracking, the static world model, CSV).

Per pass, each tree runs ``laserpeople track BAG -o CSV`` in a fresh interpreter (who runs
first alternates, so both see the same load); printed per recording: the median CPU time
(user + system of the child) over the passes, scans per CPU second, the ratio before/after,
and the two trees' CSVs compared row by row (same scan, id and kind; the largest position
difference). The median start-up of a bare ``python -c pass`` and of ``import`` of what
``track`` needs at its first scan are printed beside it, so the fixed cost of a run is seen.

    PYTHONPATH=src .venv/bin/python benchmarks/bench_track_process.py [--before OLD/src]
        [--bags demo corridor] [--passes 5]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_scaling import THIS_SRC, _child_cpu, _env, csv_difference, run_track

BAGS = {
    "demo": "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag",
    "corridor": "mir/rosbags/corridor/corridor.bag",
}
"""Recordings of the shared data (``--data``) by name."""

IMPORTS = (
    "import laserpeople.cli.track, laserpeople.pipeline, laserpeople.tracking.registry, "
    "laserpeople.detection.detector, laserpeople.io.rosbag, laserpeople.background.occupancy"
)
"""The modules ``track`` imports before its first scan."""


def cpu_of(src: Path, code: str) -> float:
    """CPU seconds (user + system) of a fresh interpreter running ``code`` with ``src``."""
    c0 = _child_cpu()
    subprocess.run([sys.executable, "-c", code], env=_env(src), check=True)
    return _child_cpu() - c0


def scans_in(bag: Path) -> int:
    """The scans of the first laser topic of ``bag``."""
    from laserpeople.io import open_recording

    rec = open_recording(bag)
    try:
        return sum(1 for _ in rec.scans())
    finally:
        rec.close()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--before", type=Path, help="the other source tree (its src/)")
    ap.add_argument("--bags", nargs="+", default=["demo"], choices=list(BAGS))
    ap.add_argument("--passes", type=int, default=5)
    ap.add_argument(
        "--data",
        type=Path,
        default=Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "/work/shared/data")),
    )
    args = ap.parse_args()
    trees = {"after": THIS_SRC}
    if args.before is not None:
        trees = {"before": args.before, "after": THIS_SRC}
    bags = {name: args.data / BAGS[name] for name in args.bags}
    missing = [str(p) for p in bags.values() if not p.exists()]
    if missing:
        raise SystemExit(f"no recording at {', '.join(missing)} (--data names the shared data)")
    cpu: dict[tuple[str, str], list[float]] = {(b, t): [] for b in bags for t in trees}
    start: dict[str, list[float]] = {t: [] for t in ["python -c pass", *trees]}
    with tempfile.TemporaryDirectory() as tmp:
        for p in range(args.passes):
            order = list(trees.items())
            if p % 2:
                order.reverse()
            start["python -c pass"].append(cpu_of(THIS_SRC, "pass"))
            for tree, src in order:
                start[tree].append(cpu_of(src, IMPORTS))
            for bag_name, bag in bags.items():
                for tree, src in order:
                    out = Path(tmp) / f"{bag_name}-{tree}.csv"
                    cpu[(bag_name, tree)].append(run_track(src, bag, out))
            print(f"pass {p + 1} of {args.passes} done", flush=True)
        print(f"\nmedian CPU (user + system) of {args.passes} passes, trees alternating")
        for name, values in start.items():
            what = "bare interpreter" if name == "python -c pass" else f"imports of track, {name}"
            print(f"  {what:28s} {statistics.median(values):6.3f} s")
        for bag_name, bag in bags.items():
            scans = scans_in(bag)
            print(f"`laserpeople track` on {bag_name} ({scans} scans), whole process:")
            medians = {t: statistics.median(cpu[(bag_name, t)]) for t in trees}
            for tree, m in medians.items():
                runs = ", ".join(f"{v:.2f}" for v in cpu[(bag_name, tree)])
                print(f"  {tree:6s} {m:6.2f} s CPU -> {scans / m:5.0f} scans/s  (runs: {runs})")
            if len(trees) == 2:
                print(f"  before/after {medians['before'] / medians['after']:.2f}x")
                a, b = (Path(tmp) / f"{bag_name}-{t}.csv" for t in ("before", "after"))
                print(f"  CSVs: {csv_difference(a, b)}")


if __name__ == "__main__":
    main()
