"""The static world: walls, furniture and clutter, and the map exported for background subtraction.

A :class:`StaticObject` is a set of circles and segments that share an object id and a
height range ``[z_min, z_max]`` [m]: a scanner mounted at height ``h`` sees the object only
when ``z_min <= h <= z_max`` (a table top is invisible to a scanner at 0.2 m, its legs
are not). Walls carry object id -1, as :class:`~laserpeople.truth.BeamLabels` asks;
every other object gets its own id.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.sim.raycast import Primitives

FloatArray = NDArray[np.float64]

WALL_HEIGHT = 3.0
"""Height of walls and pillars [m]."""


@dataclass(frozen=True, eq=False)
class StaticObject:
    """One piece of the static world.

    Attributes:
        kind: What it is ("wall", "box", "table-leg", "chair-leg", "bin", "pillar", ...).
        circles: (k, 3) rows ``x, y, radius`` [m].
        segments: (m, 4) rows ``x0, y0, x1, y1`` [m].
        z_min: Lowest height at which a scanner sees it [m].
        z_max: Highest height at which a scanner sees it [m].
        obj_id: Object id in the beam labels; -1 for walls.
    """

    kind: str
    circles: FloatArray = field(default_factory=lambda: np.empty((0, 3)))
    segments: FloatArray = field(default_factory=lambda: np.empty((0, 4)))
    z_min: float = 0.0
    z_max: float = WALL_HEIGHT
    obj_id: int = -1

    def __post_init__(self) -> None:
        object.__setattr__(self, "circles", np.asarray(self.circles, float).reshape(-1, 3))
        object.__setattr__(self, "segments", np.asarray(self.segments, float).reshape(-1, 4))

    def visible_at(self, height: float) -> bool:
        """Whether a scanner at ``height`` [m] sees this object."""
        return self.z_min <= height <= self.z_max


def polygon_segments(corners: NDArray[np.floating]) -> FloatArray:
    """Closed polygon (k, 2) -> its k edges as rows ``x0, y0, x1, y1``."""
    c = np.asarray(corners, dtype=np.float64).reshape(-1, 2)
    return np.hstack([c, np.roll(c, -1, axis=0)])


def rectangle_corners(
    cx: float, cy: float, length: float, width: float, angle: float
) -> FloatArray:
    """Corners (4, 2) of a ``length`` x ``width`` rectangle centred at (cx, cy), long side at
    ``angle`` [rad]."""
    c, s = math.cos(angle), math.sin(angle)
    half = np.array([[1, 1], [-1, 1], [-1, -1], [1, -1]], float) * [length / 2, width / 2]
    return half @ np.array([[c, s], [-s, c]]) + [cx, cy]


def room(
    x0: float, y0: float, x1: float, y1: float, doors: tuple[tuple[str, float, float], ...] = ()
) -> list[StaticObject]:
    """Four walls of the rectangle [x0, x1] x [y0, y1] [m], with door gaps.

    ``doors`` are ``(side, centre, width)`` with side one of "south" (y = y0), "north"
    (y = y1), "west" (x = x0), "east" (x = x1) and centre the coordinate along that wall.
    """
    sides = {
        "south": ((x0, y0), (x1, y0)),
        "east": ((x1, y0), (x1, y1)),
        "north": ((x1, y1), (x0, y1)),
        "west": ((x0, y1), (x0, y0)),
    }
    out: list[StaticObject] = []
    for side, (a, b) in sides.items():
        pa, pb = np.array(a, float), np.array(b, float)
        axis = 0 if side in ("south", "north") else 1
        gaps = sorted(
            (c - w / 2, c + w / 2) for s, c, w in doors if s == side
        )  # along the wall's coordinate
        lo_c, hi_c = min(pa[axis], pb[axis]), max(pa[axis], pb[axis])
        pieces = []
        cur = lo_c
        for g0, g1 in gaps:
            if g0 > cur:
                pieces.append((cur, min(g0, hi_c)))
            cur = max(cur, g1)
        if cur < hi_c:
            pieces.append((cur, hi_c))
        segs = []
        for p0, p1 in pieces:
            q0, q1 = pa.copy(), pa.copy()
            q0[axis], q1[axis] = p0, p1
            segs.append([*q0, *q1])
        out.append(StaticObject("wall", segments=np.array(segs).reshape(-1, 4)))
    return out


def wall(x0: float, y0: float, x1: float, y1: float) -> StaticObject:
    """A straight wall from (x0, y0) to (x1, y1) [m]."""
    return StaticObject("wall", segments=np.array([[x0, y0, x1, y1]], float))


def box(
    cx: float, cy: float, length: float, width: float, angle: float = 0.0, height: float = 0.8
) -> StaticObject:
    """A closed box (cupboard, crate) standing on the floor."""
    segs = polygon_segments(rectangle_corners(cx, cy, length, width, angle))
    return StaticObject("box", segments=segs, z_max=height)


def table(
    cx: float, cy: float, length: float = 1.2, width: float = 0.8, angle: float = 0.0
) -> list[StaticObject]:
    """A table: four round legs (radius 0.025 m) up to 0.72 m; the top is above any
    foot-height scanner and below an upper-body one."""
    corners = rectangle_corners(cx, cy, length - 0.1, width - 0.1, angle)
    return [
        StaticObject("table-leg", circles=np.array([[x, y, 0.025]]), z_max=0.72) for x, y in corners
    ]


def chair(cx: float, cy: float, angle: float = 0.0) -> list[StaticObject]:
    """A chair: four legs (radius 0.015 m) 0.4 m apart, up to 0.45 m; its back at 0.45-0.9 m."""
    corners = rectangle_corners(cx, cy, 0.4, 0.4, angle)
    legs = [
        StaticObject("chair-leg", circles=np.array([[x, y, 0.015]]), z_max=0.45) for x, y in corners
    ]
    back = corners[[1, 2]]  # the chair's -x side
    legs.append(
        StaticObject("chair-back", segments=np.array([[*back[0], *back[1]]]), z_min=0.45, z_max=0.9)
    )
    return legs


def round_bin(cx: float, cy: float, radius: float = 0.14) -> StaticObject:
    """A round waste bin (leg-like at foot height)."""
    return StaticObject("bin", circles=np.array([[cx, cy, radius]]), z_max=0.5)


def pillar(cx: float, cy: float, radius: float = 0.25) -> StaticObject:
    """A round pillar from floor to ceiling."""
    return StaticObject("pillar", circles=np.array([[cx, cy, radius]]), z_max=WALL_HEIGHT)


def pole(cx: float, cy: float, radius: float = 0.04, height: float = 1.8) -> StaticObject:
    """A thin pole (coat stand, barrier post): very leg-like at foot height."""
    return StaticObject("pole", circles=np.array([[cx, cy, radius]]), z_max=height)


class World:
    """The static objects of a scene; numbers the non-wall objects 0, 1, 2, ...

    Example:
        >>> w = World([*room(0, 0, 5, 5), round_bin(1, 1)])
        >>> w.objects[-1].obj_id
        0
    """

    def __init__(self, objects: list[StaticObject]) -> None:
        numbered: list[StaticObject] = []
        next_id = 0
        for o in objects:
            oid = -1
            if o.kind != "wall":
                oid = next_id
                next_id += 1
            numbered.append(StaticObject(o.kind, o.circles, o.segments, o.z_min, o.z_max, oid))
        self.objects: tuple[StaticObject, ...] = tuple(numbered)
        self.n_objects = next_id
        self._cache: dict[float, Primitives] = {}

    def primitives(self, height: float) -> Primitives:
        """The shapes a scanner at ``height`` [m] sees (world frame), with labels."""
        if height in self._cache:
            return self._cache[height]
        seen = [o for o in self.objects if o.visible_at(height)]
        circles = np.concatenate([o.circles for o in seen]) if seen else np.empty((0, 3))
        segs = np.concatenate([o.segments for o in seen]) if seen else np.empty((0, 4))
        c_obj: NDArray[np.int64] | list[int] = (
            np.concatenate([np.full(len(o.circles), o.obj_id) for o in seen]) if seen else []
        )
        s_obj: NDArray[np.int64] | list[int] = (
            np.concatenate([np.full(len(o.segments), o.obj_id) for o in seen]) if seen else []
        )
        c_lab = np.full((len(circles), 4), -1, dtype=np.int32)
        c_lab[:, 3] = c_obj
        s_lab = np.full((len(segs), 4), -1, dtype=np.int32)
        s_lab[:, 3] = s_obj
        prims = Primitives(
            circle_centres=circles[:, :2].copy(),
            circle_radii=circles[:, 2].copy(),
            circle_labels=c_lab,
            ellipse_centres=np.empty((0, 2)),
            ellipse_axes=np.empty((0, 2)),
            ellipse_angles=np.empty(0),
            ellipse_labels=np.empty((0, 4), dtype=np.int32),
            segment_starts=segs[:, :2].copy(),
            segment_ends=segs[:, 2:].copy(),
            segment_labels=s_lab,
        )
        self._cache[height] = prims
        return prims

    def static_map(self) -> dict[str, Any]:
        """The map for background subtraction, as JSON-ready lists.

        Keys: ``segments`` rows ``[x0, y0, x1, y1, z_min, z_max, obj_id]`` and ``circles``
        rows ``[x, y, r, z_min, z_max, obj_id]`` (metres, world frame), plus ``kinds``
        (object id -> kind).
        """
        segs: list[list[float]] = []
        circles: list[list[float]] = []
        kinds: dict[str, str] = {}
        for o in self.objects:
            extra = [o.z_min, o.z_max, o.obj_id]
            segs.extend([*map(float, s), *extra] for s in o.segments)
            circles.extend([*map(float, c), *extra] for c in o.circles)
            if o.obj_id >= 0:
                kinds[str(o.obj_id)] = o.kind
        return {"segments": segs, "circles": circles, "kinds": kinds}
