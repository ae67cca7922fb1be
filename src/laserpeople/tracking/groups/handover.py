"""Reported ids handed over to the groups that take a vanished group's place (an extension
of 000 Sec. 4, for the group tracker's reports only).

In 000 every split, merge and birth starts a new track, so a party that walks past another
is reported under a new id when the two are merged, and under two more when they part; a
party hidden for longer than its track lives comes back under a new id. Here a group first
reported in a scan may take the id of a group reported within the last ``memory`` seconds
and not reported now, when the vanished group's constant-velocity prediction lies within
``gate`` of it: the merged group takes the id of the nearer of the two it merged, each half
of a split the id of the party it came nearest to (the group that was split, or one merged
into it before). Pairs are taken nearest first; each vanished id goes to one group at most.

The tracker (:class:`~laserpeople.tracking.groups.GroupMHTTracker`) also reports a new
group near a vanished one at once instead of after ``confirm_scans`` (it continues a group
the user saw), and lets a new group within ``gate`` of a reported group that is coasting
(unseen this scan) take that group's place: the party the MHT took up again under a new
track. The MHT does not see any of this; only which groups are reported, and their ids,
change.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Vanished:
    """Where a reported id was last seen.

    Attributes:
        stamp: Time of its last report [s].
        position: Its position then (2,) [m].
        velocity: Its velocity then (2,) [m/s].
    """

    stamp: float
    position: FloatArray
    velocity: FloatArray

    def predicted(self, stamp: float) -> FloatArray:
        """Its constant-velocity position at ``stamp`` [s] (2,) [m]."""
        return self.position + self.velocity * (stamp - self.stamp)


class IdHandover:
    """Remembers the reported ids of the last ``memory`` seconds and hands the vanished ones
    to new groups within ``gate`` of their predictions (see the module doc)."""

    def __init__(self, memory: float, gate: float) -> None:
        self.memory = memory
        self.gate = gate
        self._last: dict[int, Vanished] = {}  # reported id -> its last report

    def __len__(self) -> int:
        return len(self._last)

    def hand_over(self, stamp: float, new: list[FloatArray], current: set[int]) -> list[int | None]:
        """For the positions ``new`` [m] of groups first reported at ``stamp`` [s], the
        vanished id each takes, or None; ``current`` holds the ids reported in this scan
        already (never handed over)."""
        out: list[int | None] = [None] * len(new)
        if self.memory <= 0.0 or not new:
            return out
        gone = [
            (i, v)
            for i, v in self._last.items()
            if i not in current and v.stamp < stamp and stamp - v.stamp <= self.memory
        ]
        pairs = sorted(
            (math.dist(at, v.predicted(stamp)), k, j)
            for k, at in enumerate(new)
            for j, (_, v) in enumerate(gone)
        )
        used: set[int] = set()
        for d, k, j in pairs:
            if d > self.gate:
                break
            if out[k] is None and j not in used:
                out[k] = gone[j][0]
                used.add(j)
        return out

    def near_vanished(self, stamp: float, position: FloatArray) -> bool:
        """True when a group not reported in the last scan recorded, reported within
        ``memory`` seconds of ``stamp`` [s], is predicted within ``gate`` of ``position``
        [m] (a new group there may take its id)."""
        if self.memory <= 0.0:
            return False
        last = max((v.stamp for v in self._last.values()), default=-math.inf)
        return any(
            v.stamp < last
            and stamp - v.stamp <= self.memory
            and math.dist(position, v.predicted(stamp)) <= self.gate
            for v in self._last.values()
        )

    def record(self, stamp: float, ids: list[int], states: list[FloatArray]) -> None:
        """Remember the ids reported at ``stamp`` [s] with their states (x, y, vx, vy, ...)
        and forget those last reported more than ``memory`` seconds before."""
        for i, s in zip(ids, states, strict=True):
            self._last[i] = Vanished(stamp, np.array(s[:2]), np.array(s[2:4]))
        self._last = {i: v for i, v in self._last.items() if stamp - v.stamp <= self.memory}


__all__ = ["IdHandover", "Vanished"]
