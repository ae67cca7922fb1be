"""Scoring default and learned parameters on the validation part of the labelled data.

People tracker: a fresh :class:`~laserpeople.tracking.legs.LegMHTTracker` over each
validation recording's leg detections, scored with CLEAR MOT and IDF1 (full truth) or the
followed-person scores (identity recall, recall, ids; no other track is a false positive).
Group tracker: :func:`~laserpeople.evaluation.groups.run_groups` on the scans (clustering
error of 000 Fig. 17 and the group-size error of Sec. 4.6.3).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

from laserpeople.fitting.data import LabelledRecording
from laserpeople.scan import CoordinateFrame
from laserpeople.tracks import Tracks

COUNT_SCORES = frozenset({"ids", "ID switches"})
"""Scores that are counts (shown without decimals)."""


@dataclass(frozen=True)
class ValidationRow:
    """Scores of one parameter set on one validation recording.

    Attributes:
        recording: Name of the validation part.
        label: ``default`` or ``learned``.
        scores: Metric name -> value, in display order.
    """

    recording: str
    label: str
    scores: dict[str, float]


def track_legs(rec: LabelledRecording, params: Any) -> list[Tracks]:
    """The leg MHT's output for every scan of ``rec``."""
    from laserpeople.tracking.legs import LegMHTTracker

    tracker = LegMHTTracker(params)
    return [tracker.update(d) for d in rec.detections]


def score_legs(rec: LabelledRecording, tracks: list[Tracks]) -> dict[str, float]:
    """Scores of person tracks against the recording's truth.

    Tracks without a pose (a recording without poses, whose labels are in the laser frame)
    are compared as they are, taken to be in the frame the truth states (the world frame
    when it states none).
    """
    frames = rec.truth_frames()
    stated: CoordinateFrame = next((f.frame for f in frames if f.frame is not None), "world")
    tracks = [
        replace(t, frame=stated) if t.frame != stated and t.sensor_pose is None else t
        for t in tracks
    ]
    if rec.followed:
        from laserpeople.evaluation.followed import evaluate_followed, most_labelled_person

        metric, _ = evaluate_followed(
            frames, tracks, most_labelled_person(frames), keep_frames=False
        )
        r = metric.result()
        return {
            "identity recall": r.identity_recall,
            "recall": r.recall,
            "ids": float(r.ids),
        }
    from laserpeople.evaluation.report import evaluate

    report = evaluate(frames, tracks, keep_frames=False).result()
    return {
        "MOTA": report.clear_mot.mota,
        "IDF1": report.identity.idf1,
        "recall": report.clear_mot.recall,
        "ID switches": float(report.clear_mot.id_switches),
    }


def validate_legs(
    recordings: Sequence[LabelledRecording], sets: dict[str, Any]
) -> list[ValidationRow]:
    """Each parameter set of ``sets`` (label -> LegTrackerParams) on each recording."""
    rows = []
    for rec in recordings:
        for label, params in sets.items():
            rows.append(ValidationRow(rec.name, label, score_legs(rec, track_legs(rec, params))))
    return rows


def validate_groups(
    recordings: Sequence[LabelledRecording], sets: dict[str, Any]
) -> list[ValidationRow]:
    """Each parameter set (label -> GroupTrackerParams) on each recording's scans."""
    from laserpeople.evaluation.groups import run_groups

    rows = []
    for rec in recordings:
        for label, params in sets.items():
            r = run_groups(list(rec.scans), params)
            rows.append(
                ValidationRow(
                    rec.name,
                    label,
                    {
                        "clustering error": r.clustering.error,
                        "memory-less": r.memoryless.error,
                        "size error": r.size.mean_error,
                        "exact size": r.size.exact_share,
                    },
                )
            )
    return rows
