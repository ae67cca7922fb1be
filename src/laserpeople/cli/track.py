"""`laserpeople track`: Track legs, people or groups in a recording."""

from __future__ import annotations

import typer

from laserpeople.cli.common import not_built


def register(app: typer.Typer) -> None:
    """Add the `track` command to ``app``."""

    @app.command("track", help="Track legs, people or groups in a recording. (not built yet)")
    def _command() -> None:
        raise not_built("track", "the leg tracker issue")
