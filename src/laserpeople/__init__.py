"""laserpeople: detect and track people, legs and groups of people in 2D laser scans.

The data model lives in :mod:`laserpeople.scan` (scans, points, segments),
:mod:`laserpeople.tracks` (detections and tracks) and :mod:`laserpeople.truth`
(ground truth). Readers and writers are in :mod:`laserpeople.io`.

The names below are imported on first use (PEP 562), so that importing a light module of
the package (the command line, the errors, the configuration) does not pay for numpy.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

from laserpeople.errors import LaserPeopleError

if TYPE_CHECKING:
    from laserpeople.scan import PointSet, Pose2D, Scan, Segment
    from laserpeople.tracks import Detections, Track, Tracks
    from laserpeople.truth import BeamLabels, TruthFrame

__version__ = "0.1.0"

_LAZY: dict[str, str] = {
    "PointSet": "laserpeople.scan",
    "Pose2D": "laserpeople.scan",
    "Scan": "laserpeople.scan",
    "Segment": "laserpeople.scan",
    "Detections": "laserpeople.tracks",
    "Track": "laserpeople.tracks",
    "Tracks": "laserpeople.tracks",
    "BeamLabels": "laserpeople.truth",
    "TruthFrame": "laserpeople.truth",
}

__all__ = [
    "BeamLabels",
    "Detections",
    "LaserPeopleError",
    "PointSet",
    "Pose2D",
    "Scan",
    "Segment",
    "Track",
    "Tracks",
    "TruthFrame",
    "__version__",
]


def __getattr__(name: str) -> Any:
    """The data-model classes, imported when first asked for."""
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'laserpeople' has no attribute {name!r}")
    value = getattr(import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
