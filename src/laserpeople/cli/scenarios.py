"""`laserpeople scenarios`: List the named simulation scenarios."""

from __future__ import annotations

import typer

from laserpeople.cli.common import not_built


def register(app: typer.Typer) -> None:
    """Add the `scenarios` command to ``app``."""

    @app.command("scenarios", help="List the named simulation scenarios. (not built yet)")
    def _command() -> None:
        raise not_built("scenarios", "the simulator issue")
