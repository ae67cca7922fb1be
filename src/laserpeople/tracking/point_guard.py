"""What a point tracker (``csa``, ``group-mht``, ``feet-pf``, ``upper-body-pf``) is fed of a
hostile frame: one guard for every tracker that reads ``frame.points``.

:class:`GuardedTracker` wraps such a frame tracker (the registry wraps each one it hands
out) and passes every frame through :class:`PointFrameGuard` first:

* a point whose position is not finite or farther than :data:`MAX_COORDINATE` from the
  origin in a coordinate is left out, with its foreground and cluster entries, and
  counted (:attr:`PointFrameGuard.dropped_points`; a KD-tree overflows on 1e300);
* stamps are checked as for detections (:meth:`InputGuard.check_stamp`): not finite is an
  error naming the scan, repeated and jumping ones are counted, one before the previous
  is counted and replaced by the previous (so no filter predicts backwards);
* a world-frame frame without a sensor pose is counted (:attr:`PointFrameGuard.no_pose`);
  its points are used as they are (the pipeline placed them).

The summary is the detections guard's one line, with the points and poses added.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from laserpeople.frame import Frame, FrameField
from laserpeople.scan import PointSet
from laserpeople.tracking.guard import InputGuard
from laserpeople.tracks import Tracks

MAX_COORDINATE = 1e6
"""Largest |x| or |y| [m] of a point kept (1,000 km: far beyond any laser's range, so only
nonsense is dropped, while KD-trees and squared distances stay finite)."""


class PointFrameGuard(InputGuard):
    """Cleans one frame's points and stamp and counts what it changed."""

    def __init__(self) -> None:
        super().__init__()
        self.dropped_points = 0
        self.no_pose = 0

    def check_frame(self, frame: Frame) -> Frame:
        """The frame to track: finite points, at a stamp not before the previous one.

        Raises:
            LaserPeopleError: The stamp is not finite.
        """
        stamp = self.check_stamp(float(frame.stamp), frame.index)
        changes: dict[str, Any] = {}
        if stamp != frame.stamp:
            changes["stamp"] = stamp
        if frame.frame == "world" and frame.sensor_pose is None:
            self.no_pose += 1
        pts = frame.points
        if pts is not None:
            finite = (np.abs(pts.points) <= MAX_COORDINATE).all(axis=1)  # False for NaN
            if not finite.all():
                self.dropped_points += int(np.count_nonzero(~finite))
                keep = np.flatnonzero(finite)
                changes["points"] = PointSet(
                    pts.stamp, pts.points[keep], pts.sensor_ids[keep], pts.beams[keep],
                    pts.sensors, pts.frame, pts.index,
                )  # fmt: skip
                if frame.foreground is not None:
                    changes["foreground"] = frame.foreground[keep]
                if frame.clusters is not None:
                    changes["clusters"] = frame.clusters[keep]
        return frame.with_fields(**changes) if changes else frame

    def summary(self) -> str:
        """What was changed, as one line ("" when nothing was)."""
        parts = [super().summary()] if super().summary() else []
        if self.dropped_points:
            parts.append(
                f"{self.dropped_points} points with non-finite positions (or beyond "
                f"{MAX_COORDINATE:g} m) left out"
            )
        if self.no_pose:
            parts.append(f"{self.no_pose} world-frame frames without a sensor pose")
        return "; ".join(parts)


class GuardedTracker:
    """A frame tracker behind a :class:`PointFrameGuard` (same ``consumes``, same tracks).

    Attributes:
        tracker: The wrapped tracker (its own attributes are reachable through this one).
        guard: The guard and its counts.
    """

    def __init__(self, tracker: Any) -> None:
        self.tracker = tracker
        self.consumes: frozenset[FrameField] = tracker.consumes
        self.guard = PointFrameGuard()

    def update(self, frame: Frame) -> Tracks:
        """Track ``frame`` after the guard's checks."""
        out: Tracks = self.tracker.update(self.guard.check_frame(frame))
        return out

    def __getattr__(self, name: str) -> Any:
        # statistics and parameters of the wrapped tracker
        if name in ("tracker", "guard"):
            raise AttributeError(name)
        return getattr(self.tracker, name)
