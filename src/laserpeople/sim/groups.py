"""Groups of people: walking in formation and standing in a circle, keeping proxemic spacing.

Hall's proxemics (000 Sec. 4.2, citing Hall) puts friends in each other's *personal
space*, 0.45-1.2 m apart. Formations here place neighbours :data:`DEFAULT_SPACING`
apart, inside that range, and move every member on a shared clock so the formation
holds through turns.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment

from laserpeople.sim.motion import Route

FloatArray = NDArray[np.float64]

PERSONAL_SPACE = (0.45, 1.2)
"""Hall's personal distance [m] (000 Sec. 4.6.1)."""
DEFAULT_SPACING = 0.75
"""Distance between neighbours in a formation [m]."""


def line_offsets(n: int, spacing: float = DEFAULT_SPACING) -> FloatArray:
    """Side-by-side formation: offsets (n, 2) ``(ahead, left)`` [m]; three or more walk as
    a row of up to three with the rest one step behind."""
    offs = []
    for i in range(n):
        row, col = divmod(i, 3)
        width = min(3, n - 3 * row)
        offs.append((-0.8 * row, (col - (width - 1) / 2) * spacing))
    return np.asarray(offs, dtype=np.float64)


def circle_slots(
    centre: tuple[float, float], n: int, spacing: float = DEFAULT_SPACING, start: float = 0.0
) -> FloatArray:
    """Positions (n, 2) of n people standing in a circle with neighbours ``spacing`` apart."""
    if n == 1:
        return np.asarray([centre], dtype=np.float64)
    radius = spacing / (2.0 * math.sin(math.pi / n))
    ang = start + 2.0 * math.pi * np.arange(n) / n
    return np.column_stack([centre[0] + radius * np.cos(ang), centre[1] + radius * np.sin(ang)])


def sync(routes: list[Route]) -> float:
    """Make every route wait until the latest of them ends; returns that time [s]."""
    t = max(r.end_time for r in routes)
    for r in routes:
        r.wait_until(t)
    return t


def walk_in_formation(
    routes: list[Route],
    path: NDArray[np.floating],
    speed: float,
    offsets: NDArray[np.floating] | None = None,
) -> float:
    """Move the members (``routes``) along ``path`` (N, 2) [m] keeping ``offsets``.

    Each member first joins its place at the path's first point, then follows the path
    with its offset turned with the path direction (the bisector at corners). All
    members keep the same clock: the returned end time [s] is common to all routes.
    """
    pts = np.asarray(path, dtype=np.float64).reshape(-1, 2)
    n = len(routes)
    offs = line_offsets(n) if offsets is None else np.asarray(offsets, float).reshape(n, 2)
    if pts.shape[0] < 2:
        raise ValueError("a formation path needs at least two points")
    seg = np.diff(pts, axis=0)
    seg_dir = np.arctan2(seg[:, 1], seg[:, 0])
    head = np.empty(pts.shape[0])
    head[0], head[-1] = seg_dir[0], seg_dir[-1]
    if pts.shape[0] > 2:
        a, b = seg_dir[:-1], seg_dir[1:]
        head[1:-1] = np.arctan2(np.sin(a) + np.sin(b), np.cos(a) + np.cos(b))

    def place(i: int, k: int) -> tuple[float, float]:
        c, s = math.cos(head[k]), math.sin(head[k])
        ahead, left = offs[i]
        return (pts[k, 0] + ahead * c - left * s, pts[k, 1] + ahead * s + left * c)

    t0 = sync(routes)
    # members take the places nearest to them (an optimal assignment never crosses paths)
    starts = np.array([r.end for r in routes])
    firsts = np.array([place(i, 0) for i in range(n)])
    _, order = linear_sum_assignment(np.linalg.norm(starts[:, None] - firsts[None], axis=2))
    offs = offs[order]
    join = max(
        math.hypot(place(i, 0)[0] - r.end[0], place(i, 0)[1] - r.end[1])
        for i, r in enumerate(routes)
    )
    if join > 1e-6:
        for i, r in enumerate(routes):
            r.move_to(*place(i, 0), seconds=max(join / speed, 0.3))
        t0 = sync(routes)
    lengths = np.hypot(seg[:, 0], seg[:, 1])
    times = t0 + np.concatenate([[0.0], np.cumsum(lengths)]) / speed
    for k in range(1, pts.shape[0]):
        for i, r in enumerate(routes):
            r.move_to(*place(i, k), seconds=max(float(times[k] - r.end_time), 1e-3))
    return sync(routes)


def gather_in_circle(
    routes: list[Route], slots: NDArray[np.floating], speed: float, facing_centre: bool = True
) -> float:
    """Move the members to the slots (rows of ``slots``; each to the one that keeps paths from
    crossing) arriving together, then face the centre; returns the time [s]."""
    slots = np.asarray(slots, dtype=np.float64).reshape(-1, 2)
    sync(routes)
    starts = np.array([r.end for r in routes])
    _, order = linear_sum_assignment(np.linalg.norm(starts[:, None] - slots[None], axis=2))
    slots = slots[order]  # nearest slots: the straight paths to them do not cross
    dist = max(
        math.hypot(s[0] - r.end[0], s[1] - r.end[1]) for s, r in zip(slots, routes, strict=True)
    )
    seconds = max(dist / speed, 0.5)
    centre = slots.mean(axis=0)
    for s, r in zip(slots, routes, strict=True):
        r.move_to(float(s[0]), float(s[1]), seconds)
        if facing_centre and len(routes) > 1:
            want = math.atan2(centre[1] - s[1], centre[0] - s[0])
            turn = math.atan2(math.sin(want - r.last_heading), math.cos(want - r.last_heading))
            r.turn_by(turn, 0.8)
    return sync(routes)
