"""Group tracking (000 Sec. 4): a multi-model MHT over groups of people with split, merge
and group size, on the MHT core of :mod:`laserpeople.tracking.mht`."""

from laserpeople.tracking.groups.observations import GroupObservations
from laserpeople.tracking.groups.params import GroupTrackerParams
from laserpeople.tracking.groups.tracker import GroupEstimate, GroupEvent, GroupMHTTracker

__all__ = [
    "GroupEstimate",
    "GroupEvent",
    "GroupMHTTracker",
    "GroupObservations",
    "GroupTrackerParams",
]
