"""Legs a coarse scanner shows by one or two points.

The boosted classifier scores segments of at least three points (000 Sec. 2.2). A coarse
scanner puts fewer on a leg: a leg of width w at range r spans about w / (r |dtheta|) beams,
fewer than three for a 0.12 m leg beyond 3.4 m at 0.67 deg or 2.3 m at 1 deg (6.9 m at
0.33 deg). A segment of ``min_points`` (2) points or more, but fewer than three, is a
*sparse leg* when

1. a leg at its range is expected to get fewer than three beams (``leg_width`` over the
   beam spacing ``r |dtheta|`` at the segment's mean range r, with the scan's own angle
   increment, so that a fine scanner's legs are left to the classifier);
2. it stands out in front of both neighbouring beams: each beam just outside the segment
   either has no return or a range at least the segmentation's jump distance larger than
   the segment's end point next to it (a leg before the background; a piece of a wall cut
   up by coarse beams has neighbours at its own depth, a mixed pixel at a depth edge one
   neighbour nearer);
3. it is no wider than a leg: its first-to-last distance is at most ``leg_width``;
4. its points are distinct readings: two beams of exactly the same range count as one point
   (a scanner that reports each reading on two beams, as the leg_tracker lobby recording
   does for 65 % of its neighbouring beams).

It gets the detector score ``score`` (the classifier's margins of legs are 0-3).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.detection.features import MIN_POINTS
from laserpeople.scan import Scan
from laserpeople.segmentation import SegmentBlock, SegmentTable, covers_full_circle

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]


@dataclass(frozen=True)
class SparseLegParams:
    """When a segment of one or two points is a leg (see the module docstring)."""

    config_section = "sparse_legs"

    enabled: bool = param(
        True,
        "extension (000 classifies only segments of more than two points; false gives that): "
        "measured (docs/leg-detection.md): held-back randomised MOTA / IDF1 0.345 / 0.413 -> "
        "0.376 / 0.437, moving-robot 0.647 / 0.699 -> 0.695 / 0.722, real recordings at "
        "their own resolution unchanged",
        "segments of two points become legs where a leg is expected to get fewer than three "
        "beams and the segment stands out in front of both neighbours",
    )
    leg_width: float = param(
        0.12,
        "assumption: the median labelled leg_tracker leg is 0.137 m wide, a neko7055 leg "
        "0.083 m (docs/leg-detection.md); measured on the randomised tuning scenes 0-19 "
        "(score 0.25): 0.09 / 0.12 / 0.15 m give MOTA 0.263 / 0.333 / 0.334, IDF1 0.406 / "
        "0.443 / 0.430",
        "width of a leg as the scanner sees it: sets the range beyond which a leg gets fewer "
        "than three beams, and the widest two-point segment taken for a leg",
        "m",
    )
    min_points: int = param(
        2,
        "measured on the randomised tuning scenes (seeds 0-9): of the one-point segments the "
        "rule took, 721 were legs and 28,244 other things (chair and table legs, poles, wall "
        "pieces); of the two-point ones 2,202 legs and 392 other things",
        "fewest points of a sparse leg",
        "points",
    )
    score: float = param(
        0.6,
        "measured on the randomised tuning scenes: MOTA / IDF1 seeds 0-19 0.333 / 0.443 at "
        "0.25 -> 0.344 / 0.447 at 0.6, seeds 20-49 0.403 / 0.453 -> 0.431 / 0.465 (above the "
        "people layer's birth_min_score 0.5: a pair of sparse legs counts as two legs)",
        "detector score of a sparse leg",
    )

    def __post_init__(self) -> None:
        if not (math.isfinite(self.leg_width) and self.leg_width > 0.0):
            raise ValueError(f"leg_width must be a positive, finite width, not {self.leg_width}")
        if not 1 <= self.min_points < MIN_POINTS:
            raise ValueError(f"min_points must be 1 or 2, not {self.min_points}")
        if not math.isfinite(self.score):
            raise ValueError(f"score must be finite, got {self.score}")


def expected_beams(distance: FloatArray, increment: float, leg_width: float) -> FloatArray:
    """Beams (n,) a leg of ``leg_width`` [m] gets at ``distance`` (n,) [m] from a scanner of
    angle increment ``increment`` [rad] (either sign): the width over the beam spacing."""
    spacing = np.maximum(np.asarray(distance, dtype=np.float64) * abs(increment), 1e-12)
    return np.asarray(leg_width / spacing)


def sparse_legs(
    table: SegmentTable, scan: Scan, jump_distance: float, params: SparseLegParams
) -> IntArray:
    """Indices (L,) of the segments of ``table`` (the segmentation of ``scan`` with jump
    distance ``jump_distance`` [m]) that are sparse legs, increasing."""
    sizes = table.sizes
    cand = np.flatnonzero((sizes >= params.min_points) & (sizes < MIN_POINTS))
    if not params.enabled or cand.size == 0:
        return cand[:0]
    lo = table.offsets[cand]
    hi = table.offsets[cand + 1] - 1
    p0, p1 = table.points[lo], table.points[hi]
    ranges = np.asarray(scan.ranges, dtype=np.float64)
    r0, r1 = ranges[table.beams[lo]], ranges[table.beams[hi]]
    distance = 0.5 * (r0 + r1)
    ok = expected_beams(distance, scan.angle_increment, params.leg_width) < MIN_POINTS
    distinct = 1 + (sizes[cand] == 2) * (r0 != r1)  # (ranges exactly equal: one reading twice)
    ok &= distinct >= params.min_points
    ok &= np.hypot(p1[:, 0] - p0[:, 0], p1[:, 1] - p0[:, 1]) <= params.leg_width
    before, after = table.beams[lo] - 1, table.beams[hi] + 1
    full = covers_full_circle(scan)
    ok &= _behind(scan.valid, ranges, before, r0, jump_distance, full)
    ok &= _behind(scan.valid, ranges, after, r1, jump_distance, full)
    return cand[ok]


def sparse_legs_of_block(
    block: SegmentBlock,
    scans: Sequence[Scan],
    jump_distance: float,
    params: SparseLegParams,
) -> IntArray:
    """Indices (L,) of the sparse legs among all segments of ``block`` (the segmentation of
    ``scans``), increasing."""
    if not params.enabled:
        return np.empty(0, dtype=np.int64)
    parts = [
        start + sparse_legs(table, scan, jump_distance, params)
        for start, table, scan in zip(
            block.table_starts[:-1].tolist(), block.tables, scans, strict=True
        )
    ]
    return np.concatenate(parts) if parts else np.empty(0, dtype=np.int64)


def _behind(
    valid: BoolArray,
    ranges: FloatArray,
    beams: IntArray,
    distance: FloatArray,
    jump_distance: float,
    full_circle: bool,
) -> BoolArray:
    """Whether each beam of ``beams`` (L,) (may run one past either end of the scan, whose
    beams are ``valid`` (N,) with ``ranges`` (N,) [m]) has no return, or one at least
    ``jump_distance`` [m] beyond ``distance`` (L,) [m]. Past the end of a scan that covers
    less than the full circle (``full_circle`` False) there is no beam: no return."""
    n = valid.size
    if full_circle:
        beams = beams % n
    inside = (beams >= 0) & (beams < n)
    at = np.clip(beams, 0, n - 1)
    valid = inside & valid[at]
    return np.asarray(~valid | (ranges[at] - distance >= jump_distance))
