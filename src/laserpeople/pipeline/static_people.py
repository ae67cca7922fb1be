"""The static world model that a people tracker asks, fed by the pipeline (issue 10).

The leg MHT (people policy ``tracks``) does not read the foreground: it asks a
:class:`~laserpeople.background.StaticWorldModel` how long the place of a person candidate
has been static (:meth:`~laserpeople.background.StaticWorldModel.static_time`) and does not
confirm a candidate on a place static for longer than ``people.static_time`` until it has
moved (``tracking/person_tracks.py``). :class:`PeopleStaticModel` is the preprocess stage
(after :class:`~laserpeople.pipeline.Fuse`) that learns that model from every frame and
answers the tracker. It holds one of the models of ``track --background``
(:func:`~laserpeople.pipeline.background.background_stage`) and adds one rule:

**No sensor-frame model on a moving laser.** A run without poses is tracked in the sensor
frame, where a person walking with the robot (a followed person) stays in one place and
would look like furniture. In the sensor frame the stage therefore watches the lasers
themselves: a per-beam range histogram learned over its first seconds explains most returns
of a laser that stands still (people cover a few beams) and few of one that moves. When the
median share of returns it does not explain, over ``window`` seconds, exceeds
``moved_share``, the laser moves: the model is dropped for the rest of the run (every place
is 0 s static, every point foreground) and :meth:`PeopleStaticModel.describe` says so.
Until the lasers have been seen still for ``still_seconds`` after learning, the model
learns but answers 0 s static (a person walking with a robot that has not yet been found
moving must not look static).
Measured shares (histogram of the first 2 s, 0.05 m bins): static lasers, median (90th
percentile) over the scans after learning 0.20 (0.27) on the leg_tracker demo bag, 0.09
(0.17) on corridor.bag, 0.05 (0.10) on the MiR bag; the robot following a person outdoors
1.00 (1.00; 10th percentile 0.75). A ``--map`` is in the world frame and is refused in a
sensor-frame run.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any, Protocol, TypeGuard

import numpy as np
from numpy.typing import NDArray

from laserpeople.background import StaticWorldModel
from laserpeople.errors import ConfigError
from laserpeople.frame import Frame, FrameField
from laserpeople.pipeline.background import (
    SensorMotionCheck,
    SensorMotionParams,
    StaticWorldParams,
    background_stage,
    describe_background,
    occupancy_model,
)
from laserpeople.pipeline.stages import Stage


class PeopleStaticModel:
    """The static world model of a people tracker as a preprocess stage (module docstring).

    Args:
        choice: ``auto`` (the occupancy grid, which answers how long a place has been
            static; measured on the real MiR bag, see docs/people-benchmarks.md),
            ``histogram``, ``occupancy`` (see
            :func:`~laserpeople.pipeline.background.background_stage`) or a model object.
        map_path: ROS ``map.yaml`` seeding the occupancy grid (world-frame runs only).
        motion: When a laser of a sensor-frame run counts as moving (default: that of
            ``static``).
        static: The models' parameters (None: defaults).

    Attributes:
        model: The model in use (None once dropped).
        frame: The coordinate frame of the run (None before the first frame).
        motion: The sensor-frame motion check (None in a world-frame run).
    """

    consumes: frozenset[FrameField] = frozenset({"scans", "points"})
    provides: frozenset[FrameField] = frozenset({"foreground"})

    def __init__(
        self,
        choice: str | Stage,
        map_path: str | Path | None = None,
        motion: SensorMotionParams | None = None,
        static: StaticWorldParams | None = None,
    ) -> None:
        static = static if static is not None else StaticWorldParams()
        model = (
            occupancy_model(map_path, static.occupancy)
            if choice == "auto"
            else background_stage(choice, map_path, static)
        )
        if model is None:
            raise ConfigError("PeopleStaticModel needs a model", hint="give auto or occupancy")
        self.model: Any = model
        self.map_path = map_path
        self.frame: str | None = None
        self._motion_params = motion if motion is not None else static.sensor_motion
        self.motion: SensorMotionCheck | None = None
        self._name = describe_background(model)
        self.query_cpu = 0.0
        """Process CPU time [s] spent answering :meth:`static_time` (the stage's own time
        learning is the pipeline's, :meth:`~laserpeople.pipeline.core.Pipeline.stage_cpu`)."""
        self.fill_foreground = True
        """False when nothing after this stage reads ``foreground`` (the leg MHT does not):
        a model that can learn without it (the occupancy grid) then leaves the frame's
        foreground as it is, which saves computing every point's static time."""

    @property
    def dropped_at(self) -> int | None:
        """Frame index at which the model was dropped because the laser moves (None: kept)."""
        return None if self.motion is None else self.motion.moved_at

    def __call__(self, frame: Frame) -> Frame:
        """Learn from ``frame`` and return it with ``foreground`` from the model (all True
        once the model is dropped), or with its own foreground when :attr:`fill_foreground`
        is False (the foreground of another stage, e.g. the trackers' static world model,
        is not overwritten)."""
        if self.frame is None:
            self.frame = frame.frame
            if frame.frame == "sensor":
                if self.map_path is not None:
                    raise ConfigError(
                        "--map is a world-frame map, but this run is tracked in the sensor "
                        "frame (the recording has no sensor poses)",
                        hint="give poses (--world-frame, --mount) or drop --map",
                    )
                self.motion = SensorMotionCheck(self._motion_params)
        if self.motion is not None and self.model is not None:
            self.motion(frame)
            if self.motion.moved_at is not None:
                self.model = None
        if self.model is None:
            if not self.fill_foreground:
                return frame
            n = 0 if frame.points is None else len(frame.points)
            return replace(frame, foreground=np.ones(n, dtype=bool))
        learn_only = getattr(self.model, "learn_frame", None)
        if not self.fill_foreground and learn_only is not None:
            learnt: Frame = learn_only(frame)  # nobody reads the foreground: not computed
            return learnt
        out: Frame = self.model(frame)
        if not self.fill_foreground:  # another stage's foreground stays the trackers'
            return replace(out, foreground=frame.foreground)
        return out

    def static_time(self, positions: NDArray[np.float64]) -> NDArray[np.float64]:
        """How long [s] ``positions`` (M, 2) [m] have been static; zeros once dropped, and in
        a sensor-frame run until the lasers have been seen still for ``still_seconds``."""
        t0 = time.process_time()
        pos = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
        if self.model is None or (self.motion is not None and not self.motion.settled):
            out = np.zeros(len(pos))
        else:
            out = np.asarray(self.model.static_time(pos), dtype=np.float64)
        self.query_cpu += time.process_time() - t0
        return out

    def describe(self) -> str:
        """One line for the user: which model the people tracker used, and in which frame."""
        if self.dropped_at is not None:
            return (
                f"static world model for people: none from frame {self.dropped_at} (the "
                "laser moves and the recording has no poses: in the sensor frame a person "
                "walking with the robot would look static; give poses with --world-frame or "
                "--mount to use the occupancy grid)"
            )
        where = f" in the {self.frame} frame" if self.frame is not None else ""
        line = describe_background(self.model, where)
        return line.replace("static world model:", "static world model for people:", 1)


def people_static_model(
    choice: str | Stage | None,
    map_path: str | Path | None = None,
    motion: SensorMotionParams | None = None,
    static: StaticWorldParams | None = None,
) -> PeopleStaticModel | None:
    """The stage for ``choice`` (None or ``"none"``: no model; ``--map`` with ``none`` is a
    ConfigError); ``static`` holds the models' parameters (None: defaults)."""
    if choice is None or choice == "none":
        background_stage("none", map_path)  # raises for --map with none
        return None
    return PeopleStaticModel(choice, map_path, motion, static)


def static_world_cpu(pipeline: Any) -> float:
    """Process CPU time [s] the static world models of ``pipeline`` (a
    :class:`~laserpeople.pipeline.core.Pipeline`) took so far: the people's model learning
    and answering the tracker, and the trackers' foreground model."""
    from laserpeople.pipeline.background import background_of

    models: list[object] = [s for s in pipeline.stages if isinstance(s, PeopleStaticModel)]
    foreground = background_of(pipeline.stages)
    if foreground is not None and foreground not in models:
        models.append(foreground)
    cpu = sum(pipeline.stage_cpu(m) for m in models)
    return cpu + sum(m.query_cpu for m in models if isinstance(m, PeopleStaticModel))


def describe_static_cost(pipeline: Any, loop_cpu: float) -> str:
    """One line for the user: what the static world models of ``pipeline`` cost, in CPU
    seconds, per frame and as a share of ``loop_cpu`` [s], the CPU time of the whole
    tracking loop (reading, detection, tracking, writing); "" without a model."""
    cpu = static_world_cpu(pipeline)
    frames = pipeline.stats.frames
    if cpu <= 0.0 or frames == 0:
        return ""
    share = f", {cpu / loop_cpu:.0%} of the tracking loop's CPU" if loop_cpu > 0.0 else ""
    return (
        f"static world model cost: {cpu:.2f} s CPU ({1e3 * cpu / frames:.2f} ms per frame"
        f"{share}; --background none runs without it)"
    )


class StaticModelUser(Protocol):
    """A tracker that asks a static world model (the leg MHT's ``tracks`` people policy,
    :class:`~laserpeople.tracking.registry.LegMHTAdapter`; the group tracker). One that
    can do without may say why in a ``static_model_off`` string attribute."""

    @property
    def wants_static_model(self) -> bool:
        """True when the tracker asks a model (it may depend on its parameters)."""
        ...

    def use_static_model(self, model: StaticWorldModel | None) -> None:
        """Ask ``model`` from now on (None: none)."""
        ...


def uses_static_model(tracker: object) -> TypeGuard[StaticModelUser]:
    """True when ``tracker`` asks a static world model (``use_static_model``) and wants one
    (its ``wants_static_model`` is true)."""
    return callable(getattr(tracker, "use_static_model", None)) and bool(
        getattr(tracker, "wants_static_model", False)
    )


def reads_foreground(tracker: object) -> bool:
    """Whether ``tracker`` reads the frames' ``foreground`` (directly or via clusters)."""
    return bool(frozenset(getattr(tracker, "consumes", ())) & {"foreground", "clusters"})


def describe_people_model(tracker: object, stages: Sequence[object]) -> str:
    """One line for the user naming the static world model of a leg MHT's people (empty
    for a tracker that has no use for one)."""
    model = next((s for s in stages if isinstance(s, PeopleStaticModel)), None)
    if model is not None:
        return model.describe()
    if uses_static_model(tracker):
        return "static world model for people: none (--background none)"
    if callable(getattr(tracker, "use_static_model", None)):
        why = getattr(tracker, "static_model_off", "it wants none")
        return f"static world model for people: none ({why})"
    return ""


class StaticFed:
    """A frame tracker that feeds a static world model itself (for callers without a
    pipeline, e.g. ``benchmarks/people_suite.py``): each frame goes through
    :class:`~laserpeople.pipeline.Fuse` and ``model`` before ``tracker.update``.

    Attributes:
        tracker: The wrapped frame tracker (its model set with ``use_static_model``).
        model: The model stage.
    """

    def __init__(self, tracker: Any, model: PeopleStaticModel) -> None:
        from laserpeople.pipeline.preprocess import Fuse

        self.tracker = tracker
        self.model = model
        self._fuse = Fuse()
        tracker.use_static_model(model)
        self.consumes: frozenset[FrameField] = frozenset(tracker.consumes) | {"scans"}
        model.fill_foreground = reads_foreground(tracker)

    def update(self, frame: Frame) -> Any:
        """Learn the model from ``frame``, then track it."""
        if frame.points is None:
            frame = self._fuse(frame)
        return self.tracker.update(self.model(frame))

    def __getattr__(self, name: str) -> Any:
        if name == "tracker":
            raise AttributeError(name)
        return getattr(self.tracker, name)


__all__ = [
    "PeopleStaticModel",
    "SensorMotionCheck",
    "SensorMotionParams",
    "StaticFed",
    "StaticModelUser",
    "describe_people_model",
    "describe_static_cost",
    "people_static_model",
    "reads_foreground",
    "static_world_cpu",
    "uses_static_model",
]
