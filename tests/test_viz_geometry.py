"""Covariance ellipses, square extents and track colours."""

from __future__ import annotations

import itertools
import math

import numpy as np

from laserpeople.viz.colors import PALETTE, palette_index, track_color
from laserpeople.viz.geometry import (
    ELLIPSE_SIGMA,
    covariance_ellipses,
    square_extent,
    velocity_segments,
)


def test_ellipse_sigma_is_the_95_percent_chi_square_quantile() -> None:
    # chi2(2 dof) CDF is 1 - exp(-x/2); at 0.95 that gives x = -2 ln 0.05
    assert math.isclose(ELLIPSE_SIGMA**2, -2.0 * math.log(0.05), rel_tol=1e-12)


def test_axis_aligned_ellipse_reaches_scaled_standard_deviations() -> None:
    out = covariance_ellipses(np.array([[1.0, 2.0]]), np.array([np.diag([4.0, 1.0])]), scale=1.0)
    pts = out[0]
    assert np.allclose(pts[0], pts[-1])
    assert math.isclose(pts[:, 0].max(), 3.0, abs_tol=1e-9)  # 1 + sqrt(4)
    assert math.isclose(pts[:, 0].min(), -1.0, abs_tol=1e-2)
    assert math.isclose(pts[:, 1].max(), 3.0, abs_tol=1e-2)  # 2 + sqrt(1)


def test_rotated_ellipse_points_lie_on_the_mahalanobis_contour() -> None:
    cov = np.array([[0.5, 0.3], [0.3, 0.4]])
    centre = np.array([-1.0, 0.5])
    pts = covariance_ellipses(centre[None], cov[None])[0]
    d = pts - centre
    maha = np.einsum("ni,ij,nj->n", d, np.linalg.inv(cov), d)
    assert np.allclose(maha, ELLIPSE_SIGMA**2)


def test_broken_covariances_give_nan_outlines_not_errors() -> None:
    covs = np.array([np.full((2, 2), np.nan), np.diag([-1.0, 1.0]), np.eye(2)])
    out = covariance_ellipses(np.zeros((3, 2)), covs)
    assert np.all(np.isnan(out[0])) and np.all(np.isnan(out[1]))
    assert np.all(np.isfinite(out[2]))
    assert covariance_ellipses(np.empty((0, 2)), np.empty((0, 2, 2))).shape == (0, 33, 2)


def test_velocity_segment_ends_one_horizon_ahead() -> None:
    seg = velocity_segments(np.array([[1.0, 1.0]]), np.array([[0.5, -1.0]]), horizon=2.0)
    assert np.allclose(seg[0], [[1.0, 1.0], [2.0, -1.0]])


def test_square_extent_keeps_metres_square_and_contains_the_input() -> None:
    ext = square_extent((0.0, 10.0, 0.0, 2.0), (400.0, 300.0))
    x0, x1, y0, y1 = ext
    assert math.isclose((x1 - x0) / 400.0, (y1 - y0) / 300.0)
    assert x0 <= 0.0 and x1 >= 10.0 and y0 <= 0.0 and y1 >= 2.0
    assert math.isclose(0.5 * (y0 + y1), 1.0)


def test_track_colours_are_stable_and_neighbouring_ids_differ() -> None:
    assert track_color(5, "person") == track_color(5, "person")
    assert all(0 <= palette_index(i) < len(PALETTE) for i in range(1000))
    firsts = [track_color(i, "person") for i in range(12)]
    assert all(a != b for a, b in itertools.pairwise(firsts))
    assert len(set(firsts)) >= 10
