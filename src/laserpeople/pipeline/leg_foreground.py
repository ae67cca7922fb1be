"""Foreground that holds on a moving laser: the points near the legs the leg detector finds.

The point trackers (``csa`` of 002, ``feet-pf`` and ``upper-body-pf`` of 004, the group
tracker) were built for still lasers, whose static world a per-beam background explains.
On a moving laser without poses no static world model is left (in the sensor frame nothing
stays put, :class:`~laserpeople.pipeline.background.AutoBackground`): every point, walls
and bushes included, is foreground, and a tracker of points sees clutter as people. On a
moving laser with poses the occupancy grid has not yet learned what the robot drives past.

:class:`LegForeground` keeps, of the points a frame's foreground holds (every point without
one), only those within ``radius`` of a leg detection of the shipped leg detector (000 Sec.
2; the pipeline's :class:`~laserpeople.pipeline.observe.DetectLegs` stage, reused: a frame
that already holds ``legs`` is not detected again, and with a tracker that consumes legs too
the pipeline's stage detects each frame once for both; otherwise its own stage detects the
frames ahead 16 at a time, :meth:`LegForeground.prefetch`). A leg's points lie within about 0.1 m
of its detection (leg radius ~0.07 m, the detection moved 0.045 m behind the points'
centroid); a larger radius also keeps a second leg the detector missed in this scan.

A leg the detector misses for a few scans can be held at its last position: every leg for
``memory`` seconds, and a leg of a person that a leg MHT tracks (``leg-mht`` with the
``[leg_tracker]`` parameters, run by the stage on the same detections, see
:func:`stage_leg_tracker`; its people coast through missed detections with their own
existence) for ``person_memory`` seconds; for the particle filters, which die
without points after 0.2 s, ``steady_memory`` and ``steady_person_memory``. By default
only the legs of people are held, and only for the particle filters (1 s): held clutter
legs keep the point trackers' false tracks alive.

On a moving laser with poses at torso height (the recording states the laser's height,
:mod:`laserpeople.pipeline.laser_height`) it also keeps the runs of foreground points
shaped like a torso (:mod:`laserpeople.pipeline.torso_blobs`): there the leg detector
seldom fires on a person.

On a moving laser with poses (the occupancy grid in the world frame) it also keeps the
grid's foreground points of a person-sized blob that moved ``moving_travel`` (0.5 m) over
``moving_seconds`` (1 s) in the world frame (:mod:`laserpeople.pipeline.moving_blobs`):
the leg detector misses many people the grid's foreground holds, and walls and clutter
do not move there while walkers do (0: only points near legs).

For the trackers that need steady points (the particle filters), on a moving laser with
poses not known to sit at torso height, it also keeps the grid's foreground points of a
person-sized blob whose leg-wide runs hold at most ``leg_run_points`` (4) points
(:mod:`laserpeople.pipeline.leg_runs`): far legs shown by one or two beams each, which the
detector cannot classify (0: none).

When :class:`~laserpeople.pipeline.background.AutoBackground` uses it is
``[leg_foreground] use`` (:class:`LegForegroundParams`): ``never`` (the papers: every
point, or plain background subtraction), ``no-poses`` (only once the model is dropped on a
moving laser without poses), ``moving`` (also intersected with the occupancy grid's
foreground once a laser with poses moves) or ``always`` (also with the still lasers'
per-beam histogram). Measured choice: docs/people-benchmarks.md, "Foreground on moving
robots".
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.errors import ConfigError
from laserpeople.frame import Frame, FrameField
from laserpeople.pipeline.moving_blobs import MovingBlobs

if TYPE_CHECKING:
    from laserpeople.tracking.legs import LegTrackerParams

LEG_FOREGROUND_USES: tuple[str, ...] = ("never", "no-poses", "moving", "always")
"""When ``auto`` keeps only points near legs (module docstring), from never to always."""


@dataclass(frozen=True)
class LegForegroundParams:
    """When and how the foreground is narrowed to the points near leg detections."""

    config_section = "leg_foreground"
    paper_preset = MappingProxyType(  # 002, 004: no moving blobs, no torso runs
        {"moving_travel": 0.0, "torso_blobs": False, "leg_run_points": 0}
    )

    use: str = param(
        "moving",
        "measured (docs/people-benchmarks.md, 'Foreground on moving robots'): on the real "
        "person-following robot and on simulated moving robots; 'never' is the papers' "
        "behaviour (002, 004: every point, or plain background subtraction)",
        "when --background auto keeps only foreground points near leg detections: never, "
        "no-poses (a moving laser without poses, where no static world model is left), "
        "moving (also a moving laser with poses, with the occupancy grid) or always (also "
        "still lasers, with the per-beam histogram)",
    )
    memory: float = param(
        0.0,
        "measured (docs/people-benchmarks.md, 'Foreground on moving robots'; tried 0 and "
        "0.5 s): held legs keep clutter alive and draw the CSA's targets into groups that "
        "never split (real person-following robot: identity recall 0.37 with 0 s, 0.33 "
        "with 0.5 s)",
        "for trackers other than those in steady_memory: a leg detection is held this long "
        "at its last position while no later detection comes within radius of it, and the "
        "points near held legs are kept too (0: the frame's own detections only)",
        "s",
    )
    steady_memory: float = param(
        0.0,
        "measured (docs/people-benchmarks.md, 'Foreground on moving robots'; tried 0, 0.5, 1 "
        "and 2 s): with the legs of the leg "
        "MHT's people held steady_person_memory, holding the other legs too only keeps "
        "clutter (real person-following robot: feet-pf identity recall / ids 0.51 / 5 with "
        "0 s, 0.51 / 5 with 0.2 s; simulated moving robots, tuning seeds: feet-pf MOTA 0.16 "
        "with 0 s, -0.25 with 0.2 s)",
        "memory for trackers that die without points for a few scans (feet-pf, "
        "upper-body-pf: their needs_steady_points)",
        "s",
    )
    min_score: float = param(
        0.0,
        "000 Table 1 (score above 0); measured (docs/people-benchmarks.md): 0.4 lowers csa on "
        "the real following robot",
        "only leg detections scoring above this keep points (AdaBoost margin; with the "
        "detector's [leg_detector] score_threshold lowered, lower this too)",
    )
    radius: float = param(
        0.35,
        "measured (docs/people-benchmarks.md, 'Foreground on moving robots'; tried 0.15 and "
        "0.35 m: csa on the real person-following robot equal, feet-pf recall 0.85 and 0.91)",
        "a foreground point is kept when it lies within this distance of a leg detection",
        "m",
    )
    person_memory: float = param(
        0.0,
        "measured (docs/people-benchmarks.md, 'Foreground on moving robots'; "
        "tried 0, 0.5 and 1 s): as memory, held legs draw the CSA's targets into groups "
        "that never split (real person-following robot: csa identity recall / recall 0.37 / "
        "0.84 with 0 s, 0.32 / 0.33 with 0.5 and 1 s; group-mht's groups 0.33 / 14 ids with "
        "0 s, 0.48 / 7 ids with 1 s)",
        "for trackers other than those in steady_person_memory: a leg detection within "
        "radius of a leg of a person the leg MHT tracks (leg-mht with [leg_tracker], k 20 "
        "and N-scan 8 where unset, run on the same detections) is held this long instead "
        "of memory, if longer (0 for both: no leg MHT is run)",
        "s",
    )
    steady_person_memory: float = param(
        1.0,
        "measured (docs/people-benchmarks.md, 'Foreground on moving robots'; "
        "tried 0.5, 1 and 2 s): the particle filters of 004 die after miss_time = 0.2 s "
        "without points and the detector misses the followed person's legs for up to a "
        "second while the leg MHT still holds them (real person-following robot: feet-pf / "
        "upper-body-pf identity recall 0.37 / 0.37 with 0.5 s, 0.51 / 0.57 with 1 s and "
        "2 s)",
        "person_memory for trackers that die without points for a few scans (feet-pf, "
        "upper-body-pf: their needs_steady_points)",
        "s",
    )

    moving_travel: float = param(
        0.5,
        "measured (docs/csa.md, 'People the leg detector misses on a moving laser'; tried "
        "0.3 m over 0.5 s: feet-pf MOTA 0.489 -> 0.457 on the tuning seeds): the leg "
        "detector misses people the grid's foreground holds (feet-pf: of 1,267 person-scans "
        "without foreground 830 had grid foreground, 112 a leg detection); walls and "
        "clutter do not move in the world frame",
        "on a moving laser with poses, also keep the grid's foreground points of a "
        "person-sized blob whose centre moved this far in the world frame over "
        "moving_seconds (0: only points near legs; pipeline/moving_blobs.py)",
        "m",
    )
    moving_seconds: float = param(
        1.0,
        "measured with moving_travel (docs/csa.md, 'People the leg detector misses on a "
        "moving laser'; tried 0.5 s): a walker at 0.5 m/s or faster",
        "the time over which a blob must have moved moving_travel, steadily (its centre "
        "halfway in time a third of it from either end)",
        "s",
    )
    leg_run_points: int = param(
        4,
        "measured (docs/schenk-tables.md, 'Far legs on a moving laser'): of the moving tuning "
        "person-scans 10.6 % had the grid's foreground in a person-sized blob near no leg "
        "detection and not moving, at a median 4.9 m with 3 returns on the legs; feet-pf "
        "random-groups moving tuning seeds 0.532 -> 0.547 with [leg_detector.sparse], "
        "0.525 -> 0.548 without (3: 0.533, 5: 0.546, any number: 0.550 but the real lobby "
        "recording MOTA -0.281 -> -0.825 on wall ends)",
        "for the trackers that need steady points (feet-pf, upper-body-pf), on a moving "
        "laser with poses not stated at torso height: also keep the grid's foreground "
        "points of a person-sized blob whose runs as wide as a leg (2 or more neighbouring "
        "beams, 0.08-0.2 m, apart from the returns beside) hold at most this many points in "
        "all (0: none; pipeline/leg_runs.py)",
        "points",
    )
    torso_blobs: bool = param(
        True,
        "measured (docs/csa.md, 'Torso blobs on a moving laser'): at torso height the leg "
        "detector fires on a person in under a third of the scans (moving torso-height "
        "tuning seeds 11, 13: 29 / 15 %); torso-shaped runs of the grid's foreground lie "
        "within 0.5 m of a person in 73 / 61 % of them",
        "for a tracker that asks for them (csa), on a moving laser with poses whose "
        "recording states it at torso height (0.7 m or higher), also keep the foreground "
        "points of runs shaped like a torso: 0.2-0.65 m between the ends, bulging 0.03 m "
        "towards the laser (pipeline/torso_blobs.py)",
    )

    learn_people_warmup: int = param(
        4,
        "measured (docs/csa.md, 'The people of the learning period'): the leg MHT confirms "
        "the standing people of crossing-3 in their 3rd or 4th scan; 0 cost crossing-3 "
        "seed 7 (cli) IDF1 0.012 on p0 and p5",
        "for [csa] background_people: while the per-beam histogram learns, the legs of the "
        "person tracks of a leg MHT run on the same detections are marked as people (not "
        "learned as static); in the first this many scans the points near every leg "
        "detection are foreground too (not marked: the leg MHT has not confirmed anybody "
        "yet)",
        "scans",
    )

    def __post_init__(self) -> None:
        if self.leg_run_points < 0:
            raise ValueError(f"leg_run_points must not be negative, got {self.leg_run_points}")
        if self.learn_people_warmup < 0:
            raise ValueError(
                f"learn_people_warmup must not be negative, got {self.learn_people_warmup}"
            )
        if self.use not in LEG_FOREGROUND_USES:
            raise ValueError(
                f"use must be one of {', '.join(LEG_FOREGROUND_USES)}, not {self.use!r}"
            )
        if not 0.0 < self.radius < float("inf"):
            raise ValueError(f"radius must be positive and finite, got {self.radius}")
        if not 0.0 <= self.memory < float("inf"):
            raise ValueError(f"memory must be finite and not negative, got {self.memory}")
        if not 0.0 <= self.steady_memory < float("inf"):
            raise ValueError(
                f"steady_memory must be finite and not negative, got {self.steady_memory}"
            )
        if not 0.0 <= self.moving_travel < float("inf"):
            raise ValueError(
                f"moving_travel must be finite and not negative, got {self.moving_travel}"
            )
        if not 0.0 < self.moving_seconds < float("inf"):
            raise ValueError(
                f"moving_seconds must be positive and finite, got {self.moving_seconds}"
            )
        for name in ("person_memory", "steady_person_memory"):
            value = getattr(self, name)
            if not 0.0 <= value < float("inf"):
                raise ValueError(f"{name} must be finite and not negative, got {value}")


def near_legs(
    points: NDArray[np.float64], legs: NDArray[np.float64], radius: float
) -> NDArray[np.bool_]:
    """Which of ``points`` (N, 2) [m] lie within ``radius`` [m] of one of ``legs`` (M, 2) [m]
    (inclusive)."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    centres = np.asarray(legs, dtype=np.float64).reshape(-1, 2)
    keep = np.zeros(len(pts), dtype=bool)
    if len(pts) == 0 or len(centres) == 0:
        return keep
    r2 = radius * radius
    for c in centres:  # M is a few dozen at most; N a few thousand
        d = pts - c
        keep |= np.einsum("ij,ij->i", d, d) <= r2
    return keep


def stage_leg_tracker(params: LegTrackerParams | None = None) -> LegTrackerParams:
    """The leg MHT's parameters this stage runs with: ``params`` (``LegTrackerParams``;
    None: its defaults), with ``mht.k_best`` and ``mht.n_scan`` where unset at 000's 20 and 8
    rather than the ``tracks`` policy's 5 and 4. Measured on the real person-following
    recording: feet-pf identity recall 0.512 with 5 ids at 20 / 8, 0.329 with
    6 ids at 5 / 4 (one more id switch on the followed person); upper-body-pf 0.566 either
    way. The stage runs the MHT only for trackers of points on moving lasers."""
    from laserpeople.tracking.legs import POLICY_MIN_RATIO, LegTrackerParams
    from laserpeople.tracking.mht.core import K_BEST, N_SCAN

    p = params if params is not None else LegTrackerParams()
    mht = p.mht.with_defaults(POLICY_MIN_RATIO[p.people_policy], K_BEST, N_SCAN)
    return replace(p, mht=mht)


class LegForeground:
    """Keeps of a frame's foreground the points near its leg detections (module docstring).

    A stage: after :class:`~laserpeople.pipeline.Fuse` (and a static world model, whose
    foreground it narrows). Legs come from the frame when an earlier stage filled them,
    else from ``legs_stage`` (the pipeline's own
    :class:`~laserpeople.pipeline.observe.DetectLegs` for a tracker that consumes legs
    too: each frame is detected once), else from its own ``DetectLegs`` with ``detector``
    (None: the shipped AdaBoost detector). ``steady``: the tracker dies without points for
    a few scans (:func:`needs_steady_points`), so legs are held ``steady_memory`` seconds
    instead of ``memory`` (and people's legs ``steady_person_memory`` instead of
    ``person_memory``).

    Attributes:
        frames: Frames narrowed.
        points_in: Foreground points seen, summed over those frames.
        points_kept: Foreground points kept, summed over those frames.
        detected: Frames whose legs it detected itself (the others held legs).
    """

    consumes: frozenset[FrameField] = frozenset({"scans", "points"})
    provides: frozenset[FrameField] = frozenset({"foreground"})

    def __init__(
        self,
        params: LegForegroundParams | None = None,
        detector: Any = None,
        *,
        steady: bool = False,
        leg_tracker: LegTrackerParams | None = None,
        legs_stage: Any = None,
    ) -> None:
        self.params = params or LegForegroundParams()
        self._leg_tracker = leg_tracker
        """The leg MHT's parameters (``LegTrackerParams``; None: its defaults)."""
        self.memory = self.params.steady_memory if steady else self.params.memory
        """How long [s] legs are held (``steady_memory`` for a tracker that needs steady
        points, else ``memory``)."""
        self.person_memory = (
            self.params.steady_person_memory if steady else self.params.person_memory
        )
        """How long [s] legs of the leg MHT's people are held (``steady_person_memory`` or
        ``person_memory``; 0: no leg MHT is run)."""
        self._detector = detector
        self._detect: Any = legs_stage
        self._own_detect = legs_stage is None
        """Whether the :class:`~laserpeople.pipeline.observe.DetectLegs` it asks is its own
        (else the pipeline's, which detects each frame once and in blocks)."""
        self.frames = 0
        self.points_in = 0
        self.points_kept = 0
        self.detected = 0
        self._held = np.empty((0, 2))
        self._held_stamps = np.empty(0)
        self._held_long = np.empty(0, dtype=bool)
        self._last_stamp = -np.inf
        self._tracker: Any = None
        self.moving = False
        """Whether the laser moves with poses (set by the static world model): then the
        blobs of the foreground that move in the world frame are kept too."""
        self._blobs: MovingBlobs | None = None
        self.points_moving = 0
        """Foreground points kept only because their blob moved, summed over frames."""
        self.leg_runs = self.params.leg_run_points if steady else 0
        """At most how many points of leg-wide runs a grid foreground blob that is kept on a
        moving laser at feet height holds (``leg_run_points`` for the trackers that need
        steady points, else 0: none)."""
        self.points_leg_runs = 0
        """Foreground points kept only because their blob holds a few leg-wide runs."""
        self.torso = False
        """Whether the laser is known to sit at torso height (set by the static world
        model from the recording's laser height): then torso-shaped runs of the
        foreground are kept too (``torso_blobs``)."""
        self.points_torso = 0
        """Foreground points kept only because they lie in a torso-shaped run."""

    def remembered(
        self,
        stamp: float,
        legs: NDArray[np.float64],
        people: NDArray[np.bool_] | None = None,
    ) -> NDArray[np.float64]:
        """``legs`` (M, 2) [m] of the frame at ``stamp`` [s] and the held legs: each leg of
        the last ``memory`` seconds (``person_memory`` for those flagged in ``people``, (M,),
        a person's legs) that no leg of a later frame came within ``radius`` of, at its
        last position (so a leg the detector misses for a few scans keeps its points, and
        one it sees again is not smeared along its path). A stamp before the previous one
        forgets them."""
        legs = np.asarray(legs, dtype=np.float64).reshape(-1, 2)
        flags = np.zeros(len(legs), dtype=bool) if people is None else np.asarray(people, bool)
        if self._held_stamps.size and stamp < self._last_stamp:
            self._held_stamps = np.empty(0)
            self._held = np.empty((0, 2))
            self._held_long = np.empty(0, dtype=bool)
        self._last_stamp = stamp
        limit = np.where(self._held_long, max(self.memory, self.person_memory), self.memory)
        keep = stamp - self._held_stamps <= limit
        if keep.any() and len(legs):
            d = self._held[:, None, :] - legs[None, :, :]
            seen = (np.einsum("hmk,hmk->hm", d, d) <= self.params.radius**2).any(axis=1)
            keep &= ~seen
        held = self._held[keep]
        self._held_stamps = np.concatenate([self._held_stamps[keep], np.full(len(legs), stamp)])
        self._held_long = np.concatenate([self._held_long[keep], flags])
        self._held = np.concatenate([held, legs])
        return self._held

    def legs_of(self, frame: Frame) -> NDArray[np.float64]:
        """Leg positions (M, 2) [m] of ``frame``, in its coordinate frame."""
        return self._confident(self.detections_of(frame))

    def people_flags(self, frame: Frame, legs: Any, mine: NDArray[np.float64]) -> Any:
        """Which of the positions ``mine`` (M, 2) [m] lie within ``radius`` of a leg of a
        person track of the leg MHT fed with ``legs`` (None: ``person_memory`` is not
        longer than ``memory``, no MHT is run)."""
        if self.person_memory <= self.memory:
            return None
        return self._person_flags(frame, legs, mine)

    def person_legs(self, frame: Frame) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """The confident leg detections of ``frame`` (M, 2) [m] and which of them (M,) lie
        within ``radius`` of a leg of a person track of the leg MHT (000's people: two
        legs), whatever ``person_memory`` says; the MHT runs on every frame given here."""
        legs = self.detections_of(frame)
        mine = self._confident(legs)
        return mine, np.asarray(self._person_flags(frame, legs, mine), dtype=bool)

    def _person_flags(self, frame: Frame, legs: Any, mine: NDArray[np.float64]) -> Any:
        """Which of ``mine`` (M, 2) [m] lie within ``radius`` of a leg of a person track of
        the leg MHT fed with ``legs`` (M,) bool."""
        if self._tracker is None:
            from laserpeople.tracking.legs import LegMHTTracker
            from laserpeople.tracking.registry import LegsAdapter

            self._tracker = LegsAdapter(LegMHTTracker(stage_leg_tracker(self._leg_tracker)))
        tracks = self._tracker.update(frame.with_fields(legs=legs))
        members = {m for t in tracks.of_kind("person") for m in t.members}
        pos = [t.position for t in tracks.of_kind("leg") if t.track_id in members]
        return near_legs(mine, np.asarray(pos, dtype=np.float64).reshape(-1, 2), self.params.radius)

    def _detect_stage(self) -> Any:
        """The stage's own :class:`~laserpeople.pipeline.observe.DetectLegs` (made at first
        use, with ``detector`` or the shipped one)."""
        if self._detect is None:
            from laserpeople.pipeline.observe import DetectLegs

            detector = self._detector
            if detector is None:
                from laserpeople.detection.detector import AdaBoostLegDetector

                detector = AdaBoostLegDetector.default()
            self._detect = DetectLegs(detector)
        return self._detect

    def prefetch(self, frames: Sequence[Frame]) -> None:
        """Detect the legs of the scans of ``frames`` (frames about to be narrowed, in
        order) at once (:meth:`~laserpeople.pipeline.observe.DetectLegs.prefetch`): the same
        detections as one frame at a time, for about a third of the CPU. Frames that hold
        their legs already are left out (they are not detected again); nothing with the
        pipeline's stage (``legs_stage``: the pipeline prefetches it)."""
        if self._own_detect:
            self._detect_stage().prefetch([f for f in frames if f.legs is None])

    def detections_of(self, frame: Frame) -> Any:
        """Leg detections of ``frame``, in its coordinate frame."""
        if frame.legs is not None:
            return frame.legs
        self.detected += 1
        legs = self._detect_stage()(frame).legs
        if legs is None:
            from laserpeople.tracks import Detections

            return Detections.empty(frame.stamp, frame.index, frame.frame, frame.sensor_pose)
        return legs

    def _confident(self, legs: Any) -> NDArray[np.float64]:
        """Positions of the ``legs`` (Detections) scoring above ``min_score``."""
        return np.asarray(legs.positions[legs.scores > self.params.min_score], dtype=np.float64)

    def __call__(self, frame: Frame) -> Frame:
        """The frame with ``foreground`` narrowed to the points near its legs."""
        if frame.points is None:
            raise ConfigError(f"frame {frame.index} has no points", hint="run Fuse first")
        n = len(frame.points)
        fg = np.ones(n, dtype=bool) if frame.foreground is None else frame.foreground
        detections = self.detections_of(frame)
        mine = self._confident(detections)
        people = self.people_flags(frame, detections, mine)
        legs = self.remembered(float(frame.stamp), mine, people)
        kept = fg & near_legs(frame.points.points, legs, self.params.radius)
        if self.moving and self.params.moving_travel > 0 and frame.frame == "world":
            if self._blobs is None:
                self._blobs = MovingBlobs(self.params.moving_travel, self.params.moving_seconds)
            moved = self._blobs(float(frame.stamp), frame.points.points, fg) & ~kept
            self.points_moving += int(np.count_nonzero(moved))
            kept |= moved
        if self._wants_leg_runs(frame):
            runs = self._far_legs(frame, fg) & ~kept
            self.points_leg_runs += int(np.count_nonzero(runs))
            kept |= runs
        if self.torso and self.params.torso_blobs and frame.frame == "world":
            pose = frame.sensor_pose
            if pose is not None:
                from laserpeople.pipeline.torso_blobs import torso_blobs

                sensor = np.array([pose.x, pose.y])
                torsos = torso_blobs(frame.points.points, frame.points.beams, fg, sensor) & ~kept
                self.points_torso += int(np.count_nonzero(torsos))
                kept |= torsos
        self.frames += 1
        self.points_in += int(np.count_nonzero(fg))
        self.points_kept += int(np.count_nonzero(kept))
        return frame.with_fields(foreground=kept)

    def _wants_leg_runs(self, frame: Frame) -> bool:
        """Whether ``frame`` keeps the blobs of far legs (``leg_run_points``): a tracker that
        needs steady points, a moving laser with poses (world frame) not known to sit at
        torso height, one laser (beam order is one scan's)."""
        return (
            self.leg_runs > 0
            and self.moving
            and not self.torso
            and frame.frame == "world"
            and len(frame.scans) == 1
        )

    def _far_legs(self, frame: Frame, fg: NDArray[np.bool_]) -> NDArray[np.bool_]:
        """The foreground points (N,) of ``frame`` (one laser, world frame) in a
        person-sized blob whose leg-wide runs hold at most ``leg_run_points`` points."""
        from laserpeople.pipeline.leg_runs import far_leg_blobs

        points, pose = frame.points, frame.sensor_pose
        if points is None or pose is None:
            return np.zeros(len(fg), dtype=bool)
        sensor = np.array([pose.x, pose.y])
        increment = frame.scans[0].angle_increment
        return far_leg_blobs(points.points, points.beams, fg, sensor, increment, self.leg_runs)

    def describe_hold(self) -> str:
        """How long missed legs are held, for the user (empty: not held)."""
        memory, people = self.memory, max(self.memory, self.person_memory)
        if people <= 0:
            return ""
        if people == memory:
            return f", missed legs held {memory:g} s"
        if memory <= 0:
            return f", missed legs of the people a leg MHT tracks held {people:g} s"
        return (
            f", missed legs held {memory:g} s ({people:g} s those of the people a leg MHT tracks)"
        )

    @property
    def degraded_scans(self) -> int:
        """Scans the stage's leg MHT could not process in full within its work bounds (0:
        none, or no leg MHT run)."""
        if self._tracker is None:
            return 0
        return int(self._tracker.tracker.guard.degraded_scans)

    @property
    def kept_share(self) -> float:
        """Share of the foreground points kept, over every frame narrowed (nan: none)."""
        return self.points_kept / self.points_in if self.points_in else float("nan")


def needs_steady_points(tracker: object) -> bool:
    """Whether ``tracker`` dies without points for a few scans (its class sets
    ``needs_steady_points``: the particle filters of 004), so that missed legs are held."""
    return bool(getattr(tracker, "needs_steady_points", False))


def learns_behind_people(tracker: object) -> bool:
    """Whether ``tracker`` wants the per-beam histogram of ``--background auto`` to leave
    out the people standing while it learns (it sets ``learns_behind_people``: the CSA,
    ``[csa] background_people``)."""
    return bool(getattr(tracker, "learns_behind_people", False))


def wants_torso_runs(tracker: object) -> bool:
    """Whether ``tracker`` takes the torso-shaped runs of the foreground at torso height
    (its class sets ``wants_torso_runs``: the CSA, measured in docs/csa.md; the particle
    filters and the group tracker keep the points near legs alone until measured)."""
    return bool(getattr(tracker, "wants_torso_runs", False))


__all__ = [
    "LEG_FOREGROUND_USES",
    "LegForeground",
    "LegForegroundParams",
    "learns_behind_people",
    "near_legs",
    "needs_steady_points",
    "stage_leg_tracker",
    "wants_torso_runs",
]
