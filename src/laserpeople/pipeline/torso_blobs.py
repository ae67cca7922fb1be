"""Torso-shaped runs of foreground points: a laser at torso height sees a person as one arc.

At torso height (1.0-1.3 m) a person is one blob, the torso with the arms, about 0.3-0.45 m
across, and the leg detector (000, trained on legs) fires on it in under a third of the
scans (docs/csa.md, "Torso blobs on a moving laser"). Width alone is no test: walls broken
by whatever stands in front of them give runs of every width. A torso is a convex arc
that bulges towards the laser; a piece of wall is a straight line.

:func:`torso_blobs` walks a scan's foreground points in beam order, cuts a run wherever
two neighbours lie farther than :data:`RUN_GAP` apart or beams are skipped, and keeps a
run of at least :data:`MIN_POINTS` points whose ends lie :data:`MIN_WIDTH` to
:data:`MAX_WIDTH` apart and whose points bulge at least :data:`MIN_BULGE` from the chord
between its ends towards the laser.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

RUN_GAP = 0.15
"""Neighbouring points (in beam order) farther apart than this [m] start a new run:
assumption, under the 0.2 m between a torso and an arm or a person behind it, over the
spacing of 1° beams at 6 m (0.1 m)."""
MIN_WIDTH = 0.2
"""Narrowest run [m] between its ends taken for a torso: the simulator's torsos are
0.36-0.44 m across and 0.25-0.31 m deep, seen partly from the side (assumption)."""
MAX_WIDTH = 0.65
"""Widest run [m] taken for a torso (arms held out, assumption)."""
MIN_POINTS = 3
"""Fewest points of a run: two points make no arc."""
MIN_BULGE = 0.03
"""Least distance [m] of the run's points from the chord between its ends, towards the
laser: a torso's depth seen across is 0.1-0.15 m; a wall's noise a centimetre or two
(measured on the moving torso-height tuning seeds 11 and 13: with 0.03 m, 1.1 and 1.5
such runs per scan lie farther than 1.5 m from every person; csa MOTA 0.420 / 0.261,
with 0.02 m 0.361 / 0.189, with 0.05 m 0.280 / 0.248)."""


def torso_blobs(
    points: NDArray[np.float64],
    beams: NDArray[np.int64],
    mask: NDArray[np.bool_],
    sensor: NDArray[np.float64],
) -> NDArray[np.bool_]:
    """Which of ``points`` (N, 2) [m] lie in a torso-shaped run (module docstring).

    Args:
        points: The frame's points (N, 2) [m].
        beams: Beam index (N,) of each point within its scan (one laser).
        mask: Points (N,) that may belong to a run (the foreground).
        sensor: The laser's position (2,) [m], in the frame of ``points``.

    Returns:
        (N,) bool: the points of the runs kept (always within ``mask``).
    """
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    keep = np.zeros(len(pts), dtype=bool)
    idx = np.flatnonzero(np.asarray(mask, dtype=bool))
    if len(idx) < MIN_POINTS:
        return keep
    order = idx[np.argsort(np.asarray(beams)[idx], kind="stable")]
    step = np.hypot(*np.diff(pts[order], axis=0).T)
    skip = np.diff(np.asarray(beams)[order])
    cuts = np.flatnonzero((step > RUN_GAP) | (skip > 2)) + 1
    origin = np.asarray(sensor, dtype=np.float64).reshape(2)
    for run in np.split(order, cuts):
        if len(run) < MIN_POINTS:
            continue
        p = pts[run]
        chord = p[-1] - p[0]
        width = float(np.hypot(*chord))
        if not MIN_WIDTH <= width <= MAX_WIDTH:
            continue
        normal = np.array([-chord[1], chord[0]]) / width
        if float((origin - p[0]) @ normal) < 0.0:
            normal = -normal  # towards the laser
        if float(((p - p[0]) @ normal).max()) >= MIN_BULGE:
            keep[run] = True
    return keep


__all__ = ["MAX_WIDTH", "MIN_BULGE", "MIN_POINTS", "MIN_WIDTH", "RUN_GAP", "torso_blobs"]
