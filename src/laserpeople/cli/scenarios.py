"""`laserpeople scenarios`: list the named simulation scenarios."""

from __future__ import annotations

import typer

from laserpeople.cli.common import console


def register(app: typer.Typer) -> None:
    """Add the `scenarios` command to ``app``."""

    @app.command("scenarios", help="List the named simulation scenarios.")
    def _command() -> None:
        from rich.table import Table

        from laserpeople.citations import cite
        from laserpeople.sim.scenarios import REGISTRY

        table = Table(title="laserpeople simulation scenarios", show_lines=False)
        table.add_column("name", style="bold")
        table.add_column("description")
        table.add_column("source")
        table.add_column("seconds", justify="right")
        for s in REGISTRY.values():
            table.add_row(s.name, cite(s.description), cite(s.source), f"{s.duration:g}")
        console.print(table)
