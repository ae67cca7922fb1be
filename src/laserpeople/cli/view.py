"""`laserpeople view`: Plot or animate a recording with tracks."""

from __future__ import annotations

import typer

from laserpeople.cli.common import not_built


def register(app: typer.Typer) -> None:
    """Add the `view` command to ``app``."""

    @app.command("view", help="Plot or animate a recording with tracks. (not built yet)")
    def _command() -> None:
        raise not_built("view", "the visualisation issue")
