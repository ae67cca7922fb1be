"""A split driven by the track's own history (an extension of 000 Sec. 4.4).

000's splits are data-driven: a track may split only when two observations fall in its
gate, i.e. when memory-less clustering separates its members too. Two parties in one
cluster - a wrong merge of parties walking past each other, or members starting to
leave a group while still within d_P - can therefore not be told apart by the tracker
until the clusters part, and the motion-coherence term (:mod:`.coherence`), which sees
that such an observation does not move as one, can only make the track die and be
re-born (docs/groups.md). This module finds the two motions inside one observation from
the snapshots the track keeps for the coherence term, so that the model generation can
offer a split of the track into them:

* **tracing** (:func:`trace_velocities`): every observed point z_l is followed back
  through the track's snapshots, newest to oldest. From its position x at time t' the
  point is moved back to the snapshot's time t_s by its velocity estimate u_l,
  x - u_l (t' - t_s), and replaced by the snapshot's point nearest to that guess; u_l is
  the track's predicted velocity until the trace is ``min_age`` seconds long and then
  the point's mean velocity since, (z_l - x) / (t - t_s). What remains is each point's
  mean velocity over the history, u_l = (z_l - x_l,oldest) / (t - t_oldest), over the
  snapshots at most ``window`` seconds old (the motion now);
* **velocity modes** (:func:`velocity_modes`): the points' velocities are averaged per
  human-sized blob (one leg or one person at d_hs), and the blobs are divided into two
  modes by 2-means (weighted by their points, started from the halves on either side of
  the mean along the principal axis of the blob velocities). The observation falls into
  two modes when each holds at least ``min_points`` points, the mode velocities u_A, u_B
  differ by at least ``min_dv`` and by at least ``separation`` times the blobs' pooled
  spread about their modes, s = sqrt(sum_b k_b |u_b - u_mode(b)|^2 / sum_b k_b);
* **the split** (:func:`divide_contour`, used by
  :meth:`~.interaction.GroupBranches.history_split`): the track splits into two halves
  (labels X-0 and X-1, n/2 people each, covariance C_0 as 000's split) that must match
  the two parts of the observation. Each half's predicted contour is the part of the
  track's contour nearest to its mode's points (the nearest-neighbour rule of Sec. 4.3),
  its position the old position moved to that part's mean, its velocity the mode's.
  The model's prior is p_S (the same binary split event as 000's) and it brings its own
  partition of the observations, the two modes' points.

Off by default (``GroupTrackerParams.history_split``); it needs the snapshots of the
motion-coherence term (``coherence_lag`` > 0) and is considered only for a track whose
observation the coherence term finds incoherent (log c < 0).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracking.groups.model import Snapshot

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True)
class HistorySplitSettings:
    """The history split (see the module doc).

    Attributes:
        min_age: Shortest trace [s]: no modes from a younger history; also the age from
            which a point's own velocity replaces the track's in the tracing.
        window: Longest trace [s]: the modes are of the velocities over the last
            ``window`` seconds (the motion now, not since the history began).
        min_dv: Least difference of the two modes' velocities [m/s].
        separation: Least ratio of that difference to the pooled spread of the blob
            velocities about their modes.
        min_points: Fewest points of a mode.
        unit_distance: Single-linkage distance [m] of the units whose mean velocities
            are divided into modes (0: the scan's human-sized blobs at d_hs).
        iterations: 2-means iterations.
    """

    min_age: float = 0.5
    window: float = 1.0
    min_dv: float = 0.5
    separation: float = 2.0
    min_points: int = 4
    unit_distance: float = 0.0
    iterations: int = 8


def trace_velocities(
    points: FloatArray,
    history: Sequence[Snapshot],
    stamp: float,
    velocity: FloatArray,
    min_age: float,
    window: float = np.inf,
) -> tuple[FloatArray, float, list[Snapshot]] | None:
    """Mean velocity (K, 2) [m/s] of each of ``points`` (K, 2) [m] over the track's
    snapshots ``history`` (oldest first; absolute points), traced back from ``stamp`` [s]
    as the module doc says, starting from the track's ``velocity`` (2,) [m/s], over the
    snapshots at most ``window`` [s] old; the length of the trace [s]; and the trace, per
    snapshot traced through (oldest first) its time [s] and the positions (K, 2) [m]
    the points were traced to. None when no such snapshot is ``min_age`` seconds old or
    there are no points."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    snaps = [(t, p) for t, p in history if stamp - window - 1e-9 <= t < stamp - 1e-9 and len(p)]
    if pts.shape[0] == 0 or not snaps or stamp - snaps[0][0] < min_age - 1e-9:
        return None
    x = pts.copy()
    u = np.broadcast_to(np.asarray(velocity, dtype=np.float64)[:2], pts.shape)
    t_prev = stamp
    path: list[Snapshot] = []
    for t_s, past in reversed(snaps):
        guess = x - u * (t_prev - t_s)
        dx = np.subtract.outer(guess[:, 0], past[:, 0])
        dy = np.subtract.outer(guess[:, 1], past[:, 1])
        x = past[np.argmin(dx * dx + dy * dy, axis=1)]
        path.append((t_s, x))
        t_prev = t_s
        if stamp - t_s >= min_age - 1e-9:
            u = (pts - x) / (stamp - t_s)
    age = stamp - t_prev
    return (pts - x) / age, age, path[::-1]


def divide_history(
    history: Sequence[Snapshot], path: Sequence[Snapshot], modes: IntArray, mode: int
) -> tuple[Snapshot, ...]:
    """The snapshots of one half of a history split: of every snapshot of ``history``
    that the trace ``path`` (:func:`trace_velocities`) went through, the points whose
    nearest traced position belongs to a point of ``mode`` (``modes`` (K,) of the traced
    points); snapshots left without points are dropped."""
    at = {t: x for t, x in path}
    out = []
    for t, past in history:
        traced = at.get(t)
        if traced is None:
            continue
        mine = past[divide_contour(past, traced, modes) == mode]
        if mine.shape[0]:
            out.append((t, mine))
    return tuple(out)


def velocity_modes(
    velocities: FloatArray, blobs: IntArray, settings: HistorySplitSettings
) -> IntArray | None:
    """Mode (K,) 0 or 1 of every point from the points' velocities (K, 2) [m/s] and
    their blob labels (K,) (any integers), or None when the points do not fall into two
    modes (module doc). Every point of a blob gets the blob's mode."""
    u = np.asarray(velocities, dtype=np.float64)
    _, blob, count = np.unique(np.asarray(blobs), return_inverse=True, return_counts=True)
    n_blobs = count.size
    if n_blobs < 2:
        return None
    k = count.astype(np.float64)
    ub = (
        np.column_stack([np.bincount(blob, u[:, 0], n_blobs), np.bincount(blob, u[:, 1], n_blobs)])
        / k[:, None]
    )
    centre = (k[:, None] * ub).sum(axis=0) / k.sum()
    dev = ub - centre
    scatter = (k[:, None, None] * dev[:, :, None] * dev[:, None, :]).sum(axis=0)
    axis = np.linalg.eigh(scatter)[1][:, -1]  # the principal axis
    mode = (dev @ axis > 0.0).astype(np.int64)
    for _ in range(settings.iterations):
        if mode.min() == mode.max():
            return None
        means = _mode_means(ub, k, mode)
        d = ((ub[:, None, :] - means[None, :, :]) ** 2).sum(axis=2)
        new = np.argmin(d, axis=1).astype(np.int64)
        if np.array_equal(new, mode):
            break
        mode = new
    if mode.min() == mode.max():
        return None
    means = _mode_means(ub, k, mode)
    points_per_mode = np.bincount(mode, k, 2)
    if points_per_mode.min() < settings.min_points:
        return None
    dv = float(np.hypot(*(means[0] - means[1])))
    spread = float(np.sqrt((k * ((ub - means[mode]) ** 2).sum(axis=1)).sum() / k.sum()))
    if dv < settings.min_dv or dv < settings.separation * spread:
        return None
    return np.asarray(mode[blob], dtype=np.int64)


def _mode_means(ub: FloatArray, k: FloatArray, mode: IntArray) -> FloatArray:
    """Mean velocity (2, 2) [m/s] of mode 0 and of mode 1: the blob velocities ``ub``
    (B, 2) of each mode (``mode`` (B,)) weighted by their points ``k`` (B,) (the centre
    step of the 2-means of :func:`velocity_modes`, also its final modes)."""
    return np.array(
        [(k[mode == c, None] * ub[mode == c]).sum(0) / k[mode == c].sum() for c in (0, 1)]
    )


def mode_velocities(velocities: FloatArray, modes: IntArray) -> FloatArray:
    """Mean velocity (2, 2) [m/s] of the points of mode 0 and of mode 1."""
    u = np.asarray(velocities, dtype=np.float64)
    return np.array([u[modes == c].mean(axis=0) for c in (0, 1)])


def divide_contour(contour: FloatArray, points: FloatArray, modes: IntArray) -> IntArray:
    """Mode (C,) of every contour point (C, 2) [m]: the mode of the nearest of ``points``
    (K, 2) [m] (same frame) with ``modes`` (K,) (the nearest-neighbour rule of Sec. 4.3)."""
    c = np.asarray(contour, dtype=np.float64).reshape(-1, 2)
    if c.shape[0] == 0:
        return np.empty(0, dtype=np.int64)
    dx = np.subtract.outer(c[:, 0], points[:, 0])
    dy = np.subtract.outer(c[:, 1], points[:, 1])
    return np.asarray(modes[np.argmin(dx * dx + dy * dy, axis=1)], dtype=np.int64)


__all__ = [
    "HistorySplitSettings",
    "divide_contour",
    "divide_history",
    "mode_velocities",
    "trace_velocities",
    "velocity_modes",
]
