"""What every command shares: global flags, consoles and the progress bar.

Output that is not a terminal (a pipe, a log file, a test runner) is never folded: status
lines stay one line whatever the path length, and tables are laid out for
:data:`PIPE_WIDTH` columns whatever ``COLUMNS`` says. On a terminal rich sizes everything
to the window as usual.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, TypeVar, cast

import typer

from laserpeople.errors import ConfigError, LaserPeopleError, NotBuiltError, RecordingError

if TYPE_CHECKING:
    from rich.console import Console
    from rich.text import Text

    from laserpeople.io import RecordingSource

T = TypeVar("T")


def given_options(ctx: typer.Context, names: Sequence[str]) -> list[str]:
    """The options among the parameters ``names`` of the command of ``ctx`` that the user
    gave on the command line (``--seconds``), in the order of ``names``."""
    return [
        f"--{name.replace('_', '-')}"
        for name in names
        if getattr(ctx.get_parameter_source(name), "name", "") == "COMMANDLINE"
    ]


def no_scan_read(recording: Path, output: Path) -> RecordingError:
    """The error of a run of ``recording`` that read not one scan (a laser topic recorded
    empty, every scan damaged and skipped): not an empty success; its CSV ``output`` holds
    the header alone."""
    return RecordingError(
        f"no scan was read, so {output} holds the CSV header alone",
        path=recording,
        hint="`laserpeople info` lists the recording's laser topics and their scans; "
        "choose one with --topic",
    )


def frame_name(value: str | None) -> str | None:
    """``--world-frame``: a frame's name; empty (``--world-frame ""``, an unset shell
    variable) is refused, not taken for the default."""
    if value is not None and not value.strip():
        raise typer.BadParameter("is empty: give a frame name such as map or odom, or drop it")
    return value


def laser_name(value: str | None) -> str | None:
    """A laser's topic or frame id; empty is refused, not taken for the default."""
    if value is not None and not value.strip():
        raise typer.BadParameter("is empty: give a laser's topic or frame id, or drop it")
    return value


WorldFrameOption = Annotated[
    str | None,
    typer.Option(
        "--world-frame",
        help="Fixed frame for sensor poses in bags (default: map, else odom).",
        callback=frame_name,
    ),
]
"""The ``--world-frame`` option of commands that read sensor poses from a bag's tf."""

MountOption = Annotated[
    list[str] | None,
    typer.Option(
        "--mount",
        help="Laser mount missing from the bag's tf, CHILD=PARENT:x,y,theta (m, rad; "
        "repeatable), a known robot: mir100, or a mounts .toml file (laserpeople align -o).",
    ),
]
"""The ``--mount`` option: laser mounts a bag's tf lacks."""

MountsFileOption = Annotated[
    Path | None,
    typer.Option(
        "--mounts",
        help="TOML file of laser mounts written by `laserpeople align -o` (as --mount FILE).",
    ),
]
"""The ``--mounts`` option: the mounts file ``align`` estimated."""

PresetOption = Annotated[
    str | None,
    typer.Option(
        "--preset",
        help="paper: every tracker exactly as its paper (Arras et al., Kräußling et al., "
        "Schenk et al.; docs/papers.md), before --config.",
    ),
]
"""The ``--preset`` option (:data:`laserpeople.config.PRESETS`)."""


ConfigOption = Annotated[
    Path | None,
    typer.Option("--config", help="TOML file with tracker and detector parameters."),
]
"""The ``--config`` option: a TOML file of parameter sections (``--print-config`` shows them)."""

DetectorOption = Annotated[
    str, typer.Option("--detector", help="Leg detector: adaboost or heuristic.")
]
"""The ``--detector`` option."""

ModelOption = Annotated[
    Path | None, typer.Option("--model", help="AdaBoost model JSON (default: shipped).")
]
"""The ``--model`` option: an AdaBoost leg model written by ``laserpeople train``."""

OutputFrameOption = Annotated[
    str | None,
    typer.Option(
        "--output-frame",
        help="Frame of the written positions: sensor or world (default: the "
        "tracking frame, world when the recording has sensor poses).",
    ),
]
"""The ``--output-frame`` option."""

PeoplePolicyOption = Annotated[
    str | None,
    typer.Option(
        "--people-policy",
        help="leg-mht person layer: tracks (default; people as tracks of their own) "
        "or arras (Arras et al. 2008 Sec. 3.3: people from validated leg pairs; "
        "--preset paper's).",
    ),
]
"""The ``--people-policy`` option of the leg MHT."""

BackgroundOption = Annotated[
    str,
    typer.Option(
        "--background",
        help="Static world model, which tells people from furniture: auto (a "
        "histogram per beam while the lasers stand still, an occupancy grid once "
        "they move), histogram, occupancy or none.",
    ),
]
"""The ``--background`` option (default ``auto``)."""

MapOption = Annotated[
    Path | None,
    typer.Option(
        "--map",
        help="Map seeding the occupancy grid (world frame only): a ROS map.yaml, or "
        "BAG:/topic for a nav_msgs/OccupancyGrid in a bag (e.g. the recording's "
        "own /map), in the frame of the scans' poses.",
    ),
]
"""The ``--map`` option."""

RestampOption = Annotated[
    float | None,
    typer.Option(
        "--restamp",
        metavar="HZ",
        help="Track at this fixed scan rate [Hz] from each laser's first stamp "
        "instead of the recorded stamps (for a recording whose clock does not "
        "advance; without it such a recording is refused).",
    ),
]
"""The ``--restamp`` option."""


def mount_specs(mount: list[str] | None, mounts: Path | None) -> list[str]:
    """The ``--mount`` specs with the ``--mounts`` file after them (a missing file is a
    ConfigError naming it)."""
    specs = list(mount or [])
    if mounts is not None:
        if not mounts.is_file():
            raise ConfigError(
                "no such mounts file", path=mounts, hint="write it with laserpeople align -o"
            )
        specs.append(str(mounts))
    return specs


OnErrorOption = Annotated[
    str,
    typer.Option(
        "--on-error",
        help="A damaged scan in the middle of a recording: stop (default; the error names "
        "the scan and how many were read) or skip (leave it out, count it, read on).",
    ),
]
"""The ``--on-error stop|skip`` option of commands that read recordings."""

PIPE_WIDTH = 200
"""Columns rich lays tables out for when the output is not a terminal."""

PIPE_PROGRESS_SECONDS = 10.0
"""Seconds between two progress lines when stderr is not a terminal (the first comes after
this long, so short runs print none)."""


def _isatty(stream: object) -> bool:
    try:
        return bool(stream.isatty())  # type: ignore[attr-defined]
    except (AttributeError, ValueError):  # no isatty, or a closed stream
        return False


def make_console(stderr: bool = False) -> Console:
    """A rich console for stdout (or stderr): sized to the window on a terminal; otherwise
    :data:`PIPE_WIDTH` columns wide with soft wrapping, so that no line is ever folded."""
    from rich.console import Console

    if _isatty(sys.stderr if stderr else sys.stdout):
        return Console(stderr=stderr)
    return Console(stderr=stderr, soft_wrap=True, width=PIPE_WIDTH)


class _LazyConsole:
    """Stands for the console made by :func:`make_console` on first use, so that starting
    the program (``--help``) does not import rich's console."""

    def __init__(self, stderr: bool) -> None:
        self._stderr = stderr
        self._console: Console | None = None

    def get(self) -> Console:
        """The console itself, made on first use: what to hand to rich's own objects
        (a progress bar's live display enters it as a context manager, which an attribute
        look-up cannot stand for)."""
        if self._console is None:
            self._console = make_console(self._stderr)
        return self._console

    def __getattr__(self, name: str) -> Any:
        return getattr(self.get(), name)


def plain(text: object) -> Text:
    """``text`` as written, for a rich table's title or cell or a console line: never markup
    nor an emoji code. A file named ``run[a].bag``, a topic, a track id or an error quoting
    ``[leg_tracker]`` would otherwise lose its brackets, and ``:fire:`` become a picture."""
    from rich.text import Text

    return Text(str(text))


console = cast("Console", _LazyConsole(stderr=False))
"""The console for results (stdout)."""
err_console = cast("Console", _LazyConsole(stderr=True))
"""The console for status lines, warnings and errors (stderr)."""


def _stderr_console() -> Console:
    """The console of :data:`err_console` itself (see :meth:`_LazyConsole.get`)."""
    lazy: Any = err_console
    return lazy.get() if isinstance(lazy, _LazyConsole) else lazy


@dataclass
class CliState:
    """Global flags given before the command name."""

    debug: bool = False
    quiet: bool = False


STATE = CliState()


def progress(
    items: Iterable[T], total: int | None = None, description: str = "scans"
) -> Iterator[T]:
    """Iterate with a progress bar showing scans/s on a terminal. When stderr is not a
    terminal, a plain line (``drawing: 500/10,000 (5 %), 48 per s``) every
    :data:`PIPE_PROGRESS_SECONDS`, so long runs show life in a log; silent with --quiet."""
    if STATE.quiet:
        yield from items
        return
    if not _isatty(sys.stderr):
        yield from _progress_lines(items, total, description)
        return
    yield from _progress_bar(items, total, description)


def _progress_lines(items: Iterable[T], total: int | None, description: str) -> Iterator[T]:
    start = last = time.monotonic()
    for done, item in enumerate(items, start=1):
        yield item
        now = time.monotonic()
        if now - last >= PIPE_PROGRESS_SECONDS:
            last = now
            of = f"/{total:,} ({100.0 * done / total:.0f} %)" if total else ""
            say(f"{description}: {done:,}{of}, {rate_text(done, now - start)}")


def rate_text(done: int, seconds: float) -> str:
    """How fast ``done`` items took ``seconds`` [s]: ``48 per s``, or, slower than one a
    second, ``26 s each`` (not ``0 per s``)."""
    if done * 1.0 >= seconds:
        return f"{done / seconds:,.0f} per s"
    return f"{seconds / done:,.0f} s each"


def _progress_bar(items: Iterable[T], total: int | None, description: str) -> Iterator[T]:
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        ProgressColumn,
        Task,
        TextColumn,
        TimeElapsedColumn,
    )
    from rich.text import Text

    class RateColumn(ProgressColumn):
        def render(self, task: Task) -> Text:
            speed = task.finished_speed or task.speed
            return Text(f"{speed:,.0f} scans/s" if speed else "", style="progress.data.speed")

    columns = [
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        RateColumn(),
        TimeElapsedColumn(),
    ]
    with Progress(*columns, console=_stderr_console(), transient=False) as bar:
        task = bar.add_task(description, total=total)
        last = time.monotonic()
        pending = 0
        for item in items:
            yield item
            pending += 1
            now = time.monotonic()
            if now - last > 0.1:
                bar.advance(task, pending)
                pending, last = 0, now
        bar.advance(task, pending)


class JobProgress:
    """One progress display for a job of many items (recordings): items done of ``total``,
    scans per second and failures. A bar on a terminal; a plain line every
    :data:`PIPE_PROGRESS_SECONDS` when stderr is not one; nothing with --quiet. Use as a
    context manager and call :meth:`advance` per finished item."""

    def __init__(self, total: int, description: str = "recordings") -> None:
        self.total = total
        self.description = description
        self.done = self.scans = self.failed = 0
        self._start = self._last = time.monotonic()
        self._bar: Any = None
        self._task: Any = None

    def __enter__(self) -> JobProgress:
        if not STATE.quiet and _isatty(sys.stderr):
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                Progress,
                TextColumn,
                TimeElapsedColumn,
            )

            self._bar = Progress(
                TextColumn("{task.description}"),
                BarColumn(),
                MofNCompleteColumn(),
                TextColumn("{task.fields[rate]}", style="progress.data.speed"),
                TextColumn("{task.fields[failed]}", style="red"),
                TimeElapsedColumn(),
                console=_stderr_console(),
                transient=False,
            )
            self._bar.__enter__()
            self._task = self._bar.add_task(self.description, total=self.total, rate="", failed="")
        return self

    def advance(self, items: int = 1, scans: int = 0, failed: int = 0) -> None:
        """Count ``items`` finished with ``scans`` scans, ``failed`` of them failed."""
        self.done += items
        self.scans += scans
        self.failed += failed
        now = time.monotonic()
        rate = self.scans / max(now - self._start, 1e-9)
        if self._bar is not None:
            self._bar.update(
                self._task,
                advance=items,
                rate=f"{rate:,.0f} scans/s",
                failed=f"{self.failed} failed" if self.failed else "",
            )
        elif not STATE.quiet and now - self._last >= PIPE_PROGRESS_SECONDS:
            self._last = now
            say(
                f"{self.description}: {self.done:,}/{self.total:,}, {rate:,.0f} scans/s, "
                f"{self.failed} failed"
            )

    def __exit__(self, *exc: object) -> None:
        if self._bar is not None:
            self._bar.__exit__(None, None, None)


def say(message: str) -> None:
    """Print a status line to stderr unless --quiet."""
    if not STATE.quiet:
        _status_line(message)


def _status_line(text: str) -> None:
    """``text`` as one line on stderr: through the rich console on a terminal, written as
    it is otherwise (a log or a pipe; rich would replace ``:name:`` emoji codes and expand
    tabs), without importing rich's console there (a tenth of a second of a run that
    prints only status lines)."""
    if _isatty(sys.stderr):
        err_console.print(plain(text), soft_wrap=True)
    else:
        sys.stderr.write(text + "\n")
        sys.stderr.flush()


def open_with_poses(
    path: Path, world_frame: str | None, mounts: list[str], on_error: str = "stop"
) -> RecordingSource:
    """Open a recording; for ROS bags, ``world_frame`` and laser ``mounts`` missing from the
    bag's tf let the reader give sensor poses (moving robots). ``on_error`` is the reader's
    damaged-scan policy (``stop`` or ``skip``, :mod:`laserpeople.io.damage`)."""
    from laserpeople.pipeline.recording import open_source

    return open_source(path, world_frame, mounts, on_error)


def explain_missing_poses(
    exc: LaserPeopleError, recording: object, topics: Sequence[str] | None = None
) -> None:
    """Add to ``exc``, an error for scans without a sensor pose (a
    :class:`~laserpeople.errors.PoseUnavailableError`, or a fusion refused for want of
    poses), why the recording's scans have none: the laser frames /tf does not link to the
    world and what to do (:meth:`~laserpeople.io.rosbag.RosbagRecording.pose_problem`;
    recordings other than bags are left as they are)."""
    from laserpeople.errors import PoseUnavailableError

    if not (isinstance(exc, PoseUnavailableError) or "no sensor poses" in exc.detail):
        return
    pose_problem = getattr(recording, "pose_problem", None)
    if not callable(pose_problem):
        return
    try:
        problem = pose_problem(topics)
    except LaserPeopleError:
        return
    if problem:
        exc.noted(problem)


def report_damage(recording: object) -> None:
    """Warn about the damaged scans a reader skipped (``--on-error skip``), if any."""
    damaged = getattr(recording, "damaged", None)
    text = damaged.summary() if damaged is not None else ""
    if text:
        warn(text)


def warn(message: str) -> None:
    """Print a warning to stderr, even with --quiet."""
    _status_line(f"warning: {message}")


def warnings_as_lines() -> None:
    """Print this package's warnings (:class:`~laserpeople.errors.LaserPeopleWarning`) as
    :func:`warn` lines, not as Python shows them (with the source file and line of the
    code that warned), each text once per command (a note of a file read twice, a setting
    checked by two modules); other warnings, and all with --debug, as Python shows them."""
    import warnings

    from laserpeople.errors import LaserPeopleWarning

    shown = getattr(warnings.showwarning, "python_showwarning", warnings.showwarning)
    said: set[str] = set()

    def show(message: Warning | str, category: type[Warning], *args: Any, **kw: Any) -> None:
        if issubclass(category, LaserPeopleWarning) and not STATE.debug:
            if str(message) not in said:
                said.add(str(message))
                warn(str(message))
        else:
            shown(message, category, *args, **kw)

    show.python_showwarning = shown  # type: ignore[attr-defined]
    warnings.showwarning = show


def ignored_sections(path: Path | None, sections: Sequence[str]) -> None:
    """Say which sections of a shared ``--config`` file this command does not read."""
    for name in sections:
        warn(f"{path}: [{name}] is read by another command or tracker, not by this one")


def not_built(command: str, issue: str) -> NotBuiltError:
    """The error a command raises while the feature behind it is not part of this version."""
    return NotBuiltError(
        f"`laserpeople {command}` is not built in this version yet",
        hint=f"it arrives with {issue}",
    )
