"""``laserpeople track`` as a whole process on real recordings, for one or two source trees
side by side: what a user's run costs (interpreter start, imports, reading, detection,
tracking, the static world model, CSV).

Per pass, each tree runs ``laserpeople track BAG -o CSV`` in a fresh interpreter twice, in
the order of :func:`pass_order` (ABBA, then BAAB, ...: each pass balanced on its own, so an
odd number of passes favours neither tree); printed per recording: the median CPU time
(user + system of the child) over all runs, scans per CPU second, the median over the
passes of each pass's ratio before/after (its two runs summed per tree), and the two trees'
CSVs compared line by line and row by row (same scan, id and kind; the largest position
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
from bench_scaling import THIS_SRC, _child_cpu, _env, csv_difference, goes_first, run_track

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


def pass_order(p: int, trees: list[str]) -> list[str]:
    """The runs of pass ``p`` (0, 1, ...): with two trees A, B each twice, A B B A or
    B A A B by the Thue-Morse sequence over the runs (:func:`bench_scaling.goes_first`), so
    within every pass each tree runs once first and once last of a pair and both have the
    same mean position (a drift of the load during the pass cancels); with one tree, once."""
    if len(trees) == 1:
        return list(trees)
    return [trees[goes_first(4 * p + k)] for k in range(4)]


def lines_differing(a: Path, b: Path) -> int:
    """Lines that differ between two text files (position by position, plus the extra
    lines of the longer one)."""
    la = a.read_text(encoding="utf-8").splitlines()
    lb = b.read_text(encoding="utf-8").splitlines()
    return sum(x != y for x, y in zip(la, lb, strict=False)) + abs(len(la) - len(lb))


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
    ratios: dict[str, list[float]] = {b: [] for b in bags}
    start: dict[str, list[float]] = {t: [] for t in ["python -c pass", *trees]}
    with tempfile.TemporaryDirectory() as tmp:
        for p in range(args.passes):
            order = pass_order(p, list(trees))
            start["python -c pass"].append(cpu_of(THIS_SRC, "pass"))
            for tree in order:
                start[tree].append(cpu_of(trees[tree], IMPORTS))
            for bag_name, bag in bags.items():
                this: dict[str, float] = dict.fromkeys(trees, 0.0)
                for tree in order:
                    out = Path(tmp) / f"{bag_name}-{tree}.csv"
                    took = run_track(trees[tree], bag, out)
                    cpu[(bag_name, tree)].append(took)
                    this[tree] += took
                if len(trees) == 2:
                    ratios[bag_name].append(this["before"] / this["after"])
            print(f"pass {p + 1} of {args.passes} done", flush=True)
        how = "each tree twice per pass, ABBA / BAAB" if len(trees) == 2 else "one run per pass"
        print(f"\nmedian CPU (user + system) of {args.passes} passes, {how}")
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
                r = ratios[bag_name]
                of_medians = medians["before"] / medians["after"]
                print(
                    f"  before/after {statistics.median(r):.3f}x, median of the passes' ratios "
                    f"({min(r):.3f}-{max(r):.3f}); of the medians {of_medians:.3f}x"
                )
                a, b = (Path(tmp) / f"{bag_name}-{t}.csv" for t in ("before", "after"))
                print(f"  CSVs: {lines_differing(a, b)} lines differ; {csv_difference(a, b)}")


if __name__ == "__main__":
    main()
