"""Detections (what a detector found in one scan) and tracks (what a tracker believes).

Positions [m] and velocities [m/s] are in the frame named by ``frame``.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from laserpeople.scan import CoordinateFrame, Pose2D, Segment

TrackKind = Literal["leg", "person", "group"]
TRACK_KINDS: tuple[TrackKind, ...] = ("leg", "person", "group")


@dataclass(frozen=True, eq=False)
class Detections:
    """Detected objects (legs, people or blobs) of one scan or point set.

    Attributes:
        stamp: Time of the scan [s].
        scan_index: 0-based index of the scan on its topic.
        positions: Centres (M, 2) [m] in ``frame``.
        covariances: Measurement covariances (M, 2, 2) [m^2].
        scores: Detector confidence (M,); larger is more certain (AdaBoost margin, 1.0 for
            rule-based detectors).
        frame: Frame of ``positions``.
        sensor_pose: Pose of the sensor in the world frame, if known.
        segments: The segment behind each detection (M,), when the detector is segment-based.
    """

    stamp: float
    scan_index: int
    positions: NDArray[np.float64]
    covariances: NDArray[np.float64]
    scores: NDArray[np.float64]
    frame: CoordinateFrame = "sensor"
    sensor_pose: Pose2D | None = None
    segments: tuple[Segment, ...] = field(default=(), repr=False)

    def __post_init__(self) -> None:
        pos = np.asarray(self.positions, dtype=np.float64).reshape(-1, 2)
        m = pos.shape[0]
        object.__setattr__(self, "positions", pos)
        object.__setattr__(
            self, "covariances", np.asarray(self.covariances, dtype=np.float64).reshape(m, 2, 2)
        )
        object.__setattr__(self, "scores", np.asarray(self.scores, dtype=np.float64).reshape(m))
        if self.segments and len(self.segments) != m:
            raise ValueError(f"{len(self.segments)} segments for {m} detections")

    def __len__(self) -> int:
        return int(self.positions.shape[0])

    @classmethod
    def empty(
        cls,
        stamp: float,
        scan_index: int,
        frame: CoordinateFrame = "sensor",
        sensor_pose: Pose2D | None = None,
    ) -> Detections:
        """No detections."""
        return cls(
            stamp,
            scan_index,
            np.empty((0, 2)),
            np.empty((0, 2, 2)),
            np.empty(0),
            frame,
            sensor_pose,
        )

    def to_world(self) -> Detections:
        """These detections in the world frame (requires ``sensor_pose`` when in sensor frame)."""
        if self.frame == "world":
            return self
        if self.sensor_pose is None:
            from laserpeople.errors import PoseUnavailableError

            raise PoseUnavailableError("detections have no sensor pose", scan=self.scan_index)
        rot = self.sensor_pose.rotation()
        return Detections(
            self.stamp,
            self.scan_index,
            self.sensor_pose.transform_points(self.positions),
            rot @ self.covariances @ rot.T,
            self.scores,
            "world",
            self.sensor_pose,
            self.segments,
        )


_FLOAT64 = np.dtype(np.float64)

_NO_CONTOUR = np.empty((0, 2))
_NO_CONTOUR.setflags(write=False)
"""The contour of a track without one (legs, persons): one empty read-only array for all."""


@dataclass(frozen=True, eq=False)
class Track:
    """One track's estimate at one time.

    Attributes:
        track_id: Identity, unique among tracks of the same kind in one run.
        kind: "leg", "person" or "group".
        position: (2,) [m].
        velocity: (2,) [m/s].
        covariance: Position covariance (2, 2) [m^2].
        size: Estimated number of people (1 for legs and persons).
        labels: Group label set such as ``"1-0|2"`` (empty for legs/persons).
        score: Tracker-specific confidence in [0, 1] (e.g. hypothesis probability).
        members: Ids of the tracks this one is built from (the legs of a person).
        contour: Group contour (K, 2) [m], empty for legs and persons.
    """

    track_id: int
    kind: TrackKind
    position: NDArray[np.float64]
    velocity: NDArray[np.float64]
    covariance: NDArray[np.float64]
    size: int = 1
    labels: str = ""
    score: float = 1.0
    members: tuple[int, ...] = ()
    contour: NDArray[np.float64] = field(default_factory=lambda: _NO_CONTOUR, repr=False)

    def __post_init__(self) -> None:
        # (float64 arrays of the right shape, what the trackers give, are kept as they are)
        p, v, c = self.position, self.velocity, self.covariance
        if type(p) is not np.ndarray or p.shape != (2,) or p.dtype is not _FLOAT64:
            object.__setattr__(self, "position", np.asarray(p, dtype=np.float64).reshape(2))
        if type(v) is not np.ndarray or v.shape != (2,) or v.dtype is not _FLOAT64:
            object.__setattr__(self, "velocity", np.asarray(v, dtype=np.float64).reshape(2))
        if type(c) is not np.ndarray or c.shape != (2, 2) or c.dtype is not _FLOAT64:
            object.__setattr__(self, "covariance", np.asarray(c, dtype=np.float64).reshape(2, 2))


@dataclass(frozen=True, eq=False)
class Tracks:
    """All tracks a tracker reports after one scan.

    Attributes:
        stamp: Time [s].
        scan_index: 0-based index of the scan on its topic.
        tracks: The tracks, any kinds mixed.
        frame: Frame of the positions.
        sensor_pose: Sensor pose in the world frame at ``stamp``, if known (lets writers
            convert between frames).
    """

    stamp: float
    scan_index: int
    tracks: tuple[Track, ...] = ()
    frame: CoordinateFrame = "world"
    sensor_pose: Pose2D | None = None

    def __len__(self) -> int:
        return len(self.tracks)

    def __iter__(self) -> Iterator[Track]:
        return iter(self.tracks)

    def of_kind(self, kind: TrackKind) -> tuple[Track, ...]:
        """The tracks of one kind."""
        return tuple(t for t in self.tracks if t.kind == kind)
