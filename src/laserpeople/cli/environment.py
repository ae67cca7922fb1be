"""The environment variables ``laserpeople`` reads, and a word on a misspelt one.

A variable named ``LASERPEOPLE_...`` that the program does not read (``LASERPEOPLE_PURE_PYHTON=1``)
would otherwise change nothing without a word; every command warns of it, naming the
variables that are read.
"""

from __future__ import annotations

from collections.abc import Mapping

from laserpeople.extensions import PURE_PYTHON
from laserpeople.spelling import did_you_mean

PREFIX = "LASERPEOPLE_"
"""The prefix of the program's environment variables."""

KNOWN = (PURE_PYTHON, "LASERPEOPLE_SHARED_DATA")
"""The variables read: :data:`~laserpeople.extensions.PURE_PYTHON` (the Python references
of the C extensions) and ``LASERPEOPLE_SHARED_DATA`` (the real recordings the shipped leg
model is trained on, ``laserpeople.detection.default_training``)."""


def unknown_variables(environ: Mapping[str, str]) -> list[str]:
    """One warning line per variable of ``environ`` named ``LASERPEOPLE_...`` that is not
    one of :data:`KNOWN` (case counts: ``laserpeople_pure_python`` is not read either)."""
    lines = []
    for name in sorted(environ):
        if not name.upper().startswith(PREFIX) or name in KNOWN:
            continue
        guess = did_you_mean(name.upper(), KNOWN)
        lines.append(
            f"the environment variable {name} is not read by laserpeople"
            + (f" ({guess})" if guess else "")
            + f"; it reads {' and '.join(KNOWN)}"
        )
    return lines


__all__ = ["KNOWN", "PREFIX", "unknown_variables"]
