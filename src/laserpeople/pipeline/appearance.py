"""Colour appearance for a recording: where ``frame.appearance`` comes from.

No reader of this project decodes camera images, so the only source of appearance is the
simulated camera (:class:`~laserpeople.sim.camera.SimulatedCamera`) fed by the clothing
hues of a recording's ground truth (``.npz`` recordings from ``laserpeople simulate``).
:func:`with_appearance` wraps a pipeline source so that every frame carries the camera's
observations, or raises :class:`AppearanceUnavailableError` naming the file.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace
from typing import Any

import numpy as np

from laserpeople.errors import ConfigError
from laserpeople.frame import Frame
from laserpeople.truth import TruthFrame

MAX_TRUTH_OFFSET = 0.05
"""A frame takes the truth frame nearest in time, at most this far off [s] (half a scan
period at 10 Hz)."""


class AppearanceUnavailableError(ConfigError):
    """The recording has no colour appearance (no camera, no ground truth with hues)."""


class SimulatedAppearance:
    """Frames of ``frames`` with ``appearance`` from a simulated camera looking at the
    people of ``truth`` (and ``truth`` filled in).

    Truth positions are in the world frame; in a sensor-frame run they are moved into the
    sensor frame with the frame's pose (frames without a pose get no observations).
    Other attributes (``topics``, ``total``, ``summary``, ``close``) are the wrapped
    source's.
    """

    def __init__(self, frames: Any, truth: list[TruthFrame], seed: int = 0) -> None:
        from laserpeople.sim.camera import SimulatedCamera

        self.frames = frames
        self.truth = truth
        self.camera = SimulatedCamera(seed=seed)
        self._stamps = np.array([t.stamp for t in truth])

    def _truth_at(self, stamp: float) -> TruthFrame | None:
        if self._stamps.size == 0:
            return None
        k = int(np.argmin(np.abs(self._stamps - stamp)))
        return self.truth[k] if abs(self._stamps[k] - stamp) <= MAX_TRUTH_OFFSET else None

    def __iter__(self) -> Iterator[Frame]:
        for frame in self.frames:
            truth = self._truth_at(frame.stamp)
            if truth is None:
                yield frame
                continue
            positions = truth.positions
            if frame.frame == "sensor":
                if frame.sensor_pose is None:
                    yield replace(frame, truth=truth)
                    continue
                positions = frame.sensor_pose.inverse_transform_points(positions)
            obs = self.camera.observe(frame.stamp, truth.person_ids, positions, truth.hues)
            yield replace(frame, appearance=obs, truth=truth)

    def __getattr__(self, name: str) -> Any:
        if name == "frames":
            raise AttributeError(name)
        return getattr(self.frames, name)


def with_appearance(frames: Any, recording: Any) -> SimulatedAppearance:
    """``frames`` with simulated colour observations from ``recording``'s truth hues.

    Raises:
        AppearanceUnavailableError: The recording has no ground truth with clothing hues.
    """
    truth_of = getattr(recording, "truth", None)
    has_truth = bool(getattr(recording, "has_truth", False))
    truth = list(truth_of()) if callable(truth_of) and has_truth else []
    if not any(np.isfinite(t.hues).any() for t in truth):
        raise AppearanceUnavailableError(
            "the recording has no colour appearance: no camera is read, and it has no "
            "ground truth with clothing hues for the simulated camera",
            path=getattr(recording, "path", None),
            hint="use an .npz recording from `laserpeople simulate`, or run without "
            "--appearance on / --reidentify colour",
        )
    return SimulatedAppearance(frames, truth)


__all__ = [
    "MAX_TRUTH_OFFSET",
    "AppearanceUnavailableError",
    "SimulatedAppearance",
    "with_appearance",
]
