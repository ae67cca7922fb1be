"""Which group tracks the laser cannot see this scan: adaptive occlusion probabilities for
groups (000 Sec. 3.3.1, carried over from legs to groups).

000 adapts the label probabilities of a leg track to how likely it is to be occluded (an
approved leg, hidden by the other leg, is detected with 0.2, occluded with 0.79 and
deleted with 0.01 per scan, 000 Table 10). Its group tracker (Sec. 4.5) keeps one set,
p_M = 0.79, p_O = 0.19, p_T = 0.02, so a group hidden behind another group or an object
is deleted after a few scans (p_O^m falls below p_T) and comes back as a new group, with
a new id and unconfirmed for ``confirm_scans``. Here a group whose predicted points all
lie in the shadow of a closer return of the scan (the beam at their bearing ends more
than ``margin`` in front of them) is *shadowed*, and, once it has been detected in
``shadow_hits`` scans (000 adapts only the legs of validated people), takes the adapted
probabilities; every other group 000's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.frame import Frame

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


@dataclass(frozen=True)
class ScanView:
    """What one scan saw, in the coordinates of the frame's points.

    Attributes:
        origin: Position (2,) of the laser [m].
        heading: Direction of the laser's x axis [rad].
        angle_min: Angle of beam 0 in the laser frame [rad].
        angle_increment: Angle between beams [rad] (may be negative).
        ranges: Range (N,) of each beam [m]; +inf where the beam gave no valid return.
        wraps: True when the beams cover the full circle (bearings wrap around).
    """

    origin: FloatArray
    heading: float
    angle_min: float
    angle_increment: float
    ranges: FloatArray
    wraps: bool

    def hidden(self, points: FloatArray, margin: float) -> tuple[BoolArray, BoolArray]:
        """For points (K, 2) [m]: (covered, shadowed) (K,) each: whether a beam of this
        scan points at it (inside the field of view), and whether that beam ended more
        than ``margin`` [m] in front of it."""
        covered, ends, dist = self._beam_ends(points)
        return covered, covered & (ends < dist - margin)

    def seen_past(self, points: FloatArray, margin: float) -> BoolArray:
        """For points (K, 2) [m]: (K,) whether a beam of this scan points at it and went on
        more than ``margin`` [m] beyond it (nothing there)."""
        covered, ends, dist = self._beam_ends(points)
        return covered & (ends > dist + margin)

    def _beam_ends(self, points: FloatArray) -> tuple[BoolArray, FloatArray, FloatArray]:
        """For points (K, 2) [m]: whether a beam points at each (K,), the range of that
        beam (K,) [m] (+inf where none does or it gave no return) and the point's distance
        from the laser (K,) [m]."""
        d = points - self.origin
        dist = np.hypot(d[:, 0], d[:, 1])
        bearing = np.arctan2(d[:, 1], d[:, 0]) - self.heading - self.angle_min
        bearing = (bearing + math.pi) % (2 * math.pi) - math.pi  # (-pi, pi]
        if self.angle_increment < 0:
            bearing = -bearing
        step = abs(self.angle_increment)
        beam = np.rint(np.where(bearing < -step / 2, bearing + 2 * math.pi, bearing) / step)
        n = self.ranges.size
        if self.wraps:
            beam = beam % n
        covered = (beam >= 0) & (beam < n)
        ends = np.full(len(points), np.inf)
        ends[covered] = self.ranges[beam[covered].astype(np.int64)]
        return covered, ends, dist


@dataclass(frozen=True)
class FrameShadows:
    """The scans of one frame, asked which points none of them can see."""

    views: tuple[ScanView, ...]

    @classmethod
    def from_frame(cls, frame: Frame) -> FrameShadows | None:
        """The views of ``frame``'s scans; None when a scan's pose in the frame's
        coordinates is unknown (a world frame without that scan's pose)."""
        views = []
        for scan in frame.scans:
            if frame.frame == "world":
                if scan.pose is None:
                    return None
                origin, heading = np.array([scan.pose.x, scan.pose.y]), scan.pose.theta
            else:
                origin, heading = np.zeros(2), 0.0
            ranges = np.where(scan.valid, scan.ranges, np.inf)
            span = abs(scan.angle_increment) * scan.n_beams
            views.append(
                ScanView(
                    origin,
                    float(heading),
                    float(scan.angle_min),
                    float(scan.angle_increment),
                    ranges,
                    span >= 2 * math.pi - 1e-9,
                )
            )
        return cls(tuple(views))

    def shadowed(self, points: FloatArray, margin: float) -> bool:
        """True when every one of ``points`` (K, 2) [m] lies behind a closer return of a
        scan that covers it and in no scan's view in front of the beam's end (out of every
        scan's field of view counts as not shadowed: the group left the view, it is not
        hidden); False for no points."""
        if not len(points):
            return False
        return bool(self.shadowed_sets(points, np.array([len(points)]), margin)[0])

    def shadowed_sets(
        self, points: FloatArray, counts: NDArray[np.int64], margin: float
    ) -> BoolArray:
        """:meth:`shadowed` of consecutive sets of ``points`` (K, 2) [m], ``counts`` (S,)
        points each (every count at least one): (S,) bool."""
        ok = np.zeros(len(points), dtype=bool)  # behind a return of some scan
        seen = np.zeros(len(points), dtype=bool)  # in front of a beam's end in some scan
        for view in self.views:
            covered, hidden = view.hidden(points, margin)
            ok |= hidden
            seen |= covered & ~hidden
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        return np.logical_and.reduceat(ok & ~seen, starts)

    def seen_empty(self, points: FloatArray, margin: float) -> bool:
        """True when a beam of some scan went more than ``margin`` [m] beyond each one of
        ``points`` (K, 2) [m]: the laser saw that nothing is there. Out of every scan's
        field of view, or behind or at a return, counts as not seen; False for no points."""
        if not len(points):
            return False
        past = np.zeros(len(points), dtype=bool)
        for view in self.views:
            past |= view.seen_past(points, margin)
        return bool(past.all())


__all__ = ["FrameShadows", "ScanView"]
