"""Which listing of a cluster's k best children runs: the optional C extension
(``_clisting``, built by ``pip install -e .`` where a C compiler is) or the Python reference
in :mod:`~laserpeople.tracking.mht.listing`, which gives the same children and costs. The
same choice holds for the extension's other functions (a scan's clusters,
``core.components``; the occupancy grid's static time of a few positions).

The Python listing runs when the environment variable :data:`PURE_PYTHON` is set (to
anything but ``0`` or nothing), when the extension is not built, or when it is stale: built
from another ``_clisting.c`` than the one beside it (its checksum is compiled in), with a
warning that says how to rebuild it (:mod:`laserpeople.extensions`).
"""

from __future__ import annotations

from pathlib import Path
from types import ModuleType

from laserpeople.extensions import (
    OFF_VALUES,
    ON_VALUES,
    PURE_PYTHON,
    REBUILD,
    StaleExtensionWarning,
    forced_pure_python,
    load_extension,
    source_hash,
)

__all__ = [
    "OFF_VALUES",
    "ON_VALUES",
    "PURE_PYTHON",
    "REBUILD",
    "SOURCE",
    "StaleExtensionWarning",
    "forced_pure_python",
    "load",
    "source_hash",
]

SOURCE = Path(__file__).with_name("_clisting.c")
"""The extension's source, beside this module (in an installed package as well)."""


def load() -> tuple[ModuleType | None, str]:
    """The extension module, or None when the Python listing is to run, and which one runs
    (and why): ``"compiled (C extension)"`` or ``"pure Python (...)"``."""
    return load_extension("laserpeople.tracking.mht._clisting", SOURCE, "MHT listing")
