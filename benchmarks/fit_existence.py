"""Fit the moving robot's existence evidence table (``people.existence``) from labels.

Tracks the real lobby dev recording of the leg_tracker benchmark
(``general_tracking_moving_1_first``, its 57 labels on scans 133-257) and the moving-robot
simulated family's tuning seeds (0-9, never the held-back 100-119) with the given
settings, logs the evidence class and range row of every person candidate on every scan
(:attr:`PersonTracker.evidence_log`), counts those within ``--near`` of a labelled person
as "person" and those farther than ``--far`` from every one as "clutter" (the dev
recording: on its labelled scans only), and prints the fitted log-likelihood ratios
(:func:`laserpeople.tracking.existence.fit_table`) with the counts. ``--write`` writes them
as a TOML the tracker reads (``--config``); the shipped defaults are this script's output.

    PYTHONPATH=src python benchmarks/fit_existence.py [--config params.toml]
        [--seeds 0-9] [--seconds 30] [--no-dev] [--write existence.toml]
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterable, Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

sys.path.insert(0, str(Path(__file__).resolve().parent))

from moving_people import TOPIC, default_paths, read_labels  # noqa: E402
from people_suite import make_factory, parse_seeds  # noqa: E402

from laserpeople.config import load_config  # noqa: E402
from laserpeople.detection.detector import AdaBoostLegDetector  # noqa: E402
from laserpeople.evaluation.suite import SuiteScene, frames_for, prepare  # noqa: E402
from laserpeople.pipeline import build  # noqa: E402
from laserpeople.tracking import registry  # noqa: E402
from laserpeople.tracking.existence import (  # noqa: E402
    EVIDENCE_CLASSES,
    RANGE_NAMES,
    fit_table,
)
from laserpeople.tracking.legs import LegTrackerParams  # noqa: E402
from laserpeople.tracking.person_tracks import PersonTracker  # noqa: E402

Log = list[tuple[float, int, float, float, int, int]]
Counts = NDArray[np.int64]


def person_layer(tracker: Any) -> PersonTracker:
    """The person tracker inside the wrappers (``.tracker`` chain) of a leg MHT."""
    obj = tracker
    for _ in range(6):
        people = getattr(obj, "person_tracks", None)
        if isinstance(people, PersonTracker):
            return people
        obj = getattr(obj, "tracker", None)
        if obj is None:
            break
    raise ValueError("no person layer of the 'tracks' people policy in this tracker")


def count(
    log: Log, truth: Mapping[float, NDArray[np.float64]], near: float, far: float
) -> tuple[Counts, Counts]:
    """Person and clutter counts (3 ranges, 6 classes) of the logged evidence whose scan
    (by time) has truth positions (P, 2) [m] in ``truth``."""
    n = (len(RANGE_NAMES), len(EVIDENCE_CLASSES))
    person, clutter = np.zeros(n, np.int64), np.zeros(n, np.int64)
    for stamp, _, x, y, row, c in log:
        xy = truth.get(stamp)
        if xy is None:
            continue
        d = float(np.min(np.hypot(xy[:, 0] - x, xy[:, 1] - y))) if len(xy) else np.inf
        if d <= near:
            person[row, c] += 1
        elif d > far:
            clutter[row, c] += 1
    return person, clutter


def dev_counts(
    params: LegTrackerParams, near: float, far: float, bag: Path, labels: Path
) -> tuple[Counts, Counts]:
    """Counts on the labelled scans of the real dev recording (labels moved to the world
    frame with each scan's laser pose)."""
    tracker = registry.get("leg-mht").make(params)
    pipe = build(bag, tracker=tracker, topics=[TOPIC], detector=AdaBoostLegDetector.default())
    lab = read_labels(labels)
    truth: dict[float, NDArray[np.float64]] = {}
    log: Log = []
    person_layer(tracker).evidence_log = log
    for step in pipe:
        f = step.frame
        if f.index in lab and f.sensor_pose is not None:
            xy = np.array(list(lab[f.index].values()), dtype=np.float64)
            truth[f.stamp] = f.sensor_pose.transform_points(xy)
    return count(log, truth, near, far)


def sim_counts(
    config: Path | None,
    family: str,
    seeds: Iterable[int],
    seconds: float,
    near: float,
    far: float,
) -> tuple[Counts, Counts]:
    """Counts on the simulated ``family``'s ``seeds`` (every scan has truth)."""
    detector = AdaBoostLegDetector.default()
    make = make_factory("leg-mht", config)
    n = (len(RANGE_NAMES), len(EVIDENCE_CLASSES))
    person, clutter = np.zeros(n, np.int64), np.zeros(n, np.int64)
    for seed in seeds:
        prepared = prepare(SuiteScene(family, family, seed, seconds), detector)
        tracker = make()
        log: Log = []
        person_layer(tracker).evidence_log = log
        for frame in frames_for(prepared, frozenset(tracker.consumes)):
            tracker.update(frame)
        truth = {t.stamp: t.positions for t in prepared.truth}
        p, c = count(log, truth, near, far)
        person += p
        clutter += c
        print(
            f"{family} seed {seed}: {int(p.sum())} person, {int(c.sum())} clutter candidate-scans"
        )
    return person, clutter


def to_toml(table: NDArray[np.float64]) -> str:
    """The ``[leg_tracker.people.existence]`` table of fitted values."""
    lines = ["[leg_tracker.people.existence]"]
    for name, row in zip(RANGE_NAMES, table, strict=True):
        lines.append(f"llr_{name} = [{', '.join(f'{v:.2f}' for v in row)}]")
    return "\n".join(lines) + "\n"


def main() -> None:
    bag, labels = default_paths()
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--config", type=Path, help="TOML of the settings to run while fitting")
    ap.add_argument("--seeds", default="0-9", help="tuning seeds (never the held-back 100-119)")
    ap.add_argument(
        "--family",
        action="append",
        help="simulated families (default: moving-robot and randomised)",
    )
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--no-dev", action="store_true", help="leave out the real dev recording")
    ap.add_argument("--bag", type=Path, default=bag)
    ap.add_argument("--labels", type=Path, default=labels)
    ap.add_argument("--near", type=float, default=0.5, help="person: within this of a label [m]")
    ap.add_argument("--far", type=float, default=1.0, help="clutter: beyond this from all [m]")
    ap.add_argument("--smoothing", type=float, default=1.0, help="Laplace smoothing")
    ap.add_argument("--write", type=Path, help="write the fitted table as TOML here")
    args = ap.parse_args()
    seeds = parse_seeds(args.seeds)
    if set(seeds) & set(range(100, 120)):
        ap.error("seeds 100-119 are held back: never fit on them")
    params = load_config(LegTrackerParams, args.config)
    params = replace(params, people_policy="tracks")
    shape = (len(RANGE_NAMES), len(EVIDENCE_CLASSES))
    person, clutter = np.zeros(shape, np.int64), np.zeros(shape, np.int64)
    if not args.no_dev:
        if not args.bag.exists():
            ap.error(f"{args.bag} not found: give --bag/--labels or --no-dev")
        p, c = dev_counts(params, args.near, args.far, args.bag, args.labels)
        print(f"dev recording: {int(p.sum())} person, {int(c.sum())} clutter candidate-scans")
        person += p
        clutter += c
    for family in args.family or ["moving-robot", "randomised"]:
        sp, sc = sim_counts(args.config, family, seeds, args.seconds, args.near, args.far)
        person += sp
        clutter += sc
    table = fit_table(person, clutter, args.smoothing)
    print(f"{'range':6s} " + " ".join(f"{c:>11s}" for c in EVIDENCE_CLASSES))
    for name, prow, crow, lrow in zip(RANGE_NAMES, person, clutter, table, strict=True):
        print(f"{name:6s} " + " ".join(f"{a:5d}/{b:<5d}" for a, b in zip(prow, crow, strict=True)))
        print(f"{'llr':6s} " + " ".join(f"{v:11.2f}" for v in lrow))
    text = to_toml(table)
    print(text, end="")
    if args.write is not None:
        if args.config is not None and args.write.resolve() == args.config.resolve():
            ap.error("--write would overwrite the --config it read: give another path")
        args.write.write_text(text)
        print(f"wrote {args.write}")


if __name__ == "__main__":
    main()
