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

from laserpeople.errors import ConfigError
from laserpeople.frame import Frame
from laserpeople.io.rosbag_writer import ROS1_SUFFIXES
from laserpeople.io.tracks_bag import MARKER_TOPIC, TRACK_TOPICS
from laserpeople.live.messages import Message, TrackEncoder, moved_topic
from laserpeople.live.source import LiveScans
from laserpeople.pipeline.core import PipelineStats
from laserpeople.pipeline.sinks import TracksBagSink
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


class RecordSink(TracksBagSink):
    """``live --record``: an MCAP with each frame's scans, their poses and the tracks, the
    tracks being the very bytes published (the frame is encoded once, by the shared
    ``encoder``).

    The tracks go on the topics ``track --bag`` writes (``/laserpeople/people`` ...) whatever
    the published prefix, so ``track``, ``view`` and ``evaluate`` read the recording as
    they read a ``track --bag`` output. Their headers name the frames as published (the
    robot's world frame and lasers' frame ids); the ``frame`` tag of each person says
    whether the positions are in the world or the sensor frame.

    Args:
        path: The ``.mcap`` to write.
        encoder: The publisher's encoder.
    """

    def __init__(self, path: str | Path, encoder: TrackEncoder) -> None:
        if Path(path).suffix.lower() in ROS1_SUFFIXES:
            raise ConfigError(
                f"the recording {Path(path).name!r} would be a ROS 1 bag, but live records "
                "the published ROS 2 (CDR) bytes",
                hint="give --record a .mcap path",
            )
        super().__init__(path)
        self.encoder = encoder
        prefix = encoder.sink.prefix
        self._topics = {moved_topic(t, prefix): t for t in (*TRACK_TOPICS.values(), MARKER_TOPIC)}

    def write(self, frame: Frame, tracks: Tracks | None) -> None:
        """Append the frame's scans and poses, and its published tracks."""
        if tracks is None:
            return
        self._writer.write_scans(frame.scans, tracks.frame == "world")
        bag = self._writer.sink
        for m in self.encoder.encode(frame.scans, tracks):
            bag.write_serialised(self._topics.get(m.topic, m.topic), m.msgtype, m.data, m.stamp)
        self._writer.frames += 1


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
