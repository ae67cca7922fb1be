"""`laserpeople bench`: Run the speed and accuracy benchmarks."""

from __future__ import annotations

import typer

from laserpeople.cli.common import not_built


def register(app: typer.Typer) -> None:
    """Add the `bench` command to ``app``."""

    @app.command("bench", help="Run the speed and accuracy benchmarks. (not built yet)")
    def _command() -> None:
        raise not_built("bench", "the benchmark issues")
