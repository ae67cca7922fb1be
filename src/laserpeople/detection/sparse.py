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
from laserpeople.detection import compiled
from laserpeople.detection.features import MIN_POINTS
from laserpeople.scan import Scan
from laserpeople.segmentation import SegmentBlock, SegmentTable, covers_full_circle

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

_extension = compiled.EXTENSION
"""Leg detection's C extension (:func:`sparse_legs_of_block` in one call), or None."""


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


def expected_beams(
    distance: FloatArray, increment: FloatArray | float, leg_width: float
) -> FloatArray:
    """Beams (n,) a leg of ``leg_width`` [m] gets at ``distance`` (n,) [m] from a scanner of
    angle increment ``increment`` [rad] (either sign; one or (n,)): the width over the beam
    spacing."""
    spacing = np.maximum(np.asarray(distance, dtype=np.float64) * np.abs(increment), 1e-12)
    return np.asarray(leg_width / spacing)


def sparse_legs(
    table: SegmentTable, scan: Scan, jump_distance: float, params: SparseLegParams
) -> IntArray:
    """Indices (L,) of the segments of ``table`` (the segmentation of ``scan`` with jump
    distance ``jump_distance`` [m]) that are sparse legs, increasing."""
    starts = np.array([0, len(table)], dtype=np.int64)
    return _sparse(table.beams, table.points, table.offsets, starts, [scan], jump_distance, params)


def sparse_legs_of_block(
    block: SegmentBlock,
    scans: Sequence[Scan],
    jump_distance: float,
    params: SparseLegParams,
) -> IntArray:
    """Indices (L,) of the sparse legs among all segments of ``block`` (the segmentation of
    ``scans``), increasing: those :func:`sparse_legs` gives each scan's table, found for
    all of them at once."""
    typed = block.points.dtype == np.float64 and block.beams.dtype == np.int64
    if _extension is not None and params.enabled and typed:
        return _sparse_compiled(block, scans, jump_distance, params)
    return _sparse(
        block.beams, block.points, block.offsets, block.table_starts, scans, jump_distance, params
    )


def _sparse_compiled(
    block: SegmentBlock, scans: Sequence[Scan], jump_distance: float, params: SparseLegParams
) -> IntArray:
    """:func:`_sparse` of a block by the C extension's ``sparse`` in one call: the same
    rules by the same floating-point operations (the same legs)."""
    assert _extension is not None
    found = _extension.sparse(
        np.ascontiguousarray(block.offsets),
        np.ascontiguousarray(block.beams),
        np.ascontiguousarray(block.points),
        np.ascontiguousarray(block.table_starts, dtype=np.int64),
        [scan.ranges for scan in scans],
        [scan.valid for scan in scans],
        np.array([abs(scan.angle_increment) for scan in scans]),
        np.array(block.full_circle, dtype=np.int64),
        params.min_points,
        float(params.leg_width),
        float(jump_distance),
    )
    return np.frombuffer(found, dtype=np.int64)


def _sparse(
    beams: IntArray,
    points: FloatArray,
    offsets: IntArray,
    table_starts: IntArray,
    scans: Sequence[Scan],
    jump_distance: float,
    params: SparseLegParams,
) -> IntArray:
    """The sparse legs among the segments (``offsets`` (M + 1,) into ``beams`` (K,) and
    ``points`` (K, 2) [m]) of ``scans`` (T,), scan q's segments from ``table_starts[q]``."""
    sizes = np.diff(offsets)
    cand = np.flatnonzero((sizes >= params.min_points) & (sizes < MIN_POINTS))
    if not params.enabled or cand.size == 0:
        return cand[:0]
    lo, hi = offsets[cand], offsets[cand + 1] - 1
    first, last = beams[lo], beams[hi]
    if len(scans) == 1:
        scan = scans[0]
        ranges, valid = np.asarray(scan.ranges, dtype=np.float64), scan.valid
        base: IntArray | int = 0
        n: IntArray | int = scan.n_beams
        increment: FloatArray | float = abs(scan.angle_increment)
        full: BoolArray | bool = covers_full_circle(scan)
    else:
        owner = np.searchsorted(table_starts, cand, side="right") - 1
        counts = np.array([s.n_beams for s in scans], dtype=np.int64)
        starts = np.concatenate(([0], np.cumsum(counts)[:-1]))
        ranges = np.concatenate([np.asarray(s.ranges, dtype=np.float64) for s in scans])
        valid = np.concatenate([s.valid for s in scans])
        base, n = starts[owner], counts[owner]
        increment = np.array([abs(s.angle_increment) for s in scans])[owner]
        full = np.array([covers_full_circle(s) for s in scans])[owner]
    r0, r1 = ranges[base + first], ranges[base + last]
    distance = 0.5 * (r0 + r1)
    ok = expected_beams(distance, increment, params.leg_width) < MIN_POINTS
    if not ok.any():  # (a fine scanner's: none, and nothing more to compute)
        return cand[:0]
    distinct = 1 + (sizes[cand] == 2) * (r0 != r1)  # (ranges exactly equal: one reading twice)
    ok &= distinct >= params.min_points
    p0, p1 = points[lo], points[hi]
    ok &= np.hypot(p1[:, 0] - p0[:, 0], p1[:, 1] - p0[:, 1]) <= params.leg_width
    for beam, r in ((first - 1, r0), (last + 1, r1)):
        beam = np.where(full, beam % n, beam)
        inside = (beam >= 0) & (beam < n)
        at = base + np.clip(beam, 0, n - 1)
        seen = inside & valid[at]
        ok &= ~seen | (ranges[at] - r >= jump_distance)
    return cand[ok]
