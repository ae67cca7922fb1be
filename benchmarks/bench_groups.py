"""Cycle time of the group tracker (000 Sec. 4.6.2): median CPU ms per scan by people in
view on the simulated entrance hall (up to 20 people), and on the real leg_tracker demo
bag (people walking past a static laser; foreground from the pipeline's static world
model) when the shared data are there.

CPU time of this process (``time.process_time``), so that other jobs on the machine do
not inflate it; ``laserpeople bench`` reports wall-clock time.

    PYTHONPATH=src python benchmarks/bench_groups.py [--seeds 3 4] [--seconds 60] [--no-bag]
        [--breakdown] [--against OTHER/src] [--preset default|paper] [--digest]
        [--min-ratio R]

``--breakdown`` also prints where the CPU time of the scans with 15-20 people in view goes
(median over those scans of each part's ms; parts nest as indented).

``--against OTHER/src`` compares this code with another checkout (e.g. the code before a
change) in lock step: two worker processes, one per code, track the same frames and take
turns scan by scan (which one goes first alternates), so both see the same load on a
shared machine; prints both medians and their ratio per bin of people in view.

``--preset paper`` runs 000's group tracker exactly (the ``paper`` preset of
docs/papers.md) instead of the defaults (``default``).

``--min-ratio R`` sets the MHT's ratio pruning (``mht.min_ratio``) of the preset, e.g.
``1e-3``, the group tracker's default before session 9 (now ``GROUP_MIN_RATIO``, 3e-3).

``--digest`` prints, per simulated run (and the bag), a SHA-256 of the tracker's whole
state after every scan (every hypothesis' log weight; every node's ids, label, counts,
state, covariance, contour, members, labels and history; the reported tracks and
events): equal digests of two codes mean bit-identical outputs.
"""

from __future__ import annotations

import argparse
import functools
import hashlib
import os
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from laserpeople.config import load_config
from laserpeople.evaluation.groups import frames_from_scans
from laserpeople.frame import Frame
from laserpeople.sim.scenarios import run_scenario
from laserpeople.tracking.groups import GroupMHTTracker, GroupTrackerParams

PARTS = (
    ("update (whole scan)", "laserpeople.tracking.groups.tracker", "GroupMHTTracker", "update"),
    ("  observe: clustering, blob counts", "laserpeople.tracking.groups.tracker",
     "GroupMHTTracker", "observe"),
    ("  MHT step", "laserpeople.tracking.mht.core", "MHT", "step"),
    ("    predict", "laserpeople.tracking.groups.model", "GroupModel", "predict"),
    ("    score (all calls, eqs. 19-24)", "laserpeople.tracking.groups.model", "GroupModel",
     "_score_nodes"),
    ("    updates of gated pairs, initiations", "laserpeople.tracking.mht.core", "MHT",
     "_prepare_children"),
    ("    model generation (branches)", "laserpeople.tracking.groups.interaction",
     "GroupBranches", "branches"),
    ("      re-clustering", "laserpeople.tracking.groups.interaction", "GroupBranches",
     "_recluster"),
    ("    k-best listing", "laserpeople.tracking.mht.core", "MHT", "_k_best"),
)  # fmt: skip
DEMO_BAG = "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag"
BINS = ((0, 4), (5, 9), (10, 14), (15, 20))
PRESETS = {
    "default": GroupTrackerParams,
    "paper": lambda: load_config(GroupTrackerParams, None, "paper"),
}


def preset_params(args: argparse.Namespace) -> GroupTrackerParams:
    """The parameters of ``args.preset`` with ``args.min_ratio`` (when given)."""
    params = PRESETS[args.preset]()
    if args.min_ratio is None:
        return params
    return replace(params, mht=replace(params.mht, min_ratio=args.min_ratio))


def digest(frames: list[Frame], params: GroupTrackerParams) -> str:
    """SHA-256 (hex) of a fresh tracker's state after every one of ``frames`` (see the
    module doc)."""
    tracker = GroupMHTTracker(params)
    h = hashlib.sha256()
    for frame in frames:
        out = tracker.update(frame)
        for c in tracker.mht.clusters:
            h.update(repr(sorted(c.families)).encode())
            for hyp in c.hypotheses:
                h.update(np.float64(hyp.log_weight).tobytes())
                for t in hyp.tracks:
                    p = t.payload
                    h.update(repr((t.node_id, t.family, t.parent_id, t.label, t.measurement,
                                   t.hits, t.misses, t.age, t.loglik, p.labels, p.must_match,
                                   p.event, p.merged_stamp)).encode())  # fmt: skip
                    for a in (t.mean, t.cov, p.contour, p.members):
                        h.update(np.ascontiguousarray(a).tobytes())
                    for stamp, pts in p.history:
                        h.update(np.float64(stamp).tobytes())
                        h.update(np.ascontiguousarray(pts).tobytes())
        h.update(repr([(t.track_id, t.size, t.labels, t.score) for t in out.tracks]).encode())
        h.update(repr([(e.stamp, e.kind, e.labels) for e in tracker.events]).encode())
    return h.hexdigest()


def time_frames(frames: list[Frame], params: GroupTrackerParams) -> np.ndarray:
    """CPU ms (F,) of each ``update`` of a fresh tracker over ``frames``."""
    tracker = GroupMHTTracker(params)
    out = np.empty(len(frames))
    for k, frame in enumerate(frames):
        t0 = time.process_time()
        tracker.update(frame)
        out[k] = (time.process_time() - t0) * 1e3
    return out


def instrument(spent: dict[str, float]) -> Callable[[], None]:
    """Wrap the functions of :data:`PARTS` so that their CPU time [ms] adds up in
    ``spent`` (nested calls of one function count once); returns the undo."""
    import importlib

    undo = []
    for label, module, cls_name, name in PARTS:
        cls = getattr(importlib.import_module(module), cls_name)
        orig = getattr(cls, name)
        depth = [0]

        def wrapped(*a: Any, _f: Any = orig, _l: str = label, _d: list[int] = depth,
                    **k: Any) -> Any:  # fmt: skip
            _d[0] += 1
            t0 = time.process_time()
            try:
                return _f(*a, **k)
            finally:
                _d[0] -= 1
                if _d[0] == 0:
                    spent[_l] = spent.get(_l, 0.0) + (time.process_time() - t0) * 1e3

        setattr(cls, name, functools.wraps(orig)(wrapped))
        undo.append((cls, name, orig))

    def restore() -> None:
        for cls, name, orig in undo:
            setattr(cls, name, orig)

    return restore


def breakdown(runs: list[tuple[list[Frame], np.ndarray]], params: GroupTrackerParams) -> None:
    """Print the median ms of each part of :data:`PARTS` over the frames with 15-20
    people in view, ``runs`` being (frames, people in view) per recording, each tracked
    by a fresh tracker (the wrappers add a little time of their own)."""
    spent: dict[str, float] = {}
    rows: list[dict[str, float]] = []
    restore = instrument(spent)
    try:
        for frames, people in runs:
            tracker = GroupMHTTracker(params)
            for frame, n in zip(frames, people, strict=True):
                spent.clear()
                tracker.update(frame)
                if 15 <= n <= 20:
                    rows.append(dict(spent))
    finally:
        restore()
    if not rows:
        return
    print(f"\nwhere the time goes, {len(rows)} scans with 15-20 people (median ms):\n")
    print("| part | median ms |")
    print("|---|---|")
    for label, *_ in PARTS:
        depth = (len(label) - len(label.lstrip())) // 2
        values = [r.get(label, 0.0) for r in rows]
        print(f"| {'. ' * depth}{label.strip()} | {np.median(values):.2f} |")


def demo_frames(root: Path) -> list[Frame]:
    """Frames of the real demo bag as the pipeline makes them for a foreground tracker."""
    from laserpeople.io import open_recording
    from laserpeople.pipeline import FrameChooser, Pipeline, laser_frames, observe_stages_for

    rec = open_recording(root / DEMO_BAG)
    try:
        scans = list(rec.scans(None))
    finally:
        rec.close()
    pre, obs = observe_stages_for(GroupMHTTracker.consumes, None)
    pipe = Pipeline(FrameChooser()(laser_frames(scans)), preprocess=pre, observe=obs)
    return [step.frame for step in pipe]


def hall_runs(
    scenario: str, seeds: list[int], seconds: float
) -> list[tuple[list[Frame], np.ndarray]]:
    """(frames, people in view (F,)) of each simulated run."""
    runs = []
    for seed in seeds:
        scans = run_scenario(scenario, seconds=seconds, seed=seed).scans
        labelled = list(frames_from_scans(scans))
        people = []
        for lf in labelled:
            seen = lf.true_person[np.asarray(lf.frame.foreground)]
            people.append(np.unique(seen[seen >= 0]).size)
        runs.append(([lf.frame for lf in labelled], np.asarray(people)))
    return runs


def worker(args: argparse.Namespace) -> None:
    """Lock-step worker: print the number of frames, then track one frame per line read
    from stdin and print its CPU ms and people in view (-1 for the bag)."""
    runs = [] if args.worker == "bag" else hall_runs(args.scenario, args.seeds, args.seconds)
    if args.worker == "bag":
        root = Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "/work/shared/data"))
        frames = demo_frames(root)
        runs = [(frames, np.full(len(frames), -1))]
    print(sum(len(f) for f, _ in runs), flush=True)
    for frames, people in runs:
        tracker = GroupMHTTracker(preset_params(args))
        for frame, n in zip(frames, people, strict=True):
            sys.stdin.readline()
            t0 = time.process_time()
            tracker.update(frame)
            print(f"{(time.process_time() - t0) * 1e3!r} {n}", flush=True)


def lock_step(args: argparse.Namespace, kind: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """CPU ms (F,) of this code and of ``args.against``, and people in view (F,), tracked
    in turns by two worker processes (see the module doc)."""
    import laserpeople

    here = str(Path(laserpeople.__file__).resolve().parents[1])
    cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", kind,
           "--scenario", args.scenario, "--seconds", str(args.seconds),
           "--seeds", *map(str, args.seeds), "--preset", args.preset,
           *([] if args.min_ratio is None else ["--min-ratio", repr(args.min_ratio)])]  # fmt: skip
    procs = []
    for src in (here, args.against):
        env = dict(os.environ, PYTHONPATH=src)
        procs.append(
            subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, env=env)
        )
    pipes = [(p.stdin, p.stdout) for p in procs]
    counts = {int(out.readline()) for _, out in pipes if out is not None}
    if len(counts) != 1:
        raise RuntimeError(f"the two codes made different numbers of frames: {counts}")
    n = counts.pop()
    ms = np.empty((2, n))
    people = np.empty(n, dtype=np.int64)
    for k in range(n):
        for w in (0, 1) if k % 2 == 0 else (1, 0):
            inp, out = pipes[w]
            assert inp is not None and out is not None
            inp.write("\n")
            inp.flush()
            value, seen = out.readline().split()
            ms[w, k], people[k] = float(value), int(seen)
    for p in procs:
        p.wait()
    return ms[0], ms[1], people


def print_against(args: argparse.Namespace) -> None:
    """The lock-step comparison with ``args.against`` (hall, then the demo bag)."""
    here, other, people = lock_step(args, "hall")
    print(f"{args.scenario}, seeds {args.seeds}, {args.seconds:g} s each, preset {args.preset}, "
          f"lock step: CPU ms per scan, this code vs {args.against}\n")  # fmt: skip
    print("| people in view | other | this | this / other | median of per-scan ratios | frames |")
    print("|---|---|---|---|---|---|")
    bins = [*BINS, (0, 10**6)]
    for lo, hi in bins:
        sel = (people >= lo) & (people <= hi)
        if sel.any():
            a, b = np.median(other[sel]), np.median(here[sel])
            name = f"{lo}-{hi}" if hi < 10**6 else "all"
            print(f"| {name} | {a:.2f} | {b:.2f} | {b / a:.2f} | "
                  f"{np.median(here[sel] / other[sel]):.2f} | {sel.sum()} |")  # fmt: skip
    root = Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "/work/shared/data"))
    if not args.no_bag and (root / DEMO_BAG).is_file():
        here, other, _ = lock_step(args, "bag")
        a, b = np.median(other), np.median(here)
        print(f"| real demo bag ({here.size} scans) | {a:.2f} | {b:.2f} | {b / a:.2f} | "
              f"{np.median(here / other):.2f} | {here.size} |")  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--scenario", default="entrance-hall")
    ap.add_argument("--seeds", type=int, nargs="+", default=[3, 4])
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--no-bag", action="store_true", help="skip the real demo bag")
    ap.add_argument("--breakdown", action="store_true", help="time the parts at 15-20 people")
    ap.add_argument("--against", default="", help="src directory of the code to compare with")
    ap.add_argument(
        "--preset",
        choices=sorted(PRESETS),
        default="default",
        help="default: the tracker's defaults; paper: 000's group tracker (docs/papers.md)",
    )
    ap.add_argument("--digest", action="store_true", help="print state digests, no timing")
    ap.add_argument(
        "--min-ratio", type=float, default=None, help="ratio pruning (mht.min_ratio), e.g. 1e-3"
    )
    ap.add_argument("--worker", default="", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        worker(args)
        return
    if args.against:
        print_against(args)
        return
    params = preset_params(args)
    runs = hall_runs(args.scenario, args.seeds, args.seconds)
    if args.digest:
        root = Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "/work/shared/data"))
        for seed, (frames, _) in zip(args.seeds, runs, strict=True):
            print(f"{args.scenario} seed {seed}, {args.seconds:g} s: {digest(frames, params)}")
        if not args.no_bag and (root / DEMO_BAG).is_file():
            print(f"demo bag: {digest(demo_frames(root), params)}")
        return
    ms = np.concatenate([time_frames(frames, params) for frames, _ in runs])
    people = np.concatenate([p for _, p in runs])
    print(f"{args.scenario}, seeds {args.seeds}, {args.seconds:g} s each, preset {args.preset}: "
          "CPU ms per scan\n")  # fmt: skip
    print("| people in view | median | p95 | frames |")
    print("|---|---|---|---|")
    for lo, hi in BINS:
        sel = ms[(people >= lo) & (people <= hi)]
        if sel.size:
            p95 = np.percentile(sel, 95)
            print(f"| {lo}-{hi} | {np.median(sel):.2f} | {p95:.2f} | {sel.size} |")
    print(f"| all | {np.median(ms):.2f} | {np.percentile(ms, 95):.2f} | {ms.size} |")
    if args.breakdown:
        breakdown(runs, params)
    root = Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "/work/shared/data"))
    if not args.no_bag and (root / DEMO_BAG).is_file():
        bag_ms = time_frames(demo_frames(root), params)
        print(
            f"\nreal demo bag ({DEMO_BAG}, {bag_ms.size} scans): median {np.median(bag_ms):.2f} "
            f"ms, p95 {np.percentile(bag_ms, 95):.2f} ms per scan (CPU)"
        )


if __name__ == "__main__":
    main()
