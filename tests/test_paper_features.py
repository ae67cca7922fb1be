"""The fourteen segment features of 000 Sec. 2.2, each against its definition in the paper
written out here, on values that tell it from its near misses.

Both implementations are checked: the Python reference (``features._compute``) and the
public :func:`compute_features` (the C extension where it is built). Every expected value
is computed by another route than the code's: the median by sorting (000's odd/even rule),
the line fit by minimising 000's residual over the angle, the circle by 000's ``A x = b``
with the pseudo-inverse in raw coordinates, the triangle area of the curvature by Heron's
formula, the turning angles from chord headings. Each test also computes the nearest
wrong formulas (a divisor n instead of n - 1, the lower median, the mean instead of the
median, the largest instead of the smallest residual, ...) and asserts that the segment
used separates them from the right value by far more than the tolerance, so the test
fails on any of them.

Where 000 is ambiguous or silent, the code's documented choice is pinned (see
docs/papers.md): feature 11 is the sample standard deviation, feature 12 the *mean* of
the curvatures over the n - 2 interior points (000 writes ``k = sum k_j`` but calls it the
mean), feature 13 the *signed* turning angle averaged over the interior points, feature 14
averaged over the beams valid in both scans.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from laserpeople.detection import features
from laserpeople.scan import Scan
from laserpeople.segmentation import SegmentTable

TOL = 1e-9
"""Relative (and absolute, on metres, radians and m/s) tolerance of every comparison."""
APART = 1e-4
"""A near miss must differ from the right value by more than this (relative)."""

# three segments: the middle one (6 points, an even count; an irregular arc) is measured
PREV = [(0.40, -0.50), (0.55, -0.45), (0.70, -0.42)]
SEG = [(1.00, 0.20), (1.05, 0.27), (1.13, 0.31), (1.20, 0.29), (1.27, 0.21), (1.28, 0.10)]
NEXT = [(1.90, 0.80), (1.95, 0.90), (2.05, 0.95), (2.10, 1.05)]

Compute = Callable[..., features.SegmentFeatures]


def _python(
    table: SegmentTable, scan: Scan, previous: Scan | None = None
) -> features.SegmentFeatures:
    with np.errstate(divide="ignore", invalid="ignore"):
        return features._compute(
            [table], [scan], [previous], features.DEFAULT_FEATURE_PARAMS, [False]
        )


def _public(
    table: SegmentTable, scan: Scan, previous: Scan | None = None
) -> features.SegmentFeatures:
    return features.compute_features(table, scan, previous)


PATHS = [
    pytest.param(_python, id="python-reference"),
    pytest.param(
        _public,
        id="compute_features",
        marks=pytest.mark.skipif(
            features._extension is None, reason="the C extension is not built (same as python)"
        ),
    ),
]


def _table(segments: Sequence[Sequence[tuple[float, float]]]) -> tuple[SegmentTable, Scan]:
    pts = np.array([p for s in segments for p in s], dtype=np.float64)
    sizes = [len(s) for s in segments]
    offsets = np.concatenate(([0], np.cumsum(sizes))).astype(np.int64)
    n = pts.shape[0]
    table = SegmentTable(np.arange(n, dtype=np.int64), pts, offsets, n)
    return table, Scan(0.0, -1.0, 0.01, np.hypot(pts[:, 0], pts[:, 1]))


def _middle(compute: Compute) -> np.ndarray:
    table, scan = _table([PREV, SEG, NEXT])
    return compute(table, scan).values[1]


def _close(got: float, want: float, tol: float = TOL) -> None:
    assert got == pytest.approx(want, rel=tol, abs=tol)


def _apart(want: float, *near_misses: float) -> None:
    """The test values tell ``want`` from each near miss."""
    for miss in near_misses:
        assert abs(miss - want) > APART * max(abs(want), 1e-3), (want, miss)


def _median(values: Sequence[float]) -> float:
    """000 Sec. 2.2, feature 3: x_((K+1)/2) for odd K, (x_(K/2) + x_(K/2+1)) / 2 for even."""
    x = sorted(values)
    k = len(x)
    if k % 2:
        return x[(k + 1) // 2 - 1]
    return 0.5 * (x[k // 2 - 1] + x[k // 2])


def _lower_median(values: Sequence[float]) -> float:
    x = sorted(values)
    return x[(len(x) - 1) // 2]


@pytest.mark.parametrize("compute", PATHS)
def test_features_1_2_3_count_deviation_and_deviation_from_the_vector_of_medians(
    compute: Compute,
) -> None:
    f = _middle(compute)
    p = np.array(SEG)
    n = len(SEG)
    assert f[0] == n
    sq = float(((p - p.mean(axis=0)) ** 2).sum())
    sigma = math.sqrt(sq / (n - 1))
    _apart(sigma, math.sqrt(sq / n))
    _close(f[1], sigma)
    med = (_median(p[:, 0].tolist()), _median(p[:, 1].tolist()))
    dev = sum(math.dist(q, med) for q in SEG) / n
    lower = (_lower_median(p[:, 0].tolist()), _lower_median(p[:, 1].tolist()))
    _apart(
        dev,
        sum(math.dist(q, lower) for q in SEG) / n,  # the lower median of an even count
        sum(math.dist(q, p.mean(axis=0)) for q in SEG) / n,  # the mean, not the median
        sum(math.dist(q, med) for q in SEG) / (n - 1),
    )
    _close(f[2], dev)


@pytest.mark.parametrize("compute", PATHS)
def test_odd_count_median_is_the_middle_value(compute: Compute) -> None:
    odd = SEG[:5]
    table, scan = _table([PREV, odd, NEXT])
    f = compute(table, scan).values[1]
    p = np.array(odd)
    med = (_median(p[:, 0].tolist()), _median(p[:, 1].tolist()))
    _close(f[2], sum(math.dist(q, med) for q in odd) / len(odd))


@pytest.mark.parametrize("compute", PATHS)
def test_features_4_5_6_jump_distances_and_width(compute: Compute) -> None:
    f = _middle(compute)
    before = math.dist(SEG[0], PREV[-1])  # first point of S_i, last of S_i-1
    after = math.dist(SEG[-1], NEXT[0])  # last point of S_i, first of S_i+1
    _apart(before, after, math.dist(SEG[0], PREV[0]))
    _close(f[3], before)
    _close(f[4], after)
    width = math.dist(SEG[0], SEG[-1])
    _apart(width, math.dist(SEG[0], SEG[-2]))
    _close(f[5], width)


def _line_residual(alpha: float, p: np.ndarray) -> float:
    """000 feature 7: sum (x cos a + y sin a - r)^2 with the best r for this alpha (the
    Hessian line through the centroid, which minimises over r)."""
    c, s = math.cos(alpha), math.sin(alpha)
    r = float(p[:, 0].mean() * c + p[:, 1].mean() * s)
    return float(((p[:, 0] * c + p[:, 1] * s - r) ** 2).sum())


@pytest.mark.parametrize("compute", PATHS)
def test_feature_7_linearity_is_the_least_residual_of_a_hessian_line(compute: Compute) -> None:
    f = _middle(compute)
    p = np.array(SEG)
    grid = np.linspace(0.0, math.pi, 3601)
    coarse = min(grid, key=lambda a: _line_residual(float(a), p))
    step = grid[1] - grid[0]
    best = minimize_scalar(
        lambda a: _line_residual(a, p),
        bounds=(coarse - step, coarse + step),
        method="bounded",
        options={"xatol": 1e-12},
    )
    s_l = float(best.fun)
    worst = max(_line_residual(float(a), p) for a in grid)  # the normal along the segment
    _apart(s_l, worst, s_l / len(SEG))
    _close(f[6], s_l, 1e-7)


@pytest.mark.parametrize("compute", PATHS)
def test_features_8_9_circle_by_the_papers_pseudo_inverse(compute: Compute) -> None:
    f = _middle(compute)
    p = np.array(SEG)
    x, y = p[:, 0], p[:, 1]
    A = np.column_stack([-2.0 * x, -2.0 * y, np.ones(len(x))])
    b = -(x**2) - y**2
    xc, yc, c = np.linalg.inv(A.T @ A) @ A.T @ b  # x = (A^T A)^-1 A^T b
    rc = math.sqrt(xc * xc + yc * yc - c)  # c = xc^2 + yc^2 - rc^2
    dist = np.hypot(xc - x, yc - y)
    s_c = float(((rc - dist) ** 2).sum())
    _apart(s_c, float(np.abs(rc - dist).sum()), float(((rc**2 - dist**2) ** 2).sum()))
    _apart(rc, math.sqrt(xc * xc + yc * yc + c), float(dist.mean()))
    _close(f[8], rc, 1e-8)
    _close(f[7], s_c, 1e-6)


@pytest.mark.parametrize("compute", PATHS)
def test_features_10_11_boundary_length_and_regularity(compute: Compute) -> None:
    f = _middle(compute)
    d = [math.dist(SEG[j], SEG[j - 1]) for j in range(1, len(SEG))]
    _close(f[9], sum(d))
    mean = sum(d) / len(d)
    sample = math.sqrt(sum((v - mean) ** 2 for v in d) / (len(d) - 1))  # (our choice)
    population = math.sqrt(sum((v - mean) ** 2 for v in d) / len(d))
    _apart(sample, population)
    _close(f[10], sample)


def _heron_curvature(
    a: tuple[float, float], b: tuple[float, float], c: tuple[float, float]
) -> float:
    """000 feature 12: 4 A / (d_A d_B d_C), the area by Heron's formula."""
    da, db, dc = math.dist(b, c), math.dist(a, c), math.dist(a, b)
    s = 0.5 * (da + db + dc)
    area = math.sqrt(max(s * (s - da) * (s - db) * (s - dc), 0.0))
    return 4.0 * area / (da * db * dc)


@pytest.mark.parametrize("compute", PATHS)
def test_feature_12_curvature_is_the_mean_over_the_interior_points(compute: Compute) -> None:
    f = _middle(compute)
    k = [_heron_curvature(SEG[j - 1], SEG[j], SEG[j + 1]) for j in range(1, len(SEG) - 1)]
    mean = sum(k) / len(k)
    # 000's literal sum, half the area factor, the mean over all n points
    _apart(mean, sum(k), 0.5 * mean, sum(k) / len(SEG))
    _close(f[11], mean)


def _heading(a: tuple[float, float], b: tuple[float, float]) -> float:
    return math.atan2(b[1] - a[1], b[0] - a[0])


def _turns(points: Sequence[tuple[float, float]]) -> list[float]:
    """beta_j: the angle from chord x_j-1 x_j to chord x_j x_j+1, unwrapped to (-pi, pi]."""
    out = []
    for j in range(1, len(points) - 1):
        d = _heading(points[j], points[j + 1]) - _heading(points[j - 1], points[j])
        out.append(math.atan2(math.sin(d), math.cos(d)))
    return out


@pytest.mark.parametrize("compute", PATHS)
def test_feature_13_mean_angular_difference_signed_over_the_interior(compute: Compute) -> None:
    # a zig-zag (turns of both signs) tells the signed mean from the mean of |beta|
    zig = [(1.0, 0.0), (1.1, 0.05), (1.2, 0.02), (1.28, 0.1), (1.3, 0.2), (1.25, 0.3)]
    table, scan = _table([PREV, zig, NEXT])
    f = compute(table, scan).values[1]
    beta = _turns(zig)
    assert min(beta) < 0.0 < max(beta)
    mean = sum(beta) / len(beta)
    _apart(mean, sum(abs(b) for b in beta) / len(beta), sum(beta) / (len(zig) - 1), sum(beta))
    _close(f[12], mean)
    # the arc of the middle segment (its near side, as the sensor sees a leg) turns right
    # at every point, traversed by increasing beam angle: clockwise, negative
    g = _middle(compute)
    _close(g[12], sum(_turns(SEG)) / (len(SEG) - 2))
    assert g[12] < 0.0


@pytest.mark.parametrize("compute", PATHS)
def test_feature_14_mean_speed_along_the_beams(compute: Compute) -> None:
    before = np.array([2.0, 1.50, 1.40, np.nan, 1.30, 3.0])
    now = np.array([2.0, 1.45, 1.43, 1.36, 1.20, 3.0])
    prev = Scan(5.00, 0.0, 0.01, before)
    scan = Scan(5.08, 0.0, 0.01, now)
    beams = np.array([1, 2, 3, 4], dtype=np.int64)  # one segment; beam 3 had no return
    pts = np.column_stack([now[beams] * np.cos(0.01 * beams), now[beams] * np.sin(0.01 * beams)])
    table = SegmentTable(beams, pts, np.array([0, 4], dtype=np.int64), 6)
    f = compute(table, scan, prev).values[0]
    dt = 5.08 - 5.00
    v = [(now[j] - before[j]) / dt for j in (1, 2, 4)]  # v_j = (rho_k+1 - rho_k) / dT
    mean = sum(v) / len(v)
    _apart(mean, -mean, sum(v) / 4, sum(v))  # sign, every beam counted, no average
    _close(f[13], mean)
