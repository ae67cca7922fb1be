"""Trackers: constant-velocity Kalman filter (:mod:`.kalman`), assignment (Hungarian and
Murty k-best, :mod:`.assignment`), the MHT core (:mod:`.mht`), the adaptive leg and people
tracker of 000 Sec. 3 (:mod:`.legs`, :mod:`.people`), a nearest-neighbour baseline
(:mod:`.nearest`), and the registry behind ``laserpeople track --tracker`` (:mod:`.registry`).
Every tracker offers ``update(detections) -> Tracks``.
"""

from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams
from laserpeople.tracking.nearest import NearestNeighbourParams, NearestNeighbourTracker
from laserpeople.tracking.people import PersonFuser, PersonParams

__all__ = [
    "LegMHTTracker",
    "LegTrackerParams",
    "NearestNeighbourParams",
    "NearestNeighbourTracker",
    "PersonFuser",
    "PersonParams",
]
