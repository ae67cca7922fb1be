"""Batch runs on a Dask LocalCluster: wall time and speed-up with 1 and 2 workers, peak
memory per worker, bad recordings reported, a killed worker and a killed run.

The recordings: simulated ones of several kinds (short, different seeds), the real bags of
``../shared/data`` (when present) and, on purpose, broken files: truncated and corrupted
copies of a simulated recording and of a bag, and an empty file (about 1 in 20). Every
recording is tracked fused (``--topics all``) with the default tracker.

Figures: per worker count, the wall time, the speed-up over one worker, scans per second,
the CPU seconds the workers spent (so that a shared machine's load can be read off: wall
time x workers much above CPU time means the cores were busy elsewhere) and each worker's
peak resident memory. ``--kill`` kills one worker process in the middle of a two-worker run
(its tasks are redone, the summary counts their attempts); ``--resume`` kills a whole
``laserpeople batch`` run after a third of the recordings and runs it again (only the
unfinished ones run).

    .venv/bin/python benchmarks/bench_batch.py [--recordings 40] [--seconds 4]
        [--workers 1 2] [--kill] [--resume] [--data /tmp/bench_batch_data]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

from laserpeople.batch import ClusterSpec, TrackOptions, open_client, run_batch

SHARED = Path(__file__).resolve().parents[1].parent / "shared" / "data"
KINDS = ("demo", "crossing-3", "speed-normal", "corridor", "office", "randomised", "circle")
OPTIONS = TrackOptions(topics=("all",))


def real_bags() -> list[Path]:
    """The small real bags (hundreds of scans each), when ../shared/data is there."""
    if not SHARED.is_dir():
        return []
    found = sorted(
        SHARED.glob("leg_tracker/rosbags/training_scans_res=0.33/positive_not_extracted/*.bag")
    )
    found += sorted(SHARED.glob("leg_tracker_benchmarks/general_tracking_moving_1_first.bag"))
    return found


def make_data(folder: Path, count: int, seconds: float) -> list[Path]:
    """``count`` recordings in ``folder`` (made once, then reused): see the module docstring."""
    from laserpeople.sim import run_scenario

    folder.mkdir(parents=True, exist_ok=True)
    real = real_bags()
    broken = max(count // 20, 3)
    simulated = max(count - len(real) - broken, 1)
    paths = []
    for k in range(simulated):
        kind = KINDS[k % len(KINDS)]
        path = folder / f"sim-{k:03d}-{kind}.npz"
        if not path.exists():
            run_scenario(kind, seconds=seconds, seed=k).write(path)
        paths.append(path)
    for bag in real[: max(count - simulated - broken, 0)]:
        link = folder / f"real-{bag.name}"
        if not link.exists():
            link.symlink_to(bag)
        paths.append(link)
    source = paths[0].read_bytes()
    bag = real[0].read_bytes() if real else source
    bad = [
        ("bad-truncated-sim.npz", source[: len(source) // 3]),
        ("bad-truncated-real.bag", bag[: len(bag) // 2]),
        ("bad-empty.npz", b""),
        ("bad-corrupt.npz", source[:100] + bytes(200) + source[300:]),
    ]
    for name, data in bad[:broken]:
        (folder / name).write_bytes(data)
        paths.append(folder / name)
    return paths


def worker_stats(client: object) -> dict[str, tuple[float, float]]:
    """Per worker: (peak resident memory [MiB], CPU seconds so far)."""

    def probe() -> tuple[float, float]:
        use = resource.getrusage(resource.RUSAGE_SELF)
        return use.ru_maxrss / 1024.0, use.ru_utime + use.ru_stime

    return client.run(probe)  # type: ignore[attr-defined,no-any-return]


def timed_run(paths: list[Path], out: Path, workers: int, kill: bool) -> dict[str, object]:
    """One batch run on a fresh LocalCluster of ``workers`` processes."""
    shutil.rmtree(out, ignore_errors=True)
    with open_client(ClusterSpec(workers=workers, retries=2)) as client:
        before = worker_stats(client)
        done = [0]
        killed: list[int] = []

        def on_done(rows: list) -> None:
            done[0] += 1
            if kill and not killed and done[0] == len(paths) // 3:
                pids = client.run(os.getpid)
                victim = sorted(pids.values())[0]
                os.kill(victim, signal.SIGKILL)
                killed.append(victim)

        start = time.perf_counter()
        result = run_batch(paths, out, OPTIONS, client=client, on_done=on_done)
        wall = time.perf_counter() - start
        time.sleep(1.0)  # a killed worker's replacement registers
        after = worker_stats(client)
    cpu = sum(c for _, c in after.values()) - sum(c for a, (_, c) in before.items() if a in after)
    return {
        "workers": workers,
        "wall_s": round(wall, 1),
        "rows": len(result.rows),
        "done": sum(r.status == "done" for r in result.rows),
        "failed": result.failed,
        "failed_names": [r.name for r in result.rows if r.status == "failed"],
        "scans": result.scans,
        "scans_per_s": round(result.scans / wall, 1),
        "worker_cpu_s": round(cpu, 1),
        "peak_mib_per_worker": sorted(round(m, 0) for m, _ in after.values()),
        "killed_worker_pid": killed[0] if killed else None,
        "retried": [(r.name, r.attempts) for r in result.retried],
        "load_1min": round(os.getloadavg()[0], 1),
    }


def resume_run(paths: list[Path], out: Path) -> dict[str, object]:
    """Kill a `laserpeople batch` run after a third of the recordings, then run it again."""
    shutil.rmtree(out, ignore_errors=True)
    cmd = [sys.executable, "-m", "laserpeople.cli", "-q", "batch", *map(str, paths)]
    cmd += ["--out", str(out), "--topics", "all", "--workers", "2"]
    proc = subprocess.Popen(cmd, start_new_session=True, stdout=subprocess.DEVNULL)
    manifest = out / "manifest.jsonl"
    while proc.poll() is None:
        time.sleep(0.5)
        if manifest.exists() and len(manifest.read_text().splitlines()) >= len(paths) // 3:
            os.killpg(proc.pid, signal.SIGKILL)
            break
    proc.wait()
    finished = len(manifest.read_text().splitlines())
    start = time.perf_counter()
    result = run_batch(paths, out, OPTIONS, ClusterSpec(workers=2))
    return {
        "finished_before_kill": finished,
        "rerun_submitted": result.submitted,
        "rerun_skipped": result.skipped,
        "rerun_wall_s": round(time.perf_counter() - start, 1),
        "rerun_failed": result.failed,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--recordings", type=int, default=40)
    parser.add_argument("--seconds", type=float, default=4.0, help="length of simulated ones")
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--kill", action="store_true", help="kill a worker mid-run (2 workers)")
    parser.add_argument("--resume", action="store_true", help="kill a whole run, run again")
    parser.add_argument(
        "--data",
        type=Path,
        default=Path("/tmp/bench_batch_data"),
        help="folder the recordings are made in (not ../shared/data, whose bags it links)",
    )
    args = parser.parse_args()
    if args.data.resolve().is_relative_to(SHARED.resolve()):
        parser.error(f"--data {args.data} lies in {SHARED}: the recordings are made there")
    paths = make_data(args.data, args.recordings, args.seconds)
    print(f"{len(paths)} recordings in {args.data}; load {os.getloadavg()[0]:.1f}", flush=True)
    runs = []
    for workers in args.workers:
        run = timed_run(paths, args.data.parent / f"bench_batch_out_{workers}", workers, False)
        runs.append(run)
        print(json.dumps(run), flush=True)
    base = next((r for r in runs if r["workers"] == 1), None)
    if base is not None:
        for run in runs:
            print(
                f"workers {run['workers']}: {run['wall_s']} s wall, speed-up "
                f"{float(base['wall_s']) / float(run['wall_s']):.2f}x, "  # type: ignore[arg-type]
                f"{run['scans_per_s']} scans/s, worker CPU {run['worker_cpu_s']} s, "
                f"peak MiB per worker {run['peak_mib_per_worker']}, load {run['load_1min']}"
            )
    if args.kill:
        run = timed_run(paths, args.data.parent / "bench_batch_out_kill", 2, True)
        print("kill:", json.dumps(run), flush=True)
    if args.resume:
        print("resume:", json.dumps(resume_run(paths, args.data.parent / "bench_batch_out_resume")))


if __name__ == "__main__":
    main()
