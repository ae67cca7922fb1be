"""`laserpeople evaluate`: Score tracks against ground truth."""

from __future__ import annotations

import typer

from laserpeople.cli.common import not_built


def register(app: typer.Typer) -> None:
    """Add the `evaluate` command to ``app``."""

    @app.command("evaluate", help="Score tracks against ground truth. (not built yet)")
    def _command() -> None:
        raise not_built("evaluate", "the metrics issue")
