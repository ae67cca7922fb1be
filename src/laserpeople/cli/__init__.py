"""The ``laserpeople`` command line.

Each command lives in its own module of this package and registers itself with
:data:`app` through a ``register(app)`` function, so that commands stay small and
independent. Errors a user can cause (:class:`~laserpeople.errors.LaserPeopleError`)
are printed as one line and exit with status 1; ``--debug`` shows the traceback.
"""

from __future__ import annotations

import sys

import typer
from rich.markup import escape

from laserpeople.cli import (
    align,
    bench,
    demo,
    detect,
    evaluate,
    info,
    scenarios,
    simulate,
    track,
    train,
    view,
)
from laserpeople.cli.common import STATE, err_console
from laserpeople.errors import LaserPeopleError

app = typer.Typer(
    name="laserpeople",
    help="Detect and track people, legs and groups of people in 2D laser range scans.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
    add_completion=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)


@app.callback()
def _global_options(
    debug: bool = typer.Option(False, "--debug", help="Show full tracebacks on errors."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress bars or chatter."),
) -> None:
    """Detect and track people, legs and groups of people in 2D laser range scans."""
    STATE.debug = debug
    STATE.quiet = quiet


for _module in (
    info,
    simulate,
    scenarios,
    detect,
    train,
    track,
    evaluate,
    bench,
    view,
    demo,
    align,
):
    _module.register(app)


def main() -> None:
    """Entry point of the ``laserpeople`` command."""
    try:
        app()
    except LaserPeopleError as exc:
        if STATE.debug:
            raise
        err_console.print(
            f"[bold red]error:[/] {escape(str(exc))}", highlight=False, soft_wrap=True
        )
        sys.exit(1)
    except KeyboardInterrupt:
        err_console.print("interrupted")
        sys.exit(130)
