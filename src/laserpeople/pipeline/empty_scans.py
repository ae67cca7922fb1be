"""Scans in which no beam is valid: counted and said, not passed over in silence.

A driver that writes NaN or negative ranges, a laser whose every beam reads its
``range_max`` outdoors, or ranges in another unit than the limits' leave scans in which
nothing can be seen. Such a scan is tracked as an empty one (tracks coast through it);
:class:`EmptyScanCheck` passes the scans through and counts them, so that the command says
how many there were and where the first one was.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator

from laserpeople.scan import Scan


class EmptyScanCheck:
    """Passes scans through unchanged; counts those without a valid beam
    (:attr:`Scan.valid <laserpeople.scan.Scan.valid>`: finite, positive and within
    ``[range_min, range_max]``).

    Attributes:
        scans: Scans passed through.
        empty: Scans without a valid beam.
        first: ``(topic, scan index)`` of the first of them (None without any).
    """

    def __init__(self) -> None:
        self.scans = 0
        self.empty = 0
        self.first: tuple[str, int] | None = None

    def __call__(self, scans: Iterable[Scan]) -> Iterator[Scan]:
        """``scans`` unchanged, counted."""
        for scan in scans:
            self.scans += 1
            if not scan.valid.any():
                self.empty += 1
                if self.first is None:
                    self.first = (scan.sensor, scan.index)
            yield scan

    def summary(self) -> str:
        """One line for the user; empty when every scan had a valid beam."""
        if self.first is None:
            return ""
        topic, index = self.first
        return (
            f"{self.empty} of {self.scans} scans had no valid beam (every range NaN, "
            f"infinite, not positive or outside [range_min, range_max]; the first: scan "
            f"{index} of {topic}): nothing was seen in them"
        )
