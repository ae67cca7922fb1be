"""Things people carry, pull or wear (004 Exp. 6), as shapes that move with their owner.

Each accessory is built for many instants at once from the owner's body position, heading
and legs. Beams that hit an accessory carry the owner's person and group id, leg -1 and
the accessory's own object id. Heights ``[z_min, z_max]`` [m] decide which scanners see
it: a suitcase shows only at foot height, a baggage cart at both heights, a large item
carried in front of the body only at upper-body height.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class AccessoryShape:
    """Geometry of one accessory kind (all lengths in metres, in the owner's body frame:
    x ahead, y to the left)."""

    kind: str
    z_min: float
    z_max: float
    description: str


ACCESSORIES: dict[str, AccessoryShape] = {
    a.kind: a
    for a in (
        AccessoryShape("suitcase-carried", 0.10, 0.65, "0.45x0.15 m suitcase at the right hand"),
        AccessoryShape("suitcase-pulled", 0.02, 0.65, "0.40x0.25 m trolley suitcase 0.75 m behind"),
        AccessoryShape("baggage-cart", 0.05, 1.20, "1.0x0.6 m cart pushed 0.35 m ahead"),
        AccessoryShape("cane", 0.0, 0.90, "cane (radius 12 mm) moving with the left leg"),
        AccessoryShape("long-skirt", 0.03, 1.00, "long skirt enclosing both legs"),
        AccessoryShape("carried-item", 0.80, 1.40, "0.3x0.5 m box carried in front"),
        AccessoryShape("shoulder-bag", 0.80, 1.20, "0.3x0.12 m bag at the left hip"),
    )
}


def _rect_segments(
    xy: FloatArray, heading: FloatArray, ahead: float, left: float, length: float, width: float
) -> FloatArray:
    """Edges (K, 4, 4) of rectangles centred ``ahead``/``left`` of each body (K instants),
    long side ``length`` along the heading."""
    c, s = np.cos(heading), np.sin(heading)
    cx = xy[:, 0] + ahead * c - left * s
    cy = xy[:, 1] + ahead * s + left * c
    hl, hw = length / 2, width / 2
    local = np.array([[hl, hw], [-hl, hw], [-hl, -hw], [hl, -hw]])
    px = cx[:, None] + local[None, :, 0] * c[:, None] - local[None, :, 1] * s[:, None]
    py = cy[:, None] + local[None, :, 0] * s[:, None] + local[None, :, 1] * c[:, None]
    pts = np.stack([px, py], axis=-1)  # (K, 4, 2)
    nxt = np.roll(pts, -1, axis=1)
    return np.concatenate([pts, nxt], axis=-1)


@dataclass(frozen=True, eq=False)
class AccessoryGeometry:
    """Shapes of one accessory at K instants (world frame).

    Attributes:
        circles: (K, c, 3) ``x, y, r``.
        ellipses: (K, e, 5) ``x, y, a, b, angle``.
        segments: (K, s, 4) ``x0, y0, x1, y1``.
    """

    circles: FloatArray
    ellipses: FloatArray
    segments: FloatArray


def accessory_geometry(
    kind: str,
    xy: FloatArray,
    heading: FloatArray,
    legs: FloatArray,
    leg_radius: float,
) -> AccessoryGeometry:
    """Shapes of accessory ``kind`` for K instants of its owner: body ``xy`` (K, 2),
    ``heading`` (K,), ``legs`` (K, 2, 2), leg radius [m]."""
    k = xy.shape[0]
    none_c = np.empty((k, 0, 3))
    none_e = np.empty((k, 0, 5))
    none_s = np.empty((k, 0, 4))
    if kind == "suitcase-carried":
        return AccessoryGeometry(
            none_c, none_e, _rect_segments(xy, heading, 0.0, -0.32, 0.45, 0.15)
        )
    if kind == "suitcase-pulled":
        return AccessoryGeometry(
            none_c, none_e, _rect_segments(xy, heading, -0.75, -0.15, 0.40, 0.25)
        )
    if kind == "baggage-cart":
        return AccessoryGeometry(none_c, none_e, _rect_segments(xy, heading, 0.85, 0.0, 1.0, 0.6))
    if kind == "carried-item":
        return AccessoryGeometry(none_c, none_e, _rect_segments(xy, heading, 0.35, 0.0, 0.3, 0.5))
    if kind == "shoulder-bag":
        return AccessoryGeometry(none_c, none_e, _rect_segments(xy, heading, 0.0, 0.28, 0.3, 0.12))
    if kind == "cane":
        c, s = np.cos(heading), np.sin(heading)
        # on the right-hand side, planted and lifted with the left leg (contralateral use)
        lateral = -0.45
        base = legs[:, 0]
        cx = base[:, 0] + 0.1 * c - lateral * s
        cy = base[:, 1] + 0.1 * s + lateral * c
        circ = np.stack([cx, cy, np.full(k, 0.012)], axis=-1)[:, None, :]
        return AccessoryGeometry(circ, none_e, none_s)
    if kind == "long-skirt":
        mid = legs.mean(axis=1)
        d = legs[:, 1] - legs[:, 0]
        half = 0.5 * np.hypot(d[:, 0], d[:, 1])
        a = np.maximum(half + leg_radius + 0.05, 0.24)
        b = np.full(k, 0.2)
        ang = np.arctan2(d[:, 1], d[:, 0])
        ell = np.stack([mid[:, 0], mid[:, 1], a, b, ang], axis=-1)[:, None, :]
        return AccessoryGeometry(none_c, ell, none_s)
    raise ValueError(f"unknown accessory {kind!r}; known: {', '.join(ACCESSORIES)}")
