"""Writing learned parameters as a TOML file that ``laserpeople track --config`` reads.

Only the learned keys are written, in the tracker's section (``[leg_tracker]``,
``[group_tracker]``) and its nested tables (``[leg_tracker.kalman]``), each with what it was
counted from as a comment; a header names the data and the keys that were not learned.
The file is read back with :func:`laserpeople.config.load_config` before it is kept, and
must give exactly the learned parameters.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from laserpeople.config import load_config, section_name
from laserpeople.fitting.estimates import Estimate, FitError
from laserpeople.io.paths import staging_name, why_unwritable


def check(estimates: Sequence[Estimate]) -> None:
    """Every learned value is finite and every probability (a key whose last part starts
    with ``p_``) lies in [0, 1].

    Raises:
        FitError: naming the first bad value.
    """
    for e in estimates:
        last = e.key.rsplit(".", 1)[-1]
        if not math.isfinite(e.value):
            raise FitError(f"learned {e.key} = {e.value} is not finite ({e.note})")
        if last.startswith("p_") and not 0.0 <= e.value <= 1.0:
            raise FitError(f"learned probability {e.key} = {e.value} is outside [0, 1]")


def _clean(text: str) -> str:
    return " ".join(text.split())


def render(
    params: Any,
    estimates: Sequence[Estimate],
    kept: Sequence[tuple[str, str]],
    header: Sequence[str],
) -> str:
    """The TOML text: header comments, then the learned keys by table."""
    section = section_name(type(params))
    lines = [f"# {_clean(h)}" for h in header]
    if kept:
        lines.append("# not learned (value of the tracker's defaults or --config kept):")
        lines += [f"#   {key}: {_clean(why)}" for key, why in kept]
    tables: dict[str, list[Estimate]] = {}
    for e in estimates:
        head = e.key.rpartition(".")[0]
        tables.setdefault(head, []).append(e)
    for table in sorted(tables, key=lambda t: (t != "", t)):
        lines.append("")
        lines.append(f"[{section}{'.' + table if table else ''}]")
        for e in tables[table]:
            name = e.key.rpartition(".")[2]
            lines.append(f"{name} = {e.value!r}  # {_clean(e.note)}")
    return "\n".join(lines) + "\n"


def write(
    path: Path,
    params: Any,
    estimates: Sequence[Estimate],
    kept: Sequence[tuple[str, str]],
    header: Sequence[str],
) -> None:
    """Check, write and read back the learned parameters.

    The text goes to a temporary file beside ``path`` that replaces it only once it reads
    back as ``params``.

    Raises:
        FitError: a bad value, or the file does not read back as ``params``.
    """
    check(estimates)
    text = render(params, estimates, kept, header)
    tmp = staging_name(path)
    try:
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            tmp.write_text(text, encoding="utf-8")
        except OSError as exc:
            raise FitError(
                f"cannot write the parameters: {why_unwritable(exc, path)}",
                path=path,
                hint="choose a writable file path with -o",
            ) from exc
        back = load_config(type(params), tmp)
        if back != params:
            raise FitError("the written parameters do not read back as learned", path=path)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
