"""`laserpeople demo`: simulate a scene, detect, track, evaluate, and draw the tracks."""

from __future__ import annotations

import time
from collections.abc import Iterable
from pathlib import Path
from typing import Annotated, Any

import typer

from laserpeople.cli.common import console, progress, say


def _fmt(value: float | int | None, digits: int = 3) -> str:
    if value is None:
        return "n/a"
    if isinstance(value, int):
        return str(value)
    return f"{value:.{digits}f}"


def plotting_available() -> bool:
    """Whether the libraries that draw ``demo.gif`` (matplotlib, pillow) are installed."""
    from importlib.util import find_spec

    return find_spec("matplotlib") is not None and find_spec("PIL") is not None


def register(app: typer.Typer) -> None:
    """Add the `demo` command to ``app``."""

    @app.command("demo")
    def demo(
        seconds: Annotated[
            float | None,
            typer.Option("--seconds", help="Simulated duration [s] (default: the scenario's)."),
        ] = None,
        out_dir: Annotated[
            Path,
            typer.Option(
                "--out-dir",
                "-o",
                help="Folder where demo.gif, demo-tracks.csv and demo.npz go (-o as in the "
                "other commands).",
            ),
        ] = Path("."),
        seed: Annotated[int, typer.Option("--seed", help="Random seed of the scene.")] = 0,
        no_gif: Annotated[bool, typer.Option("--no-gif", help="Skip the animation.")] = False,
    ) -> None:
        """Simulate people (some in groups, one standing, leg-like clutter), detect legs,
        track with every tracker fed by leg detections alone (the leg MHT and the
        nearest-neighbour baseline), score against ground truth, and
        write demo.gif, demo-tracks.csv and the simulated recording demo.npz."""
        from laserpeople.demo import run_demo

        def bar(items: Iterable[Any], total: int | None, description: str) -> Iterable[Any]:
            return progress(items, total, description)

        can_draw = plotting_available()
        t0 = time.perf_counter()
        result = run_demo(
            out_dir, seconds=seconds, seed=seed, progress=bar, gif=not no_gif and can_draw
        )
        wall = time.perf_counter() - t0

        from rich.table import Table

        table = Table(
            title=(
                f"demo: {result.n_people} people, {result.n_scans} scans "
                f"({result.seconds:.1f} s), {result.n_detections} leg detections "
                f"({result.detection_ms_per_scan:.1f} ms/scan)"
            )
        )
        for col in ("tracker", "MOTA", "MOTP m", "IDF1", "ID switches", "FP", "misses", "ms/scan"):
            table.add_column(col, justify="left" if col == "tracker" else "right")
        for s in result.scores:
            m = s.summary
            table.add_row(
                s.name,
                _fmt(m.get("mota")),
                _fmt(m.get("motp_m")),
                _fmt(m.get("idf1")),
                _fmt(m.get("id_switches")),
                _fmt(m.get("false_positives")),
                _fmt(m.get("misses")),
                f"{s.ms_per_scan:.2f}",
            )
        console.print(table)
        for name, reason in result.skipped:
            say(f"tracker {name} not run: {reason}")
        say(f"wrote {result.recording}, {result.tracks_csv}")
        if result.gif is not None:
            say(f"wrote {result.gif} ({result.gif_frames} frames)")
        elif not no_gif:
            say(
                "no demo.gif: drawing needs matplotlib and pillow; "
                "pip install 'laserpeople[all]' and run the demo again for the picture"
            )
        say(f"done in {wall:.1f} s")
