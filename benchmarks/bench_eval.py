"""Speed of the tracking metrics: frames scored per second (median of repeats).

Run: ``.venv/bin/python benchmarks/bench_eval.py``. A scene of 10 people and 12 tracks
(two of them clutter), 10 000 frames, every metric of ``laserpeople evaluate``.
"""

from __future__ import annotations

import statistics
import time
import tracemalloc

import numpy as np

from laserpeople.evaluation import TrackingEvaluation
from laserpeople.evaluation.synthetic import synthetic_sequence


def scene(frames: int, people: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    truth = {
        p: rng.uniform(0, 10, 2) + np.cumsum(rng.normal(0, 0.05, (frames, 2)), axis=0)
        for p in range(people)
    }
    tracks = {100 + p: xy + rng.normal(0, 0.1, xy.shape) for p, xy in truth.items()}
    for k in range(2):
        tracks[500 + k] = rng.uniform(0, 10, 2) + np.cumsum(rng.normal(0, 0.05, (frames, 2)), 0)
    return synthetic_sequence(truth, tracks)


def run(truth, tracks, keep_frames: bool, trace: bool = False) -> tuple[float, float]:
    """Seconds and (with ``trace``, which slows the run) peak memory [MB] of scoring the
    whole scene once."""
    if trace:
        tracemalloc.start()
    start = time.perf_counter()
    ev = TrackingEvaluation(keep_frames=keep_frames)
    for t, tr in zip(truth, tracks, strict=True):
        ev.accumulate(t, tr)
    ev.result()
    if keep_frames:
        ev.frames()
    seconds = time.perf_counter() - start
    if not trace:
        return seconds, float("nan")
    peak = tracemalloc.get_traced_memory()[1] / 1e6
    tracemalloc.stop()
    return seconds, peak


def main() -> None:
    frames = 10_000
    truth, tracks = scene(frames, 10)
    for keep in (False, True):
        median = statistics.median(run(truth, tracks, keep)[0] for _ in range(3))
        peak = run(truth, tracks, keep, trace=True)[1]
        print(
            f"evaluate (keep_frames={keep}): 10 people, 12 tracks, {frames} frames: "
            f"median {median:.2f} s = {frames / median:,.0f} frames/s, "
            f"peak {peak:.2f} MB allocated while scoring"
        )


if __name__ == "__main__":
    main()
