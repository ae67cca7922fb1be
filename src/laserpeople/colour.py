"""Colour conversions for appearance cues: RGB <-> HSV and the hues of an image region.

Hue [deg] in [0, 360) as in 002 Table 1; saturation and value in [0, 1]. Bottom layer, so
that the simulated camera and the identity stage share one implementation.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


def rgb_to_hue(
    rgb: NDArray[np.floating] | NDArray[np.integer],
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Hue, saturation and value of RGB pixels (HSV colour space, Gonzalez & Woods).

    Args:
        rgb: Pixels (..., 3); integers are read as 0-255, floats as 0-1.

    Returns:
        ``(hue, saturation, value)``, each of shape ``rgb.shape[:-1]``; hue in [0, 360)
        degrees (0 where saturation is 0), saturation and value in [0, 1].
    """
    arr = np.asarray(rgb)
    x = (
        arr.astype(np.float64) / 255.0
        if np.issubdtype(arr.dtype, np.integer)
        else arr.astype(np.float64)
    )
    r, g, b = x[..., 0], x[..., 1], x[..., 2]
    mx = x.max(axis=-1)
    mn = x.min(axis=-1)
    c = mx - mn
    safe = np.where(c > 0, c, 1.0)
    h = np.where(
        mx == r,
        ((g - b) / safe) % 6.0,
        np.where(mx == g, (b - r) / safe + 2.0, (r - g) / safe + 4.0),
    )
    hue = np.where(c > 0, 60.0 * h, 0.0) % 360.0
    sat = np.where(mx > 0, c / np.where(mx > 0, mx, 1.0), 0.0)
    return hue, sat, mx


def hsv_to_rgb(hue: FloatArray, sat: FloatArray, val: FloatArray) -> FloatArray:
    """RGB (..., 3) in [0, 1] of HSV pixels; hue [deg], saturation and value in [0, 1]."""
    h = (np.asarray(hue, dtype=np.float64) % 360.0) / 60.0
    s = np.asarray(sat, dtype=np.float64)
    v = np.asarray(val, dtype=np.float64)
    c = v * s
    x = c * (1.0 - np.abs(h % 2.0 - 1.0))
    sector = np.floor(h).astype(np.int64) % 6
    zero = np.zeros_like(c)
    table = np.stack(
        [
            np.stack([c, x, zero], -1),
            np.stack([x, c, zero], -1),
            np.stack([zero, c, x], -1),
            np.stack([zero, x, c], -1),
            np.stack([x, zero, c], -1),
            np.stack([c, zero, x], -1),
        ],
        axis=0,
    )
    rgb = np.take_along_axis(table, sector[None, ..., None].repeat(3, -1), axis=0)[0]
    return rgb + (v - c)[..., None]


def region_hues(
    rgb: NDArray[np.floating] | NDArray[np.integer],
    mask: NDArray[np.bool_] | None = None,
    min_saturation: float = 0.2,
    min_value: float = 0.15,
) -> FloatArray:
    """Hues [rad, in (-pi, pi]] of the coloured pixels of an image region.

    Args:
        rgb: Image (H, W, 3) or pixels (N, 3).
        mask: Which pixels belong to the person (same leading shape); all when None.
        min_saturation: Pixels less saturated have no defined hue and are ignored.
        min_value: Pixels darker than this are ignored.
    """
    hue, sat, val = rgb_to_hue(rgb)
    keep = (sat >= min_saturation) & (val >= min_value)
    if mask is not None:
        keep &= np.asarray(mask, dtype=bool)
    deg = hue[keep]
    return np.angle(np.exp(1j * np.deg2rad(deg)))
