"""Tracking metrics: CLEAR MOT, IDF1, the adapted MOTP of 004 and 000's clustering error.

Every metric follows one protocol (:class:`Metric`): ``accumulate(truth_frame, tracks)`` per
scored scan, ``result()`` for a frozen dataclass of numbers, ``frames()`` for the per-frame
table. :func:`evaluate` pairs truth frames and tracks by scan index and runs them all.

Example:
    >>> from laserpeople.io import open_recording  # doctest: +SKIP
    >>> from laserpeople.io.tracks_csv import iter_tracks_csv  # doctest: +SKIP
    >>> run = evaluate(open_recording("sim.npz").truth(),  # doctest: +SKIP
    ...                iter_tracks_csv("tracks.csv", kinds=("person",)))
    >>> run.result().summary()["mota"]  # doctest: +SKIP
"""

from laserpeople.evaluation.clear_mot import ClearMot, ClearMotResult
from laserpeople.evaluation.clustering import (
    ClusteringError,
    ClusteringErrorResult,
    ClusteringFrame,
    beam_group_labels,
    clustering_error,
    frame_counts,
    partition_labels,
)
from laserpeople.evaluation.detail import FrameTable
from laserpeople.evaluation.identity import IdentityF1, IdentityResult
from laserpeople.evaluation.matching import FramePoints, frame_points, gated_assignment
from laserpeople.evaluation.pairing import PairingCounts, pair_by_scan
from laserpeople.evaluation.params import EvaluationParams
from laserpeople.evaluation.protocol import Metric
from laserpeople.evaluation.report import (
    SUMMARY_KEYS,
    EvaluationReport,
    TrackingEvaluation,
    evaluate,
)
from laserpeople.evaluation.schenk_motp import SchenkMotp, SchenkMotpResult, matching_value

__all__ = [
    "SUMMARY_KEYS",
    "ClearMot",
    "ClearMotResult",
    "ClusteringError",
    "ClusteringErrorResult",
    "ClusteringFrame",
    "EvaluationParams",
    "EvaluationReport",
    "FramePoints",
    "FrameTable",
    "IdentityF1",
    "IdentityResult",
    "Metric",
    "PairingCounts",
    "SchenkMotp",
    "SchenkMotpResult",
    "TrackingEvaluation",
    "beam_group_labels",
    "clustering_error",
    "evaluate",
    "frame_counts",
    "frame_points",
    "gated_assignment",
    "matching_value",
    "pair_by_scan",
    "partition_labels",
]
