"""Scan stamps that do not advance: refused loudly, or replaced by a fixed rate on request.

A tracker predicts by the time between scans. A driver that stamps every scan with the
same time (a stuck clock, a recording tool that wrote its own start time) gives a time
step of zero, and no motion can be tracked: on a simulated walk with all stamps equal the
leg MHT reports no person at all. The trackers' input guard counts an isolated repeated
stamp (a driver hiccup); :class:`StampCheck` stops a recording whose stamps stay put for
:attr:`StampCheck.limit` scans in a row, naming the scans, so that nothing is written
from a clock that is not running. :class:`Restamp` is the way out the error offers:
``--restamp HZ`` tracks every laser at a fixed rate from its first stamp.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import replace

from laserpeople.errors import ConfigError, LaserPeopleError
from laserpeople.scan import Scan

STUCK_SCANS = 20
"""Scans of one laser in a row with one stamp after which a recording is refused."""


class StampCheck:
    """Passes scans through; raises when one laser's stamp stays put for ``limit`` scans.

    Args:
        limit: Consecutive scans of one laser with the same stamp that are an error.
    """

    def __init__(self, limit: int = STUCK_SCANS) -> None:
        if limit < 2:
            raise ConfigError(f"the stuck-stamp limit must be at least 2, got {limit}")
        self.limit = limit
        self._last: dict[str, tuple[float, int, int]] = {}  # sensor -> stamp, first, run

    def __call__(self, scans: Iterable[Scan]) -> Iterator[Scan]:
        """``scans`` unchanged, checked one by one."""
        for scan in scans:
            stamp, first, run = self._last.get(scan.sensor, (math.nan, scan.index, 0))
            if scan.stamp == stamp:
                run += 1
            else:
                first, run = scan.index, 1
            self._last[scan.sensor] = (scan.stamp, first, run)
            if run >= self.limit:
                raise LaserPeopleError(
                    f"scans {first}-{scan.index} of laser {scan.sensor!r} all carry the stamp "
                    f"{scan.stamp:.6f} s: the recording's clock does not advance, so no motion "
                    "can be tracked (the output written so far stays valid)",
                    path=scan.source or None,
                    scan=scan.index,
                    hint="track at the laser's nominal rate with --restamp HZ (e.g. --restamp "
                    "10 for a 10 Hz scanner), or fix the stamps of the recording",
                )
            yield scan


RESTAMP_RANGE = (0.1, 1000.0)
"""Lowest and highest ``--restamp`` rate [Hz]: laser scanners run at 5-100 Hz; outside this
range the new stamps would all be equal (1e308 Hz) or overflow (1e-300 Hz)."""


class Restamp:
    """Replaces every scan's stamp by a fixed rate: stamp_k = t_0 + k / rate, per laser.

    t_0 is the laser's first stamp and k the number of that laser's scans before this one,
    so several lasers keep their relative offset at the start.

    Args:
        rate: Scans per second of every laser [Hz].

    Attributes:
        restamped: Scans whose stamp was replaced.
        changed: Of those, scans whose stamp differed from the recorded one by more than a
            millisecond.
    """

    def __init__(self, rate: float) -> None:
        lo, hi = RESTAMP_RANGE
        if not (math.isfinite(rate) and lo <= rate <= hi):
            raise ConfigError(
                f"--restamp must be a scan rate in [{lo:g}, {hi:g}] Hz, got {rate:.6g}",
                hint="give the scanner's rate, e.g. --restamp 12.5",
            )
        self.rate = float(rate)
        self.restamped = 0
        self.changed = 0
        self._start: dict[str, tuple[float, int]] = {}  # sensor -> first stamp, count

    def __call__(self, scans: Iterable[Scan]) -> Iterator[Scan]:
        """``scans`` with their stamps replaced."""
        for scan in scans:
            start, count = self._start.get(scan.sensor, (scan.stamp, 0))
            if not math.isfinite(start):
                raise LaserPeopleError(
                    f"the first scan of laser {scan.sensor!r} has the stamp {start!r}",
                    path=scan.source or None,
                    scan=scan.index,
                    hint="--restamp counts from each laser's first stamp, which must be finite",
                )
            self._start[scan.sensor] = (start, count + 1)
            stamp = start + count / self.rate
            self.restamped += 1
            if not abs(stamp - scan.stamp) <= 1e-3:
                self.changed += 1
            yield replace(scan, stamp=stamp)

    def summary(self) -> str:
        """What was replaced, for the user."""
        return (
            f"re-stamped {self.restamped} scans at {self.rate:g} Hz from each laser's first "
            f"stamp ({self.changed} differed from the recorded stamp by more than 1 ms)"
        )


__all__ = ["RESTAMP_RANGE", "STUCK_SCANS", "Restamp", "StampCheck"]
