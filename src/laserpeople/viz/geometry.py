"""Shapes drawn for tracks: covariance ellipses, velocity arrows; vectorised over tracks."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

ELLIPSE_SIGMA = math.sqrt(5.991464547107979)
"""Scale of the drawn covariance ellipse: the 95 % region of a 2-D Gaussian
(chi-square with 2 degrees of freedom at 0.95 is 5.9915, so about 2.45 sigma)."""


def covariance_ellipses(
    centres: NDArray[np.floating],
    covariances: NDArray[np.floating],
    *,
    scale: float = ELLIPSE_SIGMA,
    n_points: int = 33,
) -> FloatArray:
    """Closed outlines (T, n_points, 2) [m] of the ellipses ``{x: (x-c)^T C^-1 (x-c) = scale^2}``.

    ``centres`` is (T, 2) [m], ``covariances`` (T, 2, 2) [m^2]. The first and last point of
    each outline coincide. Non-finite or negative-definite covariances give NaN outlines
    (nothing is drawn for them) rather than an error, because a tracker's output is drawn
    as it is.
    """
    c = np.asarray(centres, dtype=np.float64).reshape(-1, 2)
    cov = np.asarray(covariances, dtype=np.float64).reshape(-1, 2, 2)
    t = np.linspace(0.0, 2.0 * np.pi, n_points)
    circle = np.stack([np.cos(t), np.sin(t)], axis=1)  # (n, 2)
    out = np.full((c.shape[0], n_points, 2), np.nan)
    if c.shape[0] == 0:
        return out
    finite = np.all(np.isfinite(cov.reshape(-1, 4)), axis=1)
    sym = 0.5 * (cov + np.swapaxes(cov, 1, 2))
    sym[~finite] = np.eye(2)
    eigval, eigvec = np.linalg.eigh(sym)  # ascending eigenvalues, columns are vectors
    ok = finite & (eigval[:, 0] >= 0.0)
    radii = scale * np.sqrt(np.clip(eigval, 0.0, None))  # (T, 2)
    # outline = c + V @ diag(r) @ circle
    axes = eigvec * radii[:, None, :]  # (T, 2, 2): columns scaled
    pts = np.einsum("tij,nj->tni", axes, circle) + c[:, None, :]
    out[ok] = pts[ok]
    return out


def velocity_segments(
    positions: NDArray[np.floating], velocities: NDArray[np.floating], horizon: float = 1.0
) -> FloatArray:
    """Segments (T, 2, 2) [m] from each position to where it is ``horizon`` seconds later."""
    p = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
    v = np.nan_to_num(np.asarray(velocities, dtype=np.float64).reshape(-1, 2), nan=0.0)
    return np.stack([p, p + horizon * v], axis=1)


def square_extent(
    extent: tuple[float, float, float, float], box_px: tuple[float, float]
) -> tuple[float, float, float, float]:
    """Widen ``(xmin, xmax, ymin, ymax)`` [m] about its centre so that one metre spans the
    same number of pixels along x and y in an axes box of ``box_px = (width, height)`` [px]."""
    x0, x1, y0, y1 = extent
    dx, dy = max(x1 - x0, 1e-3), max(y1 - y0, 1e-3)
    want = box_px[0] / box_px[1]
    if dx / dy < want:
        dx = dy * want
    else:
        dy = dx / want
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    return (cx - 0.5 * dx, cx + 0.5 * dx, cy - 0.5 * dy, cy + 0.5 * dy)


GROUP_OUTLINE_MARGIN = 0.15
"""Margin [m] round a group's points in its drawn outline (about a leg's radius plus the
range noise, so that the outline encloses the legs rather than cutting through them)."""


def group_outline(contour: FloatArray, margin: float = GROUP_OUTLINE_MARGIN) -> FloatArray:
    """Closed outline (M + 1, 2) [m] of a group: the convex hull of its contour points
    (K, 2) [m], each widened to a 12-gon of radius ``margin``; first vertex repeated last.
    Empty (0, 2) for K = 0."""
    from scipy.spatial import ConvexHull

    pts = np.asarray(contour, dtype=np.float64).reshape(-1, 2)
    pts = pts[np.isfinite(pts).all(axis=1)]
    if pts.shape[0] == 0:
        return np.empty((0, 2))
    ang = np.linspace(0.0, 2.0 * np.pi, 12, endpoint=False)
    ring = margin * np.stack([np.cos(ang), np.sin(ang)], axis=1)
    cloud = (pts[:, None, :] + ring[None, :, :]).reshape(-1, 2)
    hull = cloud[ConvexHull(cloud).vertices]
    return np.vstack([hull, hull[:1]])
