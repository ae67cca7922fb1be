"""The feet tracker (``feet-pf``) with one of its inputs replaced by the truth, to tell which
part limits it on a simulated recording: the foreground, or the births.

Each mode runs ``feet-pf`` with its defaults through the pipeline as ``track`` does, and
changes one thing per scan (truth from the recording, in the frame of the tracker's points):

- ``oracle-foreground``: the foreground is exactly the returns within
  :data:`NEAR_LEG` of a true leg centre (no missed legs, no clutter);
- ``oracle-foreground-added``: the pipeline's foreground plus those returns (no missed legs;
  clutter stays);
- ``oracle-foreground-cut``: the pipeline's foreground less everything else (no clutter;
  missed legs stay missed);
- ``oracle-births``: after each update a filter starts on the true legs of every person the
  laser shows (a return within :data:`NEAR_LEG` of a leg centre) with no filter's feet
  midpoint within :data:`BIRTH_GAP` (a new identity each time, as a birth gets).

``benchmarks/feet_ceiling.py --trackers feet-pf oracle-foreground oracle-births`` scores them
beside the other trackers.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.frame import Frame
from laserpeople.io import open_recording
from laserpeople.lazy_scipy import cKDTree
from laserpeople.pipeline import build
from laserpeople.tracking import registry
from laserpeople.tracks import Tracks

NEAR_LEG = 0.15
"""Returns this close to a true leg centre are the leg's [m] (radii 0.05-0.09 m)."""
BIRTH_GAP = 0.4
"""An oracle birth needs no filter's feet midpoint this close to the person [m]."""
MODES = (
    "oracle-foreground",
    "oracle-foreground-added",
    "oracle-foreground-cut",
    "oracle-births",
)


def near_legs(points: NDArray[np.float64], legs: NDArray[np.float64]) -> NDArray[np.bool_]:
    """(N,) which ``points`` (N, 2) lie within :data:`NEAR_LEG` of a leg centre of ``legs``
    (P, 2, 2); all in one frame."""
    if len(points) == 0 or len(legs) == 0:
        return np.zeros(len(points), dtype=bool)
    d, _ = cKDTree(legs.reshape(-1, 2)).query(points, k=1)
    return np.asarray(d <= NEAR_LEG, dtype=bool)


def _in_frame(frame: Frame, world: NDArray[np.float64]) -> NDArray[np.float64]:
    """World positions (..., 2) in the frame of ``frame``'s points."""
    if frame.frame == "sensor" and frame.sensor_pose is not None:
        flat = frame.sensor_pose.inverse_transform_points(world.reshape(-1, 2))
        return np.asarray(flat, dtype=np.float64).reshape(world.shape)
    return world


def track_with_oracle(npz: Path, out: Path, mode: str) -> Path:
    """Track the simulated recording ``npz`` with ``feet-pf`` and the oracle ``mode`` (one
    of :data:`MODES`); the tracks CSV ``out``."""
    if mode not in MODES:
        raise ValueError(f"mode must be one of {', '.join(MODES)}, not {mode!r}")
    with open_recording(npz) as rec:
        legs_at = {t.scan_index: t.leg_positions for t in rec.truth()}
    tracker: Any = registry.get("feet-pf").make(None)
    update = tracker.update

    def oracle_update(frame: Frame) -> Tracks:
        world = legs_at.get(frame.index)
        if world is None or len(world) == 0 or frame.points is None:
            result: Tracks = update(frame)
            return result
        legs = _in_frame(frame, np.asarray(world, dtype=np.float64))
        pts = np.asarray(frame.points.points, dtype=np.float64)
        on_leg = near_legs(pts, legs)
        own = np.ones(len(pts), dtype=bool) if frame.foreground is None else frame.foreground
        if mode == "oracle-foreground":
            frame = replace(frame, foreground=on_leg)
        elif mode == "oracle-foreground-added":
            frame = replace(frame, foreground=own | on_leg)
        elif mode == "oracle-foreground-cut":
            frame = replace(frame, foreground=own & on_leg)
        result = update(frame)
        if mode == "oracle-births":
            _oracle_births(tracker, legs, pts, frame.stamp)
        return result

    tracker.update = oracle_update
    build(npz, tracker=tracker, outputs=[out]).run()
    return out


def _oracle_births(
    tracker: Any, legs: NDArray[np.float64], pts: NDArray[np.float64], stamp: float
) -> None:
    """Start a filter on the legs (P, 2, 2) of each person the returns ``pts`` show with no
    filter's feet midpoint within :data:`BIRTH_GAP`."""
    if len(pts) == 0:
        return
    d, _ = cKDTree(pts).query(legs.reshape(-1, 2), k=1)
    shown = (d.reshape(-1, 2) <= NEAR_LEG).any(axis=1)
    mids = legs.mean(axis=1)
    bank = tracker.bank
    if len(bank):
        est = np.einsum("fp,fpc->fc", bank.weights, tracker.midpoints())
        free = cKDTree(est).query(mids, k=1)[0] > BIRTH_GAP
    else:
        free = np.ones(len(mids), dtype=bool)
    starts = [tracker._initial(legs[j]) for j in np.flatnonzero(shown & free)]
    if starts:
        bank.add(np.stack(starts), stamp)
