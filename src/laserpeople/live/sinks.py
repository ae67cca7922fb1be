"""Live sinks: publish the tracks, measure latency, record, and keep sinks open across resets.

:class:`LiveStats` is the run's :class:`~laserpeople.pipeline.core.PipelineStats` with the
latency of every published frame: from the scan's stamp to publication (needs the robot's
clock and ours to agree) and from the scan's arrival to publication (our clock only; for a
fused frame, the arrival of its last scan).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from laserpeople.errors import ConfigError, RecordingError
from laserpeople.frame import Frame
from laserpeople.io.mcap_record import McapRecorder
from laserpeople.io.paths import why_unwritable
from laserpeople.io.rosbag_writer import ROS1_SUFFIXES
from laserpeople.io.tracks_bag import MARKER_TOPIC, TRACK_TOPICS, TracksBagWriter
from laserpeople.live.messages import Message, TrackEncoder, moved_topic
from laserpeople.live.source import LiveScans
from laserpeople.pipeline.core import PipelineStats
from laserpeople.pipeline.stages import Sink
from laserpeople.samples import Samples
from laserpeople.tracks import Tracks


@dataclass
class LiveStats(PipelineStats):
    """Pipeline counts and timings, plus latencies of the published frames.

    Attributes:
        published: Frames whose tracks were published.
        stamp_ms: Publication time minus the frame's stamp [ms] (wall clocks).
        arrival_ms: Publication time minus the arrival of the frame's last scan [ms].
    """

    published: int = 0
    stamp_ms: Samples = field(default_factory=Samples)
    arrival_ms: Samples = field(default_factory=Samples)

    def latency(self, which: str = "arrival", q: float = 0.5) -> float:
        """The ``q`` quantile of the ``arrival`` or ``stamp`` latency [ms]."""
        values = self.arrival_ms if which == "arrival" else self.stamp_ms
        return values.quantile(q)


class PublishSink:
    """Publishes each frame's tracks (the ``track --bag`` messages) and records latency.

    Args:
        publish: Puts messages on the wire (e.g. :meth:`Publishers.publish`).
        encoder: Turns tracks into messages.
        scans: The live scans (their arrival times).
        stats: Where latencies go.
        wall: Wall clock [s] (``time.time``), compared with stamps.
    """

    def __init__(
        self,
        publish: Callable[[Sequence[Message]], None],
        encoder: TrackEncoder,
        scans: LiveScans,
        stats: LiveStats,
        wall: Callable[[], float] = time.time,
    ) -> None:
        self.publish = publish
        self.encoder = encoder
        self.scans = scans
        self.stats = stats
        self.wall = wall

    def write(self, frame: Frame, tracks: Tracks | None) -> None:
        """Publish ``tracks`` and record the latencies."""
        if tracks is None:
            return
        self.publish(self.encoder.encode(frame.scans, tracks))
        now_wall = self.wall()
        now = self.scans.now()
        arrivals = [self.scans.arrivals.pop((s.sensor, s.index), None) for s in frame.scans]
        known = [a for a in arrivals if a is not None]
        given = self.scans.given.pop((frame.scans[0].sensor, frame.scans[0].index), None)
        if given is not None:
            self.scans.timings.tracked_ms.append(1e3 * (now - given))
        if known:
            self.stats.arrival_ms.append(1e3 * (now - max(known)))
        self.stats.stamp_ms.append(1e3 * (now_wall - frame.stamp))
        self.stats.published += 1

    def close(self) -> None:
        """Nothing to close (the publishers belong to the run)."""


class RecordSink:
    """``live --record``: an MCAP with each frame's scans, their poses and the tracks, the
    tracks being the very bytes published (the frame is encoded once, by the shared
    ``encoder``).

    The tracks go on the topics ``track --bag`` writes (``/laserpeople/people`` ...) whatever
    the published prefix, so ``track``, ``view`` and ``evaluate`` read the recording as
    they read a ``track --bag`` output. Their headers name the frames as published (the
    robot's world frame and lasers' frame ids); the ``frame`` tag of each person says
    whether the positions are in the world or the sensor frame.

    The file is written out after every frame (see :class:`~laserpeople.io.mcap_record.
    McapRecorder`): when the disk refuses a write, it is ended after the last whole frame,
    moved into place, and the error says how many frames and scans it holds.

    Args:
        path: The ``.mcap`` to write.
        encoder: The publisher's encoder.

    Attributes:
        scans: Scans in the whole frames written.
        last_stamp: Stamp of the last of them [s] (None: none yet).
    """

    def __init__(self, path: str | Path, encoder: TrackEncoder) -> None:
        if Path(path).suffix.lower() in ROS1_SUFFIXES:
            raise ConfigError(
                f"the recording {Path(path).name!r} would be a ROS 1 bag, but live records "
                "the published ROS 2 (CDR) bytes",
                hint="give --record a .mcap path",
            )
        self.path = Path(path)
        self._recorder = McapRecorder(self.path)
        self._writer = TracksBagWriter(self._recorder.sink)
        self.encoder = encoder
        self.scans = 0
        self.last_stamp: float | None = None
        prefix = encoder.sink.prefix
        self._topics = {moved_topic(t, prefix): t for t in (*TRACK_TOPICS.values(), MARKER_TOPIC)}

    @property
    def frames(self) -> int:
        """Whole frames written."""
        return self._writer.frames

    def write(self, frame: Frame, tracks: Tracks | None) -> None:
        """Append the frame's scans and poses, and its published tracks, and write them out.

        Raises:
            RecordingError: The disk refused them; the recording was ended before this frame
                (the message says what it holds).
        """
        if tracks is None:
            return
        try:
            self._writer.write_scans(frame.scans, tracks.frame == "world")
            bag = self._writer.sink
            for m in self.encoder.encode(frame.scans, tracks):
                bag.write_serialised(self._topics.get(m.topic, m.topic), m.msgtype, m.data, m.stamp)
            self._recorder.checkpoint()
        except OSError as exc:
            self._recorder.salvage(exc)
            raise self._stopped(exc, f"at frame {self.frames + 1}") from exc
        self._writer.frames += 1
        self.scans += len(frame.scans)
        self.last_stamp = max(s.stamp for s in frame.scans)

    def close(self) -> None:
        """End the recording and move it into place.

        Raises:
            RecordingError: It could not be ended (it is kept up to the last whole frame).
        """
        try:
            self._recorder.close()
        except OSError as exc:
            raise self._stopped(exc, "at its end") from exc

    def _stopped(self, exc: OSError, where: str) -> RecordingError:
        """The error for a recording the disk refused ``where``: what the file holds."""
        upto = (
            "" if self.last_stamp is None else f", up to the scan stamped {self.last_stamp:.3f} s"
        )
        return RecordingError(
            f"the recording stopped {where}: {why_unwritable(exc, self.path)}; the file holds "
            f"the {self.frames} whole frame{'' if self.frames == 1 else 's'} before "
            f"({self.scans} scan{'' if self.scans == 1 else 's'}{upto}) and is ended "
            "there, readable",
            path=self.path,
            hint="free disk space or record into another folder; `laserpeople track` reads "
            "what the file holds",
        )


class KeepOpen:
    """A sink that outlives one pipeline: a reset after a time jump builds a new pipeline,
    which closes its sinks when it ends; this one closes only with :meth:`close_now`."""

    def __init__(self, sink: Sink) -> None:
        self.sink = sink

    def write(self, frame: Frame, tracks: Tracks | None) -> None:
        """Pass the frame on."""
        self.sink.write(frame, tracks)

    def close(self) -> None:
        """Keep the sink open (see the class notes)."""

    def close_now(self) -> None:
        """Close the sink."""
        self.sink.close()


__all__ = ["KeepOpen", "LiveStats", "PublishSink", "RecordSink"]
