"""Checks on the files a command is about to write, and writing a small text file whole.

:func:`check_outputs` refuses an output that is one of the command's inputs (the same
file under another name included: the paths are resolved and, when both exist, compared
by device and inode), lies inside an input ROS 2 bag folder, or is given twice
as output. Commands call it before they open anything for writing, so that
``laserpeople track X.npz -o X.npz`` stops with a message instead of truncating the
recording it is about to read.
"""

from __future__ import annotations

import os
from collections.abc import Collection, Iterable, Mapping
from contextlib import suppress
from pathlib import Path

from laserpeople.errors import ConfigError, LaserPeopleError, RecordingError


def _resolved(path: Path) -> Path:
    try:
        return path.expanduser().resolve(strict=False)
    except (OSError, RuntimeError):
        return path.absolute()


def same_file(a: str | Path, b: str | Path) -> bool:
    """Whether ``a`` and ``b`` name the same file (resolved paths, or device and inode)."""
    pa, pb = Path(a), Path(b)
    if _resolved(pa) == _resolved(pb):
        return True
    try:
        return os.path.samefile(pa, pb)
    except OSError:
        return False


def path_argument(value: object, name: str, function: str) -> Path:
    """``value`` as a path, for a function of the Python API that reads or writes a file.

    Args:
        value: What the caller passed.
        name: The argument's name (``"path"``).
        function: The function (``"open_recording"``), for the message.

    Raises:
        TypeError: ``value`` is no ``str`` or ``os.PathLike`` (a number, None, bytes, an
            open file); names the function, the argument and what it takes.
        ValueError: ``value`` is the empty string (it would be read as ``.``).
    """
    if isinstance(value, Path):
        return value
    if isinstance(value, str):
        if not value:
            raise ValueError(f"{function}(): {name} is empty: give the path of a file")
        return Path(value)
    if isinstance(value, os.PathLike):
        named = os.fspath(value)
        if isinstance(named, str):
            return Path(named)
    shown = repr(value)
    shown = shown if len(shown) <= 60 else shown[:57] + "..."
    raise TypeError(
        f"{function}(): {name} must be a file path (str or pathlib.Path), "
        f"got {type(value).__name__} {shown}"
    )


FORMATS = frozenset(
    {
        ".bag", ".mcap", ".db3", ".npz", ".log", ".clf",  # recordings
        ".csv", ".parquet", ".json", ".toml", ".yaml", ".yml",  # tables, models, settings
        ".png", ".gif", ".mp4", ".rrd",  # pictures and viewer files
    }
)  # fmt: skip
"""Extensions of the formats this package reads or writes."""


def not_found(path: str | Path) -> str:
    """Why ``path`` cannot be opened when it does not exist, for an error message: ``file not
    found``, or for a symbolic link whose target is missing, where it points."""
    p = Path(path)
    if not p.is_symlink():
        return "file not found"
    target = os.readlink(p)
    relative = "" if os.path.isabs(target) else " (a relative link is read from its own folder)"
    return f"a symbolic link to {target!r}, which does not exist{relative}"


def empty_file(path: str | Path, what: str) -> RecordingError:
    """The error for a file of 0 bytes given as ``what`` (``"a bag"``, ``"a recording"``)."""
    return RecordingError(
        f"the file is empty (0 bytes), not {what}",
        path=Path(path),
        hint="the copy or the recording was cut short: copy or record it again",
    )


def why_unwritable(exc: OSError, path: str | Path) -> str:
    """Why ``path`` could not be written, for an error message: the system's reason, or
    ``runs.bag is a file, not a folder`` when a folder on the way to it is a file (where the
    system says only "File exists" or "Not a directory")."""
    if isinstance(exc, FileExistsError | NotADirectoryError):
        for parent in Path(path).parents:
            if parent.exists() and not parent.is_dir():
                return f"{parent} is a file, not a folder"
    return str(exc.strerror or exc)


def make_folder(folder: Path, option: str) -> None:
    """Make the output folder ``folder`` (given as ``option``) and its parents if missing.

    Raises:
        ConfigError: it cannot be made (a file on the way, no permission); names it.
    """
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ConfigError(
            f"cannot make the folder: {why_unwritable(exc, folder / 'x')}",
            path=folder,
            hint=f"give {option} a folder (made when missing)",
        ) from exc


def check_output_format(
    name: str, path: Path | None, suffix: str, what: str, hint: str = ""
) -> None:
    """Refuse an output whose extension names another format than the one written: a CSV
    written to ``tracks.parquet`` is no Parquet file, and to ``other.bag`` it replaces a
    recording. Other extensions (``.txt``, none) and ``/dev/...`` are written as asked.

    Args:
        name: The option (``"-o"``).
        path: The output (None: not given).
        suffix: The extension of what is written (``".csv"``).
        what: What is written (``"a tracks CSV"``).
        hint: What to do instead (default: give a path ending in ``suffix``).

    Raises:
        ConfigError: names the option, the path and what it writes.
    """
    if path is None:
        return
    got = path.suffix.lower()
    if got != suffix and got in FORMATS:
        raise ConfigError(
            f"{name} writes {what}, not a {got} file: {path}",
            hint=hint or f"give a path ending in {suffix}",
        )


def check_outputs(
    outputs: Mapping[str, str | Path | None],
    inputs: Iterable[str | Path | None],
    folders: Collection[str] = (),
) -> None:
    """Refuse to write over an input, or a file over a folder, before any work is done.

    Args:
        outputs: Option name (``"-o"``, ``"--plot"``) -> the path it names (None: not given).
        inputs: Every file or folder the command reads (None entries are ignored).
        folders: The options of ``outputs`` that name a folder (``batch --out``); every
            other output is a file.

    Raises:
        ConfigError: An output is an input, lies inside an input folder, or two outputs
            are the same file; the message names both paths. A file output names an
            existing folder (it was found only after the run, as "Is a directory").
    """
    given = [(name, Path(p)) for name, p in outputs.items() if p is not None]
    sources = [Path(p) for p in inputs if p is not None]
    for name, out in given:
        if str(out) in ("-", "/dev/null") or out.is_char_device():
            continue
        for src in sources:
            bag_folder = src.is_dir() and (src / "metadata.yaml").is_file()
            inside = bag_folder and _resolved(src) in _resolved(out).parents
            if same_file(out, src) or inside:
                raise ConfigError(
                    f"{name} {out} would write over the input {src}",
                    hint="choose another output path; inputs are never overwritten",
                )
    for name, out in given:
        if name not in folders and out.is_dir():
            raise ConfigError(
                f"{name} {out} is a folder: {name} writes a file",
                hint="give the path of a file: a name inside that folder, or another name",
            )
    for i, (name, out) in enumerate(given):
        for other, path in given[i + 1 :]:
            if same_file(out, path):
                raise ConfigError(
                    f"{name} {out} and {other} {path} are the same file",
                    hint="give each output its own path",
                )


def lock_for_one_writer(fd: int) -> bool:
    """Take an exclusive lock (``flock``, released when ``fd`` is closed) on the open file
    ``fd``: False when another process holds it; True when taken, or when the system or the
    file system has no such locks (some network ones: then nothing is locked)."""
    try:
        import fcntl
    except ImportError:  # not on a POSIX system
        return True
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    except OSError:
        return True
    return True


def staging_name(path: str | Path) -> Path:
    """A hidden file beside ``path`` to write it under until it is complete (then
    ``os.replace`` gives it its name): named for this process and call alone, so that two
    runs writing one output at once never write into the same file (the last complete one
    wins), and ending in ``path``'s extension, for writers that choose the format by it."""
    import uuid

    p = Path(path)
    return p.with_name(f".{p.stem}.{os.getpid()}-{uuid.uuid4().hex[:6]}.partial{p.suffix}")


def staging_folder(target: Path) -> Path:
    """A new hidden folder beside ``target`` to assemble it in (a bag, an MCAP),
    named ``.NAME.PID-`` and a random suffix (``tempfile.mkdtemp``'s): it names this
    process, so that a later run can tell the folder of a run that was killed
    (:func:`left_by_killed_runs`).

    Raises:
        OSError: The folder cannot be made.
    """
    import tempfile

    return Path(tempfile.mkdtemp(prefix=f".{target.name}.{os.getpid()}-", dir=target.parent))


def _running(pid: int) -> bool:
    """Whether a process ``pid`` runs on this machine (unknown counts as running)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # another user's process, or no signals here
        return True
    return True


def left_by_killed_runs(target: Path) -> list[Path]:
    """The hidden folders of :func:`staging_folder` beside ``target`` whose process no
    longer runs: a run writing ``target`` that was killed outright (``kill -9``, a power
    cut) left them, with what it had written. Empty when the folder cannot be listed."""
    import re

    pattern = re.compile(rf"\.{re.escape(target.name)}\.(\d+)-[^/]*")
    try:
        entries = sorted(target.parent.iterdir())
    except OSError:
        return []
    return [
        e
        for e in entries
        if (m := pattern.fullmatch(e.name)) and e.is_dir() and not _running(int(m.group(1)))
    ]


def write_text_file(
    path: str | Path,
    text: str,
    what: str,
    error: type[LaserPeopleError] = ConfigError,
    hint: str = "choose a writable file path with -o",
) -> Path:
    """Write ``text`` to ``path`` whole: its folder is created as the other outputs' are, the
    text goes to a temporary file beside it that replaces ``path`` once written (a failed
    write leaves no half file, and an older file stays as it was).

    Args:
        what: What the file holds, for the error (``"model"``).
        error: The error class raised.
        hint: What to do, for the error.

    Raises:
        LaserPeopleError: (``error``) the file cannot be written; names it.
    """
    p = Path(path)
    tmp = staging_name(p)
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        tmp.write_text(text, encoding="utf-8")
        os.replace(tmp, p)
    except OSError as exc:
        with suppress(OSError):
            tmp.unlink(missing_ok=True)
        raise error(
            f"cannot write the {what}: {why_unwritable(exc, p)}",
            path=p,
            hint=hint,
        ) from exc
    return p
