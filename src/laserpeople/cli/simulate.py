"""`laserpeople simulate`: Simulate a scenario and write a recording with ground truth."""

from __future__ import annotations

import typer

from laserpeople.cli.common import not_built


def register(app: typer.Typer) -> None:
    """Add the `simulate` command to ``app``."""

    @app.command(
        "simulate",
        help="Simulate a scenario and write a recording with ground truth. (not built yet)",
    )
    def _command() -> None:
        raise not_built("simulate", "the simulator issue")
