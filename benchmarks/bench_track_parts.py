"""Where the default leg MHT's CPU goes per scan, part by part, on suite scenes.

Runs the default tracker as ``people_suite.py`` and ``cost_vs_gnn.py`` run it (leg MHT,
people ``tracks``, re-identification, the static world model ``auto``) on each scene with
the parts of the MHT step wrapped in timers, and prints per scan: the process CPU of the
whole update, then the time inside each part (nested: the step holds the branching, which
holds the k-best problems, which are listed or go to Murty's method). It also counts what
Murty's method did: the assignment problems solved, those found infeasible, and those whose
solution cost more than the last child kept (solved for nothing, had a bound ruled them
out), with the children it returned.

The timers add some overhead of their own (a few per cent of the step); compare parts
within a run, not with ``cost_vs_gnn.py``.

    PYTHONPATH=src .venv/bin/python benchmarks/bench_track_parts.py
        [--scenes randomised:0 randomised:3 crossing-3:1 entrance-hall:1] [--seconds 30]
        [--cpu-parts]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections import Counter, defaultdict
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

import laserpeople.tracking.assignment as assignment
import laserpeople.tracking.mht.core as core
from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.evaluation.suite import SuiteScene, frames_for, prepare
from people_suite import make_factory

PARTS: list[tuple[Any, str, str]] = [
    (core.MHT, "step", "MHT step"),
    (core.MHT, "_branch", "  branching, general path"),
    (core.MHT, "_k_best", "    k-best problems"),
    (core, "list_children", "      listing (branch and bound)"),
    (core, "enumerate_children", "      listing (branch and bound)"),
    (core, "k_best_children", "      Murty's method"),
    (core.MHT, "_branch_lone", "  branching, one track per parent"),
    (core.MHT, "_prepare_children", "  Kalman updates of the gated pairs"),
    (core.MHT, "_fill_deferred", "  states of the kept children (deferred)"),
    (core.MHT, "_prune_children", "  normalising and pruning"),
    (core.MHT, "_expire", "  expiry of unseen tracks"),
]
"""(owner, attribute, label) of the parts timed; a part the code imported does not have (an
older version's, run with its ``src`` on PYTHONPATH) is left out. The plain
MHT makes its children's states at the end of the step (``_fill_deferred``), no longer per
gated pair before branching (``_prepare_children``)."""


def timed(
    seconds: dict[str, float],
    label: str,
    fn: Callable[..., Any],
    clock: Callable[[], float] = time.perf_counter,
) -> Callable[..., Any]:
    """``fn`` adding its time by ``clock`` (wall time by default) to ``seconds[label]``
    (nested calls of the same function are not counted twice: none of the parts calls
    itself)."""

    def wrapper(*args: Any, **kwargs: Any) -> Any:
        t0 = clock()
        try:
            return fn(*args, **kwargs)
        finally:
            seconds[label] += clock() - t0

    return wrapper


def murty_counts(counts: Counter[str], fn: Callable[..., Any]) -> Callable[..., Any]:
    """``core.k_best_children`` counting the assignment problems its streams solve (see
    the module doc)."""
    solved: list[tuple[float, float | None]] = []  # (the stream's parent cost, cost)
    stream_cls = assignment.MurtyStream
    original_refine = stream_cls.refine

    def refine(self: Any) -> None:
        if self.front_solved():
            return
        node = self._heap[0][2]
        original_refine(self)
        solved.append((getattr(self, "_bench_prior", 0.0), node.solution and node.solution.cost))

    def wrapper(priors: Any, matrices: Any, *args: Any, **kwargs: Any) -> Any:
        solved.clear()
        stream_cls.refine = refine  # type: ignore[method-assign]
        matrix_mod = sys.modules["laserpeople.tracking.mht.matrix"]
        original_init = matrix_mod._MatchingStream.__init__
        prior_of = {id(m): p for p, m in zip(priors, matrices, strict=True)}

        def init(self: Any, matrix: Any, limit: int) -> None:
            original_init(self, matrix, limit)
            if self._murty is not None:
                self._murty._bench_prior = prior_of[id(matrix)]

        matrix_mod._MatchingStream.__init__ = init
        try:
            out = fn(priors, matrices, *args, **kwargs)
        finally:
            stream_cls.refine = original_refine  # type: ignore[method-assign]
            matrix_mod._MatchingStream.__init__ = original_init
        last = out[-1][2] if out else math.inf
        counts["calls"] += 1
        counts["children"] += len(out)
        counts["solved"] += len(solved)
        counts["infeasible"] += sum(1 for _, c in solved if c is None)
        counts["above the last child"] += sum(
            1 for p, c in solved if c is not None and p + c > last
        )
        return out

    return wrapper


def run(
    scenario: str, seed: int, seconds: float, cpu_parts: bool = False
) -> tuple[int, float, dict[str, float], Counter[str]]:
    """Scans, process CPU ms per scan of the whole update, ms per scan in each part (wall
    time, or process CPU time with ``cpu_parts``: on a loaded machine the wall time of a
    part holds the time other jobs ran), and Murty's counts, for one scene."""
    detector = AdaBoostLegDetector.default(LegDetectorParams())
    prepared = prepare(SuiteScene(scenario, scenario, seed, seconds), detector)
    tracker = make_factory("leg-mht", None, "auto")()
    frames = frames_for(prepared, frozenset(tracker.consumes))
    spent: dict[str, float] = defaultdict(float)
    counts: Counter[str] = Counter()
    parts = [part for part in PARTS if hasattr(part[0], part[1])]
    saved = [(owner, name, getattr(owner, name)) for owner, name, _ in parts]
    try:
        for owner, name, label in parts:
            fn = getattr(owner, name)
            if name == "k_best_children":
                fn = murty_counts(counts, fn)
            clock = time.process_time if cpu_parts else time.perf_counter
            setattr(owner, name, timed(spent, label, fn, clock))
        t0 = time.process_time()
        for frame in frames:
            tracker.update(frame)
        cpu = time.process_time() - t0
    finally:
        for owner, name, fn in saved:
            setattr(owner, name, fn)
    n = max(len(frames), 1)
    per_scan = {label: 1e3 * spent[label] / n for _, _, label in parts}
    return len(frames), 1e3 * cpu / n, per_scan, counts


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument(
        "--scenes",
        nargs="+",
        default=["randomised:0", "randomised:3", "crossing-3:1", "entrance-hall:1"],
        help="SCENARIO:SEED (tuning seeds only)",
    )
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument(
        "--cpu-parts",
        action="store_true",
        help="time the parts by process CPU time instead of wall time (a loaded machine)",
    )
    args = ap.parse_args()
    for text in args.scenes:
        scenario, seed = text.split(":")
        scans, cpu, parts, counts = run(scenario, int(seed), args.seconds, args.cpu_parts)
        print(f"{text}: {scans} scans, {cpu:.2f} ms CPU per scan (the whole update)")
        for _, _, label in PARTS:
            if label in parts:
                print(f"  {label:<40s} {parts[label]:7.3f} ms per scan")
        if counts["calls"]:
            print(
                f"  Murty's method: {counts['calls']} clusters, {counts['children']} children, "
                f"{counts['solved']} assignment problems solved, {counts['infeasible']} "
                f"infeasible, {counts['above the last child']} costing more than the last "
                "child kept",
                flush=True,
            )


if __name__ == "__main__":
    main()
