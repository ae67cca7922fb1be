"""The optional C extension of the leg MHT's listing (everything else is in pyproject.toml).

``pip install -e .`` builds ``laserpeople.tracking.mht._clisting`` beside its source when a C
compiler is there, and installs without it (the pure-Python listing runs) when not. The
source's SHA-256 is compiled in, so that an extension built from another version of the
source is not used (``laserpeople.tracking.mht.compiled``).
"""

from __future__ import annotations

import hashlib
from pathlib import Path

from setuptools import Extension, setup

SOURCE = "src/laserpeople/tracking/mht/_clisting.c"
DIGEST = hashlib.sha256((Path(__file__).parent / SOURCE).read_bytes()).hexdigest()

setup(
    ext_modules=[
        Extension(
            "laserpeople.tracking.mht._clisting",
            sources=[SOURCE],
            define_macros=[("LP_SOURCE_HASH", f'"{DIGEST}"')],
            # no fused multiply-add (aarch64 gcc contracts by default): Python's floats
            extra_compile_args=["-O2", "-ffp-contract=off", "-std=c99"],
            optional=True,
        )
    ]
)
