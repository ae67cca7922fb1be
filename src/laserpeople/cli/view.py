"""`laserpeople view`: draw a recording with tracks as PNG, GIF/MP4, or export MCAP/rerun."""

from __future__ import annotations

import math
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from laserpeople.cli.common import (
    MountOption,
    OnErrorOption,
    WorldFrameOption,
    explain_missing_poses,
    open_with_poses,
    progress,
    report_damage,
    say,
    warn,
)
from laserpeople.errors import LaserPeopleError

if TYPE_CHECKING:
    from laserpeople.viz.scene import SceneFrame

_FRAMES = ("auto", "world", "sensor")


def _parse_size(text: str | None) -> tuple[int, int] | None:
    if text is None:
        return None
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError as exc:
        raise LaserPeopleError(
            f"--size {text!r} is not WIDTHxHEIGHT", hint="e.g. --size 800x600"
        ) from exc
    if not (16 <= w <= 8192 and 16 <= h <= 8192):
        raise LaserPeopleError(f"--size {text!r} is out of range 16..8192 pixels")
    return w, h


def _parse_extent(text: str | None) -> tuple[float, float, float, float] | None:
    if text is None:
        return None
    try:
        x0, x1, y0, y1 = (float(v) for v in text.split(","))
    except ValueError as exc:
        raise LaserPeopleError(
            f"--extent {text!r} is not XMIN,XMAX,YMIN,YMAX", hint="e.g. --extent -5,5,-2,8"
        ) from exc
    if not all(math.isfinite(v) and abs(v) <= EXTENT_LIMIT for v in (x0, x1, y0, y1)):
        raise LaserPeopleError(
            f"--extent {text!r} must be finite numbers within +-{EXTENT_LIMIT:g} m"
        )
    if not (x1 > x0 and y1 > y0):
        raise LaserPeopleError(f"--extent {text!r} is empty: need XMIN<XMAX and YMIN<YMAX")
    return x0, x1, y0, y1


EXTENT_LIMIT = 1e6
"""Largest coordinate [m] of ``--extent`` (a laser sees a few hundred metres at most)."""
FPS_LIMIT = 1000.0
"""Highest ``--fps`` accepted [frames/s]."""
FPS_MIN = 0.01
"""Lowest ``--fps`` accepted [frames/s] (a GIF shows a frame at most 655.35 s)."""


def _check_fps(fps: float | None) -> float | None:
    if fps is not None and not (math.isfinite(fps) and FPS_MIN <= fps <= FPS_LIMIT):
        raise LaserPeopleError(
            f"--fps {fps!r} must be a number in [{FPS_MIN:g}, {FPS_LIMIT:g}] frames per second"
        )
    return fps


def register(app: typer.Typer) -> None:
    """Add the `view` command to ``app``."""

    @app.command("view")
    def view(
        recording: Annotated[
            Path, typer.Argument(help="Recording (.bag, .mcap, .db3, .npz, ...).")
        ],
        output: Annotated[
            Path,
            typer.Option(
                "--output", "-o", help="Output: .png, .gif, .mp4, .mcap (Foxglove) or .rrd."
            ),
        ],
        tracks: Annotated[Path | None, typer.Option("--tracks", help="Tracks CSV to draw.")] = None,
        tracks_frame: Annotated[
            str | None,
            typer.Option(
                "--tracks-frame",
                help="Frame the tracks CSV was written in (world/sensor); default world when the "
                "recording has sensor poses, else sensor.",
            ),
        ] = None,
        truth: Annotated[
            str | None,
            typer.Option(
                "--truth",
                help="Ground truth, as evaluate reads it: a CSV scan,stamp,person_id,x,y, "
                "BAG:/topic (a people topic of a bag) or 'recording'. Default: the "
                "recording's own truth when it has some.",
            ),
        ] = None,
        truth_frame: Annotated[
            str | None,
            typer.Option(
                "--truth-frame",
                help="Frame of the --truth positions (world/sensor: each scan's laser frame, "
                "as the leg_tracker benchmark labels); default sensor for a bag's people "
                "topic, else the tracks' frame.",
            ),
        ] = None,
        no_truth: Annotated[
            bool, typer.Option("--no-truth", help="Do not draw ground truth.")
        ] = False,
        topic: Annotated[
            list[str] | None,
            typer.Option(
                "--topic",
                help="Laser topic (default: the first; repeatable: the first one's scans are "
                "drawn with the others' points, as a fused run sees them).",
            ),
        ] = None,
        topics: Annotated[
            str | None,
            typer.Option("--topics", help="'all': draw every laser of the recording."),
        ] = None,
        frame: Annotated[
            str,
            typer.Option(
                "--frame", help="Display frame: auto (world if poses are known), world, sensor."
            ),
        ] = "auto",
        scan: Annotated[
            int | None,
            typer.Option(
                "--scan",
                min=0,
                help="PNG of this one scan (0-based); default: trajectory overview.",
            ),
        ] = None,
        start: Annotated[
            int | None, typer.Option("--start", min=0, help="First scan index drawn.")
        ] = None,
        stop: Annotated[
            int | None, typer.Option("--stop", min=0, help="Scan index to stop before.")
        ] = None,
        every: Annotated[int, typer.Option("--every", min=1, help="Draw every N-th scan.")] = 1,
        fps: Annotated[
            float | None, typer.Option("--fps", help="Animation frame rate (default: real time).")
        ] = None,
        size: Annotated[
            str | None, typer.Option("--size", help="Image size WIDTHxHEIGHT [px].")
        ] = None,
        extent: Annotated[
            str | None,
            typer.Option(
                "--extent", help="Shown area XMIN,XMAX,YMIN,YMAX [m] (default: fit the data)."
            ),
        ] = None,
        trail: Annotated[
            int, typer.Option("--trail", min=0, max=10_000, help="Scans of trail behind tracks.")
        ] = 20,
        world_frame: WorldFrameOption = None,
        mount: MountOption = None,
        on_error: OnErrorOption = "stop",
    ) -> None:
        """Draw a recording with its tracks and ground truth, or export it for Foxglove/rerun."""
        if frame not in _FRAMES:
            raise LaserPeopleError(f"--frame {frame!r} is not one of {', '.join(_FRAMES)}")
        for option, value in (("--tracks-frame", tracks_frame), ("--truth-frame", truth_frame)):
            if value is not None and value not in ("world", "sensor"):
                raise LaserPeopleError(f"{option} {value!r} is not world or sensor")
        if no_truth and truth is not None:
            raise LaserPeopleError(
                f"--no-truth and --truth {truth} ask for opposites", hint="give one of them"
            )
        if start is not None and stop is not None and stop <= start:
            raise LaserPeopleError(
                f"--start {start} --stop {stop} draw no scan (--stop is the scan index to stop "
                "before)",
                hint=f"give a --stop after --start, e.g. --start {start} --stop {start + 100}",
            )
        truth_arg: str | None = None if no_truth else (truth or "auto")
        from laserpeople.io.paths import check_outputs

        truth_file = truth if truth not in (None, "auto", "recording") else None
        check_outputs({"-o": output}, [recording, tracks, truth_file])
        from laserpeople.cli.track import topics_from

        asked = topics_from(topic, topics)
        first_topic = asked[0] if asked and asked != ["all"] else None
        truth_input: Any = truth_arg
        if truth_file is not None and not no_truth:
            from laserpeople.io.truth_bag import is_bag_path, split_truth_spec

            if is_bag_path(split_truth_spec(truth_file)[0]):  # BAG[:TOPIC], as evaluate
                from laserpeople.cli.evaluate import truth_frames

                notes: list[str] = []
                truth_input = list(truth_frames(truth_file, first_topic, notes, on_error))
                truth_frame = truth_frame or "sensor"  # a people topic's laser frame
                for note in notes:
                    say(note)
        size_px, extent_m, fps = _parse_size(size), _parse_extent(extent), _check_fps(fps)
        source = open_with_poses(recording, world_frame, mount or [], on_error)
        try:  # the recording is closed on every path, the error paths included
            result, scene = _draw(
                source, recording, output, tracks, (tracks_frame, truth_frame), truth_input,
                asked, frame, (start, stop, every), scan, size_px, extent_m, fps, trail,
            )  # fmt: skip
            lasers_here = [t.name for t in source.topics()] if not asked else []
        finally:
            source.close()
        if result.overview_scans:  # one image of many scans: say how many
            what = f"overview of {result.overview_scans} scans"
        else:
            what = f"{result.frames} frame{'' if result.frames == 1 else 's'}"
        lasers = ", ".join([str(scene.topic), *scene.other_topics])
        say(
            f"wrote {result.path} ({what}, "
            f"topic{'s' if scene.other_topics else ''} "
            f"{lasers}, {scene.frame} frame)"
        )
        if len(lasers_here) > 1:
            say(
                f"drew topic {scene.topic} (the recording has {', '.join(lasers_here)}; use "
                "--topic, or --topics all to draw them all)"
            )
        if scene.others_unplaced:
            warn(
                f"{scene.others_unplaced} scans of {', '.join(scene.other_topics)} not drawn: "
                "no sensor pose to place them (--mount gives a laser's mount)"
            )
        if scene.skipped_without_pose:
            warn(
                f"{scene.skipped_without_pose} scans not drawn: no sensor "
                "pose for the world frame (`laserpeople info` says why; --frame sensor draws "
                "them all)"
            )
        if scene.tracks_outside.count:
            warn(scene.tracks_outside.warning())


def _draw(
    source: Any,
    recording: Path,
    output: Path,
    tracks: Path | None,
    frames: tuple[str | None, str | None],
    truth_input: Any,
    asked: list[str] | None,
    frame: str,
    scans: tuple[int | None, int | None, int],
    scan: int | None,
    size_px: tuple[int, int] | None,
    extent_m: tuple[float, float, float, float] | None,
    fps: float | None,
    trail: int,
) -> tuple[Any, Any]:
    """Check the tracks against the recording, build the scene and render it; returns the
    render result and the scene. ``frames`` are the tracks' and the truth's frames (None:
    the default). The caller closes ``source``."""
    tracks_frame, truth_frame = frames
    from laserpeople.pipeline import resolve_topics
    from laserpeople.viz import Scene, render

    drawn = resolve_topics(source, asked) if asked else []
    if tracks is not None:
        from laserpeople.pipeline.checks import tracks_mismatch

        drawn = drawn or resolve_topics(source, None)
        for problem in tracks_mismatch(tracks, source, drawn[0]):
            warn(f"{tracks} may not belong to {recording.name}: {problem}")
        from laserpeople.io.tracks_files import read_tracks_file

        rows = read_tracks_file(tracks)
        if next(iter(rows), None) is None:  # a header alone: a run that tracked nobody
            warn(f"{tracks} holds no track: the drawing shows none")
        close = getattr(rows, "close", None)
        if close is not None:
            close()
        if tracks_frame is None and tracks.suffix.lower() == ".csv":
            from laserpeople.io.tracks_csv import read_tracks_frame

            tracks_frame = read_tracks_frame(tracks)
            if tracks_frame is not None:
                say(f"tracks in the {tracks_frame} frame (the CSV's frame column)")
    if isinstance(truth_input, list) or truth_input not in (None, "auto", "recording"):
        from laserpeople.io.truth_csv import read_truth_csv
        from laserpeople.pipeline.checks import truth_mismatch

        drawn = drawn or resolve_topics(source, None)
        listed = isinstance(truth_input, list)  # (a bag's labels, already read)
        given = truth_input if listed else read_truth_csv(str(truth_input))
        for problem in truth_mismatch(given, source, drawn[0]):
            name = "the truth" if listed else truth_input
            warn(f"{name} may not belong to {recording.name}: {problem}")
        truth_input = given  # read once: its notes (names numbered) said once
    start, stop, every = scans
    try:
        scene = Scene(
            source,
            tracks,
            truth_input,
            topic=drawn[0] if drawn else None,
            other_topics=tuple(drawn[1:]),
            frame=frame,  # type: ignore[arg-type]
            tracks_frame=tracks_frame,  # type: ignore[arg-type]
            truth_frame=truth_frame,  # type: ignore[arg-type]
            start=start,
            stop=stop,
            every=every,
        )
    except LaserPeopleError as exc:
        explain_missing_poses(exc, source, drawn or None)
        raise

    def bar(frames: Iterable[SceneFrame], total: int | None) -> Iterable[SceneFrame]:
        return progress(frames, total, "drawing")

    try:
        result = render(
            scene,
            output,
            scan=scan,
            size=size_px,
            extent=extent_m,
            fps=fps,
            trail=trail,
            progress=bar,
        )
    finally:
        report_damage(source)
    return result, scene
