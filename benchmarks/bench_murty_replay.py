"""Murty's method of the default leg MHT, this version against another, on recorded calls.

Runs the default tracker (as ``bench_track_parts.py`` does) on suite scenes and records
every call of ``k_best_children`` that goes to Murty's method (a parent problem too large
to list); then replays the recorded calls with this version's ``MurtyStream`` and with the
other version's (its ``tracking/assignment.py`` loaded as a module of its own), call by
call alternately, in rounds, and prints the CPU of each and their ratio, and whether the
children (parents, labels, cost floats, order) and the solve counts are the same.

    PYTHONPATH=src .venv/bin/python benchmarks/bench_murty_replay.py --other OLD/src
        [--scenes randomised:0 entrance-hall:1] [--seconds 30] [--rounds 3]
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib
import importlib.util
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import laserpeople.tracking.mht.core as core
import laserpeople.tracking.mht.matrix as matrix_mod
from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.evaluation.suite import SuiteScene, frames_for, prepare
from people_suite import make_factory


def load_other(src: Path, relative: str, name: str) -> ModuleType:
    """The other version's module ``src/laserpeople/<relative>`` as a module of its own,
    registered as ``name`` (the module must import nothing of the other version)."""
    spec = importlib.util.spec_from_file_location(name, src / "laserpeople" / relative)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def load_assignment(src: Path) -> ModuleType:
    """The other version's ``laserpeople/tracking/assignment.py`` (it imports numpy and
    scipy only, or this version's compiled solver)."""
    return load_other(src, "tracking/assignment.py", "assignment_other")


def record(scenario: str, seed: int, seconds: float) -> list[tuple[Any, ...]]:
    """The ``k_best_children`` calls of one scene that use Murty's method: (priors,
    matrices, args, kwargs, the work budget); prints the ceiling (see the module doc)."""
    detector = AdaBoostLegDetector.default(LegDetectorParams())
    prepared = prepare(SuiteScene(scenario, scenario, seed, seconds), detector)
    tracker = make_factory("leg-mht", None, "auto")()
    frames = frames_for(prepared, frozenset(tracker.consumes))
    calls: list[tuple[Any, ...]] = []
    original = core.k_best_children
    inside = [0.0, 0.0]  # CPU in k_best_children this scan; whether Murty was used

    def wrapper(priors: Any, matrices: Any, *args: Any, **kwargs: Any) -> Any:
        t0 = time.process_time()
        limit = kwargs.get("enumerate_limit", args[2] if len(args) > 2 else 32)
        if any(matrix_mod.enumerate_matchings(m, limit) is None for m in matrices):
            work = kwargs.get("work")
            budget = work.max_solves if work is not None else None
            calls.append((list(priors), list(matrices), args, dict(kwargs), budget))
            inside[1] = 1.0
        try:
            return original(priors, matrices, *args, **kwargs)
        finally:
            inside[0] += time.process_time() - t0

    whole, kbest, murty = [], [], []
    core.k_best_children = wrapper  # type: ignore[assignment]
    try:
        for frame in frames:
            inside[0] = inside[1] = 0.0
            t0 = time.process_time()
            tracker.update(frame)
            whole.append(time.process_time() - t0)
            kbest.append(inside[0])
            murty.append(inside[1])
    finally:
        core.k_best_children = original  # type: ignore[assignment]
    w, k = np.array(whole[20:]), np.array(kbest[20:])
    print(
        f"{scenario}:{seed}: {len(w)} scans, {np.mean(murty[20:]):.2f} with Murty's method; "
        f"CPU per scan median {1e3 * np.median(w):.2f} ms, without the k-best problems "
        f"{1e3 * np.median(w - k):.2f} ms ({np.median(w - k) / np.median(w):.3f}); mean "
        f"{1e3 * w.mean():.2f} ms, without {1e3 * (w - k).mean():.2f} ms "
        f"({(w - k).mean() / w.mean():.3f})",
        flush=True,
    )
    return calls


def replay(call: tuple[Any, ...]) -> tuple[Any, ...]:
    """One recorded call with whatever ``matrix_mod.MurtyStream`` is now: the children as
    comparable values, and the assignment problems solved."""
    return replay_whole(matrix_mod, call, call[1])


def alternate(
    text: str,
    calls: list[Any],
    run: Callable[[str, Any], tuple[object, float]],
    rounds: int,
    what: str,
) -> None:
    """Replay ``calls`` with ``run(who, call) -> (result, CPU seconds)`` for ``who`` "this"
    and "other", alternating which goes first call by call, and print per round the CPU of
    each, their ratio and how many calls gave the same result."""
    for r in range(rounds):
        spent = {"this": 0.0, "other": 0.0}
        same = 0
        for n, call in enumerate(calls):
            results = {}
            for who in ("this", "other") if (n + r) % 2 == 0 else ("other", "this"):
                results[who], seconds = run(who, call)
                spent[who] += seconds
            same += results["this"] == results["other"]
        ratio = spent["this"] / max(spent["other"], 1e-9)
        print(
            f"{text}, round {r + 1}{what}: {len(calls)} calls, this {spent['this']:.3f} s, "
            f"other {spent['other']:.3f} s, this/other {ratio:.3f}; same results: "
            f"{same} of {len(calls)}",
            flush=True,
        )


def timed(replay_one: Callable[[], object]) -> tuple[object, float]:
    """``replay_one()`` and the process CPU [s] it took."""
    t0 = time.process_time()
    out = replay_one()
    return out, time.process_time() - t0


def fresh_problems(module: ModuleType, matrices: list[Any]) -> list[Any]:
    """New ``AssignmentMatrix`` objects of ``module`` with the recorded problems' lists (no
    square made yet); a recorded subset of a base problem stays a subset of one new base
    when ``module`` has subsets that keep their base (this version)."""
    cls = module.AssignmentMatrix
    names = [f.name for f in dataclasses.fields(matrix_mod.AssignmentMatrix)][:8]
    keeps_base = "base" in {f.name for f in dataclasses.fields(cls)}
    bases: dict[int, Any] = {}
    out = []
    for m in matrices:
        base = getattr(m, "base", None)
        if keeps_base and base is not None:
            if id(base) not in bases:
                bases[id(base)] = cls(*[getattr(base, n) for n in names])
            out.append(bases[id(base)].subset(list(m.base_rows)))
        else:
            out.append(cls(*[getattr(m, n) for n in names]))
    return out


def replay_whole(module: ModuleType, call: tuple[Any, ...], matrices: list[Any]) -> tuple[Any, ...]:
    """One recorded call with ``module``'s ``k_best_children`` on ``matrices``: the children
    as comparable values, and the assignment problems solved."""
    priors, _, args, kwargs, budget = call
    kwargs = dict(kwargs)
    work = module.Work(max_solves=budget) if budget is not None else None
    if "work" in kwargs:
        kwargs["work"] = work
    out = module.k_best_children(priors, matrices, *args, **kwargs)
    flat = [
        (i, d.track_label, tuple(d.track_measurement), d.measurement_label, d.cost.hex(), t.hex())
        for i, d, t in out
    ]
    return flat, work.solves if work is not None else -1


def compare_whole(text: str, calls: list[tuple[Any, ...]], other: ModuleType, rounds: int) -> None:
    """``--whole``: this version's and the other's ``k_best_children`` alternately (each on
    fresh problems of its own, made outside the timing)."""
    modules = {"this": matrix_mod, "other": other}

    def run(who: str, call: tuple[Any, ...]) -> tuple[object, float]:
        problems = fresh_problems(modules[who], call[1])
        return timed(lambda: replay_whole(modules[who], call, problems))

    alternate(text, calls, run, rounds, " (whole k_best_children)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--other", type=Path, required=True, help="the other version's src/")
    ap.add_argument("--scenes", nargs="+", default=["randomised:0", "entrance-hall:1"])
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--whole", action="store_true", help="replay all of k_best_children")
    args = ap.parse_args()
    other = load_assignment(args.other)
    other_matrix = None
    if args.whole:
        from bench_track_ab import PACKAGE, load_other

        load_other(args.other, Path(tempfile.mkdtemp()))
        other_matrix = importlib.import_module(f"{PACKAGE}.tracking.mht.matrix")
    this_stream = matrix_mod.MurtyStream
    for text in args.scenes:
        scenario, seed = text.split(":")
        calls = record(scenario, int(seed), args.seconds)
        if other_matrix is not None:
            compare_whole(text, calls, other_matrix, args.rounds)
            continue
        for call in calls[:3]:  # warm both (compilation, caches)
            replay(call)

        def run(who: str, call: tuple[Any, ...]) -> tuple[object, float]:
            matrix_mod.MurtyStream = this_stream if who == "this" else other.MurtyStream  # type: ignore[misc]
            try:
                return timed(lambda: replay(call))
            finally:
                matrix_mod.MurtyStream = this_stream  # type: ignore[misc]

        alternate(text, calls, run, args.rounds, "")


if __name__ == "__main__":
    main()
