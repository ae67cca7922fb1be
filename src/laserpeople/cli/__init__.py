"""The ``laserpeople`` command line.

Each command lives in its own module of this package and registers itself with the
program (:func:`make_app`; ``app`` has every command) through a ``register(app)``
function, so that commands stay small and independent. Errors a user can cause
(:class:`~laserpeople.errors.LaserPeopleError`) are printed as one line and exit with
status 1; ``--debug`` shows the traceback.

Start-up stays fast (every ``--help`` under 10 times a bare Python start but the
program's own, ``benchmarks/bench_startup.py``): the command modules import numpy, scipy,
the readers and the plotting libraries inside the command functions, never at module
level; :func:`main` builds only the command it runs (:func:`commands_needed`).
"""

from __future__ import annotations

import contextlib
import os
import sys
import typing
from collections.abc import Iterator, MutableMapping, Sequence
from importlib import import_module
from pathlib import Path
from typing import Any, NoReturn

import typer
from typer.core import TyperArgument, TyperGroup, TyperOption

from laserpeople.cli.common import STATE, err_console, warn, warnings_as_lines
from laserpeople.errors import LaserPeopleError, cut_long_values

BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS")
"""The variables by which OpenBLAS (numpy's linear algebra) reads its thread count."""


def one_blas_thread(environ: MutableMapping[str, str] | None = None) -> None:
    """Let numpy's OpenBLAS start with one thread (``OPENBLAS_NUM_THREADS=1``) unless one of
    :data:`BLAS_THREAD_VARIABLES` is set already; call it before numpy is imported.

    The package's products are small (Kalman matrices of a few rows, a few thousand points
    by 2 x 2), which OpenBLAS works out in the calling thread whatever its thread count
    (the same floats); starting its worker threads when numpy is imported
    cost 22 ms of CPU per process on an idle 2-core machine and about 45 ms at a load of 5
    (the workers wait for work busily at first), a tenth of the start of ``track``."""
    env = os.environ if environ is None else environ
    if not any(name in env for name in BLAS_THREAD_VARIABLES):
        env["OPENBLAS_NUM_THREADS"] = "1"


GLOBAL_FLAGS = ("--debug", "--quiet", "-q")
"""Flags of the whole program that are also accepted after the command name."""

HELP = (
    "Detect and track people and their legs in 2D laser range scans (Arras et al. 2008), "
    "simulate scenes with ground truth, and score tracks (CLEAR MOT, IDF1, the adapted MOTP "
    "of Schenk et al. 2011). Groups: `track --tracker group-mht` tracks groups of people "
    "and their size (Arras et al. 2008), `evaluate --kind group` scores them; `--tracker csa` "
    "(Kräußling et al.) and the particle filters feet-pf and upper-body-pf (Schenk et al. "
    "2011) track people from raw laser points."
)


def hoist_global_flags(args: list[str]) -> list[str]:
    """``args`` with the global flags that follow the command name moved in front of it
    (``laserpeople track x.bag --quiet`` = ``laserpeople --quiet track x.bag``); anything
    after ``--`` is left alone."""
    if "--" in args:
        cut = args.index("--")
        head, tail = args[:cut], args[cut:]
    else:
        head, tail = args, []
    flags = [a for a in head if a in GLOBAL_FLAGS]
    rest = [a for a in head if a not in GLOBAL_FLAGS]
    return [*flags, *rest, *tail]


def _usage_name(param: TyperArgument) -> Any:
    """Usage text of an argument: ``NAME`` when required, ``[NAME]`` when optional,
    ``...`` when repeatable (the same for every command)."""

    def show() -> str:
        name = (param.metavar or param.name or "").upper()
        name = name if param.required else f"[{name}]"
        return name + ("..." if param.nargs != 1 else "")

    return show


OPTION_METAVARS = {"int": "N", "float": "NUMBER", "path": "PATH", "Path": "PATH"}
"""What an option's value is called in ``--help`` by its type (``TEXT`` otherwise), in
place of typer's ``<list[str]>`` / ``<float range>``."""


def _metavar(param: TyperOption) -> str:
    """``N``, ``NUMBER``, ``PATH`` or ``TEXT`` for typer's ``<int>``, ``<float range>``,
    ``<list[Path]>``, ``<str>``..."""
    try:
        label = str(param.display_type(None))  # type: ignore[arg-type]
    except Exception:  # a choice type needs a context: its values are text
        return "TEXT"
    label = label.strip("<>").removesuffix(" range")
    if label.startswith("list[") and label.endswith("]"):
        label = label[5:-1]
    return OPTION_METAVARS.get(label, "TEXT")


def _no_type(ctx: Any) -> None:
    """An argument's help line names the argument only (its help says what it takes)."""
    return None


class PlainValues:
    """typer's coercion of one parameter's value, without pydantic where the value is
    plain: ``None``, text for a ``str`` parameter (as typer passes it on, unchanged), a
    default of the parameter's own ``int`` or ``float`` type, text for a list of texts,
    and a path for a ``Path`` parameter (through typer's own checks of paths). Anything
    else (a number or choice typed on the command line, constraints, parsers) goes to
    typer's own coercion, built at its first use, so values and error messages stay
    typer's.

    typer from 0.2x coerces every parameter of the command run through a pydantic
    ``TypeAdapter``: importing pydantic and building them costs about 0.2 s CPU per run,
    for values it hands on unchanged. Installed by :class:`LaserPeopleGroup` on
    parameters of typer versions that build them lazily (``_runtime_param``).
    """

    def __init__(self, param: Any) -> None:
        self._param = param
        self._typer: Any = None
        descriptor = param.type_descriptor
        info = descriptor.parameter_info
        self._kind = ""
        plain = (
            info.parser is None
            and getattr(info, "click_type", None) is None
            and descriptor.file_annotation is None
            and not descriptor.is_choice
            and info.min is None
            and info.max is None
        )
        annotation = descriptor.annotation
        if not plain:
            return
        if annotation in (str, int, float):
            self._kind = annotation.__name__
        elif annotation == list[str]:
            self._kind = "list[str]"
        elif (
            isinstance(annotation, type)
            and issubclass(annotation, Path)
            and info.path_type is None
            and not (info.allow_dash and info.file_okay)
        ):
            self._kind = "path"

    def coerce(self, value: Any, param: Any, ctx: Any) -> Any:
        """The value as typer's coercion gives it."""
        kind = self._kind
        multi = param.multiple or param.nargs == -1
        if value is None:
            return () if multi else None
        if kind and not (multi and isinstance(value, str)):
            if kind == "str" and type(value) is str:
                return value
            if kind in ("int", "float") and type(value).__name__ == kind:
                return value
            if (
                kind == "list[str]"
                and isinstance(value, (list, tuple))
                and all(type(v) is str for v in value)
            ):
                return list(value)
            if kind == "path" and type(value) is str:
                from typer._param_types import coerce_cli_path

                annotation = self._param.type_descriptor.annotation
                info = self._param.type_descriptor.parameter_info
                return coerce_cli_path(
                    annotation(value), info, path_type=annotation, param=param, ctx=ctx
                )
        if self._typer is None:
            from typer._coercion import build_runtime_param

            self._typer = build_runtime_param(self._param.type_descriptor)
        return self._typer.coerce(value, param=param, ctx=ctx)


def _plain_values(param: Any) -> None:
    """Give ``param`` :class:`PlainValues` where typer builds its coercion lazily."""
    if getattr(param, "_runtime_param", False) is None and hasattr(param, "type_descriptor"):
        param._runtime_param = PlainValues(param)


def _plain_help(get_help_option: Any) -> Any:
    """A command's ``get_help_option`` whose flag gets :class:`PlainValues` (not given, it
    is ``None``, which typer would coerce through pydantic)."""

    def get(ctx: Any) -> Any:
        option = get_help_option(ctx)
        if option is not None:
            _plain_values(option)
        return option

    return get


class LaserPeopleGroup(TyperGroup):
    """The command group: global flags after the command name, one style of usage line,
    plain value names in ``--help`` (``--tracker TEXT``, ``--gate NUMBER``), plain values
    coerced without pydantic (:class:`PlainValues`)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        for param in self.params:
            _plain_values(param)
        for name, command in self.commands.items():
            for param in command.params:
                _plain_values(param)
                if is_path_parameter(name, param):
                    _refuse_empty_paths(param)
                if isinstance(param, TyperOption) and param.metavar is None:
                    param.metavar = _metavar(param)
                if isinstance(param, TyperArgument):
                    param.display_type_rich = _no_type  # type: ignore[method-assign]
                    param.metavar = (param.metavar or param.name or "").upper()
                    # typer writes required arguments as {name}; the instance attribute
                    # makes every usage line read NAME / [NAME] / NAME...
                    param._usage_display_name = _usage_name(param)  # type: ignore[method-assign]
            command.get_help_option = _plain_help(command.get_help_option)  # type: ignore[method-assign]

    def get_help_option(self, ctx: Any) -> Any:
        """The help flag, ``False`` when not given: typer leaves it ``None``, which makes it
        build a pydantic converter for it (0.1-0.2 s of start-up, pydantic and
        ``importlib.metadata``) on ``laserpeople COMMAND --help``, where the program's own
        flags are parsed before the command's help is printed."""
        option = _help_flag_false(super().get_help_option(ctx))
        if option is not None:
            _plain_values(option)
        return option

    def parse_args(self, ctx: Any, args: list[str]) -> list[str]:
        with _short_usage_errors():
            return super().parse_args(ctx, hoist_global_flags(list(args)))

    def invoke(self, ctx: Any) -> Any:
        with _short_usage_errors():
            try:
                return super().invoke(ctx)
            except KeyboardInterrupt as exc:  # (typer would exit 130 without a word)
                from laserpeople.cli.stopping import stop_name, stop_status

                status = stop_status(exc)
                err_console.print(
                    f"interrupted ({stop_name(status)})", markup=False, highlight=False
                )
                raise typer.Exit(status) from None


TEXT_PATH_PARAMETERS = frozenset(
    {("evaluate", "truth_args"), ("fit", "truth"), ("view", "truth"), ("batch", "recordings")}
)
"""(command, parameter) of the files given as text (``BAG[:TOPIC]``, globs)."""


def is_path_parameter(command: str, param: Any) -> bool:
    """Whether ``param`` of ``command`` names files: typed ``Path`` (or a list of them), or
    one of :data:`TEXT_PATH_PARAMETERS`."""
    if (command, param.name) in TEXT_PATH_PARAMETERS:
        return True
    descriptor = getattr(param, "type_descriptor", None)
    annotation = getattr(descriptor, "annotation", None)
    return annotation is Path or Path in typing.get_args(annotation)


def _refuse_empty_paths(param: Any) -> None:
    """Make ``param`` refuse an empty path (``--config ""``, an unset shell variable),
    which ``Path`` would take for ``.``, the current folder: a usage error naming the
    option, before any file is read or written."""
    process = param.process_value

    def checked(ctx: Any, value: Any) -> Any:
        values = value if isinstance(value, (list, tuple)) else (value,)
        if any(isinstance(v, str) and v == "" for v in values):
            raise typer.BadParameter("is empty: give a file or folder name, or drop it")
        return process(ctx, value)

    param.process_value = checked


def _help_flag_false(option: Any) -> Any:
    """``option`` (a help flag or None) with default ``False`` in place of ``None``."""
    if option is not None and option.default is None:
        option.default = False
    return option


@contextlib.contextmanager
def _short_usage_errors() -> Iterator[None]:
    """Usage errors (a bad option value) echo long values cut to their first characters."""
    try:  # typer from 0.2x carries its own click; importing click itself costs 10-20 ms
        from typer._click.exceptions import UsageError
    except ImportError:
        from click.exceptions import UsageError  # type: ignore[assignment]

    try:
        yield
    except UsageError as exc:
        short = cut_long_values(exc.message)
        if short == exc.message:
            raise
        raise UsageError(short, ctx=exc.ctx) from exc


def version() -> str:
    """The installed version of laserpeople (the package's own when not installed)."""
    from importlib.metadata import PackageNotFoundError
    from importlib.metadata import version as installed

    try:
        return installed("laserpeople")
    except PackageNotFoundError:
        from laserpeople import __version__

        return __version__


def _print_version(value: bool) -> None:
    if value:
        print(f"laserpeople {version()}")
        raise typer.Exit()


def _global_options(
    debug: bool = typer.Option(
        False, "--debug", help="Show full tracebacks on errors (also after the command)."
    ),
    quiet: bool = typer.Option(
        False, "--quiet", "-q", help="No progress or status lines (also after the command)."
    ),
    show_version: bool = typer.Option(
        False,
        "--version",
        help="Print the version and exit.",
        is_eager=True,
        callback=_print_version,
    ),
) -> None:
    """Global flags (the program's help text is :data:`HELP`)."""
    STATE.debug = debug
    STATE.quiet = quiet
    warnings_as_lines()
    from laserpeople.cli.environment import unknown_variables

    for line in unknown_variables(os.environ):
        warn(line)


COMMANDS = (
    "info",
    "simulate",
    "scenarios",
    "detect",
    "train",
    "track",
    "evaluate",
    "fit",
    "bench",
    "view",
    "demo",
    "align",
    "batch",
    "live",
)
"""The commands in the order ``--help`` lists them; each is the module
``laserpeople.cli.NAME`` with its ``register(app)``."""


def make_app(commands: Sequence[str] = COMMANDS) -> typer.Typer:
    """The ``laserpeople`` program with the global flags and ``commands`` (default: all)."""
    program = typer.Typer(
        name="laserpeople",
        cls=LaserPeopleGroup,
        no_args_is_help=True,
        pretty_exceptions_enable=False,
        rich_markup_mode=None,
        add_completion=False,
        context_settings={"help_option_names": ["-h", "--help"]},
    )
    _resolve_annotations(_global_options)
    program.callback(help=HELP)(_global_options)
    for name in commands:
        import_module(f"laserpeople.cli.{name}").register(program)
    for info in program.registered_commands:
        _resolve_annotations(info.callback)
    return program


def _resolve_annotations(function: Any) -> None:
    """Replace the text annotations of ``function`` (``from __future__ import
    annotations``) by what they name, once: typer evaluates every text annotation of every
    command four times while building the program (a third of building ``--help``)."""
    if function is not None and any(
        isinstance(a, str) for a in getattr(function, "__annotations__", {}).values()
    ):
        function.__annotations__ = typing.get_type_hints(function, include_extras=True)


def commands_needed(args: Sequence[str]) -> tuple[str, ...]:
    """The commands the program must build for ``args``: the one named first (after the
    global flags) when it is a command, none for ``--version`` alone, otherwise all (the
    program's help, a mistyped command with suggestions). typer builds every registered
    command, its options and their types before parsing, so a run or a command's help with
    only its own command is faster by the other commands' share; its output is the same."""
    rest = [a for a in hoist_global_flags(list(args)) if a not in GLOBAL_FLAGS]
    if rest == ["--version"]:  # (printed before any command is looked at)
        return ()
    if rest and rest[0] in COMMANDS:
        return (rest[0],)
    return COMMANDS


def __getattr__(name: str) -> Any:
    """``app``, the program with every command, built on first use (PEP 562)."""
    if name == "app":
        program = make_app()
        globals()["app"] = program
        return program
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def run() -> NoReturn:
    """The ``laserpeople`` program (and ``python -m laserpeople.cli``): :func:`main`, then
    :func:`end_process` with its exit status."""
    try:
        main()
    except SystemExit as exc:
        end_process(exc.code)
    end_process(0)


def end_process(code: object) -> NoReturn:
    """End the process with the exit status ``code`` (None or an int, as ``sys.exit``)
    without the interpreter's finalisation: the ``atexit`` functions run and the standard
    streams are flushed, then ``os._exit``. Tearing down the modules and objects of a run
    cost 67 ms of CPU after ``track`` on the demo bag (41 ms after its imports alone), for
    a process that ends anyway; the files a command writes are closed by then. With other
    Python threads alive, another kind of ``code``, or a stream that cannot be flushed (a
    closed pipe), the usual ``sys.exit`` ends it."""
    import atexit
    import threading

    if threading.active_count() > 1 or not (code is None or isinstance(code, int)):
        raise SystemExit(code)
    atexit._run_exitfuncs()
    try:
        for stream in (sys.stdout, sys.stderr):
            if stream is not None:
                stream.flush()
    except (OSError, ValueError):
        raise SystemExit(code) from None
    os._exit(code or 0)


def main() -> None:
    """Entry point of the ``laserpeople`` command."""
    one_blas_thread()
    from laserpeople.cli.stopping import stop_on_sigterm, stop_status

    stop_on_sigterm()
    try:
        make_app(commands_needed(sys.argv[1:]))(prog_name="laserpeople")
    except LaserPeopleError as exc:
        if STATE.debug:
            raise
        from rich.text import Text

        # the message as written: file names and topics are neither markup nor emoji codes
        err_console.print(Text.assemble(("error:", "bold red"), " ", str(exc)), soft_wrap=True)
        sys.exit(1)
    except KeyboardInterrupt as exc:
        err_console.print("interrupted")
        sys.exit(stop_status(exc))
