"""The one-command demo: simulate the ``demo`` scenario, detect legs, track with every
available tracker, score against the simulator's ground truth, and draw the leg MHT's tracks.

Each pipeline stage is looked up when the demo runs; a stage that this version does not
provide yet stops the demo with :class:`DemoPartMissingError` naming it (never a made-up
result).
"""

from __future__ import annotations

import importlib
import math
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

from laserpeople.errors import LaserPeopleError
from laserpeople.io.tracks_csv import TracksCsvWriter
from laserpeople.scan import Scan
from laserpeople.tracks import Detections, Tracks
from laserpeople.truth import TruthFrame

T = TypeVar("T")
Progress = Callable[[Iterable[Any], int | None, str], Iterable[Any]]

DEMO_SCENARIO = "demo"
MAIN_TRACKER = "leg-mht"
GIF_MAX_FRAMES = 250


class DemoPartMissingError(LaserPeopleError):
    """A stage of the demo pipeline is not part of this version yet."""


def _missing(what: str, where: str, exc: BaseException | None = None) -> DemoPartMissingError:
    detail = f" ({type(exc).__name__}: {exc})" if exc is not None else ""
    return DemoPartMissingError(
        f"the demo needs {what} ({where}), which this version does not provide yet{detail}",
        hint="the demo runs once the simulator, detector, trackers and metrics are all built",
    )


def _lookup(what: str, modules: tuple[str, ...], name: str) -> Any:
    """``name`` from the first of ``modules`` that has it, or a clear missing-part error."""
    error: BaseException | None = None
    for module in modules:
        try:
            mod = importlib.import_module(module)
        except ImportError as exc:
            error = exc
            continue
        if hasattr(mod, name):
            return getattr(mod, name)
    raise _missing(what, f"{modules[0]}.{name}", error)


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


def simulate_demo(seconds: float | None, seed: int) -> tuple[list[Scan], list[TruthFrame], Any]:
    """Run the ``demo`` scenario; returns the first sensor's scans, the truth, the result."""
    run_scenario = _lookup(
        "the simulator", ("laserpeople.sim", "laserpeople.sim.scenarios"), "run_scenario"
    )
    try:
        result = run_scenario(DEMO_SCENARIO, seconds=seconds, seed=seed)
    except LaserPeopleError as exc:
        if "unknown scenario" in str(exc):
            raise _missing("the 'demo' scenario", "laserpeople.sim scenario library") from exc
        raise
    scans: list[Scan] = list(result.scans)
    if not scans:
        raise LaserPeopleError("the demo scenario produced no scans", hint="try more --seconds")
    first = scans[0].sensor
    return [s for s in scans if s.sensor == first], list(result.truth), result


def tracker_factories() -> list[tuple[str, Callable[[], Any]]]:
    """``(name, make)`` for every tracker of :mod:`laserpeople.tracking.registry` with its
    default parameters, the leg MHT first; only the leg MHT while there is no registry."""
    factories: list[tuple[str, Callable[[], Any]]] = []
    try:
        registry = importlib.import_module("laserpeople.tracking.registry")
        entries = dict(registry.TRACKERS)
    except (ImportError, AttributeError):
        entries = {}
    for name, entry in entries.items():
        factories.append((name, _factory(entry)))
    if not any(name == MAIN_TRACKER for name, _ in factories):
        leg_mht = _lookup(
            "the leg MHT tracker",
            ("laserpeople.tracking", "laserpeople.tracking.legs"),
            "LegMHTTracker",
        )
        factories.append((MAIN_TRACKER, leg_mht))
    factories.sort(key=lambda item: item[0] != MAIN_TRACKER)
    return factories


def _factory(entry: Any) -> Callable[[], Any]:
    """A no-argument maker of a registry entry's tracker with its default parameters."""
    return lambda: entry.factory(entry.params_cls())


def run_tracker(
    make: Callable[[], Any], detections: list[Detections]
) -> tuple[list[Tracks], float]:
    """All scans through a new tracker; returns its outputs and the mean time per scan [ms]."""
    tracker = make()
    outputs: list[Tracks] = []
    elapsed = 0.0
    for det in detections:
        t0 = time.perf_counter()
        outputs.append(tracker.update(det))
        elapsed += time.perf_counter() - t0
    return outputs, 1000.0 * elapsed / max(1, len(detections))


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
    # Resolve every stage before the slow work, so a missing one fails at once.
    evaluate = _lookup("the tracking metrics", ("laserpeople.evaluation",), "evaluate")
    detector_cls = _lookup(
        "the AdaBoost leg detector",
        ("laserpeople.detection", "laserpeople.detection.detector"),
        "AdaBoostLegDetector",
    )
    factories = tracker_factories()
    skipped: list[tuple[str, str]] = []
    scans, truth, sim = simulate_demo(seconds, seed)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    recording = sim.write(out / "demo.npz")

    detector = detector_cls.default()
    t0 = time.perf_counter()
    detections = [detector.detect(s) for s in progress(scans, len(scans), "detecting")]
    det_ms = 1000.0 * (time.perf_counter() - t0) / len(scans)

    scores: list[TrackerScore] = []
    main_tracks: list[Tracks] = []
    for name, make in factories:
        feed = progress(detections, len(detections), f"tracking ({name})")
        try:
            outputs, ms = run_tracker(make, list(feed))
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

    tracks_csv = out / "demo-tracks.csv"
    with TracksCsvWriter(tracks_csv, frame="world") as writer:
        for tracks in main_tracks:
            writer.write(tracks)

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
        n_detections=sum(len(d) for d in detections),
        recording=Path(recording),
        tracks_csv=tracks_csv,
        gif=gif_path,
        gif_frames=gif_frames,
        meta=dict(getattr(sim, "meta", {})),
    )
