"""A map of what stays put, counted over a whole recording of a moving robot.

The decaying occupancy grid (:mod:`laserpeople.background.occupancy`) learns online: the
walls and furniture a robot drives past are new to it, and every return on them is
foreground until it has seen them long enough. A recording on disk can be read whole first.
:class:`RecordingMapCounter` counts, per cell of a world-frame grid and over the frames it
is given, the frames with a return in the cell (*hits*) and the frames whose beams passed
through it to a return behind (*seen free*; up to ``free_range``, stopping ``free_margin``
before the return; a cell within ``hit_reach`` of a return of the frame is not seen free in
it: the same post or chair leg, seen from poses that drift by some centimetres, or between
the beams that hit it, would otherwise be seen through). A cell is static when it was hit in
at least ``min_hits`` frames and in at least ``hit_share`` of the frames that saw it, hit or
free: a wall is never seen through;
the places of a walker, or of a person who stood for a while and left, are. A person who
stands on one spot for the whole recording is not told from furniture.

:meth:`RecordingMapCounter.static_map` returns the static cells as an
:class:`~laserpeople.background.occupancy.OccupancyMap`, the prior map a ``map.yaml`` would
give (``track --map``). The counts take 12 bytes per cell of the area the lasers saw (a
100 m x 100 m floor at 0.05 m: 48 MB).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.background.occupancy import OccupancyMap, grown_extent, moved_into

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True)
class RecordingMapRule:
    """How the map is counted and which cells are static (module docstring).

    Attributes:
        resolution: Cell size [m].
        min_hits: Fewest frames with a return in a static cell.
        hit_share: Smallest share of hits among the frames that saw a static cell.
        free_range: Free space is cast along each beam up to this range [m].
        free_margin: The part of a beam this close before its return is not free [m].
        hit_reach: A cell this close to a return of a frame is not seen free in that
            frame [m] (0: only the cells with a return).
    """

    resolution: float = 0.05
    min_hits: int = 5
    hit_share: float = 0.97
    free_range: float = 10.0
    free_margin: float = 0.2
    hit_reach: float = 0.2

    def reach_offsets(self) -> IntArray:
        """Cell offsets (K, 2) within ``hit_reach`` of a cell (by their centres)."""
        k = int(self.hit_reach / self.resolution)
        span = np.arange(-k, k + 1)
        di, dj = np.meshgrid(span, span, indexing="ij")
        keep = di * di + dj * dj <= k * k
        return np.column_stack([di[keep], dj[keep]]).astype(np.int64)


class RecordingMapCounter:
    """Hits and seen-free counts per cell over the frames given to :meth:`add`."""

    def __init__(self, rule: RecordingMapRule | None = None) -> None:
        self.rule = rule if rule is not None else RecordingMapRule()
        self._origin = np.zeros(2, dtype=np.int64)  # cell index of array element [0, 0]
        self._hits = np.zeros((0, 0), dtype=np.int32)
        self._free = np.zeros((0, 0), dtype=np.int32)
        self._marked = np.zeros((0, 0), dtype=np.int32)  # last frame that saw the cell free
        self.frames = 0
        """Frames counted."""
        step = self.rule.resolution
        self._steps = np.arange(0.5 * step, self.rule.free_range, step)
        self._reach = self.rule.reach_offsets()

    def _cells(self, xy: FloatArray) -> IntArray:
        return np.floor(xy / self.rule.resolution).astype(np.int64)

    def _grow(self, lo: IntArray, hi: IntArray) -> None:
        """Grow the arrays to hold the cells from ``lo`` (2,) to ``hi`` (2,)."""
        shape = np.array(self._hits.shape, dtype=np.int64)
        if shape.prod() and (lo >= self._origin).all() and (hi < self._origin + shape).all():
            return
        new_lo, size = grown_extent(
            self._origin,
            self._hits.shape,
            lo,
            hi,
            self.rule.resolution,
            "the map of the whole recording",
            "set [auto_background] prelearn = false",
        )
        at = (self._origin, new_lo, size)
        self._hits = moved_into(self._hits, *at, 0)
        self._free = moved_into(self._free, *at, 0)
        self._marked = moved_into(self._marked, *at, 0)
        self._origin = new_lo

    def add(self, origins: FloatArray, points: FloatArray) -> None:
        """Count one frame: returns ``points`` (N, 2) [m] in the world frame, measured
        from the laser positions ``origins`` (N, 2) [m] (one row per point)."""
        self.frames += 1
        if points.shape[0] == 0:
            return
        d = points - origins
        r = np.hypot(d[:, 0], d[:, 1])
        reach = np.minimum(r - self.rule.free_margin, self.rule.free_range)
        along = self._steps[None, :] < reach[:, None]  # (N, S)
        beam, k = np.nonzero(along)
        unit = d[beam] / r[beam, None]
        free_xy = origins[beam] + unit * self._steps[k, None]
        hit = self._cells(points)
        free = self._cells(free_xy)
        # the free samples lie on the segments from the origins to the returns
        pad = self._reach.max(axis=0)  # the cells within hit_reach of the returns too
        ends = np.array([hit.min(axis=0) - pad, hit.max(axis=0) + pad])
        start = self._cells(np.array([origins.min(axis=0), origins.max(axis=0)]))
        self._grow(np.minimum(ends[0], start[0]), np.maximum(ends[1], start[1]))
        w = self._hits.shape[1]
        hit_flat = (hit[:, 0] - self._origin[0]) * w + (hit[:, 1] - self._origin[1])
        free_flat = (free[:, 0] - self._origin[0]) * w + (free[:, 1] - self._origin[1])
        near_flat = (np.unique(hit_flat)[:, None] + self._reach @ np.array([w, 1])).ravel()
        # a[idx] += 1 adds once per distinct index: each cell counts once per frame
        hits, seen, marked = (
            self._hits.reshape(-1),
            self._free.reshape(-1),
            self._marked.reshape(-1),
        )
        hits[hit_flat] += 1
        seen[free_flat] += 1
        marked[free_flat] = self.frames
        # passed in this frame within hit_reach of one of its returns: not seen free
        seen[near_flat[marked[near_flat] == self.frames]] -= 1

    def _static(self) -> NDArray[np.bool_]:
        rule = self.rule
        hits = self._hits.astype(np.float64)
        return (self._hits >= rule.min_hits) & (hits >= rule.hit_share * (hits + self._free))

    def static_map(self, source: str = "") -> OccupancyMap:
        """The static cells as a prior map (``source`` names it for the user)."""
        static = self._static()
        res = self.rule.resolution
        # arrays are indexed (x cell, y cell); a map's rows run from the largest y down
        occupied = np.ascontiguousarray(static.T[::-1])
        x0, y0 = (self._origin * res).tolist()
        return OccupancyMap(occupied=occupied, resolution=res, origin=(x0, y0, 0.0), path=source)


__all__ = ["RecordingMapCounter", "RecordingMapRule"]
