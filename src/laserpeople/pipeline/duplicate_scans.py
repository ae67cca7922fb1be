"""Scans recorded twice: dropped, counted and said.

A bag recorded from two subscribers of one topic, a relay that republishes, or a log
concatenated with an overlapping part holds some scans twice: the same laser, the same
stamp and the same ranges. Tracked again, such a copy gives every filter a second update
at a time step of zero, which shrinks its covariance as if the scan had been measured
twice. :class:`DuplicateScanCheck` passes the other scans through and drops a scan that
equals the previous scan of its laser in stamp, ranges and intensities, counting what it
dropped so that the command says how many there were and where the first one was. A scan
with the previous one's stamp but other ranges (a stuck clock) is not a copy and passes
on to the stamp checks (:mod:`laserpeople.pipeline.stamps`).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator

import numpy as np

from laserpeople.scan import Scan


def same_scan(a: Scan, b: Scan) -> bool:
    """Whether ``b`` is a copy of ``a``: the same laser, stamp, beam layout, ranges and
    intensities (NaN ranges equal to NaN ranges)."""
    return (
        a.sensor == b.sensor
        and a.stamp == b.stamp
        and a.angle_min == b.angle_min
        and a.angle_increment == b.angle_increment
        and np.array_equal(a.ranges, b.ranges, equal_nan=True)
        and (
            (a.intensities is None and b.intensities is None)
            or (
                a.intensities is not None
                and b.intensities is not None
                and np.array_equal(a.intensities, b.intensities, equal_nan=True)
            )
        )
    )


class DuplicateScanCheck:
    """Drops a scan that is a copy of the previous scan of its laser (:func:`same_scan`).

    Attributes:
        scans: Scans read.
        dropped: Scans dropped as copies.
        first: ``(laser, scan index)`` of the first copy dropped (None without any).
    """

    def __init__(self) -> None:
        self.scans = 0
        self.dropped = 0
        self.first: tuple[str, int] | None = None
        self._last: dict[str, Scan] = {}

    def __call__(self, scans: Iterable[Scan]) -> Iterator[Scan]:
        """``scans`` without the copies."""
        for scan in scans:
            self.scans += 1
            last = self._last.get(scan.sensor)
            if last is not None and same_scan(last, scan):
                self.dropped += 1
                if self.first is None:
                    self.first = (scan.sensor, scan.index)
                continue
            self._last[scan.sensor] = scan
            yield scan

    def summary(self) -> str:
        """One line for the user; empty when no scan was a copy."""
        if self.first is None:
            return ""
        laser, index = self.first
        return (
            f"{self.dropped} of {self.scans} scans were copies of the scan before them (same "
            f"laser, stamp and ranges; the first: scan {index} of {laser}) and were dropped: "
            "no rows are written for them"
        )


__all__ = ["DuplicateScanCheck", "same_scan"]
