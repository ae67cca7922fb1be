"""Sources: where frames come from.

A source is any iterable of :class:`~laserpeople.frame.Frame` whose frames carry ``scans``
(one per laser), in time order. Three pieces make one from a recording:

- :func:`laser_frames`: one laser, one frame per scan (``index`` = the scan's index).
- :class:`LaserGrouper`: several lasers as one: the scans of every laser are grouped by
  time around the scans of the first (reference) laser, with a tolerance; a laser with no
  scan within the tolerance is *missing* from that frame, a scan that arrives after its
  frame was given out is *late*, one that no frame takes is *unmatched*; all counted
  (:class:`GroupingStats`). Its latency is bounded: a frame leaves as soon as a scan newer
  than its stamp plus the tolerance has arrived.
- :class:`FrameChooser`: fixes the coordinate frame of every frame for the whole run:
  ``world`` when most frames of a look-ahead window have sensor poses, else ``sensor``;
  in the world frame, scans without a pose are dropped from their frame and frames left
  without any scan are skipped, both counted.

A live source (a ROS system, a scanner driver) is the same thing: a generator of frames
built from scans as they arrive; see ``docs/architecture.md``.
"""

from __future__ import annotations

import itertools
from collections import Counter, deque
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from os import PathLike
from typing import Literal, TypeVar

from laserpeople.config import param
from laserpeople.errors import ConfigError
from laserpeople.frame import Frame
from laserpeople.scan import CoordinateFrame, Scan

FUSED = "fused"
"""The topic of frames made of several lasers."""


@dataclass(frozen=True)
class GroupingParams:
    """How scans of several lasers are grouped into frames."""

    config_section = "grouping"

    tolerance: float = param(
        0.0,
        "our choice: automatic (see period_fraction)",
        "a laser's scan joins the reference scan's frame when their stamps differ by at "
        "most this; 0 = period_fraction of the reference laser's scan period",
        "s",
    )
    period_fraction: float = param(
        0.6,
        "measured (docs/recording.md): MiR back laser 30-43 ms after the front one; 0.6 of the "
        "period leaves no frame without it",
        "with tolerance 0: the tolerance as a fraction of the reference laser's median "
        "scan period (over its last 20 scans)",
    )
    policy: str = param(
        "partial",
        "assumption",
        "a frame with a laser missing: 'partial' keeps it with the lasers present, "
        "'complete' drops it",
    )

    def __post_init__(self) -> None:
        if not self.tolerance >= 0:
            raise ValueError("grouping tolerance must be non-negative")
        if not 0 < self.period_fraction <= 1:
            raise ValueError("grouping period_fraction must be in (0, 1]")
        if self.policy not in ("partial", "complete"):
            raise ValueError("grouping policy must be 'partial' or 'complete'")


@dataclass
class GroupingStats:
    """What the grouping did, per laser.

    Attributes:
        topics: The lasers, reference first.
        frames: Frames given out.
        dropped_frames: Frames dropped for a missing laser (policy ``complete``).
        missing: Frames without a scan of each laser.
        late: Scans that arrived after the frame they belong to had left.
        unmatched: Scans no frame took (a second scan within one reference period, or
            none within the tolerance).
        max_offset: Largest |stamp - reference stamp| of a grouped scan [s].
        tolerance: The tolerance used last [s].
    """

    topics: tuple[str, ...]
    frames: int = 0
    dropped_frames: int = 0
    missing: Counter[str] = field(default_factory=Counter)
    late: Counter[str] = field(default_factory=Counter)
    unmatched: Counter[str] = field(default_factory=Counter)
    max_offset: float = 0.0
    tolerance: float = 0.0

    def summary(self) -> str:
        """One line for the user."""
        parts = [f"{self.frames} frames from {len(self.topics)} lasers"]
        for topic in self.topics[1:]:
            parts.append(
                f"{topic}: missing in {self.missing[topic]}, late {self.late[topic]}, "
                f"unmatched {self.unmatched[topic]}"
            )
        if self.dropped_frames:
            parts.append(f"{self.dropped_frames} frames dropped for a missing laser")
        parts.append(
            f"largest offset {1e3 * self.max_offset:.1f} ms "
            f"(tolerance {1e3 * self.tolerance:.1f} ms)"
        )
        return "; ".join(parts)


_Item = TypeVar("_Item", Scan, Frame)


def _checked(
    given: object, function: str, name: str, kind: type[_Item], hint: str
) -> Iterator[_Item]:
    """The items of ``given`` (the argument ``name`` of ``function``: an iterable of
    ``kind``), each checked to be a ``kind`` as it is taken (a type test per item).

    Raises:
        TypeError: ``given`` is a lone scan or frame, a path or no iterable (at once), or
            an item is no ``kind`` (when it is reached); names the function, the argument,
            what it takes and, for a scan or frame in the wrong place, what to do
            (``hint``).
    """
    expects = f"{function}(): {name} must be an iterable of {kind.__name__}"
    if isinstance(given, Scan | Frame):
        what = type(given).__name__
        todo = f"give a list of it, [{what.lower()}]" if isinstance(given, kind) else hint
        raise TypeError(f"{expects}, got one {what}: {todo}")
    if isinstance(given, str | bytes | PathLike):
        raise TypeError(
            f"{expects}, got the path {str(given)!r}: read its scans first, "
            "open_recording(path).scans()"
        )
    try:
        items = iter(given)  # type: ignore[call-overload]
    except TypeError:
        raise TypeError(f"{expects}, got {type(given).__name__} {given!r:.40}") from None

    def checked() -> Iterator[_Item]:
        for number, item in enumerate(items):
            if not isinstance(item, kind):
                todo = f": {hint}" if isinstance(item, Scan | Frame) else ""
                raise TypeError(
                    f"{expects}, got an item of type {type(item).__name__} (item {number}){todo}"
                )
            yield item

    return checked()


def laser_frames(scans: Iterable[Scan], topic: str | None = None) -> Iterator[Frame]:
    """One frame per scan of one laser (``index`` and ``stamp`` are the scan's).

    Raises:
        TypeError: ``scans`` is one scan, a path or no iterable (at the call), or holds
            what is no :class:`~laserpeople.scan.Scan` (when it is reached); names what it
            takes.
    """
    checked = _checked(scans, "laser_frames", "scans", Scan, "it takes scans, not frames")
    return _laser_frames(checked, topic)


def _laser_frames(scans: Iterator[Scan], topic: str | None) -> Iterator[Frame]:
    for scan in scans:
        yield Frame(
            index=scan.index,
            stamp=scan.stamp,
            scans=(scan,),
            topic=topic or scan.sensor,
            sensor_pose=scan.pose,
        )


@dataclass
class _Open:
    ref: Scan
    candidates: dict[str, list[Scan]] = field(default_factory=dict)


class LaserGrouper:
    """Groups the time-ordered scans of several lasers into frames (see the module notes).

    Frame ``index`` and ``stamp`` are those of the reference laser's scan (the first topic),
    so a fused tracks CSV lines up with that laser's scans.
    """

    def __init__(self, topics: Sequence[str], params: GroupingParams | None = None) -> None:
        if len(topics) < 2:
            raise ConfigError("grouping needs at least two laser topics")
        self.topics = tuple(topics)
        self.params = params or GroupingParams()
        self.stats = GroupingStats(self.topics)
        self._used: set[int] = set()
        self._intervals: deque[float] = deque(maxlen=20)

    def _tolerance(self) -> float:
        """The tolerance now [s]: fixed, or a fraction of the reference period (infinite
        until two reference scans have been seen)."""
        if self.params.tolerance > 0:
            return self.params.tolerance
        if not self._intervals:
            return float("inf")
        period = float(sorted(self._intervals)[len(self._intervals) // 2])
        return self.params.period_fraction * period

    def __call__(self, scans: Iterable[Scan]) -> Iterator[Frame]:
        """Frames from ``scans`` (any lasers of :attr:`topics`, in time order).

        Raises:
            TypeError: ``scans`` is one scan, a path or no iterable, or holds what is no
                :class:`~laserpeople.scan.Scan`; names what it takes.
        """
        return self._frames(
            _checked(scans, "LaserGrouper", "scans", Scan, "it takes scans, not frames")
        )

    def _frames(self, scans: Iterator[Scan]) -> Iterator[Frame]:
        ref_topic = self.topics[0]
        last_ref: float | None = None
        others = set(self.topics[1:])
        pending: deque[_Open] = deque()
        recent: deque[Scan] = deque()  # other lasers' scans that a later frame may still take
        last_out = -float("inf")
        for scan in scans:
            t = scan.stamp
            if scan.sensor == ref_topic:
                if last_ref is not None and t > last_ref:
                    self._intervals.append(t - last_ref)
                last_ref = t
            tol = self._tolerance()
            while pending and t > pending[0].ref.stamp + tol:
                yield from self._emit(pending.popleft())
                last_out = self._last_stamp
            while recent and recent[0].stamp < t - 2 * tol:
                old = recent.popleft()
                if id(old) not in self._used:
                    self.stats.unmatched[old.sensor] += 1
                self._used.discard(id(old))
            if scan.sensor == ref_topic:
                frame = _Open(scan)
                for other in recent:
                    if abs(other.stamp - t) <= tol:
                        frame.candidates.setdefault(other.sensor, []).append(other)
                pending.append(frame)
            elif scan.sensor in others:
                if t <= last_out + tol and not any(abs(p.ref.stamp - t) <= tol for p in pending):
                    self.stats.late[scan.sensor] += 1
                    continue
                for p in pending:
                    if abs(p.ref.stamp - t) <= tol:
                        p.candidates.setdefault(scan.sensor, []).append(scan)
                recent.append(scan)
        while pending:
            yield from self._emit(pending.popleft())
        for old in recent:
            if id(old) not in self._used:
                self.stats.unmatched[old.sensor] += 1
        self._used.clear()

    _last_stamp = -float("inf")

    def _emit(self, frame: _Open) -> Iterator[Frame]:
        ref = frame.ref
        self._last_stamp = ref.stamp
        tol = self._tolerance()
        self.stats.tolerance = tol
        scans = [ref]
        missing: list[str] = []
        for topic in self.topics[1:]:
            options = sorted(
                (
                    s
                    for s in frame.candidates.get(topic, [])
                    if id(s) not in self._used and abs(s.stamp - ref.stamp) <= tol
                ),
                key=lambda s: abs(s.stamp - ref.stamp),
            )
            if not options:
                missing.append(topic)
                self.stats.missing[topic] += 1
                continue
            best = options[0]
            self._used.add(id(best))
            self.stats.max_offset = max(self.stats.max_offset, abs(best.stamp - ref.stamp))
            scans.append(best)
        if missing and self.params.policy == "complete":
            self.stats.dropped_frames += 1
            return
        self.stats.frames += 1
        yield Frame(
            index=ref.index,
            stamp=ref.stamp,
            scans=tuple(scans),
            topic=FUSED,
            sensor_pose=ref.pose,
            missing=tuple(missing),
        )


FrameChoice = Literal["auto", "world", "sensor"]


@dataclass
class FrameStats:
    """What :class:`FrameChooser` decided and dropped.

    Attributes:
        frame: The coordinate frame chosen for the run (None before the first frame).
        requested: What was asked for (``auto`` = decided from the poses).
        window: Frames looked at before deciding.
        window_with_pose: Of those, frames whose every scan has a pose.
        skipped_frames: Frames skipped (world frame; no scan with a pose).
        dropped_scans: Scans dropped from a frame for lack of a pose (world frame).
    """

    requested: FrameChoice
    frame: CoordinateFrame | None = None
    window: int = 0
    window_with_pose: int = 0
    skipped_frames: int = 0
    dropped_scans: int = 0

    def summary(self) -> str:
        """One line for the user, naming the frame and why."""
        if self.frame is None:
            return "no frames"
        why = (
            f"{self.window_with_pose} of the first {self.window} frames have sensor poses"
            if self.requested == "auto"
            else "as requested"
        )
        text = f"working in the {self.frame} frame ({why})"
        if self.skipped_frames or self.dropped_scans:
            text += (
                f"; {self.skipped_frames} frames skipped and {self.dropped_scans} scans "
                "dropped for lack of a sensor pose"
            )
        return text


class FrameChooser:
    """Sets the coordinate frame of every frame, one frame for the whole run.

    Args:
        requested: ``world``, ``sensor`` or ``auto`` (world when more than half of the first
            ``window`` frames have a pose for every scan).
        window: Frames buffered before deciding (the latency of the decision).
    """

    def __init__(self, requested: FrameChoice = "auto", window: int = 200) -> None:
        if requested not in ("auto", "world", "sensor"):
            raise ConfigError(f"frame {requested!r} is not auto, world or sensor")
        if window < 1:
            raise ConfigError("the frame look-ahead window must be at least 1 frame")
        self.window = window
        self.stats = FrameStats(requested)

    def __call__(self, frames: Iterable[Frame]) -> Iterator[Frame]:
        """``frames`` with ``frame`` and ``sensor_pose`` set (see the class notes).

        Raises:
            TypeError: ``frames`` is one frame, a path or no iterable, or holds what is no
                :class:`~laserpeople.frame.Frame` (scans, say); names what it takes.
        """
        hint = "make frames of the scans first, FrameChooser()(laser_frames(scans))"
        return self._placed(_checked(frames, "FrameChooser", "frames", Frame, hint))

    def _placed(self, it: Iterator[Frame]) -> Iterator[Frame]:
        head = deque(itertools.islice(it, self.window))
        if not head:
            return
        with_pose = sum(all(s.pose is not None for s in f.scans) for f in head)
        self.stats.window, self.stats.window_with_pose = len(head), with_pose
        if self.stats.requested == "auto":
            chosen: CoordinateFrame = "world" if 2 * with_pose > len(head) else "sensor"
        else:
            chosen = self.stats.requested
        self.stats.frame = chosen
        while head:  # (each buffered frame let go once handed on, not kept for the run)
            out = self._place(head.popleft(), chosen)
            if out is not None:
                yield out
        for frame in it:
            out = self._place(frame, chosen)
            if out is not None:
                yield out

    def _place(self, frame: Frame, chosen: CoordinateFrame) -> Frame | None:
        if chosen == "sensor":
            if len(frame.scans) > 1:
                raise ConfigError(
                    f"frame {frame.index}: several lasers can only be fused in the world "
                    "frame, and their scans have no sensor poses",
                    hint="give the laser mounts (--mount, e.g. --mount mir100) and a world "
                    "frame from /tf or odometry, or track one --topic",
                )
            return frame.with_fields(frame="sensor")
        posed = tuple(s for s in frame.scans if s.pose is not None)
        if len(posed) < len(frame.scans):
            if not posed or frame.scans[0].pose is None:
                self.stats.skipped_frames += 1
                self.stats.dropped_scans += len(posed)
                return None
            self.stats.dropped_scans += len(frame.scans) - len(posed)
            dropped = tuple(s.sensor for s in frame.scans if s.pose is None)
            frame = frame.with_fields(scans=posed, missing=frame.missing + dropped)
        return frame.with_fields(frame="world", sensor_pose=frame.scans[0].pose)


__all__ = [
    "FUSED",
    "FrameChooser",
    "FrameStats",
    "GroupingParams",
    "GroupingStats",
    "LaserGrouper",
    "laser_frames",
]
