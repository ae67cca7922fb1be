"""Start-up time of the command line: ``laserpeople --help`` and each command's ``--help``.

Run: ``.venv/bin/python benchmarks/bench_startup.py [--repeat 15] [--src DIR]``. Each case
runs in a fresh interpreter ``--repeat`` times (interleaved, so a busy machine slows every
case alike) and the median wall time and CPU time (user + system: what the program itself
costs, much less sensitive to other load on the machine) are printed, next to two floors
measured the same way: a bare interpreter and ``import typer`` (what any typer program
pays). ``--src`` puts another source tree first on ``sys.path`` (e.g. an older checkout's
``src`` to get the "before" figures).

Goal (issue 15): ``laserpeople --help`` under 0.3 s. Figures on the project machine (2
cores shared with 7 other jobs, load ~20, so wall times are ~10x the CPU times; 10 runs):

=========================  ==============================  ==============================
median CPU (wall)          before (eager imports)          after (imports where used)
=========================  ==============================  ==============================
bare interpreter           0.019 s (0.25 s)                0.020 s (0.24 s)
``import typer``           0.126 s (1.54 s)                0.128 s (1.55 s)
``laserpeople --help``     1.749 s (20.8 s)                0.202 s (2.47 s)
``laserpeople --version``  (no such option)                0.228 s (3.05 s)
``track --help``           1.936 s (24.8 s)                0.401 s (4.92 s)
``view --help``            1.971 s (24.2 s)                0.416 s (4.90 s)
=========================  ==============================  ==============================

What is left of a command's ``--help`` above ``--help`` is typer's own: typer 0.29
builds each parameter's converter with pydantic (``typer._adapters``), about 0.2 s.

The command modules import numpy, scipy, rosbags and matplotlib inside their functions;
``python -X importtime -m laserpeople.cli --help`` shows what is still imported at start.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

RUN_CLI = "import sys; sys.argv[0] = 'laserpeople'; from laserpeople.cli import main; main()"

CASES: dict[str, list[str]] = {
    "python (bare interpreter)": ["-c", "pass"],
    "import typer": ["-c", "import typer"],
    "laserpeople --help": ["-c", RUN_CLI, "--help"],
    "laserpeople --version": ["-c", RUN_CLI, "--version"],
    "laserpeople track --help": ["-c", RUN_CLI, "track", "--help"],
    "laserpeople view --help": ["-c", RUN_CLI, "view", "--help"],
}


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def time_once(args: list[str], env: dict[str, str]) -> tuple[float, float] | None:
    """Wall time and CPU time (user + system) [s] of one fresh interpreter running ``args``;
    None when it fails (an older version without ``--version``)."""
    cpu0, t0 = _children_cpu(), time.perf_counter()
    done = subprocess.run(
        [sys.executable, *args], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    elapsed, cpu = time.perf_counter() - t0, _children_cpu() - cpu0
    return (elapsed, cpu) if done.returncode == 0 else None


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=15)
    parser.add_argument(
        "--src",
        type=Path,
        default=Path(__file__).resolve().parents[1] / "src",
        help="source tree to import laserpeople from (default: this checkout's src)",
    )
    args = parser.parse_args()
    # bytecode caches are written (an installed package has them), whatever the caller's
    # PYTHONDONTWRITEBYTECODE says
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPATH"] = str(args.src.resolve())
    for argv in CASES.values():  # warm the bytecode caches and the file system
        time_once(argv, env)
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in CASES}
    for _ in range(args.repeat):
        for name, argv in CASES.items():
            t = time_once(argv, env)
            if t is not None:
                times[name].append(t)
    print(f"source: {args.src}  ({args.repeat} runs each, interleaved)")
    for name, values in times.items():
        if not values:
            print(f"{name:28s} fails (not in this version)")
            continue
        wall, cpu = [v[0] for v in values], [v[1] for v in values]
        print(
            f"{name:28s} wall median {statistics.median(wall):5.3f} s (min {min(wall):5.3f}), "
            f"CPU median {statistics.median(cpu):5.3f} s"
        )


if __name__ == "__main__":
    main()
