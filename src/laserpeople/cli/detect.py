"""`laserpeople detect`: Detect legs in a recording and write detections CSV."""

from __future__ import annotations

import typer

from laserpeople.cli.common import not_built


def register(app: typer.Typer) -> None:
    """Add the `detect` command to ``app``."""

    @app.command(
        "detect", help="Detect legs in a recording and write detections CSV. (not built yet)"
    )
    def _command() -> None:
        raise not_built("detect", "the leg detection issue")
