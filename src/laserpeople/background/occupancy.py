"""A decaying occupancy grid of returns that stay put, for a moving robot (issue 10), and
the ROS ``map_server`` map loader.

Every cell of a regular grid in the frame of the frames it is fed (the world frame when the
robot's poses are known) keeps an occupancy evidence ``e`` that grows by ``hit_evidence``
in each frame with a return in the cell (capped at ``max_evidence``) and decays with time
constant ``decay_time`` in between: ``e(t) = e(t0) exp(-(t - t0) / decay_time)``. A cell is
occupied while ``e >= occupied_evidence``; its *static time* is the time since it last became
occupied. Returns of things that stay put keep their cells occupied for as long as they are
seen; a walker's legs leave a trail whose cells fall free within about
``decay_time * ln(max_evidence / occupied_evidence)`` seconds. The decay is applied lazily
(per cell, when the cell is read or hit), so one frame costs O(points).

**Free space and first sight.** Given the sensor's position, every beam also marks the
cells it passed through as seen free (up to ``free_range``, stopping ``free_margin`` before
its return; cells with a return in the same frame are not marked). A cell that becomes
occupied without having been seen free in the ``arrival_window`` before was occupied at
first sight: whatever is there was there before the laser looked. Once such a cell has
stayed occupied for ``first_sight_hold`` seconds (longer than a walker's footprint stays
occupied) its static time is raised by ``first_sight_static``. Walls and furniture in view
from the start thus count as static after 6 s instead of after ``background_time`` (30 s)
or the people's 10 s, while something that arrived in seen-free space (a person who walked
there and stands) is static only for as long as it has stood. For a laser that stands
still (one sensor position, unchanged since the frame before, and beam ids from
:meth:`OccupancyGrid.learn_frame`) the casting is kept up to date beam by beam instead of
sampled afresh (``background/still_cast.py``): the same ``seen_free``, bit for bit.

leg_tracker (Leigh et al. 2015) keeps a local occupancy grid for the same purpose (a leg
track must be in free space to start a person); here the grid answers
:meth:`OccupancyGrid.static_time`, and a prior map's obstacles count as static for ever.

The ROS map format (``map.yaml`` with ``image``, ``resolution``, ``origin``, ``negate``,
``occupied_thresh``, ``free_thresh``; the image a PGM or PNG whose first row is the top,
i.e. the largest y): a pixel's occupancy probability is ``(255 - v) / 255`` (``v / 255``
with ``negate: 1``), and it is an obstacle above ``occupied_thresh``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.background.still_cast import StillCast, Where
from laserpeople.config import param
from laserpeople.errors import LaserPeopleError
from laserpeople.frame import Frame, FrameField
from laserpeople.scan import POSE_LIMIT, CoordinateFrame, PointSet, Scan

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


FEW_POSITIONS = 8
"""Up to this many positions :meth:`OccupancyGrid.static_time` works in plain floats (the
same values; fewer numpy calls), beyond it on arrays (measured: 12 / 21 / 44 us against
48 / 44 / 51 us for 1 / 3 / 8 positions)."""


class MapFileError(LaserPeopleError):
    """A ROS map (``map.yaml`` and its image) cannot be read."""


MAP_RESOLUTION_RANGE = (0.01, 100.0)
"""Smallest and largest cell size [m] of a prior map (map_server maps use 0.02-0.1)."""
MAP_PIXEL_LIMIT = 50_000_000
"""Most pixels of a prior map image (e.g. 7,000 x 7,000: 350 m square at 0.05 m), checked
from the image header before the pixels are read."""
GRID_CELL_LIMIT = 2**25
"""Most cells the occupancy grid may hold (about 1.1 GB; e.g. 580 m x 580 m at 0.1 m).
A grid that would grow beyond it stops the run with an error: the sensor poses span more
ground than any recording this grid is meant for (or they are corrupt)."""
FREE_RANGE_LIMIT = 1000.0
"""Largest ``free_range`` [m] (the casting's samples per beam are ``free_range /
resolution``)."""
MIN_RESOLUTION = 0.001
"""Smallest cell size [m] of the grid (1 mm)."""


@dataclass(frozen=True)
class OccupancyParams:
    """The decaying occupancy grid of static returns."""

    config_section = "occupancy"

    resolution: float = param(
        0.1,
        "assumption: about a leg's diameter",
        "cell size",
        "m",
    )
    hit_evidence: float = param(1.0, "assumption", "evidence added by a frame with a return")
    occupied_evidence: float = param(
        2.0, "assumption: two frames with a return", "evidence at which a cell is occupied"
    )
    max_evidence: float = param(
        5.0,
        "assumption: a cell left alone falls free after decay_time * ln(5/2) = 1.8 s",
        "cap of the evidence",
    )
    decay_time: float = param(
        2.0,
        "assumption: longer than a stance phase (~0.6 s), shorter than a person who waits",
        "time constant of the evidence's decay",
        "s",
    )
    neighbourhood: int = param(
        1,
        "assumption: a leg's points lie up to ~0.1 m from its centre",
        "static_time looks this many cells around each position (the largest wins)",
        "cells",
    )
    max_range: float = param(
        30.0,
        "assumption: farther returns are sparse and bound the grid's size",
        "returns farther than this from the sensor are not learned",
        "m",
    )
    background_time: float = param(
        30.0,
        "assumption: longer than most people stand still",
        "points on cells static for at least this long are background (foreground False)",
        "s",
    )
    free_range: float = param(
        10.0,
        "assumption: about the leg detector's useful range; bounds the cost of casting",
        "free space is cast along each beam up to this range (0: no free space is cast)",
        "m",
    )
    free_margin: float = param(
        0.2,
        "assumption: two cells, more than the range noise of a return",
        "the part of a beam this close before its return is not taken as free",
        "m",
    )
    arrival_window: float = param(
        10.0,
        "assumption",
        "a cell seen free within this long before it became occupied got something that "
        "arrived; otherwise it was occupied at first sight",
        "s",
    )
    first_sight_hold: float = param(
        6.0,
        "measured (docs/people-benchmarks.md): demo seeds 0-4 MOTA 0.774 with 3 s, 0.865 with 6 s",
        "a cell occupied at first sight and held this long counts as static since before "
        "it was seen",
        "s",
    )
    first_sight_static: float = param(
        30.0,
        "assumption: as long as background_time, so walls seen from the start are background "
        "after first_sight_hold rather than after background_time",
        "static time added to a cell occupied at first sight once held first_sight_hold",
        "s",
    )
    free_period: float = param(
        0.5,
        "measured (docs/people-benchmarks.md): seen-free stamps are only "
        "compared with arrival_window (10 s), and casting is about half of the grid's CPU "
        "per frame of a still laser; at 0.5 s the tracks CSVs of the demo, MiR, corridor "
        "and dev recordings, the 6 tuning scenes and the held-back randomised means are "
        "unchanged, at 0.81-0.84x of the CPU on still scenes (0 casts in every frame)",
        "a laser standing still (the same sensor position as in the last cast frame) casts "
        "free space at most once per this many seconds (0: in every frame); the frames in "
        "between only add their returns. A moving laser casts in every frame",
        "s",
    )

    learn_period: float = param(
        0.05,
        "measured (docs/people-benchmarks.md): at most 20 frames a "
        "second per laser; the real 10-13 Hz recordings learn every frame; the real 45 Hz "
        "corridor bag learns 743 of its 1,561 frames with its person ids, walkers and static "
        "seconds unchanged; the simulated 50 Hz narrow-corridor tuning scenes score the same "
        "at about 0.8x of the CPU per scan",
        "each sensor's frames are learned at most once per this many seconds: a frame all "
        "of whose sensors were learned less than this long ago is not learned (it is asked "
        "the last learned grid, aged to its stamp); 0: every frame. Bounds the grid's cost "
        "on fast scanners and makes its evidence grow at about the same rate whatever the "
        "scan rate",
        "s",
    )

    def __post_init__(self) -> None:
        if min(self.resolution, self.hit_evidence, self.decay_time, self.max_range) <= 0:
            raise ValueError("resolution, hit_evidence, decay_time and max_range must be > 0")
        if not 0 < self.occupied_evidence <= self.max_evidence:
            raise ValueError("need 0 < occupied_evidence <= max_evidence")
        if self.neighbourhood < 0:
            raise ValueError("neighbourhood must be >= 0")
        if min(self.free_range, self.free_margin, self.arrival_window, self.free_period) < 0:
            raise ValueError("free_range, free_margin, arrival_window and free_period must be >= 0")
        if not self.resolution >= MIN_RESOLUTION:
            raise ValueError(f"resolution must be at least {MIN_RESOLUTION:g} m")
        if not self.free_range <= FREE_RANGE_LIMIT:
            raise ValueError(f"free_range must be at most {FREE_RANGE_LIMIT:g} m")
        if not self.free_range / self.resolution <= 1e5:
            raise ValueError("free_range / resolution must be at most 100,000 samples per beam")
        if not self.learn_period >= 0:
            raise ValueError("learn_period must be >= 0")
        if min(self.first_sight_hold, self.first_sight_static) < 0:
            raise ValueError("first_sight_hold and first_sight_static must be >= 0")


@dataclass(frozen=True, eq=False)
class OccupancyMap:
    """A prior map of obstacles (ROS ``map_server`` format).

    Attributes:
        occupied: (H, W) bool, row 0 = largest y (the image's top row).
        resolution: Cell size [m].
        origin: (x [m], y [m], yaw [rad]) of the lower-left pixel's corner in the world.
        path: The yaml file.
        frame: The map's frame id (a bag's ``header.frame_id``); empty when the source
            does not say (a ``map.yaml``).
    """

    occupied: NDArray[np.bool_]
    resolution: float
    origin: tuple[float, float, float]
    path: str = ""
    frame: str = ""

    def contains_obstacle(self, positions: FloatArray, radius: int = 0) -> NDArray[np.bool_]:
        """(M,) True where ``positions`` (M, 2) [m] fall on an obstacle pixel (or one
        within ``radius`` pixels)."""
        pos = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
        x0, y0, yaw = self.origin
        c, s = math.cos(yaw), math.sin(yaw)
        dx, dy = pos[:, 0] - x0, pos[:, 1] - y0
        u = (c * dx + s * dy) / self.resolution  # along image columns
        v = (-s * dx + c * dy) / self.resolution  # up from the bottom row
        h, w = self.occupied.shape
        col = np.floor(u).astype(np.int64)
        row = h - 1 - np.floor(v).astype(np.int64)
        grid = self if radius == 0 else self.dilated(radius)
        if radius:
            row, col = row + radius, col + radius
            h, w = grid.occupied.shape
        hit = np.zeros(pos.shape[0], dtype=bool)
        ok = (row >= 0) & (row < h) & (col >= 0) & (col < w)
        hit[ok] = grid.occupied[row[ok], col[ok]]
        return hit

    def dilated(self, radius: int) -> OccupancyMap:
        """The map whose obstacles are every pixel within ``radius`` pixels (a square of
        2 radius + 1) of one of this map's, padded by ``radius`` pixels on each side so that
        none is cut off: ``dilated(r).contains_obstacle(p)`` is ``contains_obstacle(p, r)``.
        Asking the dilated map once per frame costs one lookup per position."""
        if radius <= 0:
            return self
        h, w = self.occupied.shape
        out = np.zeros((h + 2 * radius, w + 2 * radius), dtype=bool)
        for dr in range(2 * radius + 1):  # a square's dilation: rows, then columns
            out[dr : dr + h, radius : radius + w] |= self.occupied
        rows = out.copy()
        for dc in range(2 * radius + 1):
            out[:, dc : dc + w] |= rows[:, radius : radius + w]
        x0, y0, yaw = self.origin
        shift = radius * self.resolution  # the lower-left corner moves back along u and v
        c, s = math.cos(yaw), math.sin(yaw)
        origin = (x0 - shift * (c - s), y0 - shift * (s + c), yaw)
        return replace(self, occupied=out, origin=origin)


def _parse_map_yaml(path: Path) -> dict[str, str]:
    """The flat ``key: value`` pairs of a map_server yaml (comments dropped)."""
    out: dict[str, str] = {}
    try:
        text = path.read_text()
    except OSError as exc:
        raise MapFileError(f"cannot read the map file ({exc})", path=path) from exc
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        key, sep, value = line.partition(":")
        if not sep:
            raise MapFileError(f"not a 'key: value' line: {line!r}", path=path)
        out[key.strip()] = value.strip().strip("'\"")
    return out


def map_files(path: str | Path | None) -> list[Path]:
    """The files of a ROS map: ``map.yaml`` and the image it names (just the yaml when it
    cannot be read; nothing for None), so that a command can refuse to write over them."""
    if path is None:
        return []
    p = Path(path)
    try:
        image = Path(_parse_map_yaml(p)["image"])
    except (LaserPeopleError, KeyError, ValueError):
        return [p]
    return [p, image if image.is_absolute() else p.parent / image]


def load_ros_map(path: str | Path) -> OccupancyMap:
    """Read a ROS ``map_server`` map: ``map.yaml`` and the PGM/PNG image it names.

    Raises:
        MapFileError: the yaml or image is missing or malformed.
    """
    from PIL import Image

    p = Path(path)
    keys = _parse_map_yaml(p)
    missing = [k for k in ("image", "resolution", "origin") if k not in keys]
    if missing:
        raise MapFileError(
            f"the map yaml lacks {', '.join(missing)}",
            path=p,
            hint="a map_server map needs image, resolution and origin",
        )
    try:
        resolution = float(keys["resolution"])
        origin_vals = [float(v) for v in keys["origin"].strip("[]").split(",")]
        negate = int(keys.get("negate", "0"))
        occupied_thresh = float(keys.get("occupied_thresh", "0.65"))
    except ValueError as exc:
        raise MapFileError(f"bad number in the map yaml ({exc})", path=p) from exc
    if len(origin_vals) != 3:
        raise MapFileError("origin must be [x, y, yaw]", path=p)
    lo, hi = MAP_RESOLUTION_RANGE
    if not lo <= resolution <= hi:
        raise MapFileError(
            f"resolution {resolution:g} m is outside {lo:g}-{hi:g} m per pixel",
            path=p,
            hint="a map_server map gives its cell size in metres, e.g. 0.05",
        )
    if not all(abs(v) <= POSE_LIMIT for v in origin_vals):
        raise MapFileError(
            f"origin {keys['origin'][:80]} is beyond {POSE_LIMIT:g} m or not finite", path=p
        )
    image = Path(keys["image"])
    if not image.is_absolute():
        image = p.parent / image
    try:
        with Image.open(image) as im:
            width, height = im.size
            if width * height > MAP_PIXEL_LIMIT:
                raise MapFileError(
                    f"the map image {image} claims {width} x {height} pixels, more than the "
                    f"{MAP_PIXEL_LIMIT:,} accepted",
                    path=p,
                    hint="the image is damaged, or crop the map to the recorded area",
                )
            pixels = np.asarray(im.convert("L"), dtype=np.float64)
    except MapFileError:
        raise
    except Image.DecompressionBombError as exc:  # Pillow's own check, for the largest claims
        raise MapFileError(
            f"the map image {image} claims more than the {MAP_PIXEL_LIMIT:,} pixels accepted "
            f"({exc})",
            path=p,
            hint="the image is damaged, or crop the map to the recorded area",
        ) from exc
    except (OSError, ValueError, MemoryError) as exc:
        raise MapFileError(
            f"cannot read the map image {image} ({exc})",
            path=p,
            hint="the yaml's image must be a PGM or PNG beside it",
        ) from exc
    prob = pixels / 255.0 if negate else (255.0 - pixels) / 255.0
    return OccupancyMap(
        occupied=prob > occupied_thresh,
        resolution=resolution,
        origin=(origin_vals[0], origin_vals[1], origin_vals[2]),
        path=str(p),
    )


class OccupancyGrid:
    """Decaying world-frame occupancy grid of static returns, a
    :class:`~laserpeople.background.StaticWorldModel` (see the module docstring).

    Args:
        params: Parameters.
        prior: Optional prior map; its obstacles are static for ever (``inf``).
    """

    consumes: frozenset[FrameField] = frozenset({"points"})

    def __init__(
        self, params: OccupancyParams | None = None, prior: OccupancyMap | None = None
    ) -> None:
        self.params = params if params is not None else OccupancyParams()
        self.prior = prior
        # the prior's obstacles as far as the grid's neighbourhood reaches (up to
        # neighbourhood + 1 cells), dilated once instead of looked up around every point
        self._prior_near: OccupancyMap | None = None
        if prior is not None:
            p = self.params
            reach = math.ceil((p.neighbourhood + 1) * p.resolution / prior.resolution - 1e-9)
            self._prior_near = prior.dilated(reach)
        self.stamp = -math.inf
        self._origin = np.zeros(2, dtype=np.int64)  # cell index of array element [0, 0]
        self._evidence = np.zeros((0, 0))
        self._touched = np.zeros((0, 0))  # time [s] the evidence was last brought up to date
        self._since = np.zeros((0, 0))  # time [s] the cell became occupied (nan: free)
        self._seen_free = np.zeros((0, 0))  # last time [s] a beam passed through (-inf: never)
        self._first_sight = np.zeros((0, 0), dtype=bool)  # occupied when first seen
        self.casting = False
        """True once free space has been cast (the learn calls gave sensor positions)."""
        self._cast_at = -math.inf  # stamp [s] of the last frame whose free space was cast
        self._learned_at: dict[str, float] = {}  # stamp [s] each sensor was last learned at
        self.skipped = 0
        """Frames not learned (``learn_period``)."""
        res = self.params.resolution
        # the casting's sample distances: arange's k-th element does not depend on its stop
        self._steps = np.arange(0.5 * res, self.params.free_range + res, res)
        self._still = StillCast(res, self._steps)  # the casting of a laser standing still

    # ------------------------------------------------------------------ storage

    def _cells(self, positions: FloatArray) -> IntArray:
        return np.floor(positions / self.params.resolution).astype(np.int64)

    def _ensure(self, cells: IntArray, more: IntArray | None = None) -> None:
        """Grow the arrays to hold ``cells`` (K, 2) and ``more`` (L, 2) (with a margin)."""
        if cells.shape[0] == 0:
            if more is None:
                return
            cells, more = more, None
        # (one column at a time: four 1-d reductions take a quarter of min/max(axis=0)'s
        # time on (K, 2))
        rows, cols = cells[:, 0], cells[:, 1]
        i0, i1, j0, j1 = int(rows.min()), int(rows.max()), int(cols.min()), int(cols.max())
        if more is not None:  # (a few rows: in plain ints, without stacking the arrays)
            for a, b in more.tolist():
                i0, i1, j0, j1 = min(i0, a), max(i1, a), min(j0, b), max(j1, b)
        h, w = self._evidence.shape
        if h * w > 0:
            o0, o1 = self._origin.tolist()
            if i0 >= o0 and j0 >= o1 and i1 < o0 + h and j1 < o1 + w:
                return
        lo = np.array([i0, j0], dtype=np.int64)
        hi = np.array([i1, j1], dtype=np.int64)
        new_lo, size = grown_extent(
            self._origin,
            self._evidence.shape,
            lo,
            hi,
            self.params.resolution,
            "the occupancy grid",
            "raise [occupancy] resolution",
        )
        self._still.settle(self._seen_free.reshape(-1))  # its flat indices are about to move
        at = (self._origin, new_lo, size)
        self._evidence = moved_into(self._evidence, *at, 0.0)
        self._touched = moved_into(self._touched, *at, -np.inf)
        self._since = moved_into(self._since, *at, np.nan)
        self._seen_free = moved_into(self._seen_free, *at, -np.inf)
        self._first_sight = moved_into(self._first_sight, *at, False)
        self._origin = new_lo

    def _holds_disc(self, centre: FloatArray, radius: float) -> bool:
        """Whether the arrays hold every cell within ``radius`` [m] of ``centre`` (2,) [m],
        with a cell to spare (for the rounding of the returns' distances): then they hold
        the cells of the returns at most ``radius`` from a sensor at ``centre`` and the
        sensor's own, and :meth:`_ensure` need not look at them (four reductions fewer per
        frame; False, the exact check, when the arrays are empty or a value not finite)."""
        h, w = self._evidence.shape
        x, y = centre.tolist()
        if not (h * w > 0 and math.isfinite(x) and math.isfinite(y) and math.isfinite(radius)):
            return False
        res = self.params.resolution
        o0, o1 = self._origin.tolist()
        return (
            math.floor((x - radius) / res) - 1 >= o0
            and math.floor((y - radius) / res) - 1 >= o1
            and math.floor((x + radius) / res) + 1 < o0 + h
            and math.floor((y + radius) / res) + 1 < o1 + w
        )

    def _decayed(self, flat: IntArray, stamp: float) -> FloatArray:
        """Evidence of the cells ``flat`` (flat indices into the arrays) decayed to ``stamp``."""
        dt = np.maximum(stamp - self._touched.take(flat), 0.0)
        return np.asarray(self._evidence.take(flat) * np.exp(-dt / self.params.decay_time))

    def _flat(self, cells: IntArray) -> IntArray:
        """Flat indices into the arrays of ``cells`` (K, 2) (which they must hold)."""
        w = self._evidence.shape[1]
        o0, o1 = self._origin.tolist()
        # (i - o0) w + (j - o1) as i w + j - (o0 w + o1): the same integers, one pass fewer
        flat = cells[:, 0] * w
        flat += cells[:, 1]
        flat -= o0 * w + o1
        return flat

    # ------------------------------------------------------------------ learning

    def _beam_samples(
        self, origins: FloatArray, points: FloatArray, r: FloatArray | None = None
    ) -> tuple[FloatArray, FloatArray]:
        """Points ``(x, y)`` every ``resolution`` along the beams from ``origins`` (N, 2) to
        their returns ``points`` (N, 2) (``r``: their lengths, when known), from half a cell
        on, up to ``free_margin`` before the return and at most ``free_range`` from the
        sensor (vectorised over beams: the samples of all beams in one flat array, beam
        after beam)."""
        p = self.params
        d = points - origins
        if r is None:
            r = np.hypot(d[:, 0], d[:, 1])
        reach = np.minimum(r - p.free_margin, p.free_range)
        keep = reach > 0
        if not keep.any():
            return np.zeros(0), np.zeros(0)
        res = p.resolution
        o = origins
        if not keep.all():  # (else the arrays as they are: the same rows, no copies)
            d, r, reach, o = d[keep], r[keep], reach[keep], origins[keep]
        u = d / r[:, None]
        steps = np.arange(0.5 * res, float(reach.max()), res)
        counts = np.searchsorted(steps, reach, side="left")  # steps < reach per beam
        start = np.cumsum(counts) - counts
        k = np.arange(int(counts.sum()))
        k -= np.repeat(start, counts)  # the step number of each sample along its beam
        step = steps.take(k)
        # one sensor position (a broadcast row, or equal rows): a scalar (same values)
        single = o.strides[0] == 0 or bool((o == o[0]).all())
        ox = o[0, 0] if single else np.repeat(o[:, 0], counts)
        oy = o[0, 1] if single else np.repeat(o[:, 1], counts)
        xs = np.repeat(u[:, 0], counts)
        xs *= step
        xs += ox
        ys = np.repeat(u[:, 1], counts)
        ys *= step
        ys += oy
        return xs, ys

    def _free_flat(
        self, origins: FloatArray, points: FloatArray, r: FloatArray | None = None
    ) -> IntArray:
        """Flat indices into the arrays (which must hold them) of the cells of the samples
        of :meth:`_beam_samples` (one per sample; cells repeat)."""
        xs, ys = self._beam_samples(origins, points, r)
        if not xs.size:
            return np.zeros(0, dtype=np.int64)
        res = self.params.resolution
        # floor(x / res) - origin, times the row length, plus the same of y, in place and in
        # floating point: exact, as all values are integers far below 2**53
        np.divide(xs, res, out=xs)
        np.floor(xs, out=xs)
        xs -= self._origin[0]
        xs *= self._seen_free.shape[1]
        np.divide(ys, res, out=ys)
        np.floor(ys, out=ys)
        ys -= self._origin[1]
        xs += ys
        return xs.astype(np.int64)

    def _cast_still(
        self,
        origin: FloatArray,
        points: FloatArray,
        r: FloatArray,
        beams: IntArray,
        hit: IntArray,
        stamp: float,
    ) -> None:
        """Cast the beams ``beams`` from one sensor position ``origin`` (2,) that has not
        moved since the frame before, through :class:`StillCast` (the same ``seen_free``)."""
        p = self.params
        reach = np.minimum(r - p.free_margin, p.free_range)
        keep = reach > 0
        if not keep.all():
            points, r, reach, beams = points[keep], r[keep], reach[keep], beams[keep]
        u = points - origin
        u /= r[:, None]
        n = np.searchsorted(self._steps, reach, side="left")  # samples below the reach
        self._still.cast(self._seen_free.reshape(-1), origin, beams, u, n, hit, stamp)

    def _cast(
        self,
        pts: FloatArray,
        r: FloatArray,
        ids: IntArray | None,
        hit: IntArray,
        stamp: float,
        single: FloatArray | None,
        origins: FloatArray | None,
        where: Where | None,
    ) -> None:
        """Cast the free space of one frame's returns ``pts`` (N, 2) at distances ``r`` (N,)
        from their sensors (``single`` (2,) for all, else ``origins`` (N, 2)), beams ``ids``
        (N,), the cells with a return ``hit``: through :class:`StillCast` when the laser
        stands where it stood (``where``, None: not one still laser), else beam by beam."""
        seen_free = self._seen_free.reshape(-1)  # (C-contiguous, made in _ensure: a view)
        self._cast_at = stamp
        if self._still.still(where) and ids is not None:
            assert single is not None
            self._cast_still(single, pts, r, ids, hit, stamp)
            return
        self._still.settle(seen_free)
        if origins is None:
            assert single is not None
            origins = np.broadcast_to(single, pts.shape)
        free = self._free_flat(origins, pts, r)
        if free.size:
            kept = seen_free.take(hit)  # a cell with a return now is not free
            seen_free[free] = stamp
            seen_free[hit] = kept

    def _seen_free_now(self) -> FloatArray:
        """``seen_free`` [s] of every cell (the array's shape), the still laser's live cells
        included."""
        flat = np.arange(self._seen_free.size)
        return self._still.value(self._seen_free.reshape(-1), flat).reshape(self._seen_free.shape)

    def _free_cells(self, origins: FloatArray, points: FloatArray) -> IntArray:
        """Cells (K, 2) that the beams from ``origins`` (N, 2) to their returns ``points``
        (N, 2) pass through (see :meth:`_beam_samples`)."""
        xs, ys = self._beam_samples(origins, points)
        res = self.params.resolution
        return np.stack([np.floor(xs / res), np.floor(ys / res)], axis=1).astype(np.int64)

    def learn(
        self,
        points: FloatArray,
        stamp: float,
        sensor: FloatArray | None = None,
        beams: IntArray | None = None,
    ) -> None:
        """Add one frame's returns ``points`` (N, 2) [m] seen at ``stamp`` [s] from the sensor
        position ``sensor`` ((2,), or (N, 2) one per return; returns beyond ``max_range`` from
        it are skipped). With the sensor position, the cells each beam passed through are
        marked seen free (free-space casting), which tells a cell occupied at first sight
        from one whose occupant arrived. ``beams`` (N,) names the beam of each return (the
        same id for the same beam in every frame, increasing along ``points``): a laser
        that stands still then casts from lists of its beams' cells (the same cells,
        ``background/still_cast.py``)."""
        p = self.params
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        ids = None if beams is None else np.asarray(beams, dtype=np.int64).reshape(-1)
        origins: FloatArray | None = None  # the sensor position of each return (N, 2)
        single: FloatArray | None = None  # the one sensor position of all returns (2,)
        r: FloatArray | None = None  # distances of the returns from their sensor
        reach = math.nan  # the largest of them (nan: not known)
        increasing: bool | None = None  # whether ids increase along pts (None: not known)
        looked = self._look(pts, ids, sensor)
        if looked is not None:  # (one sensor position, every value finite: one C pass)
            single, r, reach, increasing = looked
        else:
            every = bool(np.isfinite(pts).all())  # (the usual case: no copies)
            finite = None
            if not every:
                finite = np.isfinite(pts).all(axis=1)
                pts = pts[finite]
                ids = None if ids is None else ids[finite]
            if sensor is not None:
                sen = np.asarray(sensor, dtype=np.float64)
                if sen.ndim == 1 or (sen.shape[0] > 0 and sen.strides[0] == 0):  # (broadcast)
                    single = sen if sen.ndim == 1 else sen[0]
                    d = pts - single
                else:
                    origins = sen if finite is None else sen[finite]
                    d = pts - origins
                r = np.hypot(d[:, 0], d[:, 1])
                # (one reduction: every return is near when the farthest is; NaN is not near)
                reach = float(r.max()) if r.size else 0.0
        if r is not None and not reach <= p.max_range:
            near = r <= p.max_range
            pts, r = pts[near], r[near]
            origins = None if origins is None else origins[near]
            ids = None if ids is None else ids[near]
            reach = math.nan
            if not increasing:  # (a part of an increasing run increases too)
                increasing = None
        self.stamp = max(self.stamp, stamp)
        if pts.shape[0] == 0:
            return
        cells: IntArray | None = None  # (made when the arrays may have to grow)
        casting = sensor is not None and p.free_range > 0
        if casting:
            self.casting = True
            # the free cells lie between the sensors and the returns: grow the arrays for
            # those cells too (the corners of the sensors' bounding box suffice)
            if single is not None:
                if not self._holds_disc(single, reach):
                    cells = self._cells(pts)
                    self._ensure(cells, self._cells(single.reshape(1, 2)))
            else:
                assert origins is not None
                cells = self._cells(pts)
                corners = self._cells(np.vstack([origins.min(axis=0), origins.max(axis=0)]))
                self._ensure(cells, corners)
        else:
            cells = self._cells(pts)
            self._ensure(cells)
        hit, exponent = self._hits(pts, cells, stamp)  # each cell with a return once
        if casting:
            assert r is not None
            if single is None:
                assert origins is not None
                if bool((origins == origins[0]).all()):
                    single = origins[0]
            where: Where | None = None
            if increasing is None and ids is not None and single is not None:
                increasing = bool((ids[1:] > ids[:-1]).all())
            if ids is not None and single is not None and increasing:
                (i0, j0), (h, w) = self._origin.tolist(), self._seen_free.shape
                ox, oy = single.tolist()
                where = (ox, oy, i0, j0, w, h * w)
            skip = (  # (the option: a laser standing still casts once per free_period)
                p.free_period > 0.0
                and self._still.stays(where)
                and 0.0 <= stamp - self._cast_at < p.free_period
            )
            if not skip:
                self._cast(pts, r, ids, hit, stamp, single, origins, where)
        self._mark_hits(hit, exponent, stamp)

    def _look(
        self, pts: FloatArray, ids: IntArray | None, sensor: FloatArray | None
    ) -> tuple[FloatArray, FloatArray, float, bool] | None:
        """For :meth:`learn`, where the C extension is built: a frame's returns ``pts``
        (N, 2) [m] seen from one sensor position ``sensor`` (2,), beams ``ids`` (N,), all
        finite, in one pass: the position, the returns' distances from it (numpy's
        ``hypot`` of the same differences: the C library's), the largest (0.0 without
        returns) and whether ``ids`` increase. None for any other frame (several
        positions, no sensor or ids, a value not finite): :meth:`learn` looks at it in
        numpy."""
        if sensor is None or ids is None:
            return None
        compiled = _compiled_look()
        if compiled is None:
            return None
        sen = np.asarray(sensor, dtype=np.float64)
        if sen.shape != (2,):
            return None
        ox, oy = sen.tolist()
        r = np.empty(pts.shape[0])
        out = compiled(pts, ids, ox, oy, r)
        if out is NotImplemented:
            return None
        reach, increasing = out
        return sen, r, reach, increasing

    def _hits(
        self, pts: FloatArray, cells: IntArray | None, stamp: float
    ) -> tuple[IntArray, FloatArray | None]:
        """:meth:`_hits_python` compiled where the MHT's C extension is built (the same
        cells), with the exponents ``-max(stamp - touched, 0) / decay_time`` of their
        evidence's decay (None: the Python one ran)."""
        compiled = _compiled_grid()
        if compiled is not None:
            n = pts.shape[0]
            hit, exponent = np.empty(n, dtype=np.int64), np.empty(n)
            o0, o1 = self._origin.tolist()
            k = compiled[0](
                pts,
                self._touched,
                o0,
                o1,
                float(self.params.resolution),
                float(stamp),
                float(self.params.decay_time),
                hit,
                exponent,
            )
            if k is not NotImplemented:
                return hit[:k], exponent[:k]
        return self._hits_python(pts, cells), None

    def _hits_python(self, pts: FloatArray, cells: IntArray | None) -> IntArray:
        """Flat indices (sorted, each once) of the cells of the returns ``pts`` (N, 2) [m]
        (``cells``, their cells, when known), which the arrays must hold."""
        return sorted_unique(self._flat(self._cells(pts) if cells is None else cells))

    def _mark_hits(self, hit: IntArray, exponent: FloatArray | None, stamp: float) -> None:
        """:meth:`_mark_hits_python` compiled where the MHT's C extension is built and
        :meth:`_hits` gave the exponents: numpy's ``exp`` of them, then the same floats."""
        compiled = _compiled_grid()
        if compiled is not None and exponent is not None:
            p = self.params
            live = self._still.live()
            cover, hit_frame, frame, cast_stamp = (None, None, 0, 0.0) if live is None else live
            done = compiled[1](
                self._evidence,
                self._touched,
                self._since,
                self._first_sight,
                self._seen_free,
                hit,
                np.exp(exponent),
                float(stamp),
                float(p.occupied_evidence),
                float(p.hit_evidence),
                float(p.max_evidence),
                float(p.arrival_window),
                self.casting,
                cover,
                hit_frame,
                frame,
                float(cast_stamp),
            )
            if done is not NotImplemented:
                return
        self._mark_hits_python(hit, stamp)

    def _mark_hits_python(self, hit: IntArray, stamp: float) -> None:
        """Add a return at ``stamp`` [s] to each of the cells ``hit`` (flat indices, each
        once): their evidence decayed and raised, the time since they are occupied, and
        whether they were occupied at first sight (occupied now, and not seen free within
        ``arrival_window``)."""
        p = self.params
        before = self._decayed(hit, stamp)
        was = before >= p.occupied_evidence
        after = np.minimum(before + p.hit_evidence, p.max_evidence)
        now = after >= p.occupied_evidence
        self._evidence.reshape(-1)[hit] = after
        self._touched.reshape(-1)[hit] = stamp
        since = self._since.take(hit)
        kept_since = was & (since == since)  # (occupied before, and not free: since not nan)
        self._since.reshape(-1)[hit] = np.where(kept_since, since, np.where(now, stamp, np.nan))
        seen = self._still.value(self._seen_free.reshape(-1), hit)
        arrived = stamp - seen <= p.arrival_window
        first = (now & ~arrived) if self.casting else np.zeros_like(now)
        self._first_sight.reshape(-1)[hit] = np.where(
            kept_since, self._first_sight.take(hit), first
        )

    def _cell_static(self, flat: IntArray) -> FloatArray:
        """Static time [s] of the cells ``flat`` (flat indices into the arrays) at the last
        frame's time (0 where free)."""
        p = self.params
        occ = self._decayed(flat, self.stamp) >= p.occupied_evidence
        since = self._since.take(flat)
        tk = np.where(occ & ~np.isnan(since), self.stamp - since, 0.0)
        held = self._first_sight.take(flat) & (tk >= p.first_sight_hold)
        return np.asarray(np.where(held, tk + p.first_sight_static, tk))

    def _static_few(self, xy: list[list[float]]) -> list[float] | None:
        """:meth:`_static_few_python` compiled where the MHT's C extension is built (the
        same values; it leaves to the Python one what that one decides otherwise)."""
        compiled = _compiled_static_few()
        if compiled is not None:
            p = self.params
            out = compiled(
                self._evidence,
                self._touched,
                self._since,
                self._first_sight,
                int(self._origin[0]),
                int(self._origin[1]),
                xy,
                float(p.resolution),
                int(p.neighbourhood),
                float(self.stamp),
                float(p.decay_time),
                float(p.occupied_evidence),
                float(p.first_sight_hold),
                float(p.first_sight_static),
                1e-9 * p.occupied_evidence,
            )
            if out is not NotImplemented:
                return out
        return self._static_few_python(xy)

    def _static_few_python(self, xy: list[list[float]]) -> list[float] | None:
        """:meth:`static_time` without the prior map of a few positions ``xy`` (M lists
        ``[x, y]`` [m]) in plain floats: the same values, at a fraction of the ~40 numpy
        calls of the array path (which costs ~60 us whatever M; the people layer asks 1-3
        positions a few times a scan). None (take the array path) when a position is not
        finite or a neighbour cell lies outside the arrays.

        The same IEEE operations as :meth:`_cell_static` on the same floats (division,
        floor, subtraction, multiplication are exact in both), except ``exp``: ``math.exp``
        may differ from ``np.exp`` in the last bit, so a decayed evidence within a relative
        1e-9 of ``occupied_evidence`` is decided by ``np.exp`` itself. None also when the
        grid's time is not finite."""
        p = self.params
        if not math.isfinite(self.stamp):
            return None
        res, n = p.resolution, p.neighbourhood
        h, w = self._evidence.shape
        o0, o1 = int(self._origin[0]), int(self._origin[1])
        flat: list[int] = []
        for x, y in xy:
            if not (math.isfinite(x) and math.isfinite(y)):
                return None
            i, j = math.floor(x / res) - o0, math.floor(y / res) - o1
            if i < n or j < n or i >= h - n or j >= w - n:
                return None
            for a in range(i - n, i + n + 1):
                row = a * w
                flat.extend(range(row + j - n, row + j + n + 1))
        idx = np.array(flat, dtype=np.intp)
        ev = self._evidence.reshape(-1).take(idx).tolist()
        touched = self._touched.reshape(-1).take(idx).tolist()
        since = self._since.reshape(-1).take(idx).tolist()
        first = self._first_sight.reshape(-1).take(idx).tolist()
        stamp, tau, thr = self.stamp, p.decay_time, p.occupied_evidence
        hold, extra = p.first_sight_hold, p.first_sight_static
        near = 1e-9 * thr
        times: list[float] = []
        for e, t, s, f in zip(ev, touched, since, first, strict=True):
            tk = 0.0
            if s == s:  # (a free cell, since nan, is 0 s static whatever its evidence)
                dt = stamp - t
                if dt < 0.0:  # np.maximum(dt, 0.0) (dt is never nan: the stamp is finite)
                    dt = 0.0
                decayed = e * math.exp(-dt / tau)
                if abs(decayed - thr) <= near:  # at the threshold: numpy's own exp decides
                    decayed = e * float(np.exp(np.array([-dt / tau]))[0])
                if decayed >= thr:
                    tk = stamp - s
            times.append(tk + extra if f and tk >= hold else tk)
        k = (2 * n + 1) ** 2
        out: list[float] = []
        for m in range(len(xy)):
            best = max(times[m * k : (m + 1) * k])
            out.append(best if best > 0.0 else 0.0)
        return out

    def static_time(self, positions: NDArray[np.float64]) -> NDArray[np.float64]:
        """Static time [s] (M,) of ``positions`` (M, 2) [m] at the last frame's time: the
        largest over the cells within ``neighbourhood``; ``inf`` on a prior map's obstacle,
        0 where free or never seen."""
        p = self.params
        pos = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
        few = None
        if self._evidence.size and 0 < pos.shape[0] <= FEW_POSITIONS:
            few = self._static_few(pos.tolist())
        out = np.zeros(pos.shape[0]) if few is None else np.array(few, dtype=np.float64)
        if few is None and self._evidence.size and pos.shape[0]:
            n = p.neighbourhood
            off = np.arange(-n, n + 1)
            base = self._cells(pos) - self._origin
            h, w = self._evidence.shape
            (i0, j0), (i1, j1) = base.min(axis=0).tolist(), base.max(axis=0).tolist()
            if i0 >= n and j0 >= n and i1 < h - n and j1 < w - n:
                # (the usual case) every neighbour cell is in the arrays: (M, K) flat indices
                # of the K = (2n + 1)^2 cells round each position
                ring = (off[:, None] * w + off[None, :]).ravel()
                flat = ((base[:, 0] * w + base[:, 1])[:, None] + ring[None, :]).ravel()
                t = self._cell_static(flat)
            else:
                # (M, K): the K cells round each position, row offset major; outside: 0 s
                i = (base[:, 0, None] + np.repeat(off, off.size)[None, :]).ravel()
                j = (base[:, 1, None] + np.tile(off, off.size)[None, :]).ravel()
                ok = (i >= 0) & (i < h) & (j >= 0) & (j < w)
                t = np.zeros(i.size)
                if ok.any():
                    t[ok] = self._cell_static(i[ok] * w + j[ok])
            out = np.maximum(t.reshape(pos.shape[0], -1).max(axis=1), 0.0)
        if self._prior_near is not None and pos.shape[0]:
            out[self._prior_near.contains_obstacle(pos)] = np.inf
        return out

    def __call__(self, frame: Frame) -> Frame:
        """Learn from ``frame.points`` (built from ``frame.scans`` when missing) and return
        the frame with ``foreground``: False on cells static for ``background_time``."""
        frame = self.learn_frame(frame)
        assert frame.points is not None
        foreground = self.static_time(frame.points.points) < self.params.background_time
        return replace(frame, foreground=foreground)

    def _recently_learned(self, sensors: Sequence[str], stamp: float) -> bool:
        """Whether every one of ``sensors`` was learned less than ``learn_period`` before
        ``stamp`` [s] (then the frame is not learned); otherwise their stamps become
        ``stamp``. A stamp before a sensor's last one counts as not recent."""
        period = self.params.learn_period
        if period <= 0.0:
            return False
        last = self._learned_at
        if sensors and all(0.0 <= stamp - last.get(s, -math.inf) < period for s in sensors):
            return True
        for s in sensors:
            last[s] = stamp
        return False

    def learn_frame(self, frame: Frame) -> Frame:
        """Learn from ``frame.points`` (built from ``frame.scans`` when missing) and return
        the frame with its points, its ``foreground`` untouched (for a caller that asks only
        :meth:`static_time`)."""
        points = frame.points
        if points is None:
            points = PointSet.from_scans(list(frame.scans), frame.frame)
            frame = replace(frame, points=points)
        if self._recently_learned(points.sensors, frame.stamp):
            self.stamp = max(self.stamp, frame.stamp)
            self.skipped += 1
            return frame
        # (sensor, beam): one id per beam (the beam index itself with one laser)
        ids = points.beams if len(points.sensors) == 1 else (points.sensor_ids << 32) | points.beams
        self.learn(points.points, frame.stamp, _one_sensor_position(frame, points), ids)
        return frame


_UNLOADED = object()
_static_few_compiled: object = _UNLOADED
_grid_compiled: object = _UNLOADED
_look_compiled: object = _UNLOADED


GROW_MARGIN = 64
"""Cells a grid's arrays grow by beyond what they must hold."""


def grown_extent(
    origin: IntArray,
    shape: tuple[int, ...],
    lo: IntArray,
    hi: IntArray,
    resolution: float,
    what: str,
    remedy: str,
) -> tuple[IntArray, tuple[int, int]]:
    """The first cell (2,) and the size of arrays that hold the cells of arrays of
    ``shape`` starting at cell ``origin`` (none when empty) and the cells ``lo`` to ``hi``
    (2,), with :data:`GROW_MARGIN` cells to spare.

    Raises:
        LaserPeopleError: more than :data:`GRID_CELL_LIMIT` cells (``what`` names the
            grid, ``remedy`` what else to do).
    """
    held = np.array(shape, dtype=np.int64)
    if held.prod() == 0:
        new_lo, new_hi = lo - GROW_MARGIN, hi + GROW_MARGIN
    else:
        new_lo = np.minimum(origin, lo - GROW_MARGIN)
        new_hi = np.maximum(origin + held - 1, hi + GROW_MARGIN)
    rows, cols = (int(n) for n in new_hi - new_lo + 1)
    if rows * cols > GRID_CELL_LIMIT:
        raise LaserPeopleError(
            f"{what} would span {rows * resolution:.6g} m x {cols * resolution:.6g} m "
            f"({rows * cols:,} cells, more than the {GRID_CELL_LIMIT:,} accepted)",
            hint="the sensor poses jump far apart (a corrupt /tf or odometry record?); "
            f"check them with `laserpeople info`, or {remedy}",
        )
    return new_lo, (rows, cols)


def moved_into(
    old: NDArray[Any], origin: IntArray, new_lo: IntArray, size: tuple[int, int], fill: Any
) -> NDArray[Any]:
    """An array of ``size`` starting at cell ``new_lo``, ``fill`` where ``old`` (starting
    at cell ``origin``) has no cell."""
    new = np.full(size, fill, dtype=old.dtype)
    if old.size:
        a = origin - new_lo
        new[a[0] : a[0] + old.shape[0], a[1] : a[1] + old.shape[1]] = old
    return new


def compiled_function(name: str) -> Any:
    """The static world's function ``name`` of the MHT's C extension (``grid_hits``,
    ``still_cast_usual``, ...), run where its ``static_few`` is (built, not stale, not
    forced off), or None."""
    few = _compiled_static_few()
    module = None if few is None else few.__self__  # (a module's function: the module)
    return getattr(module, name, None)


def _compiled_grid() -> tuple[Any, Any] | None:
    """The compiled ``grid_hits`` and ``grid_mark``, or None."""
    global _grid_compiled
    if _grid_compiled is _UNLOADED:
        hits, mark = compiled_function("grid_hits"), compiled_function("grid_mark")
        _grid_compiled = None if hits is None or mark is None else (hits, mark)
    return _grid_compiled  # type: ignore[return-value]


def _compiled_look() -> Any:
    """The compiled ``grid_frame`` (:meth:`OccupancyGrid._look`), or None."""
    global _look_compiled
    if _look_compiled is _UNLOADED:
        _look_compiled = compiled_function("grid_frame")
    return _look_compiled


def _compiled_static_few() -> Any:
    """The compiled ``static_few`` of the MHT's C extension, or None where it is not built
    (imported at first use: the trackers have loaded it by then)."""
    global _static_few_compiled
    if _static_few_compiled is _UNLOADED:
        from laserpeople.tracking.mht import listing

        _static_few_compiled = listing.COMPILED_STATIC_FEW
    return _static_few_compiled


def sorted_unique(values: IntArray) -> IntArray:
    """The distinct ``values`` (N,), sorted: ``np.unique(values)``, which on a few hundred
    values takes several times as long (numpy 2.4)."""
    s = np.sort(values)
    if s.size < 2:
        return s
    keep = np.ones(s.size, dtype=bool)
    np.not_equal(s[1:], s[:-1], out=keep[1:])
    return s[keep]


def _one_sensor_position(frame: Frame, points: PointSet) -> FloatArray | None:
    """:func:`sensor_positions` for :meth:`OccupancyGrid.learn`: the one position (2,) of
    a frame of one laser (the same values, without broadcasting them to every point), else
    :func:`sensor_positions` itself."""
    if len(frame.scans) != 1 or points.sensors != (frame.scans[0].sensor,):
        return sensor_positions(frame, points)
    if frame.frame == "sensor":
        return np.zeros(2)
    scan = frame.scans[0]
    pose = scan.pose if scan.pose is not None else frame.sensor_pose
    return None if pose is None else np.array([pose.x, pose.y], dtype=np.float64)


def sensor_positions(frame: Frame, points: PointSet) -> FloatArray | None:
    """The position (N, 2) [m] of the laser that measured each of ``points``, in the
    frame's coordinate frame: each scan's pose in the world frame, the origin in the sensor
    frame (one laser); None when a world-frame scan has no pose. With one laser, one row
    broadcast to all (read-only)."""
    if frame.frame == "sensor":
        return np.broadcast_to(np.zeros(2), (len(points), 2))
    where: dict[str, tuple[float, float]] = {}
    for scan in frame.scans:
        pose = scan.pose if scan.pose is not None else frame.sensor_pose
        if pose is None:
            return None
        where[scan.sensor] = (pose.x, pose.y)
    try:
        table = np.array([where[name] for name in points.sensors], dtype=np.float64)
    except KeyError:
        return None
    if table.shape[0] == 1:  # one laser: one position (a read-only view)
        return np.broadcast_to(table[0], (len(points), 2))
    return table[points.sensor_ids].reshape(-1, 2)


def frame_from_scan(scan: Scan, frame: CoordinateFrame = "sensor") -> Frame:
    """A :class:`~laserpeople.frame.Frame` of one scan with its valid points in ``frame``
    (the world frame needs the scan's pose), for feeding a static world model before the
    pipeline does it."""
    points = PointSet.from_scans([scan], frame)
    return Frame(
        index=scan.index,
        stamp=scan.stamp,
        scans=(scan,),
        topic=scan.sensor,
        frame=frame,
        sensor_pose=scan.pose,
        points=points,
    )
