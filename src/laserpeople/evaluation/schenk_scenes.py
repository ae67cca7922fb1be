"""Run a frame tracker on one simulated 004 scene and score it with the adapted MOTP.

The static world comes from a background recording: the same scene without people,
simulated for ``background_seconds`` and learned by the per-beam histogram
(:class:`~laserpeople.background.beam_histogram.BeamHistogramBackground`). Frames fuse
the two feet-height lasers (``"feet"``) or the two upper-body lasers (``"torso"``); the
truth frames belong to the first laser of the scene, whose scan index every laser shares.
A tracker that consumes ``legs`` (the leg MHT) gets the leg detections of the fused lasers
from the pipeline's leg detection stage
(:class:`~laserpeople.pipeline.observe.DetectLegs` with the shipped AdaBoost detector).
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable
from dataclasses import dataclass

from laserpeople.background.beam_histogram import BeamHistogramBackground, BeamHistogramParams
from laserpeople.evaluation.schenk_motp import SchenkMotp
from laserpeople.frame import FrameTracker
from laserpeople.sim.scenarios import build_scene, get_scenario
from laserpeople.sim.simulator import SimResult, simulate
from laserpeople.tracking.particle.frames import fused_frames


@dataclass(frozen=True)
class SceneRun:
    """The result of one tracker on one simulated scene.

    Attributes:
        scene: Scenario name.
        seed: Its seed.
        motp: 004's adapted MOTP (eq. 11).
        scans: Frames tracked.
        ms_per_scan: Mean CPU time of ``update`` per frame [ms] (background subtraction not
            included).
        tracks: Distinct track ids reported.
    """

    scene: str
    seed: int
    motp: float
    scans: int
    ms_per_scan: float
    tracks: int


def simulate_scene(
    name: str, seed: int, rate: float | None = None, background_seconds: float = 1.0
) -> tuple[SimResult, SimResult]:
    """The recording of scenario ``name`` and a background recording of the same room and
    lasers without people."""
    s = get_scenario(name)
    scene = build_scene(name, seed=seed)
    rec = simulate(scene, s.duration, seed=seed, rate=rate, name=name)
    empty = dataclasses.replace(scene, people=[])
    bg = simulate(empty, background_seconds, seed=seed + 10_000, rate=rate, name=name + "-empty")
    return rec, bg


def lasers_of(rec: SimResult, height: str) -> list[str]:
    """Names of the lasers at ``height`` ("feet" <= 0.5 m, "torso" above)."""
    out = []
    for s in rec.meta["sensors"]:
        z = float(s.get("height_m", s.get("height", 0.0)))
        if (z <= 0.5) == (height == "feet"):
            out.append(str(s["name"]))
    return out


def run_tracker(
    rec: SimResult,
    background: SimResult,
    height: str,
    tracker: FrameTracker,
    name: str = "",
    seed: int = 0,
) -> SceneRun:
    """Track the ``height`` lasers of ``rec`` and score against its truth."""
    sensors = lasers_of(rec, height)
    bg = BeamHistogramBackground(BeamHistogramParams()).learn_scans(
        s for s in background.scans if s.sensor in sensors
    )
    frames = fused_frames(rec.scans, sensors, bg)
    if "legs" in tracker.consumes:
        from laserpeople.detection.detector import AdaBoostLegDetector
        from laserpeople.pipeline.observe import DetectLegs

        legs = DetectLegs(AdaBoostLegDetector.default())
        frames = [legs(f) for f in frames]
    truth = {t.scan_index: t for t in rec.truth}
    motp = SchenkMotp(keep_frames=False)
    ids: set[int] = set()
    spent = 0.0
    for frame in frames:
        t0 = time.process_time()
        tracks = tracker.update(frame)
        spent += time.process_time() - t0
        ids.update(t.track_id for t in tracks)
        if frame.index in truth:
            motp.accumulate(truth[frame.index], tracks)
    return SceneRun(
        name, seed, motp.result().motp, len(frames), 1000.0 * spent / max(len(frames), 1), len(ids)
    )


def run_scene(
    name: str,
    seed: int,
    trackers: dict[str, tuple[str, Callable[[], FrameTracker]]],
    rate: float | None = None,
) -> dict[str, SceneRun]:
    """Simulate scene ``name`` once and run every tracker of ``trackers`` (label ->
    (height, factory)) on it."""
    rec, bg = simulate_scene(name, seed, rate)
    return {
        label: run_tracker(rec, bg, height, factory(), name, seed)
        for label, (height, factory) in trackers.items()
    }


__all__ = ["SceneRun", "lasers_of", "run_scene", "run_tracker", "simulate_scene"]
