"""The static world model: what in a scan is furniture, walls and other things that stay put.

One protocol, two faces (DESIGN.md, "static world model"):

- a per-beam range histogram for a static sensor (Schenk et al. 2011, Sec. 2), in
  ``background/beam_histogram.py``;
- a decaying world-frame occupancy grid for a moving robot, optionally seeded from a ROS
  map (``map.yaml`` + image), in ``background/occupancy.py``, or from what stayed put in the
  whole recording, counted in ``background/recording_map.py``.

Both are preprocess stages of the pipeline: ``model(frame)`` returns the frame with
``foreground`` filled in, and both answer :meth:`StaticWorldModel.static_time` so that a
tracker can refuse to confirm a person on something that has not moved for a long time.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from laserpeople.frame import Frame, FrameField


class StaticWorldModel(Protocol):
    """A model of the static world, learned online from the frames it sees."""

    consumes: frozenset[FrameField]

    def __call__(self, frame: Frame) -> Frame:
        """Learn from ``frame`` and return it with ``foreground`` set over ``frame.points``
        (True = not explained by the static world)."""
        ...

    def static_time(self, positions: NDArray[np.float64]) -> NDArray[np.float64]:
        """How long [s] the places ``positions`` (M, 2) [m], in the frame of the last frame
        seen, have been occupied by something that stays put; 0 where free or unknown,
        ``inf`` for a prior map's obstacles."""
        ...


__all__ = ["StaticWorldModel"]
