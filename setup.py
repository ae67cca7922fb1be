"""The optional C extension of the leg MHT's listing, its clusters and the occupancy grid's
static times of a few positions (everything else is in pyproject.toml).

``pip install -e .`` builds ``laserpeople.tracking.mht._clisting`` beside its source when a C
compiler is there, and installs without it (the pure-Python listing runs) when not. The
source's checksum (CRC-32 and length, as ``laserpeople.tracking.mht.compiled.source_hash``
computes it) is compiled in, so that an extension built from another version of the source
is not used.
"""

from __future__ import annotations

import zlib
from pathlib import Path

from setuptools import Extension, setup

SOURCE = "src/laserpeople/tracking/mht/_clisting.c"
DATA = (Path(__file__).parent / SOURCE).read_bytes()
DIGEST = f"{zlib.crc32(DATA):08x}-{len(DATA)}"

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
