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


def register(entry: TrackerEntry) -> None:
    """Add a tracker (a name can be registered once)."""
    if entry.name in TRACKERS:
        raise ValueError(f"tracker {entry.name!r} is already registered")
    TRACKERS[entry.name] = entry


def get(name: str) -> TrackerEntry:
    """The tracker called ``name``; ConfigError listing the known ones otherwise."""
    try:
        return TRACKERS[name]
    except KeyError:
        raise ConfigError(
            f"unknown tracker {name!r}", hint=f"choose one of: {', '.join(sorted(TRACKERS))}"
        ) from None


def _leg_mht(params: Any) -> Tracker:
    from laserpeople.tracking.legs import LegMHTTracker

    return LegMHTTracker(params)


def _nn(params: Any) -> Tracker:
    from laserpeople.tracking.nearest import NearestNeighbourTracker

    return NearestNeighbourTracker(params)


def _feet_pf(params: Any) -> Any:
    from laserpeople.tracking.particle.feet import FeetTracker

    return FeetTracker(params)  # a FrameTracker: consumes points and foreground


def _upper_body_pf(params: Any) -> Any:
    from laserpeople.tracking.particle.upper_body import UpperBodyTracker

    return UpperBodyTracker(params)  # a FrameTracker: consumes points and foreground


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
    from laserpeople.tracking.particle.feet import FeetParams
    from laserpeople.tracking.particle.upper_body import UpperBodyParams

    register(
        TrackerEntry(
            "feet-pf",
            FeetParams,
            _feet_pf,
            "feet-height particle filters with a walking model, on fused foreground points "
            "(004 Sec. 2.1)",
        )
    )
    register(
        TrackerEntry(
            "upper-body-pf",
            UpperBodyParams,
            _upper_body_pf,
            "upper-body-height particle filters in Voronoi cells, on fused foreground points "
            "(004 Sec. 2.2)",
        )
    )


_register_builtin()
