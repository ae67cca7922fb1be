"""Each of the 14 features of 000 Sec. 2.2 against hand-computed values."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.detection.features import FeatureParams, compute_features
from laserpeople.scan import Scan
from laserpeople.segmentation import SegmentTable, jump_distance_table


def features_of(points: list[tuple[float, float]] | np.ndarray, increment: float = 0.01):
    """Features of one segment made of ``points`` (no previous scan)."""
    pts = np.asarray(points, dtype=np.float64)
    n = pts.shape[0]
    table = jump_distance_table(pts, np.arange(n), n, threshold=1e9)
    scan = Scan(0.0, 0.0, increment, np.ones(n))
    return compute_features(table, scan).values[0]


def test_count_and_standard_deviation_of_a_square() -> None:
    f = features_of([(0, 0), (1, 0), (1, 1), (0, 1)])
    assert f[0] == 4
    # each corner is sqrt(0.5) from the centre: sqrt(4 * 0.5 / 3)
    assert f[1] == pytest.approx(math.sqrt(2.0 / 3.0))


def test_mean_deviation_from_vector_of_medians_odd_and_even() -> None:
    assert features_of([(0, 0), (1, 0), (10, 0)])[2] == pytest.approx(10.0 / 3.0)
    # even count: median x = (1 + 2) / 2
    assert features_of([(0, 0), (1, 0), (2, 0), (10, 0)])[2] == pytest.approx(11.0 / 4.0)
    # vector of medians takes x and y medians independently: (1, 1) here
    f = features_of([(0, 5), (1, 1), (7, 0)])
    expected = (math.hypot(1, 4) + 0 + math.hypot(6, 1)) / 3
    assert f[2] == pytest.approx(expected)


def test_jump_distances_and_width() -> None:
    pts = np.array([(0, 0), (0, 0.05), (0, 0.1), (1, 0.1), (1, 0.15), (1, 0.3)], float)
    table = jump_distance_table(pts, np.arange(6), 6, threshold=0.5)
    assert len(table) == 2
    scan = Scan(0.0, 0.0, 0.01, np.ones(6))
    params = FeatureParams(no_neighbour_jump=42.0)
    f = compute_features(table, scan, params=params).values
    assert f[0, 3] == 42.0 and f[1, 4] == 42.0  # no neighbour on that side
    assert f[0, 4] == pytest.approx(1.0) and f[1, 3] == pytest.approx(1.0)
    assert f[0, 5] == pytest.approx(0.1) and f[1, 5] == pytest.approx(0.2)
    # full circle: first and last segment are neighbours
    g = compute_features(table, scan, params=params, full_circle=True).values
    assert g[0, 3] == pytest.approx(math.hypot(1, 0.3)) == pytest.approx(g[1, 4])


def test_straight_line_has_zero_linearity_and_no_circle() -> None:
    t = np.linspace(0, 1, 7)
    f = features_of(np.stack([1 + 0.3 * t, 2 - 0.5 * t], axis=1))
    assert f[6] == pytest.approx(0.0, abs=1e-20)
    assert f[8] == FeatureParams().no_circle_radius
    assert f[7] == pytest.approx(0.0, abs=1e-20)
    assert f[11] == pytest.approx(0.0, abs=1e-9)  # curvature
    assert f[12] == pytest.approx(0.0, abs=1e-9)  # angular difference


def test_linearity_is_the_residual_of_the_best_line() -> None:
    # symmetric zig-zag about y = 0: best line is y = 0, residuals 0.1 each
    f = features_of([(0, 0.1), (1, -0.1), (2, -0.1), (3, 0.1)])
    assert f[6] == pytest.approx(0.04)
    # and in general it is the smallest eigenvalue of the scatter matrix
    rng = np.random.default_rng(3)
    pts = rng.normal(size=(9, 2)) * [1.0, 0.2]
    d = pts - pts.mean(axis=0)
    assert features_of(pts)[6] == pytest.approx(np.linalg.eigvalsh(d.T @ d)[0])


def test_circle_arc_gives_its_radius_and_zero_circularity() -> None:
    r, cx, cy = 0.1, 2.0, 0.5
    phi = np.linspace(np.deg2rad(120), np.deg2rad(240), 11)
    f = features_of(np.stack([cx + r * np.cos(phi), cy + r * np.sin(phi)], axis=1))
    assert f[8] == pytest.approx(r, rel=1e-9)
    assert f[7] == pytest.approx(0.0, abs=1e-20)
    # every interior triangle is inscribed in the circle: curvature 1 / r
    assert f[11] == pytest.approx(1.0 / r, rel=1e-9)
    # boundary: 10 equal chords
    chord = 2 * r * math.sin(np.deg2rad(12) / 2)
    assert f[9] == pytest.approx(10 * chord)
    assert f[10] == pytest.approx(0.0, abs=1e-12)
    # turning angle between equal chords is the arc step, counter-clockwise positive
    assert f[12] == pytest.approx(np.deg2rad(12))


def test_circle_fit_residuals_match_direct_evaluation() -> None:
    rng = np.random.default_rng(7)
    phi = np.linspace(0, 2, 8)
    pts = np.stack([np.cos(phi), np.sin(phi)], axis=1) * 0.2 + rng.normal(0, 0.01, (8, 2))
    f = features_of(pts)
    # independent solve of 000's A x = b with the pseudo-inverse
    A = np.column_stack([-2 * pts[:, 0], -2 * pts[:, 1], np.ones(8)])
    b = -(pts**2).sum(axis=1)
    xc, yc, c = np.linalg.pinv(A) @ b
    rc = math.sqrt(xc**2 + yc**2 - c)
    assert f[8] == pytest.approx(rc, rel=1e-9)
    expected = ((rc - np.hypot(xc - pts[:, 0], yc - pts[:, 1])) ** 2).sum()
    assert f[7] == pytest.approx(expected, rel=1e-6)


def test_boundary_length_and_regularity() -> None:
    f = features_of([(0, 0), (3, 4), (3, 5), (3, 7)])  # steps 5, 1, 2
    assert f[9] == pytest.approx(8.0)
    assert f[10] == pytest.approx(np.std([5.0, 1.0, 2.0], ddof=1))


def test_curvature_of_a_right_triangle() -> None:
    # area 1/2, sides 1, 1, sqrt(2): 4A / (dA dB dC) = 2 / sqrt(2)
    f = features_of([(1, 0), (0, 0), (0, 1)])
    assert f[11] == pytest.approx(math.sqrt(2.0))


def test_angular_difference_of_a_polyline_and_beam_direction() -> None:
    square = [(0, 0), (1, 0), (1, 1), (0, 1)]
    assert features_of(square)[12] == pytest.approx(math.pi / 2)
    # a scanner turning the other way traverses the other way round: same sign convention
    assert features_of(square, increment=-0.01)[12] == pytest.approx(-math.pi / 2)
    # right turn then left turn: mean 0
    assert features_of([(0, 0), (1, 0), (1, -1), (2, -1)])[12] == pytest.approx(0.0)


def test_angular_difference_is_unwrapped_across_pi() -> None:
    # chord directions 170 deg then -170 deg: the turn is +20 deg, not -340 deg
    a = np.deg2rad(170.0)
    p1 = np.array([math.cos(a), math.sin(a)])
    p2 = p1 + np.array([math.cos(-a), math.sin(-a)])
    f = features_of([(0.0, 0.0), tuple(p1), tuple(p2)])
    assert f[12] == pytest.approx(np.deg2rad(20.0))


def test_mean_speed_along_beams_skips_beams_invalid_before() -> None:
    n = 5
    prev_ranges = np.array([1.0, 1.0, np.nan, 1.0, 1.0])
    now_ranges = np.array([1.1, 1.2, 1.3, 1.1, 1.1])
    prev = Scan(10.0, 0.0, 0.01, prev_ranges)
    now = Scan(10.1, 0.0, 0.01, now_ranges)
    pts, beams = now.valid_points()
    table = jump_distance_table(pts, beams, n, threshold=1.0)
    feats = compute_features(table, now, prev)
    # beams 0, 1, 3, 4 moved 0.1, 0.2, 0.1, 0.1 m in 0.1 s
    assert feats.values[0, 13] == pytest.approx(1.25)
    assert feats.max_beam_motion[0] == pytest.approx(0.2)
    # no previous scan, or one with another beam layout: 0
    assert compute_features(table, now).values[0, 13] == 0.0
    other = Scan(10.0, 0.0, 0.02, prev_ranges)
    assert compute_features(table, now, other).values[0, 13] == 0.0


def test_many_segments_match_one_at_a_time() -> None:
    rng = np.random.default_rng(11)
    ranges = np.repeat(rng.uniform(1, 5, 40), rng.integers(1, 8, 40))[:180]
    ranges = ranges + rng.normal(0, 0.01, ranges.size)
    ranges[rng.integers(0, ranges.size, 10)] = np.nan
    scan = Scan(0.0, -1.5, 0.0174, ranges)
    pts, beams = scan.valid_points()
    table = jump_distance_table(pts, beams, scan.n_beams, 0.1)
    whole = compute_features(table, scan).values
    for i in range(len(table)):
        a, b = table.offsets[i], table.offsets[i + 1]
        if b - a < 3:
            continue
        single = features_of(pts[a:b], increment=0.0174)
        np.testing.assert_allclose(
            whole[i, [0, 1, 2, 5, 6, 7, 8, 9, 10, 11, 12]],
            single[[0, 1, 2, 5, 6, 7, 8, 9, 10, 11, 12]],
            rtol=1e-7,
            atol=1e-12,
        )


def test_vector_of_medians_of_many_segments_equals_numpy_median() -> None:
    """Feature 3 of every segment of a long scan (hundreds of segments, coordinates of
    both signs, repeated values) equals its mean distance to the per-coordinate medians of
    np.median, segment by segment."""
    rng = np.random.default_rng(35)
    sizes = rng.integers(1, 12, 400)
    pts = np.round(rng.normal(0.0, 8.0, (int(sizes.sum()), 2)), 1)  # ties within segments
    offsets = np.concatenate(([0], np.cumsum(sizes)))
    seg = np.repeat(np.arange(sizes.size), sizes)
    n = pts.shape[0]
    scan = Scan(0.0, 0.0, 0.01, np.ones(n))
    table = SegmentTable(np.arange(n), pts, offsets, n)
    got = compute_features(table, scan).values[:, 2]
    for i in range(sizes.size):
        p = pts[seg == i]
        med = np.median(p, axis=0)
        assert got[i] == pytest.approx(np.mean(np.hypot(*(p - med).T)), rel=1e-12, abs=1e-12)
