"""Person-sized blobs of foreground points that move in the world frame.

On a moving laser with poses the occupancy grid has not yet learned what the robot drives
past, so its foreground holds walls and clutter besides people
(:mod:`laserpeople.pipeline.leg_foreground`). In the world frame (the robot's own motion
taken out by the poses) walls and clutter stay put and walking people do not.

:class:`MovingBlobs` groups a frame's foreground points by single linkage at
:data:`BLOB_LINK` (a person's two legs are one blob), keeps the person-sized blobs (at
least :data:`BLOB_MIN_POINTS` points, no two farther apart than :data:`BLOB_MAX_EXTENT`),
follows each blob's centre from frame to frame (greedy nearest-centre association within
:data:`BLOB_GATE`) and says which points belong to a blob whose centre lies at least
``travel`` from where it was ``seconds`` or more ago (within the last ``2 * seconds``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering.single_linkage import single_linkage

BLOB_LINK = 0.35
"""Points closer than this [m] are one blob: 002's legs of one standing or walking person lie
0.1-0.5 m apart, the detector's leg segments 0.05-0.2 m wide."""
BLOB_MAX_EXTENT = 0.8
"""A blob wider than this [m] (its bounding box's diagonal) is no person (a wall, a row of
furniture, a party)."""
BLOB_MIN_POINTS = 2
"""A blob of fewer points is noise (a single return)."""
BLOB_GATE = 0.5
"""A blob continues the nearest blob of the previous frame within this [m] (2.5 m/s at 5 Hz;
a walker covers 0.05-0.15 m between scans at 10-20 Hz)."""


@dataclass
class _BlobTrack:
    """One blob followed over frames: its centres [m] and their stamps [s]."""

    stamps: list[float] = field(default_factory=list)
    centres: list[NDArray[np.float64]] = field(default_factory=list)


def blob_labels(points: NDArray[np.float64], mask: NDArray[np.bool_]) -> NDArray[np.int64]:
    """Labels (N,) of the person-sized blobs of the ``points`` (N, 2) [m] where ``mask``
    (N,) holds (module docstring; -1: in no such blob), numbered 0..K-1."""
    labels = single_linkage(points, BLOB_LINK, mask=mask, min_points=BLOB_MIN_POINTS)
    out = np.full(len(labels), -1, dtype=np.int64)
    k = 0
    for lab in range(int(labels.max(initial=-1)) + 1):
        members = labels == lab
        pts = points[members]
        extent = float(np.hypot(*(pts.max(axis=0) - pts.min(axis=0))))
        if extent <= BLOB_MAX_EXTENT:
            out[members] = k
            k += 1
    return out


class MovingBlobs:
    """Follows person-sized foreground blobs in the world frame and says which move.

    Args:
        travel: Net distance [m] a blob's centre must have moved (> 0).
        seconds: ... over at least this long [s] (> 0); the reference centre is the oldest
            of the last ``2 * seconds``.
    """

    def __init__(self, travel: float, seconds: float) -> None:
        if not 0.0 < travel < float("inf") or not 0.0 < seconds < float("inf"):
            raise ValueError(f"travel and seconds must be positive, got {travel}, {seconds}")
        self.travel = travel
        self.seconds = seconds
        self._tracks: list[_BlobTrack] = []
        self._last = -np.inf

    def __call__(
        self, stamp: float, points: NDArray[np.float64], mask: NDArray[np.bool_]
    ) -> NDArray[np.bool_]:
        """Which of ``points`` (N, 2) [m, world frame] at ``stamp`` [s], among those where
        ``mask`` (N,) holds, belong to a blob that moved (module docstring). A stamp before
        the previous one forgets every blob."""
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        if stamp < self._last:
            self._tracks = []
        self._last = stamp
        labels = blob_labels(pts, np.asarray(mask, dtype=bool))
        k = int(labels.max(initial=-1)) + 1
        centres = np.array([pts[labels == i].mean(axis=0) for i in range(k)]).reshape(-1, 2)
        tracks = self._associate(centres)
        moving = np.zeros(len(pts), dtype=bool)
        for i, track in enumerate(tracks):
            track.stamps.append(stamp)
            track.centres.append(centres[i])
            while track.stamps and stamp - track.stamps[0] > 2 * self.seconds:
                track.stamps.pop(0)
                track.centres.pop(0)
            if self._moved(track):
                moving[labels == i] = True
        self._tracks = tracks
        return moving

    def _moved(self, track: _BlobTrack) -> bool:
        """Whether ``track`` moved consistently: its oldest centre is ``seconds`` or more old
        and lies ``travel`` or more from its newest, and the centre halfway between them in
        time lies at least a third of ``travel`` from either (a blob that jumped once, when
        its association switched or part of it was hidden, and stood still is no walker)."""
        t0, t1 = track.stamps[0], track.stamps[-1]
        if t1 - t0 < self.seconds:
            return False
        first, last = track.centres[0], track.centres[-1]
        mid = track.centres[int(np.searchsorted(track.stamps, (t0 + t1) / 2))]
        return bool(
            np.hypot(*(last - first)) >= self.travel
            and np.hypot(*(mid - first)) >= self.travel / 3
            and np.hypot(*(last - mid)) >= self.travel / 3
        )

    def _associate(self, centres: NDArray[np.float64]) -> list[_BlobTrack]:
        """The track of each of ``centres`` (K, 2) [m]: the nearest previous blob within
        :data:`BLOB_GATE`, greedily by distance, one to one; else a new track."""
        prev = np.array([t.centres[-1] for t in self._tracks]).reshape(-1, 2)
        out: list[_BlobTrack | None] = [None] * len(centres)
        if len(prev) and len(centres):
            d = np.linalg.norm(centres[:, None, :] - prev[None, :, :], axis=2)
            used: set[int] = set()
            for flat in np.argsort(d, axis=None, kind="stable"):
                i, j = divmod(int(flat), len(prev))
                if d[i, j] > BLOB_GATE:
                    break
                if out[i] is None and j not in used:
                    out[i] = self._tracks[j]
                    used.add(j)
        return [t if t is not None else _BlobTrack() for t in out]


__all__ = ["BLOB_GATE", "BLOB_LINK", "BLOB_MAX_EXTENT", "BLOB_MIN_POINTS", "MovingBlobs"]
