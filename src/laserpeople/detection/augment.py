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
from laserpeople.segmentation import SegmentTable, covers_full_circle

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
