"""What is drawn: scans, tracks and ground truth of one recording, aligned by scan index and
expressed in the display frame.

A :class:`Scene` can be iterated several times (a first pass sizes the plot, a second draws
it) and streams: memory does not grow with the length of the recording.

Alignment: tracks (from a tracks CSV or a tracker) and truth frames are matched to scans by
their 0-based ``scan_index`` on the drawn topic. Both streams must come in increasing scan
order, as the tracks CSV writer and every reader produce them.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Literal, TypeVar

import numpy as np
from numpy.typing import NDArray

from laserpeople.errors import LaserPeopleError, PoseUnavailableError, RecordingError
from laserpeople.io import RecordingSource, open_recording
from laserpeople.io.topics import no_laser_topic
from laserpeople.io.tracks_csv import convert_tracks
from laserpeople.io.tracks_files import read_tracks_file
from laserpeople.io.truth_csv import read_truth_csv
from laserpeople.scan import CoordinateFrame, Pose2D, Scan
from laserpeople.tracks import Track, Tracks
from laserpeople.truth import TruthFrame

FloatArray = NDArray[np.float64]
FrameChoice = Literal["auto", "world", "sensor"]
POSE_PROBE_SCANS = 50
"""Scans looked at to decide whether the recording has sensor poses (``frame="auto"``)."""
T = TypeVar("T", Tracks, TruthFrame)
ProgressFn = Callable[[Iterable["SceneFrame"], int | None], Iterable["SceneFrame"]]
"""Wraps the frame stream of a drawing or export, e.g. in a progress bar; gets the number of
frames when known."""

_IDENTITY = Pose2D()


@dataclass(frozen=True, eq=False)
class SceneFrame:
    """One scan with everything drawn on it, all in the display frame.

    Attributes:
        scan: The scan.
        points: Valid beam end points (K, 2) [m].
        sensor_pose: Pose of the sensor in the display frame.
        tracks: The tracks reported after this scan (empty when none).
        truth: The true people at this scan, or None when there is no truth for it.
    """

    scan: Scan
    points: FloatArray
    sensor_pose: Pose2D
    tracks: Tracks
    truth: TruthFrame | None


def _aligned(stream: Iterator[T]) -> Callable[[int], T | None]:
    """A lookup ``scan_index -> item`` over an increasing stream, consuming it lazily."""
    pending: list[T] = []

    def at(index: int) -> T | None:
        while True:
            if not pending:
                nxt = next(stream, None)
                if nxt is None:
                    return None
                pending.append(nxt)
            head = pending[0]
            if head.scan_index < index:
                pending.pop()
                continue
            return head if head.scan_index == index else None

    return at


def _transform_truth(truth: TruthFrame, pose: Pose2D, to: CoordinateFrame) -> TruthFrame:
    """Truth expressed in frame ``to`` (``"sensor"``: from the world into the sensor frame
    of ``pose``; ``"world"``: from that sensor frame into the world)."""
    legs = truth.leg_positions.reshape(-1, 2)
    rot = pose.rotation()
    move = pose.inverse_transform_points if to == "sensor" else pose.transform_points
    return replace(
        truth,
        positions=move(truth.positions),
        velocities=truth.velocities @ (rot if to == "sensor" else rot.T),
        leg_positions=move(legs).reshape(-1, 2, 2),
    )


class Scene:
    """Scans of one topic with tracks and truth, ready to draw.

    Args:
        recording: A recording path, an open :class:`RecordingSource`, or a sequence of
            scans (e.g. the scans a tracker just processed).
        tracks: A tracks CSV path, a sequence of :class:`Tracks`, or None.
        truth: A truth CSV path, a sequence of :class:`TruthFrame`, ``"recording"`` for
            the recording's own truth (an error when it has none), ``"auto"`` for the
            recording's truth when it has some, or None.
        topic: The laser topic to draw; None takes the recording's first topic.
        frame: Display frame; ``"auto"`` is world when the scans carry a sensor pose,
            else sensor.
        tracks_frame: The frame the tracks CSV was written in; None means world when the
            scans carry a sensor pose, else sensor (what ``laserpeople track`` writes).
        truth_frame: The frame of the positions in a truth CSV or sequence (``"sensor"``:
            each scan's laser frame, as the leg_tracker benchmark labels); None means the
            tracks' frame. The recording's own truth is always in the world frame.
        start: First scan index drawn (0-based on the topic, inclusive).
        stop: Scan index to stop before (exclusive); None runs to the end.
        every: Draw every ``every``-th scan of the window.
        title: Text on the pictures; None names the file and topic.
        other_topics: Further lasers whose points are drawn with each scan of ``topic``
            (their latest scan at or before it, in the display frame; a fused run's other
            lasers). In the sensor frame they need sensor poses (mounts) to be placed.
    """

    def __init__(
        self,
        recording: str | Path | RecordingSource | Iterable[Scan],
        tracks: str | Path | Iterable[Tracks] | None = None,
        truth: str | Path | Iterable[TruthFrame] | None = None,
        *,
        topic: str | None = None,
        frame: FrameChoice = "auto",
        tracks_frame: CoordinateFrame | None = None,
        truth_frame: CoordinateFrame | None = None,
        start: int | None = None,
        stop: int | None = None,
        every: int = 1,
        title: str | None = None,
        other_topics: tuple[str, ...] = (),
    ) -> None:
        if every < 1:
            raise LaserPeopleError(f"every must be at least 1, got {every}")
        if start is not None and stop is not None and stop <= start:
            raise LaserPeopleError(f"empty scan window: start {start} >= stop {stop}")
        # a scene is read more than once (sizing, then drawing): one-shot iterators are
        # kept as lists so that the second pass does not silently see nothing
        if isinstance(recording, Iterator):
            recording = list(recording)
        if isinstance(tracks, Iterator):
            tracks = list(tracks)
        if isinstance(truth, Iterator):
            truth = list(truth)
        self._recording = recording
        self.source_name = (
            str(recording) if isinstance(recording, str | Path) else getattr(recording, "path", "")
        )
        self.title = title
        self._tracks = tracks
        self._truth = truth
        self.topic = topic
        self.other_topics = tuple(t for t in other_topics if t != topic)
        self.others_unplaced = 0
        """Scans of the other topics not drawn in the last pass (no pose to place them)."""
        self.start = start if start is not None else 0
        self.stop = stop
        self.every = every
        self.skipped_without_pose = 0
        """Scans of the last :meth:`frames` pass not drawn: world frame, but no sensor pose."""
        self.tracks_outside = TracksOutside()
        """Track positions the last :meth:`extent` left out of the area drawn."""
        self._first_stamp: float | None = None
        auto = self._pose_frame()
        if frame == "world" and auto == "sensor":
            raise PoseUnavailableError(
                "cannot draw in the world frame: the scans carry no sensor pose",
                path=self.source_name or None,
                hint="use --frame sensor, or a recording with /tf or odometry",
            )
        self.frame: CoordinateFrame = auto if frame == "auto" else frame
        self.tracks_frame: CoordinateFrame = tracks_frame or auto
        own_truth = isinstance(truth, str) and truth in ("auto", "recording")
        self.truth_frame: CoordinateFrame = (
            "world" if own_truth else truth_frame or self.tracks_frame
        )

    # -- inputs --------------------------------------------------------------------------
    def _open(self) -> tuple[Iterator[Scan], Iterator[TruthFrame] | None, Callable[[], None]]:
        rec = self._recording
        if isinstance(rec, str | Path):
            source = open_recording(rec)
            return self._topic_scans(source), self._recording_truth(source), source.close
        if isinstance(rec, RecordingSource):
            return self._topic_scans(rec), self._recording_truth(rec), lambda: None
        scans = iter(rec)
        first = next(scans, None)
        if first is None:
            return iter(()), None, lambda: None
        name = self.topic or first.sensor

        def chain() -> Iterator[Scan]:
            if first.sensor == name:
                yield first
            yield from (s for s in scans if s.sensor == name)

        return chain(), None, lambda: None

    def _topic_scans(self, source: RecordingSource) -> Iterator[Scan]:
        topic = self.topic
        if topic is None:
            topics = source.topics()
            if not topics:
                no_laser_topic(source, source.path)
            topic = topics[0].name
            self.topic = topic
        if not self.other_topics:
            return source.scans([topic])
        return self._with_others(source.scans([topic, *self.other_topics]), topic)

    def _with_others(self, scans: Iterator[Scan], topic: str) -> Iterator[Scan]:
        """The scans of ``topic``, each carrying the other lasers' latest scans (kept in
        :attr:`_latest` for :meth:`_frame`)."""
        self._latest: dict[str, Scan] = {}
        for scan in scans:
            if scan.sensor == topic:
                yield scan
            else:
                self._latest[scan.sensor] = scan

    def _other_points(self, scan: Scan) -> FloatArray:
        """The other lasers' latest points (K, 2) in the display frame at ``scan``."""
        latest = getattr(self, "_latest", {})
        parts = []
        for other in latest.values():
            if other.pose is None or (self.frame == "sensor" and scan.pose is None):
                self.others_unplaced += 1
                continue
            pts, _ = other.valid_points("world")
            if self.frame == "sensor":
                assert scan.pose is not None
                pts = scan.pose.inverse_transform_points(pts)
            parts.append(pts)
        return np.concatenate(parts) if parts else np.empty((0, 2))

    def _recording_truth(self, source: RecordingSource) -> Iterator[TruthFrame] | None:
        return source.truth() if source.has_truth else None

    def _pose_frame(self) -> CoordinateFrame:
        """World when one of the first :data:`POSE_PROBE_SCANS` scans has a sensor pose
        (real bags often lack one for the first scan or two), else sensor."""
        scans, _, close = self._open()
        try:
            for _, scan in zip(range(POSE_PROBE_SCANS), scans, strict=False):
                if scan.pose is not None:
                    return "world"
        finally:
            close()
        return "sensor"

    def _truth_stream(self, recording_truth: Iterator[TruthFrame] | None) -> Iterator[TruthFrame]:
        truth = self._truth
        if truth is None:
            return iter(())
        if isinstance(truth, str) and truth == "auto":
            return recording_truth if recording_truth is not None else iter(())
        if isinstance(truth, str) and truth == "recording":
            if recording_truth is None:
                raise RecordingError(
                    "the recording carries no ground truth",
                    path=self.source_name or None,
                    hint="give a truth CSV (scan,stamp,person_id,x,y) or drop --truth",
                )
            return recording_truth
        if isinstance(truth, str | Path):
            return iter(read_truth_csv(truth))
        return iter(truth)

    def _tracks_stream(self) -> Iterator[Tracks]:
        tracks = self._tracks
        if tracks is None:
            return iter(())
        if isinstance(tracks, str | Path):
            return read_tracks_file(tracks, self.tracks_frame)
        return iter(tracks)

    def track_kinds(self) -> frozenset[str]:
        """The kinds of the tracks to draw (``leg``, ``person``, ``group``; one pass over
        them)."""
        return frozenset(t.kind for tracks in self._tracks_stream() for t in tracks.tracks)

    def count(self) -> int | None:
        """Number of frames the window holds, when the recording can tell without reading."""
        rec = self._recording
        if isinstance(rec, str | Path):
            source = open_recording(rec)
            try:
                return self._count(source)
            finally:
                source.close()
        if isinstance(rec, RecordingSource):
            return self._count(rec)
        if isinstance(rec, list | tuple) and rec:
            name = self.topic or rec[0].sensor
            return sum(
                1
                for s in rec
                if s.sensor == name
                and s.index >= self.start
                and (self.stop is None or s.index < self.stop)
                and (s.index - self.start) % self.every == 0
            )
        return None

    def _count(self, source: RecordingSource) -> int | None:
        topics = source.topics()
        name = self.topic or (topics[0].name if topics else None)
        n = next((t.count for t in topics if t.name == name), None)
        if n is None:
            return None
        stop = n if self.stop is None else min(n, self.stop)
        return max(0, -(-(stop - self.start) // self.every))

    def first_stamp(self) -> float | None:
        """Time stamp [s] of the topic's first scan (before ``start``): captions count
        seconds from it. None when the topic has no scan."""
        if self._first_stamp is None:
            scans, _, close = self._open()
            try:
                first = next(scans, None)
            finally:
                close()
            self._first_stamp = first.stamp if first is not None else None
        return self._first_stamp

    def draws_truth(self) -> bool:
        """Whether ground truth is drawn: given explicitly, or ``"auto"`` and the recording
        carries some."""
        truth = self._truth
        if truth is None:
            return False
        if not (isinstance(truth, str) and truth == "auto"):
            return True
        rec = self._recording
        if isinstance(rec, str | Path):
            source = open_recording(rec)
            try:
                return bool(source.has_truth)
            finally:
                source.close()
        return isinstance(rec, RecordingSource) and bool(rec.has_truth)

    # -- output ---------------------------------------------------------------------------
    def frames(self) -> Iterator[SceneFrame]:
        """The frames of the window, in order, in the display frame."""
        scans, rec_truth, close = self._open()
        self.skipped_without_pose = 0
        streams: list[Iterator[Any]] = []
        try:
            streams.append(self._tracks_stream())
            streams.append(self._truth_stream(rec_truth))
            track_at = _aligned(streams[0])
            truth_at = _aligned(streams[1])
            for scan in scans:
                if scan.index < self.start or (scan.index - self.start) % self.every:
                    continue
                if self.stop is not None and scan.index >= self.stop:
                    break
                if self.frame == "world" and scan.pose is None:
                    self.skipped_without_pose += 1
                    continue
                yield self._frame(scan, track_at(scan.index), truth_at(scan.index))
        finally:
            for stream in (*streams, scans):  # the CSV files they hold open, on every path
                shut = getattr(stream, "close", None)
                if shut is not None:
                    shut()
            close()

    def _frame(self, scan: Scan, tracks: Tracks | None, truth: TruthFrame | None) -> SceneFrame:
        pose = scan.pose
        if self.frame == "world":
            points, _ = scan.valid_points("world")
            assert pose is not None  # valid_points("world") raised otherwise
            sensor_pose = pose
        else:
            points, _ = scan.valid_points("sensor")
            sensor_pose = _IDENTITY
        if tracks is None:
            tracks = Tracks(scan.stamp, scan.index, (), self.frame, pose)
        elif tracks.frame != self.frame:
            if tracks.sensor_pose is None and pose is None:
                raise LaserPeopleError(
                    f"the tracks are in the {tracks.frame} frame, and the scan has no sensor "
                    f"pose to draw them in the {self.frame} frame",
                    path=self.source_name or None,
                    scan=scan.index,
                    hint="give view the --mount or --world-frame that track was given, e.g. "
                    "--mount mir100; `laserpeople info` says why scans have no pose",
                )
            tracks = convert_tracks(
                replace(tracks, sensor_pose=tracks.sensor_pose or pose), self.frame
            )
        if truth is not None and self.truth_frame != self.frame and pose is not None:
            truth = _transform_truth(truth, pose, self.frame)
        if self.other_topics:
            points = np.concatenate([points, self._other_points(scan)])
        return SceneFrame(scan, points, sensor_pose, tracks, truth)

    def empty_window_error(self, options: str = "--topic, --start and --stop") -> LaserPeopleError:
        """The error for a window without scans, naming the command-line ``options`` to
        check."""
        window = (
            f"scans from {self.start}"
            if self.stop is None
            else f"scans {self.start}-{self.stop - 1}"
        )
        count = self._topic_count()
        held = (
            ""
            if count is None
            else f": topic {self.topic} holds " + (f"scans 0-{count - 1}" if count else "no scan")
        )
        return LaserPeopleError(
            f"no scans in the chosen window ({window}){held}",
            path=self.source_name or None,
            hint=f"check {options}",
        )

    def _topic_count(self) -> int | None:
        """Scans of the drawn topic as the recording's index counts them (None when the
        scans do not come from a recording or the topic is not known)."""
        rec = self._recording
        if self.topic is None or not isinstance(rec, str | Path | RecordingSource):
            return None
        source = open_recording(rec) if isinstance(rec, str | Path) else rec
        try:
            return next((t.count for t in source.topics() if t.name == self.topic), None)
        finally:
            if source is not rec:
                source.close()

    def extent(
        self, margin: float = 0.5, max_scans: int = 400, track_slack: float = 2.0
    ) -> tuple[float, float, float, float]:
        """``(xmin, xmax, ymin, ymax)`` [m] that holds the sensor, the truth, the bulk of
        the scan points (1st to 99th percentile, so a few stray far returns do not shrink
        everything else; sampled from at most ``max_scans`` scans and every 10th after)
        and the track positions within ``track_slack`` [m] of that box."""
        pts: list[FloatArray] = []
        objs: list[FloatArray] = []
        tracked: list[FloatArray] = []
        for i, f in enumerate(self.frames()):
            if i < max_scans or i % 10 == 0:
                pts.append(f.points[:: max(1, f.points.shape[0] // 256)])
            objs.append(np.array([[f.sensor_pose.x, f.sensor_pose.y]]))
            if f.tracks.tracks:
                tracked.append(np.array([t.position for t in f.tracks.tracks]))
            if f.truth is not None and len(f.truth):
                objs.append(f.truth.positions)
        if not objs:
            raise self.empty_window_error("--topic, --start, --stop and --scan")
        o = np.concatenate(objs)
        o = o[np.all(np.isfinite(o), axis=1)]
        lo, hi = o.min(axis=0), o.max(axis=0)
        cloud = np.concatenate(pts)
        if cloud.shape[0]:
            lo = np.minimum(lo, np.percentile(cloud, 1.0, axis=0))
            hi = np.maximum(hi, np.percentile(cloud, 99.0, axis=0))
        self.tracks_outside = TracksOutside()
        if tracked:
            # tracks far outside everything measured (a diverging estimate) would shrink
            # the scene to a corner; they are left out of the extent, not of the drawing
            t = np.concatenate(tracked)
            near = np.all((t >= lo - track_slack) & (t <= hi + track_slack), axis=1)
            if np.any(near):
                lo = np.minimum(lo, t[near].min(axis=0))
                hi = np.maximum(hi, t[near].max(axis=0))
        lo, hi = lo - margin, hi + margin
        if tracked:
            off = np.maximum(lo - t, t - hi).max(axis=1)  # > 0: outside the area [m]
            out = ~(off <= 0.0)  # (NaN positions too)
            if np.any(out):
                finite = off[out & np.isfinite(off)]
                self.tracks_outside = TracksOutside(
                    int(np.count_nonzero(out)),
                    len(t),
                    float(finite.max()) if len(finite) else float("inf"),
                )
        return float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1])


@dataclass(frozen=True)
class TracksOutside:
    """Track positions outside the area :meth:`Scene.extent` fits (those more than its
    ``track_slack`` outside the box of the sensor, the truth and the bulk of the points are
    left out of the fit).

    Attributes:
        count: Positions outside the area.
        of: Track positions in all.
        farthest: How far the farthest lies outside it [m] (per axis).
    """

    count: int = 0
    of: int = 0
    farthest: float = 0.0

    def warning(self) -> str:
        """What to tell the user (empty when none is left out): a track that diverged, or
        positions in millimetres, would otherwise be missing from the picture unsaid."""
        if not self.count:
            return ""
        why = (
            "positions in millimetres, or tracks that diverged?"
            if self.farthest > FAR_OUTSIDE
            else "tracks beyond the bulk of the scan points"
        )
        return (
            f"{self.count:,} of {self.of:,} track positions lie outside the area the picture "
            f"is fitted to (the scans, sensor and truth; up to {self.farthest:,.1f} m beyond it) "
            f"and may be cut from it ({why}); --extent XMIN,XMAX,YMIN,YMAX draws a larger area"
        )


FAR_OUTSIDE = 100.0
"""Distance [m] beyond the drawn area past which track positions are asked about as
millimetres (a laser sees a few tens of metres; a person 5 m away written in mm is 5,000
m out)."""


def track_positions(tracks: Iterable[Track]) -> FloatArray:
    """Positions (T, 2) of tracks."""
    arr = [t.position for t in tracks]
    return np.array(arr, dtype=np.float64).reshape(-1, 2)
