"""The fourteen segment features of 000 Sec. 2.2, vectorised over all segments of a scan.

Every feature is computed for every segment at once from the flat arrays of a
:class:`~laserpeople.segmentation.SegmentTable` (segment ids + ``np.bincount`` /
``np.add.reduceat``); no Python loop runs over segments. Where the optional C extension is
built (:mod:`~laserpeople.detection.compiled`) it computes the same floats, every operation
in the same order. Features are returned as a matrix (M, 14) whose column ``j - 1`` is
feature ``j`` of the paper:

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
  increasing beam *angle*, so a scanner with negative ``angle_increment`` gives the same value;
  so are features 4 and 5: the preceding segment is the one at smaller angles (for such a
  scanner, the next in beam order), so that the features of a segment do not depend on the
  direction the scanner sweeps.
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

from collections.abc import Sequence
from dataclasses import dataclass
from types import ModuleType

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.detection import compiled
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
DEFERRED = (2, 7)
"""Columns of the features (3, the mean distance to the vector of medians, and 8, the
circularity) that :func:`compute_features_deferred` may leave for :meth:`Deferred.complete`:
each costs a pass over the points (a median and a ``hypot`` per point)."""

_extension = compiled.EXTENSION
"""The C extension computing :func:`_compute`'s features (the same floats), or None: the
Python reference runs (:mod:`~laserpeople.detection.compiled`)."""


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
    return compute_features_many([table], [scan], [previous], params, [full_circle])[0]


def compute_features_many(
    tables: Sequence[SegmentTable],
    scans: Sequence[Scan],
    previous: Sequence[Scan | None],
    params: FeatureParams = DEFAULT_FEATURE_PARAMS,
    full_circle: Sequence[bool] | None = None,
) -> list[SegmentFeatures]:
    """:func:`compute_features` of several scans at once (each with its table, previous
    scan and ``full_circle`` flag; all False when None): the same values, with the fixed
    cost of the whole-scan array operations paid once for all of them."""
    if not tables:
        return []
    every = compute_features_joined(tables, scans, previous, params, full_circle)
    if len(tables) == 1:
        return [every]
    return split_features(every, [len(t) for t in tables])


def split_features(every: SegmentFeatures, counts: Sequence[int]) -> list[SegmentFeatures]:
    """``every`` cut into consecutive parts of ``counts`` segments (views of its rows)."""
    out = []
    start = 0
    for m in counts:
        sl = slice(start, start + m)
        out.append(
            SegmentFeatures(
                every.values[sl],
                every.max_beam_motion[sl],
                every.centres[sl],
                every.circle_centres[sl],
            )
        )
        start += m
    return out


def compute_features_joined(
    tables: Sequence[SegmentTable],
    scans: Sequence[Scan],
    previous: Sequence[Scan | None],
    params: FeatureParams = DEFAULT_FEATURE_PARAMS,
    full_circle: Sequence[bool] | None = None,
    joined: tuple[FloatArray, NDArray[np.int64]] | None = None,
) -> SegmentFeatures:
    """The features of :func:`compute_features_many` as one (the tables' rows one after the
    other); ``joined``: the tables' points (K, 2) and offsets (M + 1,) as one, when the
    caller has them (a :class:`~laserpeople.segmentation.SegmentBlock`'s)."""
    flags = [False] * len(scans) if full_circle is None else list(full_circle)
    if joined is None:
        joined = _joined(tables)
    if joined[1].size == 1:
        return SegmentFeatures(
            np.empty((0, N_FEATURES)), np.empty(0), np.empty((0, 2)), np.empty((0, 2))
        )
    if _extension is not None:
        return _compute_compiled(_extension, tables, scans, previous, params, flags, joined)[0]
    with np.errstate(divide="ignore", invalid="ignore"):
        return _compute(tables, scans, previous, params, flags, joined)


@dataclass(frozen=True, eq=False)
class Deferred:
    """Features of a block with the columns :data:`DEFERRED` possibly left NaN (compiled
    path) until :meth:`complete` fills them for the segments that need them.

    Attributes:
        features: The features; the other columns and arrays are final.
    """

    features: SegmentFeatures
    _rest: tuple[FloatArray, NDArray[np.int64], FloatArray] | None = None
    """Points, offsets and centred moments for the extension's ``complete``; None: every
    column is computed already."""

    def complete(self, rows: NDArray[np.int64]) -> None:
        """Fill the deferred columns of the segments ``rows`` (the same floats as
        :func:`compute_features_joined`'s); the other rows keep NaN there."""
        if self._rest is None or rows.size == 0 or _extension is None:
            return
        points, offsets, work = self._rest
        _extension.complete(
            points,
            offsets,
            np.ascontiguousarray(rows, dtype=np.int64),
            self.features.centres,
            work,
            self.features.values,
        )


def compute_features_deferred(
    tables: Sequence[SegmentTable],
    scans: Sequence[Scan],
    previous: Sequence[Scan | None],
    params: FeatureParams,
    full_circle: Sequence[bool],
    joined: tuple[FloatArray, NDArray[np.int64]],
) -> Deferred:
    """:func:`compute_features_joined`, the columns :data:`DEFERRED` left NaN where the
    extension computes them (its ``complete`` fills them later, for the segments whose
    score can matter); the Python reference computes them all at once."""
    if joined[1].size == 1 or _extension is None:
        return Deferred(
            compute_features_joined(tables, scans, previous, params, full_circle, joined)
        )
    features, work = _compute_compiled(
        _extension, tables, scans, previous, params, full_circle, joined, defer=True
    )
    points, offsets = joined
    return Deferred(
        features,
        (
            np.ascontiguousarray(points, dtype=np.float64),
            np.ascontiguousarray(offsets, dtype=np.int64),
            work,
        ),
    )


def _joined(tables: Sequence[SegmentTable]) -> tuple[FloatArray, NDArray[np.int64]]:
    """Points (K, 2) and offsets (M + 1,) of several tables as one."""
    if len(tables) == 1:
        return tables[0].points, tables[0].offsets
    points = np.concatenate([t.points for t in tables])
    sizes = np.concatenate([np.diff(t.offsets) for t in tables])
    offsets = np.zeros(sizes.size + 1, dtype=np.int64)
    np.cumsum(sizes, out=offsets[1:])
    return points, offsets


def _compute(
    tables: Sequence[SegmentTable],
    scans: Sequence[Scan],
    previous: Sequence[Scan | None],
    params: FeatureParams,
    full_circle: Sequence[bool],
    joined: tuple[FloatArray, NDArray[np.int64]] | None = None,
) -> SegmentFeatures:
    """All features of the segments of ``tables`` (at least one segment in all; ``joined``
    their points and offsets as one, if at hand), in three
    passes over the points, each a few reductions of (K, C) matrices of per-point terms:
    (1) centres; boundary steps, curvature, turning angles and the beams' range changes;
    (2) the centred moments and distances to the vector of medians; the steps' deviations
    from their mean; (3) the circle residuals. A per-point term is 0 where it does not
    apply (the step into a segment's first point, curvature and angle at its end points),
    so each segment's sum is its own, whichever scan it belongs to.

    Every value is computed by the same floating-point operations in the same order as a
    computation feature by feature and scan by scan would (``np.add.reduceat``'s pairwise
    sums for the moments, residuals and centres; sums in point order for the steps,
    curvature, angles and range changes, as ``np.bincount`` adds; the medians of the
    coordinates themselves, sorted within their segments, see :func:`_sorted_within`):
    features that are zero but for rounding (the circularity of three points,
    the regularity of evenly spaced points) then keep their rounding, and the stumps whose
    thresholds lie at that level decide the same."""
    P, offsets = _joined(tables) if joined is None else joined
    m = offsets.size - 1
    k = P.shape[0]
    off = offsets[:-1]
    sizes = offsets[1:] - off
    n = sizes.astype(np.float64)
    seg = np.repeat(np.arange(m), sizes)
    px, py = P[:, 0], P[:, 1]
    usable = [_usable_previous(s, p) for s, p in zip(scans, previous, strict=True)]
    speed = any(usable)

    # pass 1: centres; step from the previous point, curvature, turning angle, [valid in
    # both scans, range change], summed in point order
    centres = np.add.reduceat(P, off, axis=0) / n[:, None]
    c1 = 5 if speed else 3
    t1 = np.zeros((k, c1))
    starts = np.zeros(k, dtype=bool)
    starts[off] = True
    steps = np.zeros(0)
    if k > 1:
        vx = px[1:] - px[:-1]
        vy = py[1:] - py[:-1]
        steps = np.hypot(vx, vy)
        t1[1:, 0] = steps
        t1[off, 0] = 0.0
        if k > 2:
            # 12, 13 at interior points: curvature 4A/(dA dB dC), signed turning angle
            v1x, v1y, v2x, v2y = vx[:-1], vy[:-1], vx[1:], vy[1:]
            cross = v1x * v2y - v1y * v2x
            dot = v1x * v2x + v1y * v2y
            prod = steps[:-1] * steps[1:] * np.hypot(v1x + v2x, v1y + v2y)
            mid = ~(starts[1:-1] | starts[2:])
            # (2 |cross| / prod: 4 A with A = |cross| / 2)
            t1[1:-1, 1] = np.where(mid & (prod > 0.0), 2.0 * np.abs(cross) / prod, 0.0)
            t1[1:-1, 2] = np.where(mid, np.arctan2(cross, dot), 0.0)
    delta = np.zeros(k)
    dt = np.ones(m)
    if speed:
        _beam_changes(tables, scans, previous, usable, delta, t1[:, 3], dt)
        t1[:, 4] = delta
    s1 = _sums_in_order(seg, t1, m)
    length = s1[:, 0]

    # vector of medians (feature 3): sort each coordinate within its segment
    lo = off + (sizes - 1) // 2
    hi = off + sizes // 2
    vals = _sorted_within(P, seg, m)
    med = 0.5 * (vals[:, lo] + vals[:, hi])  # (2, M)

    # pass 2: centred moments and distances to the medians (pairwise sums); squared
    # deviations of the steps from their mean (in point order)
    dx = px - centres[seg, 0]
    dy = py - centres[seg, 1]
    t2 = np.empty((k, 7))
    xx, yy = t2[:, 0], t2[:, 1]
    np.multiply(dx, dx, out=xx)
    np.multiply(dy, dy, out=yy)
    np.multiply(dx, dy, out=t2[:, 2])
    z = t2[:, 5]
    np.add(xx, yy, out=z)
    np.multiply(dx, z, out=t2[:, 3])
    np.multiply(dy, z, out=t2[:, 4])
    t2[:, 6] = np.hypot(px - med[0, seg], py - med[1, seg])
    sxx, syy, sxy, sxz, syz, sz, sdev = np.add.reduceat(t2, off, axis=0).T
    mean_step = np.where(n > 1, length / (n - 1.0), 0.0)
    dev = np.zeros(k)
    if k > 1:
        np.subtract(steps, mean_step[seg[1:]], out=dev[1:])
        np.multiply(dev, dev, out=dev)
        dev[off] = 0.0
    ss = np.bincount(seg, weights=dev, minlength=m)

    out = np.empty((m, N_FEATURES))
    out[:, 0] = n
    # 2: standard deviation; 3: mean deviation from the vector of medians
    out[:, 1] = np.sqrt((sxx + syy) / (n - 1.0))
    out[n <= 1, 1] = 0.0
    out[:, 2] = sdev / n

    # 4, 5, 6: jump distances and width
    fx, fy = px[off], py[off]
    ends = offsets[1:] - 1
    lx, ly = px[ends], py[ends]
    out[:, 5] = np.hypot(lx - fx, ly - fy)
    gap = np.hypot(fx[1:] - lx[:-1], fy[1:] - ly[:-1])
    out[1:, 3] = gap
    out[:-1, 4] = gap
    first = 0
    for table, circle in zip(tables, full_circle, strict=True):
        count = len(table)
        if count == 0:
            continue
        last = first + count - 1
        if circle and count > 1:
            closing = float(np.hypot(fx[first] - lx[last], fy[first] - ly[last]))
            out[first, 3] = closing
            out[last, 4] = closing
        else:
            out[first, 3] = params.no_neighbour_jump
            out[last, 4] = params.no_neighbour_jump
        first += count

    # 7: linearity, residual of the Hessian (alpha, r) line fit; r passes the centroid
    alpha = 0.5 * np.arctan2(-2.0 * sxy, syy - sxx)
    ca, sa = np.cos(alpha), np.sin(alpha)
    linearity = np.maximum(sxx * ca * ca + 2.0 * sxy * ca * sa + syy * sa * sa, 0.0)
    out[:, 6] = linearity

    # 8, 9: algebraic circle fit; centred normal equations reduce to a 2x2 system
    det = sxx * syy - sxy * sxy
    scale = (sxx + syy) ** 2
    has_circle = (n >= MIN_POINTS) & (det > 1e-12 * scale) & (scale > 0.0)
    no_circle = ~has_circle
    safe = 2.0 * det
    safe[no_circle] = 1.0
    xc = (syy * sxz - sxy * syz) / safe
    yc = (sxx * syz - sxy * sxz) / safe
    xc[no_circle] = 0.0
    yc[no_circle] = 0.0
    rc = np.sqrt(xc * xc + yc * yc + sz / n)
    resid = rc[seg] - np.hypot(dx - xc[seg], dy - yc[seg])
    sc = np.add.reduceat(resid * resid, off)
    out[:, 7] = np.where(has_circle, sc, linearity)
    out[:, 8] = np.where(has_circle, rc, params.no_circle_radius)
    circle_centres = np.empty((m, 2))
    np.add(centres[:, 0], xc, out=circle_centres[:, 0])
    np.add(centres[:, 1], yc, out=circle_centres[:, 1])
    circle_centres[no_circle] = np.nan

    # 10, 11: boundary length and regularity (sample standard deviation of the steps)
    out[:, 9] = length
    out[:, 10] = np.sqrt(ss / (n - 2.0))
    out[n < MIN_POINTS, 10] = 0.0

    # 12, 13: means over the n - 2 interior points (13 traversed by increasing angle)
    n_inner = np.maximum(n - 2.0, 1.0)
    out[:, 11] = s1[:, 1] / n_inner
    out[:, 12] = s1[:, 2] / n_inner
    first = 0
    for table, scan in zip(tables, scans, strict=True):
        if scan.angle_increment < 0.0:  # 4, 5 and 13 by increasing angle, as for the others
            rows = slice(first, first + len(table))
            out[rows, 12] *= -1.0
            out[rows, 3:5] = out[rows, 4:2:-1].copy()
        first += len(table)

    # 14: mean speed along the beams, against the same beams of the previous scan (0 for
    # the segments of a scan without a usable previous one: no beam counts there)
    if speed:
        counts, total = s1[:, 3], s1[:, 4]
        out[:, 13] = np.where(counts > 0, total / np.maximum(counts, 1.0) / dt, 0.0)
        max_motion = np.maximum.reduceat(np.abs(delta), off)
    else:
        out[:, 13] = 0.0
        max_motion = np.zeros(m)
    return SegmentFeatures(out, max_motion, centres, circle_centres)


def _beam_changes(
    tables: Sequence[SegmentTable],
    scans: Sequence[Scan],
    previous: Sequence[Scan | None],
    usable: Sequence[bool],
    delta: FloatArray,
    both: FloatArray,
    dt: FloatArray,
) -> None:
    """Fill, for feature 14, every segment point's range change [m] since the same beam of
    the previous scan ``delta`` (K,) and whether that beam is valid in both ``both`` (K,)
    (1.0 or left as it is), and each segment's time since the previous scan ``dt`` (M,)
    [s], for the scans with a ``usable`` previous one (left as they are for the others)."""
    at = seg_at = 0
    for table, scan, prev, ok in zip(tables, scans, previous, usable, strict=True):
        size, count = table.beams.size, len(table)
        if ok and size:
            assert prev is not None
            beams = table.beams
            valid = prev.valid[beams]
            delta[at : at + size] = np.where(valid, scan.ranges[beams] - prev.ranges[beams], 0.0)
            both[at : at + size] = valid
            dt[seg_at : seg_at + count] = scan.stamp - prev.stamp
        at += size
        seg_at += count


def _compute_compiled(
    ext: ModuleType,
    tables: Sequence[SegmentTable],
    scans: Sequence[Scan],
    previous: Sequence[Scan | None],
    params: FeatureParams,
    full_circle: Sequence[bool],
    joined: tuple[FloatArray, NDArray[np.int64]] | None = None,
    *,
    defer: bool = False,
) -> tuple[SegmentFeatures, FloatArray]:
    """:func:`_compute` by the C extension ``_cfeatures``: the same floats, the same
    operations in the same order (see ``_cfeatures.c``), in two calls for all segments of
    the block; numpy's ``arctan2`` between them, as :func:`_compute` takes it. Also the
    segments' centred moments (M, 6); with ``defer``, the columns :data:`DEFERRED` are
    left NaN (see :class:`Deferred`)."""
    P, offsets = _joined(tables) if joined is None else joined
    P = np.ascontiguousarray(P, dtype=np.float64)
    offsets = np.ascontiguousarray(offsets, dtype=np.int64)
    m = offsets.size - 1
    k = P.shape[0]
    counts = [len(t) for t in tables]
    bounds = np.zeros(len(tables) + 1, dtype=np.int64)
    np.cumsum(counts, out=bounds[1:])
    changes = None  # (_beam_changes's, in C)
    usable = [_usable_previous(s, p) for s, p in zip(scans, previous, strict=True)]
    if any(usable):
        changes = [
            (
                np.ascontiguousarray(table.beams, dtype=np.int64),
                np.ascontiguousarray(scan.ranges, dtype=np.float64),
                np.ascontiguousarray(prev.ranges, dtype=np.float64),
                np.ascontiguousarray(prev.valid, dtype=np.bool_),
                scan.stamp - prev.stamp,
            )
            if ok and prev is not None and table.beams.size
            else None
            for table, scan, prev, ok in zip(tables, scans, previous, usable, strict=True)
        ]
    out = np.empty((m, N_FEATURES))
    centres = np.empty((m, 2))
    max_motion = np.empty(m)
    work = np.empty((m, 6))
    ys = np.empty(k + m)
    xs = np.empty(k + m)
    circle = np.array(full_circle, dtype=np.int64)
    t = ext.pass1(
        P, offsets, bounds, circle, changes, float(params.no_neighbour_jump), out, centres,
        max_motion, work, ys, xs, defer,
    )  # fmt: skip
    angles = np.arctan2(ys[: t + m], xs[: t + m])
    flip = np.array([scan.angle_increment < 0.0 for scan in scans], dtype=np.int64)
    circle_centres = np.empty((m, 2))
    ext.pass2(
        P, offsets, bounds, flip, angles, float(params.no_circle_radius), out, centres, work,
        circle_centres, defer,
    )  # fmt: skip
    return SegmentFeatures(out, max_motion, centres, circle_centres), work


def _sums_in_order(seg: NDArray[np.int64], terms: FloatArray, m: int) -> FloatArray:
    """Per-segment sums (M, C) of the per-point ``terms`` (K, C) of the segments ``seg``
    (K,), every one added in point order (one ``np.bincount`` over all columns: its bins
    are (segment, column) pairs, each filled in the order of the points)."""
    c = terms.shape[1]
    bins = (seg[:, None] * c + np.arange(c)).ravel()
    sums = np.bincount(bins, weights=terms.ravel(), minlength=m * c)
    return np.asarray(sums.reshape(m, c), dtype=np.float64)


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
