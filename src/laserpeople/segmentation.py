"""Splitting a scan into segments of neighbouring beams (000 Sec. 2.2).

A segmenter is any callable ``segmenter(scan) -> SegmentTable``; the table is the
vectorised form every consumer uses (flat beam indices plus segment offsets) and
``table.segments()`` gives the ordered list of :class:`~laserpeople.scan.Segment` the
design names. Further segmenters (single linkage, mean shift) implement the same
:class:`Segmenter` protocol.

Jump distance (000 Sec. 2.2): walk the valid beams in beam order; a new segment starts
whenever the Euclidean distance between a point and the previous valid point exceeds the
threshold. Invalid beams (no return) are *skipped*: they neither break a segment nor join
it, so a leg with one dropped beam stays one segment, and a gap of several invalid beams
still splits whenever the two valid points on either side are farther apart than the
threshold. The number of skipped beams is reported by ``SegmentTable.n_invalid``.

For a scan covering the full circle the last and first segment are merged when their
end points are close (``wrap_around``); the merged segment keeps index 0 and its beams
run from the end of the scan through beam 0 (its ``stop`` then exceeds the beam count,
beams are ``beams % n_beams``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.detection import compiled
from laserpeople.scan import Scan, Segment

IntArray = NDArray[np.int64]
FloatArray = NDArray[np.float64]

_extension = compiled.EXTENSION
"""Leg detection's C extension (:func:`jumps`), or None: :func:`at_least` runs."""


@dataclass(frozen=True, eq=False)
class SegmentTable:
    """All segments of one scan as flat arrays (M segments over K points).

    Attributes:
        beams: Beam index (K,) of every segment point, segment after segment, each segment
            in scan order (a wrap-around segment continues past the last beam with beam 0).
        points: Sensor-frame coordinates (K, 2) [m] of those beams.
        offsets: Start (M + 1,) of each segment in ``beams``; segment i is
            ``beams[offsets[i]:offsets[i + 1]]``.
        n_beams: Beam count of the scan.
        n_invalid: Invalid beams skipped by the segmentation.
    """

    beams: IntArray
    points: FloatArray
    offsets: IntArray
    n_beams: int
    n_invalid: int = 0

    def __len__(self) -> int:
        return int(self.offsets.size - 1)

    @property
    def sizes(self) -> IntArray:
        """Number of points (M,) of each segment."""
        return np.diff(self.offsets)

    @property
    def segment_ids(self) -> IntArray:
        """Segment index (K,) of every point."""
        return np.repeat(np.arange(len(self), dtype=np.int64), self.sizes)

    def centres(self) -> FloatArray:
        """Mean point (M, 2) [m] of each segment."""
        if len(self) == 0:
            return np.empty((0, 2))
        sums = np.add.reduceat(self.points, self.offsets[:-1], axis=0)
        return np.asarray(sums / self.sizes[:, None], dtype=np.float64)

    def segment(self, i: int) -> Segment:
        """Segment ``i`` as a :class:`Segment` (``stop`` beyond ``n_beams`` when it wraps)."""
        a, b = int(self.offsets[i]), int(self.offsets[i + 1])
        beams = self.beams[a:b]
        first, last = int(beams[0]), int(beams[-1])
        stop = last + 1 if last >= first else last + 1 + self.n_beams
        return Segment(first, stop, beams.copy(), self.points[a:b].copy())

    def segments(self) -> list[Segment]:
        """The ordered list of segments."""
        return list(self.segments_at(np.arange(len(self))))

    def segments_at(self, which: IntArray) -> tuple[Segment, ...]:
        """Segments ``which`` (L,) as :meth:`segment` gives them (the same values), built
        in one pass: the bounds read at once, not one numpy scalar at a time. Their arrays
        are read-only views of one read-only copy of the table's arrays (none when those
        are read-only already, as a scan's shared valid points are)."""
        if len(which) == 0:
            return ()
        which = np.asarray(which, dtype=np.int64)
        lo = self.offsets[which]
        hi = self.offsets[which + 1]
        first = self.beams[lo]
        last = self.beams[hi - 1]
        stop = last + 1 + np.where(last >= first, 0, self.n_beams)
        beams, points = _read_only(self.beams), _read_only(self.points)
        of = Segment.of
        return tuple(
            of(f, t, beams[a:b], points[a:b])
            for a, b, f, t in zip(
                lo.tolist(), hi.tolist(), first.tolist(), stop.tolist(), strict=True
            )
        )

    @classmethod
    def empty(cls, n_beams: int, n_invalid: int = 0) -> SegmentTable:
        """A table without segments."""
        return cls(
            np.empty(0, dtype=np.int64),
            np.empty((0, 2)),
            np.zeros(1, dtype=np.int64),
            n_beams,
            n_invalid,
        )


def _read_only(a: NDArray[Any]) -> NDArray[Any]:
    """``a`` itself when it is read-only, else a read-only copy."""
    if not a.flags.writeable:
        return a
    b = a.copy()
    b.flags.writeable = False
    return b


class Segmenter(Protocol):
    """Anything that splits a scan into ordered segments."""

    def __call__(self, scan: Scan) -> SegmentTable:
        """The segments of ``scan``."""
        ...


@dataclass(frozen=True)
class JumpDistanceParams:
    """Parameters of the jump-distance segmentation."""

    config_section = "jump_distance"

    threshold: float = param(
        0.1,
        "000 Sec. 2.2 gives no value; 0.1 m is the rule of the neko7055 leg labels",
        "a new segment starts where adjacent valid points are at least this far apart",
        "m",
    )
    wrap_around: bool = param(
        True,
        "neko7055 label rule",
        "merge the last and first segment of a full-circle scan when they are close",
    )

    def __post_init__(self) -> None:
        if not (math.isfinite(self.threshold) and self.threshold > 0.0):
            raise ValueError(f"threshold must be a positive, finite distance, not {self.threshold}")


@dataclass(frozen=True)
class JumpDistanceSegmenter:
    """Jump-distance segmentation of 000 Sec. 2.2 (see the module docstring)."""

    params: JumpDistanceParams = JumpDistanceParams()

    def __call__(self, scan: Scan) -> SegmentTable:
        """The segments of ``scan`` in beam order."""
        return _table_of(scan, self.params, covers_full_circle(scan))

    def many(self, scans: Sequence[Scan]) -> list[SegmentTable]:
        """The segments of each of ``scans`` (the same tables as one at a time), the
        distances between neighbouring points of all of them computed at once."""
        return self.block(scans).tables

    def block(self, scans: Sequence[Scan]) -> SegmentBlock:
        """The segments of ``scans`` as one :class:`SegmentBlock`: the same tables as one
        scan at a time."""
        return segment_block(scans, self.params)


@dataclass(frozen=True, eq=False)
class SegmentBlock:
    """The segments of several scans (T scans, M segments over K points) as flat arrays,
    and each scan's :class:`SegmentTable` (all read-only).

    Attributes:
        tables: Each scan's table (T,); its ``beams`` and ``points`` are the scan's own
            valid beams and points (a wrapped scan's a reordered copy), as one scan at a
            time gives them, so that its segments do not hold the block's arrays.
        beams: Beam index (K,) of every point, the scans' tables one after the other.
        points: Sensor-frame coordinates (K, 2) [m] of those beams.
        offsets: Start (M + 1,) of every segment in ``beams``.
        table_starts: First segment (T + 1,) of each scan's table in ``offsets``.
        point_starts: First point (T + 1,) of each scan's table in ``beams``.
        full_circle: Whether each scan covers the full circle (T,).
    """

    tables: list[SegmentTable]
    beams: IntArray
    points: FloatArray
    offsets: IntArray
    table_starts: IntArray
    point_starts: IntArray
    full_circle: list[bool]

    def segments_at(self, which: IntArray) -> list[Segment]:
        """Segments ``which`` (L,) of the block, increasing, as their tables'
        :meth:`SegmentTable.segments_at` gives them (the same values, views of the same
        arrays), their bounds read for all of them at once."""
        if len(which) == 0:
            return []
        owner = np.searchsorted(self.table_starts, which, side="right") - 1
        lo = self.offsets[which]
        hi = self.offsets[which + 1]
        first = self.beams[lo]
        last = self.beams[hi - 1]
        n_beams = np.array([t.n_beams for t in self.tables], dtype=np.int64)[owner]
        stop = last + 1 + np.where(last >= first, 0, n_beams)
        base = self.point_starts[owner]
        tables, of = self.tables, Segment.of
        return [
            of(f, t, tables[q].beams[a:b], tables[q].points[a:b])
            for q, a, b, f, t in zip(
                owner.tolist(),
                (lo - base).tolist(),
                (hi - base).tolist(),
                first.tolist(),
                stop.tolist(),
                strict=True,
            )
        ]


def segment_block(scans: Sequence[Scan], params: JumpDistanceParams) -> SegmentBlock:
    """Jump-distance segmentation of ``scans`` (in order) at once: one distance between
    neighbouring points over all of them, one pass over the starts, a scan's last and
    first segment merged where it wraps (as :func:`jump_distance_table` does)."""
    if len(scans) == 1:  # (one scan: its table's arrays are the block's)
        return _block_of_one(scans[0], params)
    parts = [scan.valid_points("sensor") for scan in scans]
    sizes = [idx.size for _, idx in parts]
    bounds = np.zeros(len(scans) + 1, dtype=np.int64)
    np.cumsum(sizes, out=bounds[1:])
    k = int(bounds[-1])
    circle = [covers_full_circle(scan) for scan in scans]
    if k == 0:
        points = np.empty((0, 2))
        beams = np.empty(0, dtype=np.int64)
    else:
        points = np.concatenate([pts for pts, _ in parts])
        beams = np.concatenate([idx for _, idx in parts]).astype(np.int64, copy=False)
    wrap = [params.wrap_around and full for full in circle]
    compiled = _extension is not None and points.dtype == np.float64
    starts = _block_starts_compiled if compiled else _block_starts
    offsets, table_starts, local, wrapped = starts(points, beams, bounds, wrap, params.threshold)
    for array in (points, beams, offsets, table_starts, local, bounds):
        array.flags.writeable = False
    lo, hi, at = bounds.tolist(), table_starts.tolist(), 0
    tables = []
    for q, scan in enumerate(scans):
        n_invalid = scan.n_beams - sizes[q]
        if sizes[q] == 0:
            tables.append(SegmentTable.empty(scan.n_beams, n_invalid))
        else:
            pts, idx = parts[q]
            if wrapped[q]:  # (its reordered rows, copied: the block's die with it)
                pts, idx = points[lo[q] : lo[q + 1]].copy(), beams[lo[q] : lo[q + 1]].copy()
                pts.flags.writeable = idx.flags.writeable = False
            end = at + hi[q + 1] - hi[q] + 1
            tables.append(SegmentTable(idx, pts, local[at:end], scan.n_beams, n_invalid))
        at += hi[q + 1] - hi[q] + 1
    return SegmentBlock(tables, beams, points, offsets, table_starts, bounds, circle)


_Starts = tuple[IntArray, IntArray, IntArray, list[bool]]
"""A block's segments (:func:`_block_starts`): offsets (M + 1,), each scan's first segment
(T + 1,), each scan's offsets from its own first point followed by its point count
(M + T,), and whether each scan wrapped (T,)."""


def _block_starts(
    points: FloatArray, beams: IntArray, bounds: IntArray, wrap: list[bool], threshold: float
) -> _Starts:
    """The segments of the joined valid points (K, 2) [m] and beams (K,) of T scans, scan q's
    at rows ``bounds[q]:bounds[q + 1]``: a segment starts at each scan's first point and at
    every jump of ``threshold`` [m] (:func:`jumps`); a scan whose ``wrap`` is set has its
    last segment merged into its first where its ends are close (:func:`_wrap`, points and
    beams reordered in place). The Python reference of :func:`_block_starts_compiled`."""
    k = points.shape[0]
    is_start = np.zeros(k + 1, dtype=bool)  # (the step into a point is a jump)
    if k > 1:
        is_start[1:k] = jumps(points, threshold)
    is_start[bounds[:-1]] = True  # (every scan's first point; an empty one's is the next's)
    wrapped = [False] * len(wrap)
    for q, full in enumerate(wrap):
        a, b = int(bounds[q]), int(bounds[q + 1])
        if full and b > a and _wrap(points, beams, is_start, a, b, threshold):
            wrapped[q] = True
    is_start[k] = True
    offsets = np.flatnonzero(is_start)  # (M + 1,): the segments' starts, then K
    table_starts = np.searchsorted(offsets, bounds)
    table_starts[-1] = offsets.size - 1
    # each table's offsets from its own first point, one table after the other (M + T,)
    counts = np.diff(table_starts)
    owner = np.repeat(np.arange(len(wrap)), counts)
    local = np.empty(offsets.size - 1 + len(wrap), dtype=np.int64)
    local[np.arange(offsets.size - 1) + owner] = offsets[:-1] - bounds[owner]
    local[table_starts[1:] + np.arange(len(wrap))] = np.diff(bounds)
    return offsets, table_starts, local, wrapped


def _block_starts_compiled(
    points: FloatArray, beams: IntArray, bounds: IntArray, wrap: list[bool], threshold: float
) -> _Starts:
    """:func:`_block_starts` by the C extension's ``segment`` in one call (the same
    segments, the same reordered rows)."""
    assert _extension is not None
    flags = np.array(wrap, dtype=np.int64)
    parts = _extension.segment(points, beams, bounds, flags, threshold)
    offsets, table_starts, local, wrapped = (np.frombuffer(p, dtype=np.int64) for p in parts)
    return offsets, table_starts, local, [w != 0 for w in wrapped.tolist()]


def _table_of(scan: Scan, params: JumpDistanceParams, full_circle: bool) -> SegmentTable:
    """The table of :class:`JumpDistanceSegmenter` ``params`` of ``scan`` (``full_circle``
    whether it covers the full circle)."""
    pts, idx = scan.valid_points("sensor")
    n_invalid = scan.n_beams - idx.size
    if idx.size == 0:
        return SegmentTable.empty(scan.n_beams, n_invalid)
    return jump_distance_table(
        pts,
        idx,
        scan.n_beams,
        params.threshold,
        wrap=params.wrap_around and full_circle,
        n_invalid=n_invalid,
    )


def _block_of_one(scan: Scan, params: JumpDistanceParams) -> SegmentBlock:
    """:func:`segment_block` of one scan: its :class:`JumpDistanceSegmenter` table."""
    circle = covers_full_circle(scan)
    table = _table_of(scan, params, circle)
    for a in (table.beams, table.points, table.offsets):
        a.flags.writeable = False
    starts = np.array([0, len(table)], dtype=np.int64)
    at = np.array([0, table.beams.size], dtype=np.int64)
    starts.flags.writeable = at.flags.writeable = False
    return SegmentBlock([table], table.beams, table.points, table.offsets, starts, at, [circle])


def _wrap(
    points: FloatArray,
    beams: IntArray,
    is_start: NDArray[np.bool_],
    a: int,
    b: int,
    threshold: float,
) -> bool:
    """Merge the last segment of the scan at rows ``[a, b)`` into its first, in place, as
    :func:`_table_from_starts` does: its rows moved to the front, its start cleared;
    whether it did (the scan has more than one segment, and its ends are close)."""
    starts = np.flatnonzero(is_start[a + 1 : b])
    if starts.size == 0:
        return False
    closing = float(np.hypot(*(points[a] - points[b - 1])))
    if closing >= threshold:
        return False
    last = a + 1 + int(starts[-1])
    order = np.concatenate((np.arange(last, b), np.arange(a, last)))
    points[a:b] = points[order]
    beams[a:b] = beams[order]
    moved = is_start[a:last].copy()
    is_start[a : a + b - last] = False
    is_start[a + b - last : b] = moved
    is_start[a] = True
    is_start[a + b - last] = False  # (the first segment now continues the moved last one)
    return True


NEAR = 1e-12
"""Relative band round the squared threshold within which :func:`at_least` asks ``hypot``
(the squared length and hypot's length squared differ by a few 1e-16 relative)."""


def at_least(steps: FloatArray, threshold: float) -> NDArray[np.bool_]:
    """Whether each step (L, 2) [m] is at least ``threshold`` [m] long, exactly as
    ``np.hypot(dx, dy) >= threshold`` decides it: by the squared length where it lies
    farther than :data:`NEAR` (relative) from the squared threshold, by ``hypot`` within
    (a squared length costs a tenth of a ``hypot``). Thresholds whose square would leave
    the normal floats are all decided by ``hypot``."""
    if not 1e-150 < threshold < 1e150:
        return np.asarray(np.hypot(steps[:, 0], steps[:, 1]) >= threshold)
    limit = threshold * threshold
    squares = steps * steps
    lengths = squares[:, 0] + squares[:, 1]
    out = np.asarray(lengths >= limit)
    near = np.flatnonzero(np.abs(lengths - limit) <= NEAR * limit)
    if near.size:
        out[near] = np.hypot(steps[near, 0], steps[near, 1]) >= threshold
    return out


def jumps(points: FloatArray, threshold: float) -> NDArray[np.bool_]:
    """Whether each step between neighbouring points (K, 2) [m] (K - 1,) is at least
    ``threshold`` [m] long (:func:`at_least`), by the C extension of leg detection where it
    is built (the same decisions, without the arrays of steps and squares), else by
    :func:`at_least` itself."""
    if _extension is not None and points.shape[0] > 1:
        out = np.empty(points.shape[0] - 1, dtype=bool)
        _extension.jumps(np.ascontiguousarray(points, dtype=np.float64), threshold, out)
        return out
    return at_least(points[1:] - points[:-1], threshold)


def covers_full_circle(scan: Scan) -> bool:
    """Whether the beams of ``scan`` go all the way round (beam N-1 neighbours beam 0)."""
    span = abs(scan.angle_increment) * scan.n_beams
    return span >= 2.0 * math.pi - 0.5 * abs(scan.angle_increment)


def jump_distance_table(
    points: FloatArray,
    beams: IntArray,
    n_beams: int,
    threshold: float,
    *,
    wrap: bool = False,
    n_invalid: int = 0,
) -> SegmentTable:
    """Jump-distance segmentation of valid points (K, 2) given in beam order.

    Args:
        points: Valid points (K, 2) [m], ordered by beam.
        beams: Their beam indices (K,).
        n_beams: Beam count of the scan.
        threshold: Jump distance [m]; a gap ``>= threshold`` starts a new segment.
        wrap: Merge the last segment into the first when the last and first point are
            closer than ``threshold`` (full-circle scans).
        n_invalid: Skipped beams, recorded in the table.
    """
    k = points.shape[0]
    if k == 0:
        return SegmentTable.empty(n_beams, n_invalid)
    starts = np.concatenate(([0], np.flatnonzero(jumps(points, threshold)) + 1)).astype(np.int64)
    return _table_from_starts(
        points, beams, starts, n_beams, threshold, wrap=wrap, n_invalid=n_invalid
    )


def _table_from_starts(
    points: FloatArray,
    beams: IntArray,
    starts: IntArray,
    n_beams: int,
    threshold: float,
    *,
    wrap: bool,
    n_invalid: int,
) -> SegmentTable:
    """The table of :func:`jump_distance_table` from the first point ``starts`` (S,) of
    each segment (0 first) of the points (K, 2), K > 0."""
    k = points.shape[0]
    offsets = np.concatenate((starts, [k])).astype(np.int64)
    if wrap and starts.size > 1:
        closing = float(np.hypot(*(points[0] - points[-1])))
        if closing < threshold:
            last = int(starts[-1])
            order = np.concatenate((np.arange(last, k), np.arange(0, last)))
            points = points[order]
            beams = beams[order]
            shift = k - last
            offsets = np.concatenate(([0], starts[1:-1] + shift, [k])).astype(np.int64)
    return SegmentTable(beams, points, offsets, n_beams, n_invalid)
