"""`laserpeople info`: Summarise a recording."""

from __future__ import annotations

import typer

from laserpeople.cli.common import not_built


def register(app: typer.Typer) -> None:
    """Add the `info` command to ``app``."""

    @app.command("info", help="Summarise a recording. (not built yet)")
    def _command() -> None:
        raise not_built("info", "the foundation issue")
