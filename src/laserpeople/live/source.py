"""A live source: scans as they arrive -> frames for the pipeline, with bounded latency.

:class:`LiveScans` sits between the transport's receiving thread and the pipeline:

- **Keep newest per laser**: each laser has a queue of at most ``depth`` scans (default 1
  with one laser, 2 with several).
  A scan arriving at a full queue pushes out the oldest one, which is *dropped* and counted
  (:attr:`LiveCounts.dropped`), so a slow tracker never builds a backlog: it always works
  on the newest scans.
- **No waiting for order**: the oldest queued scan (by stamp) leaves as soon as the
  pipeline takes one; with several lasers the grouping waits for the other lasers' scans
  of an instant instead (:class:`~laserpeople.live.grouping.LiveGrouper`: a frame closes as
  soon as every laser has delivered, at most ``order_wait`` after its reference scan, and
  only once no received scan waits in a queue).
- **Poses**: a scan's pose comes from :class:`~laserpeople.live.poses.LiveTransforms`;
  when the transforms have no sample at or after the scan's stamp yet, the scan waits for
  one up to ``tf_wait`` seconds (as a ROS tf message filter does), then takes what there is
  (the last sample, within the pose tolerance).
- **Time jumps**: a scan whose stamp is more than ``jump_back`` seconds before the previous
  scan of its laser (a bag replayed in a loop, a clock reset), or more than ``jump_ahead``
  seconds after it, raises :class:`TimeJump`; the run resets tracking and says so
  (:class:`~laserpeople.live.runner.LiveRun`) instead of letting every track die silently.

:class:`LiveFrames` turns the scans into frames as a recording's are made
(:func:`~laserpeople.pipeline.sources.laser_frames` for one laser,
:class:`~laserpeople.live.grouping.LiveGrouper` for several, which closes a frame as soon as
it is complete instead of when the next one starts,
:class:`~laserpeople.pipeline.sources.FrameChooser` for the coordinate frame), except that
``auto`` decides as the frames come instead of from a look-ahead window
(:mod:`laserpeople.live.choice`).
"""

from __future__ import annotations

import itertools
import threading
import time
from collections import Counter, deque
from collections.abc import Callable, Generator, Iterator, Sequence
from dataclasses import dataclass, field, replace

from laserpeople.errors import ConfigError
from laserpeople.frame import Frame
from laserpeople.live.choice import FrameDecision, FrameSwitch
from laserpeople.live.grouping import LiveGrouper
from laserpeople.live.poses import LiveTransforms
from laserpeople.pipeline.sources import FUSED, FrameChooser, GroupingParams, laser_frames
from laserpeople.samples import Samples
from laserpeople.scan import Scan

SEVERAL_LASERS_DEPTH = 2
"""Default queue per laser with several lasers. Each pass of the tracker takes one scan of
every laser, so a pass delayed by more than one scan period (a loaded computer) drops a
scan of every laser with a queue of 1; measured on the MiR bag (2 lasers at 12.7 Hz, 2
loaded cores): 15-61 scans of 590 dropped with 1, 0-1 with 2."""

MAX_ARRIVALS = 4096
"""Arrival times kept for scans not yet published (scans that no frame takes are forgotten
after this many)."""


class TimeJump(Exception):  # noqa: N818 (a signal to the run, not an error)
    """A laser's stamps jumped; the scan that jumped is put back for the next run.

    Attributes:
        topic: The laser.
        previous: Stamp of its previous scan [s].
        stamp: Stamp of the scan that jumped [s].
    """

    def __init__(self, topic: str, previous: float, stamp: float) -> None:
        self.topic, self.previous, self.stamp = topic, previous, stamp
        super().__init__(
            f"{topic}: stamp jumped {stamp - previous:+.3f} s (from {previous:.3f} to "
            f"{stamp:.3f}); tracking reset"
        )


SILENT_PERIODS = 10
"""Mean scan periods without a scan after which a laser counts as having stopped (a scan
or two lost on the link is not a stop)."""
SILENT_MIN = 1.0
"""Shortest silence [s] counted as a stop, whatever the scan rate."""
DROPPED_WARN = 0.01
"""Share of a laser's scans dropped (queue full) from which the summary warns: a scan or
two dropped while the computer was busy is no news; a tracker that falls behind the laser
drops a steady share, and the tracks then skip those scans."""


@dataclass
class LiveCounts:
    """What arrived and what was dropped, per laser.

    Attributes:
        received: Scans received.
        dropped: Scans pushed out of a full queue before the pipeline took them.
        taken: Scans the pipeline took.
        undecodable: Messages that were not valid scans (each one reported once per
            topic in :attr:`errors`).
        without_pose: Scans taken without a pose (world frame wanted; see ``reasons``).
        waited_for_tf: Scans that waited for a transform [count].
        tf_timeouts: Scans whose wait ran out: their pose is the last transform held (within
            the pose tolerance) rather than interpolated.
        resets: Time jumps that reset tracking.
        errors: The first decoding error per topic.
        reasons: Why scans had no pose, counted.
        first_arrival: Arrival time of each laser's first scan [s] (the source's clock).
        last_arrival: Arrival time of each laser's latest scan [s].
    """

    received: Counter[str] = field(default_factory=Counter)
    dropped: Counter[str] = field(default_factory=Counter)
    taken: Counter[str] = field(default_factory=Counter)
    undecodable: Counter[str] = field(default_factory=Counter)
    without_pose: Counter[str] = field(default_factory=Counter)
    waited_for_tf: int = 0
    tf_timeouts: int = 0
    resets: int = 0
    errors: dict[str, str] = field(default_factory=dict)
    reasons: Counter[str] = field(default_factory=Counter)
    first_arrival: dict[str, float] = field(default_factory=dict)
    last_arrival: dict[str, float] = field(default_factory=dict)

    def dropped_warning(self, laser: str, tracking_ms: float) -> str:
        """A warning when more than :data:`DROPPED_WARN` of ``laser``'s scans were dropped,
        with the laser's mean scan period against ``tracking_ms`` (the tracker's median
        time per frame [ms]); empty otherwise."""
        n, dropped = self.received[laser], self.dropped[laser]
        if not n or dropped <= DROPPED_WARN * n:
            return ""
        every = self.mean_period(laser)
        period = f" against a scan every {1e3 * every:.1f} ms" if every else ""
        return (
            f"{laser}: {dropped} of {n} scans ({dropped / n:.0%}) were dropped, not tracked: "
            f"the tracking did not keep up (median {tracking_ms:.2f} ms a frame{period}), so "
            "the tracks skip them; a lighter tracker, fewer lasers or a less loaded computer "
            "keeps up"
        )

    def mean_period(self, laser: str) -> float | None:
        """``laser``'s mean time between scans [s] from their arrivals (None before two)."""
        n = self.received[laser]
        if n < 2:
            return None
        return (self.last_arrival[laser] - self.first_arrival[laser]) / (n - 1)

    def silence(self, laser: str, end: float) -> float | None:
        """How long [s] ``laser`` had been silent at ``end`` when that is longer than
        :data:`SILENT_PERIODS` of its mean scan period and :data:`SILENT_MIN` (its driver,
        the robot or the link stopped publishing); None otherwise, or before two scans."""
        period = self.mean_period(laser)
        if period is None:
            return None
        quiet = end - self.last_arrival[laser]
        return quiet if quiet > max(SILENT_MIN, SILENT_PERIODS * period) else None


@dataclass
class LiveTimings:
    """Where a frame's time goes, from the arrival of a scan to the publication of its
    frame (all on the ``clock`` of :class:`LiveScans`, in ms).

    Attributes:
        queued_ms: Per scan: arrival -> taken from its laser's queue (waiting for the
            pipeline).
        tf_ms: Per scan: taken -> its pose known (waiting for a transform).
        grouped_ms: Per frame: its last scan posed -> the frame given out (waiting for the
            other lasers' scans of the instant, or for a later scan to close the frame).
        tracked_ms: Per published frame: given out -> its tracks published (tracking,
            encoding, publishing, the other sinks).
    """

    queued_ms: Samples = field(default_factory=Samples)
    tf_ms: Samples = field(default_factory=Samples)
    grouped_ms: Samples = field(default_factory=Samples)
    tracked_ms: Samples = field(default_factory=Samples)

    def summary(self) -> str:
        """One line: median and p99 of each step [ms]."""
        parts = [
            f"{name} {values.quantile(0.5):.1f} / {values.quantile(0.99):.1f}"
            for name, values in (
                ("queued", self.queued_ms),
                ("tf", self.tf_ms),
                ("grouping", self.grouped_ms),
                ("tracking and publishing", self.tracked_ms),
            )
        ]
        return "where the time went, median / p99 ms: " + ", ".join(parts)


@dataclass
class _Queued:
    scan: Scan
    frame_id: str
    arrival: float


class LiveScans:
    """Thread-safe per-laser bounded queues between a receiver and the pipeline.

    Args:
        topics: The laser topics, in the order of ``--topic`` (the first is the reference
            laser of fused frames).
        transforms: Pose source (None: no poses, sensor frame).
        depth: Scans kept per laser (the newest); older ones are dropped and counted (None:
            1 with one laser, :data:`SEVERAL_LASERS_DEPTH` with several).
        tf_wait: Longest wait for a transform covering a scan's stamp [s].
        order_wait: Several lasers: longest wait of a frame for the other lasers' scans of
            its instant, after its reference scan arrived [s] (None: one scan period of the
            slowest other laser, measured).
        jump_back: A stamp this much before the previous one of its laser is a time jump [s].
        jump_ahead: A stamp this much after the previous one of its laser is a time jump [s].
        clock: Monotonic clock for arrival times [s] (``time.monotonic``).
    """

    def __init__(
        self,
        topics: Sequence[str],
        transforms: LiveTransforms | None = None,
        *,
        depth: int | None = None,
        tf_wait: float = 0.1,
        order_wait: float | None = None,
        jump_back: float = 0.5,
        jump_ahead: float = 30.0,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        if not topics:
            raise ConfigError("give at least one laser topic")
        if depth is None:
            depth = 1 if len(topics) == 1 else SEVERAL_LASERS_DEPTH
        if depth < 1:
            raise ConfigError("the queue depth per laser must be at least 1")
        self.topics = tuple(topics)
        self.transforms = transforms
        self.depth = depth
        self.tf_wait = tf_wait
        self.order_wait = order_wait
        self.jump_back = jump_back
        self.jump_ahead = jump_ahead
        self.clock = clock
        self.counts = LiveCounts()
        self.timings = LiveTimings()
        self.ready: dict[tuple[str, int], float] = {}
        """When each scan taken and not yet in a frame had its pose [s, ``clock``]."""
        self.given: dict[tuple[str, int], float] = {}
        """When each frame not yet published was given out, by its first scan [s, ``clock``]."""
        self.arrivals: dict[tuple[str, int], float] = {}
        """Arrival time [s, ``clock``] per (laser, scan index) of the scans taken and not
        yet published."""
        self._queues: dict[str, deque[_Queued]] = {t: deque() for t in self.topics}
        self._index: Counter[str] = Counter()
        self._last: dict[str, float] = {}
        self._newest: dict[str, float] = {}
        self._pushed_back: _Queued | None = None
        self._cond = threading.Condition()
        self._closed = False
        self._finished = False
        self.limit: int | None = None
        """Scans to receive before the input ends (None: no limit); later ones are ignored."""
        self.lookup_poses = transforms is not None
        """Whether scans get poses (False once the run works in the sensor frame: no lookup,
        no wait for transforms)."""
        self.undecided = False
        """Whether the run's frame is still being chosen: a scan then waits for a transform
        only once some transform has come, and at most until ``tf_wait`` after the first
        scan's arrival (not ``tf_wait`` each)."""
        self.first_arrival: float | None = None
        """Arrival of the first scan given out [s, ``clock``]."""
        self.last_reason = ""
        """Why the last scan without a pose has none."""

    def now(self) -> float:
        """The clock's time [s]."""
        return float(self.clock())

    def next_index(self, topic: str) -> int:
        """The index the next scan of ``topic`` gets (0-based count of scans received)."""
        return self._index[topic]

    def put(self, scan: Scan, frame_id: str) -> None:
        """Add a received scan (from the receiving thread; its ``index`` is set to the count
        of scans of its laser before it); a full queue drops its oldest scan."""
        arrival = self.now()
        with self._cond:
            if self._finished or self._closed:
                return
            queue = self._queues[scan.sensor]
            scan = replace(scan, index=self._index[scan.sensor])
            self.counts.received[scan.sensor] += 1
            self.counts.first_arrival.setdefault(scan.sensor, arrival)
            self.counts.last_arrival[scan.sensor] = arrival
            self._index[scan.sensor] += 1
            if self.limit is not None and sum(self.counts.received.values()) >= self.limit:
                self._finished = True
            if len(queue) >= self.depth:
                queue.popleft()
                self.counts.dropped[scan.sensor] += 1
            queue.append(_Queued(scan, frame_id, arrival))
            self._newest[scan.sensor] = max(self._newest.get(scan.sensor, scan.stamp), scan.stamp)
            self._cond.notify_all()

    def waiting(self) -> int:
        """Scans received and not taken yet."""
        with self._cond:
            return sum(len(q) for q in self._queues.values()) + (self._pushed_back is not None)

    def undecodable(self, topic: str, error: str) -> None:
        """Count a message that was not a valid scan (the first error per topic is kept)."""
        with self._cond:
            self.counts.undecodable[topic] += 1
            self.counts.errors.setdefault(topic, error)

    def poke(self) -> None:
        """Wake a waiting :meth:`take` (a transform arrived, or the run stops)."""
        with self._cond:
            self._cond.notify_all()

    def finish(self) -> None:
        """End the input: scans already queued are still given out, then :meth:`take`
        returns None."""
        with self._cond:
            self._finished = True
            self._cond.notify_all()

    def close(self) -> None:
        """End :meth:`scans` now: the next take returns None (queued scans are left)."""
        with self._cond:
            self._closed = True
            self._cond.notify_all()

    @property
    def closed(self) -> bool:
        """Whether :meth:`close` was called."""
        return self._closed

    @property
    def finished(self) -> bool:
        """Whether the input ended (:meth:`finish`, or the scan limit was reached)."""
        return self._finished or self._closed

    def _oldest(self) -> str | None:
        best: str | None = None
        for topic, queue in self._queues.items():
            if queue and (best is None or queue[0].scan.stamp < self._queues[best][0].scan.stamp):
                best = topic
        return best

    def take(self, timeout: float | None = None) -> _Queued | None:
        """The oldest queued scan (by stamp, over the lasers), waiting for one; None when
        closed or after ``timeout`` seconds."""
        if self._pushed_back is not None:
            item, self._pushed_back = self._pushed_back, None
            return item
        deadline = None if timeout is None else self.now() + timeout
        with self._cond:
            while True:
                if self._closed:
                    return None
                topic = self._oldest()
                if topic is not None:
                    item = self._queues[topic].popleft()
                    self.counts.taken[topic] += 1
                    self.timings.queued_ms.append(1e3 * (self.now() - item.arrival))
                    return item
                if self._finished:
                    return None
                now = self.now()
                left = None if deadline is None else deadline - now
                if left is not None and left <= 0:
                    return None
                self._cond.wait(0.2 if left is None else min(left, 0.2))

    def push_back(self, item: _Queued) -> None:
        """Give ``item`` out again at the next :meth:`take` (the scan that jumped)."""
        self._pushed_back = item

    def _tf_deadline(self, item: _Queued) -> float | None:
        """Until when [s, ``clock``] a scan without a settled pose waits for transforms (None:
        it does not wait; see :attr:`undecided`)."""
        deadline = item.arrival + self.tf_wait
        if not self.undecided:
            return deadline
        if self.transforms is None or not self.transforms.samples:
            return None  # none has come: a robot without tf must not wait for the choice
        first = item.arrival if self.first_arrival is None else self.first_arrival
        deadline = min(deadline, first + self.tf_wait)
        return deadline if deadline > self.now() else None

    def _posed(self, item: _Queued) -> Scan:
        scan = item.scan
        if self.transforms is None or not self.lookup_poses:
            return scan
        pose, reason, settled = self.transforms.lookup(item.frame_id, scan.stamp)
        deadline = None if settled else self._tf_deadline(item)
        if deadline is not None:
            self.counts.waited_for_tf += 1
            with self._cond:
                while not settled and not self._closed:
                    left = deadline - self.now()
                    if left <= 0:
                        break
                    self._cond.wait(min(left, 0.01))
                    pose, reason, settled = self.transforms.lookup(item.frame_id, scan.stamp)
            if not settled:
                self.counts.tf_timeouts += 1
        if pose is None:
            self.counts.without_pose[scan.sensor] += 1
            self.counts.reasons[reason] += 1
            self.last_reason = reason
            return scan
        return replace(scan, pose=pose)

    def scans(self, deadline: Callable[[], float | None] = lambda: None) -> Iterator[Scan | None]:
        """Scans in the order taken, with poses, until :meth:`close`.

        Args:
            deadline: When the caller wants control back if no scan came [s, ``clock``]
                (None: not before a scan); None is then given instead of a scan.

        Raises:
            TimeJump: A laser's stamp jumped (the scan is pushed back first).
        """
        while True:
            until = deadline()
            item = self.take(None if until is None else max(0.0, until - self.now()))
            if item is None:
                if self.finished:
                    return
                yield None
                continue
            scan = item.scan
            previous = self._last.get(scan.sensor)
            if previous is not None and (
                scan.stamp < previous - self.jump_back or scan.stamp > previous + self.jump_ahead
            ):
                self._last.clear()
                self.counts.resets += 1
                self.push_back(item)
                raise TimeJump(scan.sensor, previous, scan.stamp)
            self._last[scan.sensor] = max(scan.stamp, previous or scan.stamp)
            if self.first_arrival is None:
                self.first_arrival = item.arrival
            self.arrivals[(scan.sensor, scan.index)] = item.arrival
            for kept in (self.arrivals, self.ready, self.given):
                while len(kept) > MAX_ARRIVALS:  # scans no frame published
                    del kept[next(iter(kept))]
            taken = self.now()
            posed = self._posed(item)
            ready = self.now()
            self.timings.tf_ms.append(1e3 * (ready - taken))
            self.ready[(scan.sensor, scan.index)] = ready
            yield posed

    def given_out(self, frame: Frame) -> None:
        """Time a frame given to the pipeline (:attr:`LiveTimings.grouped_ms`)."""
        now = self.now()
        ready = [self.ready.pop((s.sensor, s.index), None) for s in frame.scans]
        known = [r for r in ready if r is not None]
        if known:
            self.timings.grouped_ms.append(1e3 * (now - max(known)))
        if frame.scans:
            self.given[(frame.scans[0].sensor, frame.scans[0].index)] = now


class LiveFrames:
    """Frames from :class:`LiveScans`, made as a recording's are (iterate once per run).

    Args:
        scans: The live scans.
        decision: The run's frame choice (``auto``: decided as the frames come, see
            :mod:`laserpeople.live.choice`; kept across the run's pipelines).
        grouping: Grouping of several lasers.
        carry: Frames given out first (the frame that switched the run to the world frame).
        on_choice: Told the choice when ``auto`` makes it.
    """

    def __init__(
        self,
        scans: LiveScans,
        decision: FrameDecision,
        *,
        grouping: GroupingParams | None = None,
        carry: Sequence[Frame] = (),
        on_choice: Callable[[str], None] = lambda message: None,
    ) -> None:
        self.live = scans
        self.decision = decision
        self.topics = list(scans.topics)
        self.topic = self.topics[0] if len(self.topics) == 1 else FUSED
        self.grouper = (
            LiveGrouper(self.topics, grouping, wait=scans.order_wait)
            if len(self.topics) > 1
            else None
        )
        self.carry = tuple(carry)
        self.on_choice = on_choice
        self.chooser: FrameChooser | None = None
        """Places the frames once the frame is chosen (its counts of skipped frames)."""
        if decision.frame is not None:
            self.chooser = FrameChooser(decision.frame, 1)
        self.tracked_in_sensor = 0
        """Frames given out in the sensor frame while undecided (by this iteration)."""

    def __iter__(self) -> Iterator[Frame]:
        for frame in self._frames():
            self.live.given_out(frame)
            yield frame

    def _grouped(self, grouper: LiveGrouper) -> Iterator[Frame]:
        """Frames of several lasers, each given out as soon as it is complete or its wait
        ran out."""
        live = self.live
        try:
            for scan in live.scans(grouper.deadline):
                now = live.now()
                if scan is None:
                    yield from grouper.expire(now)
                    continue
                arrival = live.arrivals.get((scan.sensor, scan.index), now)
                yield from grouper.push(scan, arrival)
                if not live.waiting():  # the scans received are in: a wait may run out
                    yield from grouper.expire(live.now())
        except TimeJump:
            yield from grouper.flush()  # the frames still open are tracked before the reset
            raise
        yield from grouper.flush()

    def _frames(self) -> Iterator[Frame]:
        if self.grouper is None:
            made = laser_frames((s for s in self.live.scans() if s is not None), self.topic)
        else:
            made = self._grouped(self.grouper)
        frames = itertools.chain(self.carry, made)
        if self.decision.undecided:
            self.live.undecided = True
            first = yield from self._undecided(frames)
            if first is None:
                return
            frames = itertools.chain([first], frames)
        assert self.decision.frame is not None
        self.chooser = FrameChooser(self.decision.frame, 1)
        yield from self.chooser(frames)

    def _undecided(self, frames: Iterator[Frame]) -> Generator[Frame, None, Frame | None]:
        """Give out frames while the frame is not chosen (one laser: in the sensor frame;
        several: skipped); returns the frame that decided (None: the scans ended first).

        Raises:
            FrameSwitch: World was chosen after frames were given out in the sensor frame.
        """
        decision, live = self.decision, self.live
        for frame in frames:
            arrival = max(live.arrivals.get((s.sensor, s.index), live.now()) for s in frame.scans)
            world = live.transforms.world_frame if live.transforms is not None else None
            if decision.look(
                frame,
                arrival,
                reason=live.last_reason,
                world=world,
                posable=live.transforms is not None,
            ):
                live.undecided = False
                live.lookup_poses = decision.frame == "world"
                self.on_choice(decision.message)
                if decision.frame == "world" and self.tracked_in_sensor:
                    raise FrameSwitch(frame, decision.message)
                return frame
            if self.grouper is not None:
                decision.skipped += 1
                continue
            decision.sensor_frames += 1
            self.tracked_in_sensor += 1
            yield frame.with_fields(frame="sensor")
        return None

    def summary(self) -> list[str]:
        """Lines for the user: the frame used and why; the grouping figures."""
        decision = self.decision
        if decision.frame is None:
            lines = [
                f"no frame chosen: the run ended after {decision.looked_at} frames without a "
                f"sensor pose ({decision.sensor_frames} tracked in the sensor frame, "
                f"{decision.skipped} skipped)"
                if decision.looked_at
                else "no frames"
            ]
        elif self.chooser is not None and decision.requested == "auto":
            lines = [decision.message]
            stats = self.chooser.stats
            if stats.skipped_frames or stats.dropped_scans:
                lines.append(
                    f"{stats.skipped_frames} frames skipped and {stats.dropped_scans} scans "
                    "dropped for lack of a sensor pose"
                )
        else:
            lines = [self.chooser.stats.summary() if self.chooser else decision.message]
        if self.grouper is not None:
            lines.append(self.grouper.stats.summary())
        return lines


__all__ = [
    "SEVERAL_LASERS_DEPTH",
    "SILENT_MIN",
    "SILENT_PERIODS",
    "LiveCounts",
    "LiveFrames",
    "LiveScans",
    "LiveTimings",
    "TimeJump",
]
