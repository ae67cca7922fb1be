"""`laserpeople align`: estimate the mounts of several lasers from a recording."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import typer

from laserpeople.cli.common import MountOption, console, laser_name, plain, warn


def register(app: typer.Typer) -> None:
    """Add the `align` command to ``app``."""

    @app.command(
        "align",
        help="Estimate the lasers' mounts by point-to-line ICP and write them as TOML.",
    )
    def _command(
        recording: Annotated[Path, typer.Argument(help="Recording with two or more lasers.")],
        output: Annotated[Path, typer.Option("-o", "--output", help="Mounts file (.toml).")],
        reference: Annotated[
            str | None,
            typer.Option(
                "--reference",
                help="Laser whose frame is the reference (its topic or frame id).",
                callback=laser_name,
            ),
        ] = None,
        static: Annotated[
            bool,
            typer.Option("--static", help="Static lasers: register their median backgrounds."),
        ] = False,
        mount: MountOption = None,
    ) -> None:
        from rich.table import Table

        from laserpeople.alignment import align_recording, write_mounts
        from laserpeople.io.paths import check_output_format, check_outputs
        from laserpeople.io.poses import parse_mounts

        check_outputs({"-o": output}, [recording])
        check_output_format("-o", output, ".toml", "the mounts as TOML")
        notes: list[str] = []
        mounts = align_recording(
            recording,
            reference=reference,
            static=static,
            mounts=parse_mounts(mount or []),
            notes=notes,
        )
        for note in notes:
            warn(note)
        write_mounts(output, mounts, f"from {recording.name}")
        table = Table(title=plain(f"laser mounts of {recording.name}"))
        for col in (
            "laser",
            "parent",
            "x [m]",
            "y [m]",
            "theta [deg]",
            "residual [m]",
            "explained",
            "vs given [m / deg]",
        ):
            table.add_column(plain(col))  # the units' brackets are not markup
        for m in mounts:
            diff = ""
            if m.given is not None and m.fit is not None:
                dth = math.degrees(math.remainder(m.pose.theta - m.given.theta, 2 * math.pi))
                diff = f"{math.hypot(m.pose.x - m.given.x, m.pose.y - m.given.y):.3f} / {dth:.2f}"
            table.add_row(
                plain(m.laser),
                plain(m.parent),
                f"{m.pose.x:.3f}",
                f"{m.pose.y:.3f}",
                f"{math.degrees(m.pose.theta):.2f}",
                "given" if m.fit is None else f"{m.fit.residual:.4f}",
                "" if m.fit is None else f"{m.fit.explained:.2f}",
                diff,
            )
        console.print(table)
        console.print(f"wrote {output}", highlight=False, markup=False)
