"""`laserpeople batch`: track many recordings on a Dask cluster, with one summary table."""

from __future__ import annotations

import glob
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from laserpeople.cli.common import (
    BackgroundOption,
    ConfigOption,
    DetectorOption,
    MapOption,
    ModelOption,
    MountOption,
    OnErrorOption,
    OutputFrameOption,
    PeoplePolicyOption,
    PresetOption,
    RestampOption,
    WorldFrameOption,
    console,
    plain,
    say,
    warn,
)
from laserpeople.errors import ConfigError

if TYPE_CHECKING:
    from rich.table import Table

    from laserpeople.batch import BatchResult, ClusterSpec, TopicRow, TrackOptions

HELP = (
    "Track many recordings at once on a Dask cluster: one task per recording (every laser "
    "topic on its own, or fused with --topics all), every tracker and option of `track`. "
    "Writes DIR/tracks/NAME[.TOPIC].csv (or .parquet), DIR/summary.parquet and "
    "DIR/summary.csv (one row per recording and topic) and DIR/manifest.jsonl: a rerun skips "
    "the recordings done with the same content and configuration (--force redoes them). A "
    "bad recording gets a row with its error and never stops the rest; the exit code is the "
    "number of failed rows (at most 100). Needs the batch extra (dask, pyarrow)."
)

MAX_EXIT = 100
"""Largest exit code (the number of failed rows, capped)."""

TABLE_ROWS = 40
"""Rows printed in full; a larger run prints its failed and retried rows only."""


def expand(patterns: list[str], out: Path | None = None) -> list[Path]:
    """Recording paths from paths and globs (``**`` recurses), in the order given, each
    once (a recording named twice, also by another spelling of its path such as
    ``./run.bag`` and ``/data/run.bag``, is said, and tracked once). A path that exists is
    taken as it is, even with glob characters (``run[1].bag``). Glob matches inside the
    output folder ``out`` (a rerun with the output folder among the inputs) are left out,
    and said. A glob matching nothing is a ConfigError; a missing plain path is kept (its
    row then says so)."""
    found_paths: list[Path] = []
    inside = 0
    home = out.resolve() if out is not None else None
    for pattern in patterns:
        if glob.has_magic(pattern) and not Path(pattern).exists():  # run[1].bag is a name
            found = sorted(glob.glob(pattern, recursive=True))
            found = [f for f in found if not f.endswith(".people.csv")]
            if home is not None:
                kept = [f for f in found if not Path(f).resolve().is_relative_to(home)]
                inside += len(found) - len(kept)
                if found and not kept:
                    raise ConfigError(
                        f"{pattern!r} matches only the output folder {out} and what is in it",
                        hint="check the glob, or write the output elsewhere",
                    )
                found = kept
            if not found:
                raise ConfigError(f"{pattern!r} matches no file", hint="check the glob")
            found_paths.extend(Path(f) for f in found)
        elif Path(pattern).is_dir() and not (Path(pattern) / "metadata.yaml").is_file():
            found_paths.extend(folder_recordings(Path(pattern), home))
        else:
            found_paths.append(Path(pattern))
    if inside:
        say(f"left out {inside} glob matches in the output folder {out} (its own files)")
    spellings: dict[Path, list[Path]] = {}  # resolved -> as named, the first first
    for path in found_paths:
        spellings.setdefault(path.resolve(), []).append(path)
    twice = []
    for first, *more in (v for v in spellings.values() if len(v) > 1):
        others = sorted({str(m) for m in more} - {str(first)})
        twice.append(f"{first} (also as {', '.join(others)})" if others else str(first))
    if twice:
        shown = ", ".join(twice[:3]) + (f" and {len(twice) - 3} more" if len(twice) > 3 else "")
        say(f"named more than once by the paths and globs given, tracked once: {shown}")
    return [v[0] for v in spellings.values()]


RECORDING_SUFFIXES = (".bag", ".mcap", ".db3", ".npz", ".log", ".clf", ".carmen")
"""What `batch FOLDER` takes from a folder: files of these extensions (and ROS 2 bag
folders, those with a metadata.yaml)."""


def folder_recordings(folder: Path, home: Path | None) -> list[Path]:
    """The recordings directly in ``folder`` (given without a glob), in name order: files of
    :data:`RECORDING_SUFFIXES` and ROS 2 bag folders, but not the output folder ``home`` or
    what is in it; says how many it took and how many other entries it left, naming every
    one that looks like a recording still being written
    (:func:`~laserpeople.io.sniff.unfinished_recording`).

    Raises:
        ConfigError: None is there.
    """
    from laserpeople.io.sniff import unfinished_recording

    taken, left, unfinished = [], [], []
    for entry in sorted(folder.iterdir()):
        if home is not None and entry.resolve().is_relative_to(home):
            left.append(f"{entry.name} (the output folder)")
            continue
        bag_folder = entry.is_dir() and (entry / "metadata.yaml").is_file()
        if bag_folder or (entry.is_file() and entry.suffix.lower() in RECORDING_SUFFIXES):
            taken.append(entry)
        elif not entry.name.endswith(".people.csv"):  # (the truth of a recording beside it)
            being_written = unfinished_recording(entry)
            if being_written:
                unfinished.append(f"{entry.name} ({being_written})")
            else:
                left.append(entry.name)
    if not taken:
        raise ConfigError(
            f"the folder {folder} holds no recording ({', '.join(RECORDING_SUFFIXES)} files or "
            "ROS 2 bag folders)",
            hint=f"for recordings in its subfolders give a glob: '{folder}/**/*.bag'",
        )
    left = unfinished + left  # (each recording still being written is named)
    if left:
        cut = len(unfinished) + 3
        shown = ", ".join(left[:cut]) + (", ..." if len(left) > cut else "")
        kind = "entry" if len(left) == 1 else "entries"
        extra = f"; left out {len(left)} other {kind} ({shown})"
    else:
        extra = ""
    say(f"{folder}: a folder: its {len(taken)} recordings{extra}; subfolders are not searched")
    return taken


def render(rows: list[TopicRow], title: str) -> Table:
    """The summary rows as a rich table (names, topics and errors as plain text: a file
    named ``run[a].bag`` or an error quoting ``[leg_tracker]`` is not rich markup)."""
    from rich.table import Table

    table = Table(title=title, show_header=True)
    for name, justify in (
        ("recording", "left"),
        ("topic", "left"),
        ("scans", "right"),
        ("s", "right"),
        ("people", "right"),
        ("ids", "right"),
        ("person-s", "right"),
        ("ms/scan", "right"),
        ("status", "left"),
        ("tries", "right"),
        ("error", "left"),
    ):
        table.add_column(name, justify=justify)  # type: ignore[arg-type]
    for r in rows:
        table.add_row(
            plain(r.name),
            plain(r.topic),
            str(r.scans),
            f"{r.duration_s:.1f}",
            str(r.people),
            str(r.ids),
            f"{r.person_seconds:.1f}",
            f"{r.track_ms_per_scan:.2f}",
            r.status,
            str(r.attempts),
            plain(r.error),
        )
    return table


def report(result: BatchResult, out: Path) -> None:
    """Print the summary table and the totals."""
    rows = result.rows
    if len(rows) > TABLE_ROWS:
        shown = [r for r in rows if r.status == "failed" or r.attempts > 1]
        title = f"{len(shown)} of {len(rows)} rows: failed or retried (all in summary.csv)"
    else:
        shown, title = rows, "batch summary"
    if shown:
        console.print(render(shown, title))
    done = sum(r.status == "done" for r in rows)
    rate = result.scans / result.seconds if result.seconds > 0 else 0.0
    say(
        f"{len(rows)} rows: {done} tracked, {result.skipped} done before (skipped), "
        f"{result.failed} failed; {result.scans:,} scans in {result.seconds:.1f} s "
        f"({rate:,.0f} scans/s) on {result.workers} worker{'' if result.workers == 1 else 's'}"
    )
    for r in result.retried:
        say(f"{r.name} {r.topic}: started {r.attempts} times (a worker died under it)")
    for r in rows:
        if r.notes:
            warn(f"{r.name} {r.topic}: {r.notes}")
    for line in result.unused:
        warn(line)
    say(
        f"wrote {out / 'summary.parquet'}, {out / 'summary.csv'} and the tracks in {out / 'tracks'}"
    )


def register(app: typer.Typer) -> None:
    """Add the `batch` command to ``app``."""

    @app.command("batch", help=HELP)
    def _command(
        recordings: Annotated[
            list[str],
            typer.Argument(
                help="Recordings, globs (quote them: 'runs/**/*.bag') or folders (the "
                "recordings directly in them)."
            ),
        ],
        out: Annotated[Path, typer.Option("--out", "-o", help="Output folder.")],
        tracker: Annotated[
            str,
            typer.Option("--tracker", help="Tracker (as `track`): leg-mht, nn, group-mht, ..."),
        ] = "leg-mht",
        config: ConfigOption = None,
        preset: PresetOption = None,
        topic: Annotated[
            list[str] | None,
            typer.Option(
                "--topic",
                "-t",
                help="Laser topic (repeatable: several are fused into one frame; default: "
                "every laser topic on its own).",
            ),
        ] = None,
        topics: Annotated[
            str | None,
            typer.Option(
                "--topics", help="all: fuse every laser topic; each (default): one run per topic."
            ),
        ] = None,
        detector: DetectorOption = "adaboost",
        model: ModelOption = None,
        output_frame: OutputFrameOption = None,
        world_frame: WorldFrameOption = None,
        mount: MountOption = None,
        people_policy: PeoplePolicyOption = None,
        background: BackgroundOption = "auto",
        map_path: MapOption = None,
        reidentify: Annotated[
            str | None,
            typer.Option("--reidentify", help="colour: re-identify by clothing colour."),
        ] = None,
        on_error: OnErrorOption = "stop",
        restamp: RestampOption = None,
        fmt: Annotated[
            str, typer.Option("--format", help="Tracks files: csv (as `track`) or parquet.")
        ] = "csv",
        scheduler: Annotated[
            str | None,
            typer.Option(
                "--scheduler",
                help="Address of a running Dask scheduler (tcp://HOST:PORT); default: a local "
                "cluster. Its workers must see the recordings and --out under the same paths.",
            ),
        ] = None,
        workers: Annotated[
            int | None,
            typer.Option("--workers", help="Local workers (default: one per core)."),
        ] = None,
        threads: Annotated[int, typer.Option("--threads", help="Threads per local worker.")] = 1,
        processes: Annotated[
            bool,
            typer.Option(
                "--processes/--no-processes",
                help="Local workers as processes (default) or as threads of this process.",
            ),
        ] = True,
        retries: Annotated[
            int,
            typer.Option("--retries", help="Times a task is restarted after its worker died."),
        ] = 2,
        force: Annotated[
            bool, typer.Option("--force", help="Track every recording, even those done.")
        ] = False,
        sweep: Annotated[
            Path | None,
            typer.Option(
                "--sweep",
                help="TOML grid of settings: track the labelled recordings with each, rank "
                "them by a metric, score the best on the held-out recordings (docs/batch.md).",
            ),
        ] = None,
    ) -> None:
        from laserpeople.batch import ClusterSpec, TrackOptions, parse_topics, run_batch
        from laserpeople.cli.common import JobProgress
        from laserpeople.cli.track import appearance_choice
        from laserpeople.pipeline.unused_options import preset_note
        from laserpeople.tracking import registry

        note = preset_note(tracker, registry.get(tracker).params_cls, preset)
        if note:
            warn(note)
        options = TrackOptions(
            tracker=tracker,
            config=config,
            preset=preset,
            topics=parse_topics(topic, topics),
            detector=detector,
            model=model,
            output_frame=output_frame,
            world_frame=world_frame,
            mounts=tuple(mount or ()),
            people_policy=people_policy,
            background=background,
            map_path=map_path,
            reidentify=appearance_choice(tracker, "off", reidentify),
            on_error=on_error,
            restamp=restamp,
            format=fmt,
        )
        cluster = ClusterSpec(
            scheduler=scheduler,
            workers=workers,
            threads=threads,
            processes=processes,
            retries=retries,
        )
        paths = expand(recordings, out)
        from laserpeople.io.paths import check_outputs

        check_outputs({"--out": out}, [*paths, config, model, map_path, sweep], folders={"--out"})
        if sweep is not None:
            raise typer.Exit(_sweep(sweep, paths, out, options, cluster, force))
        with JobProgress(len(paths)) as bar:
            seen: set[str] = set()

            def on_done(rows: list[TopicRow]) -> None:
                fresh = rows[0].name not in seen
                seen.add(rows[0].name)
                bar.advance(
                    int(fresh),
                    sum(r.scans for r in rows if r.status == "done"),
                    sum(r.status == "failed" for r in rows),
                )

            try:
                result = run_batch(paths, out, options, cluster, force=force, on_done=on_done)
            except KeyboardInterrupt:
                say(
                    f"{len(seen)} of {len(paths)} recordings finished before the interruption; "
                    f"their tracks and rows in {out / 'manifest.jsonl'} are kept, no summary "
                    "was written: the same command again tracks the rest and writes it"
                )
                raise
        report(result, out)
        raise typer.Exit(min(result.failed, MAX_EXIT))


def _sweep(
    path: Path,
    recordings: list[Path],
    out: Path,
    options: TrackOptions,
    cluster: ClusterSpec,
    force: bool,
) -> int:
    """Run a sweep, print its ranking; returns the exit code (settings with failures)."""
    from rich.table import Table

    from laserpeople.batch.sweep import METRICS, load_sweep, run_sweep

    spec = load_sweep(path)
    say(f"sweep: {len(spec.settings())} settings, ranked by pooled {spec.metric}")
    result = run_sweep(
        recordings,
        out,
        options,
        spec,
        cluster,
        force=force,
        on_setting=lambda s: say(
            f"settings-{s.index:03d} {s.label}: {spec.metric} {s.tune[spec.metric]:.3f}"
        ),
    )
    table = Table(
        title=f"sweep ranked by {spec.metric}: tuned on {len(result.tune)} "
        f"recording{'' if len(result.tune) == 1 else 's'}, "
        f"held out {len(result.held_out)}",
        show_header=True,
    )
    table.add_column("rank", justify="right")
    table.add_column("settings")
    for m in METRICS:
        table.add_column(m, justify="right")
    for m in METRICS:
        table.add_column(f"held-out {m}", justify="right")
    table.add_column("failed", justify="right")

    def num(value: float | None) -> str:
        return "" if value is None else ("n/a" if value != value else f"{value:.3f}")

    for rank, s in enumerate(result.ranked, start=1):
        table.add_row(
            str(rank),
            plain(s.label),
            *(num(s.tune.get(m)) for m in METRICS),
            *(num(s.held_out.get(m)) for m in METRICS),
            str(s.failed),
        )
    console.print(table)
    for line in result.unused:
        warn(line)
    best = result.ranked[0]
    say(
        f"best: settings-{best.index:03d}; its --config is "
        f"{out / f'settings-{best.index:03d}' / 'config.toml'}"
    )
    say(f"wrote {out / 'sweep.csv'}")
    return min(sum(s.failed > 0 for s in result.ranked), MAX_EXIT)
