"""`laserpeople simulate`: simulate a named scenario and write a recording with ground truth."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from laserpeople.cli.common import progress, say


def register(app: typer.Typer) -> None:
    """Add the `simulate` command to ``app``."""

    @app.command(
        "simulate",
        help="Simulate a scenario and write a recording (.npz with ground truth; "
        ".mcap/.db3/.bag scans only). `laserpeople scenarios` lists the names.",
    )
    def _command(
        scenario: Annotated[str, typer.Argument(help="Scenario name, e.g. speed-normal or demo.")],
        output: Annotated[
            Path, typer.Option("--output", "-o", help="Output file (.npz, .mcap, .db3, .bag).")
        ],
        seconds: Annotated[
            float | None,
            typer.Option("--seconds", "-s", help="Length [s]; the scenario's default if omitted."),
        ] = None,
        seed: Annotated[
            int, typer.Option("--seed", help="Random seed (same seed, same recording).")
        ] = 0,
        rate: Annotated[
            float | None,
            typer.Option("--rate", help="Scan rate [Hz] of every sensor; the models' if omitted."),
        ] = None,
    ) -> None:
        from laserpeople.io.paths import check_outputs
        from laserpeople.sim import run_scenario
        from laserpeople.sim.simulator import check_recording_suffix

        check_outputs({"-o": output}, [])
        check_recording_suffix(output)  # (before the simulation, not after it)
        result = run_scenario(scenario, seconds=seconds, seed=seed, rate=rate, progress=progress)
        path = result.write(output)
        sensors = ", ".join(s["name"] for s in result.meta["sensors"])
        people = len(result.meta["people"])
        truth = "" if path.suffix == ".npz" else " (not written: only .npz keeps ground truth)"
        say(
            f"wrote {path}: {len(result.scans)} scans ({sensors}), {len(result.truth)} truth "
            f"frames{truth}, {people} people, {result.meta['duration_s']:g} s, seed {seed}"
        )
