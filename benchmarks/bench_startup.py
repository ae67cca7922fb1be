"""Start-up time of the command line: ``laserpeople --help``, ``--version`` and every
command's ``--help``, for one source tree or two side by side.

Run: ``.venv/bin/python benchmarks/bench_startup.py [--repeat 15] [--src DIR] [--before
DIR]``. Each case runs in a fresh interpreter ``--repeat`` times, every case (of both trees)
once per round, so a busy machine slows every case alike. Printed: the median CPU time
(user + system: what the program itself costs, much less sensitive to other load than the
wall time) and its ratio to a bare ``python -c pass`` measured the same way, per tree, the
before/after ratio, and the median wall time of the last tree. ``import typer`` is timed as
a floor: what any typer program pays. ``--src`` puts a source tree first on ``sys.path``
(default: this checkout's ``src``); ``--before`` adds an older checkout's ``src``.

Goal: every ``--help`` under 10 times a bare interpreter start. The figures of the current
code are in docs/speed.md (Start-up). ``python -X importtime -m laserpeople.cli track
--help`` shows what is imported at start.
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

RUN_CLI = (
    "import sys; sys.argv[0] = 'laserpeople'; from laserpeople import cli; "
    "getattr(cli, 'run', cli.main)()"
)
"""The ``laserpeople`` program of the tree on ``PYTHONPATH`` (``cli.run``; ``cli.main`` in
trees from before it)."""

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))
from laserpeople.cli import COMMANDS  # noqa: E402  (every command: its --help is timed)

FLOORS: dict[str, list[str]] = {
    "python -c pass": ["-c", "pass"],
    "import typer": ["-c", "import typer"],
}
"""What any Python program / any typer program pays (timed with the first source tree)."""

CASES: dict[str, list[str]] = {
    "laserpeople --help": ["-c", RUN_CLI, "--help"],
    "laserpeople --version": ["-c", RUN_CLI, "--version"],
    **{f"{c} --help": ["-c", RUN_CLI, c, "--help"] for c in COMMANDS},
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


def _env(src: Path) -> dict[str, str]:
    # bytecode caches are written (an installed package has them), whatever the caller's
    # PYTHONDONTWRITEBYTECODE says
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPATH"] = str(src.resolve())
    return env


def measure(
    trees: dict[str, Path], repeat: int
) -> dict[tuple[str, str], list[tuple[float, float]]]:
    """Wall and CPU times per (tree, case): every case of every tree once per round,
    ``repeat`` rounds (after one warm-up round), so a load change hits all alike. The
    floors run once per round with the first tree."""
    envs = {name: _env(src) for name, src in trees.items()}
    first = next(iter(trees))
    jobs = [(first, name, argv) for name, argv in FLOORS.items()]
    jobs += [(tree, name, argv) for name, argv in CASES.items() for tree in trees]
    for tree, _, argv in jobs:  # warm the bytecode caches and the file system
        time_once(argv, envs[tree])
    times: dict[tuple[str, str], list[tuple[float, float]]] = {
        (tree, name): [] for tree, name, _ in jobs
    }
    for _ in range(repeat):
        for tree, name, argv in jobs:
            t = time_once(argv, envs[tree])
            if t is not None:
                times[(tree, name)].append(t)
    return times


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=15)
    parser.add_argument(
        "--src",
        type=Path,
        default=Path(__file__).resolve().parents[1] / "src",
        help="source tree to import laserpeople from (default: this checkout's src)",
    )
    parser.add_argument(
        "--before",
        type=Path,
        default=None,
        help="another source tree (an older checkout's src) timed in the same rounds",
    )
    args = parser.parse_args()
    trees = {"after": args.src} if args.before is None else {"before": args.before}
    trees["after"] = args.src
    times = measure(trees, args.repeat)
    first = next(iter(trees))
    bare = statistics.median(v[1] for v in times[(first, "python -c pass")])
    print(f"sources: {', '.join(f'{k} {v}' for k, v in trees.items())}")
    print(f"{args.repeat} runs each, interleaved; median CPU (user + system) [s], x bare python")
    header = f"{'case':24s}" + "".join(f"{k + ' CPU s':>14s}{'x bare':>8s}" for k in trees)
    print(header + ("   before/after" if len(trees) == 2 else "") + "   after wall s")
    for name in [*FLOORS, *CASES]:
        row, cpus = f"{name:24s}", []
        for tree in trees:
            values = times.get((tree, name))
            if values is None:
                row += f"{'':14s}{'':8s}"
                continue
            if not values:
                row += f"{'fails':>14s}{'':8s}"
                continue
            cpu = statistics.median(v[1] for v in values)
            cpus.append(cpu)
            row += f"{cpu:14.3f}{cpu / bare:7.1f}x"
        if len(trees) == 2 and len(cpus) == 2:
            row += f"{cpus[0] / cpus[1]:14.2f}x"
        elif len(trees) == 2:
            row += f"{'':15s}"
        wall = times.get(("after", name)) or times.get((first, name)) or []
        if wall:
            row += f"{statistics.median(v[0] for v in wall):14.3f}"
        print(row)


if __name__ == "__main__":
    main()
