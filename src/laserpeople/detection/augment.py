"""Training scans as another scanner would have seen them: angular resampling and scaling.

A leg classifier trained on one scanner sees legs with that scanner's point spacing, at the
ranges and of the sizes its recordings hold. Two operations turn one labelled scan into
scans of other scanners and scenes, so that training data covers them:

* **Angular resampling** (:func:`resample_scan`): the same field of view sampled with a
  different angle increment. Each new beam reads the source at its angle: linearly
  interpolated between the two neighbouring source beams when both returned and lie on the
  same surface (ranges within :attr:`AugmentParams.interpolation_gap`), otherwise the
  nearest source beam (so depth edges stay sharp and no point is invented in a gap).
  Coarser increments drop points as a coarser scanner would; finer ones add points along
  the surfaces.
* **Scaling the world** (``range_scale``): every range multiplied by ``s``. The points of
  each object stay the same in number, while sizes, gaps and ranges grow by ``s``: a leg
  of radius ``r`` at range ``d`` becomes one of radius ``s r`` at ``s d`` with the same
  number of points. Together with resampling this decouples the three things a one-scanner
  training set ties together: point count, size and range.

Beam classes carry the labels through: ``+1`` leg, ``-1`` not a leg, ``0`` unknown (e.g.
the unlabelled segments of a leg_tracker positive scan). A new beam takes the class of its
nearest source beam; :func:`segment_labels_from_beams` turns them back into segment labels.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.scan import Scan
from laserpeople.segmentation import (
    JumpDistanceParams,
    JumpDistanceSegmenter,
    SegmentTable,
    covers_full_circle,
)

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True)
class AugmentParams:
    """How training scans are resampled (see the module docstring)."""

    config_section = "augment"

    interpolation_gap: float = param(
        0.05,
        "our choice: a few times the range noise of a real scanner (~1-3 cm), well below the "
        "0.1-0.13 m jump distances that separate objects",
        "two neighbouring beams are interpolated only when their ranges differ by less than "
        "this (otherwise the nearest beam is taken)",
        "m",
    )


DEFAULT_AUGMENT_PARAMS = AugmentParams()


def resample_scan(
    scan: Scan,
    increment: float,
    range_scale: float = 1.0,
    beam_class: IntArray | None = None,
    params: AugmentParams = DEFAULT_AUGMENT_PARAMS,
) -> tuple[Scan, IntArray]:
    """``scan`` sampled every ``increment`` over its field of view, ranges times ``range_scale``.

    Args:
        scan: The source scan.
        increment: New angle increment magnitude [rad] (the source's sign is kept).
        range_scale: Factor s > 0 for every range (and the range limits).
        beam_class: Class (N,) of every source beam (+1 leg, -1 not, 0 unknown); all -1
            when not given.
        params: Interpolation gap.

    Returns:
        The new scan (N',) (per-beam truth and intensities are dropped) and the class
        (N',) of each of its beams (that of the nearest source beam).
    """
    if not (increment > 0.0 and math.isfinite(increment)):
        raise ValueError(f"increment must be a positive angle, got {increment!r}")
    if not (range_scale > 0.0 and math.isfinite(range_scale)):
        raise ValueError(f"range_scale must be positive, got {range_scale!r}")
    n = scan.n_beams
    classes = (
        np.full(n, -1, dtype=np.int64)
        if beam_class is None
        else np.asarray(beam_class, dtype=np.int64)
    )
    if classes.shape != (n,):
        raise ValueError(f"{classes.size} beam classes for {n} beams")
    step = abs(scan.angle_increment)
    ratio = increment / step  # new beam spacing in source beams
    full = covers_full_circle(scan)
    # a full circle keeps covering it; otherwise the span up to the last source beam
    n_new = max(round(n / ratio), 1) if full else math.floor((n - 1) / ratio + 1e-9) + 1
    u = np.arange(n_new) * ratio
    i0 = np.floor(u).astype(np.int64)
    f = u - i0
    i1 = i0 + 1
    if full:
        i0 %= n
        i1 %= n
    else:
        i1 = np.minimum(i1, n - 1)
    near = np.where(f < 0.5, i0, i1)
    valid = scan.valid
    r = np.where(valid, scan.ranges, np.nan)
    r0, r1 = r[i0], r[i1]
    same_surface = valid[i0] & valid[i1] & (np.abs(r0 - r1) < params.interpolation_gap)
    ranges = np.where(same_surface, (1.0 - f) * r0 + f * r1, r[near]) * range_scale
    new = Scan(
        stamp=scan.stamp,
        angle_min=scan.angle_min,
        angle_increment=math.copysign(increment, scan.angle_increment),
        ranges=ranges,
        range_min=scan.range_min * range_scale,
        range_max=scan.range_max * range_scale,
        sensor=scan.sensor,
        pose=scan.pose,
        index=scan.index,
        source=scan.source,
    )
    return new, classes[near]


def beam_classes(table: SegmentTable, segment_labels: IntArray) -> IntArray:
    """Class (N,) of every beam of a scan from the labels (M,) of its segments.

    Beams in no segment (no return) are unknown (0).
    """
    out = np.zeros(table.n_beams, dtype=np.int64)
    out[table.beams % table.n_beams] = np.repeat(np.asarray(segment_labels), table.sizes)
    return out


def segment_labels_from_beams(table: SegmentTable, classes: IntArray) -> IntArray:
    """Label (M,) of every segment from the classes (N,) of its beams.

    A leg (+1) when more than half of its beams are leg beams; not a leg (-1) when none of
    its beams is unknown; otherwise unknown (0, left out of training).
    """
    if len(table) == 0:
        return np.empty(0, dtype=np.int64)
    c = np.asarray(classes)[table.beams % table.n_beams]
    off = table.offsets[:-1]
    legs = np.add.reduceat((c > 0).astype(np.float64), off)
    unknown = np.add.reduceat((c == 0).astype(np.float64), off)
    out = np.where(unknown > 0, 0, -1).astype(np.int64)
    out[legs > 0.5 * table.sizes] = 1
    return out


@dataclass(frozen=True)
class Variant:
    """One scanner/scene variant of the training scans: new increment and world scale."""

    increment: float
    range_scale: float = 1.0

    @property
    def name(self) -> str:
        """``0.50deg x1.4``."""
        return f"{math.degrees(self.increment):.2f}deg x{self.range_scale:g}"


def variants(increments_deg: Sequence[float], scales: Sequence[float]) -> tuple[Variant, ...]:
    """Every combination of increments [deg] and world scales."""
    return tuple(Variant(math.radians(a), s) for a in increments_deg for s in scales)


TRANSFER_VARIANTS: tuple[Variant, ...] = variants((0.25, 0.35, 0.5, 0.7, 1.0), (0.7, 1.0, 1.4, 2.0))
"""The 20 variants of ``laserpeople train --augment`` and benchmarks/detector_transfer.py:
angle increments of common scanners (those of the randomised simulator, 0.25-1 deg) times
world scales that turn legs of 0.06-0.09 m radius at 0.5-5 m into 0.04-0.18 m at 0.35-10 m
(see docs/leg-detection.md for how it was chosen and a grid that did less well)."""


def resampled_stream(
    scans: Iterable[tuple[Scan, IntArray]],
    variant: Variant,
    params: AugmentParams = DEFAULT_AUGMENT_PARAMS,
) -> Iterator[tuple[Scan, IntArray]]:
    """Each (scan, beam classes) of a time-ordered stream as ``variant`` sees it."""
    for scan, classes in scans:
        yield resample_scan(scan, variant.increment, variant.range_scale, classes, params)


# --------------------------------------------------------------------- moving segments out
# A labelled scan recorded with people at 1-4 m says little about legs at 4-8 m on the same
# scanner: there a leg gets a third of the beams. Moving every segment out along its bearing
# and casting the scanner's beams at it again gives the scan the same scene would give with
# everything farther away, each object its own size (see docs/leg-detection.md).


@dataclass(frozen=True)
class RangeShiftParams:
    """How :func:`shift_scan_out` moves segments out and casts beams at them again."""

    config_section = "augment_range_shift"

    range_noise: float = param(
        0.01,
        "our choice: the range noise of the leg_tracker recordings' 0.35 deg Hokuyo "
        "(datasheet +-30 mm, i.e. about 3 sigma; the simulator's Hokuyo models use 0.01 m)",
        "standard deviation of the Gaussian noise added to every re-cast range",
        "m",
    )
    edge_extension: float = param(
        0.5,
        "our choice: a surface ends between the last beam that hit it and the first that "
        "missed, half a beam spacing beyond its last point on average",
        "how far each end of a segment's surface is extended beyond its end point, in beam "
        "spacings at its original range",
        "beams",
    )


DEFAULT_RANGE_SHIFT_PARAMS = RangeShiftParams()

RANGE_SHIFTS: tuple[float, ...] = (2.0, 3.5)
"""[m] How far the shipped default model's training scans of the leg_tracker recordings are
moved out (their labelled legs at 0.5-5 m become legs at 2.5-8.5 m): see
docs/leg-detection.md."""


def segment_surfaces(
    table: SegmentTable, shift: float, increment: float, extension: float
) -> tuple[FloatArray, FloatArray, IntArray]:
    """The surface of every segment of ``table`` moved ``shift`` metres out along the bearing
    of its centre, as a polyline: edges from ``starts`` (E, 2) to ``ends`` (E, 2) [m] and the
    segment (E,) each edge belongs to.

    The polyline runs through the segment's points in beam order; each end is extended by
    ``extension`` beam spacings (``increment`` [rad] times the end point's original range)
    along the end edge (a single point becomes a patch of that half-width facing the sensor).
    """
    m = len(table)
    if m == 0:
        return np.empty((0, 2)), np.empty((0, 2)), np.empty(0, dtype=np.int64)
    centres = table.centres()
    norm = np.hypot(centres[:, 0], centres[:, 1])
    bearing = centres / np.where(norm > 0.0, norm, 1.0)[:, None]
    ids = table.segment_ids
    pts = table.points + shift * bearing[ids]
    first = table.offsets[:-1]
    last = table.offsets[1:] - 1
    spacing = extension * increment * np.hypot(table.points[:, 0], table.points[:, 1])
    # direction away from the segment at each end: along the end edge, or across the bearing
    single = first == last
    out_first = np.where(
        single[:, None],
        np.column_stack((bearing[:, 1], -bearing[:, 0])),
        pts[first] - pts[np.minimum(first + 1, last)],
    )
    out_last = np.where(
        single[:, None],
        np.column_stack((-bearing[:, 1], bearing[:, 0])),
        pts[last] - pts[np.maximum(last - 1, first)],
    )

    def unit(v: FloatArray) -> FloatArray:
        n = np.hypot(v[:, 0], v[:, 1])
        return np.asarray(v / np.where(n > 0.0, n, 1.0)[:, None], dtype=np.float64)

    head = pts[first] + unit(out_first) * spacing[first][:, None]
    tail = pts[last] + unit(out_last) * spacing[last][:, None]
    inner = np.flatnonzero(ids[1:] == ids[:-1])  # edges between points of one segment
    starts = np.concatenate((head, pts[inner], pts[last]))
    ends = np.concatenate((pts[first], pts[inner + 1], tail))
    seg = np.concatenate((np.arange(m), ids[inner], np.arange(m))).astype(np.int64)
    return starts, ends, seg


def cast_beams(
    angles: FloatArray, starts: FloatArray, ends: FloatArray
) -> tuple[FloatArray, IntArray]:
    """Range (N,) [m] along each beam of ``angles`` (N,) [rad] to the nearest of the edges
    ``starts`` -> ``ends`` (E, 2) it crosses (inf when none), and that edge's index (-1)."""
    n = angles.size
    ranges = np.full(n, np.inf)
    which = np.full(n, -1, dtype=np.int64)
    if starts.shape[0] == 0 or n == 0:
        return ranges, which
    step = (angles[-1] - angles[0]) / (n - 1) if n > 1 else 1.0
    a0 = np.arctan2(starts[:, 1], starts[:, 0])
    a1 = np.arctan2(ends[:, 1], ends[:, 0])
    lo = np.minimum(a0, a1)
    hi = np.maximum(a0, a1)
    wraps = hi - lo > math.pi  # an edge across the +-pi seam behind the sensor: left out
    j_lo = np.ceil((lo - angles[0]) / step - 1e-9).astype(np.int64)
    j_hi = np.floor((hi - angles[0]) / step + 1e-9).astype(np.int64)
    if step < 0:
        j_lo, j_hi = (
            np.ceil((hi - angles[0]) / step - 1e-9).astype(np.int64),
            np.floor((lo - angles[0]) / step + 1e-9).astype(np.int64),
        )
    j_lo = np.maximum(j_lo, 0)
    j_hi = np.minimum(j_hi, n - 1)
    counts = np.where(wraps, 0, np.maximum(j_hi - j_lo + 1, 0))
    edge = np.repeat(np.arange(starts.shape[0]), counts)
    if edge.size == 0:
        return ranges, which
    offsets = np.cumsum(counts) - counts
    beam = j_lo[edge] + np.arange(edge.size) - offsets[edge]
    d = np.column_stack((np.cos(angles[beam]), np.sin(angles[beam])))
    a = starts[edge]
    e = ends[edge] - a
    denom = d[:, 0] * e[:, 1] - d[:, 1] * e[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (a[:, 0] * e[:, 1] - a[:, 1] * e[:, 0]) / denom
    ok = np.isfinite(t) & (t > 0.0)
    beam, edge, t = beam[ok], edge[ok], t[ok]
    np.minimum.at(ranges, beam, t)
    hit = t <= ranges[beam]
    which[beam[hit]] = edge[hit]
    return ranges, which


def shift_scan_out(
    scan: Scan,
    beam_class: IntArray,
    shift: float,
    segmentation: JumpDistanceParams,
    rng: np.random.Generator,
    params: RangeShiftParams = DEFAULT_RANGE_SHIFT_PARAMS,
) -> tuple[Scan, IntArray]:
    """``scan`` as its scanner would see the scene with every segment ``shift`` metres
    farther out along its bearing, each object keeping its size and shape.

    The scan is segmented (``segmentation``), each segment's surface (:func:`segment_surfaces`)
    moved out, the scanner's own beams cast at the moved surfaces (the nearest hit counts,
    so nearer objects hide farther ones) and Gaussian noise added to every return. A beam
    takes the class of the segment it hits (``beam_class`` of that segment's beams, the
    majority when they differ); a beam that hits nothing, or lands beyond the scanner's
    ``range_max``, returns nothing (class 0).

    Args:
        scan: The source scan (N,).
        beam_class: Class (N,) of every source beam (+1 leg, -1 not, 0 unknown).
        shift: How far to move every segment out [m] (> 0).
        segmentation: How the source scan is cut into objects.
        rng: Noise source.
        params: Noise and surface extension.

    Returns:
        The new scan (N,), same beam geometry (per-beam truth and intensities dropped), and
        the class (N,) of each of its beams.
    """
    if not (shift > 0.0 and math.isfinite(shift)):
        raise ValueError(f"shift must be a positive distance, got {shift!r}")
    classes = np.asarray(beam_class, dtype=np.int64)
    if classes.shape != (scan.n_beams,):
        raise ValueError(f"{classes.size} beam classes for {scan.n_beams} beams")
    table = JumpDistanceSegmenter(segmentation)(scan)
    step = abs(scan.angle_increment)
    starts, ends, seg = segment_surfaces(table, shift, step, params.edge_extension)
    angles = np.asarray(
        scan.angle_min + scan.angle_increment * np.arange(scan.n_beams), dtype=np.float64
    )
    ranges, edge = cast_beams(angles, starts, ends)
    seg_class = (
        np.sign(np.add.reduceat(classes[table.beams % table.n_beams], table.offsets[:-1]))
        if len(table)
        else np.empty(0, dtype=np.int64)
    )
    out_class = np.where(edge >= 0, seg_class[np.maximum(seg[np.maximum(edge, 0)], 0)], 0)
    noisy = ranges + rng.standard_normal(scan.n_beams) * params.range_noise
    echo = np.isfinite(noisy) & (noisy <= scan.range_max) & (noisy >= scan.range_min)
    new = Scan(
        stamp=scan.stamp,
        angle_min=scan.angle_min,
        angle_increment=scan.angle_increment,
        ranges=np.where(echo, noisy, np.inf),
        range_min=scan.range_min,
        range_max=scan.range_max,
        sensor=scan.sensor,
        pose=scan.pose,
        index=scan.index,
        source=scan.source,
    )
    return new, np.where(echo, out_class, 0).astype(np.int64)
