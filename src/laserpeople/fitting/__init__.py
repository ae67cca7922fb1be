"""Learning tracker parameters from labelled recordings by counting events (000 Sec. 3.4,
4.6): :class:`~laserpeople.fitting.legs.LegMHTFitter` (leg and people tracker),
:class:`~laserpeople.fitting.groups.GroupModelFitter` (group tracker), and the flow of
``laserpeople fit`` in :mod:`laserpeople.fitting.flow`."""

from laserpeople.fitting.estimates import FitError, NotEnoughEventsError

__all__ = ["FitError", "NotEnoughEventsError"]
