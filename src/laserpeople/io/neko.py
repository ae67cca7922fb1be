"""Reader of the neko7055 leg-detection data set (``xy_data.txt`` + ``leg_segment_labels.json``).

``xy_data.txt`` starts with a header ``<beams> 2 <frames>`` followed by ``frames * beams``
lines ``x y`` [m] (sensor at the origin, 360 degrees, ``0 0`` = no return).
``leg_segment_labels.json`` lists per frame the indices of the leg segments under the
segmentation rule written in the file: drop ``(0, 0)`` / non-finite points, start a new
segment where consecutive points are >= 0.1 m apart, merge the last segment into the first
when the first and last point are < 0.1 m apart. That is exactly
:class:`~laserpeople.segmentation.JumpDistanceSegmenter` with ``threshold=0.1`` and
``wrap_around=True`` on these full-circle scans, so segment ``i`` of our table is segment
``i`` of the labels.

The file gives no time stamps; frames get ``stamp = index * frame_period``.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from laserpeople.errors import RecordingError
from laserpeople.scan import Scan

NEKO_SEGMENT_THRESHOLD = 0.1
"""Jump distance [m] of the neko7055 label rule."""
NEKO_XY_LIMIT = 1000.0
"""Largest |x|, |y| [m] of a point in ``xy_data.txt`` (a 2D laser sees at most a few
hundred metres; larger values are damage and overflow the segment features)."""
NEKO_BEAM_LIMIT = 100_000
"""Most beams per frame (and so segments) a neko7055 file may declare."""
NEKO_TRAIN_FRAMES = range(0, 60)
NEKO_TEST_FRAMES = range(60, 120)


@dataclass(frozen=True, eq=False)
class NekoData:
    """The frames of ``xy_data.txt`` as scans, and the leg segment indices per frame."""

    scans: list[Scan]
    leg_segments: dict[int, frozenset[int]]
    rule: str


def read_neko_scans(path: str | Path, frame_period: float = 0.1) -> list[Scan]:
    """Read ``xy_data.txt`` into full-circle scans (sensor frame; angle_min = -pi).

    Args:
        path: The ``xy_data.txt`` file.
        frame_period: Time between frames [s] (not recorded in the file).
    """
    p = Path(path)
    try:
        with p.open(encoding="utf-8") as fh:
            header = fh.readline().split()
            data = np.loadtxt(fh, dtype=np.float64, ndmin=2)
    except FileNotFoundError as exc:
        raise RecordingError("file not found", path=p) from exc
    except (OSError, ValueError) as exc:
        raise RecordingError(f"cannot parse neko7055 xy data: {exc}", path=p) from exc
    try:
        beams, dims, frames = (int(v) for v in header)
        if not (0 < beams <= NEKO_BEAM_LIMIT and frames >= 0):
            raise ValueError(f"{beams} beams")
    except ValueError as exc:
        raise RecordingError(
            f"bad header {' '.join(header)!r}; expected '<beams> 2 <frames>'", path=p
        ) from exc
    if dims != 2 or data.shape != (beams * frames, 2):
        raise RecordingError(
            f"header says {frames} frames x {beams} beams of 2 values, file has "
            f"{data.shape[0]} rows of {data.shape[1] if data.ndim == 2 else 0}",
            path=p,
            hint="the file is truncated or not in the neko7055 layout",
        )
    far = np.abs(data) > NEKO_XY_LIMIT
    if far.any():
        row = int(np.flatnonzero(far.any(axis=1))[0])
        raise RecordingError(
            f"line {row + 2}: point ({data[row, 0]:.6g}, {data[row, 1]:.6g}) is more than "
            f"{NEKO_XY_LIMIT:g} m from the sensor",
            path=p,
            hint="the file is damaged; neko7055 points are metres within the scanner's range",
        )
    xy = data.reshape(frames, beams, 2)
    ranges = np.hypot(xy[..., 0], xy[..., 1])
    ranges[(ranges == 0.0) | ~np.isfinite(ranges)] = np.nan
    increment = 2.0 * math.pi / beams
    return [
        Scan(
            stamp=i * frame_period,
            angle_min=-math.pi,
            angle_increment=increment,
            ranges=ranges[i],
            sensor="neko7055",
            index=i,
            source=str(p),
        )
        for i in range(frames)
    ]


def read_neko_labels(path: str | Path) -> tuple[dict[int, frozenset[int]], str]:
    """Leg segment indices per frame and the segmentation rule text from the labels JSON."""
    p = Path(path)
    try:
        doc = json.loads(p.read_text(encoding="utf-8"))
        labels = {int(k): frozenset(_label_index(i) for i in v) for k, v in doc["labels"].items()}
        rule = str(doc.get("description", ""))
    except FileNotFoundError as exc:
        raise RecordingError("file not found", path=p) from exc
    except (
        OSError,
        ValueError,
        KeyError,
        TypeError,
        AttributeError,
        OverflowError,
        RecursionError,
    ) as exc:
        raise RecordingError(
            f"not a neko7055 label file: {str(exc)[:200]}",
            path=p,
            hint="labels must map frame numbers to lists of segment indices "
            f"(integers 0-{NEKO_BEAM_LIMIT - 1})",
        ) from exc
    return labels, rule


def _label_index(value: object) -> int:
    """A segment index of the labels JSON: an integer (or integral number) in
    ``[0, NEKO_BEAM_LIMIT)``; ValueError otherwise (``Infinity``, ``1e300``, text)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ValueError(f"segment index {str(value)[:40]!r} is not a number")
    if not (math.isfinite(value) and value == int(value) and 0 <= value < NEKO_BEAM_LIMIT):
        raise ValueError(f"segment index {value!r} is not an integer 0-{NEKO_BEAM_LIMIT - 1}")
    return int(value)


NEKO_XY = "xy_data.txt"
NEKO_LABELS = "leg_segment_labels.json"
"""The two files of a neko7055 folder: the points and the leg segments' labels."""


def read_neko(directory: str | Path, frame_period: float = 0.1) -> NekoData:
    """Scans and labels of a neko7055 directory."""
    d = Path(directory)
    hint = "give the neko7055 folder, the one holding xy_data.txt and leg_segment_labels.json"
    if not d.exists():
        raise RecordingError("neko7055 folder not found", path=d, hint=hint)
    if not d.is_dir():
        raise RecordingError("is a file, not a neko7055 folder", path=d, hint=hint)
    missing = [n for n in (NEKO_XY, NEKO_LABELS) if not (d / n).exists()]
    if missing:
        raise RecordingError(
            f"no {' and no '.join(missing)} in this folder: not a neko7055 folder",
            path=d,
            hint=hint,
        )
    scans = read_neko_scans(d / NEKO_XY, frame_period)
    labels, rule = read_neko_labels(d / NEKO_LABELS)
    return NekoData(scans, labels, rule)


def neko_segment_labels(leg_segments: frozenset[int], n_segments: int) -> NDArray[np.bool_]:
    """Mask (n_segments,) of leg segments of one frame."""
    mask = np.zeros(n_segments, dtype=bool)
    idx = [i for i in leg_segments if i < n_segments]
    mask[idx] = True
    return mask
