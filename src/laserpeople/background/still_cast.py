"""Free-space casting of a laser that stands still, kept up to date beam by beam: the
occupancy grid's ``seen_free`` (``background/occupancy.py``) without sampling every beam
in every frame.

The casting samples a beam from ``o`` to its return ``p`` (``r = |p - o|``, direction
``u = (p - o) / r``) at ``o + u s_k``, ``s_k`` the ``k``-th element of
``arange(res / 2, ., res)``, for every ``s_k < reach = min(r - free_margin, free_range)``;
every cell with a sample and without a return in the frame gets the frame's stamp
(``seen_free``, the last time a beam passed through it). That is about a hundred samples a
beam; on a 717-beam scan 32 000 a frame, half of the grid's time per frame.

For a laser that stands still a beam keeps its direction from frame to frame (up to
rounding, ~1e-16) and only its reach changes, so its cells are a prefix of one list, and
from one frame to the next most beams keep the number of their samples. :class:`StillCast`
keeps, per beam (sensor and beam index), the cells of all its samples out to
``free_range`` (computed with the casting's own arithmetic) and per cell the number of
samples of the last frame in it (its *coverage*). A frame changes the coverage only by the
samples its beams gained or lost. A cell *live* (covered in the last frame and without a
return in it) has ``seen_free`` = the last frame's stamp without that being written; the
stamp is written into the grid's array when a cell stops being live (it loses its last
sample, or gets a return while covered), and for every live cell when the laser moves
(:meth:`StillCast.settle`). The grid's ``seen_free`` is therefore the same as with the
casting of every sample, bit for bit.

A beam takes its cells from its list when the sensor stands where it stood (bit for bit),
the grid's arrays have not moved, its direction differs from the listed one by at most
:data:`DIRECTION_TOL` per coordinate, and every listed sample lies at least
:data:`BOUNDARY_MARGIN` from a cell boundary (so that the change of direction, at most
``DIRECTION_TOL * free_range``, and the rounding cannot move a sample into another cell);
otherwise its list is computed again from its present direction.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

DIRECTION_TOL = 1e-12
"""Largest change per coordinate of a beam's unit direction that keeps its listed cells."""
BOUNDARY_MARGIN = 1e-9
"""Smallest distance [m] of a listed sample from a cell boundary that keeps its beam's list
when its direction changed (above ``DIRECTION_TOL`` times the sample's distance, 1e-11 m at
10 m, plus the rounding of its coordinates, ~1e-11 m within :data:`MAX_COORDINATE`)."""
MAX_COORDINATE = 1e4
"""Sensors farther than this [m] from the origin of the frame are never taken as still."""

TABLE_SIZE = 1 << 16
"""Beam ids below this are looked up in a table of positions (one laser's beam indices)."""

Where = tuple[float, float, int, int, int, int]
"""Sensor x, y [m]; the grid arrays' row and column origin [cells], row length and size."""


class StillCast:
    """Coverage of the grid by the beams of a laser that stands still (module docstring).

    Args:
        resolution: Cell size [m].
        steps: The casting's sample distances ``arange(res / 2, free_range + res, res)``
            [m]; a beam's ``n`` samples are the first ``n`` of them.

    Attributes:
        active: True while the coverage stands for the grid's live cells.
    """

    def __init__(self, resolution: float, steps: FloatArray) -> None:
        self.resolution = resolution
        self.steps = steps
        self.active = False
        self._where: Where | None = None
        self._k = np.arange(steps.size)
        self._arange = np.arange(0)
        self._reset()

    def _reset(self) -> None:
        self._ids = np.zeros(0, dtype=np.int64)  # sorted beam ids
        self._table = np.zeros(0, dtype=np.int64)  # position of each id in _ids (-1: none)
        self._u = np.zeros((0, 2))  # the direction each list was computed from
        self._safe = np.zeros(0, dtype=bool)  # every listed sample clear of the boundaries
        self._all_safe = True  # every listed beam safe
        self._cells = np.zeros((0, self.steps.size), dtype=np.int64)  # flat index per sample
        self._n = np.zeros(0, dtype=np.int64)  # samples of each listed beam in the last frame
        self._cover = np.zeros(0, dtype=np.int32)  # samples per cell in the last frame
        self._hit_frame = np.zeros(0, dtype=np.int64)  # last frame with a return per cell
        self._frame = 0  # number of the last frame cast
        self._stamp = -np.inf  # its stamp

    def _identity(self, n: int) -> IntArray:
        """``arange(n)`` (kept between frames: the positions of the beams in the lists when
        a frame has the listed beams)."""
        if self._arange.size != n:
            self._arange = np.arange(n)
        return self._arange

    def _make_table(self) -> None:
        """The table of :meth:`_positions`, when the ids are few and small (one laser's
        beam indices; none for several lasers' ids, which are large)."""
        ids = self._ids
        if ids.size and ids[0] >= 0 and ids[-1] < TABLE_SIZE:
            self._table = np.full(int(ids[-1]) + 1, -1, dtype=np.int64)
            self._table[ids] = np.arange(ids.size)
        else:
            self._table = np.zeros(0, dtype=np.int64)

    def _positions(self, ids: IntArray) -> tuple[IntArray, NDArray[np.bool_]]:
        """Where the beams ``ids`` (increasing) are in the lists, and whether they are
        listed (the position of an id not listed is any valid index, never read): by
        the table when it holds them, else by bisection."""
        listed, table = self._ids, self._table
        if not listed.size:
            return np.zeros(ids.size, dtype=np.int64), np.zeros(ids.size, dtype=bool)
        if ids.size and table.size and ids[0] >= 0 and ids[-1] < table.size:
            pos = table.take(ids)
            known = pos >= 0
            return np.maximum(pos, 0), known
        pos = np.minimum(np.searchsorted(listed, ids), listed.size - 1)
        return pos, listed[pos] == ids

    def __len__(self) -> int:
        """Number of beams listed."""
        return int(self._ids.size)

    def value(self, seen_free: FloatArray, flat: IntArray) -> FloatArray:
        """``seen_free`` [s] of the cells ``flat`` (flat indices into the grid's arrays),
        given the grid's array ``seen_free`` (flat)."""
        stored = seen_free.take(flat)
        if not self.active:
            return stored
        live = (self._cover.take(flat) > 0) & (self._hit_frame.take(flat) != self._frame)
        return np.where(live, self._stamp, stored)

    def live(self) -> tuple[NDArray[np.int32], IntArray, int, float] | None:
        """What :meth:`value` reads besides ``seen_free`` while active: the samples per
        cell, the last frame with a return per cell, the last frame's number and stamp [s]
        (a cell is live, its ``seen_free`` that stamp, where it has samples and no return
        in that frame); None when not active (``seen_free`` holds every cell's)."""
        if not self.active:
            return None
        return self._cover, self._hit_frame, self._frame, float(self._stamp)

    def settle(self, seen_free: FloatArray) -> None:
        """Write the last frame's stamp into ``seen_free`` (the grid's array, flat, of the
        shape the coverage was made for) for every live cell and stop (the laser moved, or
        the arrays are about to)."""
        if self.active:
            live = (self._cover > 0) & (self._hit_frame != self._frame)
            seen_free[live] = self._stamp
        self.active = False
        self._reset()

    def stays(self, where: Where | None) -> bool:
        """True when ``where`` is where the sensor and the arrays were at the last
        :meth:`still` (bit for bit; None: never), which it does not change."""
        if where is None or max(abs(where[0]), abs(where[1])) > MAX_COORDINATE:
            return False
        return where == self._where

    def still(self, where: Where | None) -> bool:
        """Remember ``where`` the sensor and the arrays are (None: not one still laser);
        True when they were there in the frame before too (bit for bit)."""
        if where is not None and max(abs(where[0]), abs(where[1])) > MAX_COORDINATE:
            where = None
        same = where is not None and where == self._where
        self._where = where
        return same

    def _lists(
        self, origin: FloatArray, u: FloatArray, where: Where
    ) -> tuple[IntArray, NDArray[np.bool_]]:
        """Flat indices (B, K) of the cells of all K samples of the beams ``u`` (B, 2) from
        ``origin``, with the casting's arithmetic, and whether each beam is safe."""
        res = self.resolution
        o0, o1, width = where[2], where[3], where[4]
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

    def cast(
        self,
        seen_free: FloatArray,
        origin: FloatArray,
        ids: IntArray,
        u: FloatArray,
        n: IntArray,
        hit: IntArray,
        stamp: float,
    ) -> None:
        """Cast one frame of the still laser: beams ``ids`` (B,) (increasing) with
        directions ``u`` (B, 2) from ``origin`` (2,) and ``n`` (B,) samples each; ``hit``
        the flat indices of the cells with a return (each once); ``seen_free`` the grid's
        array (flat), where the stamps of the cells that stop being live are written.
        :meth:`still` must have been told where, and said True."""
        assert self._where is not None
        where = self._where
        if not self.active:
            self._reset()
            self._cover = np.zeros(where[5], dtype=np.int32)
            self._hit_frame = np.full(where[5], -1, dtype=np.int64)
            self.active = True
        listed = self._ids
        compiled = _compiled_cast()
        if compiled is not None and listed.size:
            state = (listed, u, self._u, n, self._n, self._cells, self._cover, self._hit_frame)
            done = compiled(
                ids, *state, seen_free, hit, self._safe, self._frame, self._stamp, DIRECTION_TOL
            )
            if done is not NotImplemented:
                self._frame += 1
                self._stamp = stamp
                return
        same = listed.size == ids.size and listed.size > 0 and bool((listed == ids).all())
        if same:  # (the usual frame: the same beams as the lists, in the same order)
            pos = self._identity(ids.size)
            known = np.ones(ids.size, dtype=bool)
            listed_u, listed_safe = self._u, self._safe
        else:
            pos, known = self._positions(ids)
            if listed.size:
                listed_u, listed_safe = self._u.take(pos, axis=0), self._safe[pos]
        keep = known
        if same or (listed.size and bool(known.all())):
            # (the usual frames: every beam listed, and every direction within the tolerance
            # of a safe list or the same bit for bit: one reduction instead of the test per
            # beam below)
            dev = np.abs(u - listed_u)
            top = float(dev.max()) if dev.size else 0.0
            if not (top == 0.0 or (top <= DIRECTION_TOL and self._all_safe)):
                off = np.maximum(dev[:, 0], dev[:, 1])
                keep = (off == 0.0) | (listed_safe & (off <= DIRECTION_TOL))
        elif listed.size:
            # the same direction bit for bit gives the same cells; a close one, when safe
            dev = np.abs(u - listed_u)
            off = np.maximum(dev[:, 0], dev[:, 1])
            keep = (off == 0.0) | (listed_safe & (off <= DIRECTION_TOL))
            keep &= known
        # samples gained (+1) and lost (-1) per cell: cells of [lo, hi) of each changed list
        lost: list[IntArray] = []  # the old samples of beams listed again
        if not keep.all():
            fresh = ~keep
            redo = pos[fresh & known]  # listed beams whose list is computed again
            if redo.size:  # their old samples go
                old = self._cells[redo]
                lost.append(old[self._k[None, :] < self._n[redo, None]])
                self._n[redo] = 0
            lists, safe = self._lists(origin, u[fresh], where)
            sub = known[fresh]
            self._cells[redo] = lists[sub]
            self._u[redo] = u[fresh & known]
            self._safe[redo] = safe[sub]
            new = fresh & ~known
            if new.any():
                all_ids = np.concatenate([listed, ids[new]])
                order = np.argsort(all_ids, kind="stable")
                self._ids = all_ids[order]
                self._u = np.concatenate([self._u, u[new]])[order]
                self._safe = np.concatenate([self._safe, safe[~sub]])[order]
                self._cells = np.concatenate([self._cells, lists[~sub]])[order]
                self._n = np.concatenate([self._n, np.zeros(int(new.sum()), np.int64)])[order]
                pos = np.searchsorted(self._ids, ids)
                self._make_table()
            self._all_safe = bool(self._safe.all())
        if same:  # (every listed beam is in this frame, in the same order)
            n_new = np.array(n, dtype=np.int64)
        else:
            n_new = np.zeros(self._ids.size, dtype=np.int64)  # 0: the beam is not in this frame
            n_new[pos] = n
        apply = _compiled_cast_apply()
        if apply is not None:
            counts = (self._n, self._cells, self._cover, self._hit_frame, seen_free, hit)
            done = apply(n_new, *counts, lost[0] if lost else None, self._frame, self._stamp)
            if done is not NotImplemented:
                self._n = n_new
                self._frame += 1
                self._stamp = stamp
                return
        changed = np.flatnonzero(n_new != self._n)
        n_old = self._n[changed]
        n_now = n_new[changed]
        grows = n_now > n_old
        lo = np.where(grows, n_old, n_now)
        count = np.abs(n_now - n_old)  # the samples [lo, lo + count) of each
        total = int(count.sum())
        # flat indices into the lists (C-contiguous): row * K + lo + the sample's rank
        cum = np.cumsum(count)
        first_sample = changed * self.steps.size + lo - (cum - count)
        span = self._cells.reshape(-1).take(np.arange(total) + np.repeat(first_sample, count))
        sign = np.repeat(np.where(grows, 1, -1), count)
        if lost:  # (rare) the old samples of re-listed beams
            span = np.concatenate([span, lost[0]])
            sign = np.concatenate([sign, np.full(lost[0].size, -1, dtype=sign.dtype)])
        self._n = n_new
        # cells live in the last frame that stop being live now: their stamp is written
        cover, hit_frame, last = self._cover, self._hit_frame, self._frame
        order = np.argsort(span, kind="stable")  # (np.unique is slower on small arrays)
        span, sign = span[order], sign[order]
        first = np.ones(span.size, dtype=bool)
        np.not_equal(span[1:], span[:-1], out=first[1:])
        starts = np.flatnonzero(first)
        touched = span[starts]
        before = cover.take(touched)
        after = before
        if starts.size:
            after = before + np.add.reduceat(sign, starts).astype(np.int32)
        was_live = (before > 0) & (hit_frame.take(touched) != last)
        hit_live = (cover.take(hit) > 0) & (hit_frame.take(hit) != last)
        cover[touched] = after
        hit_frame[hit] = last + 1
        seen_free[touched[was_live & (after == 0)]] = self._stamp
        seen_free[hit[hit_live]] = self._stamp
        self._frame = last + 1
        self._stamp = stamp


_UNLOADED = object()
_cast_compiled: object = _UNLOADED
_cast_apply_compiled: object = _UNLOADED


def _compiled_cast() -> Any:
    """The compiled usual frame of :meth:`StillCast.cast` (``still_cast_usual``), or None."""
    global _cast_compiled
    if _cast_compiled is _UNLOADED:
        from laserpeople.background.occupancy import compiled_function  # (it imports this)

        _cast_compiled = compiled_function("still_cast_usual")
    return _cast_compiled


def _compiled_cast_apply() -> Any:
    """The compiled coverage and stamps of :meth:`StillCast.cast` once its beams are listed
    (``still_cast_apply``), or None."""
    global _cast_apply_compiled
    if _cast_apply_compiled is _UNLOADED:
        from laserpeople.background.occupancy import compiled_function

        _cast_apply_compiled = compiled_function("still_cast_apply")
    return _cast_apply_compiled


__all__ = ["BOUNDARY_MARGIN", "DIRECTION_TOL", "MAX_COORDINATE", "StillCast"]
