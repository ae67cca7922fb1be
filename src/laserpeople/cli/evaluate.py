"""`laserpeople evaluate`: score tracks against ground truth (CLEAR MOT, IDF1, 004's MOTP)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from laserpeople.cli.common import (
    OnErrorOption,
    console,
    plain,
    progress,
    report_damage,
    say,
    warn,
)
from laserpeople.errors import ConfigError, EvaluationError, RecordingError

if TYPE_CHECKING:
    from rich.table import Table
    from rich.text import Text

    from laserpeople.evaluation import EvaluationParams, EvaluationReport
    from laserpeople.evaluation.followed import FollowedPersonResult
    from laserpeople.evaluation.pairing import PairingCounts
    from laserpeople.io.tracks_csv import TrackIdNames
    from laserpeople.tracks import Tracks
    from laserpeople.truth import TruthFrame

HELP = (
    "Score tracks against ground truth (CLEAR MOT, IDF1, the adapted MOTP of Schenk et al. 2011)."
    "\n\n"
    "TRACKS is a tracks CSV in the world frame (or the sensor frame when the recording has no "
    "poses), as written by `laserpeople track` (or the bag it writes with "
    "--bag, people_msgs/People); track ids may be any text. TRUTH is a recording with "
    "ground truth (.npz, e.g. from `laserpeople simulate`), a CSV "
    "scan,stamp,person_id,x,y of which only the listed scans are scored, or a bag topic "
    "BAG[:TOPIC] of leg_tracker/Person, spencer_tracking_msgs/TrackedPersons or "
    "people_msgs/People (paired with the scans of --laser-topic). Tracks and truth are "
    "paired by scan index; a scored scan without track rows counts all its people as "
    "missed. --followed-person ID (or auto: the most labelled person) scores one labelled "
    "person and counts no other track as a false positive."
)


_RECORDINGS_ONLY = frozenset({".npz", ".log", ".clf", ".carmen", ".gz"})
"""Extensions of recordings that never hold tracks (given as TRACKS: swapped arguments)."""


def _check_laser_topic(many: bool, truths: list[str]) -> None:
    """Refuse ``--laser-topic`` where nothing reads it: it names the laser whose scans the
    labels of a bag's truth topic are paired with, one TRACKS file at a time.

    Raises:
        ConfigError: several tracks files (or a batch folder), or a --truth of no bag.
    """
    from laserpeople.io.truth_bag import is_bag_path, split_truth_spec

    if many:
        raise ConfigError(
            "--laser-topic applies to one TRACKS file with --truth BAG[:TOPIC]; the scores "
            "of several tracks files or of a batch folder do not read it",
            hint="drop --laser-topic, or score the tracks of one recording at a time",
        )
    if not any(is_bag_path(split_truth_spec(t)[0]) for t in truths):
        raise ConfigError(
            f"--laser-topic applies to ground truth from a bag (--truth BAG[:TOPIC]), not "
            f"to --truth {', '.join(truths)}: its scans are numbered as they are",
            hint="drop --laser-topic (a recording's own truth belongs to its scans)",
        )


def truth_frames(
    spec: str | Path,
    laser_topic: str | None = None,
    notes: list[str] | None = None,
    on_error: str = "stop",
) -> Iterator[TruthFrame]:
    """Ground-truth frames from a recording with truth, a truth CSV or a bag topic
    (``BAG[:TOPIC]``), damaged scans skipped warned of (see
    :func:`laserpeople.evaluation.recordings.truth_frames`)."""
    from laserpeople.evaluation.recordings import truth_frames as frames

    return frames(spec, laser_topic, notes, on_error, on_damage=report_damage)


def _unstated_frame_note(tracks: Path, truth: str, notes: list[str]) -> None:
    """A note when a tracks CSV has no ``frame`` column, naming the frame it is taken in
    (:func:`~laserpeople.evaluation.recordings.unstated_tracks_frame`)."""
    from laserpeople.evaluation.recordings import unstated_tracks_frame
    from laserpeople.io.tracks_csv import read_tracks_frame

    try:
        stated = read_tracks_frame(tracks)
    except RecordingError:  # not readable as text: the reader says what is wrong, and where
        return
    if stated is None:
        frame = unstated_tracks_frame(truth)
        notes.append(f"the tracks CSV states no frame (no frame column): taken as {frame}")


_PLURAL = {"person": "people", "leg": "legs", "group": "groups"}
"""The truth a ``--kind`` is scored against, as the table's meanings name it."""


def render(report: EvaluationReport) -> Table:
    """The headline numbers as a rich table."""
    from rich.table import Table

    c, i, s = report.clear_mot, report.identity, report.schenk
    kind = report.params.kind  # what the truth counts: people, legs or groups
    truths = _PLURAL.get(kind, f"{kind}s")

    def num(value: float, fmt: str = ".3f") -> str:
        return "n/a" if value != value else format(value, fmt)

    table = Table(title=f"{report.params.kind} tracks vs ground truth", show_header=True)
    table.add_column("metric")
    table.add_column("value", justify="right")
    table.add_column("meaning", style="dim")
    rows = [
        ("MOTA", num(c.mota), f"1 - (misses + false positives + ID switches) / {truths}"),
        ("MOTP", num(c.motp, ".3f") + " m", f"mean distance of matches (gate {c.gate:g} m)"),
        ("MOTP (Schenk)", num(s.motp), f"Schenk et al. 2011 eqs. 10-11, h = {s.h:g}"),
        ("IDF1", num(i.idf1), f"IDP {num(i.idp)}, IDR {num(i.idr)}"),
        ("recall", num(c.recall), f"{c.matches} of {c.num_truth} {kind}-frames matched"),
        ("precision", num(c.precision), f"{c.matches} of {c.num_tracks} track-frames matched"),
        ("ID switches", str(c.id_switches), f"fragmentations {c.fragmentations}"),
        ("false positives", str(c.false_positives), "unmatched track-frames"),
        ("misses", str(c.misses), f"unmatched {kind}-frames"),
    ]
    for row in rows:
        table.add_row(*row)
    return table


def render_followed(
    result: FollowedPersonResult, names: TrackIdNames, kind: str = "person"
) -> Table:
    """The followed-person scores as a rich table; ``kind`` names the tracks scored
    (``evaluate --kind``): their ids are counted."""
    from rich.table import Table

    def num(value: float) -> str:
        return "n/a" if value != value else f"{value:.3f}"

    table = Table(title=plain(f"followed person {result.person_id}"), show_header=True)
    table.add_column("metric")
    table.add_column("value", justify="right")
    table.add_column("meaning", style="dim")
    top = ", ".join(f"{names.name(t)}: {n}" for t, n in result.track_frames[:5])
    rows: list[tuple[str, str, str | Text]] = [
        ("identity recall", num(result.identity_recall), "frames covered by the best single id"),
        ("recall", num(result.recall), f"{result.matched} of {result.frames} labelled frames"),
        (f"{kind} ids", str(result.ids), plain(f"frames per id: {top or 'none'}")),
        ("ID switches", str(result.id_switches), "changes of the matched id"),
        ("MOTA", num(result.mota), "1 - (misses + switches) / frames; no false positives"),
        ("MOTP", num(result.motp) + " m", f"mean distance of matches (gate {result.gate:g} m)"),
    ]
    for row in rows:
        table.add_row(*row)
    return table


def _named_pairs(pairs: list[list[int]], names: TrackIdNames) -> list[list[int | str]]:
    return [[names.name(t) if len(names) else t, p] for t, p in pairs]


def register(app: typer.Typer) -> None:
    """Add the `evaluate` command to ``app``."""

    @app.command("evaluate", help=HELP)
    def _command(
        tracks_args: Annotated[
            list[Path],
            typer.Argument(
                metavar="TRACKS",
                help="Tracks CSV (world frame), tracks bag or Parquet; several, or the --out "
                "folder of `laserpeople batch`, give one table of every recording and pooled.",
            ),
        ],
        truth_args: Annotated[
            list[str] | None,
            typer.Option(
                "--truth",
                help="Ground truth: .npz recording, .csv, or BAG[:TOPIC] of people (one per "
                "TRACKS file, in order; for a batch folder found by name: X.people.csv beside "
                "X.bag, or the .npz itself).",
            ),
        ] = None,
        kind: Annotated[
            str, typer.Option("--kind", help="Track kind to score: leg/person/group.")
        ] = "person",
        gate: Annotated[
            float,
            typer.Option(
                "--gate", "--match-distance", help="Match distance in metres (CLEAR MOT gate)."
            ),
        ] = 0.75,
        laser_topic: Annotated[
            str | None,
            typer.Option(
                "--laser-topic", help="Laser topic whose scan indices a bag's labels get."
            ),
        ] = None,
        followed_person: Annotated[
            str | None,
            typer.Option(
                "--followed-person",
                metavar="ID|auto",
                help="Score only this labelled person (auto: the most labelled one); "
                "other tracks are not false positives.",
            ),
        ] = None,
        as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
        per_frame: Annotated[
            Path | None, typer.Option("--per-frame", help="Write the per-frame table to this CSV.")
        ] = None,
        on_error: OnErrorOption = "stop",
    ) -> None:
        from laserpeople.evaluation import EvaluationParams, evaluate
        from laserpeople.io import is_rosbag

        folder = tracks_args[0]
        if (
            len(tracks_args) == 1
            and folder.is_dir()
            and not (folder / "summary.csv").is_file()
            and not is_rosbag(folder)  # a ROS 2 bag of tracks is a folder
        ):
            sweep = (folder / "sweep.csv").is_file()
            raise EvaluationError(
                "is a folder but not the --out folder of `laserpeople batch` (no summary.csv)",
                path=folder,
                hint=f"a sweep's folder: give one of its {folder}/settings-NNN/tune folders, "
                "whose scores sweep.csv ranks"
                if sweep
                else "give a tracks file and its --truth, or a batch --out folder",
            )
        for given in tracks_args:  # (a .bag or .mcap may hold tracks: `track --bag`)
            if given.suffix.lower() in _RECORDINGS_ONLY and not given.is_dir():
                swapped = any(str(t).lower().endswith(".csv") for t in truth_args or [])
                raise EvaluationError(
                    f"is a recording ({given.suffix}), not tracks"
                    + (": are TRACKS and --truth swapped?" if swapped else ""),
                    path=given,
                    hint="TRACKS is what `laserpeople track -o` wrote, --truth the recording: "
                    f"laserpeople evaluate tracks.csv --truth {given.name}",
                )
        many = len(tracks_args) > 1 or (folder / "summary.csv").is_file()
        if laser_topic is not None:
            _check_laser_topic(many, [str(t) for t in truth_args or []])
        if many:
            if followed_person is not None or per_frame is not None:
                raise ConfigError(
                    "--followed-person and --per-frame score one recording",
                    hint="give one TRACKS file and its --truth",
                )
            _many(tracks_args, truth_args or [], kind, gate, as_json, on_error)
            return
        if not truth_args or len(truth_args) != 1:
            raise ConfigError(
                "one TRACKS file needs one --truth",
                hint="e.g. laserpeople evaluate tracks.csv --truth run.npz",
            )
        tracks, truth = tracks_args[0], truth_args[0]
        from laserpeople.evaluation.recordings import unstated_tracks_frame
        from laserpeople.io.paths import check_output_format, check_outputs
        from laserpeople.io.tracks_csv import TrackIdNames, iter_tracks_csv

        try:
            params = EvaluationParams(gate=gate, kind=kind)
        except ConfigError as exc:
            raise ConfigError(exc.detail, hint="check --gate and --kind") from exc
        if per_frame is not None and per_frame.is_dir():
            raise EvaluationError(
                "--per-frame is a directory", path=per_frame, hint="give a file name ending .csv"
            )
        truth_path = str(truth)
        check_outputs(
            {"--per-frame": per_frame}, [tracks, truth_path, truth_path.rsplit(":", 1)[0]]
        )
        check_output_format("--per-frame", per_frame, ".csv", "the per-frame table as CSV")
        names = TrackIdNames()
        kinds = (params.kind,)
        notes: list[str] = []
        if is_rosbag(tracks) or tracks.suffix.lower() == ".parquet":
            from laserpeople.io.tracks_files import read_tracks_file

            track_stream = read_tracks_file(tracks, kinds=kinds)  # type: ignore[arg-type]
        else:
            _check_kind(tracks, params.kind)
            _unstated_frame_note(tracks, truth_path, notes)
            track_stream = iter_tracks_csv(
                tracks,
                frame=unstated_tracks_frame(truth_path),
                kinds=kinds,  # type: ignore[arg-type]
                ids=names,
            )
        if followed_person is not None:
            _followed(
                list(truth_frames(truth, laser_topic, notes, on_error)),
                track_stream,
                followed_person,
                params,
                names,
                notes,
                as_json=as_json,
                per_frame=per_frame,
            )
            return
        run = evaluate(
            progress(truth_frames(truth, laser_topic, notes, on_error), description="frames"),
            track_stream,
            params,
            keep_frames=per_frame is not None,
        )
        report = run.result()
        for note in notes:
            say(note)
        if per_frame is not None:
            run.frames().to_csv(per_frame)
            say(f"per-frame table written to {per_frame}")
        pairing = report.pairing
        if pairing is not None:
            say(
                f"scored {pairing.frames_scored} frames ({pairing.frames_without_tracks} without "
                f"any {kind} track); {pairing.track_scans_unscored} track scans had no truth "
                "and were not scored"
            )
            _stamp_check(pairing)
        if report.nothing_matched():
            unit = pairing.position_unit() if pairing is not None else ""
            warn(
                f"no {kind} track came within {params.gate:g} m of any labelled person: "
                + (f"{unit}; if not, " if unit else "")
                + "are the truth and the tracks in the same frame? Labels in each scan's "
                "laser frame (as the leg_tracker benchmark's) need tracks written with "
                "`track --output-frame sensor`, or a truth that states its frame (the labels "
                "of the bag itself, or a frame column), into which tracks written with their "
                "sensor poses are moved"
            )
        if as_json:
            out = report.to_json_dict()
            for key in ("identity_matching", "schenk_matching"):
                out["detail"][key] = _named_pairs(out["detail"][key], names)
            import json  # (at use: not for every start-up)

            print(json.dumps(out, allow_nan=False))
        else:
            console.print(render(report))


def _check_kind(tracks: Path, kind: str) -> None:
    """Refuse a tracks CSV that has rows of other kinds but none of ``kind`` (a group
    tracker's CSV scored as people would give a table of zeros). A leg tracker's CSV of leg
    rows alone is scored as people (its tracker confirmed nobody: every label is a miss),
    with a warning."""
    from laserpeople.errors import EvaluationError
    from laserpeople.io.tracks_csv import count_track_kinds

    counts = count_track_kinds(tracks)
    if kind == "person" and set(counts) == {"leg"}:
        warn(
            f"{tracks} holds {counts['leg']} leg rows and no person tracks: the tracker "
            "confirmed nobody, so every labelled person is a miss (--kind leg scores the legs)"
        )
        return
    if counts and not counts.get(kind):
        held = ", ".join(f"{n} {k} rows" for k, n in sorted(counts.items()))
        best = max(counts, key=lambda k: counts[k])
        raise EvaluationError(
            f"holds no {kind} tracks, only {held}",
            path=tracks,
            hint=f"score them with --kind {best}",
        )


def _stamp_check(pairing: PairingCounts) -> None:
    """Print the frame compared in when the truth states none, what the paired stamps say
    (a note, or a warning when they disagree), and a warning when truth and tracks share no
    scan.

    Raises:
        EvaluationError: the scans of truth and tracks do not overlap at all (nothing to
            score)."""
    refused = pairing.disjoint()
    if refused is not None:
        raise refused
    frame = pairing.frame_check()
    if frame:
        say(frame)
    text, is_warning = pairing.stamp_check()
    if text:
        (warn if is_warning else say)(text)
    apart = pairing.overlap_check()
    if apart:
        warn(apart)


def _person_id(text: str, frames: list[TruthFrame]) -> int:
    from laserpeople.evaluation.followed import most_labelled_person

    if text.strip().lower() == "auto":
        return most_labelled_person(frames)
    try:
        return int(text)
    except ValueError:
        raise ConfigError(
            f"--followed-person {text!r} is neither a person id nor auto",
            hint="give the labelled person's integer id, or auto",
        ) from None


def _followed(
    frames: list[TruthFrame],
    track_stream: Iterator[Tracks],
    which: str,
    params: EvaluationParams,
    names: TrackIdNames,
    notes: list[str],
    *,
    as_json: bool,
    per_frame: Path | None,
) -> None:
    from laserpeople.evaluation.followed import evaluate_followed

    person = _person_id(which, frames)
    metric, pairing = evaluate_followed(
        frames, track_stream, person, params, keep_frames=per_frame is not None
    )
    result = metric.result()
    for note in notes:
        say(note)
    say(
        f"scored person {person} on {result.frames} labelled frames; "
        f"{pairing.track_scans_unscored} track scans had no truth; other tracks are ignored"
    )
    _stamp_check(pairing)
    if per_frame is not None:
        metric.frames().to_csv(per_frame)
        say(f"per-frame table written to {per_frame}")
    if as_json:
        out = {
            **result.summary(),
            "best_track": None if result.best_track is None else names.name(result.best_track),
            "track_frames": [[names.name(t), n] for t, n in result.track_frames],
        }
        import json  # (at use: not for every start-up)

        print(json.dumps(out, allow_nan=False))
    else:
        console.print(render_followed(result, names, params.kind))


def _many(
    tracks: list[Path], truth: list[str], kind: str, gate: float, as_json: bool, on_error: str
) -> None:
    """Score several tracks files (or a batch output folder): one row per recording and the
    pooled row (CLEAR MOT, IDF1, HOTA)."""
    from laserpeople.evaluation import EvaluationParams
    from laserpeople.evaluation.recordings import (
        batch_pairs,
        score_recording,
        score_rows,
    )

    pairs: list[tuple[str, Path, str | None, str | None]] = []
    files = [t for t in tracks if not t.is_dir()]
    for folder in (t for t in tracks if t.is_dir()):
        pairs.extend(batch_pairs(folder))
    if truth and len(truth) != len(files):
        folders = len(tracks) - len(files)
        raise ConfigError(
            f"{len(files)} TRACKS files but {len(truth)} --truth"
            + (
                f" ({folders} batch folder{'s' if folders > 1 else ''}: "
                f"{'their' if folders > 1 else 'its'} recordings' truth is found by name, "
                "not given)"
                if folders
                else ""
            ),
            hint="give one --truth per TRACKS file, in the same order",
        )
    if files and not truth:
        raise ConfigError(
            "TRACKS files need their --truth (one each, in order)",
            hint="or give the --out folder of `laserpeople batch`: truth is then found by name",
        )
    stems = [f.stem for f in files]
    pairs.extend(  # a stem shared by two files (a/tracks.csv, b/tracks.csv): the paths
        (f.stem if stems.count(f.stem) == 1 else str(f), f, t, None)
        for f, t in zip(files, truth, strict=True)
    )
    shared_truth_note(pairs)
    params = EvaluationParams(gate=gate, kind=kind)
    scores = []
    for name, path, spec, topic in progress(pairs, len(pairs), "recordings"):
        if spec is None:
            warn(f"{name}: no truth found (no X.people.csv beside it, not a .npz); not scored")
            continue
        scores.append(
            score_recording(name, path, spec, params, laser_topic=topic, on_error=on_error)
        )
    if not scores:
        raise EvaluationError("no recording with truth to score", hint="see --truth")
    rows = score_rows(scores)
    for s in scores:
        if s.error:
            warn(f"{s.name}: {s.error}")
    if as_json:
        safe = [
            {k: (None if isinstance(v, float) and v != v else v) for k, v in r.items()}
            for r in rows
        ]
        import json  # (at use: not for every start-up)

        print(json.dumps(safe, allow_nan=False))
    else:
        console.print(render_many(rows, gate))


def _truth_key(spec: str) -> str:
    """One spelling of a ``--truth``: the resolved path of a file, or of a bag's with its
    ``:TOPIC`` (``./run.bag:/people`` and ``run.bag:/people`` are one truth)."""
    if Path(spec).exists():
        return str(Path(spec).resolve())
    bag, sep, topic = spec.rpartition(":")
    if sep and Path(bag).exists():
        return f"{Path(bag).resolve()}:{topic}"
    return spec


def shared_truth_note(pairs: list[tuple[str, Path, str | None, str | None]]) -> None:
    """Warn when one truth scores several tracks files (e.g. two trackers' tracks of one
    recording): the pooled row then counts its people once per file; and when a batch
    tracked a recording laser by laser: each laser's tracks are scored against every
    labelled person, also those only another laser sees."""
    by_truth: dict[str, list[str]] = {}
    lasers: dict[str, tuple[str, list[str]]] = {}
    for name, _, spec, topic in pairs:
        if spec is None:
            continue
        by_truth.setdefault(f"{_truth_key(spec)}|{topic}", []).append(name)
        if topic is not None:
            recording = name.removesuffix(f" {topic}")
            lasers.setdefault(_truth_key(spec), (recording, []))[1].append(topic)
    for names in by_truth.values():
        if len(names) > 1:
            warn(
                f"one truth scores {len(names)} TRACKS files ({', '.join(names)}): the pooled "
                f"row counts its people {len(names)} times; compare those files row by row"
            )
    for recording, topics in lasers.values():
        if len(set(topics)) > 1:
            warn(
                f"{recording} was tracked laser by laser ({', '.join(sorted(set(topics)))})"
                ": each laser's tracks are scored against every labelled person, also those "
                "only another laser sees; to score what the robot sees, track it fused "
                "(`batch --topics all`)"
            )


def render_many(rows: list[dict[str, object]], gate: float) -> Table:
    """Per-recording and pooled scores as a rich table."""
    from rich.table import Table

    from laserpeople.evaluation.hota import HotaParams

    d0 = HotaParams().zero_distance
    table = Table(
        title=f"tracks vs ground truth (gate {gate:g} m; HOTA: S = max(0, 1 - d / {d0:g} m))",
        show_header=True,
    )
    columns = (
        "recording",
        "MOTA",
        "MOTP m",
        "IDF1",
        "HOTA",
        "DetA",
        "AssA",
        "LocA",
        "IDSW",
        "FP",
        "FN",
    )
    keys = (
        "recording",
        "mota",
        "motp_m",
        "idf1",
        "hota",
        "deta",
        "assa",
        "loca",
        "id_switches",
        "false_positives",
        "misses",
    )
    for c in columns:
        table.add_column(c, justify="left" if c == "recording" else "right")
    for r in rows:
        cells: list[str | Text] = []
        for k in keys:
            v = r[k]
            if isinstance(v, float):
                cells.append("n/a" if v != v else (f"{v:.0f}" if k in keys[-3:] else f"{v:.3f}"))
            else:
                cells.append(plain(v))
        if r.get("error"):  # the error itself is said on a line of its own
            cells[1:] = ["error"] + ["–"] * (len(cells) - 2)
        table.add_row(*cells)
    return table
