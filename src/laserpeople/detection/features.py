"""The fourteen segment features of 000 Sec. 2.2, vectorised over all segments of a scan.

Every feature is computed for every segment at once from the flat arrays of a
:class:`~laserpeople.segmentation.SegmentTable` (segment ids + ``np.bincount`` /
``np.add.reduceat``); no Python loop runs over segments. Features are returned as a matrix
(M, 14) whose column ``j - 1`` is feature ``j`` of the paper:

==  =====================  ========================================================
#   name                   definition (units)
==  =====================  ========================================================
1   n_points               number of points n
2   std_dev                sqrt(1/(n-1) sum ||x_j - mean||^2)  [m]
3   mad_median             1/n sum ||x_j - vector-of-medians||  [m]
4   jump_prev              distance first point -> last point of the preceding segment [m]
5   jump_next              distance last point -> first point of the succeeding segment [m]
6   width                  distance first -> last point [m]
7   linearity              residual sum of squares of the Hessian (alpha, r) line fit [m^2]
8   circularity            residual sum of squares of the algebraic circle fit [m^2]
9   radius                 radius of that circle [m]
10  boundary_length        sum of distances between adjacent points [m]
11  boundary_regularity    sample standard deviation of those distances [m]
12  mean_curvature         mean over interior points of 4A/(dA dB dC)  [1/m]
13  mean_angular_diff      mean signed turning angle between successive chords [rad]
14  mean_speed             mean over beams of (rho_k+1 - rho_k)/(T_k+1 - T_k)  [m/s]
==  =====================  ========================================================

Choices where 000 is silent or ambiguous (all documented in the tests):

* Features 4/5 of the first/last segment of a scan that does not cover the full circle have
  no neighbour; they take :attr:`FeatureParams.no_neighbour_jump`.
* Feature 11 uses the sample standard deviation (divisor n - 2 for the n - 1 distances),
  like feature 2; 0 for n < 3.
* Feature 12 is called "mean" but written as a sum in 000; we take the mean over the n - 2
  interior points (the sum would just rescale by the segment size, which feature 1 has).
* Feature 13 is signed (convex vs concave) and is measured traversing the segment by
  increasing beam *angle*, so a scanner with negative ``angle_increment`` gives the same value.
* The circle fit is done in coordinates centred on the segment's mean (the algebraic fit is
  translation invariant, and centring keeps the normal equations well conditioned). For
  collinear points (no circle) the radius is :attr:`FeatureParams.no_circle_radius` and the
  circularity equals the linearity (the residual to the infinitely large circle, a line).
* Feature 14 matches each segment beam with the *same beam* of the previous scan (the
  sensor is stationary as in 000 Sec. 2.3; a moving robot must align scans first) and
  averages over the beams valid in both scans; 0 when there is no usable previous scan
  (none, other beam layout, or non-increasing stamps) or no beam valid in both.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.scan import Scan
from laserpeople.segmentation import SegmentTable

FloatArray = NDArray[np.float64]

FEATURE_NAMES: tuple[str, ...] = (
    "n_points",
    "std_dev",
    "mad_median",
    "jump_prev",
    "jump_next",
    "width",
    "linearity",
    "circularity",
    "radius",
    "boundary_length",
    "boundary_regularity",
    "mean_curvature",
    "mean_angular_diff",
    "mean_speed",
)
"""Names of features 1..14 (index ``j - 1``)."""

N_FEATURES = len(FEATURE_NAMES)
MIN_POINTS = 3
"""Segments with fewer points are not classified (000 Sec. 2.2: only n > 2)."""


@dataclass(frozen=True)
class FeatureParams:
    """Values for the cases 000 leaves undefined."""

    config_section = "features"

    no_neighbour_jump: float = param(
        100.0,
        "our choice (000 leaves it undefined)",
        "jump distance (features 4, 5) of a segment without a neighbour on that side",
        "m",
    )
    no_circle_radius: float = param(
        100.0,
        "our choice (000 leaves it undefined)",
        "radius (feature 9) given to collinear segments, which have no circle",
        "m",
    )


DEFAULT_FEATURE_PARAMS = FeatureParams()


@dataclass(frozen=True, eq=False)
class SegmentFeatures:
    """Features of all segments of one scan.

    Attributes:
        values: Feature matrix (M, 14); column ``j - 1`` is feature ``j``.
        max_beam_motion: Largest |range change| (M,) [m] of any segment beam since the
            previous scan (0 without one), used by the heuristic baseline.
        centres: Segment centres (M, 2) [m], sensor frame.
        circle_centres: Centres (M, 2) [m] of the fitted circles (NaN when collinear).
    """

    values: FloatArray
    max_beam_motion: FloatArray
    centres: FloatArray
    circle_centres: FloatArray

    def __len__(self) -> int:
        return int(self.values.shape[0])

    @property
    def classifiable(self) -> NDArray[np.bool_]:
        """Mask (M,) of segments with at least three points."""
        return np.asarray(self.values[:, 0] >= MIN_POINTS)


def compute_features(
    table: SegmentTable,
    scan: Scan,
    previous: Scan | None = None,
    params: FeatureParams = DEFAULT_FEATURE_PARAMS,
    *,
    full_circle: bool = False,
) -> SegmentFeatures:
    """The 14 features of every segment of ``scan``.

    Args:
        table: The scan's segments (from a segmenter).
        scan: The scan itself (for ranges, stamp and beam direction).
        previous: The previous scan of the same sensor, for feature 14.
        params: Values for undefined cases.
        full_circle: The scan covers 360 degrees, so the first and last segment neighbour
            each other (features 4 and 5).
    """
    m = len(table)
    if m == 0:
        return SegmentFeatures(
            np.empty((0, N_FEATURES)), np.empty(0), np.empty((0, 2)), np.empty((0, 2))
        )
    with np.errstate(divide="ignore", invalid="ignore"):
        return _compute(table, scan, previous, params, full_circle)


def _compute(
    table: SegmentTable,
    scan: Scan,
    previous: Scan | None,
    params: FeatureParams,
    full_circle: bool,
) -> SegmentFeatures:
    m = len(table)
    P = table.points
    k = P.shape[0]
    off = table.offsets[:-1]
    sizes = np.diff(table.offsets)
    n = sizes.astype(np.float64)
    seg = np.repeat(np.arange(m), sizes)
    out = np.zeros((m, N_FEATURES))
    out[:, 0] = n

    # centre of gravity; everything below works in centred coordinates d
    centres = np.add.reduceat(P, off, axis=0) / n[:, None]
    d = P - centres[seg]
    dx, dy = d[:, 0], d[:, 1]

    # vector of medians (feature 3): sort each coordinate within its segment
    lo = off + (sizes - 1) // 2
    hi = off + sizes // 2
    vals = _sorted_within(P, seg, m)
    med = (0.5 * (vals[:, lo] + vals[:, hi])).T

    # all per-point sums in one reduceat
    terms = np.empty((k, 7))
    np.multiply(dx, dx, out=terms[:, 0])
    np.multiply(dy, dy, out=terms[:, 1])
    np.multiply(dx, dy, out=terms[:, 2])
    z = terms[:, 0] + terms[:, 1]
    np.multiply(dx, z, out=terms[:, 3])
    np.multiply(dy, z, out=terms[:, 4])
    terms[:, 5] = z
    dm = P - med[seg]
    terms[:, 6] = np.hypot(dm[:, 0], dm[:, 1])
    sums = np.add.reduceat(terms, off, axis=0)
    sxx, syy, sxy, sxz, syz, sz, sdev = sums.T

    # 2: standard deviation; 3: mean deviation from the vector of medians
    out[:, 1] = np.where(n > 1, np.sqrt((sxx + syy) / (n - 1.0)), 0.0)
    out[:, 2] = sdev / n

    # 4, 5, 6: jump distances and width
    first = P[off]
    last = P[off + sizes - 1]
    out[:, 5] = np.hypot(last[:, 0] - first[:, 0], last[:, 1] - first[:, 1])
    gap = np.hypot(first[1:, 0] - last[:-1, 0], first[1:, 1] - last[:-1, 1])
    out[1:, 3] = gap
    out[:-1, 4] = gap
    if full_circle and m > 1:
        closing = float(np.hypot(*(first[0] - last[-1])))
        out[0, 3] = closing
        out[-1, 4] = closing
    else:
        out[0, 3] = params.no_neighbour_jump
        out[-1, 4] = params.no_neighbour_jump

    # 7: linearity, residual of the Hessian (alpha, r) line fit; r passes the centroid
    alpha = 0.5 * np.arctan2(-2.0 * sxy, syy - sxx)
    ca, sa = np.cos(alpha), np.sin(alpha)
    out[:, 6] = np.maximum(sxx * ca * ca + 2.0 * sxy * ca * sa + syy * sa * sa, 0.0)

    # 8, 9: algebraic circle fit; centred normal equations reduce to a 2x2 system
    det = sxx * syy - sxy * sxy
    scale = (sxx + syy) ** 2
    has_circle = (n >= MIN_POINTS) & (det > 1e-12 * scale) & (scale > 0.0)
    safe = np.where(has_circle, 2.0 * det, 1.0)
    xc = np.where(has_circle, (syy * sxz - sxy * syz) / safe, 0.0)
    yc = np.where(has_circle, (sxx * syz - sxy * sxz) / safe, 0.0)
    rc = np.sqrt(xc * xc + yc * yc + sz / n)
    resid = rc[seg] - np.hypot(dx - xc[seg], dy - yc[seg])
    sc = np.add.reduceat(resid * resid, off)
    out[:, 7] = np.where(has_circle, sc, out[:, 6])
    out[:, 8] = np.where(has_circle, rc, params.no_circle_radius)
    circle_centres = np.where(has_circle[:, None], centres + np.stack([xc, yc], axis=1), np.nan)

    # 10, 11: boundary length and regularity (steps across segment borders weigh 0)
    if k > 1:
        step_vec = P[1:] - P[:-1]
        steps = np.hypot(step_vec[:, 0], step_vec[:, 1])
        step_seg = seg[1:]
        inner = (step_seg == seg[:-1]).astype(np.float64)
        length = np.bincount(step_seg, weights=steps * inner, minlength=m)
        out[:, 9] = length
        mean_step = np.where(n > 1, length / (n - 1.0), 0.0)
        dev = (steps - mean_step[step_seg]) ** 2 * inner
        ss = np.bincount(step_seg, weights=dev, minlength=m)
        out[:, 10] = np.where(n >= MIN_POINTS, np.sqrt(ss / (n - 2.0)), 0.0)

        # 12, 13: curvature 4A/(dA dB dC) and signed turning angle at interior points
        if k > 2:
            v1, v2 = step_vec[:-1], step_vec[1:]
            tri_seg = seg[1:-1]
            mid = inner[:-1] * inner[1:]
            cross = v1[:, 0] * v2[:, 1] - v1[:, 1] * v2[:, 0]
            dot = v1[:, 0] * v2[:, 0] + v1[:, 1] * v2[:, 1]
            dac = np.hypot(v1[:, 0] + v2[:, 0], v1[:, 1] + v2[:, 1])
            prod = steps[:-1] * steps[1:] * dac
            kappa = np.where(prod > 0.0, 2.0 * np.abs(cross) / prod, 0.0)  # 4 * |cross| / 2
            beta = np.arctan2(cross, dot) * (mid * np.sign(scan.angle_increment))
            n_inner = np.maximum(n - 2.0, 1.0)
            out[:, 11] = np.bincount(tri_seg, weights=kappa * mid, minlength=m) / n_inner
            out[:, 12] = np.bincount(tri_seg, weights=beta, minlength=m) / n_inner

    # 14: mean speed along the beams, against the same beams of the previous scan
    max_motion = np.zeros(m)
    if _usable_previous(scan, previous):
        assert previous is not None
        beams = table.beams
        both = previous.valid[beams]
        delta = np.where(both, scan.ranges[beams] - previous.ranges[beams], 0.0)
        counts = np.bincount(seg, weights=both.astype(np.float64), minlength=m)
        dt = scan.stamp - previous.stamp
        total = np.bincount(seg, weights=delta, minlength=m)
        out[:, 13] = np.where(counts > 0, total / np.maximum(counts, 1.0) / dt, 0.0)
        max_motion = np.maximum.reduceat(np.abs(delta), off)
    return SegmentFeatures(out, max_motion, centres, circle_centres)


def _sorted_within(P: FloatArray, seg: NDArray[np.int64], m: int) -> FloatArray:
    """Both coordinates of the points P (K, 2), sorted within each of the ``m`` segments
    ``seg`` (K,) (non-decreasing): (2, K), one sort for both instead of a two-key sort per
    coordinate. The sort key puts each segment and coordinate in its own interval
    (coordinate + its interval's start, a multiple of a span wider than all coordinates);
    rounding the sum cannot reorder two values of one interval, only tie two that differ
    in their last bits, whose order then does not matter to a median beyond those bits;
    the values returned are the coordinates themselves."""
    span = 2.0 * float(np.abs(P).max()) + 1.0
    keys = P.T + (np.arange(2)[:, None] * m + seg[None, :]) * span
    order = np.argsort(keys.ravel(), kind="stable")
    return P.T.ravel()[order].reshape(2, -1)


def _usable_previous(scan: Scan, previous: Scan | None) -> bool:
    return (
        previous is not None
        and previous.n_beams == scan.n_beams
        and previous.angle_min == scan.angle_min
        and previous.angle_increment == scan.angle_increment
        and previous.stamp < scan.stamp
    )
