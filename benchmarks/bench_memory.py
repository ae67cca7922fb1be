"""Memory of ``laserpeople track`` as a whole process: peak resident set and the peak of
Python's own allocations, on the real demo bag and on a long simulated run, and whether
memory grows with the scans (a per-scan history kept for the whole run).

Each run is ``laserpeople track REC -o CSV`` in a fresh interpreter (as a user runs it),
twice per tree and recording:

- **plain**: the peak resident set size (``VmHWM``: interpreter, imports, numpy, the
  tracker, and the pages of a memory-mapped recording read so far) and the anonymous
  resident set (``RssAnon``: without the recording's mapped pages, which are the file's and
  which the system reclaims) sampled every ``--every`` seconds of the run's CPU;
- **traced**: the same run under :mod:`tracemalloc` (about twice the CPU): the peak and the
  current size of the memory Python allocates (numpy arrays included; not the interpreter's
  code or the recording's mapped pages), sampled the same way, and the source lines whose
  live allocations grew most between the first sample after a tenth of the run and the last
  one (what a growth would be kept by).

The long run is the hall of ``bench_scaling.py`` (16 m x 12 m, one Hokuyo UTM-30LX, 1081
beams at 40 Hz) with ``--people`` walkers for ``--minutes`` (default 20 people, 10 minutes:
24,000 scans), simulated once and written to a recording (``--cache`` keeps it). Growth is
the traced current size (without ``--trace-long``, a long run's anonymous resident set) at
nine tenths of the run minus at half of it, per 10,000 scans: about zero when nothing is
kept per scan. A recording of more than 5,000 scans is traced only with ``--trace-long``.
With ``--before OLD/src`` both trees run, alternating which goes first.

    PYTHONPATH=src .venv/bin/python benchmarks/bench_memory.py [--before OLD/src]
        [--minutes 10] [--people 20] [--no-demo] [--no-long] [--cache DIR] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_scaling import DEMO_BAG, THIS_SRC, _env, hall_recording

CHILD = r"""
import atexit, json, os, resource, sys, threading, time, tracemalloc
OUT, TRACE = os.environ["LP_MEM_OUT"], os.environ["LP_MEM_TRACE"] == "1"
EVERY, FIRST = float(os.environ["LP_MEM_EVERY"]), float(os.environ["LP_MEM_FIRST"])
if TRACE:
    tracemalloc.start(1)
samples, snaps = [], {}

def status(key):
    # a line of /proc/self/status in bytes (0 where there is none)
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith(key + ":"):
                return int(line.split()[1]) * 1024
    return 0

def rss():
    # anonymous memory only: the pages of a memory-mapped recording (npz) are the file's
    return status("RssAnon")

def sample():
    due = EVERY
    while True:
        time.sleep(0.05)
        cpu = time.process_time()
        if cpu < due:
            continue
        due = cpu + EVERY
        cur = tracemalloc.get_traced_memory()[0] if TRACE else 0
        samples.append((cpu, rss(), cur))
        with open(OUT + ".samples", "a") as fh:  # (as it goes: readable before the end)
            fh.write(json.dumps(samples[-1]) + "\n")
        if TRACE and cpu >= FIRST:
            snap = tracemalloc.take_snapshot().filter_traces(
                [tracemalloc.Filter(False, tracemalloc.__file__)])
            snaps.setdefault("first", snap)
            snaps["last"] = snap

def done():
    top = []
    if TRACE and "last" in snaps:
        for st in snaps["last"].compare_to(snaps["first"], "lineno")[:8]:
            top.append((str(st.traceback), st.size_diff, st.count_diff))
    peak = tracemalloc.get_traced_memory()[1] if TRACE else 0
    # this process's own peak (VmHWM): ru_maxrss keeps the parent's resident set at the fork
    # that started it (1.4 GB after simulating the long recording in the parent)
    maxrss = status("VmHWM") or resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    with open(OUT, "w") as fh:
        json.dump({"maxrss": maxrss, "traced_peak": peak, "samples": samples,
                   "cpu": time.process_time(), "growth_lines": top}, fh)

atexit.register(done)
threading.Thread(target=sample, daemon=True).start()
sys.argv[0] = "laserpeople"
from laserpeople.cli import main
main()
"""
"""The child: ``laserpeople track`` with a sampling thread and, traced, :mod:`tracemalloc`."""

MB = 1024.0 * 1024.0


def run(
    src: Path, rec: Path, out: Path, *, trace: bool, every: float, first: float = 0.0
) -> dict[str, Any]:
    """One ``track rec -o out`` importing ``src``; the child's measurements (the first
    snapshot of the traced allocations taken at ``first`` s of its CPU or after)."""
    stats = out.with_suffix(".json")
    out.unlink(missing_ok=True)
    env = _env(src) | {
        "LP_MEM_OUT": str(stats),
        "LP_MEM_TRACE": "1" if trace else "0",
        "LP_MEM_EVERY": str(every),
        "LP_MEM_FIRST": str(first),
    }
    done = subprocess.run(
        [sys.executable, "-c", CHILD, "track", str(rec), "-o", str(out)],
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    if done.returncode != 0:
        raise SystemExit(f"track {rec} with {src} failed:\n{done.stderr}")
    got: dict[str, Any] = json.loads(stats.read_text())
    return got


def at(samples: list[list[float]], fraction: float, column: int) -> float:
    """The sampled value (column 1: resident set, 2: traced) nearest ``fraction`` of the
    run's CPU [MB]."""
    if not samples:
        return float("nan")
    end = samples[-1][0]
    best = min(samples, key=lambda s: abs(s[0] - fraction * end))
    return best[column] / MB


def summary(plain: dict[str, Any], traced: dict[str, Any] | None, scans: int) -> dict[str, Any]:
    """The figures of one tree on one recording [MB]; without a traced run, the growth is
    that of the resident set."""
    s = plain["samples"] if traced is None else traced["samples"]
    column = 1 if traced is None else 2
    growth = float("nan")
    if len(s) >= 4:
        # the scans run between the samples at half and nine tenths of the run, taken as
        # proportional to the CPU (the samples at the very end may follow the last scan)
        end = s[-1][0]
        half, late = (min(s, key=lambda r: abs(r[0] - f * end)) for f in (0.5, 0.9))
        share = (late[0] - half[0]) / end
        growth = (late[column] - half[column]) / MB / max(share * scans, 1.0) * 10_000
    out: dict[str, Any] = {
        "peak_rss_mb": plain["maxrss"] / MB,
        "rss_mb_at": {f: at(plain["samples"], f, 1) for f in (0.1, 0.5, 0.9)},
        "cpu_s": plain["cpu"],
        "growth_of": "anonymous" if traced is None else "traced",
        "growth_mb_per_10k_scans": growth,
        "samples": s,  # (CPU s, anonymous resident set, traced size [bytes]) through the run
    }
    if traced is not None:
        out["traced_peak_mb"] = traced["traced_peak"] / MB
        out["traced_mb_at"] = {f: at(s, f, 2) for f in (0.1, 0.5, 0.9)}
        out["growth_lines"] = traced["growth_lines"]
    return out


def count_scans(rec: Path) -> int:
    """The scans of the recording's first laser."""
    from laserpeople.io import open_recording

    r = open_recording(rec)
    try:
        return sum(1 for _ in r.scans())
    finally:
        r.close()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--before", type=Path, help="the other source tree (its src/)")
    ap.add_argument("--minutes", type=float, default=10.0, help="length of the long run")
    ap.add_argument("--people", type=int, default=20, help="walkers in the long run")
    ap.add_argument("--every", type=float, default=2.0, help="sample every so many CPU s")
    ap.add_argument("--no-demo", action="store_true", help="skip the real demo bag")
    ap.add_argument("--no-long", action="store_true", help="skip the long simulated run")
    ap.add_argument(
        "--trace-long",
        action="store_true",
        help="also trace the long run (about twice its CPU; its growth is then the traced "
        "size's, with the lines that hold it)",
    )
    ap.add_argument(
        "--data",
        type=Path,
        default=Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "/work/shared/data")),
    )
    ap.add_argument("--cache", type=Path, help="keep the long recording here (reused)")
    ap.add_argument("--json", type=Path)
    args = ap.parse_args()
    trees = {"after": THIS_SRC}
    if args.before is not None:
        trees = {"before": args.before, "after": THIS_SRC}
    recordings: dict[str, Path] = {}
    bag = args.data / DEMO_BAG
    if not args.no_demo:
        if bag.exists():
            recordings["demo bag"] = bag
        else:
            print(f"no demo bag at {bag}: its row is left out (--data names the shared data)")
    with tempfile.TemporaryDirectory() as tmp:
        if not args.no_long:
            cache = args.cache or Path(tmp)
            cache.mkdir(parents=True, exist_ok=True)
            path = cache / f"hall-{args.people:02d}-{60 * args.minutes:g}s.npz"
            if not path.exists():
                print(f"simulating the hall with {args.people} people ({args.minutes:g} min)")
                hall_recording(args.people, 60.0 * args.minutes, path)
            recordings[f"hall, {args.people} people, {args.minutes:g} min"] = path
        report: dict[str, Any] = {}
        for name, rec in recordings.items():
            scans = count_scans(rec)
            every = args.every if scans > 5000 else min(args.every, 0.25)
            got: dict[str, dict[str, dict[str, Any]]] = {t: {} for t in trees}
            order = list(trees.items())
            modes = (False, True) if scans <= 5000 or args.trace_long else (False,)
            for i, trace in enumerate(modes):
                for tree, src in order if i % 2 == 0 else order[::-1]:
                    out = Path(tmp) / f"{tree}.csv"
                    kind = "traced" if trace else "plain"
                    # first snapshot at about a quarter of the traced run (twice the CPU)
                    first = 0.5 * got[tree]["plain"]["cpu"] if trace else 0.0
                    got[tree][kind] = run(src, rec, out, trace=trace, every=every, first=first)
                    print(f"{name}: {tree} {kind} done", flush=True)
            print(f"\n`laserpeople track` on {name} ({scans} scans), MB:")
            print(
                f"  {'tree':6s} {'CPU s':>6s} {'peak RSS':>9s} {'anon 10%/50%/90%':>20s} "
                f"{'traced peak':>12s} {'traced 10%/50%/90%':>20s} {'growth/10k scans':>17s}"
            )
            report[name] = {}
            for tree in trees:
                s = summary(got[tree]["plain"], got[tree].get("traced"), scans)
                report[name][tree] = s
                r = "/".join(f"{v:.1f}" for v in s["rss_mb_at"].values())
                t = "/".join(f"{v:.1f}" for v in s.get("traced_mb_at", {}).values()) or "-"
                peak = f"{s['traced_peak_mb']:12.1f}" if "traced_peak_mb" in s else f"{'-':>12s}"
                print(
                    f"  {tree:6s} {s['cpu_s']:6.1f} {s['peak_rss_mb']:9.1f} {r:>20s} {peak} "
                    f"{t:>20s} {s['growth_mb_per_10k_scans']:11.2f} ({s['growth_of']})"
                )
            for tree in trees:
                lines = report[name][tree].get("growth_lines", [])
                if lines:
                    print(f"  {tree}: lines whose live allocations grew most over the run")
                for where, size, count in lines[:5]:
                    print(f"    {size / 1024:+9.1f} KiB {count:+7d} blocks  {where}")
            if len(trees) == 2:
                b, a = (report[name][t]["peak_rss_mb"] for t in ("before", "after"))
                print(f"  peak RSS before/after {b / a:.2f}x")
        if args.json:
            args.json.write_text(json.dumps(report, indent=1))
    if not recordings:
        raise SystemExit("nothing to measure (--no-demo, --no-long, or no demo bag)")


if __name__ == "__main__":
    main()
