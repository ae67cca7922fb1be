"""One instant of every laser, the unit that flows through a pipeline: :class:`Frame`.

A source yields frames that carry only ``scans``; each stage returns a copy with its own
fields filled in (``dataclasses.replace``), so a frame is never changed after it is made and
any stage can be run alone on a hand-made frame. What each field holds, and which stage
fills it:

=============  ==================  ========================================================
field          filled by           contents
=============  ==================  ========================================================
scans          source              the scans of this instant, one per laser (``Scan``)
points         preprocess          every valid point of every scan in ``points.frame``
foreground     preprocess          (N,) bool over ``points``: not explained by the static
                                   world model (all True without one)
clusters       observe             (N,) int64 over ``points``: cluster label, -1 = none
legs           observe             leg ``Detections`` in the tracking frame
appearance     source / observe    colour observations of people (camera or simulator)
truth          source              ``TruthFrame`` when the recording has ground truth
=============  ==================  ========================================================
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import Any, Literal, Protocol

import numpy as np
from numpy.typing import NDArray

from laserpeople.scan import CoordinateFrame, PointSet, Pose2D, Scan
from laserpeople.tracks import Detections, Tracks
from laserpeople.truth import TruthFrame

#: What a tracker may consume from a frame (see :attr:`FrameConsumer.consumes`).
FrameField = Literal["scans", "points", "foreground", "clusters", "legs", "appearance"]


@dataclass(frozen=True, eq=False)
class AppearanceObservation:
    """One colour observation of one person, from a camera region or the simulator.

    Attributes:
        position: Where the observed person stands (2,) [m], in the frame's ``frame``.
        hues: Hue samples of the person's clothing (K,) [rad], in (-pi, pi].
        person_hint: Ground-truth id when the observation comes from the simulator (only
            for evaluation; trackers must not read it), -1 otherwise.
    """

    position: NDArray[np.float64]
    hues: NDArray[np.float64]
    person_hint: int = -1

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", np.asarray(self.position, dtype=np.float64).reshape(2))
        object.__setattr__(self, "hues", np.asarray(self.hues, dtype=np.float64).reshape(-1))


@dataclass(frozen=True, eq=False)
class Frame:
    """Everything known about one instant of a recording.

    Attributes:
        index: 0-based index of the frame in its sequence: the scan index on its topic (for
            several lasers, that of the first (reference) laser's scan).
        stamp: Time of the frame [s]: the (reference laser's) scan's stamp.
        scans: The scans of this instant, one per laser, in the order of ``topics``.
        topic: The topic, or ``"fused"`` when several lasers make the frame.
        frame: The coordinate frame of ``points``, ``legs`` and the tracks, one for the whole
            run: ``"world"`` when most frames have sensor poses, else ``"sensor"`` (the
            laser's own frame; one laser only).
        sensor_pose: Pose of the first laser in the world frame, when known.
        points: All valid points of all scans in ``frame`` (with sensor and beam ids).
        foreground: (N,) bool over ``points``; True where the static world model does not
            explain the point.
        clusters: (N,) int64 cluster label per point (-1 = unclustered or background).
        legs: Leg detections in ``frame``.
        appearance: Colour observations of people at this instant.
        truth: Ground truth at this instant, when known.
        missing: Names of lasers expected but absent in this frame (late or dropped).
    """

    index: int
    stamp: float
    scans: tuple[Scan, ...]
    topic: str
    frame: CoordinateFrame = "sensor"
    sensor_pose: Pose2D | None = None
    points: PointSet | None = None
    foreground: NDArray[np.bool_] | None = field(default=None, repr=False)
    clusters: NDArray[np.int64] | None = field(default=None, repr=False)
    legs: Detections | None = None
    appearance: tuple[AppearanceObservation, ...] = ()
    truth: TruthFrame | None = field(default=None, repr=False)
    missing: tuple[str, ...] = ()

    def foreground_points(self, consumer: str) -> NDArray[np.float64]:
        """The points (K, 2) [m] marked foreground (all points without a mask).

        Raises:
            ConfigError: the frame has no points; ``consumer`` names who needed them.
        """
        if self.points is None:
            from laserpeople.errors import ConfigError

            raise ConfigError(
                f"{consumer} needs frame points",
                scan=self.index,
                hint="build frames with points and foreground (a background model)",
            )
        pts = self.points.points
        if self.foreground is not None:
            pts = pts[self.foreground]
        return np.asarray(pts, dtype=np.float64)

    def with_fields(self, **changes: Any) -> Frame:
        """A copy with ``changes``: :func:`dataclasses.replace` without re-running
        ``__init__`` (stages call it once per frame; it costs a few microseconds less).

        Raises:
            TypeError: A name in ``changes`` is not a field of :class:`Frame`.
        """
        unknown = changes.keys() - _FRAME_FIELDS
        if unknown:
            raise TypeError(f"Frame has no field(s) {', '.join(sorted(unknown))}")
        new = object.__new__(Frame)
        new.__dict__.update(self.__dict__)
        new.__dict__.update(changes)
        return new


_FRAME_FIELDS = frozenset(f.name for f in fields(Frame))


class FrameConsumer(Protocol):
    """A stage that reads fields of a frame; the pipeline checks at build time that an
    earlier stage fills each of them."""

    consumes: frozenset[FrameField]


class FrameTracker(FrameConsumer, Protocol):
    """A streaming tracker: one frame in, the current best estimate out, bounded memory."""

    def update(self, frame: Frame) -> Tracks:
        """Process one frame and return the tracks after it."""
        ...
