"""`laserpeople evaluate`: score tracks against ground truth (CLEAR MOT, IDF1, 004's MOTP)."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Annotated

import typer
from rich.table import Table

from laserpeople.cli.common import console, progress, say, warn
from laserpeople.errors import ConfigError, EvaluationError
from laserpeople.evaluation import EvaluationParams, EvaluationReport, evaluate
from laserpeople.io.paths import check_outputs
from laserpeople.io.tracks_csv import iter_tracks_csv
from laserpeople.io.truth_csv import read_truth_csv
from laserpeople.truth import TruthFrame

HELP = (
    "Score tracks against ground truth (CLEAR MOT, IDF1, the adapted MOTP of Schenk et al.)."
    "\n\n"
    "TRACKS is a tracks CSV in the world frame, as written by `laserpeople track`. TRUTH is a "
    "recording with ground truth (.npz, e.g. from `laserpeople simulate`) or a CSV "
    "scan,stamp,person_id,x,y of which only the listed scans are scored. Tracks and truth "
    "are paired by scan index; a scored scan without track rows counts all its people as "
    "missed."
)


def truth_frames(path: Path) -> Iterator[TruthFrame]:
    """Ground-truth frames from a recording with truth or a truth CSV."""
    if path.suffix.lower() == ".csv":
        yield from read_truth_csv(path)
        return
    from laserpeople.io import open_recording

    recording = open_recording(path)
    try:
        if not recording.has_truth:
            raise EvaluationError(
                "the recording has no ground truth",
                path=path,
                hint="use a simulated .npz recording or a truth CSV scan,stamp,person_id,x,y",
            )
        yield from recording.truth()
    finally:
        recording.close()


def render(report: EvaluationReport) -> Table:
    """The headline numbers as a rich table."""
    c, i, s = report.clear_mot, report.identity, report.schenk

    def num(value: float, fmt: str = ".3f") -> str:
        return "n/a" if value != value else format(value, fmt)

    table = Table(title=f"{report.params.kind} tracks vs ground truth", show_header=True)
    table.add_column("metric")
    table.add_column("value", justify="right")
    table.add_column("meaning", style="dim")
    rows = [
        ("MOTA", num(c.mota), "1 - (misses + false positives + ID switches) / people"),
        ("MOTP", num(c.motp, ".3f") + " m", f"mean distance of matches (gate {c.gate:g} m)"),
        ("MOTP (004)", num(s.motp), f"Schenk et al. eqs. 10-11, h = {s.h:g}"),
        ("IDF1", num(i.idf1), f"IDP {num(i.idp)}, IDR {num(i.idr)}"),
        ("recall", num(c.recall), f"{c.matches} of {c.num_truth} person-frames matched"),
        ("precision", num(c.precision), f"{c.matches} of {c.num_tracks} track-frames matched"),
        ("ID switches", str(c.id_switches), f"fragmentations {c.fragmentations}"),
        ("false positives", str(c.false_positives), "unmatched track-frames"),
        ("misses", str(c.misses), "unmatched person-frames"),
    ]
    for row in rows:
        table.add_row(*row)
    return table


def register(app: typer.Typer) -> None:
    """Add the `evaluate` command to ``app``."""

    @app.command("evaluate", help=HELP)
    def _command(
        tracks: Annotated[Path, typer.Argument(metavar="TRACKS", help="Tracks CSV (world frame).")],
        truth: Annotated[
            Path, typer.Option("--truth", help="Ground truth: .npz recording or .csv.")
        ],
        kind: Annotated[
            str, typer.Option("--kind", help="Track kind to score: leg/person/group.")
        ] = "person",
        gate: Annotated[
            float, typer.Option("--gate", help="Match distance gate in metres.")
        ] = 0.75,
        as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
        per_frame: Annotated[
            Path | None, typer.Option("--per-frame", help="Write the per-frame table to this CSV.")
        ] = None,
    ) -> None:
        try:
            params = EvaluationParams(gate=gate, kind=kind)
        except ConfigError as exc:
            raise ConfigError(exc.detail, hint="check --gate and --kind") from exc
        if per_frame is not None and per_frame.is_dir():
            raise EvaluationError(
                "--per-frame is a directory", path=per_frame, hint="give a file name ending .csv"
            )
        check_outputs({"--per-frame": per_frame}, [tracks, truth])
        track_stream = iter_tracks_csv(tracks, frame="world", kinds=(params.kind,))  # type: ignore[arg-type]
        run = evaluate(
            progress(truth_frames(truth), description="frames"),
            track_stream,
            params,
            keep_frames=per_frame is not None,
        )
        report = run.result()
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
            if pairing.max_stamp_offset > 0.05:
                warn(
                    f"truth and track stamps differ by up to "
                    f"{pairing.max_stamp_offset:.3f} s for the same scan index: are they from "
                    "the same recording and topic?"
                )
        if as_json:
            print(json.dumps(report.to_json_dict(), allow_nan=False))
        else:
            console.print(render(report))
