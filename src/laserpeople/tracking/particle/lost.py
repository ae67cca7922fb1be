"""Identities of filters that died for want of support, for a new filter to take back.

With one laser a person is hidden behind another for longer than a filter lives without
points; when they are seen again, a new filter starts on them under a new identity (004's
trackers count every start as a new person). Here a filter that starts within
``distance`` of where a lost filter would be now (its position at its last support, or
that position moved on at its velocity then: the segment between the two) within
``duration`` of its last support takes back the lost identity, nearest first.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracking.particle.bank import Starved


class LostIdentities:
    """The identities of starved filters (:class:`~.bank.Starved`) for ``duration`` [s]
    after their last support, claimed by new filters within ``distance`` [m]."""

    def __init__(self, distance: float, duration: float) -> None:
        self.distance = distance
        self.duration = duration
        self._ids = np.empty(0, dtype=np.int64)
        self._born = np.empty(0)
        self._seen = np.empty(0)
        self._anchors = np.empty((0, 2))
        self._velocities = np.empty((0, 2))

    def __len__(self) -> int:
        return int(self._ids.size)

    def add(self, starved: Starved) -> None:
        """Remember the starved filters that have a recorded position."""
        if self.duration <= 0.0:
            return
        ok = np.isfinite(starved.anchors).all(axis=1)
        vel = np.where(np.isfinite(starved.velocities), starved.velocities, 0.0)
        self._ids = np.concatenate([self._ids, starved.ids[ok]])
        self._born = np.concatenate([self._born, starved.born[ok]])
        self._seen = np.concatenate([self._seen, starved.last_seen[ok]])
        self._anchors = np.concatenate([self._anchors, starved.anchors[ok]])
        self._velocities = np.concatenate([self._velocities, vel[ok]])

    def claim(self, positions: NDArray[np.float64], stamp: float) -> list[tuple[int, int, float]]:
        """For new filters at ``positions`` (K, 2) [m] at ``stamp`` [s]: (new filter index,
        identity, birth time) for each one that takes back a lost identity, nearest pairs
        first, each identity once; the claimed and the expired ones are forgotten."""
        fresh = stamp - self._seen <= self.duration
        self._keep(fresh)
        if len(self) == 0 or len(positions) == 0:
            return []
        a = self._anchors
        b = a + self._velocities * (stamp - self._seen)[:, None]
        d = _segment_distance(np.asarray(positions, dtype=np.float64), a, b)  # (K, L)
        out: list[tuple[int, int, float]] = []
        used = np.zeros(len(self), dtype=bool)
        for flat in np.argsort(d, axis=None, kind="stable"):
            k, j = divmod(int(flat), d.shape[1])
            if d[k, j] > self.distance:
                break
            if used[j] or any(k == o[0] for o in out):
                continue
            used[j] = True
            out.append((k, int(self._ids[j]), float(self._born[j])))
        self._keep(~used)
        return out

    def _keep(self, mask: NDArray[np.bool_]) -> None:
        self._ids = self._ids[mask]
        self._born = self._born[mask]
        self._seen = self._seen[mask]
        self._anchors = self._anchors[mask]
        self._velocities = self._velocities[mask]


def _segment_distance(
    p: NDArray[np.float64], a: NDArray[np.float64], b: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Distances (K, L) [m] from points ``p`` (K, 2) to the segments ``a`` -> ``b`` (L, 2)."""
    ab = b - a  # (L, 2)
    ap = p[:, None, :] - a[None, :, :]  # (K, L, 2)
    den = np.einsum("lc,lc->l", ab, ab)
    t = np.where(den > 0.0, np.einsum("klc,lc->kl", ap, ab) / np.maximum(den, 1e-300), 0.0)
    t = np.clip(t, 0.0, 1.0)
    q = a[None, :, :] + t[..., None] * ab[None, :, :]
    return np.asarray(np.hypot(*(p[:, None, :] - q).transpose(2, 0, 1)), dtype=np.float64)


__all__ = ["LostIdentities"]
