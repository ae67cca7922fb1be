"""The cells along each beam of a laser that stands still, kept from frame to frame: the
free-space casting of the occupancy grid (``background/occupancy.py``) without sampling
every beam again in every frame.

The casting samples a beam from ``o`` to its return ``p`` (``r = |p - o|``, direction
``u = (p - o) / r``) at ``o + u s_k``, ``s_k`` the ``k``-th element of
``arange(res / 2, ., res)``, for every ``s_k < reach = min(r - free_margin, free_range)``,
and marks the cell ``(floor(x / res), floor(y / res))`` of each sample. For a laser that
stands still a beam keeps its direction from frame to frame (up to rounding, ~1e-16) and
only its reach changes, so its cells are a prefix of one list. :class:`CastCache` keeps,
per beam (sensor and beam index), the cells of all its samples out to ``free_range``,
computed with the casting's own arithmetic from the direction ``u`` it had then. A frame
takes the first ``n`` cells of each beam (``n`` = the samples below its reach) from the
cache when

- the sensor stands where it stood (bit for bit) and the grid's arrays have not moved,
- the beam's direction differs from the cached one by at most ``DIRECTION_TOL`` per
  coordinate, and
- every cached sample of the beam lies at least ``BOUNDARY_MARGIN`` from a cell boundary
  (so that the change of direction, at most ``DIRECTION_TOL * free_range``, and the
  rounding cannot move a sample into another cell);

the other beams are sampled afresh and cached. The cells marked are thus exactly the
casting's: the cache only saves the sampling (on a 717-beam scan, 0.39 of the grid's
0.79 ms a frame).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

DIRECTION_TOL = 1e-12
"""Largest change per coordinate of a beam's unit direction that keeps its cached cells."""
BOUNDARY_MARGIN = 1e-6
"""Smallest distance [m] of a cached sample from a cell boundary that keeps its beam's cells
(far above the rounding of the sample's coordinates, ~1e-11 m at 10 km)."""


class CastCache:
    """Cells of every sample of each beam of a laser that stands still (module docstring).

    Args:
        resolution: Cell size [m].
        steps: The casting's sample distances ``arange(res / 2, free_range + res, res)``
            [m]; a beam's ``n`` samples are the first ``n`` of them.
    """

    def __init__(self, resolution: float, steps: FloatArray) -> None:
        self.resolution = resolution
        self.steps = steps
        self._where: tuple[float, float, int, int, int] | None = None  # sensor, grid
        self._ids = np.zeros(0, dtype=np.int64)  # sorted beam ids
        self._u = np.zeros((0, 2))  # the direction each row was computed from
        self._safe = np.zeros(0, dtype=bool)  # every sample clear of the cell boundaries
        self._cells = np.zeros((0, steps.size), dtype=np.int64)  # flat index per sample
        self._k = np.arange(steps.size)

    def __len__(self) -> int:
        """Number of beams cached."""
        return int(self._ids.size)

    def _rows(
        self, origin: FloatArray, u: FloatArray, grid: tuple[int, int, int]
    ) -> tuple[IntArray, NDArray[np.bool_]]:
        """Flat indices (B, K) of the cells of all K samples of the beams ``u`` (B, 2) from
        ``origin``, with the casting's arithmetic, and whether each beam is safe."""
        res = self.resolution
        o0, o1, width = grid
        x = u[:, 0, None] * self.steps[None, :]
        x += origin[0]
        np.divide(x, res, out=x)
        y = u[:, 1, None] * self.steps[None, :]
        y += origin[1]
        np.divide(y, res, out=y)
        fx, fy = np.floor(x), np.floor(y)
        margin = BOUNDARY_MARGIN / res  # in cells
        safe = ((x - fx) >= margin) & ((fx + 1.0 - x) >= margin)
        safe &= ((y - fy) >= margin) & ((fy + 1.0 - y) >= margin)
        fx -= o0
        fx *= width
        fy -= o1
        fx += fy
        return fx.astype(np.int64), np.asarray(safe.all(axis=1))

    def free_flat(
        self,
        origin: FloatArray,
        ids: IntArray,
        u: FloatArray,
        n: IntArray,
        grid: tuple[int, int, int],
    ) -> IntArray:
        """Flat indices of the cells of the first ``n`` (B,) samples of the beams ``ids``
        (B,) (unique) with directions ``u`` (B, 2) from ``origin`` (2,), in the cache's
        order of the beams (the order does not matter to the casting);
        ``grid`` = (row origin, column origin, row length) of the grid's arrays."""
        where = (float(origin[0]), float(origin[1]), *grid)
        if where != self._where:  # the sensor or the arrays moved: start afresh
            self._where = where
            self._ids = np.zeros(0, dtype=np.int64)
            self._u = np.zeros((0, 2))
            self._safe = np.zeros(0, dtype=bool)
            self._cells = np.zeros((0, self.steps.size), dtype=np.int64)
        cached = self._ids
        pos = np.minimum(np.searchsorted(cached, ids), max(cached.size - 1, 0))
        if cached.size:
            keep = cached[pos] == ids
            keep &= self._safe[pos]
            keep &= (np.abs(u - self._u[pos]) <= DIRECTION_TOL).all(axis=1)
        else:
            keep = np.zeros(ids.size, dtype=bool)
        if not keep.all():
            fresh = ~keep
            cells, safe = self._rows(origin, u[fresh], grid)
            known = np.zeros(ids.size, dtype=bool)
            if cached.size:
                known = cached[pos] == ids
            over = fresh & known  # recompute in place
            if over.any():
                at = pos[over]
                sub = known[fresh]
                self._cells[at] = cells[sub]
                self._u[at] = u[over]
                self._safe[at] = safe[sub]
            new = fresh & ~known
            if new.any():
                sub = ~known[fresh]
                all_ids = np.concatenate([cached, ids[new]])
                order = np.argsort(all_ids, kind="stable")
                self._ids = all_ids[order]
                self._u = np.concatenate([self._u, u[new]])[order]
                self._safe = np.concatenate([self._safe, safe[sub]])[order]
                self._cells = np.concatenate([self._cells, cells[sub]])[order]
                pos = np.searchsorted(self._ids, ids)
        count = np.zeros(self._ids.size, dtype=np.int64)  # samples per cached beam (0: absent)
        count[pos] = n
        return np.asarray(self._cells[self._k[None, :] < count[:, None]])


__all__ = ["BOUNDARY_MARGIN", "DIRECTION_TOL", "CastCache"]
