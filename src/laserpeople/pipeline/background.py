"""Which static world model a pipeline runs after :class:`~laserpeople.pipeline.Fuse`.

A tracker that consumes ``foreground`` should not see walls as people or groups. The
choices (``track --background``):

- ``histogram``: per-beam range histograms (004 Sec. 2,
  :class:`~laserpeople.background.beam_histogram.BeamHistogramBackground`), learned online
  over the first ``learn_seconds`` of the recording; for lasers that do not move.
- ``occupancy``: the decaying occupancy grid of
  :class:`~laserpeople.background.occupancy.OccupancyGrid` (optionally seeded from a ROS
  ``map.yaml``); for a moving robot.
- ``auto``: the histogram while every laser keeps its first pose (a sensor-frame run, or
  constant poses), switching to the occupancy grid for good at the first frame in which a
  laser has moved by more than ``moved_distance`` or turned by more than ``moved_angle``.
  A sensor-frame run has no poses to tell: there :class:`SensorMotionCheck` watches the
  histogram's own share of returns it does not explain, and once a laser moves no model
  is left (in the sensor frame of a moving laser nothing stays put): every point is
  foreground from then on, and :meth:`AutoBackground.describe` says from which frame.
  On a recording whose lasers stand still throughout, the histogram also takes the walls
  the whole recording shows beyond what it learns (``[auto_background] prelearn``,
  :mod:`laserpeople.pipeline.prelearn`).
- ``none``: no model; every point stays foreground.

Under ``auto`` the foreground is then narrowed to the points near leg detections
(:mod:`laserpeople.pipeline.leg_foreground`, ``[leg_foreground] use``): by default once a
laser moves (without poses, where every point would be foreground; with poses, where the
occupancy grid has not learned what the robot drives past), not while the lasers stand
still. :meth:`AutoBackground.describe_foreground` says which foreground ran from which
frame.
"""

from __future__ import annotations

import bisect
import copy
import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import NDArray

from laserpeople.background import StaticWorldModel
from laserpeople.background.beam_histogram import BeamHistogramParams
from laserpeople.background.occupancy import OccupancyMap, OccupancyParams
from laserpeople.config import param
from laserpeople.errors import ConfigError
from laserpeople.frame import Frame, FrameField
from laserpeople.pipeline.leg_foreground import LegForeground, LegForegroundParams
from laserpeople.pipeline.stages import Stage, provided_by
from laserpeople.pipeline.static_tracks import StaticTrackParams
from laserpeople.scan import Pose2D

if TYPE_CHECKING:
    from laserpeople.identity.leg_width import LegReidParams
    from laserpeople.pipeline.prelearn import Prelearned
    from laserpeople.tracking.legs import LegTrackerParams

BackgroundChoice = Literal["auto", "histogram", "occupancy", "none"]
BACKGROUND_CHOICES: tuple[str, ...] = ("auto", "histogram", "occupancy", "none")


@dataclass(frozen=True)
class AutoBackgroundParams:
    """When ``auto`` takes a laser to have moved, and whether it learns the per-beam
    histogram of still lasers from the whole recording first
    (:mod:`laserpeople.pipeline.prelearn`)."""

    config_section = "auto_background"

    moved_distance: float = param(
        0.05,
        "assumption: well above localisation jitter of a robot that stands (~0.01 m)",
        "a laser that moved farther than this from its first pose is on a moving robot",
        "m",
    )
    moved_angle: float = param(
        0.02,
        "assumption: 0.02 rad displaces a return at 5 m by 0.1 m, the histogram tolerance",
        "a laser that turned more than this from its first pose is on a moving robot",
        "rad",
    )
    prelearn: bool = param(
        True,
        "assumed (not in 004, which learns from an empty room): a recording can be read whole "
        "before it is tracked; measured on random-groups and the real bags (docs/recording.md)",
        "on a recording whose lasers stand still (the tests above), the recording is read "
        "once before tracking, and the per-beam histogram that gives trackers of points their "
        "foreground takes as static too the ranges frequent in the whole recording that lie "
        "beyond what its learning period finds static (the wall behind a person in view from "
        "the start), so that such a person is foreground from the first scan; on one whose "
        "lasers move (with poses, no --map) it is read again and the occupancy grid is "
        "seeded with what stayed put in it (map_min_hits, map_hit_share, map_hit_reach); "
        "false: only the first [beam_histogram] learn_seconds (004; a live run always is) "
        "and the grid learns online",
    )
    prelearn_scans: int = param(
        3000,
        "assumed: 5 minutes at 10 Hz; the pass reads every scan, the histogram counts these",
        "the histogram of a longer recording is learned from this many of its frames, evenly "
        "spread (every k-th; all of them when the reader does not know their number); so is "
        "the map of a moving robot's recording",
    )
    map_min_hits: int = param(
        5,
        "measured: random-groups moving tuning seeds (docs/recording.md)",
        "with prelearn on a recording whose lasers move (with poses, no --map): a cell of "
        "the map of the whole recording that seeds the occupancy grid is static when this "
        "many frames or more had a return in it",
        "frames",
    )
    map_hit_share: float = param(
        0.97,
        "measured: random-groups moving tuning seeds, 0.5 / 0.8 / 0.9 / 0.97 (people who "
        "stand for most of a short recording; docs/recording.md)",
        "... and at least this share of the frames that saw the cell (a return in it, or a "
        "beam through it) had a return in it",
    )
    map_hit_reach: float = param(
        0.2,
        "measured: random-groups moving tuning seeds, 0 / 0.2 / 0.3 m, and the real lobby "
        "recording (docs/recording.md)",
        "... where a frame's beams passing within this distance of one of its returns do "
        "not count as seeing the cell (poses that drift by centimetres between passes, thin "
        "posts between the beams that hit them)",
        "m",
    )

    paper_preset = MappingProxyType({"prelearn": False})  # the online learning of 004's model

    def __post_init__(self) -> None:
        if self.prelearn_scans < 1:
            raise ValueError(f"prelearn_scans must be at least 1, got {self.prelearn_scans}")
        if self.map_min_hits < 1:
            raise ValueError(f"map_min_hits must be at least 1, got {self.map_min_hits}")
        if not 0.0 < self.map_hit_share <= 1.0:
            raise ValueError(f"map_hit_share must be in (0, 1], got {self.map_hit_share}")
        if not (0.0 <= self.map_hit_reach <= 1.0):
            raise ValueError(f"map_hit_reach must be in [0, 1] m, got {self.map_hit_reach}")


@dataclass(frozen=True)
class SensorMotionParams:
    """When a laser of a sensor-frame run counts as moving (module docstring)."""

    config_section = "sensor_motion"

    moved_share: float = param(
        0.5,
        "measured (docs/people-benchmarks.md): <= 0.27 on three still real lasers, >= 0.75 on "
        "the moving one",
        "a laser whose returns are this much off its learned per-beam ranges moves",
    )
    window: float = param(
        2.0,
        "assumption: longer than a person crossing close in front of the laser",
        "the share is the median over this many seconds",
        "s",
    )

    still_seconds: float = param(
        10.0,
        "measured (docs/people-benchmarks.md): the real following robot is found moving 5.5 s "
        "after learning",
        "the model answers (static times above 0) only once the laser has been seen still "
        "this long after learning",
        "s",
    )

    def __post_init__(self) -> None:
        if not 0.0 < self.moved_share < 1.0:
            raise ValueError("moved_share must be in (0, 1)")
        if not self.window > 0.0 or self.still_seconds < 0.0:
            raise ValueError("window must be positive and still_seconds not negative")


class SensorMotionCheck:
    """Tells from the scans alone whether a laser moves (sensor-frame runs; module
    docstring): the median share of returns off a per-beam range histogram learned over the
    first seconds.

    Attributes:
        moved_at: Index of the frame at which a laser was seen to move (None: not yet).
        share: The last median share of unexplained returns (nan while learning).
    """

    def __init__(self, params: SensorMotionParams | None = None) -> None:
        from laserpeople.background.beam_histogram import BeamHistogramBackground

        self.params = params or SensorMotionParams()
        self._histogram = BeamHistogramBackground()
        self._shares: deque[tuple[float, float]] = deque()
        self._ranked: list[float] = []  # the shares of ``_shares``, sorted
        self.moved_at: int | None = None
        self.share = math.nan
        self._checked: tuple[float, float] | None = None  # first and last stamp checked

    @property
    def still_for(self) -> float:
        """Seconds the lasers have been seen still after learning (0 once one moved)."""
        if self.moved_at is not None or self._checked is None:
            return 0.0
        return self._checked[1] - self._checked[0]

    @property
    def settled(self) -> bool:
        """True once the lasers have been seen still for ``still_seconds``."""
        return self.still_for >= self.params.still_seconds

    def __call__(self, frame: Frame) -> bool:
        """Learn from ``frame`` (it needs ``points``); True once a laser has moved."""
        if self.moved_at is not None:
            return True
        learning = self._histogram.learning
        fg = self._histogram.learn_foreground(frame)
        if learning:
            return False
        return self.record(frame, fg)

    def record(self, frame: Frame, foreground: NDArray[np.bool_]) -> bool:
        """Count ``foreground`` (N,), the returns of ``frame`` that a per-beam histogram
        learned beforehand does not explain (a caller's own histogram; :meth:`__call__`
        uses this check's); True once a laser has moved."""
        if self.moved_at is not None:
            return True
        fg = np.asarray(foreground, dtype=bool)
        if len(fg) == 0:
            return False
        first = frame.stamp if self._checked is None else self._checked[0]
        self._checked = (first, frame.stamp)
        share = int(np.count_nonzero(fg)) / len(fg)
        self._shares.append((frame.stamp, share))
        bisect.insort(self._ranked, share)
        while self._shares and frame.stamp - self._shares[0][0] > self.params.window:
            _, old = self._shares.popleft()
            del self._ranked[bisect.bisect_left(self._ranked, old)]
        self.share = _median_of_sorted(self._ranked)
        if self.share > self.params.moved_share:
            self.moved_at = frame.index
            return True
        return False


def _median_of_sorted(values: list[float]) -> float:
    """The median of the sorted ``values`` as ``statistics.median`` gives it (the middle
    value, or the mean of the two middle ones; NaN when empty)."""
    n = len(values)
    if n == 0:
        return math.nan
    if n % 2:
        return values[n // 2]
    return (values[n // 2 - 1] + values[n // 2]) / 2


def _leg_tracker_defaults() -> LegTrackerParams:
    """The leg MHT's default parameters (imported at use: the tracker imports pipeline
    modules)."""
    from laserpeople.tracking.legs import LegTrackerParams

    return LegTrackerParams()


def _leg_reid_defaults() -> LegReidParams:
    """The default parameters of re-identification by leg widths (imported at use: it
    imports the tracking package)."""
    from laserpeople.identity.leg_width import LegReidParams

    return LegReidParams()


@dataclass(frozen=True)
class StaticWorldParams:
    """The parameters of every static world model, each read from its own ``--config``
    section (:func:`load_static_world`): ``[occupancy]`` (the grid), ``[beam_histogram]``
    (the per-beam histogram), ``[auto_background]`` (when ``auto`` switches to the grid),
    ``[sensor_motion]`` (when the people's model of a sensor-frame run is dropped),
    ``[static_tracks]`` (which person tracks of trackers without a static world of their
    own are left out, :mod:`laserpeople.pipeline.static_tracks`), ``[leg_foreground]``
    (when ``auto`` keeps only points near legs, :mod:`laserpeople.pipeline.leg_foreground`)
    and ``[leg_tracker]`` (the leg MHT that stage runs); with them, ``[leg_reid]``, the
    stage after a tracker of points that gives people who come back their old ids by their
    leg widths (:mod:`laserpeople.identity.leg_width`)."""

    occupancy: OccupancyParams = field(default_factory=OccupancyParams)
    beam_histogram: BeamHistogramParams = field(default_factory=BeamHistogramParams)
    auto_background: AutoBackgroundParams = field(default_factory=AutoBackgroundParams)
    sensor_motion: SensorMotionParams = field(default_factory=SensorMotionParams)
    static_tracks: StaticTrackParams = field(default_factory=StaticTrackParams)
    leg_foreground: LegForegroundParams = field(default_factory=LegForegroundParams)
    leg_tracker: LegTrackerParams = field(default_factory=_leg_tracker_defaults)
    """The ``[leg_tracker]`` section: the leg MHT that ``[leg_foreground]`` runs to hold its
    people's legs uses it (see :func:`~.leg_foreground.stage_leg_tracker`)."""
    leg_reid: LegReidParams = field(default_factory=_leg_reid_defaults)
    """The ``[leg_reid]`` section (:func:`~.recording.leg_reid_stage`)."""

    @staticmethod
    def sections_for(consumes: frozenset[str]) -> list[type]:
        """The sections that a tracker reading ``consumes`` of a frame is given: all of
        :meth:`sections` for a tracker of laser points; without ``[leg_foreground]``, its
        ``[leg_tracker]`` and ``[leg_reid]`` for a tracker of leg detections (only the
        points' foreground keeps points near legs; the leg MHT re-identifies people
        itself)."""
        from laserpeople.identity.leg_width import LegReidParams
        from laserpeople.tracking.legs import LegTrackerParams
        from laserpeople.tracking.registry import POINT_FIELDS

        every = StaticWorldParams.sections()
        if consumes & POINT_FIELDS:
            return every
        points_only = (LegForegroundParams, LegTrackerParams, LegReidParams)
        return [c for c in every if c not in points_only]

    @staticmethod
    def sections() -> list[type]:
        """The parameter classes (TOML sections) it reads."""
        from laserpeople.identity.leg_width import LegReidParams
        from laserpeople.tracking.legs import LegTrackerParams

        return [
            OccupancyParams,
            BeamHistogramParams,
            AutoBackgroundParams,
            SensorMotionParams,
            StaticTrackParams,
            LegForegroundParams,
            LegTrackerParams,
            LegReidParams,
        ]


def static_world_preset(cls: type, preset: str | None) -> str | None:
    """The preset the static world section ``cls`` is read with: ``preset``, except for
    ``[leg_tracker]``, read without one. That section is here the MHT the leg foreground
    stage runs for a tracker of points (:func:`~.leg_foreground.stage_leg_tracker`); no
    paper has that stage, and the leg MHT's paper values (000's people from leg pairs)
    are those of ``--tracker leg-mht``. Under them the stage holds only validated pairs'
    legs: on the real person-following recording ``feet-pf --preset paper`` identity
    recall 0.641 -> 0.443, ``upper-body-pf`` 0.566 -> 0.331 (docs/papers.md)."""
    from laserpeople.tracking.legs import LegTrackerParams

    return None if cls is LegTrackerParams else preset


def load_static_world(path: str | Path | None, preset: str | None = None) -> StaticWorldParams:
    """The static world models' parameters from the TOML file ``path`` (None: defaults);
    unknown keys, wrong types and non-finite values are a ConfigError naming the key;
    ``preset`` "paper" starts each section from the papers' values
    (:func:`static_world_preset`: not ``[leg_tracker]``)."""
    from laserpeople.config import load_config
    from laserpeople.identity.leg_width import LegReidParams
    from laserpeople.tracking.legs import LegTrackerParams

    return StaticWorldParams(
        occupancy=load_config(OccupancyParams, path, preset),
        beam_histogram=load_config(BeamHistogramParams, path, preset),
        auto_background=load_config(AutoBackgroundParams, path, preset),
        sensor_motion=load_config(SensorMotionParams, path, preset),
        static_tracks=load_config(StaticTrackParams, path, preset),
        leg_foreground=load_config(LegForegroundParams, path, preset),
        leg_tracker=load_config(
            LegTrackerParams, path, static_world_preset(LegTrackerParams, preset)
        ),
        leg_reid=load_config(LegReidParams, path, preset),
    )


def pose_moved(first: dict[str, Pose2D], frame: Frame, params: AutoBackgroundParams) -> bool:
    """Whether a laser of ``frame`` (world frame; a sensor-frame frame never is) has moved
    farther than ``moved_distance`` or turned more than ``moved_angle`` from its first pose,
    kept in ``first`` (laser name -> pose; the first pose of a laser is added)."""
    if frame.frame == "sensor":
        return False
    for scan in frame.scans:
        if scan.pose is None:
            continue
        start = first.setdefault(scan.sensor, scan.pose)
        turn = math.remainder(scan.pose.theta - start.theta, math.tau)
        if (
            math.hypot(scan.pose.x - start.x, scan.pose.y - start.y) > params.moved_distance
            or abs(turn) > params.moved_angle
        ):
            return True
    return False


class AutoBackground:
    """The per-beam histogram while the lasers stand still, the occupancy grid once one
    moves (module docstring). A :class:`~laserpeople.background.StaticWorldModel` stage.

    Attributes:
        model: The model in use (None once dropped).
        chosen: ``"histogram"``, ``"occupancy"`` or ``"none"`` (what :attr:`model` is;
            ``"none"``: a sensor-frame run whose laser moves).
        switched_at: Index of the frame at which a laser was seen to move (None: never).
        motion: The check of a sensor-frame run (None in a world-frame run).
        legs: The stage that narrows the foreground to points near legs (None: not used
            yet, :mod:`laserpeople.pipeline.leg_foreground`).
        legs_from: Index of the first frame narrowed to points near legs (None: none).
        laser_height: The laser's mount height [m] when the recording states it (None:
            unknown); at torso height the narrowing keeps torso-shaped runs too.
        legs_stage: The pipeline's leg detection stage (a tracker that consumes legs too):
            the narrowing and ``learn_people`` take its detections of each frame instead of
            detecting the frame again (None: they detect with ``detector``).
        learn_people: While the histogram learns, the points within ``[leg_foreground]
            radius`` of the legs of the people a leg MHT confirms are marked as people,
            whose ranges it does not learn as static, and the wall behind every leg
            detection is guessed (``[leg_foreground] learn_people_warmup``,
            ``[beam_histogram] people_share``; the CSA's ``[csa] background_people``).
    """

    consumes: frozenset[FrameField] = frozenset({"scans", "points"})
    provides: frozenset[FrameField] = frozenset({"foreground"})

    def __init__(
        self,
        params: AutoBackgroundParams | None = None,
        map_path: str | Path | None = None,
        static: StaticWorldParams | None = None,
        detector: object | None = None,
        *,
        steady: bool = False,
        learn_people: bool = False,
        legs_stage: object | None = None,
    ) -> None:
        from laserpeople.background.beam_histogram import BeamHistogramBackground

        self.static = static if static is not None else StaticWorldParams()
        self.params = params or self.static.auto_background
        self.map_path = map_path
        self._histogram = BeamHistogramBackground(self.static.beam_histogram)
        self.model: Stage | None = _as_stage(self._histogram)
        self.chosen = "histogram"
        self.switched_at: int | None = None
        self.motion: SensorMotionCheck | None = None
        self._first: dict[str, Pose2D] = {}
        self._detector = detector
        self._legs_stage = legs_stage
        self._steady = steady
        self.legs: LegForeground | None = None
        self.legs_from: int | None = None
        self.learn_people = learn_people
        self._people_legs: LegForeground | None = None
        self._learned_scans = 0
        self.laser_height: float | None = None
        """The laser's mount height [m] when the recording states it (None: unknown; see
        :func:`set_laser_height`)."""
        self.prelearned: Prelearned | None = None
        """What the pass over the whole recording before tracking learned (None: no pass,
        e.g. a live run; :meth:`use_prelearned`)."""

    def _wants_legs(self) -> bool:
        """Whether the model in use is narrowed to points near legs (``[leg_foreground]
        use``)."""
        use = self.static.leg_foreground.use
        if use == "always":
            return True
        if use == "moving":
            return self.chosen in ("none", "occupancy")
        if use == "no-poses":
            return self.chosen == "none"
        return False

    def _near_legs(self, frame: Frame) -> Frame:
        """``frame`` with its foreground narrowed to the points near legs, when wanted."""
        if not self._wants_legs():
            return frame
        if self.legs is None:
            self.legs = LegForeground(
                self.static.leg_foreground,
                self._detector,
                steady=self._steady,
                leg_tracker=self.static.leg_tracker,
                legs_stage=self._legs_stage,
            )
            self.legs_from = frame.index
        self.legs.moving = self.chosen == "occupancy"
        self.legs.torso = at_torso_height(self.laser_height)
        return self.legs(frame)

    def _people(
        self, frame: Frame
    ) -> tuple[NDArray[np.bool_], NDArray[np.bool_] | None, NDArray[np.bool_] | None]:
        """While the histogram learns: which points (N,) of ``frame`` lie within
        ``[leg_foreground] radius`` of a leg of a person the leg MHT tracks (not learned as
        static); which (N,) lie near any leg detection, whose wall behind is guessed; and
        the points near any leg that are foreground in the first ``learn_people_warmup``
        scans (None after them)."""
        from laserpeople.pipeline.leg_foreground import near_legs

        p = self.static.leg_foreground
        if self._people_legs is None:
            self._people_legs = LegForeground(
                p,
                copy.deepcopy(self._detector),
                leg_tracker=self.static.leg_tracker,
                legs_stage=self._legs_stage,
            )
        assert frame.points is not None
        pts = frame.points.points
        self._learned_scans += 1
        legs, people = self._people_legs.person_legs(frame)
        near = near_legs(pts, legs, p.radius)
        warm = near if self._learned_scans <= p.learn_people_warmup else None
        return near_legs(pts, legs[people], p.radius), near, warm

    def _moved(self, frame: Frame) -> bool:
        return pose_moved(self._first, frame, self.params)

    def use_prelearned(self, learned: Prelearned) -> None:
        """Learn the per-beam histogram with what the pass over the whole recording before
        tracking found beyond the learning period's ranges (``learned``,
        :mod:`laserpeople.pipeline.prelearn`; its ``model`` None: as without).
        Before the first frame only."""
        self.prelearned = learned
        if learned.model is not None and self.chosen == "histogram":
            self._histogram.use_whole_recording(learned.model)

    @property
    def recording_map(self) -> OccupancyMap | None:
        """The map of what stayed put in the whole recording (None: not counted)."""
        return None if self.prelearned is None else self.prelearned.grid_map

    def prefetch(self, frames: Sequence[Frame]) -> None:
        """Detect the legs of ``frames`` (frames about to come, in order) at once once the
        foreground is narrowed to points near legs (from then on every frame is; the same
        detections as one frame at a time, :meth:`LegForeground.prefetch`). Before, nothing:
        the narrowing's detector sees its first scan at the frame it starts."""
        if self.legs is not None and self._wants_legs():
            self.legs.prefetch(frames)

    def __call__(self, frame: Frame) -> Frame:
        """The frame with ``foreground`` from the model in use (every point once dropped),
        narrowed to the points near legs when ``[leg_foreground] use`` says so."""
        return self._near_legs(self._model_foreground(frame))

    def _model_foreground(self, frame: Frame) -> Frame:
        if self.chosen == "histogram" and self._moved(frame):
            self.model = occupancy_model(self.map_path, self.static.occupancy, self.recording_map)
            self.chosen = "occupancy"
            self.switched_at = frame.index
        if self.model is None:
            n = 0 if frame.points is None else len(frame.points)
            return frame.with_fields(foreground=np.ones(n, dtype=bool))
        learning = self.chosen == "histogram" and getattr(self.model, "learning", False)
        out: Frame
        if learning and self.learn_people:
            people, legs, warm = self._people(frame)
            fg = self.model.learn_foreground(frame, people, legs)  # type: ignore[attr-defined]
            out = replace(frame, foreground=fg if warm is None else fg | warm)
        else:
            out = self.model(frame)
        if self.chosen == "histogram" and frame.frame == "sensor":
            if self.motion is None:
                self.motion = SensorMotionCheck(self.static.sensor_motion)
            if (
                not learning
                and out.foreground is not None
                and self.motion.record(frame, out.foreground)
            ):
                self.model = None
                self.chosen = "none"
                self.switched_at = frame.index
                return replace(out, foreground=np.ones(len(out.foreground), dtype=bool))
        return out

    def static_time(self, positions: NDArray[np.float64]) -> NDArray[np.float64]:
        """How long [s] ``positions`` (M, 2) [m] have been static, from the model in use
        (0 everywhere once dropped)."""
        if self.model is None:
            return np.zeros(np.asarray(positions).reshape(-1, 2).shape[0])
        model: StaticWorldModel = self.model  # type: ignore[assignment]
        return np.asarray(model.static_time(positions), dtype=np.float64)

    @property
    def detected_legs(self) -> bool:
        """Whether the model ran the leg detector on some frame to narrow its foreground to
        points near legs. (Keeping the people out of the histogram while it learns,
        ``learn_people``, is asked only by a tracker of legs, whose leg detection stage
        runs the detector anyway: :func:`detector_used`.)"""
        return self.legs is not None

    def describe(self) -> str:
        """One line for the user: which model ran and why."""
        if self.chosen == "none":
            what = (
                "no point is explained as static; the trackers get the points near legs"
                if self.legs is not None
                else "every point is foreground"
            )
            return (
                f"static world model: none from frame {self.switched_at} (the laser moves and "
                f"the recording has no poses: {what}; give poses with "
                "--world-frame or --mount to use the occupancy grid)"
            )
        if self.switched_at is None:
            return (
                "static world model: per-beam range histogram (the lasers did not move"
                + self._learned_from()
                + ")"
                + self._people_note()
            )
        return (
            "static world model: occupancy grid (a laser moved at frame "
            f"{self.switched_at}; the histogram ran before){self._grid_seed()}"
            f"{_not_learned(self.model)}"
        )

    def _grid_seed(self) -> str:
        """What seeded the occupancy grid, for :meth:`describe` (empty: nothing)."""
        learned, prior = self.prelearned, self.recording_map
        ours = prior is not None and getattr(self.model, "prior", None) is prior
        if learned is not None and learned.map_why_not:
            return f", not seeded by the whole recording ({learned.map_why_not})"
        if learned is None or prior is None or not ours:
            return _seeded(self.model)
        cells = int(np.count_nonzero(prior.occupied))
        p = self.params
        return (
            f", seeded by what stayed put in the whole recording ({cells} cells of "
            f"{prior.resolution:g} m with returns in {p.map_min_hits} or more of "
            f"{learned.map_frames} frames and in {100 * p.map_hit_share:g} % of those that "
            f"saw them farther than {p.map_hit_reach:g} m from their own returns, read before "
            f"tracking in {learned.cpu:.2f} s CPU, [auto_background] "
            "prelearn)"
        )

    def _learned_from(self) -> str:
        """From what the histogram was learned, for :meth:`describe`."""
        seconds = self.static.beam_histogram.learn_seconds
        online = f"learned online over the first {seconds:g} s"
        learned = self.prelearned
        if learned is None:
            off = "" if self.params.prelearn else " ([auto_background] prelearn = false)"
            return f"; {online}{off}"
        if learned.model is None:
            return f"; {online}: {learned.why_not}"
        of = "all" if learned.learned == learned.read else f"{learned.learned} evenly spread of"
        return (
            f"; {online}, and beyond its ranges from {of} {learned.read} frames of the whole "
            f"recording read before tracking in {learned.cpu:.2f} s CPU, [auto_background] "
            "prelearn"
        )

    def _people_note(self) -> str:
        """What the histogram left out as people while learning (empty: nothing)."""
        counts = getattr(self.model, "people_beams", None)
        if not self.learn_people or counts is None:
            return ""
        marked, settled = counts()
        if not marked:
            return ""
        return (
            f"; {marked} beams on the leg MHT's people while it learned were not learned "
            f"as static ([csa] background_people), {settled} of them static after all "
            "([beam_histogram] people_settle_seconds)"
        )

    def describe_foreground(self) -> str:
        """One line for the user: which foreground the trackers of points got, from which
        frame, and why."""
        p = self.static.leg_foreground
        if self.legs is None:
            if p.use == "never":
                return (
                    "foreground: every point the static world model does not explain "
                    "([leg_foreground] use = never, the papers' setting)"
                )
            return (
                "foreground: every point the static world model does not explain (the "
                f"lasers did not move; [leg_foreground] use = {p.use})"
            )
        why = {
            "none": "the laser moves and the recording has no poses, so no static world "
            "model is left and walls and bushes would be foreground",
            "occupancy": "a laser moved, and the occupancy grid has not yet learned what "
            "the robot drives past",
            "histogram": "[leg_foreground] use = always",
        }[self.chosen]
        share = self.legs.kept_share
        kept = f"; kept {100 * share:.1f} % of the foreground points" if share == share else ""
        held = self.legs.describe_hold()
        degraded = self.legs.degraded_scans
        if degraded:
            kept += (
                f"; the leg MHT that tells people's legs could not process {degraded} scans "
                "in full (too many detections in one place; [leg_tracker] "
                "mht.max_cluster_size): their legs may be held too briefly"
            )
        torso = ""
        if self.legs.torso and p.torso_blobs:
            torso = (
                f" and {self.legs.points_torso} points of torso-shaped runs (the laser "
                f"sits at torso height, {self.laser_height:.2f} m)"
            )
        return (
            f"foreground from frame {self.legs_from}: points within {p.radius:g} m of leg "
            f"detections{held}{torso} ({why}{kept}; [leg_foreground] use = never keeps every "
            "point, the papers' setting)"
        )


def _as_stage(model: object) -> Stage:
    """A static world model as a stage (it fills ``foreground``)."""
    return model  # type: ignore[return-value]


def occupancy_model(
    map_path: str | Path | None,
    params: OccupancyParams | None = None,
    prior: OccupancyMap | None = None,
) -> Stage:
    """The occupancy grid, seeded from the map ``map_path`` when given (a ROS ``map.yaml``
    or ``BAG:/topic``, :func:`~laserpeople.background.bag_map.load_map`), else from
    ``prior`` (e.g. the map of the whole recording, :mod:`laserpeople.pipeline.prelearn`)."""
    from laserpeople.background.bag_map import load_map
    from laserpeople.background.occupancy import OccupancyGrid

    if map_path is not None:
        prior = load_map(map_path)
    return _as_stage(OccupancyGrid(params, prior=prior))


def background_stage(
    choice: str | Stage | None,
    map_path: str | Path | None = None,
    static: StaticWorldParams | None = None,
    detector: object | None = None,
    *,
    steady: bool = False,
    behind_people: bool = False,
    legs_stage: object | None = None,
) -> Stage | None:
    """The static world model stage for ``choice`` (a name of :data:`BACKGROUND_CHOICES`
    or a model object; None or ``"none"``: no model). ``map_path`` seeds the occupancy
    grid (``occupancy`` or ``auto``); ``static`` holds the models' parameters (None:
    defaults); ``detector`` is the leg detector with which ``auto`` narrows the foreground
    to points near legs (None: the shipped one; :mod:`laserpeople.pipeline.leg_foreground`;
    ``steady``: for a tracker that needs steady points, which holds missed legs longer;
    ``behind_people``: ``auto``'s per-beam histogram does not learn the ranges on leg
    detections as static, :class:`AutoBackground`; ``legs_stage``: the pipeline's
    :class:`~laserpeople.pipeline.observe.DetectLegs`, whose detections ``auto`` takes
    instead of detecting each frame again)."""
    static = static if static is not None else StaticWorldParams()
    if choice is None or choice == "none":
        if map_path is not None:
            raise ConfigError(
                "--map seeds the occupancy grid, but --background none runs no model",
                hint="use --background occupancy or auto",
            )
        return None
    if not isinstance(choice, str):
        return choice
    if choice == "histogram":
        if map_path is not None:
            raise ConfigError(
                "--map seeds the occupancy grid, not the per-beam histogram",
                hint="use --background occupancy or auto",
            )
        from laserpeople.background.beam_histogram import BeamHistogramBackground

        return _as_stage(BeamHistogramBackground(static.beam_histogram))
    if choice == "occupancy":
        return occupancy_model(map_path, static.occupancy)
    if choice == "auto":
        return AutoBackground(
            map_path=map_path,
            static=static,
            detector=detector,
            steady=steady,
            learn_people=behind_people,
            legs_stage=legs_stage,
        )
    raise ConfigError(
        f"unknown static world model {choice!r}",
        hint=f"choose one of: {', '.join(BACKGROUND_CHOICES)}",
    )


def background_of(stages: Sequence[object]) -> object | None:
    """The static world model among a pipeline's ``stages`` (None without one; the people's
    model of :mod:`laserpeople.pipeline.static_people`, which only answers static times
    when a model follows it, is not it)."""
    from laserpeople.pipeline.preprocess import Fuse
    from laserpeople.pipeline.static_people import PeopleStaticModel

    for stage in stages:
        if isinstance(stage, Fuse) or (
            isinstance(stage, PeopleStaticModel) and not stage.fill_foreground
        ):
            continue
        if "foreground" in provided_by(stage):
            return stage
    return None


def detector_used(stages: Sequence[object]) -> bool:
    """Whether a pipeline's ``stages`` ran the leg detector on some frame: a leg detection
    stage (a tracker of legs; the CSA's people), or an ``auto`` static world model that
    narrowed its foreground to points near legs (:attr:`AutoBackground.detected_legs`).
    False for a tracker of points whose foreground never needed legs (e.g. ``feet-pf`` on a
    still laser)."""
    from laserpeople.pipeline.observe import DetectLegs

    return any(
        isinstance(stage, DetectLegs) or (isinstance(stage, AutoBackground) and stage.detected_legs)
        for stage in stages
    )


def static_model_used(stages: Sequence[object]) -> bool:
    """Whether a pipeline's ``stages`` hold a static world model: one that fills the
    trackers' foreground (:func:`background_of`) or the people's model that answers how
    long places have been static (the leg MHT's people, the filter of person tracks on
    static places)."""
    from laserpeople.pipeline.static_people import PeopleStaticModel

    return background_of(stages) is not None or any(
        isinstance(stage, PeopleStaticModel) for stage in stages
    )


def at_torso_height(height: float | None) -> bool:
    """Whether a laser mounted at ``height`` [m] (None: unknown) sits at torso height
    (:data:`~laserpeople.pipeline.laser_height.UPPER_BODY_MIN_HEIGHT` or higher)."""
    from laserpeople.pipeline.laser_height import UPPER_BODY_MIN_HEIGHT

    return height is not None and height >= UPPER_BODY_MIN_HEIGHT


def set_laser_height(stages: Sequence[object], height: float | None) -> None:
    """Tell the ``auto`` static world model among ``stages`` the laser's mount height [m]
    (None: unknown), as the recording states it: at torso height its narrowing to points
    near legs keeps torso-shaped runs too (``[leg_foreground] torso_blobs``); and a tracker
    among them that asks (``use_torso_height``: the CSA, ``[csa] torso_count_seconds``; the
    group tracker, ``[group_tracker] torso_pairs``) whether that is torso height."""
    for stage in stages:
        if isinstance(stage, AutoBackground):
            stage.laser_height = height
            continue
        tell = getattr(stage, "use_torso_height", None)
        if tell is not None:
            tell(at_torso_height(height))


def describe_foreground(stage: object | None) -> str:
    """One line for the user naming the foreground of a pipeline's trackers of points, when
    its static world model narrows it (``auto``; "" otherwise)."""
    describe = getattr(stage, "describe_foreground", None)
    return str(describe()) if callable(describe) else ""


def describe_background(stage: object | None, where: str = "") -> str:
    """One line for the user naming the static world model of a pipeline (``where``, e.g.
    " in the world frame", follows its name)."""
    if stage is None:
        return f"static world model: none (every point is foreground){where}"
    describe = getattr(stage, "describe", None)
    if callable(describe):
        return str(describe())
    names = {
        "BeamHistogramBackground": "per-beam range histogram",
        "OccupancyGrid": "occupancy grid",
    }
    name = type(stage).__name__
    said = f"{names.get(name, name)}{where}{_seeded(stage)}{_not_learned(stage)}"
    return f"static world model: {said}"


def _seeded(stage: object | None) -> str:
    """``", seeded by the map M (N obstacle cells of R m)"`` for an occupancy grid with a
    prior map (``--map``), so that the user sees the map was read; else empty."""
    prior = getattr(stage, "prior", None)
    if prior is None:
        return ""
    cells = int(np.count_nonzero(prior.occupied))
    return f", seeded by the map {prior.path} ({cells} obstacle cells of {prior.resolution:g} m)"


def _not_learned(stage: object | None) -> str:
    """``"; N frames not learned (...)"`` for a model that skipped frames
    (``[occupancy] learn_period``), else empty."""
    skipped = int(getattr(stage, "skipped", 0))
    if not skipped:
        return ""
    period = stage.params.learn_period  # type: ignore[union-attr]
    return f"; {skipped} frames not learned (each laser at most every {period:g} s)"


__all__ = [
    "BACKGROUND_CHOICES",
    "AutoBackground",
    "AutoBackgroundParams",
    "BackgroundChoice",
    "SensorMotionCheck",
    "SensorMotionParams",
    "StaticWorldParams",
    "at_torso_height",
    "background_of",
    "background_stage",
    "describe_background",
    "describe_foreground",
    "detector_used",
    "load_static_world",
    "occupancy_model",
    "pose_moved",
    "set_laser_height",
    "static_model_used",
    "static_world_preset",
]
