"""Frames of several static lasers from a list of scans (for benchmarks and tests), and
the foreground points of a frame moved from a body's surface towards its centre.

The pipeline (``laserpeople.pipeline``) is the general way to make frames; this helper
only groups the scans of the named lasers by their per-laser index, as the simulator
writes them (laser k's i-th scan belongs to instant i), and fuses their points in the world
frame.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from laserpeople.errors import RecordingError
from laserpeople.frame import Frame
from laserpeople.scan import PointSet, Scan


def fused_frames(
    scans: Sequence[Scan],
    sensors: Sequence[str],
    preprocess: Callable[[Frame], Frame] | None = None,
) -> list[Frame]:
    """One frame per scan index holding the scans of ``sensors`` (world-frame points);
    ``preprocess`` (e.g. a background model) is applied to each frame in order. Indices at
    which a laser has no scan are left out."""
    by_index: dict[int, dict[str, Scan]] = {}
    for scan in scans:
        if scan.sensor in sensors:
            by_index.setdefault(scan.index, {})[scan.sensor] = scan
    if not by_index:
        raise RecordingError(
            f"no scans of {', '.join(sensors)}",
            hint="name lasers that are in the recording",
        )
    frames = []
    for index in sorted(by_index):
        group = by_index[index]
        if len(group) != len(sensors):
            continue
        ordered = tuple(group[name] for name in sensors)
        first = ordered[0]
        frame = Frame(
            index=index,
            stamp=max(s.stamp for s in ordered),
            scans=ordered,
            topic="fused",
            frame="world",
            sensor_pose=first.pose,
            points=PointSet.from_scans(list(ordered), "world"),
        )
        frames.append(preprocess(frame) if preprocess is not None else frame)
    return frames


def beam_directions(frame: Frame, consumer: str) -> NDArray[np.float64]:
    """Unit vectors (K, 2) along the beams that measured the frame's foreground points
    (from each point's laser to the point), in the frame's ``frame``; zeros when a laser
    of a world frame has no pose (the directions are then unknown)."""
    pts = frame.foreground_points(consumer)
    if frame.points is None or len(pts) == 0:
        return np.zeros((len(pts), 2))
    ps = frame.points
    ids = ps.sensor_ids if frame.foreground is None else ps.sensor_ids[frame.foreground]
    origins = np.zeros((len(ps.sensors), 2))
    if frame.frame == "world":
        poses = {s.sensor: s.pose for s in frame.scans}
        for i, name in enumerate(ps.sensors):
            pose = poses.get(name)
            if pose is None:
                return np.zeros((len(pts), 2))
            origins[i] = (pose.x, pose.y)
    ray = pts - origins[ids]
    norm = np.maximum(np.hypot(ray[:, 0], ray[:, 1]), 1e-9)
    return np.asarray(ray / norm[:, None], dtype=np.float64)


def shifted_foreground(frame: Frame, offset: float, consumer: str) -> NDArray[np.float64]:
    """The frame's foreground points (K, 2) [m], each moved ``offset`` [m] farther along
    the beam that measured it (away from its laser): a laser sees the near surface of a
    body, whose centre lies about half the body's depth behind it along the beam.
    Lasers without a pose in a world frame (and ``offset`` 0) leave the points as they
    are."""
    pts = frame.foreground_points(consumer)
    if offset == 0.0 or len(pts) == 0:
        return pts
    return np.asarray(pts + offset * beam_directions(frame, consumer), dtype=np.float64)


__all__ = ["beam_directions", "fused_frames", "shifted_foreground"]
