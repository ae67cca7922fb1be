"""What the pass over a whole recording before tracking costs (``[auto_background]
prelearn``): the per-beam histogram of a still laser, and the map of what stayed put in a
moving robot's recording (``background/recording_map.py``).

Run: ``PYTHONPATH=src .venv/bin/python benchmarks/bench_prelearn.py [--runs 5]``

Per real recording (``../shared/data``: the lobby bag of a robot driving among people, in
the world frame from its ``/tf``; the still demo bag), measured side by side in one process,
runs interleaved, medians:

* CPU of one plain read of the recording's frames (what any pass costs at least);
* CPU of :func:`~laserpeople.pipeline.prelearn.prelearn` (every pass it makes);
* for the moving robot, CPU of the counting alone
  (:func:`~laserpeople.pipeline.prelearn.count_recording_map` on frames already read) per
  frame, and its peak Python heap (tracemalloc, a separate run).

What the pass made is named last: the histogram of a still laser, or the map.
"""

from __future__ import annotations

import argparse
import statistics
import time
import tracemalloc
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, TypeVar

from laserpeople.frame import Frame
from laserpeople.pipeline.background import AutoBackground, StaticWorldParams
from laserpeople.pipeline.prelearn import count_recording_map, prelearn
from laserpeople.pipeline.preprocess import Fuse
from laserpeople.pipeline.recording import RecordingFrames, open_source, resolve_topics

_R = TypeVar("_R")

REPO = Path(__file__).resolve().parents[1]
DATA = REPO.parent / "shared" / "data"
RECORDINGS = {
    "lobby (moving)": DATA / "leg_tracker_benchmarks" / "general_tracking_moving_1_first.bag",
    "demo (still)": DATA
    / "leg_tracker"
    / "rosbags"
    / "demos"
    / "demo_stationary_simple_environment.bag",
}


def frames_of(path: Path) -> Callable[[], Iterator[Frame]]:
    """A fresh pass over the first laser topic of ``path``, as ``track`` reads it."""

    def open_frames() -> Iterator[Frame]:
        rec = open_source(path)
        frames = RecordingFrames(rec, resolve_topics(rec, None))
        try:
            yield from frames
        finally:
            frames.close()

    return open_frames


def cpu(fn: Callable[..., _R], *args: Any) -> tuple[float, _R]:
    """Process CPU time [s] of ``fn(*args)``, and what it returned."""
    start = time.process_time()
    out = fn(*args)
    return time.process_time() - start, out


def read_all(open_frames: Callable[[], Iterator[Frame]]) -> int:
    return sum(1 for _ in open_frames())


def learn(open_frames: Callable[[], Iterator[Frame]]) -> str:
    """Run the pass; what it made."""
    auto = AutoBackground()
    prelearn([Fuse(), auto], open_frames)
    learned = auto.prelearned
    return "map" if learned is not None and learned.grid_map is not None else "histogram"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    print(
        f"{'recording':16s} {'frames':>6s} {'read s':>7s} {'prelearn s':>10s} "
        f"{'ratio':>6s} {'count ms/frame':>14s} {'count heap MB':>13s}  made"
    )
    for name, path in RECORDINGS.items():
        if not path.exists():
            print(f"{name:16s} skipped: {path} not found")
            continue
        open_frames = frames_of(path)
        frames = list(open_frames())
        reads, passes, counts = [], [], []
        static = StaticWorldParams()
        for _ in range(args.runs):
            reads.append(cpu(read_all, open_frames)[0])
            seconds, made = cpu(learn, open_frames)
            passes.append(seconds)
            counts.append(cpu(count_recording_map, frames, static)[0])
        tracemalloc.start()
        count_recording_map(frames, static)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        read, passed = statistics.median(reads), statistics.median(passes)
        count = statistics.median(counts)
        counted = (
            f"{1e3 * count / len(frames):14.2f} {peak / 1e6:13.1f}"
            if made == "map"
            else f"{'-':>14s} {'-':>13s}"
        )
        print(
            f"{name:16s} {len(frames):6d} {read:7.2f} {passed:10.2f} {passed / read:6.2f} "
            f"{counted}  {made}"
        )


if __name__ == "__main__":
    main()
