"""Observe stages: what the trackers measure in a frame.

- :class:`DetectLegs`: leg detections of every laser of the frame, in the frame's
  coordinate frame; where two lasers see the same leg (their views overlap), the weaker
  of two detections closer than ``duplicate_distance`` is dropped (counted).
- :class:`ClusterPoints`: single-linkage clusters of the foreground points (000 Sec. 4.1),
  for trackers that consume clusters (the group tracker).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from laserpeople.clustering import SingleLinkageParams, single_linkage
from laserpeople.config import param
from laserpeople.errors import ConfigError
from laserpeople.frame import Frame, FrameField
from laserpeople.scan import Scan
from laserpeople.tracks import Detections


class LegDetector(Protocol):
    """What the stage needs of a leg detector (``laserpeople.detection.detector``)."""

    def detect(self, scan: Scan) -> Detections:
        """Leg detections of one scan, sensor frame."""
        ...


@dataclass(frozen=True)
class LegFusionParams:
    """How the leg detections of several lasers are merged."""

    config_section = "leg_fusion"

    duplicate_distance: float = param(
        0.1,
        "assumption: a leg radius; two lasers' detections of one leg lie closer than this",
        "of two detections from different lasers closer than this, the lower-scoring one "
        "is dropped",
        "m",
    )


class DetectLegs:
    """Fills ``legs``: every laser's leg detections, in the frame's coordinate frame.

    Attributes:
        duplicates: Detections dropped as another laser's view of the same leg.
    """

    consumes: frozenset[FrameField] = frozenset({"scans"})
    provides: frozenset[FrameField] = frozenset({"legs"})

    def __init__(
        self,
        detector: LegDetector,
        params: LegFusionParams | None = None,
        *,
        keep_classification: bool = False,
    ) -> None:
        self.detector = detector
        self.params = params or LegFusionParams()
        self.keep_classification = keep_classification
        self.duplicates = 0
        self.per_scan: tuple[Detections, ...] = ()
        """The last frame's detections of each scan, sensor frame (for per-laser output)."""
        self._ready: dict[int, tuple[Scan, Detections]] = {}  # prefetched, by scan
        self.classifications: tuple[Any, ...] = ()
        """With ``keep_classification``: the last frame's ``ScanClassification`` per scan
        (every segment with its features and score; the detector needs ``classify``)."""
        self._last: tuple[tuple[Scan, ...], Detections] | None = None
        """The scans of the last frame and their legs: a frame asked for again (by the
        foreground's narrowing to points near legs, then by the pipeline) is not detected
        again (the detector would take it as its own previous scan)."""

    def prefetch(self, frames: Sequence[Frame]) -> None:
        """Detect the legs of every scan of ``frames`` (frames about to come, in order) at
        once, when the detector can (``detect_many``); :meth:`__call__` then takes them
        (the same detections as one scan at a time)."""
        self._ready = {}
        many = getattr(self.detector, "detect_many", None)
        if many is None or self.keep_classification:
            return
        scans = [scan for frame in frames for scan in frame.scans]
        self._ready = {id(s): (s, d) for s, d in zip(scans, many(scans), strict=True)}

    def _detect(self, scan: Scan) -> Detections:
        ready = self._ready.pop(id(scan), None)
        if ready is not None and ready[0] is scan:
            return ready[1]
        if not self.keep_classification:
            return self.detector.detect(scan)
        result = self.detector.classify(scan)  # type: ignore[attr-defined]
        self.classifications += (result,)
        dets: Detections = self.detector.detections_from(scan, result)  # type: ignore[attr-defined]
        return dets

    def __call__(self, frame: Frame) -> Frame:
        """The frame with its legs (those of the last call when ``frame`` holds the same
        scans: each frame is detected once, however many stages ask)."""
        last = self._last
        if last is not None and _same_scans(last[0], frame.scans):
            return frame.with_fields(legs=last[1])
        self.classifications = ()
        per_scan = tuple(self._detect(scan) for scan in frame.scans)
        self.per_scan = per_scan
        if frame.frame == "world":
            placed = [d.to_world() for d in per_scan]
        else:
            if len(per_scan) > 1:
                raise ConfigError(
                    f"frame {frame.index}: several lasers' legs can only be merged in the "
                    "world frame",
                    hint="give the laser mounts with --mount, or track one --topic",
                )
            placed = list(per_scan)
        legs = placed[0] if len(placed) == 1 else self._merge(frame, placed)
        self._last = (frame.scans, legs)
        return frame.with_fields(legs=legs)

    def _merge(self, frame: Frame, parts: list[Detections]) -> Detections:
        positions = np.concatenate([d.positions for d in parts])
        covariances = np.concatenate([d.covariances for d in parts])
        scores = np.concatenate([d.scores for d in parts])
        sensor = np.concatenate([np.full(len(d), i) for i, d in enumerate(parts)])
        segments = tuple(s for d in parts for s in d.segments)
        keep = np.ones(len(scores), dtype=bool)
        if len(scores) > 1:
            gap = np.linalg.norm(positions[:, None, :] - positions[None, :, :], axis=2)
            close = (gap < self.params.duplicate_distance) & (sensor[:, None] != sensor[None, :])
            # drop i when a closer-than-threshold detection of another laser scores higher
            # (ties: the later one goes)
            order = np.arange(len(scores))
            beats = (scores[None, :] > scores[:, None]) | (
                (scores[None, :] == scores[:, None]) & (order[None, :] < order[:, None])
            )
            keep = ~(close & beats).any(axis=1)
            self.duplicates += int(np.count_nonzero(~keep))
        return Detections(
            frame.stamp,
            frame.index,
            positions[keep],
            covariances[keep],
            scores[keep],
            "world",
            frame.sensor_pose,
            tuple(s for s, k in zip(segments, keep, strict=True) if k)
            if len(segments) == len(keep)
            else (),
        )


def _same_scans(a: Sequence[Scan], b: Sequence[Scan]) -> bool:
    """Whether ``a`` and ``b`` hold the same scan objects, in order."""
    return len(a) == len(b) and all(x is y for x, y in zip(a, b, strict=True))


class ClusterPoints:
    """Fills ``clusters``: single-linkage labels of the foreground points (000 Sec. 4.1)."""

    consumes: frozenset[FrameField] = frozenset({"points", "foreground"})
    provides: frozenset[FrameField] = frozenset({"clusters"})

    def __init__(self, params: SingleLinkageParams | None = None) -> None:
        self.params = params or SingleLinkageParams()

    def __call__(self, frame: Frame) -> Frame:
        """The frame with its cluster labels."""
        if frame.points is None:
            raise ConfigError(f"frame {frame.index} has no points", hint="run Fuse first")
        labels = single_linkage(
            frame.points.points,
            self.params.distance,
            frame.foreground,
            self.params.min_points,
        )
        return frame.with_fields(clusters=labels)


__all__ = ["ClusterPoints", "DetectLegs", "LegDetector", "LegFusionParams"]
