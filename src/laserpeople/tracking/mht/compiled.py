"""Which listing of a cluster's k best children runs: the optional C extension
(``_clisting``, built by ``pip install -e .`` where a C compiler is) or the Python reference
in :mod:`~laserpeople.tracking.mht.listing`, which gives the same children and costs. The
same choice holds for the extension's other functions (a scan's clusters,
``core.components``; the occupancy grid's static time of a few positions).

The Python listing runs when the environment variable :data:`PURE_PYTHON` is set (to
anything but ``0`` or nothing), when the extension is not built, or when it is stale: built
from another ``_clisting.c`` than the one beside it (its checksum is compiled in), with a
warning that says how to rebuild it.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path
from types import ModuleType

from laserpeople.errors import LaserPeopleWarning

PURE_PYTHON = "LASERPEOPLE_PURE_PYTHON"
"""Environment variable that, set to anything but ``0`` or nothing (or ``false``, ``no``,
``off``), forces the Python listing."""

OFF_VALUES = ("", "0", "false", "no", "off")
"""Values of :data:`PURE_PYTHON` (any case, spaces round them ignored) that leave the
compiled listing on."""

ON_VALUES = ("1", "true", "yes", "on")
"""Values of :data:`PURE_PYTHON` that force the Python listing without a word; any other
value forces it too, with a warning naming the value."""


def forced_pure_python() -> bool:
    """Whether :data:`PURE_PYTHON` forces the Python listing (a value neither in
    :data:`OFF_VALUES` nor :data:`ON_VALUES` does, and a warning says so)."""
    value = os.environ.get(PURE_PYTHON, "")
    word = value.strip().lower()
    if word in OFF_VALUES:
        return False
    if word not in ON_VALUES:
        warnings.warn(
            f"{PURE_PYTHON}={value[:40]!r} is neither 1 nor 0: the pure-Python MHT listing "
            f"runs (unset it or set it to 0 for the compiled one)",
            LaserPeopleWarning,
            stacklevel=3,
        )
    return True


SOURCE = Path(__file__).with_name("_clisting.c")
"""The extension's source, beside this module (in an installed package as well)."""

REBUILD = "rebuild it with `pip install -e .` (a C compiler is needed)"


class StaleExtensionWarning(RuntimeWarning):
    """The compiled listing was built from another source than the one beside it."""


def load() -> tuple[ModuleType | None, str]:
    """The extension module, or None when the Python listing is to run, and which one runs
    (and why), as :func:`describe` says it."""
    if forced_pure_python():
        return None, f"pure Python ({PURE_PYTHON} is set)"
    try:
        from laserpeople.tracking.mht import _clisting
    except ImportError:
        return None, "pure Python (the C extension is not built)"
    built_from = getattr(_clisting, "SOURCE_HASH", "")
    if SOURCE.is_file() and built_from != source_hash(SOURCE):
        warnings.warn(
            f"the compiled MHT listing ({Path(_clisting.__file__ or '').name}) was built "
            f"from another {SOURCE.name} than the one beside it; the pure-Python listing "
            f"runs instead: {REBUILD}",
            StaleExtensionWarning,
            stacklevel=2,
        )
        return None, f"pure Python (the C extension is stale: {REBUILD})"
    module: ModuleType = _clisting
    return module, "compiled (C extension)"


def source_hash(path: Path) -> str:
    """The checksum of the file at ``path`` that setup.py compiles in: its CRC-32 and its
    length in bytes (zlib is loaded anyway; hashlib would add some 5 ms to the start-up)."""
    import zlib

    data = path.read_bytes()
    return f"{zlib.crc32(data):08x}-{len(data)}"
