"""Speed of the pipeline's stages on one sequence of scans: per-scan times and throughput.

Each stage runs over the same scans ``repeats`` times from a fresh state; per-scan times
of all repeats are pooled for the median and 95th percentile, and throughput is the
median over repeats of scans per second. Tracking is timed on detections computed once,
so its figure excludes detection.

Wall time is what a user waits; on a machine shared with other work it also holds the time
other processes ran. The process CPU time (``time.process_time``) of the same steps is
recorded too: what the stage itself costs, the figure to compare across runs there.

Example:
    >>> t = time_per_item("detect", lambda: detector.detect, scans)   # doctest: +SKIP
    >>> t.median_ms, t.scans_per_s                                    # doctest: +SKIP

"""

from __future__ import annotations

import resource
import sys
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from laserpeople.scan import Scan


@dataclass(frozen=True)
class StageTiming:
    """How fast one stage ran.

    Attributes:
        stage: Stage name, e.g. ``"detect"`` or ``"track leg-mht"``.
        scans: Scans per repeat.
        repeats: Number of repeats.
        median_ms: Median time per scan over all repeats [ms].
        p95_ms: 95th percentile of the time per scan [ms].
        scans_per_s: Median over repeats of scans per second (whole-pass throughput).
        cpu_median_ms: Median process CPU time per scan over all repeats [ms].
        cpu_scans_per_s: Median over repeats of scans per second of process CPU time.
    """

    stage: str
    scans: int
    repeats: int
    median_ms: float
    p95_ms: float
    scans_per_s: float
    cpu_median_ms: float = float("nan")
    cpu_scans_per_s: float = float("nan")

    def as_dict(self) -> dict[str, Any]:
        """The timing as a JSON-ready dictionary."""
        return {
            "stage": self.stage,
            "scans": self.scans,
            "repeats": self.repeats,
            "median_ms": self.median_ms,
            "p95_ms": self.p95_ms,
            "scans_per_s": self.scans_per_s,
            "cpu_median_ms": self.cpu_median_ms,
            "cpu_scans_per_s": self.cpu_scans_per_s,
        }


def time_per_item(
    stage: str,
    make_step: Callable[[], Callable[[Any], object]],
    items: Sequence[Any],
    repeats: int = 3,
) -> StageTiming:
    """Time ``step(item)`` for every item; ``make_step`` gives a fresh step per repeat."""
    if not items:
        raise ValueError(f"no input to time for stage {stage!r}")
    if repeats < 1:
        raise ValueError("repeats must be at least 1")
    per_item = np.empty((repeats, len(items)))
    cpu_item = np.empty((repeats, len(items)))
    throughput = np.empty(repeats)
    cpu_throughput = np.empty(repeats)
    clock, cpu_clock = time.perf_counter, time.process_time
    for r in range(repeats):
        step = make_step()
        start, cpu_start = clock(), cpu_clock()
        last, cpu_last = start, cpu_start
        for i, item in enumerate(items):
            step(item)
            now, cpu_now = clock(), cpu_clock()
            per_item[r, i] = now - last
            cpu_item[r, i] = cpu_now - cpu_last
            last, cpu_last = now, cpu_now
        throughput[r] = len(items) / max(last - start, 1e-12)
        cpu_throughput[r] = len(items) / max(cpu_last - cpu_start, 1e-12)
    ms = per_item.ravel() * 1e3
    return StageTiming(
        stage,
        len(items),
        repeats,
        float(np.median(ms)),
        float(np.percentile(ms, 95)),
        float(np.median(throughput)),
        1e3 * float(np.median(cpu_item)),
        float(np.median(cpu_throughput)),
    )


def time_reading(stage: str, read: Callable[[], Iterable[Scan]], repeats: int = 3) -> StageTiming:
    """Time a full pass of ``read()`` (a fresh scan stream per repeat), per scan."""
    per_scan: list[float] = []
    cpu_per_scan: list[float] = []
    throughput: list[float] = []
    cpu_throughput: list[float] = []
    count = 0
    for _ in range(repeats):
        start = last = time.perf_counter()
        cpu_start = cpu_last = time.process_time()
        count = 0
        for _scan in read():
            now, cpu_now = time.perf_counter(), time.process_time()
            per_scan.append(now - last)
            cpu_per_scan.append(cpu_now - cpu_last)
            last, cpu_last = now, cpu_now
            count += 1
        if count == 0:
            raise ValueError(f"no scans to time for stage {stage!r}")
        throughput.append(count / max(last - start, 1e-12))
        cpu_throughput.append(count / max(cpu_last - cpu_start, 1e-12))
    ms = np.asarray(per_scan) * 1e3
    return StageTiming(
        stage,
        count,
        repeats,
        float(np.median(ms)),
        float(np.percentile(ms, 95)),
        float(np.median(throughput)),
        1e3 * float(np.median(cpu_per_scan)),
        float(np.median(cpu_throughput)),
    )


def peak_memory_mib() -> float:
    """Peak resident memory of this process so far [MiB]."""
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    # Linux reports KiB, macOS bytes.
    return peak / (1024.0 * 1024.0) if sys.platform == "darwin" else peak / 1024.0
