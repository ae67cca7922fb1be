"""Cost of the whole loop a user runs against the number of people in view, and of ``track``
on the real demo bag, for one or two source trees side by side (issue 35).

Hall scenes: a 16 m x 12 m hall seen by one Hokuyo UTM-30LX (1081 beams, 40 Hz) from the
middle of its south wall, with 1, 4, 10, 20 and 40 people walking between random points
(seed = number of people). Each is simulated once (by this checkout) and written to a
recording; its scans are read into memory and tracked as ``laserpeople track`` does: leg
detection (shipped AdaBoost), the default leg MHT with its people layer and its static world
model (``auto``, or ``--background``), through
:func:`laserpeople.pipeline.recording.tracker_stages` and
:class:`laserpeople.pipeline.Pipeline` (reading and writing excluded). With ``--before
SRC`` the other tree is imported in the same process as the package ``laserpeople_ab``
(``bench_track_ab.load_other``) and the two pipelines are stepped alternately, scan by scan
(who goes first: :func:`goes_first`), each step timed by process CPU time: on a shared
machine, whose load makes two runs minutes apart differ by tens of per cent, both trees then
see the same load. Printed: CPU ms per scan (mean over the scene, median over
``--passes``), scans per second, their ratio (the median of the passes' ratios), the
log-log slope of cost against people (4 to 40, least squares), and per tree the person
tracks created and the rows reported (the same numbers when the trees track alike).

Demo bag: its frames tracked as the halls are (both trees in one process, scan by scan:
CPU per scan of the loop, median over the passes, and their ratio), and ``laserpeople
track`` on it as a whole process (interpreter start, imports, reading, detection,
tracking, CSV) per tree, alternating which runs first each pass; its CPU time (user +
system of the child, median over the passes) and scans per second of CPU; the two trees'
CSVs are compared row by row (largest position difference). The whole process of the
same code in two trees differs by up to a tenth between runs on a loaded machine (5.76
against 6.28 s in one run of five passes, 6.33 against 5.92 s in one of three); the loop
scan by scan in one process resolves a few per cent (a ratio of 1.01 in the latter).

    PYTHONPATH=src .venv/bin/python benchmarks/bench_scaling.py [--before /path/to/old/src]
        [--people 1 4 10 20 40] [--seconds 8] [--passes 3] [--background auto|none]
        [--no-demo] [--json out.json]
"""

from __future__ import annotations

import argparse
import csv
import importlib
import itertools
import json
import math
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve()
THIS_SRC = HERE.parents[1] / "src"
DEMO_BAG = "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag"
RUN_CLI = (
    "import sys; sys.argv[0] = 'laserpeople'; from laserpeople import cli; "
    "getattr(cli, 'run', cli.main)()"
)
"""The ``laserpeople`` program of the tree on ``PYTHONPATH`` (``cli.run``; ``cli.main`` in
trees from before it)."""
sys.path.insert(0, str(HERE.parent))

sys.path.insert(0, str(HERE.parent))
from bench_track_ab import PACKAGE, load_other  # noqa: E402

HALL = (16.0, 12.0)
"""Size of the hall [m]."""


def hall_recording(n_people: int, seconds: float, path: Path) -> Path:
    """Simulate the hall with ``n_people`` walkers for ``seconds`` and write it to
    ``path`` (an .npz recording); returns ``path``."""
    import numpy as np

    from laserpeople.io.npz import write_recording
    from laserpeople.scan import Pose2D
    from laserpeople.sim.motion import Route
    from laserpeople.sim.people import random_person
    from laserpeople.sim.sensors import SensorSpec
    from laserpeople.sim.simulator import Scene, simulate
    from laserpeople.sim.world import World, pillar, room

    rng = np.random.default_rng([n_people, 35])
    w, h = HALL
    world = World([*room(0.0, 0.0, w, h), pillar(4.0, 7.0), pillar(12.0, 7.0)])
    people = []
    for i in range(n_people):

        def spot() -> tuple[float, float]:
            return float(rng.uniform(1.0, w - 1.0)), float(rng.uniform(1.5, h - 1.0))

        x, y = spot()
        route = Route(x, y, float(rng.uniform(-math.pi, math.pi)))
        speed = float(rng.uniform(0.7, 1.4))
        while route.end_time < seconds:
            route.walk_to(*spot(), speed)
            if rng.random() < 0.2:
                route.wait(float(rng.uniform(0.5, 2.0)))
        people.append(random_person(rng, i, route))
    sensors = [SensorSpec("laser", "hokuyo-utm-30lx", 0.2, Pose2D(w / 2, 0.1, math.pi / 2))]
    result = simulate(Scene(world, people, sensors), seconds, seed=n_people, name="hall")
    return write_recording(path, result.scans, result.truth, result.meta)


def pipeline(package: str, path: Path, background: str) -> Any:
    """The frames of the recording ``path`` tracked as ``track`` does (see the module doc)
    by the copy of the code imported as ``package``: an iterator of pipeline steps, the
    scans already read into memory."""
    io = importlib.import_module(f"{package}.io")
    detector = importlib.import_module(f"{package}.detection.detector")
    pipe = importlib.import_module(f"{package}.pipeline")
    recording = importlib.import_module(f"{package}.pipeline.recording")
    registry = importlib.import_module(f"{package}.tracking.registry")
    rec = io.open_recording(path)
    try:
        scans = list(rec.scans())
    finally:
        rec.close()
    tracker = registry.get("leg-mht").make()
    preprocess, observe, hide = recording.tracker_stages(
        tracker, detector=detector.AdaBoostLegDetector.default(), background=background
    )
    # as ``track`` reads a recording: frames read ahead, their legs detected at once
    ahead = getattr(recording, "LOOKAHEAD", None)
    return iter(
        pipe.Pipeline(
            pipe.FrameChooser()(pipe.laser_frames(scans)),
            preprocess=preprocess,
            observe=observe,
            tracker=tracker,
            identify=[hide] if hide is not None else [],
            **({} if ahead is None else {"lookahead": ahead}),
        )
    )


def goes_first(scan: int) -> int:
    """Which of two trees steps first at scan ``scan`` (0 or 1): the Thue-Morse sequence,
    the parity of the ones in the scan's binary number. Each pair of scans (2k, 2k+1) has
    one of each, as a plain alternation has, and so has every subsequence of scans whose
    period is a power of two (every 2nd, 16th, ... scan): a plain alternation lets the
    same tree go first at every such scan, e.g. at every batch of leg detections
    (``recording.LOOKAHEAD``, 16 scans), and the tree going second finds the shared
    code (numpy, the interpreter) warm there."""
    return bin(scan).count("1") % 2


def hall_ab(packages: list[str], path: Path, background: str) -> dict[str, dict[str, Any]]:
    """Per package: process CPU seconds per scan (a list), person tracks created and rows,
    the packages' pipelines stepped alternately scan by scan (who goes first:
    :func:`goes_first`)."""
    steps = {name: pipeline(name, path, background) for name in packages}
    out: dict[str, dict[str, Any]] = {n: {"cpu": [], "rows": 0, "persons": set()} for n in packages}
    for scan in itertools.count():
        order = packages[::-1] if goes_first(scan) else packages
        done = False
        for name in order:
            t0 = time.process_time()
            step = next(steps[name], None)
            cpu = time.process_time() - t0
            if step is None:
                done = True
                continue
            got = out[name]
            got["cpu"].append(cpu)
            for t in step.tracks.tracks:
                got["rows"] += 1
                if t.kind == "person":
                    got["persons"].add(t.track_id)
        if done:
            break
    for got in out.values():
        got["persons"] = len(got["persons"])
    return out


def _child_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _env(src: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPATH"] = str(src.resolve())
    return env


def run_track(src: Path, bag: Path, out: Path) -> float:
    """CPU seconds (user + system) of ``laserpeople track bag -o out`` importing ``src``."""
    out.unlink(missing_ok=True)
    c0 = _child_cpu()
    done = subprocess.run(
        [sys.executable, "-c", RUN_CLI, "track", str(bag), "-o", str(out)],
        env=_env(src),
        capture_output=True,
        text=True,
        check=False,
    )
    if done.returncode != 0:
        raise SystemExit(f"track with {src} failed:\n{done.stderr}")
    return _child_cpu() - c0


def csv_difference(a: Path, b: Path) -> str:
    """How two tracks CSVs differ: rows, and the largest position difference of rows with
    the same scan, id and kind."""

    def load(p: Path) -> dict[tuple[str, str, str], tuple[float, float]]:
        with open(p, newline="", encoding="utf-8") as fh:
            reader = csv.reader(line for line in fh if not line.startswith("#"))
            header = next(reader)
            i = {name: k for k, name in enumerate(header)}
            return {
                (r[i["scan"]], r[i["track_id"]], r[i["kind"]]): (float(r[i["x"]]), float(r[i["y"]]))
                for r in reader
            }

    ra, rb = load(a), load(b)
    common = ra.keys() & rb.keys()
    worst = max((math.dist(ra[k], rb[k]) for k in common), default=0.0)
    only = len(ra.keys() ^ rb.keys())
    return (
        f"{len(ra)} / {len(rb)} rows, {only} in one only, largest position difference {worst:.2e} m"
    )


def slope(people: list[int], cost: list[float]) -> float:
    """Least-squares slope of log(cost) against log(people) over 4 people and more."""
    pts = [(math.log(n), math.log(c)) for n, c in zip(people, cost, strict=True) if n >= 4]
    if len(pts) < 2:
        return float("nan")
    mx = statistics.fmean(p[0] for p in pts)
    my = statistics.fmean(p[1] for p in pts)
    sxy = sum((x - mx) * (y - my) for x, y in pts)
    sxx = sum((x - mx) ** 2 for x, _ in pts)
    return sxy / sxx


def add_scene_arguments(ap: argparse.ArgumentParser, people: list[int]) -> None:
    """The options that choose the hall scenes (``people`` by default) and the demo bag."""
    ap.add_argument("--people", type=int, nargs="+", default=people)
    ap.add_argument("--seconds", type=float, default=8.0, help="length of each hall scene [s]")
    ap.add_argument("--background", default="auto", help="static world model of the people")
    ap.add_argument("--no-demo", action="store_true", help="skip the real demo bag")
    ap.add_argument(
        "--data",
        type=Path,
        default=Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "/work/shared/data")),
    )
    ap.add_argument("--cache", type=Path, help="keep the simulated halls here (reused)")


def hall_paths(people: list[int], seconds: float, cache: Path) -> list[Path]:
    """The hall recordings with ``people`` walkers each in ``cache``, simulated where
    missing."""
    cache.mkdir(parents=True, exist_ok=True)
    paths = []
    for n in people:
        path = cache / f"hall-{n:02d}-{seconds:g}s.npz"
        if not path.exists():
            print(f"simulating the hall with {n} people ({seconds:g} s)", flush=True)
            hall_recording(n, seconds, path)
        paths.append(path)
    return paths


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--before", type=Path, help="the other source tree (its src/)")
    ap.add_argument("--passes", type=int, default=3, help="passes over the halls and the bag")
    add_scene_arguments(ap, [1, 4, 10, 20, 40])
    ap.add_argument("--json", type=Path)
    args = ap.parse_args()
    trees = {"after": THIS_SRC}
    if args.before is not None:
        trees = {"before": args.before, "after": THIS_SRC}
    bag = args.data / DEMO_BAG
    demo = not args.no_demo and bag.exists()
    if not args.no_demo and not demo:
        print(f"no demo bag at {bag}: its row is left out (--data names the shared data)")
    with tempfile.TemporaryDirectory() as tmp:
        packages = {"after": "laserpeople"}
        if args.before is not None:
            load_other(args.before, Path(tmp))
            packages = {"before": PACKAGE, "after": "laserpeople"}
        paths = hall_paths(args.people, args.seconds, args.cache or Path(tmp))
        # pass by pass: every hall (both trees in one process, scan by scan), then the bag
        # (each tree's whole process, alternating which runs first)
        hall: dict[str, dict[int, list[float]]] = {
            name: {n: [] for n in args.people} for name in trees
        }
        digest: dict[str, dict[int, str]] = {name: {} for name in trees}
        track_cpu: dict[str, list[float]] = {name: [] for name in trees}
        demo_loop: dict[str, list[float]] = {name: [] for name in trees}
        for p in range(args.passes):
            for path, n in zip(paths, args.people, strict=True):
                got = hall_ab(list(packages.values()), path, args.background)
                for name, package in packages.items():
                    cpu = got[package]["cpu"]
                    hall[name][n].append(1e3 * statistics.fmean(cpu))
                    digest[name][n] = f"{got[package]['persons']}, {got[package]['rows']}"
            if demo:  # the bag's loop, both trees in one process
                got = hall_ab(list(packages.values()), bag, args.background)
                for name, package in packages.items():
                    demo_loop[name].append(1e3 * statistics.fmean(got[package]["cpu"]))
            order = list(trees.items())
            if p % 2:
                order.reverse()
            for name, src in order if demo else ():
                track_cpu[name].append(run_track(src, bag, Path(tmp) / f"{name}.csv"))
            print(f"pass {p + 1} of {args.passes} done", flush=True)
        report: dict[str, Any] = {"background": args.background, "passes": args.passes}
        print(
            f"\nhall {HALL[0]:g} m x {HALL[1]:g} m, 1081 beams, {args.seconds:g} s per scene, "
            f"static world model {args.background!r}: CPU per scan (mean over the scene, "
            f"median of {args.passes} passes)"
        )
        head = f"{'people':>6s} " + " ".join(
            f"{n + ' ms/scan':>16s} {'scans/s':>8s}" for n in trees
        )
        print(head + ("  before/after" if len(trees) == 2 else "") + "  persons created, rows")
        costs: dict[str, list[float]] = {name: [] for name in trees}
        for n in args.people:
            cells = []
            for name in trees:
                ms = statistics.median(hall[name][n])
                costs[name].append(ms)
                cells.append(f"{ms:16.3f} {1e3 / ms:8.0f}")
            ratio = ""
            if len(trees) == 2:  # the median of the passes' ratios, as the demo bag's
                per_pass = [b / a for b, a in zip(hall["before"][n], hall["after"][n], strict=True)]
                ratio = f"  {statistics.median(per_pass):11.3f}x"
            rows = " | ".join(digest[name][n] for name in trees)
            print(f"{n:6d} " + " ".join(cells) + ratio + "  " + rows)
        for name in trees:
            report[f"hall_ms_{name}"] = dict(zip(args.people, costs[name], strict=True))
            s = slope(args.people, costs[name])
            report[f"slope_{name}"] = s
            print(f"log-log slope of cost vs people (4-40), {name}: {s:.2f}")
        if demo:
            from laserpeople.io import open_recording

            rec = open_recording(bag)
            try:
                scans = sum(1 for _ in rec.scans())
            finally:
                rec.close()
            print(f"\n{DEMO_BAG} ({scans} scans), the loop scan by scan in one process:")
            for name in trees:
                ms = statistics.median(demo_loop[name])
                report[f"demo_loop_ms_{name}"] = ms
                print(f"  {name:6s} {ms:6.3f} ms CPU per scan -> {1e3 / ms:5.0f} scans/s")
            if len(trees) == 2:
                ratios = [b / a for b, a in zip(*demo_loop.values(), strict=True)]
                print(f"  before/after {statistics.median(ratios):.3f} (median of the passes)")
            print(f"`laserpeople track` on {DEMO_BAG}, whole process:")
            for name in trees:
                cpu = statistics.median(track_cpu[name])
                report[f"track_cpu_s_{name}"] = cpu
                print(f"  {name:6s} {cpu:6.2f} s CPU -> {scans / cpu:5.0f} scans/s")
            if len(trees) == 2:
                print(
                    "  CSVs: " + csv_difference(Path(tmp) / "before.csv", Path(tmp) / "after.csv")
                )
        if args.json:
            args.json.write_text(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
