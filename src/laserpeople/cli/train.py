"""`laserpeople train`: Train the AdaBoost leg detector."""

from __future__ import annotations

import typer

from laserpeople.cli.common import not_built


def register(app: typer.Typer) -> None:
    """Add the `train` command to ``app``."""

    @app.command("train", help="Train the AdaBoost leg detector. (not built yet)")
    def _command() -> None:
        raise not_built("train", "the leg detection issue")
