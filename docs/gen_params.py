"""Generate ``docs/parameters.md``: every parameter dataclass of laserpeople, with each
parameter's default, unit, source and meaning.

Parameter classes are found, not listed: every module of the package is imported and every
dataclass defined there with at least one field declared by :func:`laserpeople.config.param`
is documented, so a new one appears on the next run. Modules that fail to import are
named on stderr (and make ``--check`` fail), never skipped silently.

Usage::

    python docs/gen_params.py            # rewrite docs/parameters.md
    python docs/gen_params.py --check    # exit 1 when the file is out of date (for CI)
    python docs/gen_params.py -o FILE    # write elsewhere
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib
import inspect
import math
import pkgutil
import sys
from pathlib import Path
from typing import Any

import laserpeople
from laserpeople.config import describe, section_name

DEFAULT_OUTPUT = Path(__file__).resolve().parent / "parameters.md"


def iter_modules(package: Any = laserpeople) -> tuple[list[str], list[tuple[str, str]]]:
    """Names of every module of ``package`` that imports, and ``(name, error)`` for the rest."""
    ok: list[str] = [package.__name__]
    failed: list[tuple[str, str]] = []
    for info in pkgutil.walk_packages(package.__path__, prefix=package.__name__ + "."):
        try:
            importlib.import_module(info.name)
        except Exception as exc:  # any import failure is reported, none hidden
            failed.append((info.name, f"{type(exc).__name__}: {exc}"))
            continue
        ok.append(info.name)
    return ok, failed


def is_param_class(obj: Any) -> bool:
    """A dataclass type with at least one field declared by ``config.param``."""
    return (
        inspect.isclass(obj)
        and dataclasses.is_dataclass(obj)
        and any("source" in f.metadata for f in dataclasses.fields(obj))
    )


def param_classes(modules: list[str]) -> list[type]:
    """Parameter classes defined in ``modules`` (each once, where it is defined), by module
    and name."""
    found: dict[str, type] = {}
    for name in modules:
        mod = sys.modules[name]
        for obj in vars(mod).values():
            if is_param_class(obj) and obj.__module__ == name:
                found[f"{obj.__module__}.{obj.__qualname__}"] = obj
    return [found[k] for k in sorted(found)]


def format_value(value: Any) -> str:
    """A default as it would be written in TOML, in backticks."""
    if isinstance(value, bool):
        text = "true" if value else "false"
    elif isinstance(value, float):
        text = "inf" if math.isinf(value) and value > 0 else repr(value)
    elif isinstance(value, str):
        text = f'"{value}"'
    elif value is None:
        return "unset"
    elif isinstance(value, tuple | list):
        text = "[" + ", ".join(format_value(v).strip("`") for v in value) + "]"
    else:
        text = repr(value)
    return f"`{text}`"


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ").strip()


def anchor(cls: type) -> str:
    """The page anchor of a parameter class's section (its TOML section name)."""
    return "sec-" + section_name(cls).replace("_", "-")


def class_section(cls: type) -> str:
    """The markdown section of one parameter class."""
    doc = inspect.getdoc(cls) or ""
    summary = doc.split("\n\n")[0].replace("\n", " ")
    lines = [
        f"## `[{section_name(cls)}]` — {cls.__name__} {{ #{anchor(cls)} }}",
        "",
        f"`{cls.__module__}.{cls.__qualname__}`" + (f": {summary}" if summary else ""),
        "",
    ]
    try:
        rows = describe(cls)
    except TypeError as exc:  # a class without defaults for every field
        lines += [f"(cannot list defaults: {exc})", ""]
        return "\n".join(lines)
    lines += [
        "| parameter | default | unit | source | meaning |",
        "|---|---|---|---|---|",
    ]
    for name, value, unit, source, text in rows:
        lines.append(
            f"| `{name}` | {_cell(format_value(value))} | {_cell(unit)} | {_cell(source)} | "
            f"{_cell(text)} |"
        )
    lines.append("")
    return "\n".join(lines)


def print_config_sections(tracker: str) -> list[str]:
    """The TOML sections ``laserpeople track --tracker NAME --print-config`` prints, in its
    order: exactly what that tracker's run reads from ``--config``."""
    from typer.testing import CliRunner

    from laserpeople.cli import app

    result = CliRunner().invoke(app, ["track", "--tracker", tracker, "--print-config"])
    if result.exit_code != 0:
        raise RuntimeError(f"track --tracker {tracker} --print-config failed: {result.output}")
    return [
        line.strip()[1:-1]
        for line in result.output.splitlines()
        if line.startswith("[") and line.strip().endswith("]") and "." not in line
    ]


def tracker_sections() -> list[tuple[str, str, list[str]]]:
    """``(name, description, sections)`` of every registered tracker."""
    from laserpeople.tracking import registry

    return [
        (name, entry.description, print_config_sections(name))
        for name, entry in registry.TRACKERS.items()  # registry order: the default first
    ]


def render_markdown(
    classes: list[type], trackers: list[tuple[str, str, list[str]]] | None = None
) -> str:
    """The whole parameter reference: per tracker, the sections its run reads (linked),
    then one section per parameter class, those a tracker reads first."""
    if trackers is None:
        trackers = tracker_sections()
    by_section = {section_name(c): c for c in classes}
    read = list(dict.fromkeys(s for _, _, sections in trackers for s in sections))
    head = [
        "# Parameter reference",
        "",
        "Generated by `python docs/gen_params.py` from the parameter dataclasses; do not edit",
        "by hand. Every default names its source: a paper (000 Arras et al., 002 Kräußling",
        "et al., 004 Schenk et al.) with its section or equation, a measurement with the page",
        "that shows it, or an assumption. How to write a configuration file:",
        "[Configuration](configuration.md).",
        "",
        "## By tracker",
        "",
        "What `laserpeople track --tracker NAME --config FILE` reads, as",
        "`track --tracker NAME --print-config` prints it, with the number of settings in each",
        "section. The tracker's own section comes first.",
        "",
    ]
    for name, description, sections in trackers:
        links = ", ".join(
            f"[`[{s}]`](#{anchor(by_section[s])}) ({len(describe(by_section[s]))})"
            if s in by_section
            else f"`[{s}]`"
            for s in sections
        )
        total = sum(len(describe(by_section[s])) for s in sections if s in by_section)
        head += [
            f"### `{name}` {{ #tracker-{name} }}",
            "",
            f"{description[:1].upper()}{description[1:]}.",
            "",
            f"Reads (settings in each, {total} in all): {links}.",
            "",
        ]
    rest = [c for c in classes if section_name(c) not in read]
    head += [
        "",
        "Sections no tracker run reads are the defaults of library components: set them from",
        "Python (`dataclasses.replace(Params(), name=value)`) or, where a command has one, with",
        "its option (e.g. `evaluate --gate`): "
        + ", ".join(f"[`[{section_name(c)}]`](#{anchor(c)})" for c in rest)
        + ".",
        "",
    ]
    ordered = [by_section[s] for s in read if s in by_section] + rest
    return "\n".join(head) + "\n" + "\n".join(class_section(c) for c in ordered)


def main(argv: list[str] | None = None) -> int:
    """Command-line entry; returns the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-o", "--output", type=Path, default=DEFAULT_OUTPUT)
    parser.add_argument("--check", action="store_true", help="fail when the file is stale")
    args = parser.parse_args(argv)
    modules, failed = iter_modules()
    for name, error in failed:
        print(f"warning: could not import {name}: {error}", file=sys.stderr)
    classes = param_classes(modules)
    text = render_markdown(classes)
    if args.check:
        current = args.output.read_text(encoding="utf-8") if args.output.exists() else ""
        if current != text or failed:
            print(f"{args.output} is out of date: run python docs/gen_params.py", file=sys.stderr)
            return 1
        return 0
    args.output.write_text(text, encoding="utf-8")
    print(f"wrote {args.output}: {len(classes)} parameter classes", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
