"""Legs too far for the leg detector: foreground blobs holding a few points of leg-wide runs.

On a moving laser far people show each leg with one or two beams, fewer than the leg
detector's segment features need (three points), and the occupancy grid's foreground holds
them in a blob that neither lies near a leg detection nor moves when they stand or when
their legs, 0.4-0.5 m apart at each stance, form two blobs that each stand still
(:mod:`laserpeople.pipeline.leg_foreground`). Width tells a leg from most clutter at any
range: legs are 0.10-0.18 m across, chair and table legs, railing posts and plant stems
0.02-0.05 m, bins, pots and pillars 0.2 m or more, and a wall's run is longer still.

:func:`leg_runs` walks a scan's foreground points in beam order, cuts a run wherever two
neighbours lie farther than :data:`RUN_GAP` apart or a beam is skipped, and keeps a run of
at least :data:`MIN_POINTS` points that stands apart from the returns beside it and whose
width, the chord between its ends plus one beam's spacing at its range (each beam covers
its share of the surface), lies between :data:`MIN_WIDTH` and :data:`MAX_WIDTH`.

:func:`far_leg_blobs` keeps the person-sized blobs
(:func:`~laserpeople.pipeline.moving_blobs.blob_labels`) whose leg-wide runs hold at most a
few points in all: a near leg is seen by many beams and found by the detector, while the
runs of many points that the detector passes over are mostly wall ends and furniture.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from laserpeople.pipeline.moving_blobs import blob_labels

RUN_GAP = 0.1
"""Neighbouring points (in beam order) farther apart than this [m] start a new run: over the
spacing of 1 deg beams at 5 m (0.09 m), under a person's leg and what stands behind it."""
MIN_POINTS = 2
"""Fewest points of a run: one point has no width."""
MIN_WIDTH = 0.08
"""Narrowest run [m] taken for a leg: the simulator's legs are 0.10-0.18 m across (a leg
seen by two beams spans one beam's spacing less), chair and table legs 0.02-0.05 m."""
MAX_WIDTH = 0.2
"""Widest run [m] taken for a leg: two legs side by side seen as one run are 0.25-0.35 m;
bins and pots 0.2-0.4 m, walls longer."""
JUMP = 0.1
"""A run stands apart when the return of the beam beside either end lies this much [m]
farther from the laser than that end, or there is none: a piece of wall the grid has
partly learned continues into its neighbours' returns."""


def leg_runs(
    points: NDArray[np.float64],
    beams: NDArray[np.int64],
    mask: NDArray[np.bool_],
    sensor: NDArray[np.float64],
    increment: float,
) -> NDArray[np.bool_]:
    """Which of ``points`` (N, 2) [m] lie in a run as wide as a leg (module docstring).

    Args:
        points: The frame's points (N, 2) [m], of one laser.
        beams: Beam index (N,) of each point within its scan.
        mask: Points (N,) that may belong to a run (the foreground).
        sensor: The laser's position (2,) [m], in the frame of ``points``.
        increment: Angle between consecutive beams [rad] (its sign is ignored).

    Returns:
        (N,) bool: the points of the runs kept (always within ``mask``).
    """
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    keep = np.zeros(len(pts), dtype=bool)
    idx = np.flatnonzero(np.asarray(mask, dtype=bool))
    if len(idx) < MIN_POINTS:
        return keep
    beam = np.asarray(beams)
    order = idx[np.argsort(beam[idx], kind="stable")]
    step = np.hypot(*np.diff(pts[order], axis=0).T)
    skip = np.diff(beam[order])
    cuts = np.flatnonzero((step > RUN_GAP) | (skip > 1)) + 1
    origin = np.asarray(sensor, dtype=np.float64).reshape(2)
    spacing = abs(float(increment))
    ranges = np.hypot(*(pts - origin).T)
    by_beam = {int(b): i for i, b in enumerate(beam.tolist())}
    for run in np.split(order, cuts):
        if len(run) < MIN_POINTS:
            continue
        if not (
            _apart(run[0], -1, beam, ranges, by_beam) and _apart(run[-1], 1, beam, ranges, by_beam)
        ):
            continue
        p = pts[run]
        reach = float(ranges[run].mean())
        width = float(np.hypot(*(p[-1] - p[0]))) + reach * spacing
        if MIN_WIDTH <= width <= MAX_WIDTH:
            keep[run] = True
    return keep


def _apart(
    end: int,
    side: int,
    beam: NDArray[np.int64],
    ranges: NDArray[np.float64],
    by_beam: dict[int, int],
) -> bool:
    """Whether the return beside point ``end`` (on beam ``beam[end] + side``) is missing or
    lies :data:`JUMP` farther from the laser."""
    other = by_beam.get(int(beam[end]) + side)
    return other is None or bool(ranges[other] - ranges[end] >= JUMP)


def far_leg_blobs(
    points: NDArray[np.float64],
    beams: NDArray[np.int64],
    mask: NDArray[np.bool_],
    sensor: NDArray[np.float64],
    increment: float,
    max_points: int,
) -> NDArray[np.bool_]:
    """The points (N,) of the person-sized blobs of ``points`` (N, 2) [m] where ``mask`` (N,)
    holds whose leg-wide runs (:func:`leg_runs`, arguments as there) hold between one and
    ``max_points`` points in all (module docstring); none when ``max_points`` is 0."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    fg = np.asarray(mask, dtype=bool)
    if max_points <= 0 or len(pts) == 0:
        return np.zeros(len(pts), dtype=bool)
    runs = leg_runs(pts, beams, fg, sensor, increment)
    labels = blob_labels(pts, fg)
    inside = labels >= 0
    if not inside.any():
        return inside
    counts = np.bincount(labels[runs & inside], minlength=int(labels.max(initial=-1)) + 1)
    few = (counts >= 1) & (counts <= max_points)
    return inside & few[np.where(inside, labels, 0)]


__all__ = ["JUMP", "MAX_WIDTH", "MIN_POINTS", "MIN_WIDTH", "RUN_GAP", "far_leg_blobs", "leg_runs"]
