"""Whether the lasers ride on a robot that has moved: the person layer gives birth from one
leg only then (``people.one_leg_birth``), so that a still laser keeps its people as before.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from laserpeople.config import param
from laserpeople.scan import Pose2D


@dataclass(frozen=True)
class MotionParams:
    """When the first laser counts as moved from its first pose (world frame)."""

    config_section = "motion"

    moved_distance: float = param(
        0.05,
        "as auto_background.moved_distance",
        "a laser that moved farther than this from its first pose (world frame) is on a "
        "moving robot: only then does the person layer give birth from one leg",
        "m",
    )
    moved_angle: float = param(
        0.02, "as auto_background.moved_angle", "or turned more than this", "rad"
    )


class MotionWatch:
    """Whether the first laser of a world-frame run has moved from its first pose (by more
    than ``moved_distance`` or ``moved_angle``); once it has, for good."""

    def __init__(self, params: MotionParams | None = None) -> None:
        self.params = params if params is not None else MotionParams()
        self._first: Pose2D | None = None
        self.moved = False

    def __call__(self, pose: Pose2D | None) -> bool:
        """Record ``pose`` (None: unknown, nothing learnt); True once the laser moved."""
        if self.moved or pose is None:
            return self.moved
        if self._first is None:
            self._first = pose
            return False
        f = self._first
        turn = abs(math.remainder(pose.theta - f.theta, 2 * math.pi))
        self.moved = (
            math.hypot(pose.x - f.x, pose.y - f.y) > self.params.moved_distance
            or turn > self.params.moved_angle
        )
        return self.moved
