"""Whether a laser should see a place now: inside its field of view and range, and not
behind nearer returns along the beams that would hit a body there (000's occlusion
reasoning applied to the sensor's own view of a person)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from laserpeople.scan import Pose2D, Scan

FloatArray = NDArray[np.float64]


def in_plain_view(
    scan: Scan,
    pose: Pose2D,
    points: FloatArray,
    max_range: float,
    half_width: float = 0.2,
    margin: float = 0.3,
) -> NDArray[np.bool_]:
    """Which of ``points`` (K, 2) [m, world frame] a laser at ``pose`` taking ``scan`` should
    see: within ``max_range`` [m] and ``scan.range_max``, every beam within ``half_width``
    [m] of the point (sideways) inside the scan's angles, and none of those beams returning
    nearer than the point's range minus ``margin`` [m] (an occluder in front)."""
    k = points.shape[0]
    out = np.zeros(k, dtype=bool)
    n = scan.ranges.shape[0]
    if k == 0 or n == 0:
        return out
    local = pose.inverse_transform_points(points)
    r = np.hypot(local[:, 0], local[:, 1])
    bearing = np.arctan2(local[:, 1], local[:, 0])
    inc = scan.angle_increment
    ranges = scan.ranges
    valid = np.isfinite(ranges) & (ranges > scan.range_min) & (ranges < scan.range_max)
    for i in range(k):
        ri = float(r[i])
        if not (0.0 < ri < min(max_range, scan.range_max)):
            continue
        spread = math.atan2(half_width, ri)
        a0 = (float(bearing[i]) - spread - scan.angle_min) / inc
        a1 = (float(bearing[i]) + spread - scan.angle_min) / inc
        lo, hi = math.floor(min(a0, a1)), math.ceil(max(a0, a1))
        if lo < 0 or hi > n - 1:
            continue  # (partly) outside the field of view
        beams = slice(lo, hi + 1)
        near = valid[beams] & (ranges[beams] < ri - margin)
        out[i] = not bool(near.any())
    return out
