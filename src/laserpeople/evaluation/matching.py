"""What every metric does first: put one scan's truth and tracks side by side, and match them.

:func:`frame_points` turns a :class:`~laserpeople.truth.TruthFrame` and the
:class:`~laserpeople.tracks.Tracks` of the same scan into id and position arrays (world
frame) and checks that they belong together; :func:`gated_assignment` is the min-cost
one-to-one matching within a distance gate that CLEAR MOT uses inside one frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment

from laserpeople.errors import EvaluationError
from laserpeople.io.tracks_csv import convert_tracks
from laserpeople.tracks import Tracks
from laserpeople.truth import TruthFrame

IntArray = NDArray[np.int64]
FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class FramePoints:
    """Truth and track positions of one scan, ready for matching.

    Attributes:
        scan_index: 0-based index of the scan.
        stamp: Time of the truth frame [s].
        truth_ids: Person ids (G,).
        truth_xy: Person positions (G, 2) [m], world frame.
        track_ids: Track ids (T,) of the scored kind.
        track_xy: Track positions (T, 2) [m], world frame.
    """

    scan_index: int
    stamp: float
    truth_ids: IntArray
    truth_xy: FloatArray
    track_ids: IntArray
    track_xy: FloatArray

    @property
    def distances(self) -> FloatArray:
        """Euclidean distances (G, T) [m] between every person and every track."""
        diff = self.truth_xy[:, None, :] - self.track_xy[None, :, :]
        return np.asarray(np.hypot(diff[..., 0], diff[..., 1]), dtype=np.float64)


def frame_points(truth: TruthFrame, tracks: Tracks | None, kind: str) -> FramePoints:
    """The people of ``truth`` and the tracks of ``kind`` in ``tracks`` as arrays.

    ``tracks=None`` means the tracker reported nothing for this scan. Tracks in another
    frame than the one the truth states are moved into it with their ``sensor_pose``;
    against truth that states no frame they are compared as they are (a tracks CSV in the
    laser frame against labels in the laser frame;
    :meth:`~laserpeople.evaluation.pairing.PairingCounts.frame_check` says so).

    Raises:
        EvaluationError: the scans differ, ids repeat within the scan, positions are not
            finite, or the tracks have no pose and the truth states another frame.
    """
    if tracks is not None and tracks.scan_index != truth.scan_index:
        raise EvaluationError(
            f"truth of scan {truth.scan_index} compared with tracks of scan {tracks.scan_index}",
            scan=truth.scan_index,
            hint="pair truth frames and tracks by scan index",
        )
    truth_ids = np.asarray(truth.person_ids, dtype=np.int64)
    truth_xy = np.asarray(truth.positions, dtype=np.float64).reshape(-1, 2)
    _check_unique(truth_ids, "person id", "ground truth", truth.scan_index)
    if not np.isfinite(truth_xy).all():
        raise EvaluationError(
            "a ground-truth position is not finite", scan=truth.scan_index, hint="fix the truth"
        )
    if tracks is None:
        track_ids = np.empty(0, dtype=np.int64)
        track_xy = np.empty((0, 2))
    else:
        if truth.frame is not None and tracks.frame != truth.frame:
            if tracks.sensor_pose is not None:
                tracks = convert_tracks(tracks, truth.frame)
            else:
                raise EvaluationError(
                    f"the tracks are in the {tracks.frame} frame with no sensor pose, the "
                    f"truth in the {truth.frame} frame",
                    scan=truth.scan_index,
                    hint=f"track with --output-frame {truth.frame}, or give truth in the "
                    f"{tracks.frame} frame",
                )
        chosen = tracks.of_kind(kind)  # type: ignore[arg-type]
        track_ids = np.array([t.track_id for t in chosen], dtype=np.int64)
        track_xy = np.array([t.position for t in chosen], dtype=np.float64).reshape(-1, 2)
        _check_unique(track_ids, "track id", f"{kind} tracks", truth.scan_index)
        if not np.isfinite(track_xy).all():
            raise EvaluationError(
                "a track position is not finite", scan=truth.scan_index, hint="fix the tracks"
            )
    return FramePoints(truth.scan_index, truth.stamp, truth_ids, truth_xy, track_ids, track_xy)


def _check_unique(ids: IntArray, what: str, where: str, scan: int) -> None:
    values, counts = np.unique(ids, return_counts=True)
    if (counts > 1).any():
        raise EvaluationError(
            f"{what} {int(values[counts > 1][0])} appears more than once in the {where}",
            scan=scan,
            hint=f"each {what} may appear once per scan",
        )


def gated_assignment(distances: FloatArray, gate: float) -> tuple[IntArray, IntArray]:
    """Rows and columns of the one-to-one matching with the most pairs within ``gate`` and,
    among those, the smallest sum of distances.

    Args:
        distances: (N, M) distances [m]; pairs farther than ``gate`` are never matched.
        gate: Largest distance of a match [m] (inclusive).

    Returns:
        ``(rows, cols)``, equally long int arrays, sorted by row.
    """
    d = np.asarray(distances, dtype=np.float64)
    valid = d <= gate
    if not valid.any():
        empty = np.empty(0, dtype=np.int64)
        return empty, empty
    rows_used = np.flatnonzero(valid.any(axis=1))
    cols_used = np.flatnonzero(valid.any(axis=0))
    sub = d[np.ix_(rows_used, cols_used)]
    sub_valid = valid[np.ix_(rows_used, cols_used)]
    # An invalid pair costs more than all valid pairs together, so every solution with
    # fewer invalid pairs is cheaper: the matching first maximises the number of valid
    # pairs, then minimises their summed distance.
    big = float(sub[sub_valid].sum()) + 1.0
    cost = np.where(sub_valid, sub, big)
    r, c = linear_sum_assignment(cost)
    keep = sub_valid[r, c]
    return rows_used[r[keep]].astype(np.int64), cols_used[c[keep]].astype(np.int64)


def max_weight_assignment(weights: FloatArray) -> tuple[IntArray, IntArray]:
    """Rows and columns of the one-to-one matching with the largest summed weight (weights
    >= 0; pairs of weight 0 are left out of the result as they change nothing)."""
    w = np.asarray(weights, dtype=np.float64)
    if w.size == 0:
        empty = np.empty(0, dtype=np.int64)
        return empty, empty
    r, c = linear_sum_assignment(w, maximize=True)
    keep = w[r, c] > 0.0
    return r[keep].astype(np.int64), c[keep].astype(np.int64)
