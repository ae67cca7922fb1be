"""The frame choice buffers its first frames to decide, and lets each go once handed on:
a long run keeps no early scans (and their cached points) for its whole length."""

from __future__ import annotations

import gc
import weakref
from collections.abc import Iterator

import numpy as np

from laserpeople.pipeline import FrameChooser, laser_frames
from laserpeople.scan import Pose2D, Scan


def _scans(n: int, refs: list[weakref.ref[Scan]]) -> Iterator[Scan]:
    """``n`` scans of 90 beams made on demand (only the generator's caller holds them),
    each with a weak reference in ``refs``."""
    for i in range(n):
        scan = Scan(0.1 * i, -np.pi / 4, np.pi / 180, np.full(90, 3.0), 0.1, 10.0, index=i)
        refs.append(weakref.ref(scan))
        yield scan


def test_buffered_frames_are_released_once_handed_on() -> None:
    refs: list[weakref.ref[Scan]] = []
    chooser = FrameChooser("auto", window=5)
    seen = []
    for frame in chooser(laser_frames(_scans(12, refs))):
        seen.append(frame.index)
        if frame.index == 8:
            del frame
            gc.collect()
            # the five buffered frames and those after them are gone; only the frame being
            # handed on (8) may still be held by the generators
            alive = [i for i, r in enumerate(refs) if r() is not None]
            assert alive and all(i >= 8 for i in alive), alive
    assert seen == list(range(12)) and chooser.stats.frame == "sensor"
    assert chooser.stats.window == 5


def test_world_frame_still_chosen_from_the_buffer() -> None:
    pose = Pose2D(1.0, 2.0, 0.5)
    scans = [
        Scan(0.1 * i, -np.pi / 4, np.pi / 180, np.full(90, 3.0), 0.1, 10.0, index=i, pose=pose)
        for i in range(8)
    ]
    refs = [weakref.ref(s) for s in scans]
    chooser = FrameChooser("auto", window=5)
    frames = list(chooser(laser_frames(scans)))
    assert chooser.stats.frame == "world" and [f.index for f in frames] == list(range(8))
    assert all(f.sensor_pose == pose for f in frames) and all(r() is not None for r in refs)
