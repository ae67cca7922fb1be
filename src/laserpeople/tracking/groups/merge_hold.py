"""Young merges reported as their two parents (an extension of 000 Sec. 4, reporting only).

Two parties walking past each other within d_P form one observation, and eq. 27 cannot
tell them from parties that meet (docs/groups.md "Merges compare velocities over 1 s"), so
the best hypothesis merges them. While a merge is younger than ``seconds``, the groups it
merged are reported in its place, each where the merged observation's points nearest to
its prediction lie (constant velocity from where it was last reported), with its own id,
velocity and size. A merge that persists is reported from then on. The MHT (hypotheses,
scores, pruning) does not see any of this.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True)
class Reported:
    """One group reported in one scan.

    Attributes:
        track_id: The id it is reported with.
        family: Its track family in the MHT.
        name: Its internal label set (roots are families of groups born from observations).
        mean: State (5,): x, y [m], vx, vy [m/s], n [people].
        cov: Covariance (5, 5).
        members: Frame point indices (K,) it was matched with this scan (empty: occluded).
        event: "split" or "merge" when a model made its family, else "".
        score: Its probability in the best hypothesis.
        stamp: Time of the scan [s].
    """

    track_id: int
    family: int
    name: tuple[str, ...]
    mean: FloatArray
    cov: FloatArray
    members: IntArray
    event: str
    score: float
    stamp: float


def _roots(name: tuple[str, ...]) -> set[str]:
    return {label.partition("-")[0] for label in name}


class MergeHold:
    """Reports the parents of merges younger than ``seconds`` (see the module doc).

    Remembers the groups reported in the last scan and, per held merge, its parents: both
    bounded by the groups reported now.
    """

    def __init__(self, seconds: float, remade: bool = False) -> None:
        self.seconds = seconds
        self.remade = remade
        self._since: dict[int, float] = {}  # held parent family -> since when [s]
        self._last: dict[int, Reported] = {}  # family -> as reported in the last scan
        self._held: dict[int, tuple[float, list[Reported]]] = {}  # merge -> (born, parents)
        self.held_scans = 0
        """Merged group-scans reported as their parents."""

    def apply(self, stamp: float, reports: list[Reported], points: FloatArray) -> list[Reported]:
        """The groups to report for one scan: ``reports`` (the tracker's, in order) with
        each merge younger than ``seconds`` replaced by its parents. ``points`` (N, 2) [m]
        are the frame's points the members index."""
        if self.seconds <= 0.0:
            return reports
        families = {r.family for r in reports}
        ids = {r.track_id for r in reports}
        out: list[Reported] = []
        held: dict[int, tuple[float, list[Reported]]] = {}
        for r in reports:
            entry = self._held.get(r.family)
            if entry is None and r.event == "merge" and r.family not in self._last:
                roots = _roots(r.name)
                parents = [
                    p
                    for f, p in self._last.items()
                    if f not in families and _roots(p.name) <= roots
                ]
                if len(parents) >= 2:
                    # held already (the best hypothesis made their merge anew): since then
                    since = [self._since.get(p.family, stamp) for p in parents]
                    entry = (min(since) if self.remade else stamp, parents)
            if entry is not None and any(
                p.track_id in ids or p.family in families for p in entry[1]
            ):
                entry = None  # a parent (or its id) is back in the best hypothesis
            if entry is None or stamp - entry[0] >= self.seconds:
                out.append(r)
                continue
            parents = self._follow(stamp, r, entry[1], points)
            held[r.family] = (entry[0], parents)
            out.extend(parents)
            self.held_scans += 1
        self._held = held
        self._since = {p.family: b for b, ps in held.values() for p in ps}
        self._last = {r.family: r for r in out}
        return out

    @staticmethod
    def _follow(
        stamp: float, merged: Reported, parents: list[Reported], points: FloatArray
    ) -> list[Reported]:
        """The parents moved to this scan: each at the centroid of the merged group's
        points nearest to its constant-velocity prediction (at the prediction when none)."""
        predicted = np.array([p.mean[:2] + p.mean[2:4] * (stamp - p.stamp) for p in parents])
        pts = points[merged.members] if len(merged.members) else np.empty((0, 2))
        nearest = (
            np.argmin(((pts[:, None, :] - predicted[None, :, :]) ** 2).sum(axis=2), axis=1)
            if len(pts)
            else np.empty(0, dtype=np.int64)
        )
        out = []
        for k, p in enumerate(parents):
            mine = nearest == k
            mean = p.mean.copy()
            mean[:2] = pts[mine].mean(axis=0) if mine.any() else predicted[k]
            out.append(
                Reported(
                    p.track_id,
                    p.family,
                    p.name,
                    mean,
                    p.cov,
                    merged.members[mine] if len(pts) else merged.members,
                    p.event,
                    merged.score,
                    stamp,
                )
            )
        return out


__all__ = ["MergeHold", "Reported"]
