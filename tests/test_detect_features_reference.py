"""The vectorised features (all segments of a scan at once) against an independent
computation, one segment at a time in plain Python floats from the definitions of 000
Sec. 2.2, on the real demo bag and on simulated scans.

The reference takes other routes where the definitions allow: the linearity as the
smallest eigenvalue of the scatter matrix (the residual of the best line), the circle by
least squares on ``x^2 + y^2 + D x + E y + F = 0`` (numpy's lstsq), the medians by
``statistics.median``, every sum in point order. Values agree within 1e-9 (absolute, on
metres and radians) or 1e-9 relative; the circle of a nearly straight segment (whose
radius the rounding of either route moves: scatter determinant below 1e-6 of its scale)
is left out of features 8 and 9, and so are segments the two routes call circular and
straight differently.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pytest

from laserpeople.detection.features import DEFAULT_FEATURE_PARAMS, compute_features
from laserpeople.scan import Scan
from laserpeople.segmentation import JumpDistanceSegmenter, covers_full_circle

TOL = 1e-9
WELL_CONDITIONED = 1e-6
"""Scatter determinant over (trace)^2 above which a segment's circle is compared."""

DEMO = "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag"


def _segment_features(
    pts: Sequence[tuple[float, float]],
    beams: Sequence[int],
    prev_last: tuple[float, float] | None,
    next_first: tuple[float, float] | None,
    scan: Scan,
    previous: Scan | None,
) -> tuple[list[float], bool]:
    """Features 1..14 of one segment, and whether its circle is well conditioned."""
    n = len(pts)
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    mx, my = sum(xs) / n, sum(ys) / n
    cx, cy = [x - mx for x in xs], [y - my for y in ys]
    sxx = sum(x * x for x in cx)
    syy = sum(y * y for y in cy)
    sxy = sum(x * y for x, y in zip(cx, cy, strict=True))
    f = [0.0] * 14
    f[0] = float(n)
    f[1] = math.sqrt((sxx + syy) / (n - 1)) if n > 1 else 0.0
    medx, medy = statistics.median(xs), statistics.median(ys)
    f[2] = sum(math.hypot(x - medx, y - medy) for x, y in pts) / n
    far = DEFAULT_FEATURE_PARAMS.no_neighbour_jump
    f[3] = math.dist(pts[0], prev_last) if prev_last is not None else far
    f[4] = math.dist(pts[-1], next_first) if next_first is not None else far
    f[5] = math.dist(pts[0], pts[-1])
    # 7: residual of the best line = smallest eigenvalue of the scatter matrix
    half = 0.5 * (sxx + syy)
    f[6] = max(half - math.sqrt(0.25 * (sxx - syy) ** 2 + sxy * sxy), 0.0)
    # 8, 9: algebraic circle by least squares (centred coordinates)
    det, scale = sxx * syy - sxy * sxy, (sxx + syy) ** 2
    circle = n >= 3 and scale > 0.0 and det > 1e-12 * scale
    well = not (n >= 3 and scale > 0.0) or abs(det - 1e-12 * scale) > WELL_CONDITIONED * scale
    if circle:
        a = np.column_stack([cx, cy, np.ones(n)])
        b = -(np.array(cx) ** 2 + np.array(cy) ** 2)
        d, e, g = np.linalg.lstsq(a, b, rcond=None)[0]
        xc, yc = -0.5 * d, -0.5 * e
        r = math.sqrt(xc * xc + yc * yc - g)
        f[7] = sum((r - math.hypot(x - xc, y - yc)) ** 2 for x, y in zip(cx, cy, strict=True))
        f[8] = r
    else:
        f[7] = f[6]
        f[8] = DEFAULT_FEATURE_PARAMS.no_circle_radius
    # 10, 11: boundary length and sample standard deviation of the steps
    steps = [math.dist(pts[i], pts[i + 1]) for i in range(n - 1)]
    f[9] = sum(steps)
    if n >= 3:
        mean = f[9] / (n - 1)
        f[10] = math.sqrt(sum((s - mean) ** 2 for s in steps) / (n - 2))
    # 12, 13: curvature 4A / (dA dB dC) and signed turning angle at interior points
    if n >= 3:
        kappa, turn = 0.0, 0.0
        for i in range(1, n - 1):
            (x0, y0), (x1, y1), (x2, y2) = pts[i - 1], pts[i], pts[i + 1]
            ux, uy, vx, vy = x1 - x0, y1 - y0, x2 - x1, y2 - y1
            cross = ux * vy - uy * vx
            area = 0.5 * abs(cross)
            sides = math.hypot(ux, uy) * math.hypot(vx, vy) * math.hypot(x2 - x0, y2 - y0)
            kappa += 4.0 * area / sides if sides > 0 else 0.0
            turn += math.atan2(cross, ux * vx + uy * vy)
        f[11] = kappa / (n - 2)
        f[12] = math.copysign(1.0, scan.angle_increment) * turn / (n - 2)
    # 14: mean range change per second over the beams valid in both scans
    if previous is not None and previous.n_beams == scan.n_beams and previous.stamp < scan.stamp:
        changes = [float(scan.ranges[b] - previous.ranges[b]) for b in beams if previous.valid[b]]
        if changes:
            f[13] = sum(changes) / len(changes) / (scan.stamp - previous.stamp)
    return f, well


def _compare(scans: list[Scan]) -> int:
    """Compare every segment of every scan; the number of segments compared."""
    segmenter = JumpDistanceSegmenter()
    previous: Scan | None = None
    done = 0
    for scan in scans:
        table = segmenter(scan)
        got = compute_features(table, scan, previous, full_circle=covers_full_circle(scan)).values
        full = covers_full_circle(scan) and len(table) > 1
        pts = table.points.tolist()
        beams = (table.beams % table.n_beams).tolist()
        off = table.offsets.tolist()
        m = len(table)
        for i in range(m):
            a, b = off[i], off[i + 1]
            prev_last = pts[off[i] - 1] if i > 0 else (pts[-1] if full else None)
            next_first = pts[off[i + 1]] if i < m - 1 else (pts[0] if full else None)
            want, well = _segment_features(
                [tuple(p) for p in pts[a:b]], beams[a:b], prev_last, next_first, scan, previous
            )
            cols = [c for c in range(14) if well or c not in (7, 8)]
            np.testing.assert_allclose(
                got[i, cols],
                np.array(want)[cols],
                rtol=TOL,
                atol=TOL,
                err_msg=f"scan {scan.index} segment {i} ({b - a} points), columns {cols}",
            )
            done += 1
        previous = scan
    return done


def test_features_match_the_reference_on_the_real_demo_bag(shared_data: Path) -> None:
    from laserpeople.io import open_recording

    rec = open_recording(shared_data / DEMO)
    try:
        scans = [s for _, s in zip(range(150), rec.scans(), strict=False)]
    finally:
        rec.close()
    assert _compare(scans) > 1000


@pytest.mark.parametrize("name", ["crossing-3", "entrance-hall"])
def test_features_match_the_reference_on_simulated_scans(name: str) -> None:
    from laserpeople.sim import run_scenario

    scans = run_scenario(name, seconds=3.0, seed=3).scans
    first = scans[0].sensor
    assert _compare([s for s in scans if s.sensor == first][:20]) > 20


def test_the_reference_tells_a_wrong_feature() -> None:
    """A feature off by a part in a million is caught (the comparison is not vacuous)."""
    rng = np.random.default_rng(2)
    ranges = np.repeat(rng.uniform(1.0, 4.0, 30), 6) + rng.normal(0.0, 0.01, 180)
    scan = Scan(0.0, -1.5, 0.0174, ranges, index=0)
    table = JumpDistanceSegmenter()(scan)
    got = compute_features(table, scan).values
    pts = table.points.tolist()
    a, b = int(table.offsets[0]), int(table.offsets[1])
    want, _ = _segment_features(
        [tuple(p) for p in pts[a:b]], list(range(a, b)), None, tuple(pts[b]), scan, None
    )
    np.testing.assert_allclose(got[0], want, rtol=TOL, atol=TOL)
    with pytest.raises(AssertionError):
        np.testing.assert_allclose(got[0] * (1 + 1e-6), want, rtol=TOL, atol=TOL)
