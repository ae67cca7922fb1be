"""A laser whose beam layout changes in the middle of a recording: noticed and said.

A driver reconfigured while recording (another resolution, another field of view) gives
scans of one topic with a different beam count or angles from some scan on. Per-beam models
(the range histograms of :mod:`laserpeople.background.beam_histogram`) drop what they learnt
and learn again from the change on, as at the start of a recording; :class:`LayoutCheck`
passes the scans through and keeps the changes, so that the command says where each one
happened.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from laserpeople.scan import Layout, Scan, same_layout


def describe_layout(layout: Layout) -> str:
    """``layout`` for the user: beams, first angle and step in degrees."""
    a0, inc, n = layout
    return f"{n} beams from {math.degrees(a0):.2f}° every {math.degrees(inc):.3f}°"


@dataclass(frozen=True)
class LayoutChange:
    """One change of a laser's beam layout.

    Attributes:
        sensor: The laser (topic).
        scan: Index of the first scan with the new layout.
        before: The layout of the scan before it.
        after: The new layout.
    """

    sensor: str
    scan: int
    before: Layout
    after: Layout


class LayoutCheck:
    """Passes scans through unchanged; records every change of a laser's beam layout.

    Attributes:
        changes: The changes seen, in order.
    """

    SHOWN = 3
    """Changes named one by one in :meth:`summary`; more are counted."""

    def __init__(self) -> None:
        self.changes: list[LayoutChange] = []
        self._layout: dict[str, Layout] = {}

    def __call__(self, scans: Iterable[Scan]) -> Iterator[Scan]:
        """``scans`` unchanged, their layouts compared with the previous scan's of the same
        laser."""
        for scan in scans:
            layout = scan.layout
            before = self._layout.get(scan.sensor)
            if before is not None and not same_layout(before, layout):
                self.changes.append(LayoutChange(scan.sensor, scan.index, before, layout))
            self._layout[scan.sensor] = layout
            yield scan

    def summary(self) -> str:
        """One line for the user; empty when no laser changed its layout."""
        if not self.changes:
            return ""
        named = "; ".join(
            f"laser {c.sensor!r} at scan {c.scan}: {describe_layout(c.before)} before, "
            f"{describe_layout(c.after)} from there"
            for c in self.changes[: self.SHOWN]
        )
        more = len(self.changes) - self.SHOWN
        return (
            f"{len(self.changes)} beam layout change(s) in the recording ({named}"
            + (f"; and {more} more" if more > 0 else "")
            + "): the per-beam static world model starts afresh at each change and learns "
            "again, as at the start of the recording"
        )


__all__ = ["LayoutChange", "LayoutCheck", "describe_layout"]
