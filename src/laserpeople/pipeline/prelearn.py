"""The per-beam histogram of still lasers learned with what the whole recording shows.

Online, ``--background auto`` learns the per-beam range histogram
(:class:`~laserpeople.background.beam_histogram.BeamHistogramBackground`) over the first
``[beam_histogram] learn_seconds`` of a recording, with people in view: a person there from
the start is background until they step off the beams they first stood on. A recording on
disk can be read whole before it is tracked. :func:`learn_recording` reads its frames once
and, while they pass the tests of :class:`~laserpeople.pipeline.background.AutoBackground`
(world frame: every laser keeps its first pose,
:func:`~laserpeople.pipeline.background.pose_moved`; sensor frame: the share of returns off
a histogram of the first seconds stays low,
:class:`~laserpeople.pipeline.background.SensorMotionCheck`) and keep their beam layout,
learns a histogram from every frame, or from every k-th frame of a recording longer than
``[auto_background] prelearn_scans`` frames. The online histogram then learns as before,
and a range frequent in the whole recording that lies beyond what it finds static on a beam
is static too
(:meth:`~laserpeople.background.beam_histogram.BeamHistogramBackground.use_whole_recording`):
the wall behind a person who stands in view from the start and leaves their place for
``min_fraction`` of the recording. Nothing nearer is added: a person who stands for much of
a short recording after the learning period is not learned as static.

A recording whose lasers move (their poses in the world frame change) is read a second
time, and :class:`~laserpeople.background.recording_map.RecordingMapCounter` counts what
stayed put in it, from every frame or every k-th of a recording longer than
``prelearn_scans`` frames: its static cells seed the occupancy grid the ``auto`` model
switches to once a laser moves, as a prior map would (``--map``, which takes its place when
given). The walls and furniture a robot drives past are then static from the first scan
instead of foreground near legs until the grid has learned them.

A change of beam layout, a laser that moves without poses, a recording that cannot be read
to its end, ``prelearn = false`` (``--preset paper``) or a live run learn as before, and
:meth:`~laserpeople.pipeline.background.AutoBackground.describe` says which ran.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, replace
from typing import TypeVar

import numpy as np

from laserpeople.background.beam_histogram import BeamHistogramBackground
from laserpeople.background.occupancy import OccupancyMap, sensor_positions
from laserpeople.background.recording_map import RecordingMapCounter, RecordingMapRule
from laserpeople.errors import LaserPeopleError
from laserpeople.frame import Frame
from laserpeople.pipeline.background import (
    AutoBackground,
    SensorMotionCheck,
    StaticWorldParams,
    background_of,
    pose_moved,
)
from laserpeople.pipeline.preprocess import Fuse
from laserpeople.scan import Layout, Pose2D, Scan, same_layout


@dataclass(frozen=True)
class Prelearned:
    """What the pass over a recording learned.

    Attributes:
        model: The histogram, learning done (None: not learned, see ``why_not``).
        learned: Frames it was learned from.
        read: Frames read.
        why_not: Why nothing was learned, for the user ("" when ``model`` is set).
        cpu: Process CPU time [s] of the pass (reading included; 0 when not measured).
        laser_moved: A laser's pose in the world frame moved (then ``grid_map`` may be
            counted).
        grid_map: What stayed put in a moving robot's recording, the occupancy grid's prior
            map (None: not counted).
        map_frames: Frames the map was counted from.
        map_why_not: Why a moving robot's recording was not mapped, for the user ("" when
            ``grid_map`` is set or no map was wanted).
    """

    model: BeamHistogramBackground | None
    learned: int
    read: int
    why_not: str = ""
    cpu: float = 0.0
    laser_moved: bool = False
    grid_map: OccupancyMap | None = None
    map_frames: int = 0
    map_why_not: str = ""


class _Pass:
    """The frames of one pass that pass the stillness tests, as scans to learn from."""

    def __init__(self, static: StaticWorldParams, step: int) -> None:
        self.static = static
        self.step = step
        self.read = 0
        self.learned = 0
        self.why_not = ""
        self.laser_moved = False
        self._first: dict[str, Pose2D] = {}
        self._layouts: dict[str, Layout] = {}
        self._motion = SensorMotionCheck(static.sensor_motion)
        self._fuse = Fuse()

    def scans(self, frames: Iterable[Frame]) -> Iterator[Scan]:
        """The scans of every ``step``-th frame; stops (setting ``why_not``) at the first
        frame whose laser moved or changed its beam layout."""
        for frame in frames:
            self.read += 1
            if pose_moved(self._first, frame, self.static.auto_background):
                self.why_not = f"a laser moved at frame {frame.index}"
                self.laser_moved = True
                return
            if (self.read - 1) % self.step:
                continue
            for scan in frame.scans:
                known = self._layouts.setdefault(scan.sensor, scan.layout)
                if not same_layout(known, scan.layout):
                    self.why_not = (
                        f"laser {scan.sensor} changed its beam layout at frame {frame.index}"
                    )
                    return
            if frame.frame == "sensor" and self._motion(self._fuse(frame)):
                self.why_not = f"the laser moved at frame {frame.index} (sensor frame)"
                return
            self.learned += 1
            yield from frame.scans


def learn_recording(
    frames: Iterable[Frame], static: StaticWorldParams, total: int | None = None
) -> Prelearned:
    """The per-beam histogram (parameters ``static.beam_histogram``) learned from
    ``frames``, the whole recording, when its lasers stand still (module docstring);
    ``total``: how many frames to expect (None: unknown, every frame is learned from), of
    which at most ``static.auto_background.prelearn_scans``, evenly spread, are."""
    walk = _Pass(static, _every(total, static.auto_background.prelearn_scans))
    model = BeamHistogramBackground(static.beam_histogram)
    try:
        model.learn_scans(walk.scans(frames))
    except LaserPeopleError as exc:  # tracking meets a read error again at its frame
        if walk.why_not:
            return Prelearned(None, 0, walk.read, walk.why_not)
        return Prelearned(None, 0, walk.read, f"the recording could not be read whole ({exc})")
    if walk.why_not:
        return Prelearned(None, 0, walk.read, walk.why_not, laser_moved=walk.laser_moved)
    return Prelearned(model, walk.learned, walk.read)


def _every(total: int | None, most: int) -> int:
    """Every how many frames a pass learns from, for ``total`` frames (None: unknown) and
    at most ``most`` learned."""
    return 1 if total is None or total <= most else math.ceil(total / most)


def count_recording_map(
    frames: Iterable[Frame], static: StaticWorldParams, total: int | None = None
) -> tuple[OccupancyMap | None, int]:
    """What stayed put in ``frames``, a whole world-frame recording of a moving robot
    (module docstring), counted from at most ``[auto_background] prelearn_scans`` of its
    frames, evenly spread: the map (None when no frame had poses) and the frames counted.
    A recording that cannot be read to its end raises as its reader does."""
    auto = static.auto_background
    rule = RecordingMapRule(
        min_hits=auto.map_min_hits,
        hit_share=auto.map_hit_share,
        hit_reach=auto.map_hit_reach,
        free_range=static.occupancy.free_range,
        free_margin=static.occupancy.free_margin,
    )
    counter = RecordingMapCounter(rule)
    step = _every(total, auto.prelearn_scans)
    fuse = Fuse()
    for read, frame in enumerate(frames):
        if read % step or frame.frame != "world":
            continue
        fused = fuse(frame)
        assert fused.points is not None
        origins = sensor_positions(fused, fused.points)
        if origins is not None:
            counter.add(np.asarray(origins, dtype=np.float64), fused.points.points)
    if counter.frames == 0:
        return None, 0
    return counter.static_map("the whole recording"), counter.frames


ShowProgress = Callable[[Iterable[Frame], int | None, str], Iterable[Frame]]
"""Wraps the frames of a pass to show its progress: (frames, total or None, description)
-> the same frames (e.g. :func:`laserpeople.cli.common.progress`)."""

PASS_DESCRIPTION = "learning the background from the whole recording"
"""What the pass is called where its progress is shown."""

MAP_PASS_DESCRIPTION = "mapping what stays put in the whole recording"
"""What the second pass, over a moving robot's recording, is called where its progress is
shown."""

_T = TypeVar("_T")


def prelearn(
    stages: Sequence[object],
    open_frames: Callable[[], Iterable[Frame]],
    total: int | None = None,
    show: ShowProgress | None = None,
) -> Prelearned | None:
    """Learn a histogram for the ``auto`` static world model among ``stages`` from the
    frames ``open_frames()`` gives (a fresh pass over the recording; closed afterwards when
    it has ``close``), or, when its lasers move and no ``--map`` was given, the map of what
    stayed put from a second pass, and hand it to the model
    (:meth:`AutoBackground.use_prelearned`).
    None (nothing read) without such a model or with ``[auto_background] prelearn`` false;
    ``total``: frames to expect (None: the pass's own ``total`` when it has one); ``show``
    wraps the frames to show the pass's progress (:data:`PASS_DESCRIPTION`)."""
    model = background_of(stages)
    if not isinstance(model, AutoBackground) or not model.params.prelearn:
        return None
    static = model.static
    if model.params is not static.auto_background:
        static = replace(static, auto_background=model.params)
    start = time.process_time()
    learned = _read_pass(
        open_frames, total, show, PASS_DESCRIPTION, lambda f, n: learn_recording(f, static, n)
    )
    if learned.laser_moved and model.map_path is None:
        try:
            grid_map, counted = _read_pass(
                open_frames,
                total,
                show,
                MAP_PASS_DESCRIPTION,
                lambda f, n: count_recording_map(f, static, n),
            )
        except LaserPeopleError as exc:  # tracking meets a read error again at its frame
            why = f"the recording could not be read whole ({exc})"
            learned = replace(learned, map_why_not=why)
        else:
            why = "" if grid_map is not None else "no frame had sensor poses"
            learned = replace(learned, grid_map=grid_map, map_frames=counted, map_why_not=why)
    learned = replace(learned, cpu=time.process_time() - start)
    model.use_prelearned(learned)
    return learned


def _read_pass(
    open_frames: Callable[[], Iterable[Frame]],
    total: int | None,
    show: ShowProgress | None,
    description: str,
    learn: Callable[[Iterable[Frame], int | None], _T],
) -> _T:
    """``learn(frames, expected number)`` over a fresh pass ``open_frames()``, its progress
    shown by ``show`` under ``description``; the pass is closed afterwards."""
    frames = open_frames()
    try:
        expect = total if total is not None else getattr(frames, "total", None)
        shown = frames if show is None else show(frames, expect, description)
        return learn(shown, expect)
    finally:
        close = getattr(frames, "close", None)
        if callable(close):
            close()


__all__ = [
    "MAP_PASS_DESCRIPTION",
    "PASS_DESCRIPTION",
    "Prelearned",
    "ShowProgress",
    "count_recording_map",
    "learn_recording",
    "prelearn",
]
