"""Tracker registry: name -> factory and parameter class, for ``track``, ``bench``, ``demo``.

Every registered factory hands out a :class:`~laserpeople.frame.FrameTracker`: it declares
what it ``consumes`` of a :class:`~laserpeople.frame.Frame` and offers
``update(frame) -> Tracks``. A new tracker registers itself with :func:`register` (or is
added to :func:`_register_builtin` below) and becomes available as
``laserpeople track --tracker NAME`` with its parameters read from the ``[section]`` of
``--config`` and printed by ``--print-config``; the pipeline checks at build time that it
can feed the tracker what it consumes.

The leg trackers of this package take one scan's leg detections
(``update(detections) -> Tracks``, :class:`DetectionsTracker`); :class:`LegsAdapter` makes
them frame trackers that consume ``{"legs"}``.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any, Protocol

from laserpeople.background import StaticWorldModel
from laserpeople.errors import ConfigError
from laserpeople.frame import Frame, FrameField, FrameTracker
from laserpeople.scan import Pose2D
from laserpeople.tracking.point_guard import GuardedTracker
from laserpeople.tracking.robot_motion import MotionWatch
from laserpeople.tracks import Detections, Tracks


class DetectionsTracker(Protocol):
    """A streaming tracker of one scan's detections: detections in, the current tracks out."""

    def update(self, detections: Detections) -> Tracks:
        """Process one scan."""
        ...


class LegsAdapter:
    """A :class:`DetectionsTracker` as a frame tracker that consumes the frame's legs.

    The legs arrive in the frame's coordinate frame. In the sensor frame they are handed
    on without a sensor pose, so that the wrapped tracker (which tracks in the world frame
    whenever its first detections carry a pose) stays in the frame the pipeline chose; the
    pose is put back on the tracks for writers that convert frames.

    Attributes:
        tracker: The wrapped tracker (for its own statistics, e.g. ``n_hypotheses``).
    """

    consumes: frozenset[FrameField] = frozenset({"legs"})

    def __init__(self, tracker: DetectionsTracker) -> None:
        self.tracker = tracker

    def update(self, frame: Frame) -> Tracks:
        """Track the legs of ``frame``."""
        legs = frame.legs
        if legs is None:
            raise ConfigError(
                f"frame {frame.index} has no leg detections",
                hint="put a leg detection stage before this tracker",
            )
        if legs.frame == "sensor" and legs.sensor_pose is not None:
            legs = replace(legs, sensor_pose=None)
        tracks = self.tracker.update(legs)
        if tracks.sensor_pose is None and frame.sensor_pose is not None:
            tracks = replace(tracks, sensor_pose=frame.sensor_pose)
        return tracks

    def __getattr__(self, name: str) -> Any:
        # statistics of the wrapped tracker (dropped_detections, n_hypotheses, ...)
        if name == "tracker":
            raise AttributeError(name)
        return getattr(self.tracker, name)


class LegMHTAdapter(LegsAdapter):
    """The leg MHT as a frame tracker that also asks a static world model (the pipeline
    feeds the model each frame before :meth:`update`; people policy ``tracks`` only), and
    whose person layer is told whether the lasers ride on a robot that has moved
    (:class:`~laserpeople.tracking.robot_motion.MotionWatch`; people policy ``tracks``)."""

    def __init__(self, tracker: DetectionsTracker) -> None:
        super().__init__(tracker)
        self._watch: MotionWatch | None = None

    def update(self, frame: Frame) -> Tracks:
        """Track the legs of ``frame``; the person layer is told when the robot has moved in
        a world-frame run (never in a sensor-frame run, whose tracks are not predicted with
        the robot's motion, nor for a static laser: both keep the person layer's rules for
        a still laser)."""
        people = getattr(self.tracker, "person_tracks", None)
        if people is not None:
            if self._watch is None:
                self._watch = MotionWatch(people.params.motion)
            world = frame.frame == "world" and bool(frame.scans)
            people.moving = world and self._watch(frame.sensor_pose)
        return super().update(frame)

    def watch_from(self, pose: Pose2D | None) -> None:
        """Measure whether the robot has moved from ``pose`` (the run's first pose; None:
        nothing learnt), as if the first frame :meth:`update` tracks came later (a caller
        that holds back the frames of a still laser and tracks only the last of them)."""
        people = getattr(self.tracker, "person_tracks", None)
        if people is None:
            return
        if self._watch is None:
            self._watch = MotionWatch(people.params.motion)
        self._watch(pose)

    @property
    def wants_static_model(self) -> bool:
        """True when the person layer asks a static world model (policy ``tracks``)."""
        return getattr(self.tracker, "person_tracks", None) is not None

    static_model_off = "the arras people policy has none"
    """Why no static world model is wanted, when it is not (for the user)."""

    def use_static_model(self, model: StaticWorldModel | None) -> None:
        """Let the person layer ask ``model`` (None: no model).

        Raises:
            ConfigError: the people policy (``arras``, 000 Sec. 3.3) has no use for one.
        """
        people = getattr(self.tracker, "person_tracks", None)
        if people is None:
            raise ConfigError(
                "the arras people policy (000 Sec. 3.3) does not use a static world model",
                hint="use --people-policy tracks, or --background none",
            )
        people.static_model = model


@dataclass(frozen=True)
class TrackerEntry:
    """A registered tracker.

    Attributes:
        name: Command-line name.
        params_ref: Frozen parameter dataclass (its ``config_section`` is the TOML section),
            or where to import it from (``"package.module:Class"``), so that a command
            imports only the trackers it runs (:attr:`params_cls` gives the class).
        factory: Builds the frame tracker from parameters.
        description: One line for ``--help``.
        consumes: What the tracker reads of a frame (the pipeline adds the stages that fill
            these fields, or refuses to build).
    """

    name: str
    params_ref: type | str
    factory: Callable[[Any], FrameTracker]
    description: str
    consumes: frozenset[FrameField] = frozenset({"legs"})

    @property
    def params_cls(self) -> type:
        """The parameter class (imported at the first use when given by name)."""
        ref = self.params_ref
        if isinstance(ref, str):
            module, _, name = ref.partition(":")
            cls: type = getattr(importlib.import_module(module), name)
            return cls
        return ref

    def make(self, params: Any | None = None) -> FrameTracker:
        """A new tracker with ``params`` (default: the parameter class's defaults); one
        that reads frame points comes behind the shared point guard
        (:class:`~laserpeople.tracking.point_guard.GuardedTracker`)."""
        tracker = self.factory(self.params_cls() if params is None else params)
        if self.consumes & POINT_FIELDS:
            return GuardedTracker(tracker)
        return tracker


POINT_FIELDS: frozenset[FrameField] = frozenset({"points", "foreground", "clusters"})
"""Frame fields of point trackers: those get the shared point guard."""

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
        from laserpeople.spelling import did_you_mean

        known = sorted(TRACKERS)
        raise ConfigError(
            f"unknown tracker {name!r}{did_you_mean(name, known, lead='; ')}",
            hint=f"choose one of: {', '.join(known)}",
        ) from None


def _leg_mht(params: Any) -> FrameTracker:
    from laserpeople.tracking.legs import LegMHTTracker

    return LegMHTAdapter(LegMHTTracker(params))


def _nn(params: Any) -> FrameTracker:
    from laserpeople.tracking.nearest import NearestNeighbourTracker

    return LegsAdapter(NearestNeighbourTracker(params))


def _group_mht(params: Any) -> FrameTracker:
    from laserpeople.tracking.groups import GroupMHTTracker

    return GroupMHTTracker(params)


def _feet_pf(params: Any) -> FrameTracker:
    from laserpeople.tracking.particle.feet import FeetTracker

    return FeetTracker(params)


def _upper_body_pf(params: Any) -> FrameTracker:
    from laserpeople.tracking.particle.upper_body import UpperBodyTracker

    return UpperBodyTracker(params)


def _register_builtin() -> None:
    # (parameter classes by name: importing every tracker costs a tenth of a second that
    # a run of one tracker need not pay)
    register(
        TrackerEntry(
            "leg-mht",
            "laserpeople.tracking.legs:LegTrackerParams",
            _leg_mht,
            "multi-hypothesis leg tracker with adaptive occlusion probabilities (000 Sec. 3)",
        )
    )
    register(
        TrackerEntry(
            "nn",
            "laserpeople.tracking.nearest:NearestNeighbourParams",
            _nn,
            "global-nearest-neighbour Kalman leg tracker (baseline)",
        )
    )
    register(
        TrackerEntry(
            "group-mht",
            "laserpeople.tracking.groups.tracker:GroupTrackerParams",
            _group_mht,
            "multi-model MHT of groups with split, merge and group size (000 Sec. 4)",
            consumes=frozenset({"points", "foreground"}),
        )
    )
    register(
        TrackerEntry(
            "feet-pf",
            "laserpeople.tracking.particle.feet:FeetParams",
            _feet_pf,
            "feet-height particle filters with a walking model, on fused foreground points "
            "(004 Sec. 2.1)",
            consumes=frozenset({"points", "foreground"}),
        )
    )
    register(
        TrackerEntry(
            "upper-body-pf",
            "laserpeople.tracking.particle.upper_body:UpperBodyParams",
            _upper_body_pf,
            "upper-body-height particle filters in Voronoi cells, on fused foreground points "
            "(004 Sec. 2.2)",
            consumes=frozenset({"points", "foreground"}),
        )
    )


_register_builtin()


# --- Cluster Sorting Algorithm (002 Sec. 2), a FrameTracker on raw foreground points ---
def _csa(params: Any) -> FrameTracker:
    from laserpeople.tracking.csa import ClusterSortingTracker

    return ClusterSortingTracker(params)


register(
    TrackerEntry(
        "csa",
        "laserpeople.tracking.csa:CSAParams",
        _csa,
        "Cluster Sorting Algorithm on raw foreground points, KFA/Viterbi switching (002)",
        consumes=frozenset({"points", "foreground", "legs"}),  # legs: [csa] moving_people
    )
)


def with_people_policy(params: Any, policy: str, tracker_name: str) -> Any:
    """``params`` with ``people_policy`` replaced (``--people-policy``).

    Raises :class:`~laserpeople.errors.ConfigError` when the tracker has no people policy
    (only ``leg-mht`` has one) or the policy is unknown.
    """
    if not hasattr(params, "people_policy"):
        raise ConfigError(f"--people-policy applies to leg-mht, not to {tracker_name!r}")
    try:
        return replace(params, people_policy=policy)
    except ValueError as exc:
        raise ConfigError(f"--people-policy: {exc}") from None
