"""Frames of several static lasers from a list of scans (for benchmarks and tests).

The pipeline (``laserpeople.pipeline``) is the general way to make frames; this helper
only groups the scans of the named lasers by their per-laser index, as the simulator
writes them (laser k's i-th scan belongs to instant i), and fuses their points in the world
frame.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from laserpeople.errors import RecordingError
from laserpeople.frame import Frame
from laserpeople.scan import PointSet, Scan
from laserpeople.tracks import Detections


def as_frame(item: Frame | Detections) -> Frame:
    """``item`` itself when it is a frame; for the detections of one scan (the input of the
    per-scan trackers of ``track``, ``bench`` and ``demo``) a frame whose foreground points
    are the detection centres, so that the particle filters also run on a leg detector's
    output (eqs. 3-4 and 9 then weigh leg centres instead of raw points)."""
    if isinstance(item, Frame):
        return item
    n = len(item)
    points = PointSet(
        item.stamp,
        item.positions,
        np.zeros(n, dtype=np.int64),
        np.arange(n, dtype=np.int64),
        ("detections",),
        item.frame,
        item.scan_index,
    )
    return Frame(
        item.scan_index,
        item.stamp,
        (),
        "detections",
        item.frame,
        item.sensor_pose,
        points=points,
        foreground=np.ones(n, dtype=bool),
    )


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


__all__ = ["as_frame", "fused_frames"]
