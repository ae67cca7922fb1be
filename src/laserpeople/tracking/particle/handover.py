"""Identities of lost feet filters handed to new filters (a departure from 004, whose
filters start with a new identity at every birth).

In a party on a coarse or slow laser, a filter loses its person (its feet drift off the
few points a far leg shows, and it dies ``miss_time`` later), and a second or so later a
birth finds the person again, under a new identity. 004's adapted MOTP matches each
person to one track trajectory for the whole recording (eq. 11), so the person counts as
lost for the shorter of the two. :class:`LostIdentities` keeps, per identity, where and
when its track was last reported; a new filter that starts within ``handover_distance`` +
``handover_speed`` x the time since of where a track no longer reported was last seen, at
most ``handover_time`` ago, takes over that identity (the nearest such one), and the old
filter, if it still coasts unreported, is removed.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


class LostIdentities:
    """Where [m] and when [s] each identity's track was last reported, and the nearest
    lost identity a new filter takes over.

    Args:
        time: Longest time since a lost track was last reported [s] (``handover_time``).
        distance: Reach at once [m] (``handover_distance``).
        speed: Growth of the reach with the time since [m/s] (``handover_speed``).
    """

    def __init__(self, time: float, distance: float, speed: float) -> None:
        self.time = time
        self.distance = distance
        self.speed = speed
        self._ids = np.empty(0, dtype=np.int64)
        self._positions = np.empty((0, 2))
        self._stamps = np.empty(0)
        self._born = np.empty(0)

    def reported(
        self,
        ids: NDArray[np.int64],
        positions: NDArray[np.float64],
        born: NDArray[np.float64],
        stamp: float,
    ) -> None:
        """Record the tracks reported at ``stamp`` [s]: identities ``ids`` (K,) at
        ``positions`` (K, 2) [m], their filters born at ``born`` (K,) [s]; identities
        last reported more than ``time`` ago are forgotten."""
        old = ~np.isin(self._ids, ids) & (stamp - self._stamps <= self.time)
        self._ids = np.concatenate([self._ids[old], ids])
        self._positions = np.concatenate([self._positions[old], positions.reshape(-1, 2)])
        self._stamps = np.concatenate([self._stamps[old], np.full(len(ids), stamp)])
        self._born = np.concatenate([self._born[old], born])

    def take(
        self, starts: NDArray[np.float64], shown: NDArray[np.int64], stamp: float
    ) -> list[tuple[int, float] | None]:
        """For new filters starting at ``starts`` (K, 2) [m] at ``stamp`` [s], in order:
        the (identity, birth stamp [s] of its filter) of the nearest lost identity in
        reach, or None; an identity in ``shown`` (reported in the last scan) is not lost,
        and each identity is taken once."""
        if self.time <= 0.0:
            return [None] * len(starts)
        since = stamp - self._stamps
        lost = (since > 0.0) & (since <= self.time) & ~np.isin(self._ids, shown)
        reach = self.distance + self.speed * since
        out: list[tuple[int, float] | None] = []
        for start in starts.reshape(-1, 2):
            d = np.hypot(*(self._positions - start).T) if len(self._ids) else np.empty(0)
            ok = np.flatnonzero(lost & (d <= reach))
            if ok.size == 0:
                out.append(None)
                continue
            k = int(ok[np.argmin(d[ok])])
            lost[k] = False
            out.append((int(self._ids[k]), float(self._born[k])))
        return out


__all__ = ["LostIdentities"]
