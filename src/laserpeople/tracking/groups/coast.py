"""Reported groups that vanish are reported a little longer at their predictions (an
extension of 000 Sec. 4, for the group tracker's reports only).

A reported group vanishes from the reports when its track is deleted (unseen for a few
scans: behind someone, out of view) or when a merge takes its points (a party walking past
another is merged with it for the scans of the pass; the merged group takes the id of the
nearer party). Here such a group is reported under its id at its constant-velocity
prediction from its last report, for up to ``seconds`` after it and no longer than it had
been reported (a group that flickered into the reports for a few scans is not carried on
for a second), unless its id is reported
again (the group is back, or a new group took its id: :mod:`.handover`), its group is in
the best hypothesis but hidden (on a static place), or the scan shows it gone (the laser saw
past every point of its predicted contour: nothing there; then it is not coasted again).
Hidden behind closer returns, among another group's points or out of view, it is coasted.
A group whose predicted contour touches the points of a group reported in this scan (a
merge took its points: a party walking past another, two parties standing side by side)
is coasted for up to ``merged_seconds`` instead, as long as it touches them; the first scan
it does not, it stops.
With ``follow_time`` a group coasted among another's points follows its share of them
(:func:`share_centres`: the points nearest to it rather than to the reported groups or the
other coasted ones): it is reported at that share's centre, and its velocity is smoothed
towards the share's motion with that time constant, so that its prediction stays with its
party through a long pass instead of drifting off at the velocity of its last report.
A coasted report has score 0 (it is in no hypothesis) and carries its last
size, covariance, labels and contour (moved with it), its last velocity (or the followed
one), and no points: the clustering error, the group size scored on points and the MHT are
unchanged.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracks import Track

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

SHARE_ROUNDS = 2
"""Rounds of :func:`share_centres` (nearest-centre partition, then each centre to its
share's mean): the first moves a coasted prediction onto its party's points, the second
settles the parts of the reported group it shares them with."""


def share_centres(
    points: FloatArray, centres: FloatArray, rounds: int = SHARE_ROUNDS
) -> tuple[FloatArray, BoolArray]:
    """Lloyd rounds over ``points`` (K, 2) [m] from ``centres`` (C, 2) [m]: each round every
    point goes to its nearest centre and every centre that got a point moves to their mean
    (a centre without points stays). Returns the centres after ``rounds`` (C, 2) and whether
    each got a point in the last round (C,)."""
    out = np.array(centres, dtype=np.float64, copy=True)
    held = np.zeros(len(out), dtype=bool)
    if not len(points) or not len(out):
        return out, held
    for _ in range(rounds):
        d2 = np.sum((points[:, None, :] - out[None, :, :]) ** 2, axis=2)
        nearest = np.argmin(d2, axis=1)
        counts = np.bincount(nearest, minlength=len(out))
        held = counts > 0
        for axis in range(2):
            sums = np.bincount(nearest, weights=points[:, axis], minlength=len(out))
            out[held, axis] = sums[held] / counts[held]
    return out, held


class CoastedReports:
    """The last report of every group id of the last ``seconds``, and the ones to coast."""

    def __init__(
        self, seconds: float, merged_seconds: float = 0.0, follow_time: float = 0.0
    ) -> None:
        self.seconds = seconds
        self.merged_seconds = merged_seconds
        self.follow_time = follow_time
        self._last: dict[int, tuple[float, Track]] = {}  # id -> (time [s], its last report)
        self._first: dict[int, float] = {}  # id -> time [s] of its first report remembered
        # id -> (time [s], position (2,) [m], velocity (2,) [m/s]) of its last followed share
        self._followed: dict[int, tuple[float, FloatArray, FloatArray]] = {}

    def __len__(self) -> int:
        return len(self._last)

    @property
    def memory(self) -> float:
        """How long a report is remembered [s]: the longer of the two times."""
        return max(self.seconds, self.merged_seconds)

    def coasted(
        self,
        stamp: float,
        reported: set[int],
        gone: Callable[[Track], bool] | None = None,
        among: Callable[[Track], bool] | None = None,
    ) -> list[Track]:
        """The groups to report at ``stamp`` [s] at their predictions: last reported within
        ``seconds`` before it (within ``merged_seconds`` while ``among`` is true of the
        prediction), and no longer before it than they had been reported up to then, and
        not among the ids ``reported`` (this scan's reports and the hidden groups'), oldest
        id first; a prediction for which ``gone`` is true, or which is older than
        ``seconds`` and not ``among``, is not reported, and its id is not coasted again
        until it is reported anew."""
        if self.memory <= 0.0:
            return []
        out = []
        for track_id, (at, track) in sorted(self._last.items()):
            age = stamp - at
            reported_for = at - self._first[track_id]
            if track_id in reported or not 0.0 < age <= min(self.memory, reported_for):
                continue
            followed = self._followed.get(track_id)
            if followed is None:
                velocity = track.velocity
                position = track.position + velocity * age
            else:
                at_share, share, velocity = followed
                position = share + velocity * (stamp - at_share)
            shift = position - track.position
            moved = dataclasses.replace(
                track,
                position=position,
                velocity=velocity,
                contour=track.contour + shift,
                score=0.0,
            )
            if (gone is not None and gone(moved)) or (
                age > self.seconds
                and (age > self.merged_seconds or among is None or not among(moved))
            ):
                del self._last[track_id], self._first[track_id]
                self._followed.pop(track_id, None)
                continue
            out.append(moved)
        return out

    def record(self, stamp: float, tracks: list[Track]) -> None:
        """Remember the groups of the best hypothesis reported at ``stamp`` [s] (not the
        coasted ones); forget those last reported more than :attr:`memory` before."""
        if self.memory <= 0.0:
            return
        for t in tracks:
            self._first.setdefault(t.track_id, stamp)
            self._last[t.track_id] = (stamp, t)
            self._followed.pop(t.track_id, None)
        self._last = {i: v for i, v in self._last.items() if stamp - v[0] <= self.memory}
        self._first = {i: v for i, v in self._first.items() if i in self._last}
        self._followed = {i: v for i, v in self._followed.items() if i in self._last}

    def follow(self, stamp: float, track: Track, share: FloatArray) -> Track:
        """``track``, coasted at ``stamp`` [s] among another group's points, moved to the
        centre ``share`` (2,) [m] of its share of them; its velocity moves towards the
        share's motion since the last followed share (or, the first time, since its
        prediction: none) by dt / ``follow_time`` (at most all the way), and its later
        predictions start from here (until it is reported again)."""
        followed = self._followed.get(track.track_id)
        velocity = np.asarray(track.velocity, dtype=np.float64)
        if followed is not None and stamp > followed[0]:
            at_share, last, velocity = followed
            dt = stamp - at_share
            gain = min(1.0, dt / self.follow_time) if self.follow_time > 0.0 else 1.0
            velocity = velocity + gain * ((share - last) / dt - velocity)
        share = np.array(share, dtype=np.float64, copy=True)
        self._followed[track.track_id] = (stamp, share, velocity)
        shift = share - track.position
        return dataclasses.replace(
            track, position=share, velocity=velocity, contour=track.contour + shift
        )


__all__ = ["SHARE_ROUNDS", "CoastedReports", "share_centres"]
