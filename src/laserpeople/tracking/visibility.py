"""What the laser should see right now: the sensor's own view for the people layer (issue 29).

000 Sec. 3.3.1 makes a leg that is not detected *occluded* rather than deleted when it is
likely to be hidden (by the other leg). From a moving robot most people who are not
detected are not hidden: they have left the field of view, or the robot has driven past
them, or they have left the place where the track still is. This module tells these
apart for a position in the tracking frame, from the scans of this instant:

- **outside**: outside every laser's field of view (behind a 270 deg scanner), or farther
  than ``max_range`` (the smaller of it and the laser's ``range_max``) or nearer than its
  ``range_min``, or fewer than ``min_valid`` of its beams return at all (a beam without a
  return may have passed through nothing or hit a dark surface): nothing can be told;
  its track coasts;
- **occluded**: inside the view, but most beams that would hit a body at that place
  (the beams within ``body_radius`` of it) return from nearer than ``margin`` in front of
  it: something stands between; the track coasts;
- **occupied**: inside the view, not occluded, and some of its beams (at least
  ``min_present``) return from within ``margin`` of its range: something is there (a
  person the detector missed this scan, e.g. two legs merged into one blob);
- **empty**: inside the view, and its beams pass it (return from more than ``margin``
  behind it): a person there would be hit by the laser now, and nothing is.

The shares of blocked and present beams are of the beams that return.

This is 000's adaptive occlusion reasoning applied to people and the sensor's own view:
the person layer lowers a track's existence for a scan without its legs only where its
place is *empty* (``people.miss_only_if_empty``); elsewhere the scan is neutral.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.scan import Pose2D, Scan

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

OUTSIDE, OCCLUDED, OCCUPIED, EMPTY = 0, 1, 2, 3
"""What the lasers can see of a place: nothing (outside the view or range), something in
front of it, something at it, nothing at it (the beams pass)."""


@dataclass(frozen=True)
class ViewParams:
    """When a place counts as visible to the lasers (module docstring)."""

    config_section = "view"

    max_range: float = param(
        8.0,
        "assumption: the shipped detector finds legs out to ~7 m on the real leg_tracker "
        "lobby recording (0.35 deg beams); farther, a person who is there is often missed",
        "places farther from the laser than this (or than its range_max) are not visible",
        "m",
    )
    body_radius: float = param(
        0.2,
        "assumption: about a leg pair's half width",
        "the beams within this distance of a place are the ones that would hit a person there",
        "m",
    )
    margin: float = param(
        0.4,
        "assumption: a person's near leg is up to ~0.3 m in front of the body centre, plus "
        "the position error of a coasting track",
        "a beam that returns from more than this in front of the place is blocked",
        "m",
    )
    min_blocked: float = param(
        0.5,
        "assumption: half of the beams",
        "a place is occluded when at least this share of its beams is blocked",
    )
    min_valid: float = param(
        0.5,
        "issue 29: on the real lobby recording (62% of the beams without a return) the legs "
        "of people at 4-5 m gave no return in some scans, so a beam without a return does "
        "not show that nobody is there",
        "a place whose beams give a return in fewer than this share is not told (it coasts "
        "as outside the view); the shares below are of the beams with a return",
    )
    min_present: float = param(
        0.2,
        "assumption: one leg of a person covers about a fifth of the beams of its body width",
        "a place that is not occluded is occupied when at least this share of its beams "
        "return from within margin of its range (else empty)",
    )

    moved_distance: float = param(
        0.05,
        "as auto_background.moved_distance",
        "a laser that moved farther than this from its first pose (world frame) is on a "
        "moving robot: only then does the person layer use the view and one-leg births",
        "m",
    )
    moved_angle: float = param(
        0.02, "as auto_background.moved_angle", "or turned more than this", "rad"
    )

    def __post_init__(self) -> None:
        if not (self.max_range > 0 and self.body_radius > 0 and self.margin >= 0):
            raise ValueError("max_range and body_radius must be positive, margin not negative")
        if not all(0.0 < v <= 1.0 for v in (self.min_blocked, self.min_present, self.min_valid)):
            raise ValueError("min_blocked, min_present and min_valid must be in (0, 1]")


@dataclass(frozen=True, eq=False)
class _Laser:
    """One laser's scan in the tracking frame: where it stands and what it returned."""

    pose: Pose2D
    angle_min: float
    angle_increment: float
    ranges: FloatArray  # (N,), inf where no valid return
    range_min: float
    max_range: float


class SensorView:
    """The view of the lasers of one instant (module docstring).

    Args:
        scans: The scans of this instant.
        poses: The pose of each scan's laser in the tracking frame (``None`` entries: the
            laser's own frame, a sensor-frame run).
        params: Thresholds.
    """

    def __init__(
        self,
        scans: Sequence[Scan],
        poses: Sequence[Pose2D | None],
        params: ViewParams | None = None,
    ) -> None:
        self.params = params if params is not None else ViewParams()
        self._lasers: list[_Laser] = []
        for scan, pose in zip(scans, poses, strict=True):
            ranges = np.where(scan.valid, scan.ranges, np.inf)
            self._lasers.append(
                _Laser(
                    pose if pose is not None else Pose2D(),
                    float(scan.angle_min),
                    float(scan.angle_increment),
                    np.asarray(ranges, dtype=np.float64),
                    float(scan.range_min),
                    min(float(scan.range_max), self.params.max_range),
                )
            )

    def classify(self, positions: FloatArray) -> IntArray:
        """For each place ``positions`` (M, 2) [m] in the tracking frame: OUTSIDE,
        OCCLUDED, OCCUPIED or EMPTY (M,); with several lasers the most telling answer
        (empty over occupied over occluded over outside)."""
        pos = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
        out = np.full(len(pos), OUTSIDE, dtype=np.int64)
        for laser in self._lasers:
            for i, (x, y) in enumerate(pos.tolist()):
                if out[i] == EMPTY:
                    continue
                out[i] = max(out[i], self._one(laser, x, y))
        return out

    def _one(self, laser: _Laser, x: float, y: float) -> int:
        p = self.params
        pose = laser.pose
        dx, dy = x - pose.x, y - pose.y
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        lx, ly = c * dx + s * dy, -s * dx + c * dy  # the place in the laser's frame
        r = math.hypot(lx, ly)
        if r > laser.max_range or r < max(laser.range_min, p.body_radius):
            return OUTSIDE
        bearing = math.atan2(ly, lx)
        n = len(laser.ranges)
        inc = laser.angle_increment
        # beam index of the bearing (angles wrap: try the bearing and the bearing +- 2 pi)
        centre = None
        for b in (bearing, bearing + 2 * math.pi, bearing - 2 * math.pi):
            k = (b - laser.angle_min) / inc
            if -0.5 <= k <= n - 0.5:
                centre = k
                break
        if centre is None:
            return OUTSIDE
        half = math.asin(min(p.body_radius / r, 1.0)) / abs(inc)
        lo = max(math.ceil(centre - half), 0)
        hi = min(math.floor(centre + half), n - 1)
        if hi < lo:
            lo = hi = min(max(round(centre), 0), n - 1)
        beams = laser.ranges[lo : hi + 1]
        valid = beams[np.isfinite(beams)]
        n_valid = len(valid)
        if n_valid < p.min_valid * len(beams):
            return OUTSIDE  # too few returns to tell (no return: nothing, or a dark surface)
        blocked = int(np.count_nonzero(valid < r - p.margin))
        if blocked >= p.min_blocked * n_valid:
            return OCCLUDED
        present = int(np.count_nonzero(np.abs(valid - r) <= p.margin))
        return OCCUPIED if present >= p.min_present * n_valid else EMPTY


class MotionWatch:
    """Whether the first laser of a world-frame run has moved from its first pose (by more
    than ``moved_distance`` or ``moved_angle``); once it has, for good."""

    def __init__(self, params: ViewParams | None = None) -> None:
        self.params = params if params is not None else ViewParams()
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


def view_of_frame(
    scans: Sequence[Scan], frame: str, params: ViewParams | None = None
) -> SensorView:
    """The view of ``scans`` in the tracking ``frame`` (``world``: each laser at its scan's
    pose; ``sensor``: at the origin, one laser)."""
    poses = [s.pose if frame == "world" else None for s in scans]
    return SensorView(scans, poses, params)
