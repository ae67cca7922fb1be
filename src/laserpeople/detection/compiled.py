"""Which leg-detection code runs: the optional C extension ``_cfeatures`` (built by
``pip install -e .`` where a C compiler is: the segment features of
:mod:`~laserpeople.detection.features`, the AdaBoost margins of
:mod:`~laserpeople.detection.adaboost`, a scan's validity and points
(:class:`~laserpeople.scan.Scan`), a block's segments
(:mod:`~laserpeople.segmentation`) and sparse legs (:mod:`~laserpeople.detection.sparse`),
the same floats and decisions) or their Python references, which
run where it is not built, is stale or :data:`~laserpeople.extensions.PURE_PYTHON` is set
(:func:`laserpeople.extensions.load_extension`)."""

from __future__ import annotations

from pathlib import Path

from laserpeople.extensions import load_extension

SOURCE = Path(__file__).with_name("_cfeatures.c")
"""The extension's source, beside this module (in an installed package as well)."""

NAME = "laserpeople.detection._cfeatures"
"""The extension's module name."""

EXTENSION, IMPLEMENTATION = load_extension(NAME, SOURCE, "segment features")
"""The extension, or None (the Python references run); and which runs, and why."""
