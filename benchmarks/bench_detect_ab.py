"""The leg detector of this tree against another, side by side in one process (A/B).

Both trees' shipped AdaBoost detectors classify the same scans (the real demo bag and the
simulated halls of ``bench_scaling.py``, 4 people or ``--people``, read once); the other tree is
imported as the package ``laserpeople_ab`` (``bench_track_ab.load_other``). Per pass each
tree segments, featurises and scores every scan (``classify``), then scores the
classifiable segments of every scan once more on their own (``decision_function``: the
AdaBoost part), then detects the legs in blocks of 16 scans as ``track`` does
(``detect_many``); who goes first alternates between passes. Printed per recording: median
process CPU per scan over the passes for the whole classification, the AdaBoost part and
the blocks' detection, their ratio other/this, and whether the two trees gave the same
features, scores and legs, and the same detections (positions and scores), bit for bit.

    PYTHONPATH=src .venv/bin/python benchmarks/bench_detect_ab.py --other /path/to/old/src
        [--passes 7] [--max-scans 400] [--halls /tmp/halls]
"""

from __future__ import annotations

import argparse
import importlib
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_scaling import DEMO_BAG, hall_recording
from bench_track_ab import PACKAGE, load_other


def scans_of(path: Path, limit: int) -> list[Any]:
    """The first ``limit`` scans of the recording ``path`` (this tree's reader)."""
    from laserpeople.io import open_recording

    rec = open_recording(path)
    try:
        out = []
        for scan in rec.scans():
            out.append(scan)
            if len(out) == limit:
                break
        return out
    finally:
        rec.close()


def as_package(package: str, scans: list[Any]) -> list[Any]:
    """The scans as ``package``'s own Scan objects (the same arrays)."""
    cls = importlib.import_module(f"{package}.scan").Scan
    return [cls(**{f: getattr(s, f) for f in s.__dataclass_fields__}) for s in scans]


def compare(name: str, scans: list[Any], packages: list[str], passes: int) -> None:
    """Time and compare the packages' detectors on ``scans`` (see the module doc)."""
    dets = {
        p: importlib.import_module(f"{p}.detection.detector").AdaBoostLegDetector.default()
        for p in packages
    }
    own = {p: as_package(p, scans) for p in packages}
    whole: dict[str, list[float]] = {p: [] for p in packages}
    boost: dict[str, list[float]] = {p: [] for p in packages}
    blocks: dict[str, list[float]] = {p: [] for p in packages}
    results: dict[str, list[Any]] = {}
    found: dict[str, list[Any]] = {}
    for k in range(passes):
        for p in packages if k % 2 == 0 else packages[::-1]:
            det = dets[p]
            det.reset()
            t0 = time.process_time()
            got = [det.classify(s) for s in own[p]]
            whole[p].append((time.process_time() - t0) / len(scans))
            results[p] = got
            rows = [r.features.values[~np.isnan(r.scores)][:, det._columns] for r in got]
            clf = det.model.classifier
            t0 = time.process_time()
            for x in rows:
                clf.decision_function(x)
            boost[p].append((time.process_time() - t0) / len(scans))
            det.reset()
            t0 = time.process_time()
            legs = [
                d for i in range(0, len(scans), 16) for d in det.detect_many(own[p][i : i + 16])
            ]
            blocks[p].append((time.process_time() - t0) / len(scans))
            found[p] = legs
    a, b = (results[p] for p in packages)
    same_features = all(
        np.array_equal(x.features.values, y.features.values, equal_nan=True)
        for x, y in zip(a, b, strict=True)
    )
    same_scores = all(
        np.array_equal(x.scores, y.scores, equal_nan=True) for x, y in zip(a, b, strict=True)
    )
    same_legs = all(np.array_equal(x.is_leg, y.is_leg) for x, y in zip(a, b, strict=True))
    same_detections = all(
        np.array_equal(x.positions, y.positions) and np.array_equal(x.scores, y.scores)
        for x, y in zip(*(found[p] for p in packages), strict=True)
    )
    other, this = packages
    print(f"\n{name}: {len(scans)} scans, {passes} passes, median CPU ms per scan")
    for label, times in (
        ("classify (segments, features, AdaBoost)", whole),
        ("AdaBoost", boost),
        ("detect_many, blocks of 16 (as track)", blocks),
    ):
        o, t = statistics.median(times[other]), statistics.median(times[this])
        print(f"  {label:42s} other {1e3 * o:7.3f}  this {1e3 * t:7.3f}  other/this {o / t:5.2f}x")
    print(f"  same features: {same_features}, same scores: {same_scores}, same legs: {same_legs}")
    print(f"  same detections in blocks: {same_detections}")


def add_recording_arguments(ap: argparse.ArgumentParser) -> None:
    """``--halls``, ``--people`` and ``--data``: where the simulated halls are kept, how
    many people walk in them, and where the shared data are."""
    ap.add_argument("--halls", type=Path, help="keep the simulated halls here (reused)")
    ap.add_argument(
        "--people", type=int, nargs="+", default=[4], help="a hall with this many people each"
    )
    ap.add_argument(
        "--data",
        type=Path,
        default=Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "/work/shared/data")),
    )


def recordings(args: argparse.Namespace, tmp: Path) -> list[tuple[str, Path]]:
    """(name, path) of the real demo bag (when the shared data hold it; said when not) and
    of the simulated halls with ``args.people`` people (simulated into ``args.halls`` or
    ``tmp`` once)."""
    out = []
    bag = args.data / DEMO_BAG
    if bag.exists():
        out.append(("real demo bag (512 beams)", bag))
    else:
        print(f"no demo bag at {bag}: left out (--data names the shared data)")
    halls = args.halls or tmp
    halls.mkdir(parents=True, exist_ok=True)
    for people in getattr(args, "people", [4]):
        hall = halls / f"hall-{people:02d}-8s.npz"
        if not hall.exists():
            hall_recording(people, 8.0, hall)
        out.append((f"hall, {people} people (1081 beams)", hall))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--other", type=Path, required=True, help="the other tree's src/")
    ap.add_argument("--passes", type=int, default=7)
    ap.add_argument("--max-scans", type=int, default=400)
    add_recording_arguments(ap)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        load_other(args.other, Path(tmp))
        packages = [PACKAGE, "laserpeople"]
        for name, path in recordings(args, Path(tmp)):
            compare(name, scans_of(path, args.max_scans), packages, args.passes)


if __name__ == "__main__":
    main()
