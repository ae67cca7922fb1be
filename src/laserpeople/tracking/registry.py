"""Tracker registry: name -> factory and parameter class, for the ``track`` command.

Every tracker offers ``update(detections) -> Tracks`` (:class:`Tracker`). A new tracker
registers itself with :func:`register` (or is added to :data:`TRACKERS` below) and becomes
available as ``laserpeople track --tracker NAME`` with its parameters read from the
``[section]`` of ``--config`` and printed by ``--print-config``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

from laserpeople.errors import ConfigError
from laserpeople.tracks import Detections, Tracks


class Tracker(Protocol):
    """A streaming tracker: one scan's detections in, the current tracks out."""

    def update(self, detections: Detections) -> Tracks:
        """Process one scan."""
        ...


@dataclass(frozen=True)
class TrackerEntry:
    """A registered tracker.

    Attributes:
        name: Command-line name.
        params_cls: Frozen parameter dataclass (its ``config_section`` is the TOML section).
        factory: Builds the tracker from parameters.
        description: One line for ``--help``.
    """

    name: str
    params_cls: type
    factory: Callable[[Any], Tracker]
    description: str


TRACKERS: dict[str, TrackerEntry] = {}

FRAME_TRACKERS: dict[str, TrackerEntry] = {}
"""Trackers that take a whole :class:`~laserpeople.frame.Frame` (``update(frame)``, e.g. the
group tracker on foreground points) rather than leg detections; kept apart from
:data:`TRACKERS` until the commands feed frames (the pipeline), so that commands looping
over :data:`TRACKERS` keep passing detections only to detection trackers."""


def register(entry: TrackerEntry) -> None:
    """Add a tracker (a name can be registered once)."""
    if entry.name in TRACKERS:
        raise ValueError(f"tracker {entry.name!r} is already registered")
    TRACKERS[entry.name] = entry


def get(name: str) -> TrackerEntry:
    """The tracker called ``name``; ConfigError listing the known ones otherwise."""
    try:
        return TRACKERS[name] if name in TRACKERS else FRAME_TRACKERS[name]
    except KeyError:
        known = sorted({*TRACKERS, *FRAME_TRACKERS})
        raise ConfigError(
            f"unknown tracker {name!r}", hint=f"choose one of: {', '.join(known)}"
        ) from None


def _leg_mht(params: Any) -> Tracker:
    from laserpeople.tracking.legs import LegMHTTracker

    return LegMHTTracker(params)


def _nn(params: Any) -> Tracker:
    from laserpeople.tracking.nearest import NearestNeighbourTracker

    return NearestNeighbourTracker(params)


def _group_mht(params: Any) -> Any:
    from laserpeople.tracking.groups import GroupMHTTracker

    return GroupMHTTracker(params)


def _register_builtin() -> None:
    from laserpeople.tracking.legs import LegTrackerParams
    from laserpeople.tracking.nearest import NearestNeighbourParams

    register(
        TrackerEntry(
            "leg-mht",
            LegTrackerParams,
            _leg_mht,
            "multi-hypothesis leg tracker with adaptive occlusion probabilities (000 Sec. 3)",
        )
    )
    register(
        TrackerEntry(
            "nn",
            NearestNeighbourParams,
            _nn,
            "global-nearest-neighbour Kalman leg tracker (baseline)",
        )
    )
    from laserpeople.tracking.groups.tracker import GroupTrackerParams

    FRAME_TRACKERS["group-mht"] = TrackerEntry(
        "group-mht",
        GroupTrackerParams,
        _group_mht,
        "multi-model MHT of groups with split, merge and group size (000 Sec. 4); frames",
    )


_register_builtin()
