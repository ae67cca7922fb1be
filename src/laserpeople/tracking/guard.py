"""What a tracker does with hostile detections, before they reach its filters.

Every tracker's ``update`` passes its input through :class:`InputGuard` first:

* a detection whose position or covariance is not finite, or whose position is farther
  than :data:`MAX_COORDINATE` from the origin (no place on Earth: its squares would
  overflow the filters' arithmetic), is left out and counted in
  :attr:`InputGuard.dropped_detections`;
* a scan stamp that is not finite is an error (:class:`~laserpeople.errors.LaserPeopleError`
  naming the scan): no time step can be made from it;
* a stamp equal to the previous one is counted in :attr:`InputGuard.repeated_stamps`
  (a time step of zero; a recording whose stamps stay put for many scans is refused
  before it reaches a tracker, :mod:`laserpeople.pipeline.stamps`);
* a stamp before the previous one is counted in :attr:`InputGuard.backward_stamps` and
  replaced by the previous stamp, so that the filters never predict backwards in time (the
  first such scan and the largest step back are kept for the summary);
* a step longer than :data:`JUMP` seconds is counted in :attr:`InputGuard.stamp_jumps`
  (the filters clip their own time step);
* a scan the tracker could not process in full within its work bounds (e.g. the leg MHT's
  ``max_cluster_size``: hundreds of detections in one place) is counted by the tracker in
  :attr:`InputGuard.degraded_scans` through :meth:`InputGuard.degraded`.

:meth:`InputGuard.summary` says what happened, for the command to print.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from laserpeople.errors import LaserPeopleError
from laserpeople.tracks import Detections

JUMP = 60.0
"""A time step [s] longer than this is counted as a jump in time."""

MAX_COORDINATE = 1e8
"""A detection coordinate [m] beyond this magnitude is left out (UTM northings, the largest
world coordinates in use, stay below 1e7 m)."""


class InputGuard:
    """Cleans one scan's detections and counts what it had to change (see module doc)."""

    def __init__(self) -> None:
        self.last_stamp: float | None = None
        self.dropped_detections = 0
        self.repeated_stamps = 0
        self.backward_stamps = 0
        self.first_backward: int | None = None
        self.largest_backward = 0.0
        self.stamp_jumps = 0
        self.degraded_scans = 0
        self.first_degraded: int | None = None

    def check(self, detections: Detections) -> Detections:
        """The detections to track: finite ones within :data:`MAX_COORDINATE`, at a stamp not
        before the previous one.

        Raises:
            LaserPeopleError: The stamp is not finite.
        """
        stamp = self.check_stamp(float(detections.stamp), detections.scan_index)
        pos, cov = detections.positions, detections.covariances
        # (the usual case first: everything in bounds, two flat checks, the first by the
        # largest magnitude, NaN if any is; no np.errstate: numpy 2's comparisons and
        # maxima raise no floating-point warning on NaN)
        clean = bool(np.abs(pos).max(initial=0.0) <= MAX_COORDINATE) and bool(
            np.isfinite(cov).all()
        )
        if not clean:
            finite = (np.abs(pos) <= MAX_COORDINATE).all(axis=1) & np.isfinite(cov).all(axis=(1, 2))
            self.dropped_detections += int(np.count_nonzero(~finite))
            keep = np.flatnonzero(finite)
            detections = replace(
                detections,
                positions=pos[keep],
                covariances=cov[keep],
                scores=detections.scores[keep],
                segments=tuple(detections.segments[i] for i in keep) if detections.segments else (),
            )
        if stamp != detections.stamp:
            detections = replace(detections, stamp=stamp)
        return detections

    def check_stamp(self, stamp: float, scan_index: int) -> float:
        """The stamp to track a scan at (the previous one when ``stamp`` is before it),
        counting repeated, backward and jumping stamps.

        Raises:
            LaserPeopleError: The stamp is not finite.
        """
        if not math.isfinite(stamp):
            raise LaserPeopleError(
                f"the scan has the stamp {stamp!r}",
                scan=scan_index,
                hint="every scan needs a finite time stamp",
            )
        if self.last_stamp is not None:
            if stamp == self.last_stamp:
                self.repeated_stamps += 1
            elif stamp < self.last_stamp:
                self.backward_stamps += 1
                if self.first_backward is None:
                    self.first_backward = scan_index
                self.largest_backward = max(self.largest_backward, self.last_stamp - stamp)
                stamp = self.last_stamp
            elif stamp - self.last_stamp > JUMP:
                self.stamp_jumps += 1
        self.last_stamp = stamp
        return stamp

    def degraded(self, scan_index: int) -> None:
        """Count a scan that was processed in a degraded way (work bounds reached)."""
        self.degraded_scans += 1
        if self.first_degraded is None:
            self.first_degraded = scan_index

    def summary(self) -> str:
        """What was changed, as one line ("" when nothing was)."""
        parts = []
        if self.dropped_detections:
            parts.append(
                f"{self.dropped_detections} detections with non-finite values or positions "
                f"beyond {MAX_COORDINATE:g} m left out"
            )
        if self.repeated_stamps:
            parts.append(f"{self.repeated_stamps} scans with the same stamp as the one before")
        if self.backward_stamps:
            parts.append(
                f"{self.backward_stamps} scans stamped before the one before, by up to "
                f"{self.largest_backward:.3g} s (first: scan {self.first_backward}; tracked at "
                "the previous stamp)"
            )
        if self.stamp_jumps:
            parts.append(f"{self.stamp_jumps} jumps in time of more than {JUMP:g} s")
        if self.degraded_scans:
            parts.append(
                f"{self.degraded_scans} scans degraded to bound the work per scan (too many "
                f"detections close together; first: scan {self.first_degraded})"
            )
        return "; ".join(parts)
