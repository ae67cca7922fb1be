"""The sensor-motion check's rolling median of the shares off the histogram."""

from __future__ import annotations

import math
import random
import statistics

import numpy as np

from laserpeople.frame import Frame
from laserpeople.pipeline.background import SensorMotionCheck, SensorMotionParams, _median_of_sorted


def test_median_of_sorted_values() -> None:
    assert _median_of_sorted([0.1, 0.4, 0.5]) == 0.4
    assert _median_of_sorted([0.1, 0.2, 0.4, 0.9]) == 0.30000000000000004  # (0.2 + 0.4) / 2
    assert _median_of_sorted([0.7]) == 0.7
    assert math.isnan(_median_of_sorted([]))


def _frame(k: int, stamp: float) -> Frame:
    return Frame(index=k, stamp=stamp, scans=(), topic="/scan", frame="sensor")


def test_rolling_median_is_the_median_of_the_window() -> None:
    """The share is the median over the last ``window`` seconds, as statistics.median
    gives it (shares with ties and a window that holds an odd and an even count)."""
    rng = random.Random(3)
    check = SensorMotionCheck(SensorMotionParams(moved_share=0.99, window=1.0))
    history: list[tuple[float, float]] = []
    for k in range(300):
        stamp = 0.1 * k + (0.03 if k % 7 == 0 else 0.0)
        n = 20
        hits = rng.choice([0, 1, 2, 5, 5, 10])
        fg = np.zeros(n, dtype=bool)
        fg[:hits] = True
        check.record(_frame(k, stamp), fg)
        history.append((stamp, hits / n))
        window = [s for t, s in history if stamp - t <= 1.0]
        assert check.share == statistics.median(window)
    assert check.moved_at is None
