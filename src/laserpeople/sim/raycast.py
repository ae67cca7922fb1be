"""Vectorised ray casting of a fan of laser beams against circles, ellipses and segments.

Every primitive is first reduced to the interval of beam indices that can possibly hit it
(from its bearing and angular half-width seen from the sensor). The candidate
``(beam, primitive)`` pairs are then built with ``np.repeat`` and intersected all at
once, and each beam keeps its nearest hit. The work is proportional to the number of
beams that point at something, not to beams x primitives, and has no Python loop over
beams or primitives.

All geometry here is in the *sensor frame*: the sensor sits at the origin and beam ``i``
points at angle ``angle_min + i * angle_increment`` [rad].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

LABEL_FIELDS = ("person", "leg", "group", "obj")
"""Columns of a primitive's label array, in order (see :class:`~laserpeople.truth.BeamLabels`)."""


@dataclass(frozen=True, eq=False)
class Primitives:
    """Shapes to ray cast, each with a label row ``(person, leg, group, obj)``.

    Attributes:
        circle_centres: (C, 2) [m].
        circle_radii: (C,) [m].
        circle_labels: (C, 4) int32.
        ellipse_centres: (E, 2) [m].
        ellipse_axes: (E, 2) semi-axes [m] along the ellipse's own x and y.
        ellipse_angles: (E,) orientation of the ellipse's x axis [rad].
        ellipse_labels: (E, 4) int32.
        segment_starts: (S, 2) [m].
        segment_ends: (S, 2) [m].
        segment_labels: (S, 4) int32.
    """

    circle_centres: FloatArray
    circle_radii: FloatArray
    circle_labels: NDArray[np.int32]
    ellipse_centres: FloatArray
    ellipse_axes: FloatArray
    ellipse_angles: FloatArray
    ellipse_labels: NDArray[np.int32]
    segment_starts: FloatArray
    segment_ends: FloatArray
    segment_labels: NDArray[np.int32]

    @classmethod
    def empty(cls) -> Primitives:
        """No shapes at all."""
        z2 = np.empty((0, 2))
        zl = np.empty((0, 4), dtype=np.int32)
        return cls(z2, np.empty(0), zl, z2, z2, np.empty(0), zl, z2, z2, zl)

    @classmethod
    def concat(cls, parts: list[Primitives]) -> Primitives:
        """All shapes of several sets in one."""
        if not parts:
            return cls.empty()
        return cls(
            *(
                np.concatenate([getattr(p, f) for p in parts])
                for f in (
                    "circle_centres",
                    "circle_radii",
                    "circle_labels",
                    "ellipse_centres",
                    "ellipse_axes",
                    "ellipse_angles",
                    "ellipse_labels",
                    "segment_starts",
                    "segment_ends",
                    "segment_labels",
                )
            )
        )

    def transformed(self, rotation: FloatArray, translation: FloatArray) -> Primitives:
        """Shapes mapped by ``p -> rotation @ p + translation`` (rotation 2x2, angle from it)."""
        angle = math.atan2(rotation[1, 0], rotation[0, 0])
        return Primitives(
            self.circle_centres @ rotation.T + translation,
            self.circle_radii,
            self.circle_labels,
            self.ellipse_centres @ rotation.T + translation,
            self.ellipse_axes,
            self.ellipse_angles + angle,
            self.ellipse_labels,
            self.segment_starts @ rotation.T + translation,
            self.segment_ends @ rotation.T + translation,
            self.segment_labels,
        )


@dataclass(frozen=True, eq=False)
class BeamFan:
    """The beam geometry of a scanner: ``n`` beams from ``angle_min`` in steps of ``increment``."""

    angle_min: float
    increment: float
    n: int

    @property
    def angles(self) -> FloatArray:
        """Beam angles (n,) [rad], unwrapped."""
        return np.asarray(self.angle_min + np.arange(self.n) * self.increment, dtype=np.float64)


@dataclass(frozen=True, eq=False)
class CastResult:
    """Nearest hit of every beam.

    Attributes:
        ranges: (n,) distance to the nearest hit [m]; ``inf`` where nothing was hit.
        labels: (n, 4) int32 label row of the hit primitive; -1 where nothing was hit.
    """

    ranges: FloatArray
    labels: NDArray[np.int32]


def _beam_pairs(
    fan: BeamFan, bearing_lo: FloatArray, bearing_hi: FloatArray
) -> tuple[IntArray, IntArray]:
    """Pairs (beam, primitive) for every beam whose angle lies in [lo, hi] of a primitive.

    ``bearing_lo <= bearing_hi`` [rad], each interval shorter than 2*pi. Beam indices are
    taken modulo a full turn so an interval crossing ``angle_min`` wraps correctly.
    """
    inc = fan.increment
    a = (bearing_lo - fan.angle_min) / inc
    b = (bearing_hi - fan.angle_min) / inc
    lo_f = np.minimum(a, b)
    hi_f = np.maximum(a, b)
    full = 2.0 * math.pi / abs(inc)
    # shift each interval so that it starts in [0, full); an interval that runs past a
    # full turn wraps round to beam 0, so it is also tried one turn earlier
    shift = np.floor(lo_f / full) * full
    lo_f = lo_f - shift
    hi_f = hi_f - shift
    wraps = hi_f >= full
    lo_all = np.concatenate([lo_f, lo_f[wraps] - full])
    hi_all = np.concatenate([hi_f, hi_f[wraps] - full])
    owner = np.concatenate([np.arange(lo_f.size), np.flatnonzero(wraps)])
    lo = np.maximum(np.ceil(lo_all - 1e-9).astype(np.int64), 0)
    hi = np.minimum(np.floor(hi_all + 1e-9).astype(np.int64), fan.n - 1)
    counts = np.maximum(hi - lo + 1, 0)
    total = int(counts.sum())
    if total == 0:
        return np.empty(0, dtype=np.int64), np.empty(0, dtype=np.int64)
    prim = np.repeat(owner, counts)
    starts = np.cumsum(counts) - counts
    within = np.arange(total) - np.repeat(starts, counts)
    beam = np.repeat(lo, counts) + within
    return beam, prim


def _beams_near(fan: BeamFan, centres: FloatArray, bound: FloatArray) -> tuple[IntArray, IntArray]:
    """Pairs (beam, primitive) for every beam that passes within ``bound`` (K,) [m] of a
    primitive's centre (K, 2); primitives whose bound holds the sensor are skipped."""
    d = np.hypot(centres[:, 0], centres[:, 1])
    idx = np.flatnonzero(d > bound)
    if idx.size == 0:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    bearing = np.arctan2(centres[idx, 1], centres[idx, 0])
    half = np.arcsin(np.clip(bound[idx] / d[idx], 0.0, 1.0))
    beam, k = _beam_pairs(fan, bearing - half, bearing + half)
    return beam, idx[k]


def _cast_circles(
    fan: BeamFan, centres: FloatArray, radii: FloatArray
) -> tuple[IntArray, FloatArray, IntArray]:
    beam, prim = _beams_near(fan, centres, radii)
    ang = fan.angle_min + beam * fan.increment
    ux, uy = np.cos(ang), np.sin(ang)
    c = centres[prim]
    proj = ux * c[:, 0] + uy * c[:, 1]
    disc = radii[prim] ** 2 - (np.hypot(c[:, 0], c[:, 1]) ** 2 - proj**2)
    ok = (disc >= 0.0) & (proj > 0.0)
    t = proj[ok] - np.sqrt(disc[ok])
    return beam[ok], t, prim[ok]


def _cast_ellipses(
    fan: BeamFan, centres: FloatArray, axes: FloatArray, angles: FloatArray
) -> tuple[IntArray, FloatArray, IntArray]:
    beam, prim = _beams_near(fan, centres, axes.max(axis=1))
    ang = fan.angle_min + beam * fan.increment - angles[prim]
    # ray in the ellipse's frame, scaled so that the ellipse becomes the unit circle
    c, s = np.cos(angles[prim]), np.sin(angles[prim])
    cx, cy = centres[prim, 0], centres[prim, 1]
    ox = -(c * cx + s * cy) / axes[prim, 0]
    oy = -(-s * cx + c * cy) / axes[prim, 1]
    dx = np.cos(ang) / axes[prim, 0]
    dy = np.sin(ang) / axes[prim, 1]
    qa = dx * dx + dy * dy
    qb = 2.0 * (ox * dx + oy * dy)
    qc = ox * ox + oy * oy - 1.0
    disc = qb * qb - 4.0 * qa * qc
    ok = disc >= 0.0
    t = np.full(beam.size, -1.0)
    t[ok] = (-qb[ok] - np.sqrt(disc[ok])) / (2.0 * qa[ok])
    ok &= t > 0.0
    return beam[ok], t[ok], prim[ok]


def _cast_segments(
    fan: BeamFan, starts: FloatArray, ends: FloatArray
) -> tuple[IntArray, FloatArray, IntArray]:
    if starts.shape[0] == 0:
        return np.empty(0, np.int64), np.empty(0), np.empty(0, np.int64)
    b0 = np.arctan2(starts[:, 1], starts[:, 0])
    b1 = np.arctan2(ends[:, 1], ends[:, 0])
    span = np.mod(b1 - b0 + math.pi, 2.0 * math.pi) - math.pi
    lo = np.where(span >= 0.0, b0, b0 + span)
    beam, prim = _beam_pairs(fan, lo, lo + np.abs(span))
    ang = fan.angle_min + beam * fan.increment
    ux, uy = np.cos(ang), np.sin(ang)
    p = starts[prim]
    e = ends[prim] - p
    denom = ux * e[:, 1] - uy * e[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (p[:, 0] * e[:, 1] - p[:, 1] * e[:, 0]) / denom
        s = (p[:, 0] * uy - p[:, 1] * ux) / denom
    ok = (np.abs(denom) > 1e-12) & (t > 0.0) & (s >= -1e-9) & (s <= 1.0 + 1e-9)
    return beam[ok], t[ok], prim[ok]


def cast(fan: BeamFan, shapes: Primitives) -> CastResult:
    """Ray cast every beam of ``fan`` against ``shapes`` (sensor frame); nearest hit wins.

    Returns ranges (n,) [m] (``inf`` = no hit) and the hit shape's labels (n, 4).
    """
    cb, ct, cp = _cast_circles(fan, shapes.circle_centres, shapes.circle_radii)
    eb, et, ep = _cast_ellipses(
        fan, shapes.ellipse_centres, shapes.ellipse_axes, shapes.ellipse_angles
    )
    sb, st, sp = _cast_segments(fan, shapes.segment_starts, shapes.segment_ends)
    beams = np.concatenate([cb, eb, sb])
    ts = np.concatenate([ct, et, st])
    labels = np.concatenate(
        [shapes.circle_labels[cp], shapes.ellipse_labels[ep], shapes.segment_labels[sp]]
    )
    ranges = np.full(fan.n, np.inf)
    out_labels = np.full((fan.n, 4), -1, dtype=np.int32)
    if beams.size:
        order = np.lexsort((ts, beams))
        b_sorted = beams[order]
        first = np.ones(b_sorted.size, dtype=bool)
        first[1:] = b_sorted[1:] != b_sorted[:-1]
        pick = order[first]
        ranges[beams[pick]] = ts[pick]
        out_labels[beams[pick]] = labels[pick]
    return CastResult(ranges, out_labels)
