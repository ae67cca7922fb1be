"""What the static world models cost in ``track``, this tree against another side by side
in one process, on the real recordings, for the trackers of points.

The other tree is imported as the package ``laserpeople_ab`` (``bench_track_ab.load_other``).
Per recording and tracker, each pass builds ``track``'s pipeline (``pipeline.build``, as
``laserpeople track BAG --tracker T`` does, without outputs) in both trees and steps the two
frame by frame in turn (who goes first alternates between passes), so both see the same
load. Per pass and tree: the static world models' CPU per frame (the stages that
``track``'s "static world model cost" line sums, ``static_world_cpu``) and the whole
loop's CPU per frame (reading, detection, static world models, tracking). Printed: the
medians over the passes, the ratio before/after, and whether every frame's tracks (ids,
kinds, positions, to the last bit) are the same in both trees.

    PYTHONPATH=src .venv/bin/python benchmarks/bench_background_ab.py --before OLD/src
        [--passes 5] [--bags follow lobby demo corridor] [--trackers csa group-mht feet-pf]
"""

from __future__ import annotations

import argparse
import importlib
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_track_ab import PACKAGE, load_other

DATA = Path("/work/shared/data")
BAGS = {
    "follow": DATA / "leg_tracker_benchmarks/person_following_outdoor_1_first.bag",
    "lobby": DATA / "leg_tracker_benchmarks/general_tracking_moving_1_first.bag",
    "demo": DATA / "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag",
    "corridor": DATA / "mir/rosbags/corridor/corridor.bag",
}
"""The recordings (``track``'s defaults for each: its first laser topic, the frame it
chooses)."""


def pipeline(package: str, bag: Path, tracker: str) -> Any:
    """``track``'s pipeline of ``bag`` with ``tracker``, built by the tree ``package``."""
    recording = importlib.import_module(f"{package}.pipeline.recording")
    return recording.build(bag, tracker=tracker)


def rows(tracks: Any) -> list[tuple[Any, ...]]:
    """Every track of a frame: id, kind and position."""
    if tracks is None:
        return []
    return [(t.track_id, t.kind, *t.position.tolist()) for t in tracks.tracks]


def one_pass(packages: list[str], bag: Path, tracker: str) -> tuple[dict[str, Any], int]:
    """Both trees' pipelines stepped frame by frame in turn, in the order of ``packages``:
    per tree the static world models' and the loop's CPU seconds per frame; and the
    number of frames whose tracks differ."""
    pipes = {p: pipeline(p, bag, tracker) for p in packages}
    steps = {p: iter(pipes[p]) for p in packages}
    loop = dict.fromkeys(packages, 0.0)
    frames = differ = 0
    clock = time.process_time
    while True:
        out = {}
        for p in packages:
            t0 = clock()
            out[p] = next(steps[p], None)
            loop[p] += clock() - t0
        if any(s is None for s in out.values()):
            assert all(s is None for s in out.values()), "the trees read different frames"
            break
        frames += 1
        a, b = (rows(out[p].tracks) for p in packages)
        differ += a != b
    result = {}
    for p in packages:
        static = importlib.import_module(f"{p}.pipeline.static_people")
        cpu = static.static_world_cpu(pipes[p])
        result[p] = {"static": cpu / frames, "loop": loop[p] / frames}
    return result, differ


def compare(bag: str, tracker: str, packages: list[str], passes: int) -> None:
    """Print the medians over ``passes`` of both trees on ``bag`` with ``tracker``."""
    seen: dict[str, dict[str, list[float]]] = {p: {"static": [], "loop": []} for p in packages}
    differ = 0
    for k in range(passes):
        order = packages if k % 2 == 0 else packages[::-1]
        result, d = one_pass(order, BAGS[bag], tracker)
        differ = max(differ, d)
        for p in packages:
            for part in ("static", "loop"):
                seen[p][part].append(result[p][part])
    before, after = packages
    cells = []
    for part in ("static", "loop"):
        b = statistics.median(seen[before][part])
        a = statistics.median(seen[after][part])
        cells.append(f"{1e3 * b:7.3f} {1e3 * a:7.3f} {b / a:6.2f}x")
    same = "same tracks" if differ == 0 else f"TRACKS DIFFER in {differ} frames"
    print(f"{bag:9s} {tracker:10s} {cells[0]}   {cells[1]}   {same}", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--before", type=Path, required=True, help="the other tree's src/")
    ap.add_argument("--passes", type=int, default=5)
    ap.add_argument("--bags", nargs="+", default=list(BAGS), choices=list(BAGS))
    ap.add_argument("--trackers", nargs="+", default=["csa", "group-mht", "feet-pf"])
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        load_other(args.before, Path(tmp))
        packages = [PACKAGE, "laserpeople"]
        print(f"ms per frame, median of {args.passes} interleaved passes; before after ratio")
        print(f"{'bag':9s} {'tracker':10s} {'static world model':>24s}   {'whole loop':>24s}")
        for bag in args.bags:
            for tracker in args.trackers:
                compare(bag, tracker, packages, args.passes)


if __name__ == "__main__":
    main()
