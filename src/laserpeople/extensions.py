"""Loading the optional C extensions (built by ``pip install -e .`` where a C compiler is),
each with its pure-Python reference as the fallback: the MHT's listing
(:mod:`laserpeople.tracking.mht.compiled`), the segment features
(:mod:`laserpeople.detection.features`) and the Kalman steps of a scan's track nodes
(:mod:`laserpeople.tracking.kalman`).

The Python reference runs when the environment variable :data:`PURE_PYTHON` is set (to
anything but ``0`` or nothing), when the extension is not built, or when it is stale: built
from another source than the one beside it (its checksum is compiled in), with a warning
that says how to rebuild it.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path
from types import ModuleType

from laserpeople.errors import LaserPeopleWarning

PURE_PYTHON = "LASERPEOPLE_PURE_PYTHON"
"""Environment variable that, set to anything but ``0`` or nothing (or ``false``, ``no``,
``off``), forces the Python references of the C extensions."""

OFF_VALUES = ("", "0", "false", "no", "off")
"""Values of :data:`PURE_PYTHON` (any case, spaces round them ignored) that leave the
compiled code on."""

ON_VALUES = ("1", "true", "yes", "on")
"""Values of :data:`PURE_PYTHON` that force the Python references without a word; any other
value forces them too, with a warning naming the value."""

REBUILD = "rebuild it with `pip install -e .` (a C compiler is needed)"

HEADER = Path(__file__).with_name("_cbuffers.h")
"""The buffer helpers every extension's source includes; :func:`source_hash` covers it."""


class StaleExtensionWarning(RuntimeWarning):
    """A C extension was built from another source than the one beside it."""


def forced_pure_python() -> bool:
    """Whether :data:`PURE_PYTHON` forces the Python references (a value neither in
    :data:`OFF_VALUES` nor :data:`ON_VALUES` does, and a warning says so)."""
    value = os.environ.get(PURE_PYTHON, "")
    word = value.strip().lower()
    if word in OFF_VALUES:
        return False
    if word not in ON_VALUES:
        warnings.warn(
            f"{PURE_PYTHON}={value[:40]!r} is neither 1 nor 0: the pure-Python MHT listing, "
            f"segment features and Kalman steps run (unset it or set it to 0 for the compiled "
            f"ones)",
            LaserPeopleWarning,
            stacklevel=4,
        )
    return True


def load_extension(name: str, source: Path, what: str) -> tuple[ModuleType | None, str]:
    """The C extension ``name`` (a module's full name), or None when its Python reference is
    to run, and which one runs (and why): ``"compiled (C extension)"`` or ``"pure Python
    (...)"``. A stale extension (its ``SOURCE_HASH`` is not :func:`source_hash` of
    ``source``, the file beside it) is not used; a :class:`StaleExtensionWarning` names
    ``what`` it computes and how to rebuild it."""
    if forced_pure_python():
        return None, f"pure Python ({PURE_PYTHON} is set)"
    import importlib

    try:
        module: ModuleType = importlib.import_module(name)
    except ImportError:
        return None, "pure Python (the C extension is not built)"
    built_from = getattr(module, "SOURCE_HASH", "")
    if source.is_file() and built_from != source_hash(source):
        warnings.warn(
            f"the compiled {what} ({Path(module.__file__ or '').name}) was built from "
            f"another {source.name} than the one beside it; the pure-Python {what} runs "
            f"instead: {REBUILD}",
            StaleExtensionWarning,
            stacklevel=3,
        )
        return None, f"pure Python (the C extension is stale: {REBUILD})"
    return module, "compiled (C extension)"


def source_hash(path: Path) -> str:
    """The checksum that setup.py compiles in: the CRC-32 and the length in bytes of the
    file at ``path`` followed by the shared header :data:`HEADER` (so a changed header makes
    the extension stale too; zlib is loaded anyway, hashlib would add some 5 ms to the
    start-up)."""
    import zlib

    data = path.read_bytes() + (HEADER.read_bytes() if HEADER.is_file() else b"")
    return f"{zlib.crc32(data):08x}-{len(data)}"
