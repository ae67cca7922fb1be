"""Per-frame figures of a run (times, latencies) kept in bounded memory.

A recording ends, but ``laserpeople live`` on a robot runs for days: a UTM-30LX gives 40
frames a second, 3.5 million a day, and a plain list of one float per frame and figure
would grow by tens of megabytes a day. :class:`Samples` keeps every value up to
``capacity`` (the quantiles are then exact), and beyond it a uniform random sample of
``capacity`` values of the whole run (reservoir sampling, Vitter's algorithm R, with a
fixed seed so that two runs of the same frames agree): the quantiles are then estimates
from that sample (the median of 65,536 values drawn from millions is within about 0.4 %
of the run's in rank). The count, the mean and the last values are always exact.
"""

from __future__ import annotations

import random
from array import array
from collections import deque
from collections.abc import Iterable, Iterator

CAPACITY = 65_536
"""Values kept for the quantiles (512 KiB of floats)."""
RECENT = 64
"""Latest values kept in order (:meth:`Samples.recent`)."""


def quantile(values: Iterable[float], q: float) -> float:
    """The ``q`` quantile (0..1) of ``values`` by the nearest-rank rule: the smallest value
    with at least a share ``q`` of them at or below it (0 when there are none)."""
    ordered = sorted(values)
    if not ordered:
        return 0.0
    rank = min(len(ordered) - 1, max(0, -int(-q * len(ordered) // 1) - 1))
    return float(ordered[rank])


class Samples:
    """One figure per frame (e.g. a latency in ms) of a run of any length.

    Args:
        capacity: Values kept for the quantiles; beyond it a uniform sample of the run.
        seed: Seed of the sampling (the same run gives the same sample).
    """

    def __init__(self, capacity: int = CAPACITY, seed: int = 0) -> None:
        if capacity < 1:
            raise ValueError("capacity must be at least 1")
        self.capacity = capacity
        self._kept: array[float] = array("d")
        self._last: deque[float] = deque(maxlen=RECENT)
        self._count = 0
        self._sum = 0.0
        self._rng = random.Random(seed)

    def append(self, value: float) -> None:
        """Add the next frame's value."""
        value = float(value)
        self._count += 1
        self._sum += value
        self._last.append(value)
        if len(self._kept) < self.capacity:
            self._kept.append(value)
            return
        slot = self._rng.randrange(self._count)  # keep with probability capacity / count
        if slot < self.capacity:
            self._kept[slot] = value

    def __len__(self) -> int:
        """Values added over the run (not only those kept)."""
        return self._count

    def __iter__(self) -> Iterator[float]:
        """The values kept: all of them while ``len(self) <= capacity``, else the sample."""
        return iter(self._kept)

    @property
    def sampled(self) -> bool:
        """Whether the quantiles come from a sample (more values than ``capacity``)."""
        return self._count > self.capacity

    @property
    def mean(self) -> float:
        """Mean of every value added (0 when none)."""
        return self._sum / self._count if self._count else 0.0

    def quantile(self, q: float) -> float:
        """The ``q`` quantile (0..1) of the values kept (:func:`quantile`)."""
        return quantile(self._kept, q)

    def recent(self, n: int = RECENT) -> list[float]:
        """The last ``n`` values added (at most :data:`RECENT`), oldest first."""
        return list(self._last)[-n:] if n > 0 else []


__all__ = ["CAPACITY", "RECENT", "Samples", "quantile"]
