"""The leg MHT's branch-and-bound listing, this version against another, on recorded calls.

Runs the default tracker (as ``bench_track_parts.py`` does) on suite scenes and records every
call of ``list_children`` (the listing of a cluster's k best children, on plain floats); then
replays
the recorded calls with this version's listing and with the other version's (its
``tracking/mht/listing.py`` loaded as a module of its own), call by call alternately, in
rounds, and prints the CPU of each, their ratio, and how many calls gave the same children
(parents, labels, cost floats, order).

    PYTHONPATH=src .venv/bin/python benchmarks/bench_listing_replay.py --other OLD/src
        [--scenes crossing-3:1 randomised:0] [--seconds 30] [--rounds 3]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np

import laserpeople.tracking.mht.core as core
import laserpeople.tracking.mht.listing as listing
from bench_murty_replay import alternate, load_other, timed
from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.evaluation.suite import SuiteScene, frames_for, prepare
from laserpeople.tracking.mht.probability import DELETED, OCCLUDED
from people_suite import make_factory


def load_listing(src: Path) -> ModuleType:
    """The other version's ``laserpeople/tracking/mht/listing.py`` (it imports only numpy
    and this version's label constants and ``LabelledAssignment``)."""
    return load_other(src, "tracking/mht/listing.py", "listing_other")


Call = tuple[tuple[Any, ...], dict[str, Any]]
"""A recorded call: (args, kwargs)."""


def record(scenario: str, seed: int, seconds: float) -> list[Call]:
    """The ``list_children`` calls of one scene."""
    detector = AdaBoostLegDetector.default(LegDetectorParams())
    prepared = prepare(SuiteScene(scenario, scenario, seed, seconds), detector)
    tracker = make_factory("leg-mht", None, "auto")()
    calls: list[Call] = []
    original = core.list_children

    def wrapper(*args: Any, **kwargs: Any) -> Any:
        calls.append((args, dict(kwargs)))
        return original(*args, **kwargs)

    core.list_children = wrapper  # type: ignore[assignment]
    try:
        for frame in frames_for(prepared, frozenset(tracker.consumes)):
            tracker.update(frame)
    finally:
        core.list_children = original  # type: ignore[assignment]
    return calls


def as_arrays(args: tuple[Any, ...]) -> tuple[Any, ...]:
    """``list_children``'s arguments as ``enumerate_children``'s (the costs as arrays of
    -log; negating twice gives the same floats; the detected column of the label
    log-probabilities is unused by the listing)."""
    priors, rows, tm, c_occ, c_del, c_new, c_fal, *rest = args
    n, m = len(tm), len(c_new)
    lp = np.zeros((n, 3))
    lp[:, OCCLUDED] = -np.asarray(c_occ, dtype=np.float64)
    lp[:, DELETED] = -np.asarray(c_del, dtype=np.float64)
    cost = np.asarray(tm, dtype=np.float64).reshape(n, m)
    log_new = -np.asarray(c_new, dtype=np.float64)
    log_fal = -np.asarray(c_fal, dtype=np.float64)
    return (priors, rows, cost, lp, log_new, log_fal, *rest)


def children(module: ModuleType, call: Call) -> object:
    """One recorded call with ``module``'s listing, as comparable values."""
    args, kwargs = call
    if hasattr(module, "list_children"):
        out = module.list_children(*args, **kwargs)
    else:  # (an older version: the same costs as its arrays)
        out = module.enumerate_children(*as_arrays(args), **kwargs)
    if out is None:
        return None
    return [
        (i, d.track_label, tuple(d.track_measurement), d.measurement_label, d.cost.hex(), t.hex())
        for i, d, t in out
    ]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--other", type=Path, required=True, help="the other version's src/")
    ap.add_argument("--scenes", nargs="+", default=["crossing-3:1", "randomised:0"])
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    other = load_listing(args.other)
    modules = {"this": listing, "other": other}
    for text in args.scenes:
        scenario, seed = text.split(":")
        calls = record(scenario, int(seed), args.seconds)
        alternate(
            text,
            calls,
            lambda who, call: timed(lambda: children(modules[who], call)),
            args.rounds,
            " (listing)",
        )


if __name__ == "__main__":
    main()
