"""The one-command demo: simulate the ``demo`` scenario, detect legs, track with every
registered tracker fed by leg detections alone, score against the simulator's ground truth,
and draw the leg MHT's tracks.

The flow is the library's pipeline (:mod:`laserpeople.pipeline`): the simulated scans of
the first sensor become frames in the world frame, one observe-only pipeline detects the
legs once, and each tracker runs in its own pipeline over those frames.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

from laserpeople.detection.detector import AdaBoostLegDetector
from laserpeople.errors import LaserPeopleError
from laserpeople.evaluation import evaluate
from laserpeople.frame import Frame, FrameTracker
from laserpeople.io.paths import make_folder
from laserpeople.pipeline import DetectLegs, FrameChooser, Pipeline, TracksCsvSink, laser_frames
from laserpeople.pipeline.recording import LOOKAHEAD
from laserpeople.scan import Scan
from laserpeople.sim import SimResult, run_scenario
from laserpeople.tracking import registry
from laserpeople.tracks import Tracks
from laserpeople.truth import TruthFrame

T = TypeVar("T")
Progress = Callable[[Iterable[Any], int | None, str], Iterable[Any]]

DEMO_SCENARIO = "demo"
MAIN_TRACKER = "leg-mht"
GIF_MAX_FRAMES = 250


@dataclass(frozen=True)
class TrackerScore:
    """One tracker's result on the demo.

    Attributes:
        name: Tracker name.
        summary: CLEAR MOT / IDF1 numbers (``EvaluationReport.summary()``; None = undefined).
        ms_per_scan: Mean tracking time per scan [ms] (detection not included).
        n_tracks: Distinct person track ids reported.
    """

    name: str
    summary: dict[str, float | int | None]
    ms_per_scan: float
    n_tracks: int


@dataclass(frozen=True)
class DemoResult:
    """Everything the demo produced.

    Attributes:
        scores: One entry per tracker that ran, the leg MHT first.
        skipped: ``(tracker, reason)`` for registered trackers that failed on the demo.
        n_scans: Scans simulated (first sensor).
        n_people: People in the scene.
        seconds: Simulated duration [s].
        detection_ms_per_scan: Mean leg detection time per scan [ms].
        n_detections: Leg detections over all scans.
        recording: The simulated recording (.npz, with ground truth).
        tracks_csv: The leg MHT's tracks.
        gif: The animation (None when not drawn).
        gif_frames: Frames in the animation.
    """

    scores: list[TrackerScore]
    skipped: list[tuple[str, str]]
    n_scans: int
    n_people: int
    seconds: float
    detection_ms_per_scan: float
    n_detections: int
    recording: Path
    tracks_csv: Path
    gif: Path | None
    gif_frames: int
    meta: dict[str, Any] = field(default_factory=dict)


def _no_progress(items: Iterable[T], total: int | None, description: str) -> Iterable[T]:
    return items


def simulate_demo(
    seconds: float | None, seed: int
) -> tuple[list[Scan], list[TruthFrame], SimResult]:
    """Run the ``demo`` scenario; returns the first sensor's scans, the truth, the result."""
    result = run_scenario(DEMO_SCENARIO, seconds=seconds, seed=seed)
    scans: list[Scan] = list(result.scans)
    if not scans:
        raise LaserPeopleError("the demo scenario produced no scans", hint="try more --seconds")
    first = scans[0].sensor
    return [s for s in scans if s.sensor == first], list(result.truth), result


def tracker_factories() -> list[tuple[str, Callable[[], FrameTracker]]]:
    """``(name, make)`` for every leg-fed tracker of :mod:`laserpeople.tracking.registry`
    (those that consume only a frame's legs, as the demo's frames carry) with its default
    parameters, the leg MHT first."""
    registry.get(MAIN_TRACKER)  # the demo draws its tracks: fail at once if it is gone
    factories = [
        (name, _factory(entry))
        for name, entry in registry.TRACKERS.items()
        if entry.consumes == frozenset({"legs"})
    ]
    factories.sort(key=lambda item: item[0] != MAIN_TRACKER)
    return factories


def _factory(entry: registry.TrackerEntry) -> Callable[[], FrameTracker]:
    """A no-argument maker of a registry entry's tracker with its default parameters."""
    return lambda: entry.make()


def detect_frames(scans: list[Scan], progress: Progress = _no_progress) -> list[Frame]:
    """The scans as world-frame frames with their leg detections (shipped AdaBoost model)."""
    chooser = FrameChooser("world")
    pipe = Pipeline(
        progress(chooser(laser_frames(scans)), len(scans), "detecting"),
        observe=[DetectLegs(AdaBoostLegDetector.default())],
        lookahead=LOOKAHEAD,
    )
    return [step.frame for step in pipe]


def run_tracker(
    make: Callable[[], FrameTracker],
    frames: Iterable[Frame],
    sinks: tuple[TracksCsvSink, ...] = (),
    background: str = "auto",
) -> tuple[list[Tracks], float]:
    """Frames with legs through a new tracker's pipeline (the leg MHT's people ask the
    static world model ``background``, learned from the frames' scans); returns its outputs
    and the mean tracking time per frame [ms] (the model's included)."""
    from laserpeople.pipeline.recording import add_people_static_model

    tracker = make()
    preprocess: list[Any] = []
    add_people_static_model(tracker, preprocess, background)  # the leg MHT's people
    pipe = Pipeline(
        frames,
        preprocess=preprocess,
        tracker=tracker,
        sinks=sinks,
        source_fields=frozenset({"scans", "legs"}),
    )
    outputs = [step.tracks for step in pipe if step.tracks is not None]
    return outputs, pipe.stats.mean_ms


def run_demo(
    out_dir: str | Path,
    *,
    seconds: float | None = None,
    seed: int = 0,
    progress: Progress = _no_progress,
    gif: bool = True,
) -> DemoResult:
    """Simulate, detect, track, evaluate and draw; writes ``demo.npz``, ``demo-tracks.csv``
    and ``demo.gif`` into ``out_dir``."""
    factories = tracker_factories()
    skipped: list[tuple[str, str]] = []
    out = Path(out_dir)
    make_folder(out, "--out-dir")  # (before the simulation)
    scans, truth, sim = simulate_demo(seconds, seed)
    recording = sim.write(out / "demo.npz")

    t0 = time.perf_counter()
    frames = detect_frames(scans, progress)
    det_ms = 1000.0 * (time.perf_counter() - t0) / len(scans)

    tracks_csv = out / "demo-tracks.csv"
    scores: list[TrackerScore] = []
    main_tracks: list[Tracks] = []
    for name, make in factories:
        feed = progress(frames, len(frames), f"tracking ({name})")
        sinks = (TracksCsvSink(tracks_csv, frame="world"),) if name == MAIN_TRACKER else ()
        try:
            outputs, ms = run_tracker(make, feed, sinks)
        except LaserPeopleError as exc:
            if name == MAIN_TRACKER:
                raise
            skipped.append((name, f"failed: {exc}"))
            continue
        report = evaluate(truth, outputs).result()
        ids = {t.track_id for o in outputs for t in o.of_kind("person")}
        scores.append(TrackerScore(name, report.summary(), ms, len(ids)))
        if name == MAIN_TRACKER:
            main_tracks = outputs

    gif_path: Path | None = None
    gif_frames = 0
    if gif:
        from laserpeople.viz.render import render
        from laserpeople.viz.scene import Scene

        every = max(1, math.ceil(len(scans) / GIF_MAX_FRAMES))
        scene = Scene(
            scans,
            main_tracks,
            truth,
            frame="world",
            every=every,
            title=f"laserpeople demo (seed {seed}): {MAIN_TRACKER} tracks, truth as black rings",
        )

        def bar(frames: Iterable[Any], total: int | None) -> Iterable[Any]:
            return progress(frames, total, "drawing")

        drawn = render(scene, out / "demo.gif", size=(640, 480), progress=bar)
        gif_path, gif_frames = drawn.path, drawn.frames

    people = {int(p) for f in truth for p in f.person_ids}
    return DemoResult(
        scores=scores,
        skipped=skipped,
        n_scans=len(scans),
        n_people=len(people),
        seconds=scans[-1].stamp - scans[0].stamp,
        detection_ms_per_scan=det_ms,
        n_detections=sum(len(f.legs) for f in frames if f.legs is not None),
        recording=Path(recording),
        tracks_csv=tracks_csv,
        gif=gif_path,
        gif_frames=gif_frames,
        meta=dict(sim.meta),
    )
