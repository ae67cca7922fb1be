"""Build truth frames and tracks from plain trajectories, for tests, examples and benchmarks.

A trajectory set is a mapping ``id -> (F, 2)`` array of positions [m] over F frames, with a
NaN row where that person or track is absent.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracks import Track, TrackKind, Tracks
from laserpeople.truth import TruthFrame

Trajectories = Mapping[int, NDArray[np.float64]]


def _frame_count(*sets: Trajectories) -> int:
    lengths = {np.asarray(xy).reshape(-1, 2).shape[0] for s in sets for xy in s.values()}
    if len(lengths) > 1:
        raise ValueError(f"trajectories have different lengths {sorted(lengths)}")
    return lengths.pop() if lengths else 0


def _present(trajectories: Trajectories, k: int) -> tuple[list[int], NDArray[np.float64]]:
    ids = []
    rows = []
    for tid, xy in trajectories.items():
        p = np.asarray(xy, dtype=np.float64).reshape(-1, 2)[k]
        if np.isfinite(p).all():
            ids.append(int(tid))
            rows.append(p)
    return ids, np.array(rows, dtype=np.float64).reshape(-1, 2)


def synthetic_sequence(
    people: Trajectories,
    tracks: Trajectories,
    dt: float = 0.1,
    kind: TrackKind = "person",
) -> tuple[list[TruthFrame], list[Tracks]]:
    """Truth frames and tracks (world frame, scan k at time k * dt) from trajectories.

    Every frame gets a truth frame (possibly with nobody) and a :class:`Tracks` (possibly
    empty).
    """
    n = _frame_count(people, tracks)
    truth_frames = []
    track_frames = []
    for k in range(n):
        ids, xy = _present(people, k)
        truth_frames.append(TruthFrame.from_positions(k * dt, k, np.array(ids, np.int64), xy))
        tids, txy = _present(tracks, k)
        track_frames.append(
            Tracks(
                k * dt,
                k,
                tuple(
                    Track(tid, kind, p, np.zeros(2), np.eye(2) * 0.01)
                    for tid, p in zip(tids, txy, strict=True)
                ),
            )
        )
    return truth_frames, track_frames
