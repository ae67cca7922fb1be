"""laserpeople: detect and track people, legs and groups of people in 2D laser scans.

The data model lives in :mod:`laserpeople.scan` (scans, points, segments),
:mod:`laserpeople.tracks` (detections and tracks) and :mod:`laserpeople.truth`
(ground truth). Readers and writers are in :mod:`laserpeople.io`.
"""

from laserpeople.errors import LaserPeopleError
from laserpeople.scan import PointSet, Pose2D, Scan, Segment
from laserpeople.tracks import Detections, Track, Tracks
from laserpeople.truth import BeamLabels, TruthFrame

__version__ = "0.1.0"

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
