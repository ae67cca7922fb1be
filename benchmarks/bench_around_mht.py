"""Where the default tracker's CPU goes per scan outside the leg MHT's step.

Runs the default tracker as ``people_suite.py`` and ``cost_vs_gnn.py`` run it (leg MHT,
people ``tracks``, the static world model ``auto`` fed from each frame) on each scene with
the parts around the MHT step wrapped in timers, and prints per scan: the process CPU of
the whole update, then the time inside each part (a part nested in another one is listed
below it, indented; its time is part of its parent's). The timers add about a microsecond
per call of their own; compare parts within a run.

With ``--other SRC`` (another version's ``src/``, imported as ``bench_track_ab.py`` does)
both versions' trackers are updated alternately, scan by scan, in one process (the machine
is shared: separate runs drift by tens of per cent), each with its own part timers, and the
table has both columns and their ratio (this / other).

    PYTHONPATH=src .venv/bin/python benchmarks/bench_around_mht.py
        [--scenes randomised:0 randomised:2 crossing-3:1] [--seconds 30] [--repeat 3]
        [--other /path/to/old/src]
"""

from __future__ import annotations

import argparse
import importlib
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_track_parts import timed
from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.evaluation.suite import SuiteScene, frames_for, prepare
from people_suite import make_factory

PART_NAMES: list[tuple[str, str | None, str, str]] = [
    ("pipeline.preprocess", "Fuse", "__call__", "points of the frame (Fuse)"),
    ("pipeline.static_people", "PeopleStaticModel", "__call__", "static world model: learning"),
    ("background.occupancy", "OccupancyGrid", "_cast_still", "  free-space casting (still laser)"),
    ("background.still_cast", "StillCast", "cast", "    StillCast.cast"),
    (
        "pipeline.static_people",
        "PeopleStaticModel",
        "static_time",
        "static world model: static_time",
    ),
    ("tracking.legs", "LegMHTTracker", "_measurements", "leg measurements (incl. on_furniture)"),
    ("tracking.person_tracks", "PersonTracker", "on_furniture", "  on_furniture"),
    ("tracking.mht.core", "MHT", "step", "MHT step"),
    ("tracking.point_model", "KalmanPointModel", "predict", "  point model predict"),
    ("tracking.point_model", "KalmanPointModel", "score", "  point model score"),
    ("tracking.point_model", "KalmanPointModel", "update", "  point model update"),
    ("tracking.legs", "LegMHTTracker", "_people_as_tracks", "people as tracks"),
    ("tracking.legs", None, "leg_observations", "  leg observations"),
    ("tracking.person_tracks", "PersonTracker", "update", "  PersonTracker.update"),
]
"""(module under the package, class or None for the module, attribute, label) of the
parts timed."""


def parts(package: str) -> list[tuple[Any, str, str]]:
    """(owner, attribute, label) of the parts timed, in ``package``."""
    out = []
    for module, cls, name, label in PART_NAMES:
        mod = importlib.import_module(f"{package}.{module}")
        out.append((mod if cls is None else getattr(mod, cls), name, label))
    return out


PARTS = parts("laserpeople")


def run(prepared: Any) -> tuple[int, float, dict[str, float]]:
    """Scans, process CPU ms per scan of the whole update and ms per scan in each part."""
    tracker = make_factory("leg-mht", None, "auto")()
    frames = frames_for(prepared, frozenset(tracker.consumes))
    spent: dict[str, float] = defaultdict(float)
    saved = [(owner, name, owner.__dict__[name]) for owner, name, _ in PARTS]
    try:
        for owner, name, label in PARTS:
            setattr(owner, name, timed(spent, label, getattr(owner, name), time.process_time))
        t0 = time.process_time()
        for frame in frames:
            tracker.update(frame)
        cpu = time.process_time() - t0
    finally:
        for owner, name, fn in saved:
            setattr(owner, name, fn)
    n = max(len(frames), 1)
    return len(frames), 1e3 * cpu / n, {k: 1e3 * v / n for k, v in spent.items()}


def prepare_other(scene_text: str, seconds: float, other: str) -> Any:
    """The scene simulated by the package ``other`` (its own scans and frames, so that its
    preprocessing reads its own objects) and detected by this version's detector (the
    renamed package refuses the shipped model file)."""
    suite = importlib.import_module(f"{other}.evaluation.suite")
    scenario, seed = scene_text.split(":")
    scene = (
        suite.SuiteScene(scenario, scenario, int(seed), seconds)
        if scenario == "randomised"
        else suite.SuiteScene(scenario, scenario, int(seed))
    )
    return suite.prepare(scene, AdaBoostLegDetector.default(LegDetectorParams()))


def run_ab(
    prepared: Any, prepared_other: Any, other: str
) -> tuple[int, list[float], list[dict[str, float]]]:
    """:func:`run` of this version and of the package ``other`` (on its own simulation of
    the same scene) at once, scan by scan alternately: scans, the whole update's ms per scan
    of each, and each one's parts."""
    suite = importlib.import_module(f"{other}.evaluation.suite")
    static = importlib.import_module(f"{other}.pipeline.static_people")
    registry = importlib.import_module(f"{other}.tracking.registry")
    entry = registry.get("leg-mht")
    old = entry.factory(entry.params_cls())
    model = static.people_static_model("auto")
    old.use_static_model(model)
    trackers = [make_factory("leg-mht", None, "auto")(), static.StaticFed(old, model)]
    frames = frames_for(prepared, frozenset(trackers[0].consumes))
    frames_other = suite.frames_for(prepared_other, frozenset(trackers[1].consumes))
    spent: list[dict[str, float]] = [defaultdict(float), defaultdict(float)]
    cpu = [0.0, 0.0]
    tables = [PARTS, parts(other)]
    saved = [(o, n, o.__dict__[n]) for table in tables for o, n, _ in table]
    try:
        for i, table in enumerate(tables):
            for owner, name, label in table:
                setattr(
                    owner, name, timed(spent[i], label, getattr(owner, name), time.process_time)
                )
        for k, pair in enumerate(zip(frames, frames_other, strict=True)):
            for i in (0, 1) if k % 2 == 0 else (1, 0):
                t0 = time.process_time()
                trackers[i].update(pair[i])
                cpu[i] += time.process_time() - t0
    finally:
        for owner, name, fn in saved:
            setattr(owner, name, fn)
    n = max(len(frames), 1)
    return (
        len(frames),
        [1e3 * c / n for c in cpu],
        [{k: 1e3 * v / n for k, v in d.items()} for d in spent],
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument(
        "--scenes",
        nargs="+",
        default=["randomised:0", "randomised:2", "crossing-3:1"],
        help="SCENARIO:SEED",
    )
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--repeat", type=int, default=3, help="runs per scene (the fastest kept)")
    ap.add_argument("--other", type=Path, default=None, help="another version's src/ (A/B)")
    args = ap.parse_args()
    other = None
    if args.other is not None:
        from bench_track_ab import PACKAGE, load_other

        load_other(args.other, Path(tempfile.mkdtemp()))
        other = PACKAGE
    detector = AdaBoostLegDetector.default(LegDetectorParams())
    for text in args.scenes:
        scenario, seed = text.split(":")
        seconds = args.seconds if scenario == "randomised" else None
        scene = (
            SuiteScene(scenario, scenario, int(seed), seconds)
            if seconds is not None
            else SuiteScene(scenario, scenario, int(seed))
        )
        prepared = prepare(scene, detector)
        if other is not None:
            prepared_other = prepare_other(text, args.seconds, other)
            ab = [run_ab(prepared, prepared_other, other) for _ in range(args.repeat)]
            scans, cpu2, parts2 = min(ab, key=lambda r: r[1][0] + r[1][1])
            print(
                f"{text}: {scans} scans, ms CPU per scan, this / other (ratio); the whole "
                f"update {cpu2[0]:.3f} / {cpu2[1]:.3f} ({cpu2[0] / cpu2[1]:.2f})"
            )
            for _, _, label in PARTS:
                a, b = parts2[0].get(label, 0.0), parts2[1].get(label, 0.0)
                ratio = f"({a / b:.2f})" if b > 0 else ""
                print(f"  {label:<44s} {a:7.3f} / {b:7.3f} {ratio}")
            a = cpu2[0] - parts2[0].get("MHT step", 0.0)
            b = cpu2[1] - parts2[1].get("MHT step", 0.0)
            print(f"  {'all but the MHT step':<44s} {a:7.3f} / {b:7.3f} ({a / b:.2f})", flush=True)
            continue
        runs = [run(prepared) for _ in range(args.repeat)]
        scans, cpu, parts = min(runs, key=lambda r: r[1])
        print(f"{text}: {scans} scans, {cpu:.3f} ms CPU per scan (the whole update)")
        for _, _, label in PARTS:
            print(f"  {label:<44s} {parts.get(label, 0.0):7.3f} ms per scan")
        outside = cpu - parts.get("MHT step", 0.0)
        print(f"  {'all but the MHT step':<44s} {outside:7.3f} ms per scan", flush=True)


if __name__ == "__main__":
    main()
