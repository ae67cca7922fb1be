"""`laserpeople demo`: Simulate, detect, track and evaluate a demo scene."""

from __future__ import annotations

import typer

from laserpeople.cli.common import not_built


def register(app: typer.Typer) -> None:
    """Add the `demo` command to ``app``."""

    @app.command("demo", help="Simulate, detect, track and evaluate a demo scene. (not built yet)")
    def _command() -> None:
        raise not_built("demo", "the visualisation issue")
