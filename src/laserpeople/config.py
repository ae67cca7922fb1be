"""Parameters as frozen dataclasses, with their source and unit, loadable from TOML.

Declare a parameter with :func:`param` so that ``--print-config`` and the generated
parameter reference can say where its default comes from::

    @dataclass(frozen=True)
    class LegTrackerParams:
        p_occ_approved: float = param(0.79, "000 Table 10", "P(occluded | approved track)")

A TOML file sets parameters by section, the section named by the dataclass's
``config_section`` class attribute (or its snake-cased class name)::

    [leg_tracker]
    p_occ_approved = 0.8
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, TypeVar, get_type_hints

from laserpeople.citations import cite
from laserpeople.errors import ConfigError, LaserPeopleError
from laserpeople.spelling import did_you_mean

T = TypeVar("T")


def param(default: Any, source: str, doc: str, unit: str = "") -> Any:
    """A dataclass field with a default, the source of that default, a description and unit."""
    meta = {"source": source, "doc": doc, "unit": unit}
    if isinstance(default, list | dict | set):
        raise TypeError("use tuples or nested frozen dataclasses for parameter defaults")
    if dataclasses.is_dataclass(default) and not isinstance(default, type):
        return dataclasses.field(default_factory=lambda: default, metadata=meta)
    return dataclasses.field(default=default, metadata=meta)


def section_name(cls: type) -> str:
    """The TOML section of a parameter class."""
    explicit = getattr(cls, "config_section", None)
    if isinstance(explicit, str):
        return explicit
    name = cls.__name__.removesuffix("Params").removesuffix("Config")
    return re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()


def dotted_names(cls: type) -> list[str]:
    """The parameters of ``cls`` as a config file names them in its section: fields, and
    the fields of nested tables with their prefix (``people.gate_probability``)."""
    names = []
    hints = get_type_hints(cls)
    for f in dataclasses.fields(cls):
        names.append(f.name)
        if dataclasses.is_dataclass(hints[f.name]):
            names.extend(f"{f.name}.{n}" for n in dotted_names(hints[f.name]))
    return names


def from_mapping(
    cls: type[T], values: Mapping[str, Any], *, where: str = "", within: str = ""
) -> T:
    """Build ``cls`` from its defaults overridden by ``values``; unknown keys are errors.
    ``within``: the section and dotted prefix a nested table is read under (errors name
    ``[leg_tracker] people.gate_probability``, as the file writes it)."""
    if not dataclasses.is_dataclass(cls):
        raise TypeError(f"{cls!r} is not a dataclass")
    fields = {f.name: f for f in dataclasses.fields(cls)}
    hints = get_type_hints(cls)
    section = within or f"[{section_name(cls)}] "
    table = section.strip().rstrip(".")  # "[leg_tracker]", "[leg_tracker] people"
    _refuse_unknown([cls], values, where, section)
    kwargs: dict[str, Any] = {}
    for key, value in values.items():
        hint = hints[key]
        if dataclasses.is_dataclass(hint):
            if not isinstance(value, Mapping):
                raise ConfigError(
                    f"{_at(where, f'{section}{key}')}{section}{key} = {_shown(value)} must be "
                    "a table of parameters "
                    f"([{section_name(cls)}.{key}])",
                    path=where or None,
                )
            kwargs[key] = from_mapping(hint, value, where=where, within=f"{section}{key}.")  # type: ignore[arg-type]
            continue
        default = getattr(cls(), key) if _has_defaults(cls) else None
        name = f"{section}{key}"
        # (a meaning that says what "inf:" does admits it; otherwise only an infinite default)
        infinite = INFINITE_MARK in fields[key].metadata.get("doc", "")
        kwargs[key] = _coerce(name, value, default, where, infinite=infinite)
        _check_range(key, name, kwargs[key], default, fields[key].metadata.get("unit", ""), where)
    try:
        return cls(**kwargs)
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"{table}: {exc}", path=where or None) from exc
    except ConfigError:
        raise
    except LaserPeopleError as exc:  # a parameter class's own check (e.g. bin_width)
        raise ConfigError(f"{table}: {exc.detail}", path=where or None, hint=exc.hint) from exc


def _refuse_unknown(
    classes: Sequence[type], values: Mapping[str, Any], where: str, section: str
) -> None:
    """Refuse the keys of ``values`` (the table ``section`` of the file ``where``) that no
    class of ``classes`` reads, naming them and the names meant.

    Raises:
        ConfigError: names the first key's line, every unknown key and the known ones.
    """
    fields = {f.name for cls in classes for f in dataclasses.fields(cls)}
    unknown = sorted(set(values) - fields)
    if not unknown:
        return
    named = [n for cls in classes for n in dotted_names(cls)]
    guesses = "".join(f"; {u}: {g}" for u in unknown if (g := did_you_mean(u, named)))
    table = section.strip().rstrip(".")
    raise ConfigError(
        f"{_at(where, f'{section}{unknown[0]}')}unknown parameter(s) {', '.join(unknown)} "
        f"in {table}{guesses}",
        path=where or None,
        hint=f"known: {', '.join(sorted(fields))}",
    )


def check_names(classes: Sequence[type], values: Mapping[str, Any], where: str) -> None:
    """Refuse the keys of a section (``values``) that none of ``classes`` (the parameter
    classes that read it) reads, nested tables included, without checking the values: the
    section of another command or tracker in a shared ``--config`` file.

    Raises:
        ConfigError: as :func:`from_mapping` names an unknown key.
    """
    section = f"[{section_name(classes[0])}] "
    _refuse_unknown(classes, values, where, section)
    if len(classes) > 1:
        return
    hints = get_type_hints(classes[0])
    for key, value in values.items():
        if dataclasses.is_dataclass(hints[key]) and isinstance(value, Mapping):
            nested: type = hints[key]
            _refuse_unknown([nested], value, where, f"{section}{key}.")


def _has_defaults(cls: type) -> bool:
    return all(
        f.default is not dataclasses.MISSING or f.default_factory is not dataclasses.MISSING
        for f in dataclasses.fields(cls)
    )


def _coerce(name: str, value: Any, default: Any, where: str, *, infinite: bool = False) -> Any:
    """``value`` as the type of ``default``; ``name`` is the parameter as errors show it;
    ``infinite``: +inf is a value of the parameter (:data:`INFINITE_MARK`)."""
    if isinstance(default, bool):
        ok = isinstance(value, bool)
    elif isinstance(default, int):
        ok = isinstance(value, int) and not isinstance(value, bool)
    elif isinstance(default, float):
        ok = isinstance(value, int | float) and not isinstance(value, bool)
        value = float(value) if ok else value
    elif isinstance(default, tuple):
        ok = isinstance(value, list | tuple)
        value = tuple(value) if ok else value
    elif isinstance(default, str):
        ok = isinstance(value, str)
    else:
        ok = True
    if not ok:
        raise ConfigError(
            f"{_at(where, name)}{name} = {_shown(value)} has the wrong type ({_kind(value)}): "
            f"expected {WANTED.get(type(default), type(default).__name__)} like the default "
            f"{_toml_value(default)}",
            path=where or None,
        )
    _check_number(name, value, default, where, infinite=infinite)
    return value


WANTED: dict[type, str] = {
    bool: "true or false",
    int: "an integer",
    float: "a number",
    str: "text in quotes",
    tuple: "a list",
}
"""What a value of a parameter whose default has this type must be, in TOML's words."""


def _kind(value: Any) -> str:
    """What a TOML value read by ``tomllib`` is, in TOML's words (a quoted "1.5" is text)."""
    if isinstance(value, bool):
        return "true or false"
    if isinstance(value, str):
        return "text"
    if isinstance(value, Mapping):
        return "a table"
    if isinstance(value, list | tuple):
        return "a list"
    if isinstance(value, int):
        return "an integer"
    if isinstance(value, float):
        return "a number"
    return type(value).__name__  # a date or time


def _shown(value: Any) -> str:
    """``value`` as the file writes it (TOML: ``true``, ``"fast"``), at most 60 characters."""
    text = "{...}" if isinstance(value, Mapping) else _toml_value(value)
    return text if len(text) <= 60 else text[:57] + "..."


TABLE_LINE = re.compile(r"\s*\[\s*([^\[\]]+?)\s*\](\s*#.*)?\s*$")
"""A TOML table header ``[a.b]`` (not an array of tables ``[[a]]``)."""

KEY_LINE = re.compile(r"\s*([A-Za-z0-9_\-.\"' ]+?)\s*=")
"""The key of a TOML ``key = value`` line (bare, dotted or quoted)."""


def _split_key(text: str) -> list[str]:
    return [part.strip().strip("\"'") for part in text.split(".")]


def key_line(path: Path, keys: Sequence[str]) -> int | None:
    """The line (1-based) of the TOML file ``path`` that sets the dotted key ``keys``
    (``["leg_tracker", "people", "static_legs"]``): its ``key = value`` line under its
    table, a dotted key under a table above it, or the inline table or header holding it.
    None when no line is found (a value from a preset, an unreadable file)."""
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError):
        return None
    target = list(keys)
    table: list[str] = []
    for number, line in enumerate(text.splitlines(), start=1):
        if header := TABLE_LINE.match(line):
            table = _split_key(header.group(1))
            if table == target:
                return number
            continue
        if key := KEY_LINE.match(line):
            full = table + _split_key(key.group(1))
            if len(full) <= len(target) and full == target[: len(full)]:
                return number
    return None


def _at(where: str, name: str) -> str:
    """``"line N: "`` for the parameter ``name`` as errors show it (``[leg_tracker]
    people.gate_probability``, ``[x] y[2]``) in the config file ``where``; empty when
    ``where`` is no file or the line is not found."""
    named = re.fullmatch(r"\[([^\]]+)\]\s*(.*?)(\[\d+\])?", name.strip().rstrip("."))
    if not where or named is None or not Path(where).is_file():
        return ""
    keys = _split_key(named.group(1)) + (_split_key(named.group(2)) if named.group(2) else [])
    number = key_line(Path(where), keys)
    return f"line {number}: " if number is not None else ""


INT_LIMIT = 2**53
"""Largest magnitude of an integer parameter (beyond it no count or size makes sense)."""


INFINITE_MARK = "inf:"
"""A parameter whose meaning (its ``doc``) says what ``inf:`` does takes +inf from a file
(``max_leg_separation``: "inf: 000's rule only"); others only where the default is."""


def _check_number(
    name: str, value: Any, default: Any, where: str, *, infinite: bool = False
) -> None:
    """NaN is never a parameter value; infinity only where the default is infinite, or +inf
    where ``infinite`` (:data:`INFINITE_MARK`); integers stay below :data:`INT_LIMIT` in
    magnitude. Elements of tuples are checked alike."""
    if isinstance(value, tuple):
        for i, v in enumerate(value):
            d = default[i] if isinstance(default, tuple) and i < len(default) else None
            _check_number(f"{name}[{i}]", v, d if d is not None else 0.0, where)
        return
    problem = None
    if isinstance(value, float):
        if math.isnan(value):
            problem = "is NaN"
        elif math.isinf(value) and not (
            (isinstance(default, float) and default == value) or (infinite and value > 0)
        ):
            problem = "is infinite"
    elif isinstance(value, int) and not isinstance(value, bool) and abs(value) > INT_LIMIT:
        problem = f"is larger than {INT_LIMIT}"
    if problem:
        raise ConfigError(
            f"{_at(where, name)}{name} {problem}",
            path=where or None,
            hint=f"give a finite number like the default {default!r}",
        )


SIGNED_UNITS = frozenset({"log-likelihood"})
"""Units of parameters that may be negative; every other unit (metres, seconds, m/s, beams,
people, ...) is a magnitude, a duration or a count, which is never negative."""

SIGNED_SUFFIXES = ("_bias",)
"""Names of parameters that may be negative whatever their unit: a bias or drift goes
either way (``[odometry] heading_bias`` in rad/m)."""


def _check_range(key: str, name: str, value: Any, default: Any, unit: str, where: str) -> None:
    """A value outside what its kind of parameter can mean: a probability (``p_*``,
    ``*probability``) outside [0, 1] (a gate's below 1: a gate of probability 1 is
    infinite); a negative value of a parameter with a physical unit, or of an integer (all
    of them counts), whose default is not negative (a bias, :data:`SIGNED_SUFFIXES`, may be)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return
    problem = ""
    if key.startswith("p_") or key.endswith("probability"):
        if key.endswith("gate_probability") and not value < 1.0:
            problem = "must be below 1 (a gate of probability 1 is infinite)"
        elif not 0.0 <= value <= 1.0:
            problem = "is a probability: it must be in [0, 1]"
    elif (
        value < 0
        and isinstance(default, int | float)
        and default >= 0
        and (isinstance(default, int) or (unit and unit not in SIGNED_UNITS))
        and not key.endswith(SIGNED_SUFFIXES)
    ):
        what = f"in {unit}" if unit else "a count"
        problem = f"is {what}: it cannot be negative"
    if problem:
        raise ConfigError(
            f"{_at(where, name)}{name} = {value!r} {problem}",
            path=where or None,
            hint=f"the default is {default!r}" + (f" {unit}" if unit else ""),
        )


PRESETS = ("paper",)
"""Names ``load_config`` takes as ``preset``: "paper" gives each tracker the papers'
behaviour (each parameter class's ``paper_preset`` values; docs/papers.md)."""


def preset_values(cls: type, preset: str | None) -> dict[str, Any]:
    """The values ``preset`` sets in ``cls``'s section (empty for None, or for a class
    that departs from no paper)."""
    if preset is None:
        return {}
    if preset not in PRESETS:
        raise ConfigError(
            f"unknown preset {preset!r}{did_you_mean(preset, PRESETS, lead=': ')}",
            hint=f"use one of {', '.join(PRESETS)} (docs/papers.md)",
        )
    return dict(getattr(cls, "paper_preset", {}))


def load_config(cls: type[T], path: str | Path | None, preset: str | None = None) -> T:
    """Read ``cls``'s section from a TOML file; missing file section means all defaults.
    With ``preset`` ("paper") the preset's values replace the defaults, and the file's
    section is read over them."""
    base = preset_values(cls, preset)
    if path is None:
        return from_mapping(cls, base) if base else cls()
    p = Path(path)
    data = read_toml(p)
    section = data.get(section_name(cls), {})
    if not isinstance(section, Mapping):
        name = f"[{section_name(cls)}]"
        raise ConfigError(f"{_at(str(p), name)}{name} must be a table", path=p)
    return from_mapping(cls, merged(base, section), where=str(p))


def merged(base: Mapping[str, Any], values: Mapping[str, Any]) -> dict[str, Any]:
    """``base`` with ``values`` over it; a nested table (both sides mappings) merged key by
    key, so that a file setting one key of ``[x.mht]`` keeps the preset's others."""
    out = dict(base)
    for key, value in values.items():
        old = out.get(key)
        if isinstance(old, Mapping) and isinstance(value, Mapping):
            out[key] = merged(old, value)
        else:
            out[key] = value
    return out


def check_sections(
    path: str | Path | None, classes: Sequence[type], others: Sequence[type] = ()
) -> list[str]:
    """Raise if the TOML file has a top-level section none of ``classes`` reads.

    A command that reads several parameter classes from one ``--config`` file calls this
    once, so a misspelt section (``[leg_trackr]``) is an error instead of being ignored.
    Sections of ``others`` (parameters other commands or trackers read) are allowed, so
    one file can serve every command; they are returned, for the command to say that it
    ignores them.
    """
    if path is None:
        return []
    p = Path(path)
    known = {section_name(c) for c in classes}
    data = read_toml(p)
    elsewhere = {section_name(c) for c in others} - known
    unknown = sorted(set(data) - known - elsewhere)
    loose = [u for u in unknown if not isinstance(data[u], Mapping)]
    if loose:  # `p_det = 0.9` above every [section]
        owners = {f"{section_name(c)}.{n}" for c in (*classes, *others) for n in dotted_names(c)}
        guesses = "".join(f"; {u}: {g}" for u in loose if (g := did_you_mean(u, sorted(owners))))
        raise ConfigError(
            f"{_at(str(p), f'[{loose[0]}]')}{', '.join(loose)} outside any [section]{guesses}",
            path=p,
            hint="write each parameter under the [section] of its class (docs/parameters.md)",
        )
    if unknown:
        guesses = "".join(
            f"; [{u}]: {g}" for u in unknown if (g := did_you_mean(u, sorted(known | elsewhere)))
        )
        raise ConfigError(
            f"{_at(str(p), f'[{unknown[0]}]')}unknown section(s) "
            f"{', '.join(f'[{u}]' for u in unknown)}{guesses}",
            path=p,
            hint=f"this command reads {', '.join(f'[{k}]' for k in sorted(known))}",
        )
    readers: dict[str, list[type]] = {}
    for cls in others:
        readers.setdefault(section_name(cls), []).append(cls)
    for name in sorted(set(data) & elsewhere):  # (misspelt names there are errors too)
        if isinstance(data[name], Mapping):
            try:
                check_names(readers[name], data[name], str(p))
            except ConfigError as exc:
                raise ConfigError(
                    f"{exc.detail} (a section another command or tracker reads: its names "
                    "are checked all the same)",
                    path=p,
                    hint=exc.hint,
                ) from None
    return sorted(set(data) & elsewhere)


TOML_LIMIT = 1 * 2**20
"""Largest config file [bytes] that is read."""
TOML_DEPTH = 32
"""Deepest nesting (arrays, inline tables, dotted key parts) a config file may have."""


def _precheck_toml(text: str, p: Path) -> None:
    """Refuse files that would make the TOML parser recurse deeply or run for minutes
    (tomllib takes quadratic time in the number of dotted key parts)."""
    if len(text) > TOML_LIMIT:
        raise ConfigError(f"config file is larger than {TOML_LIMIT} bytes", path=p)
    depth = deepest = 0
    for line in text.splitlines():
        stripped = line.strip()
        if stripped.startswith("#"):
            continue
        key = stripped.split("=", 1)[0] if "=" in stripped else stripped
        if key.count(".") > TOML_DEPTH:
            raise ConfigError(
                f"a key has more than {TOML_DEPTH} dotted parts: {key[:40]!r}...", path=p
            )
        for ch in line:
            if ch in "[{":
                depth += 1
                deepest = max(deepest, depth)
            elif ch in "]}":
                depth = max(depth - 1, 0)
        if stripped.startswith("[") and not stripped.startswith("[["):
            depth = 0  # a table header closes on its own line
    if deepest > TOML_DEPTH:
        raise ConfigError(
            f"arrays or inline tables nest {deepest} deep (at most {TOML_DEPTH})",
            path=p,
            hint="parameters are numbers, strings or short lists",
        )


def read_toml(p: Path, what: str = "config file") -> dict[str, Any]:
    """The tables of the TOML file ``p`` (a ``what``: ``"config file"``, ``"mounts file"``),
    within the size and nesting bounds; a byte order mark before the text (an editor's
    "UTF-8 with BOM") is left out.

    Raises:
        ConfigError: the file is missing, a folder, not UTF-8 text, not TOML, too large or
            nested too deeply; names the file.
    """
    import tomllib  # (at use: its regular expressions cost every start-up ~5 % of `--help`)

    try:
        text = p.read_text(encoding="utf-8").removeprefix("\ufeff")
        _precheck_toml(text, p)
        return tomllib.loads(text)
    except FileNotFoundError as exc:
        raise ConfigError(f"{what} not found", path=p) from exc
    except IsADirectoryError as exc:
        raise ConfigError(f"is a directory, not a TOML {what}", path=p) from exc
    except UnicodeDecodeError as exc:
        if p.suffix.lower() in _BINARY_FORMATS:  # a recording or picture given in its place
            raise ConfigError(
                f"a {p.suffix} file, not a TOML {what}",
                path=p,
                hint="give the TOML file of parameters (`laserpeople track --print-config` "
                "shows them)",
            ) from exc
        raise ConfigError(
            f"not UTF-8 text (byte {exc.start} is not UTF-8)",
            path=p,
            hint="save it as UTF-8 text",
        ) from exc
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"not valid TOML: {exc}", path=p) from exc
    except RecursionError as exc:
        raise ConfigError("nested too deeply to read", path=p) from exc
    except OSError as exc:
        raise ConfigError(f"cannot read the {what}: {exc.strerror or exc}", path=p) from exc


_BINARY_FORMATS = frozenset({".bag", ".mcap", ".db3", ".npz", ".parquet", ".png", ".gif", ".mp4"})
"""Extensions of files (recordings, tables, pictures) given where a TOML file goes."""


SOURCE_LENGTH = 80
"""Longest source shown as it is written (``--print-config``, docs/parameters.md)."""
_PAPER = re.compile(
    r"^(?:000|002|004)(?: (?:Sec\.|Table|Fig\.|Figs\.|eqs?\.|Exp\.) ?[\w.\-]+(?:[,/] ?[\w.\-]+)*)?"
)
_DOCS_PAGE = re.compile(r"docs/[\w./-]+\.md")


def short_source(source: str) -> str:
    """The one line shown for a parameter's source: the paper and its section or equation
    (``000 Table 10``), a measurement with its docs page (``measured: docs/groups.md``), a
    reference to another setting (``as PersonParams.max_spread``), or ``assumption``. A
    source of at most :data:`SOURCE_LENGTH` characters that names no issue or session is
    shown as written; the full text stays in the parameter's metadata (the rationale)."""
    text = " ".join(source.split())
    lower = text.lower()
    if len(text) <= SOURCE_LENGTH and "issue" not in lower and "session" not in lower:
        return text
    page = _DOCS_PAGE.search(text)
    paper = _PAPER.match(text)
    if lower.startswith("unset"):
        return "unset: the tracker's default (see the setting's meaning)"
    if lower.startswith("departure from "):
        return text[: len("departure from 000")] + (f"; measured: {page.group(0)}" if page else "")
    if lower.startswith("as "):
        return re.split(r" \(|:|;", text, maxsplit=1)[0]
    if paper and not lower.startswith(("000 (", "002 (", "004 (")):
        return paper.group(0)
    if page and ("measured" in lower or "issue" in lower or "session" in lower):
        return f"measured: {page.group(0)}"
    if lower.startswith(("assum", "extension")) or "assumption" in lower[:40]:
        return "assumption" + (f"; measured: {page.group(0)}" if page else "")
    if paper:  # "000 (0: off ...)": the paper's value, changed by a measurement
        return paper.group(0) + (f"; measured: {page.group(0)}" if page else "")
    if page:
        return f"measured: {page.group(0)}"
    return "measured" if "measured" in lower or "issue" in lower else "assumption"


def describe(obj_or_cls: Any) -> list[tuple[str, Any, str, str, str]]:
    """Rows ``(name, value, unit, source, doc)`` for every parameter (nested ones dotted);
    the source as :func:`short_source` shows it."""
    obj = obj_or_cls() if isinstance(obj_or_cls, type) else obj_or_cls
    rows: list[tuple[str, Any, str, str, str]] = []
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if dataclasses.is_dataclass(value) and not isinstance(value, type):
            rows.extend((f"{f.name}.{n}", v, u, s, d) for n, v, u, s, d in describe(value))
            continue
        rows.append(
            (
                f.name,
                value,
                f.metadata.get("unit", ""),
                short_source(f.metadata.get("source", "")),
                f.metadata.get("doc", ""),
            )
        )
    return rows


def origins(obj: Any, path: str | Path | None, preset: str | None = None) -> dict[str, str]:
    """Where each parameter of ``obj`` (as :func:`load_config` read it from ``path`` over
    ``preset``) that is not its default came from, with the default: ``{name: "from
    my.toml (default 6.0)"}``; parameters at their default are absent."""
    cls = type(obj)
    default = {name: value for name, value, *_ in describe(cls)}
    start = {name: value for name, value, *_ in describe(load_config(cls, None, preset))}
    where = Path(path).name if path is not None else ""
    out: dict[str, str] = {}
    for name, value, *_ in describe(obj):
        if value == default[name]:
            continue
        by = f"from {where}" if value != start[name] else f"from --preset {preset}"
        out[name] = f"{by} (default {_toml_value(default[name])})"
    return out


def to_toml(obj: Any, origin: Mapping[str, str] | None = None) -> str:
    """The parameters of ``obj`` as a TOML section with their sources as comments (papers
    named by their authors, :func:`laserpeople.citations.cite`); ``origin`` (see
    :func:`origins`) leads the comment of the values that are not the defaults."""
    lines = [f"[{section_name(type(obj))}]"]
    for name, value, unit, source, doc in describe(obj):
        first = (origin or {}).get(name, "")
        comment = cite("; ".join(x for x in (first, doc, f"[{unit}]" if unit else "", source) if x))
        if value is None:  # unset (TOML has no null): the line says so, as a comment
            lines.append(f"# {name} unset" + (f"  # {comment}" if comment else ""))
            continue
        lines.append(f"{name} = {_toml_value(value)}" + (f"  # {comment}" if comment else ""))
    return "\n".join(lines) + "\n"


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, tuple | list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, float) and value == float("inf"):
        return "inf"
    return repr(value)
