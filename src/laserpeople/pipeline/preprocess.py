"""Preprocess stages: the scans of a frame as one point set.

:class:`Fuse` puts every valid point of every laser of a frame into the frame's
coordinate frame (each scan through its own pose in the world frame; the one laser's own
frame otherwise), with the sensor and beam of each point, and marks every point as
foreground; a static world model (``laserpeople.background``) run after it narrows the
foreground down.
"""

from __future__ import annotations

import numpy as np

from laserpeople.frame import Frame, FrameField
from laserpeople.scan import PointSet


class Fuse:
    """Fills ``points`` (all lasers, in ``frame.frame``) and ``foreground`` (all True)."""

    consumes: frozenset[FrameField] = frozenset({"scans"})
    provides: frozenset[FrameField] = frozenset({"points", "foreground"})

    def __call__(self, frame: Frame) -> Frame:
        """The frame with its point set."""
        points = PointSet.from_scans(
            list(frame.scans), frame.frame, stamp=frame.stamp, index=frame.index
        )
        return frame.with_fields(points=points, foreground=np.ones(len(points), dtype=bool))


__all__ = ["Fuse"]
