"""Labelled recordings for learning: scans, leg detections and ground truth paired by scan.

A :class:`LabelledRecording` holds the scans of one laser, the leg detections of each scan
(in the frame of the truth: the world frame for a simulated ``.npz``, whose truth is written
there, the laser frame for a bag or CSV, whose labels are), the truth frames keyed by scan
index, and the area the laser saw in each scan (the observation volume V of 000 eq. 3, for
rates per m^2).

Two kinds of truth:

- *full* (simulated ``.npz``): every person in view is labelled, with leg positions and, in
  the per-beam labels, groups. Every unmatched detection is a false alarm.
- *followed* (a bag topic or a CSV such as the leg_tracker benchmark's, where only the
  person the robot follows is labelled): unmatched detections may be other, unlabelled
  people, so false alarms and new tracks cannot be counted there.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.fitting.estimates import FitError
from laserpeople.scan import Scan, visible_area
from laserpeople.tracks import Detections
from laserpeople.truth import TruthFrame

FloatArray = NDArray[np.float64]

MAX_UNPAIRED_SHARE = 0.1
"""Largest share of truth frames whose scan is not in the recording before pairing fails."""


@dataclass(frozen=True, eq=False)
class LabelledRecording:
    """One laser's scans with leg detections and ground truth.

    Attributes:
        name: Name for reports (file name, with the part when split).
        scans: The scans (S,), in order.
        detections: Leg detections of each scan (S,), in the truth's frame.
        truth: Scan index -> truth frame (only labelled scans).
        followed: Only one followed person is labelled (no false alarms countable).
        areas: Visible area of each scan (S,) [m^2].
        source: Description of the data (recording and truth) for the TOML comments.
        notes: What was left out while pairing (for the command to say).
    """

    name: str
    scans: tuple[Scan, ...]
    detections: tuple[Detections, ...]
    truth: dict[int, TruthFrame]
    followed: bool
    areas: FloatArray
    source: str = ""
    notes: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        if len(self.scans) != len(self.detections) or len(self.scans) != len(self.areas):
            raise ValueError("scans, detections and areas must be equally long")

    def __len__(self) -> int:
        return len(self.scans)

    @property
    def has_legs(self) -> bool:
        """The truth carries leg positions (simulated)."""
        return any(np.isfinite(f.leg_positions).all() and len(f) for f in self.truth.values())

    @property
    def has_labels(self) -> bool:
        """Every scan carries per-beam labels (simulated; needed for groups)."""
        return bool(self.scans) and all(s.labels is not None for s in self.scans)

    def truth_frames(self) -> list[TruthFrame]:
        """Truth frames in scan order."""
        return [self.truth[k] for k in sorted(self.truth)]

    def part(self, start: int, stop: int, label: str) -> LabelledRecording:
        """Scans ``start:stop`` (positions in :attr:`scans`) with their truth."""
        scans = self.scans[start:stop]
        idx = {s.index for s in scans}
        return replace(
            self,
            name=f"{self.name} [{label}]",
            scans=scans,
            detections=self.detections[start:stop],
            truth={k: f for k, f in self.truth.items() if k in idx},
            areas=self.areas[start:stop],
        )


def build(
    name: str,
    scans: Sequence[Scan],
    truth: Iterable[TruthFrame],
    detect: Callable[[Scan], Detections],
    *,
    followed: bool,
    source: str = "",
    world: bool = True,
) -> LabelledRecording:
    """Detect legs in ``scans`` and pair ``truth`` with them by scan index.

    Args:
        world: Detections go into the world frame when the scan has a pose (simulated truth
            is in the world frame); otherwise they stay in the sensor frame without a pose.

    Raises:
        FitError: no truth frame, or more than :data:`MAX_UNPAIRED_SHARE` of the truth frames
            name scans the recording does not have.
    """
    scans = list(scans)
    if not scans:
        raise FitError("the recording has no scans", path=name)
    by_index = {s.index: k for k, s in enumerate(scans)}
    frames = list(truth)
    if not frames:
        raise FitError("the ground truth has no frame", path=name, hint="give labelled truth")
    paired = {f.scan_index: f for f in frames if f.scan_index in by_index}
    unpaired = len(frames) - len(paired)
    if not paired or unpaired > MAX_UNPAIRED_SHARE * len(frames):
        lo, hi = min(f.scan_index for f in frames), max(f.scan_index for f in frames)
        raise FitError(
            f"the ground truth cannot be paired with the scans: {unpaired} of {len(frames)} "
            f"truth frames name scans {lo}-{hi}, the recording has scans "
            f"{scans[0].index}-{scans[-1].index}",
            path=name,
            hint="give the truth of this recording (and --topic for the laser it labels)",
        )
    dets: list[Detections] = []
    for scan in scans:
        d = detect(scan)
        if world and scan.pose is not None:
            d = d.to_world()
        elif d.sensor_pose is not None:
            d = replace(d, sensor_pose=None)
        dets.append(d)
    notes = (f"{unpaired} truth frames without a scan left out",) if unpaired else ()
    return LabelledRecording(
        name,
        tuple(scans),
        tuple(dets),
        paired,
        followed,
        np.array([visible_area(s) for s in scans]),
        source or name,
        notes,
    )


def load(
    path: Path,
    truth: str | None,
    detect: Callable[[Scan], Detections],
    topic: str | None = None,
) -> LabelledRecording:
    """Read a recording and its truth: the recording's own (a simulated ``.npz``) when
    ``truth`` is None, else a truth CSV or ``BAG[:TOPIC]`` (followed-person truth: only the
    labelled people count).

    Raises:
        FitError: no truth, or it cannot be paired (see :func:`build`).
    """
    from laserpeople.io import open_recording

    options: dict[str, Any] = {}
    is_npz = path.suffix.lower() == ".npz"
    if not is_npz:
        options["poses"] = False  # labels of bags and CSVs are in the laser frame
    rec = open_recording(path, **options)
    try:
        scans = list(rec.scans([topic] if topic else None))
        if scans:
            first = scans[0].sensor
            scans = [s for s in scans if s.sensor == first]
        if truth is None:
            if not rec.has_truth:
                raise FitError(
                    "the recording has no ground truth",
                    path=path,
                    hint="give --truth CSV or BAG[:TOPIC] for it, or a simulated .npz",
                )
            frames = list(rec.truth())
            return build(
                path.name, scans, frames, detect, followed=False, source=path.name, world=True
            )
    finally:
        rec.close()
    frames, note = read_truth(truth, topic or (scans[0].sensor if scans else None))
    return build(
        path.name,
        scans,
        frames,
        detect,
        followed=True,
        source=f"{path.name} with truth {note}",
        world=False,
    )


def read_truth(spec: str, laser_topic: str | None) -> tuple[list[TruthFrame], str]:
    """Truth frames from a CSV ``scan,stamp,person_id,x,y`` or ``BAG[:TOPIC]``, and a note
    naming them."""
    from laserpeople.io.truth_bag import is_bag_path, read_truth_bag, split_truth_spec

    path, topic = split_truth_spec(spec)
    if is_bag_path(path):
        bag = read_truth_bag(path, topic, laser_topic)
        return bag.frames, f"{path.name}:{bag.topic}"
    if path.suffix.lower() == ".csv" and topic is None:
        from laserpeople.io.truth_csv import read_truth_csv

        return read_truth_csv(path), path.name
    what = (
        "is a folder, not a truth file"
        if path.is_dir()
        else "does not exist"
        if not path.exists()
        else "is neither a truth CSV nor a bag"
    )
    raise FitError(
        f"cannot read ground truth: {path} {what}",
        path=path,
        hint="give a CSV scan,stamp,person_id,x,y or BAG[:TOPIC]",
    )


def split(
    recordings: Sequence[LabelledRecording], validation: float
) -> tuple[list[LabelledRecording], list[LabelledRecording]]:
    """Training and validation parts.

    With several recordings the last ``round(validation * n)`` (at least one, at most n - 1)
    are the validation part; with one recording the last ``validation`` share of its scans
    (a time block). ``validation = 0`` validates on nothing.

    Raises:
        FitError: ``validation`` outside [0, 1), or nothing left to fit on.
    """
    if not 0.0 <= validation < 1.0:
        raise FitError(f"--validation {validation} must be in [0, 1)")
    recs = list(recordings)
    if validation == 0.0 or not recs:
        return recs, []
    if len(recs) > 1:
        n_val = min(max(1, round(validation * len(recs))), len(recs) - 1)
        return recs[: len(recs) - n_val], recs[len(recs) - n_val :]
    rec = recs[0]
    cut = round((1.0 - validation) * len(rec))
    if cut < 1 or cut >= len(rec):
        raise FitError(
            f"{rec.name}: {len(rec)} scans cannot be split {1 - validation:.2f} : {validation:.2f}"
        )
    return [rec.part(0, cut, f"first {1 - validation:.0%}")], [
        rec.part(cut, len(rec), f"last {validation:.0%}")
    ]
