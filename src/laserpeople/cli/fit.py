"""`laserpeople fit`: learn a tracker's probabilities from labelled recordings (Arras et al.
2008 Sec. 3.4, 4.6) and write them as a TOML file for `track --config`."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from laserpeople.cli.common import console, plain, say, warn

if TYPE_CHECKING:
    from laserpeople.fitting.flow import FitResult

HELP = (
    "Learn a tracker's probabilities and thresholds from labelled recordings by counting "
    "events (Arras et al. 2008 Sec. 3.4 and 4.6), score default and learned parameters on a "
    "held-out part, and write the learned ones as TOML for `laserpeople track --config`."
    "\n\n"
    "RECORDING is a simulated .npz with ground truth, or any recording with one --truth per "
    "recording (a CSV scan,stamp,person_id,x,y or BAG[:TOPIC], e.g. the leg_tracker "
    "benchmark's /ground_truth_people_tracks): then only the labelled person counts, and free "
    "legs, false alarms and new tracks keep their values. leg-mht learns p_det/p_occ/p_del of "
    "free and approved legs, lambda_new, lambda_fal (per m^2 and scan), the process noise of "
    "legs and people, the leg gate and the leg-pair distance, and how often both or one leg "
    "of a person are seen; group-mht (simulated .npz only) learns p_C, p_S, p_G, p_M, p_O, "
    "p_T and p_N from the group labels. --validation holds out the last recordings, or the "
    "last scans of a single recording."
)


def register(app: typer.Typer) -> None:
    """Add the `fit` command to ``app``."""

    @app.command("fit", help=HELP)
    def _command(
        recordings: Annotated[
            list[Path], typer.Argument(help="Labelled recordings (.npz with truth, or bags).")
        ],
        output: Annotated[Path, typer.Option("-o", "--output", help="TOML file to write.")],
        truth: Annotated[
            list[str] | None,
            typer.Option("--truth", help="Truth of each recording, in order: CSV or BAG[:TOPIC]."),
        ] = None,
        tracker: Annotated[
            str, typer.Option("--tracker", help="Tracker to learn: leg-mht or group-mht.")
        ] = "leg-mht",
        validation: Annotated[
            float,
            typer.Option(
                "--validation", help="Share held out for validation (0: none).", min=0.0, max=0.99
            ),
        ] = 0.3,
        topic: Annotated[str | None, typer.Option("--topic", help="Laser topic of bags.")] = None,
        config: Annotated[
            Path | None,
            typer.Option(
                "--config",
                help="TOML with base parameters and the [fit_legs]/[fit_groups] settings.",
            ),
        ] = None,
        min_events: Annotated[
            int | None,
            typer.Option("--min-events", help="Least events behind a learned value.", min=1),
        ] = None,
        select: Annotated[
            list[str] | None,
            typer.Option(
                "--learn",
                help="Write only the learned keys matching this shell pattern (repeatable; "
                "e.g. 'p_[mot]' 'p_n' for the group tracker's association probabilities).",
            ),
        ] = None,
    ) -> None:
        from laserpeople.fitting.flow import learn, write_result
        from laserpeople.io.paths import check_output_format, check_outputs
        from laserpeople.io.truth_bag import split_truth_spec

        truth_paths = [split_truth_spec(t)[0] for t in truth or []]
        check_outputs({"-o": output}, [*recordings, *truth_paths, config])
        check_output_format("-o", output, ".toml", "the learned parameters as TOML")
        result = learn(
            recordings,
            truth or [],
            tracker=tracker,
            validation=validation,
            topic=topic,
            config=config,
            min_events=min_events,
            select=select or [],
            say=say,
        )
        _print(result)
        write_result(result, output)
        say(f"wrote {output} (for: laserpeople track ... --tracker {tracker} --config {output})")
        for line in result.worse_than_default():
            warn(line)


def _print(result: FitResult) -> None:
    from rich.table import Table

    table = Table(title=f"learned parameters of {result.tracker}")
    table.add_column("parameter", style="bold")
    table.add_column("learned", justify="right")
    table.add_column("counted from")
    for e in result.estimates:
        table.add_row(e.key, f"{e.value:.6g}", plain(e.note))
    console.print(table)
    for key, why in result.kept:
        say(f"not learned: {key} ({why})")
    if not result.rows:
        return
    metrics = list(dict.fromkeys(m for row in result.rows for m in row.scores))
    val = Table(title="validation: default vs learned parameters")
    val.add_column("recording")
    val.add_column("parameters")
    for m in metrics:
        val.add_column(m, justify="right")
    for row in result.rows:
        val.add_row(
            plain(row.recording),
            plain(row.label),
            *(_score_text(m, row.scores[m]) if m in row.scores else "" for m in metrics),
        )
    console.print(val)


def _score_text(metric: str, value: float) -> str:
    """A validation score as the table shows it: counts whole, the rest to 3 decimals."""
    from laserpeople.fitting.validate import COUNT_SCORES

    return f"{value:.0f}" if metric in COUNT_SCORES else f"{value:.3f}"
