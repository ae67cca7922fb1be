"""`laserpeople track`: detect legs in a recording, track legs and people, write tracks CSV."""

from __future__ import annotations

import time
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Protocol

import typer

from laserpeople.cli.common import (
    BackgroundOption,
    ConfigOption,
    DetectorOption,
    MapOption,
    ModelOption,
    MountOption,
    MountsFileOption,
    OnErrorOption,
    OutputFrameOption,
    PeoplePolicyOption,
    PresetOption,
    RestampOption,
    WorldFrameOption,
    explain_missing_poses,
    ignored_sections,
    mount_specs,
    no_scan_read,
    open_with_poses,
    progress,
    report_damage,
    say,
    warn,
)
from laserpeople.cli.stopping import stop_name, stop_status
from laserpeople.config import check_sections, load_config, origins, to_toml
from laserpeople.errors import ConfigError, LaserPeopleError

if TYPE_CHECKING:
    from laserpeople.io import RecordingSource
    from laserpeople.scan import CoordinateFrame, Scan
    from laserpeople.tracks import Detections


class Detector(Protocol):
    """What the command needs of a detector."""

    def detect(self, scan: Scan) -> Detections:
        """Detections of one scan (sensor frame)."""
        ...


def tracker_param_classes() -> list[type]:
    """The parameter classes of every registered tracker, of colour re-identification and
    of the static world models that ``track`` feeds them (their TOML sections may share a
    ``--config`` file with the detector's). It imports every tracker: the commands ask it
    only when they have a ``--config`` file to check."""
    from laserpeople.identity.reid import ReidParams
    from laserpeople.pipeline.background import StaticWorldParams
    from laserpeople.tracking import registry

    classes = [entry.params_cls for entry in registry.TRACKERS.values()]
    return list(dict.fromkeys([*classes, ReidParams, *StaticWorldParams.sections()]))


def make_detector(
    name: str, model: Path | None, config: Path | None, preset: str | None = None
) -> Detector:
    """The leg detector ``adaboost`` (shipped or ``model`` file) or ``heuristic``, with its
    ``[leg_detector]`` parameters from ``config`` over ``preset``'s."""
    from laserpeople.detection.detector import LegDetectorParams, make_leg_detector

    return make_leg_detector(name, model, load_config(LegDetectorParams, config, preset))


TopicOption = Annotated[
    list[str] | None,
    typer.Option(
        "--topic",
        "-t",
        help="Laser topic (repeatable: several lasers are fused into one frame; default: "
        "the first).",
    ),
]
TopicsOption = Annotated[
    str | None,
    typer.Option("--topics", help="'all': fuse every laser topic of the recording."),
]


def topics_from(topic: list[str] | None, topics: str | None) -> list[str] | None:
    """The topics asked for by ``--topic`` (repeatable) and ``--topics all``."""
    if topics is not None:
        if topics != "all":
            raise ConfigError(f"--topics {topics!r}: only 'all' is known", hint="or use --topic")
        if topic:
            raise ConfigError("give --topic or --topics all, not both")
        return ["all"]
    if not topic:
        return None
    once = list(dict.fromkeys(topic))
    if len(once) < len(topic):
        twice = [t for t in once if topic.count(t) > 1]
        say(f"--topic {', '.join(twice)} given more than once: read once")
    return once


LEFT_OUT = (
    (
        "static_legs_left_out",
        "leg detections on places static for longer than people.static_time, with nobody "
        "near who had walked, were not tracked as legs (people.static_legs = true tracks them)",
    ),
    (
        "wide_points_left_out",
        "foreground points in blobs wider than group_tracker.max_blob_size were not grouped "
        "(walls the static world model has not learned yet; 0 groups them)",
    ),
    (
        "static_groups_hidden",
        "group-scans on places static for longer than group_tracker.static_time, of groups "
        "never seen walking, were not reported (group_tracker.static_groups = true reports "
        "them)",
    ),
    (
        "unconfirmed_groups_withheld",
        "group-scans of groups not yet confirmed were not reported (in the best hypothesis "
        "for fewer than group_tracker.confirm_scans scans; confirm_scans = 1 reports them)",
    ),
)
"""What a tracker left out (its counter attribute) and what ``track`` says about it."""


def run_tracking(
    recording: Path,
    output: Path,
    tracker_name: str = "leg-mht",
    topic: str | list[str] | None = None,
    config: Path | None = None,
    output_frame: CoordinateFrame | None = None,
    detector: Detector | None = None,
    world_frame: str | None = None,
    mounts: list[str] | None = None,
    plot: Path | None = None,
    animate: Path | None = None,
    bag: Path | None = None,
    people_policy: str | None = None,
    background: str = "auto",
    map_path: Path | None = None,
    reidentify: bool = False,
    on_error: str = "stop",
    restamp: float | None = None,
    preset: str | None = None,
) -> dict[str, float]:
    """Track ``recording`` (one topic, or several fused) through the pipeline and write the
    tracks CSV ``output`` (and the bag ``bag`` with scans and tracks as ROS messages); then,
    when given, draw the tracks over the scans as a PNG overview ``plot`` and an animation
    ``animate`` (.gif, or .mp4 with ffmpeg).

    A tracker that consumes foreground points, and the leg MHT's person layer (policy
    ``tracks``), get the static world model ``background`` (auto, histogram, occupancy or
    none; ``map_path`` seeds the occupancy grid).
    ``reidentify`` adds colour re-identification from the simulated camera (recordings
    with ground-truth hues only). ``restamp`` [Hz] replaces the recorded stamps by a fixed
    rate (:class:`~laserpeople.pipeline.stamps.Restamp`). ``preset`` "paper" starts every
    parameter section from the papers' values (docs/papers.md) before ``config``.

    Returns counts and timings: scans (frames), rows, leg, person and group tracks created,
    median/mean tracking time per frame [ms] (detection excluded), and ``detector_used``
    (1.0 when the leg detector ran on some frame, :func:`detector_used`) and
    ``static_model_used`` (1.0 when a static world model ran, :func:`static_model_used`).
    """
    from laserpeople.identity.reid import ReidParams
    from laserpeople.pipeline import (
        GroupingParams,
        LegFusionParams,
        TracksCsvSink,
        background_of,
        build,
        describe_background,
        describe_foreground,
        output_sink,
    )
    from laserpeople.pipeline.background import (
        detector_used,
        load_static_world,
        static_model_used,
    )
    from laserpeople.pipeline.static_people import describe_people_model, describe_static_cost
    from laserpeople.pipeline.static_tracks import StaticTrackFilter
    from laserpeople.tracking import registry

    entry = registry.get(tracker_name)
    params: Any = load_config(entry.params_cls, config, preset)
    static_world = load_static_world(config, preset)
    if people_policy is not None:
        params = registry.with_people_policy(params, people_policy, tracker_name)
    if detector is None:
        detector = make_detector("adaboost", None, config, preset)
    from laserpeople.background.occupancy import map_files
    from laserpeople.io.paths import check_output_format, check_outputs

    check_outputs(
        {"-o": output, "--bag": bag, "--plot": plot, "--animate": animate},
        [recording, config, *map_files(map_path)],
    )
    check_output_format(
        "-o",
        output,
        ".csv",
        "a tracks CSV",
        "give a path ending in .csv; --bag writes the tracks as a bag, "
        "`laserpeople batch` as Parquet",
    )
    topics = [topic] if isinstance(topic, str) else topic
    # trackers of points may report groups: their outlines go into the CSV for `view`
    csv_sink = TracksCsvSink(
        output, frame=output_frame, contours=bool(entry.consumes & {"points", "clusters"})
    )
    sinks: list[Any] = [csv_sink]
    if bag is not None:
        sinks.append(output_sink(bag))
    pipe = build(
        recording,
        tracker=entry.make(params),
        topics=topics,
        detector=detector,
        outputs=sinks,
        world_frame=world_frame,
        mounts=mounts or [],
        grouping=load_config(GroupingParams, config),
        leg_fusion=load_config(LegFusionParams, config),
        background=background,
        map_path=map_path,
        static_world=static_world,
        reidentify=reidentify,
        reid=load_config(ReidParams, config, preset),
        on_error=on_error,
        restamp=restamp,
        show_progress=progress,
    )
    source: Any = pipe.source
    available = [t.name for t in source.recording.topics()]
    if not topics and len(available) > 1:
        say(
            f"tracking topic {source.topics[0]} (the recording has {', '.join(available)}; "
            "use --topic, or --topics all to fuse them)"
        )
    if len(source.topics) > 1:
        say(f"fusing {', '.join(source.topics)} (frames follow {source.topics[0]})")
    from laserpeople.pipeline.laser_height import laser_heights, mount_warning

    height_warning = mount_warning(
        tracker_name, list(source.topics), laser_heights(source.recording)
    )
    if height_warning:
        warn(height_warning)
    interrupted = 0  # the exit status of a stop by Ctrl-C or SIGTERM
    loop_start = time.process_time()
    try:
        for _ in progress(pipe, total=source.total, description="tracking"):
            pass
    except KeyboardInterrupt as exc:  # Ctrl-C, SIGTERM: close the outputs, report what was done
        interrupted = stop_status(exc)
        pipe.close(failed=exc)  # (as a failed run: a CSV no scan came to stays as it was)
    except LaserPeopleError as exc:
        for note in getattr(source.recording, "mount_notes", []):  # a mount left out may be
            warn(note)  # why: say so before the error
        exc.located(recording)  # (a scan without the pose -o needs names no file)
        explain_missing_poses(exc, source.recording, list(source.topics))
        raise
    except Exception:
        for note in getattr(source.recording, "mount_notes", []):
            warn(note)
        raise
    finally:
        report_damage(source.recording)
    for line in source.summary():
        say(line)
    beams = source.empty.beam_summary()
    if beams:
        say(beams)
    merged = sum(int(getattr(stage, "duplicates", 0)) for stage in pipe.stages)
    if merged:
        say(f"{merged} leg detections dropped as another laser's view of the same leg")
    if reidentify:
        say("appearance: simulated camera from the recording's ground-truth clothing hues")
    elif tracker_name == "csa":
        say("appearance: off (--appearance on re-identifies by colour; needs ground-truth hues)")
    if pipe.tracker is not None and "foreground" in pipe.tracker.consumes:
        say(describe_background(background_of(pipe.stages)))
        foreground = describe_foreground(background_of(pipe.stages))
        if foreground:
            say(foreground)
    loop_cpu = time.process_time() - loop_start
    people_model = describe_people_model(pipe.tracker, pipe.stages)
    if people_model:
        say(people_model)
    static_cost = describe_static_cost(pipe, loop_cpu)
    if static_cost:
        say(static_cost)
    written_frame: CoordinateFrame = csv_sink.written_frame or output_frame or "sensor"
    if (plot is not None or animate is not None) and csv_sink.left is None:
        drawn = open_with_poses(recording, world_frame, mounts or [], on_error)
        try:
            draw_tracks(drawn, output, source.topics[0], written_frame, plot, animate)
        finally:
            drawn.close()
    guard = getattr(pipe.tracker, "guard", None)
    checked = guard.summary() if guard is not None else ""
    dropped = int(getattr(pipe.tracker, "dropped_detections", 0))
    dropped -= int(guard.dropped_detections) if guard is not None else 0
    if checked:
        say(f"input guard: {checked}")
    if dropped:
        say(f"{dropped} detections with non-finite positions in the tracking frame were left out")
    for ident in pipe.identify:
        if isinstance(ident, StaticTrackFilter) and ident.hidden:
            say(
                f"{ident.hidden} person-scans of {len(ident.hidden_ids)} tracks on places static "
                "for longer than static_tracks.static_time, never seen walking there, were not "
                "reported (static_tracks.hide = false reports them)"
            )
    for attribute, text in LEFT_OUT:
        left_out = int(getattr(pipe.tracker, attribute, 0))
        if left_out:
            say(f"{left_out} {text}")
    stats = pipe.stats
    return {
        "interrupted": float(interrupted),
        "untouched": float(csv_sink.left is not None),
        "detector_used": float(detector_used(pipe.stages)),
        "static_model_used": float(static_model_used(pipe.stages)),
        "scans": float(stats.frames),
        "rows": float(stats.rows),
        "leg_tracks": float(stats.count("leg")),
        "person_tracks": float(stats.count("person")),
        "group_tracks": float(stats.count("group")),
        "median_ms": stats.median_ms,
        "mean_ms": stats.mean_ms,
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

    outside = ""
    if plot is not None:
        drawn = plot_tracks(recording, tracks_csv, plot, topic=topic, tracks_frame=tracks_frame)
        say(f"wrote {drawn.path}")
        outside = drawn.tracks_outside.warning()
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
        outside = drawn.tracks_outside.warning()
    if outside:  # (once: the picture and the animation are fitted to the same area)
        warn(outside)


def appearance_choice(tracker: str, appearance: str, reidentify: str | None) -> bool:
    """Whether ``--appearance`` / ``--reidentify`` ask for colour re-identification."""
    if appearance not in ("on", "off"):
        raise ConfigError(f"--appearance must be on or off, not {appearance!r}")
    if reidentify not in (None, "colour"):
        raise ConfigError(f"--reidentify {reidentify!r}: only 'colour' is known")
    if appearance == "on" and tracker != "csa":
        raise ConfigError(
            "--appearance applies to the csa tracker",
            hint=f"use --reidentify colour with {tracker}",
        )
    return appearance == "on" or reidentify == "colour"


def register(app: typer.Typer) -> None:
    """Add the `track` command to ``app``."""

    @app.command("track")
    def track(
        recording: Annotated[
            Path | None, typer.Argument(help="A recording (.bag, .mcap, .db3, CARMEN log, .npz).")
        ] = None,
        tracker: Annotated[
            str,
            typer.Option(
                "--tracker",
                help="Tracker: leg-mht (legs and people from leg detections, Arras et al. "
                "2008 Sec. 3), nn (nearest neighbour), group-mht (groups and their size), "
                "csa (people from laser points, Kräußling et al.), feet-pf or upper-body-pf "
                "(particle filters, Schenk et al. 2011; upper-body-pf needs a laser at "
                "upper-body height).",
            ),
        ] = "leg-mht",
        topic: TopicOption = None,
        topics: TopicsOption = None,
        config: ConfigOption = None,
        output_frame: OutputFrameOption = None,
        detector: DetectorOption = "adaboost",
        model: ModelOption = None,
        output: Annotated[
            Path | None, typer.Option("--output", "-o", help="Tracks CSV to write.")
        ] = None,
        bag: Annotated[
            Path | None,
            typer.Option(
                "--bag",
                help="Also write the scans and tracks as ROS messages (people_msgs/People, "
                "visualization_msgs/MarkerArray) to this .bag, .mcap or .db3.",
            ),
        ] = None,
        world_frame: WorldFrameOption = None,
        mount: MountOption = None,
        mounts: MountsFileOption = None,
        preset: PresetOption = None,
        plot: Annotated[
            Path | None,
            typer.Option("--plot", help="Also draw the trajectory overview to this PNG."),
        ] = None,
        animate: Annotated[
            Path | None,
            typer.Option("--animate", help="Also draw an animation (.gif, or .mp4 with ffmpeg)."),
        ] = None,
        people_policy: PeoplePolicyOption = None,
        background: BackgroundOption = "auto",
        map_path: MapOption = None,
        appearance: Annotated[
            str,
            typer.Option(
                "--appearance",
                help="csa: on = colour re-identification after crossings (Kräußling et "
                "al.), from the simulated camera of a recording with ground-truth hues; off "
                "(default).",
            ),
        ] = "off",
        reidentify: Annotated[
            str | None,
            typer.Option(
                "--reidentify",
                help="colour: re-identify people after crossings by clothing colour "
                "(Kräußling et al.) for any tracker; needs appearance (simulated recordings "
                "with truth).",
            ),
        ] = None,
        print_config: Annotated[
            bool,
            typer.Option(
                "--print-config", help="Print the parameters with their sources and exit."
            ),
        ] = False,
        on_error: OnErrorOption = "stop",
        restamp: RestampOption = None,
    ) -> None:
        """Detect legs in every scan, track legs and people, and write one CSV row per track
        per scan (kind leg and person; members of a person are its legs)."""
        from laserpeople.config import preset_values
        from laserpeople.detection.detector import LegDetectorParams
        from laserpeople.identity.reid import ReidParams
        from laserpeople.pipeline import GroupingParams, LegFusionParams
        from laserpeople.pipeline.background import StaticWorldParams, static_world_preset
        from laserpeople.pipeline.unused_options import (
            detector_options,
            preset_note,
            unused_background_warning,
            unused_detector_warning,
        )
        from laserpeople.tracking import registry

        preset_values(ReidParams, preset)  # an unknown preset is an error before anything
        entry = registry.get(tracker)
        note = preset_note(tracker, entry.params_cls, preset)
        if note:
            warn(note)
        static_sections = StaticWorldParams.sections()
        ignored_sections(
            config,
            check_sections(
                config,
                [
                    LegDetectorParams,
                    GroupingParams,
                    LegFusionParams,
                    entry.params_cls,
                    ReidParams,
                    *static_sections,
                ],
                tracker_param_classes() if config is not None else (),
            ),
        )
        if print_config:  # the sections this tracker reads, nothing else
            classes = [entry.params_cls, LegDetectorParams, GroupingParams, LegFusionParams]
            read = StaticWorldParams.sections_for(entry.consumes)
            every = dict.fromkeys([*classes, ReidParams, *read])  # [leg_tracker] may be in both
            # (a static world section as the run reads it: [leg_tracker] of the leg
            # foreground stage without the preset, of the leg MHT itself with it)
            presets = {
                cls: preset if cls in classes else static_world_preset(cls, preset) for cls in every
            }
            loaded: list[Any] = [load_config(cls, config, presets[cls]) for cls in every]
            for obj in loaded:  # all read (and checked) before any is printed
                print(to_toml(obj, origins(obj, config, presets[type(obj)])))
            return
        if recording is None or output is None:
            raise ConfigError(
                "a RECORDING and -o/--output are required", hint="see laserpeople track --help"
            )
        if plot is not None and plot.suffix.lower() != ".png":
            raise ConfigError(f"--plot writes a .png, not {plot.name!r}")
        if animate is not None and animate.suffix.lower() not in (".gif", ".mp4"):
            raise ConfigError(
                f"--animate writes a .gif or an .mp4, not {animate.name!r}",
                hint="--plot draws the tracks into one .png; `laserpeople view` also writes "
                ".mcap and .rrd",
            )
        if output_frame not in (None, "sensor", "world"):
            raise ConfigError(f"--output-frame must be sensor or world, not {output_frame!r}")
        frame: CoordinateFrame | None = (
            "sensor" if output_frame == "sensor" else ("world" if output_frame == "world" else None)
        )
        colour = appearance_choice(tracker, appearance, reidentify)
        from laserpeople.io.paths import check_outputs

        check_outputs(
            {"-o": output, "--bag": bag, "--plot": plot, "--animate": animate}, [model, mounts]
        )
        det = make_detector(detector, model, config, preset)
        stats = run_tracking(
            recording,
            output,
            tracker,
            topics_from(topic, topics),
            config,
            frame,
            det,
            world_frame,
            mount_specs(mount, mounts),
            plot=plot,
            animate=animate,
            bag=bag,
            people_policy=people_policy,
            background=background,
            map_path=map_path,
            reidentify=colour,
            on_error=on_error,
            restamp=restamp,
            preset=preset,
        )
        unused = unused_detector_warning(
            tracker, detector_options(detector, model, config), bool(stats["detector_used"])
        )
        if unused and stats["scans"]:
            warn(unused)
        unused = unused_background_warning(tracker, background, bool(stats["static_model_used"]))
        if unused:
            warn(unused)
        groups = int(stats["group_tracks"])
        if stats["untouched"]:  # stopped before the first scan: the CSV was not written
            from laserpeople.pipeline.sinks import left_as_it_was

            status = int(stats["interrupted"])
            kept = left_as_it_was("tracks CSV", output, output.exists())
            if bag is not None:
                kept += "; " + left_as_it_was("tracks bag", bag, bag.exists())
            warn(f"interrupted ({stop_name(status)}) before the first scan was tracked: {kept}")
            raise typer.Exit(status)
        say(
            f"{int(stats['scans'])} scans tracked: {int(stats['leg_tracks'])} leg tracks, "
            f"{int(stats['person_tracks'])} person tracks, "
            + (f"{groups} group tracks, " if groups else "")
            + f"{int(stats['rows'])} rows in "
            f"{output}; tracking {stats['median_ms']:.2f} ms/scan median "
            f"({stats['mean_ms']:.2f} mean)"
        )
        if bag is not None:
            say(f"wrote {bag}")
        if stats["interrupted"]:
            status = int(stats["interrupted"])
            warn(
                f"interrupted ({stop_name(status)}) after {int(stats['scans'])} scans: {output} "
                "holds the tracks of those scans and is a complete CSV"
            )
            raise typer.Exit(status)
        if not stats["scans"]:
            raise no_scan_read(recording, output)
