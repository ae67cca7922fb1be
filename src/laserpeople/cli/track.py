"""`laserpeople track`: detect legs in a recording, track legs and people, write tracks CSV."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Annotated, Any, Protocol

import typer

from laserpeople.cli.common import (
    MountOption,
    OnErrorOption,
    WorldFrameOption,
    ignored_sections,
    open_with_poses,
    progress,
    report_damage,
    say,
)
from laserpeople.config import check_sections, load_config, to_toml
from laserpeople.errors import ConfigError, LaserPeopleError
from laserpeople.io import RecordingSource
from laserpeople.io.paths import check_outputs
from laserpeople.scan import CoordinateFrame, Scan
from laserpeople.tracks import Detections


class Detector(Protocol):
    """What the command needs of a detector."""

    def detect(self, scan: Scan) -> Detections:
        """Detections of one scan (sensor frame)."""
        ...


def tracker_param_classes() -> list[type]:
    """The parameter classes of every registered tracker (their TOML sections may share a
    ``--config`` file with the detector's)."""
    from laserpeople.tracking import registry

    return [entry.params_cls for entry in registry.TRACKERS.values()]


def make_detector(name: str, model: Path | None, config: Path | None) -> Detector:
    """The leg detector ``adaboost`` (shipped or ``model`` file) or ``heuristic``, with its
    ``[leg_detector]`` parameters from ``config``."""
    from laserpeople.detection.detector import (
        AdaBoostLegDetector,
        HeuristicLegDetector,
        LegDetectorParams,
    )

    params = load_config(LegDetectorParams, config)
    if name == "adaboost":
        if model is not None:
            return AdaBoostLegDetector.from_file(model, params)
        return AdaBoostLegDetector.default(params)
    if name == "heuristic":
        if model is not None:
            raise ConfigError("--model applies to the adaboost detector only")
        return HeuristicLegDetector(params=params)
    raise ConfigError(f"unknown detector {name!r}", hint="choose adaboost or heuristic")


def _choose_topic(rec: Any, topic: str | None) -> str:
    topics = [t.name for t in rec.topics()]
    if topic is not None:
        return topic  # the reader raises TopicNotFoundError naming the topics it has
    if not topics:
        raise LaserPeopleError("the recording has no laser topic", path=rec.path)
    if len(topics) > 1:
        say(f"tracking topic {topics[0]} (the recording has {', '.join(topics)}; use --topic)")
    return topics[0]


def run_tracking(
    recording: Path,
    output: Path,
    tracker_name: str = "leg-mht",
    topic: str | None = None,
    config: Path | None = None,
    output_frame: CoordinateFrame | None = None,
    detector: Detector | None = None,
    world_frame: str | None = None,
    mounts: list[str] | None = None,
    plot: Path | None = None,
    animate: Path | None = None,
    on_error: str = "stop",
) -> dict[str, float]:
    """Track every scan of one topic of ``recording`` and write ``output``; then, when
    given, draw the tracks over the scans as a PNG overview ``plot`` and an animation
    ``animate`` (.gif, or .mp4 with ffmpeg).

    Returns counts and timings: scans, rows, leg and person tracks created, median/mean
    tracking time per scan [ms] (detection excluded).
    """
    from laserpeople.io.tracks_csv import TracksCsvWriter
    from laserpeople.tracking import registry

    entry = registry.get(tracker_name)
    params: Any = load_config(entry.params_cls, config)
    tracker = entry.factory(params)
    if detector is None:
        detector = make_detector("adaboost", None, config)
    check_outputs({"-o": output, "--plot": plot, "--animate": animate}, [recording, config])
    rec = open_with_poses(recording, world_frame, mounts or [], on_error)
    times: list[float] = []
    rows = 0
    leg_ids: set[int] = set()
    person_ids: set[int] = set()
    writer: TracksCsvWriter | None = None
    name: str | None = None
    written_frame: CoordinateFrame = output_frame or "sensor"
    try:
        name = _choose_topic(rec, topic)
        total = next((t.count for t in rec.topics() if t.name == name), None)
        for scan in progress(rec.scans([name]), total=total, description="tracking"):
            dets = detector.detect(scan)
            t0 = time.perf_counter()
            tracks = tracker.update(dets)
            times.append(time.perf_counter() - t0)
            if writer is None:
                written_frame = output_frame or tracks.frame
                writer = TracksCsvWriter(output, frame=written_frame)
            writer.write(tracks)
            rows += len(tracks)
            leg_ids.update(t.track_id for t in tracks if t.kind == "leg")
            person_ids.update(t.track_id for t in tracks if t.kind == "person")
    finally:
        if writer is not None:
            writer.close()
        report_damage(rec)
        rec.close()
    if writer is None:  # no scan at all: still leave a valid, empty file
        with TracksCsvWriter(output, frame=written_frame):
            pass
    if plot is not None or animate is not None:
        source = open_with_poses(recording, world_frame, mounts or [], on_error)
        try:
            draw_tracks(source, output, name, written_frame, plot, animate)
        finally:
            source.close()
    dropped = int(getattr(tracker, "dropped_detections", 0))
    if dropped:
        say(f"{dropped} detections with non-finite positions were left out")
    ms = sorted(1e3 * t for t in times)
    return {
        "scans": float(len(times)),
        "rows": float(rows),
        "leg_tracks": float(len(leg_ids)),
        "person_tracks": float(len(person_ids)),
        "median_ms": ms[len(ms) // 2] if ms else 0.0,
        "mean_ms": sum(ms) / len(ms) if ms else 0.0,
    }


def draw_tracks(
    recording: RecordingSource,
    tracks_csv: Path,
    topic: str | None,
    tracks_frame: CoordinateFrame,
    plot: Path | None,
    animate: Path | None,
) -> None:
    """Draw ``tracks_csv`` (positions in ``tracks_frame``) over the scans of ``topic``: the
    trajectory overview PNG ``plot`` and/or the animation ``animate``."""
    from laserpeople.viz import animate_tracks, plot_tracks

    if plot is not None:
        drawn = plot_tracks(recording, tracks_csv, plot, topic=topic, tracks_frame=tracks_frame)
        say(f"wrote {drawn.path}")
    if animate is not None:
        drawn = animate_tracks(
            recording,
            tracks_csv,
            animate,
            topic=topic,
            tracks_frame=tracks_frame,
            progress=lambda it, n: progress(it, n, "drawing"),
        )
        say(f"wrote {drawn.path} ({drawn.frames} frames)")


def register(app: typer.Typer) -> None:
    """Add the `track` command to ``app``."""

    @app.command("track")
    def track(
        recording: Annotated[
            Path | None, typer.Argument(help="A recording (.bag, .mcap, .db3, CARMEN log, .npz).")
        ] = None,
        tracker: Annotated[
            str, typer.Option("--tracker", help="Tracker: leg-mht (000 Sec. 3) or nn.")
        ] = "leg-mht",
        topic: Annotated[
            str | None, typer.Option("--topic", "-t", help="Laser topic (default: the first).")
        ] = None,
        config: Annotated[
            Path | None,
            typer.Option("--config", help="TOML file with tracker and detector parameters."),
        ] = None,
        output_frame: Annotated[
            str | None,
            typer.Option(
                "--output-frame",
                help="Frame of the written positions: sensor or world (default: the "
                "tracking frame, world when the recording has sensor poses).",
            ),
        ] = None,
        detector: Annotated[
            str, typer.Option("--detector", help="Leg detector: adaboost or heuristic.")
        ] = "adaboost",
        model: Annotated[
            Path | None, typer.Option("--model", help="AdaBoost model JSON (default: shipped).")
        ] = None,
        output: Annotated[
            Path | None, typer.Option("--output", "-o", help="Tracks CSV to write.")
        ] = None,
        world_frame: WorldFrameOption = None,
        mount: MountOption = None,
        plot: Annotated[
            Path | None,
            typer.Option("--plot", help="Also draw the trajectory overview to this PNG."),
        ] = None,
        animate: Annotated[
            Path | None,
            typer.Option("--animate", help="Also draw an animation (.gif, or .mp4 with ffmpeg)."),
        ] = None,
        print_config: Annotated[
            bool,
            typer.Option(
                "--print-config", help="Print the parameters with their sources and exit."
            ),
        ] = False,
        on_error: OnErrorOption = "stop",
    ) -> None:
        """Detect legs in every scan, track legs and people, and write one CSV row per track
        per scan (kind leg and person; members of a person are its legs)."""
        from laserpeople.detection.detector import LegDetectorParams
        from laserpeople.tracking import registry

        entry = registry.get(tracker)
        ignored_sections(
            config,
            check_sections(config, [LegDetectorParams, entry.params_cls], tracker_param_classes()),
        )
        if print_config:
            print(to_toml(load_config(entry.params_cls, config)))
            print(to_toml(load_config(LegDetectorParams, config)))
            return
        if recording is None or output is None:
            raise ConfigError(
                "a RECORDING and -o/--output are required", hint="see laserpeople track --help"
            )
        if plot is not None and plot.suffix.lower() != ".png":
            raise ConfigError(f"--plot writes a .png, not {plot.name!r}")
        if output_frame not in (None, "sensor", "world"):
            raise ConfigError(f"--output-frame must be sensor or world, not {output_frame!r}")
        frame: CoordinateFrame | None = (
            "sensor" if output_frame == "sensor" else ("world" if output_frame == "world" else None)
        )
        check_outputs({"-o": output, "--plot": plot, "--animate": animate}, [model])
        det = make_detector(detector, model, config)
        stats = run_tracking(
            recording,
            output,
            tracker,
            topic,
            config,
            frame,
            det,
            world_frame,
            mount or [],
            plot=plot,
            animate=animate,
            on_error=on_error,
        )
        say(
            f"{int(stats['scans'])} scans tracked: {int(stats['leg_tracks'])} leg tracks, "
            f"{int(stats['person_tracks'])} person tracks, {int(stats['rows'])} rows in "
            f"{output}; tracking {stats['median_ms']:.2f} ms/scan median "
            f"({stats['mean_ms']:.2f} mean)"
        )
