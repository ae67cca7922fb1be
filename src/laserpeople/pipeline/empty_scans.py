"""Beams and scans without a return: counted by kind and said, not passed over in silence.

A driver that writes NaN or negative ranges, a laser whose every beam reads its
``range_max`` outdoors, or ranges in another unit than the limits' leave beams (or whole
scans) in which nothing can be seen. Such a beam is left out of the points and such a scan
is tracked as an empty one (tracks coast through it); :class:`EmptyScanCheck` passes the
scans through and counts the beams left out by kind (:data:`BEAM_KINDS`: NaN, +inf, -inf,
negative, zero, under ``range_min``, over ``range_max``) and the scans left empty, so
that the command says how many of each there were and where the first empty scan was.
"""

from __future__ import annotations

import sys
from collections.abc import Iterable, Iterator
from typing import Any

import numpy as np

from laserpeople.scan import Scan

BEAM_KINDS: tuple[str, ...] = (
    "NaN",
    "+inf",
    "-inf",
    "negative",
    "zero",
    "under range_min",
    "over range_max",
)
"""The kinds of a beam without a valid return, each beam counted under the first that fits
(a NaN is no negative, an infinite range is not 'over range_max')."""


_UNLOADED = object()
_compiled: Any = _UNLOADED
LISTING = "laserpeople.tracking.mht.listing"
"""The module that loads the MHT's C extension (:func:`_compiled_beam_kinds`)."""


def _compiled_beam_kinds() -> Any:
    """The compiled :func:`beam_kinds_python` (``beam_kinds`` of the MHT's C extension,
    where its static-world part runs: built, not stale, not forced off), or None; looked up
    at the first scan counted once the leg MHT's listing is imported. Before that (``detect``
    never imports it) None: importing the tracker's modules for this alone costs 30-50 ms
    of start-up, more than the pass saves on the demo bag's 1265 scans."""
    global _compiled
    if _compiled is _UNLOADED:
        if LISTING not in sys.modules:
            return None
        from laserpeople.background.occupancy import compiled_function

        _compiled = compiled_function("beam_kinds")
    return _compiled


def beam_kinds(scan: Scan) -> np.ndarray:
    """How many of ``scan``'s beams are of each kind of :data:`BEAM_KINDS` (7,) (int64);
    their sum is :attr:`Scan.n_invalid <laserpeople.scan.Scan.n_invalid>`.
    :func:`beam_kinds_python` compiled where the C extension is built: one pass over the
    ranges instead of some fifteen array operations (the same counts)."""
    return _beam_kinds(scan)[0]


def _beam_kinds(scan: Scan) -> tuple[np.ndarray, int]:
    """:func:`beam_kinds` and the number of beams without a valid return."""
    compiled = _compiled_beam_kinds()
    if compiled is not None:
        counts = np.zeros(len(BEAM_KINDS), dtype=np.int64)
        bad = compiled(scan.ranges, scan.range_min, scan.range_max, counts)
        if bad is not NotImplemented:
            return counts, int(bad)
    counts = beam_kinds_python(scan)
    return counts, scan.n_invalid


def beam_kinds_python(scan: Scan) -> np.ndarray:
    """:func:`beam_kinds` in numpy (the reference of the compiled one)."""
    counts = np.zeros(len(BEAM_KINDS), dtype=np.int64)
    bad = ~scan.valid
    if not bad.any():
        return counts
    r = scan.ranges[bad]
    finite = np.isfinite(r)
    positive = finite & (r > 0.0)
    counts[0] = np.count_nonzero(np.isnan(r))
    counts[1] = np.count_nonzero(r == np.inf)
    counts[2] = np.count_nonzero(r == -np.inf)
    counts[3] = np.count_nonzero(finite & (r < 0.0))
    counts[4] = np.count_nonzero(r == 0.0)
    counts[5] = np.count_nonzero(positive & (r < scan.range_min))
    counts[6] = np.count_nonzero(positive & (r > scan.range_max))
    return counts


class EmptyScanCheck:
    """Passes scans through unchanged; counts the beams without a valid return by kind and
    the scans without any valid beam (:attr:`Scan.valid <laserpeople.scan.Scan.valid>`:
    finite, positive and within ``[range_min, range_max]``).

    Attributes:
        scans: Scans passed through.
        beams: Beams of those scans.
        kinds: Beams without a valid return per kind of :data:`BEAM_KINDS` (7,).
        empty: Scans without a valid beam.
        first: ``(topic, scan index)`` of the first of them (None without any).
    """

    def __init__(self) -> None:
        self.scans = 0
        self.beams = 0
        self.kinds = np.zeros(len(BEAM_KINDS), dtype=np.int64)
        self.empty = 0
        self.first: tuple[str, int] | None = None

    def __call__(self, scans: Iterable[Scan]) -> Iterator[Scan]:
        """``scans`` unchanged, counted."""
        for scan in scans:
            self.count(scan)
            yield scan

    def count(self, scan: Scan) -> None:
        """Count ``scan``'s beams without a valid return, and the scan if it has none."""
        self.scans += 1
        n = scan.n_beams
        self.beams += n
        counts, bad = _beam_kinds(scan)
        self.kinds += counts
        if bad == n:  # (no valid beam)
            self.empty += 1
            if self.first is None:
                self.first = (scan.sensor, scan.index)

    @property
    def left_out(self) -> int:
        """Beams without a valid return, all kinds."""
        return int(self.kinds.sum())

    def kinds_text(self) -> str:
        """Each kind of beam left out with its count (``NaN 3, +inf 2,690``); empty without
        any."""
        return ", ".join(
            f"{kind} {int(n):,}" for kind, n in zip(BEAM_KINDS, self.kinds, strict=True) if n
        )

    def beam_summary(self) -> str:
        """One line for the user naming each kind of beam left out and its count; empty
        when every beam had a valid return."""
        if not self.left_out:
            return ""
        return (
            f"{self.left_out:,} of {self.beams:,} beams had no valid return and were left "
            f"out ({self.kinds_text()}; +inf and over range_max are most lasers' 'nothing in "
            "range')"
        )

    def summary(self) -> str:
        """One line for the user on the scans without a valid beam; empty when every scan
        had one."""
        if self.first is None:
            return ""
        topic, index = self.first
        return (
            f"{self.empty} of {self.scans} scans had no valid beam (every range NaN, "
            f"infinite, not positive or outside [range_min, range_max]; the first: scan "
            f"{index} of {topic}): nothing was seen in them"
        )
