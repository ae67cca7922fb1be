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
A coasted report has score 0 (it is in no hypothesis) and carries its last
size, velocity, covariance, labels and contour (moved with it), and no points: the
clustering error, the group size scored on points and the MHT are unchanged.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

from laserpeople.tracks import Track


class CoastedReports:
    """The last report of every group id of the last ``seconds``, and the ones to coast."""

    def __init__(self, seconds: float, merged_seconds: float = 0.0) -> None:
        self.seconds = seconds
        self.merged_seconds = merged_seconds
        self._last: dict[int, tuple[float, Track]] = {}  # id -> (time [s], its last report)
        self._first: dict[int, float] = {}  # id -> time [s] of its first report remembered

    def __len__(self) -> int:
        return len(self._last)

    def __contains__(self, track_id: object) -> bool:
        """Whether the last report of group ``track_id`` is remembered: reported within
        :attr:`memory` before the last :meth:`record` and neither seen gone nor coasted past
        its time since (it may still not be coasted now: reported for less time than it
        has been gone)."""
        return track_id in self._last

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
            shift = track.velocity * age
            moved = dataclasses.replace(
                track, position=track.position + shift, contour=track.contour + shift, score=0.0
            )
            if (gone is not None and gone(moved)) or (
                age > self.seconds
                and (age > self.merged_seconds or among is None or not among(moved))
            ):
                del self._last[track_id], self._first[track_id]
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
        self._last = {i: v for i, v in self._last.items() if stamp - v[0] <= self.memory}
        self._first = {i: v for i, v in self._first.items() if i in self._last}


__all__ = ["CoastedReports"]
