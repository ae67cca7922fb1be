from __future__ import annotations

import numpy as np

from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.scan import Scan


def _leg_scan(centre: tuple[float, float], radius: float) -> Scan:
    """A 180 deg, 0.25 deg scan of one cylinder (exact ray-circle hits) before a wall at 4 m."""
    angles = np.deg2rad(np.arange(-90.0, 90.0 + 1e-9, 0.25))
    d = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    c = np.asarray(centre)
    b = d @ c
    disc = b**2 - (c @ c - radius**2)
    wall = 4.0 / np.maximum(np.cos(angles), 1e-3)
    ranges = np.where(disc >= 0, b - np.sqrt(np.clip(disc, 0, None)), np.minimum(wall, 15.0))
    return Scan(0.0, float(angles[0]), float(np.deg2rad(0.25)), ranges, 0.05, 20.0)


def test_leg_position_is_the_axis_not_the_surface() -> None:
    centre = (2.0, 0.3)
    scan = _leg_scan(centre, 0.07)
    det = AdaBoostLegDetector.default().detect(scan)
    assert len(det) == 1
    err = np.hypot(*(det.positions[0] - centre))
    assert err < 0.015
    plain = AdaBoostLegDetector.default(LegDetectorParams(centre_offset=0.0)).detect(scan)
    surface_err = np.hypot(*(plain.positions[0] - centre))
    assert surface_err > 0.035  # the centroid of the visible arc lies ~2r/pi before the axis
    np.testing.assert_allclose(
        np.hypot(*det.positions[0]) - np.hypot(*plain.positions[0]), 0.045, atol=1e-9
    )
