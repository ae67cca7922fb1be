"""Speed of the leg MHT against another version of the code, in one process (A/B).

On a shared machine the CPU time of a run drifts by tens of per cent with the other jobs'
load, so two runs minutes apart cannot be compared. This script imports both versions in
one process (the other version's ``src/laserpeople`` copied to a temporary directory as
the package ``laserpeople_ab``) and updates the two trackers alternately, scan by scan, on
the same synthetic crowd as ``bench_track.py`` (4 and 20 people by default), so both see
the same load; it prints the median process CPU per scan of each and their ratio per round
(the order within a pair alternates between rounds), and the same for the mean, on which
the rare scans with large clusters weigh. The other version's results are
compared too: the reported tracks must be the same, or the script says where they differ.

With ``--parts`` it also times the parts of the MHT step of both versions (those of
``bench_track_parts.py``, by process CPU time, accumulated over the alternated scans) and
prints them per round side by side, with their ratio.

With ``--scenes`` it runs instead the default tracker as ``benchmarks/people_suite.py`` and
``cost_vs_gnn.py`` run it (leg MHT, people ``tracks``, the static world model ``auto`` fed
from each frame) on suite scenes, each simulated and detected by both versions, and
compares every scan's person and leg tracks.

    PYTHONPATH=src .venv/bin/python benchmarks/bench_track_ab.py --other /path/to/old/src
        [--people 4 20] [--seconds 30] [--rounds 3]
        [--scenes randomised:0 randomised:3 crossing-3:1 ...] [--parts]
"""

from __future__ import annotations

import argparse
import importlib
import re
import shutil
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_track import crowd_scene

PACKAGE = "laserpeople_ab"
RATE = 37.5
"""Scan rate of the scene [Hz], as bench_track's default."""


def load_other(src: Path, into: Path) -> ModuleType:
    """The package ``src/laserpeople`` copied to ``into`` under the name ``laserpeople_ab``
    (its imports of itself renamed: ``from laserpeople.x``, ``import laserpeople``, module
    paths in strings; not its file formats' names such as ``laserpeople-recording``) and
    imported."""
    target = into / PACKAGE
    shutil.copytree(src / "laserpeople", target)
    pattern = re.compile(r"\blaserpeople(?=\.[a-z_])|(?<=import )laserpeople\b")
    for path in target.rglob("*.py"):
        path.write_text(pattern.sub(PACKAGE, path.read_text()))
    sys.path.insert(0, str(into))
    return importlib.import_module(PACKAGE)


def setup(package: str, n_people: int, seconds: float) -> tuple[list[Any], Any]:
    """The scene's detections (``bench_track.crowd_scene``) and a default leg MHT, both
    from ``package``."""
    syn = importlib.import_module(f"{package}.tracking.synthetic")
    registry = importlib.import_module(f"{package}.tracking.registry")
    scene = crowd_scene(n_people, seconds, RATE, synthetic=syn)
    entry = registry.get("leg-mht")
    frame_tracker = entry.factory(entry.params_cls())
    tracker = getattr(frame_tracker, "tracker", None) or frame_tracker
    return list(scene.detections), tracker


def prepare_scene(scenario: str, seed: int, seconds: float) -> Any:
    """A suite scene simulated and detected by this version (the simulator and detector
    are not what is compared; both trackers get the same detections)."""
    from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
    from laserpeople.evaluation.suite import SuiteScene, prepare

    detector = AdaBoostLegDetector.default(LegDetectorParams())
    return prepare(SuiteScene(scenario, scenario, seed, seconds), detector)


def setup_scene(package: str, prepared: Any) -> tuple[list[Any], Any]:
    """The frames of a prepared scene and ``package``'s default frame tracker with its
    static world model, as ``people_suite.make_factory`` makes it."""
    from laserpeople.evaluation.suite import frames_for

    static = importlib.import_module(f"{package}.pipeline.static_people")
    registry = importlib.import_module(f"{package}.tracking.registry")
    entry = registry.get("leg-mht")
    tracker = entry.factory(entry.params_cls())
    if static.uses_static_model(tracker):
        model = static.people_static_model("auto")
        tracker.use_static_model(model)
        if model is not None:
            tracker = static.StaticFed(tracker, model)
    return frames_for(prepared, frozenset(tracker.consumes)), tracker


def time_parts(package: str, spent: dict[str, float]) -> None:
    """Wrap the MHT parts of ``bench_track_parts.PARTS`` in ``package`` (those it has) so
    that their process CPU time adds up in ``spent`` by label."""
    import bench_track_parts

    ours = importlib.import_module("laserpeople.tracking.mht.core")
    core = importlib.import_module(f"{package}.tracking.mht.core")
    for owner, name, label in bench_track_parts.PARTS:
        target = core.MHT if owner is ours.MHT else core
        if hasattr(target, name):
            fn = bench_track_parts.timed(spent, label, getattr(target, name), time.process_time)
            setattr(target, name, fn)


def print_parts(spent: dict[str, dict[str, float]], scans: int) -> None:
    """The parts' ms per scan of this and the other version, and their ratio."""
    import bench_track_parts

    for _, _, label in bench_track_parts.PARTS:
        a, b = spent["this"].get(label), spent["other"].get(label)
        if a is None and b is None:
            continue
        ta = f"{1e3 * a / scans:7.3f}" if a is not None else "      -"
        tb = f"{1e3 * b / scans:7.3f}" if b is not None else "      -"
        ratio = f"{a / b:.3f}" if a is not None and b else "-"
        print(f"    {label:<42s} this {ta}  other {tb} ms/scan  this/other {ratio}")


def rows(tracks: Any, score: bool = True) -> list[tuple[Any, ...]]:
    """The reported tracks of one scan as comparable rows (``score=False``: without their
    scores, the probabilities of their clusters' best hypotheses; ids, members and states
    only)."""
    return [
        (
            t.track_id,
            t.kind,
            t.members,
            t.score if score else None,
            t.position.tobytes(),
            t.covariance.tobytes(),
        )
        for t in tracks
    ]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--other", type=Path, required=True, help="the other version's src/")
    ap.add_argument("--people", type=int, nargs="+", default=[4, 20])
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument(
        "--scenes",
        nargs="+",
        default=None,
        help="suite scenes SCENARIO:SEED (default tracker with its static model) instead "
        "of the crowds",
    )
    ap.add_argument("--parts", action="store_true", help="time the MHT step's parts too")
    args = ap.parse_args()
    runs: list[tuple[str, Any]] = [(f"{n:3d} people", n) for n in args.people]
    if args.scenes:
        runs = [(text, tuple(text.split(":"))) for text in args.scenes]
    with tempfile.TemporaryDirectory() as tmp:
        load_other(args.other, Path(tmp))
        spent: dict[str, dict[str, float]] = {
            "this": defaultdict(float),
            "other": defaultdict(float),
        }
        if args.parts:
            time_parts("laserpeople", spent["this"])
            time_parts(PACKAGE, spent["other"])
        for label, what in runs:
            prepared = None
            if isinstance(what, tuple):
                prepared = prepare_scene(what[0], int(what[1]), args.seconds)
            for r in range(args.rounds):
                if prepared is not None:
                    this_dets, this = setup_scene("laserpeople", prepared)
                    other_dets, other = setup_scene(PACKAGE, prepared)
                else:
                    this_dets, this = setup("laserpeople", what, args.seconds)
                    other_dets, other = setup(PACKAGE, what, args.seconds)
                cpu: dict[str, list[float]] = {"this": [], "other": []}
                for side in spent.values():
                    side.clear()
                differ = states = 0
                for scan, (d_this, d_other) in enumerate(zip(this_dets, other_dets, strict=True)):
                    pair = [("this", this, d_this), ("other", other, d_other)]
                    if r % 2:
                        pair.reverse()
                    out = {}
                    for name, tracker, d in pair:
                        t0 = time.process_time()
                        out[name] = tracker.update(d)
                        cpu[name].append(time.process_time() - t0)
                    if rows(out["this"]) != rows(out["other"]):
                        differ += 1
                        if differ == 1:
                            print(f"  tracks differ first at scan {scan}")
                        states += rows(out["this"], False) != rows(out["other"], False)
                a, b = 1e3 * np.median(cpu["this"]), 1e3 * np.median(cpu["other"])
                ma, mb = 1e3 * np.mean(cpu["this"]), 1e3 * np.mean(cpu["other"])
                print(
                    f"{label}, round {r + 1}: this {a:.3f} ms/scan, other {b:.3f} ms/scan "
                    f"(median process CPU), this/other {a / b:.3f}; mean {ma:.3f} / {mb:.3f} "
                    f"ms/scan, this/other {ma / mb:.3f}; scans with different "
                    f"tracks: {differ} ({states} beyond the scores)",
                    flush=True,
                )
                if args.parts:
                    print_parts(spent, len(cpu["this"]))


if __name__ == "__main__":
    main()
