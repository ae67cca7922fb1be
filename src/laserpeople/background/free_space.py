"""Where the beams of the recent frames passed, asked cell by cell: the free-space test of
the occupancy grid (``background/occupancy.py``).

The grid needs one fact from free space: for a cell that becomes occupied in a frame, the
stamp of the last frame in which a beam passed through the cell while the cell had no
return (its occupant arrived when that is within ``arrival_window``; otherwise it was
there at first sight). Stamping every cell along every beam of every frame costs about a
hundred samples a beam (70 000 a frame for 700 beams), but only 2-6 cells a frame become
occupied (median over the frames of the randomised scenes 0 and 2 and of the real demo,
corridor and MiR bags). :class:`BeamLog` therefore keeps the beams of the frames of the
last window, sorted by angle round their origin, and for each asked cell looks up the beams
whose angle passes within the cell's circumscribed circle and recomputes their samples
near the cell with the casting's own arithmetic, so the answer is the casting's, sample for
sample.

The casting (one beam from ``o`` to its return ``p``, ``r = |p - o|``, ``u = (p - o) / r``):
samples ``o + u s_k`` with ``s_k`` the ``k``-th element of ``arange(res / 2, ., res)``,
for every ``s_k < reach = min(r - free_margin, free_range)`` (no sample when
``reach <= 0``); a sample falls in the cell ``(floor(x / res), floor(y / res))``; a cell with
a return in the frame is not free in that frame.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

_CELL_BITS = 21
"""Bits per axis of a cell key (cells within 2**20 cells of the first one seen)."""
_FRAME_SHIFT = 2 * _CELL_BITS
_MAX_FRAME_REL = 1 << 20
"""Frames counted from the last re-basing of the hit keys (re-based before this)."""
_SECTORS = 128
"""Angular sectors round a bundle's origin, each with the reach of its farthest beam."""


class _Rows:
    """Columns of rows appended at the end and dropped from the front (a queue), each a
    view of one growing array; absolute row numbers count every row ever appended."""

    def __init__(self, dtypes: dict[str, type], widths: dict[str, int] | None = None) -> None:
        w = widths or {}
        self._cols = {
            name: np.zeros((256, *((w[name],) if name in w else ())), dtype=dt)
            for name, dt in dtypes.items()
        }
        self._start = 0  # array index of the first live row
        self._end = 0
        self.first = 0
        """Absolute number of the first live row."""

    def __len__(self) -> int:
        return self._end - self._start

    @property
    def end(self) -> int:
        """Absolute number one past the last row."""
        return self.first + len(self)

    def col(self, name: str) -> NDArray[np.generic]:
        """The live rows of column ``name`` (a view)."""
        return self._cols[name][self._start : self._end]

    def append(self, **values: NDArray[np.generic]) -> None:
        """Append rows (every column the same length)."""
        n = len(next(iter(values.values())))
        cap = len(next(iter(self._cols.values())))
        if self._end + n > cap:
            live = len(self)
            size = max(cap, 2 * (live + n))
            for name, arr in self._cols.items():
                new = arr if size == cap else np.zeros((size, *arr.shape[1:]), dtype=arr.dtype)
                new[:live] = arr[self._start : self._end]
                self._cols[name] = new
            self._start, self._end = 0, live
        for name, v in values.items():
            self._cols[name][self._end : self._end + n] = v
        self._end += n

    def drop_to(self, absolute: int) -> None:
        """Drop the rows before the absolute row number ``absolute``."""
        k = min(max(absolute - self.first, 0), len(self))
        self._start += k
        self.first += k


class BeamLog:
    """The beams of the frames of the last ``window`` seconds (module docstring).

    Args:
        resolution: Cell size [m].
        free_range: Free space reaches at most this far from the sensor [m].
        free_margin: The part of a beam this close before its return is not free [m].
        window: Frames older than this before the newest one are forgotten [s].
    """

    def __init__(
        self, resolution: float, free_range: float, free_margin: float, window: float
    ) -> None:
        self.resolution = resolution
        self.free_range = free_range
        self.free_margin = free_margin
        self.window = window
        # the casting's sample distances: arange's k-th element does not depend on its stop
        self._steps = np.arange(0.5 * resolution, free_range + resolution, resolution)
        # a cell's circumscribed circle, widened against rounding
        self._radius = resolution * math.sqrt(0.5) * (1.0 + 1e-9) + 1e-12
        self._sector_width = 2.0 * math.pi / _SECTORS
        # beams, sorted by (bundle, angle): key = 8 bundle + 4 + angle (bundles 1.7 apart)
        self._beams = _Rows({"key": np.float64, "ux": np.float64, "uy": np.float64, "n": np.int64})
        # bundles (the beams of one frame from one origin), in the order they were added
        self._bundles = _Rows(
            {
                "ox": np.float64,
                "oy": np.float64,
                "reach": np.float64,  # the farthest sample's reach
                "stamp": np.float64,
                "frame": np.int64,
                "beams_end": np.int64,
                "hits_end": np.int64,
                "sector_reach": np.float64,  # (B, _SECTORS); -inf: no beam
            },
            {"sector_reach": _SECTORS},
        )
        # the cells with a return in each logged frame: key = frame_rel << 42 | cell key
        self._hits = _Rows({"key": np.int64, "cell": np.int64, "frame": np.int64})
        self._frames = 0
        self._frame_base = 0
        self._cell_base: tuple[int, int] | None = None

    def __len__(self) -> int:
        """Number of bundles logged."""
        return len(self._bundles)

    def _cell_keys(self, cells: IntArray) -> IntArray:
        """One int per cell (K, 2), increasing with (i, j) lexicographically."""
        if self._cell_base is None:
            self._cell_base = (int(cells[0, 0]), int(cells[0, 1]))
        half = 1 << (_CELL_BITS - 1)
        i = np.clip(cells[:, 0] - self._cell_base[0] + half, 0, (1 << _CELL_BITS) - 1)
        j = np.clip(cells[:, 1] - self._cell_base[1] + half, 0, (1 << _CELL_BITS) - 1)
        return np.asarray((i << _CELL_BITS) | j, dtype=np.int64)

    def forget_before(self, stamp: float) -> None:
        """Forget the bundles of frames stamped before ``stamp`` (from the oldest on, up to
        the first one that is not)."""
        older = self._bundles.col("stamp") < stamp
        k = older.size if older.all() else int(np.argmin(older))  # the first one not older
        if k == 0:
            return
        self._beams.drop_to(int(self._bundles.col("beams_end")[k - 1]))
        self._hits.drop_to(int(self._bundles.col("hits_end")[k - 1]))
        self._bundles.drop_to(self._bundles.first + k)

    def add(
        self,
        stamp: float,
        origins: FloatArray,
        points: FloatArray,
        r: FloatArray,
        hit_cells: IntArray,
    ) -> None:
        """Log one frame: its beams from ``origins`` (N, 2) to ``points`` (N, 2) of lengths
        ``r`` (N,) [m], and ``hit_cells`` (K, 2), the cells with a return in it (sorted
        lexicographically, each once)."""
        reach = np.minimum(r - self.free_margin, self.free_range)
        keep = reach > 0
        if not keep.any():
            return
        d = points - origins
        u = d[keep] / r[keep, None]
        o = origins[keep]
        n = np.searchsorted(self._steps, reach[keep], side="left")  # samples per beam
        if bool((o == o[0]).all()):  # one sensor position (the usual case)
            groups = [(o[0], np.ones(len(o), dtype=bool))]
        else:
            uniq, inverse = np.unique(o, axis=0, return_inverse=True)
            groups = [(uniq[g], inverse.reshape(-1) == g) for g in range(len(uniq))]
        frame = self._frames
        self._frames += 1
        if frame - self._frame_base >= _MAX_FRAME_REL:
            self._rebase_hits(frame)
        keys = self._cell_keys(hit_cells) if len(hit_cells) else np.zeros(0, dtype=np.int64)
        self._hits.append(
            key=((frame - self._frame_base) << _FRAME_SHIFT) | keys,
            cell=keys,
            frame=np.full(len(keys), frame, dtype=np.int64),
        )
        for origin, member in groups:
            seq = self._bundles.end
            ux, uy, nb = u[member, 0], u[member, 1], n[member]
            angle = np.arctan2(uy, ux)
            order = np.argsort(angle, kind="stable")
            sector = np.minimum(
                np.floor((angle[order] + math.pi) / self._sector_width), _SECTORS - 1
            ).astype(np.int64)
            farthest = np.full(_SECTORS, -np.inf)
            np.maximum.at(farthest, sector, reach[keep][member][order])
            self._beams.append(
                key=(seq * 8.0 + 4.0) + angle[order], ux=ux[order], uy=uy[order], n=nb[order]
            )
            self._bundles.append(
                ox=origin[:1],
                oy=origin[1:],
                reach=np.array([float(reach[keep][member].max())]),
                stamp=np.array([stamp]),
                frame=np.array([frame]),
                beams_end=np.array([self._beams.end]),
                hits_end=np.array([self._hits.end]),
                sector_reach=farthest[None, :],
            )

    def _rebase_hits(self, frame: int) -> None:
        """Count the hit keys' frames from ``frame`` on (older ones go negative)."""
        self._frame_base = frame
        rel = self._hits.col("frame") - frame
        self._hits.col("key")[:] = (rel << _FRAME_SHIFT) | self._hits.col("cell")

    def last_free(self, cells: IntArray) -> FloatArray:
        """(M,) stamp [s] of the last logged frame in which a sample of a beam fell in each
        of ``cells`` (M, 2) while the cell had no return in that frame; ``-inf`` where
        none did."""
        m_cells = cells.shape[0]
        out = np.full(m_cells, -np.inf)
        nb = len(self._bundles)
        if m_cells == 0 or nb == 0:
            return out
        res, rad = self.resolution, self._radius
        box, boy = self._bundles.col("ox"), self._bundles.col("oy")
        # (B, M): bundle major, so that the keys searched below come in increasing order
        vx = ((cells[:, 0] + 0.5) * res)[None, :] - box[:, None]  # cell centre - origin
        vy = ((cells[:, 1] + 0.5) * res)[None, :] - boy[:, None]
        dist = np.hypot(vx, vy)
        # beams whose angle passes within the circle: |angle - theta| <= asin(rad / dist)
        theta = np.arctan2(vy, vx)
        half = np.where(dist > rad, np.arcsin(rad / np.maximum(dist, rad)) + 1e-9, math.pi + 1e-9)
        # a bundle can sample the cell only if a beam of a sector the interval touches
        # reaches past dist - rad (the interval touching up to three sectors; more: maybe)
        width = self._sector_width
        s_lo = np.floor((theta - half + math.pi) / width).astype(np.int64)
        span = np.floor((theta + half + math.pi) / width).astype(np.int64) - s_lo
        sector_reach = self._bundles.col("sector_reach")
        rows = np.arange(nb)[:, None]
        need = dist - rad
        can = span > 2
        for step in range(3):
            got = sector_reach[rows, (s_lo + step) % _SECTORS] > need
            can |= got & (span >= step)
        pb, pm = np.nonzero(can)
        if not pm.size:
            return out
        vx, vy, dist = vx[pb, pm], vy[pb, pm], dist[pb, pm]
        theta, half = theta[pb, pm], half[pb, pm]
        lo, hi = theta - half, theta + half
        pi = math.pi
        base = (pb + self._bundles.first) * 8.0 + 4.0
        a, b = np.maximum(lo, -pi), np.minimum(hi, pi)
        pairs = np.arange(pm.size)
        low, high = np.nonzero(lo < -pi)[0], np.nonzero(hi > pi)[0]
        if low.size or high.size:  # round the back of the circle: two intervals
            pairs = np.concatenate([pairs, low, high])
            a = np.concatenate([a, lo[low] + 2 * pi, np.full(high.size, -pi)])
            b = np.concatenate([b, np.full(low.size, pi), hi[high] - 2 * pi])
            base = base[pairs]
        keys = self._beams.col("key")
        i0 = np.searchsorted(keys, base + a, side="left")
        i1 = np.searchsorted(keys, base + b, side="right")
        count = np.maximum(i1 - i0, 0)
        total = int(count.sum())
        if total == 0:
            return out
        pair = np.repeat(pairs, count)
        beam = np.arange(total) - np.repeat(np.cumsum(count) - count, count)
        beam += np.repeat(i0, count)
        ux, uy = self._beams.col("ux")[beam], self._beams.col("uy")[beam]
        n = self._beams.col("n")[beam]
        cvx, cvy = vx[pair], vy[pair]
        ox, oy = box[pb[pair]], boy[pb[pair]]
        # the samples within rad of the centre along the beam: s in [proj - rad, proj + rad],
        # at most two steps; from one step earlier (rounding), three
        proj = cvx * ux + cvy * uy
        k0 = np.floor((proj - rad - 0.5 * res) / res)
        k = (np.maximum(k0, 0.0).astype(np.int64)[None, :] + np.arange(3)[:, None]).ravel()
        ux3, uy3, n3 = np.tile(ux, 3), np.tile(uy, 3), np.tile(n, 3)
        ok = k < n3
        s = self._steps[np.minimum(k, self._steps.size - 1)]
        x = ux3 * s  # the casting's arithmetic, operation by operation
        x += np.tile(ox, 3)
        y = uy3 * s
        y += np.tile(oy, 3)
        ci, cj = cells[pm[pair], 0], cells[pm[pair], 1]
        ok &= np.floor(x / res) == np.tile(ci, 3)
        ok &= np.floor(y / res) == np.tile(cj, 3)
        if not ok.any():
            return out
        q = np.tile(pair, 3)[ok]
        cell_of, bundle_of = pm[q], pb[q]
        # not where the cell had a return in that frame
        frame_rel = self._bundles.col("frame")[bundle_of] - self._frame_base
        hk = (frame_rel << _FRAME_SHIFT) | self._cell_keys(cells[cell_of])
        hkeys = self._hits.col("key")
        at = np.minimum(np.searchsorted(hkeys, hk), max(hkeys.size - 1, 0))
        free = hkeys[at] != hk if hkeys.size else np.ones(hk.size, dtype=bool)
        if not free.any():
            return out
        last = np.full(m_cells, -1, dtype=np.int64)
        np.maximum.at(last, cell_of[free], bundle_of[free])
        seen = last >= 0
        out[seen] = self._bundles.col("stamp")[last[seen]]
        return out


__all__ = ["BeamLog"]
