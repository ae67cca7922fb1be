"""Live grouping of several lasers: a frame closes as soon as every laser has delivered.

:class:`~laserpeople.pipeline.sources.LaserGrouper` groups a recording's scans, read in stamp
order, and gives a frame out when a scan newer than its stamp plus the tolerance comes. Live,
that scan is the next reference scan, one period later. :class:`LiveGrouper` takes the scans
as they arrive (each laser in stamp order, the lasers in any order) and makes the same
frames with less waiting:

- **Closed when complete.** A frame is given out as soon as every other laser has
  delivered a scan at least as new as the frame's reference scan. A laser's later scans
  are newer still, so none of them could be a closer match. The frame is the one
  ``LaserGrouper`` makes from the same scans.
- **Bounded wait.** A frame whose other lasers have not all delivered is given out
  ``wait`` seconds after its reference scan arrived, with the lasers that did deliver.
  By default ``wait`` is one scan period of the slowest other laser, measured on its
  stamps (the median of its last 20 intervals).
- **Late scans block nothing.** A scan that arrives after its frame was given out without
  its laser (within the tolerance of that frame's reference scan) is *late*: it is counted
  (:class:`LiveGroupingStats`) and no frame takes it. Putting it in the next frame instead
  would change the grouping of every frame after it (with two lasers at the same rate, a
  scan is often within the tolerance of two reference scans), and ``track`` on the
  recording, which does not hold the late scan, would then group differently from live.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

from laserpeople.frame import Frame
from laserpeople.pipeline.sources import GroupingParams, GroupingStats, LaserGrouper, _Open
from laserpeople.scan import Scan

FIRST_WAIT = 0.1
"""The wait [s] until the other lasers' periods are measured (two scans each)."""

PERIOD_SCANS = 20
"""Intervals over which a laser's period is measured (their median)."""

MAX_RECENT = 256
"""Other lasers' scans kept for frames to come (more: the reference laser is silent; the
oldest are counted unmatched)."""


@dataclass
class LiveGroupingStats(GroupingStats):
    """:class:`GroupingStats`, plus how live frames were closed.

    Attributes:
        complete: Frames given out with a scan of every laser.
        closed_by_wait: Frames given out when their wait ran out (a laser missing, or its
            scan of the instant not arrived yet).
        wait: The last wait used [s].
    """

    complete: int = 0
    closed_by_wait: int = 0
    wait: float = 0.0

    def summary(self) -> str:
        """Lines for the user: frames with every laser, with some, and where late scans
        went."""
        partial = self.frames - self.complete
        parts = [
            f"{self.frames} frames from {len(self.topics)} lasers: {self.complete} with every "
            f"laser, {partial} without some",
            f"{self.closed_by_wait} closed by the wait ({1e3 * self.wait:.1f} ms) instead of "
            "when every laser had delivered",
        ]
        for topic in self.topics[1:]:
            parts.append(
                f"{topic}: missing in {self.missing[topic]}, {self.late[topic]} late (came "
                f"after their frame left; in no frame), unmatched {self.unmatched[topic]}"
            )
        # the frames dropped and the largest offset, as for a recording
        parts += super().summary().split("; ")[len(self.topics) :]
        return "; ".join(parts)


@dataclass
class _Pending:
    frame: _Open
    deadline: float


class LiveGrouper(LaserGrouper):
    """Groups scans of several lasers into frames as they arrive (see the module notes).

    Feed each scan with :meth:`push`, call :meth:`expire` when no scan is waiting (at the
    latest when :meth:`deadline` passes), and :meth:`flush` at the end; each gives the frames
    closed, in stamp order.

    Args:
        topics: The lasers, the reference laser first.
        params: Tolerance and policy (as for a recording).
        wait: Longest wait of a frame for the other lasers after its reference scan arrived
            [s] (None: one period of the slowest other laser, measured).
    """

    def __init__(
        self,
        topics: Sequence[str],
        params: GroupingParams | None = None,
        *,
        wait: float | None = None,
    ) -> None:
        super().__init__(topics, params)
        self.stats: LiveGroupingStats = LiveGroupingStats(self.topics)
        self.fixed_wait = wait
        self._others = self.topics[1:]
        self._pending: deque[_Pending] = deque()
        self._recent: deque[Scan] = deque()  # other lasers' scans a later frame may take
        self._newest: dict[str, float] = {}
        self._periods: dict[str, deque[float]] = {
            t: deque(maxlen=PERIOD_SCANS) for t in self.topics
        }
        self._last_ref = -float("inf")
        self._timed_out: deque[tuple[float, frozenset[str]]] = deque(maxlen=8)

    def wait(self) -> float:
        """The wait now [s]: fixed, or one period of the slowest other laser."""
        if self.fixed_wait is not None:
            return self.fixed_wait
        periods = []
        for topic in self._others:
            intervals = self._periods[topic]
            if not intervals:
                return FIRST_WAIT
            periods.append(float(sorted(intervals)[len(intervals) // 2]))
        return max(periods)

    def _tolerance(self) -> float:
        """As for a recording; before the reference laser's period is measured (two scans),
        ``period_fraction`` of the wait (a frame closed then has no unbounded tolerance)."""
        tol = super()._tolerance()
        return tol if tol < float("inf") else self.params.period_fraction * self.wait()

    def deadline(self) -> float | None:
        """When the oldest open frame closes unless completed first [s, the caller's clock]
        (None: no frame open)."""
        return self._pending[0].deadline if self._pending else None

    def push(self, scan: Scan, arrival: float) -> list[Frame]:
        """Add a scan that arrived at ``arrival``; returns the frames it completed (a wait
        runs out only in :meth:`expire`: the caller first gives the scans already received,
        so that a slow tracker does not close frames whose scans are waiting in a queue)."""
        topic, t = scan.sensor, scan.stamp
        previous = self._newest.get(topic)
        if previous is not None and t > previous:
            self._periods[topic].append(t - previous)
            if topic == self.topics[0]:
                self._intervals.append(t - previous)
        self._newest[topic] = t if previous is None else max(previous, t)
        tol = self._tolerance()
        if topic == self.topics[0]:
            self._last_ref = max(self._last_ref, t)
            self._forget(tol)
            frame = _Open(scan)
            for other in self._recent:
                if abs(other.stamp - t) <= tol:
                    frame.candidates.setdefault(other.sensor, []).append(other)
            self.stats.wait = self.wait()
            self._pending.append(_Pending(frame, arrival + self.stats.wait))
        elif topic in self._others:
            if any(topic in lacking and t <= ref + tol for ref, lacking in self._timed_out):
                self.stats.late[topic] += 1
                return self.expire(None)
            for pending in self._pending:
                if abs(pending.frame.ref.stamp - t) <= tol:
                    pending.frame.candidates.setdefault(topic, []).append(scan)
            self._recent.append(scan)
            self._forget(tol)
        return self.expire(None)

    def expire(self, now: float | None) -> list[Frame]:
        """The frames closed by ``now``: in order, each complete one and each whose wait ran
        out (``now`` None: only the complete ones)."""
        out: list[Frame] = []
        while self._pending:
            head = self._pending[0]
            ref = head.frame.ref.stamp
            lacking = frozenset(o for o in self._others if self._newest.get(o, -float("inf")) < ref)
            if (lacking or not self._intervals) and (now is None or now < head.deadline):
                break  # (the tolerance is not known before two reference scans)
            self._pending.popleft()
            if lacking:
                self.stats.closed_by_wait += 1
                self._timed_out.append((ref, lacking))
            out.extend(self._close(head.frame))
        return out

    def flush(self) -> list[Frame]:
        """The frames still open (the input ended); the scans no frame took are counted."""
        out: list[Frame] = []
        while self._pending:
            out.extend(self._close(self._pending.popleft().frame))
        self._forget(float("inf"), everything=True)
        return out

    def _close(self, frame: _Open) -> Iterator[Frame]:
        for made in self._emit(frame):
            if len(made.scans) == len(self.topics):
                self.stats.complete += 1
            yield made

    def _forget(self, tol: float, everything: bool = False) -> None:
        """Drop other lasers' scans no later frame can take (stamp more than ``tol`` before
        the newest reference scan); count those no frame took as unmatched."""
        while self._recent and (
            everything
            or self._recent[0].stamp < self._last_ref - tol
            or len(self._recent) > MAX_RECENT
        ):
            old = self._recent.popleft()
            if (
                not everything
                and len(self._recent) <= MAX_RECENT
                and any(
                    c is old for p in self._pending for c in p.frame.candidates.get(old.sensor, ())
                )
            ):
                self._recent.appendleft(old)  # an open frame may still take it
                break
            if id(old) not in self._used:
                self.stats.unmatched[old.sensor] += 1
            self._used.discard(id(old))


__all__ = ["FIRST_WAIT", "MAX_RECENT", "LiveGrouper", "LiveGroupingStats"]
