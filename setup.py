"""The optional C extensions: the leg MHT's listing, its clusters and the occupancy grid's
static times of a few positions; the segment features of leg detection; the Kalman steps
of a scan's track nodes (everything else is in pyproject.toml).

``pip install -e .`` builds ``laserpeople.tracking.mht._clisting``,
``laserpeople.detection._cfeatures`` and ``laserpeople.tracking._ckalman`` beside their
sources when a C compiler is there, and installs without them (the pure-Python references
run) when not. Each source's checksum, of the source followed by the buffer helpers'
header they share (CRC-32 and length, as ``laserpeople.extensions.source_hash`` computes
it), is compiled in, so that an extension built from another version of either is not used.
"""

from __future__ import annotations

import zlib
from pathlib import Path

from setuptools import Extension, setup

SOURCES = {
    "laserpeople.tracking.mht._clisting": "src/laserpeople/tracking/mht/_clisting.c",
    "laserpeople.detection._cfeatures": "src/laserpeople/detection/_cfeatures.c",
    "laserpeople.tracking._ckalman": "src/laserpeople/tracking/_ckalman.c",
}
HEADER = "src/laserpeople/_cbuffers.h"
"""The buffer helpers the sources share (``#include "../_cbuffers.h"``, from
``tracking/mht/`` ``"../../_cbuffers.h"``)."""


def _digest(source: str) -> str:
    here = Path(__file__).parent
    data = (here / source).read_bytes() + (here / HEADER).read_bytes()
    return f"{zlib.crc32(data):08x}-{len(data)}"


setup(
    ext_modules=[
        Extension(
            name,
            sources=[source],
            depends=[HEADER],
            define_macros=[("LP_SOURCE_HASH", f'"{_digest(source)}"')],
            # no fused multiply-add (aarch64 gcc contracts by default): Python's floats
            extra_compile_args=["-O2", "-ffp-contract=off", "-std=c99"],
            optional=True,
        )
        for name, source in SOURCES.items()
    ]
)
