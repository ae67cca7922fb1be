"""Stable colours per track: the same (kind, id) gets the same colour in every frame and run.

The palette holds the twenty colours of the widely used "tab20" qualitative map (dark and
light shade of ten hues); a multiplicative hash spreads consecutive ids over it so that
neighbouring ids rarely share a hue.
"""

from __future__ import annotations

from laserpeople.tracks import TrackKind

RGB = tuple[int, int, int]

PALETTE: tuple[RGB, ...] = (
    (31, 119, 180),
    (174, 199, 232),
    (255, 127, 14),
    (255, 187, 120),
    (44, 160, 44),
    (152, 223, 138),
    (214, 39, 40),
    (255, 152, 150),
    (148, 103, 189),
    (197, 176, 213),
    (140, 86, 75),
    (196, 156, 148),
    (227, 119, 194),
    (247, 182, 210),
    (127, 127, 127),
    (199, 199, 199),
    (188, 189, 34),
    (219, 219, 141),
    (23, 190, 207),
    (158, 218, 229),
)
"""tab20 as 8-bit RGB."""

_KIND_SALT: dict[str, int] = {"leg": 0, "person": 7, "group": 13}
_GOLDEN = 2654435761  # Knuth's multiplicative hash constant (2^32 / golden ratio)

BACKGROUND: RGB = (255, 255, 255)
SCAN_POINTS: RGB = (90, 90, 90)
TRUTH: RGB = (0, 0, 0)
SENSOR: RGB = (20, 20, 20)


def palette_index(track_id: int, kind: TrackKind | str = "person") -> int:
    """Index into :data:`PALETTE` for a track; a pure function of ``(kind, track_id)``."""
    key = (int(track_id) + _KIND_SALT.get(kind, 0)) & 0xFFFFFFFF
    return ((key * _GOLDEN) >> 16) % len(PALETTE)


def track_color(track_id: int, kind: TrackKind | str = "person") -> RGB:
    """The 8-bit RGB colour of a track."""
    return PALETTE[palette_index(track_id, kind)]


def to_unit(rgb: RGB) -> tuple[float, float, float]:
    """An 8-bit RGB colour as floats in [0, 1] (matplotlib, ROS ``ColorRGBA``)."""
    return (rgb[0] / 255.0, rgb[1] / 255.0, rgb[2] / 255.0)


def label_color(track_id: int, kind: TrackKind | str = "person") -> RGB:
    """A darker shade of the track colour for its text label, readable on white."""
    r, g, b = track_color(track_id, kind)
    return (int(r * 0.6), int(g * 0.6), int(b * 0.6))
