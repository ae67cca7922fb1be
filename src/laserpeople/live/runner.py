"""A live run: receive scans and transforms, track them with the ``track`` pipeline, publish.

:class:`LiveRun` holds the whole flow; the ``live`` command only parses options and prints.
The pipeline is the one :func:`laserpeople.pipeline.build` makes for a recording (the same
tracker, stages, static world model and ``--map``), fed by
:class:`~laserpeople.live.source.LiveFrames`. A time jump ends the pipeline, and a new one
(new tracker, new models) starts from the scan that jumped; the run says so through
``on_reset``. So does a switch to the world frame (``--frame auto`` finding poses after it
began in the sensor frame, see :mod:`laserpeople.live.choice`): a new pipeline starts from the
frame that decided, said through ``on_choice``.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from laserpeople.errors import LaserPeopleError
from laserpeople.frame import Frame
from laserpeople.io.rosbag_writer import sensor_frame_id
from laserpeople.live.choice import DECIDE_WITHIN, FrameDecision, FrameSwitch
from laserpeople.live.keys import BridgeKeys, KeyStyle, RmwKeys, Transport
from laserpeople.live.messages import (
    ODOMETRY_TYPE,
    OUTPUT_PREFIX,
    SCAN_TYPE,
    RosDecoder,
    TrackEncoder,
    output_topics,
    ros2_typestore,
)
from laserpeople.live.poses import LiveTransforms
from laserpeople.live.sinks import KeepOpen, LiveStats, PublishSink, RecordSink
from laserpeople.live.source import LiveFrames, LiveScans, TimeJump
from laserpeople.live.zenoh_link import Publishers, Subscriptions, ZenohSettings, open_session
from laserpeople.pipeline.core import Pipeline, Step
from laserpeople.pipeline.sources import FrameChoice, GroupingParams
from laserpeople.pipeline.stages import Sink
from laserpeople.scan import Pose2D, Scan

TF_TYPE = "tf2_msgs/msg/TFMessage"


@dataclass(frozen=True)
class LiveTopics:
    """The ROS topics a live run reads and writes.

    Attributes:
        lasers: ``sensor_msgs/LaserScan`` topics (several are fused; the first leads).
        tf: ``tf2_msgs/TFMessage`` topic (None: none).
        tf_static: Static transforms (None: none).
        odometry: ``nav_msgs/Odometry`` topic giving the robot's pose (None: none).
        output_prefix: The tracks go to ``<prefix>/people``, ``/legs``, ``/groups``
            (``people_msgs/People``) and ``/markers`` (``visualization_msgs/MarkerArray``).
    """

    lasers: tuple[str, ...] = ("/scan",)
    tf: str | None = "/tf"
    tf_static: str | None = "/tf_static"
    odometry: str | None = "/odom"
    output_prefix: str = OUTPUT_PREFIX


def key_style(transport: Transport, domain: int = 0, hashes: str = "rihs01",
              prefix: str = "", typestore: Any = None) -> KeyStyle:  # fmt: skip
    """The key style of ``transport`` (``bridge`` or ``rmw``)."""
    if transport == "bridge":
        return BridgeKeys(prefix)
    if transport == "rmw":
        if hashes not in ("rihs01", "none"):
            raise LaserPeopleError(f"type hashes {hashes!r} are not rihs01 or none")
        return RmwKeys(domain, typestore or ros2_typestore(), hashes)  # type: ignore[arg-type]
    raise LaserPeopleError(f"transport {transport!r} is not bridge or rmw")


class Receiver:
    """Zenoh subscriptions -> :class:`LiveScans` and :class:`LiveTransforms`.

    Args:
        subscriptions: Where to subscribe.
        topics: What to subscribe to.
        scans: Receives the decoded scans.
        transforms: Receives the transforms (None: poses are not used).
        decoder: CDR decoder.
    """

    def __init__(
        self,
        subscriptions: Subscriptions,
        topics: LiveTopics,
        scans: LiveScans,
        transforms: LiveTransforms | None,
        decoder: RosDecoder,
    ) -> None:
        self.scans = scans
        self.transforms = transforms
        self.decoder = decoder
        self.frame_ids: dict[str, str] = {}
        """Laser topic -> ``header.frame_id`` of its first scan."""
        self.keys: dict[str, str] = {}
        """Topic -> key expression subscribed."""
        self.bad_transforms = 0
        for laser in topics.lasers:
            self.keys[laser] = subscriptions.add(laser, SCAN_TYPE, self._scan_callback(laser))
        if transforms is not None:
            for topic, static in ((topics.tf, False), (topics.tf_static, True)):
                if topic:
                    self.keys[topic] = subscriptions.add(
                        topic, TF_TYPE, self._tf_callback(topic, static)
                    )
            if topics.odometry:
                self.keys[topics.odometry] = subscriptions.add(
                    topics.odometry, ODOMETRY_TYPE, self._odom_callback(topics.odometry)
                )

    def _scan_callback(self, topic: str) -> Callable[[bytes], None]:
        def on_scan(data: bytes) -> None:
            try:
                scan, frame_id = self.decoder.scan(data, topic, 0)
            except LaserPeopleError as exc:
                self.scans.undecodable(topic, exc.detail)
                return
            self.frame_ids.setdefault(topic, frame_id)
            self.scans.put(scan, frame_id)

        return on_scan

    def _tf_callback(self, topic: str, static: bool) -> Callable[[bytes], None]:
        def on_tf(data: bytes) -> None:
            assert self.transforms is not None
            try:
                samples = self.decoder.transforms(data, topic)
            except LaserPeopleError:
                self.bad_transforms += 1
                return
            self.transforms.add(samples, static=static, source=topic)
            self.scans.poke()

        return on_tf

    def _odom_callback(self, topic: str) -> Callable[[bytes], None]:
        def on_odom(data: bytes) -> None:
            assert self.transforms is not None
            try:
                samples = self.decoder.odometry(data, topic)
            except LaserPeopleError:
                self.bad_transforms += 1
                return
            self.transforms.add(samples, static=False, source=topic)
            self.scans.poke()

        return on_odom


PipelineFactory = Callable[[Iterable[Frame], Sequence[Sink]], Pipeline]
"""Makes a fresh pipeline (tracker, stages) over frames and sinks."""


def tracker_pipelines(
    tracker: str,
    params: Any = None,
    *,
    detector: Any = None,
    leg_fusion: Any = None,
    background: str = "auto",
    map_path: str | Path | None = None,
    static_world: Any = None,
) -> PipelineFactory:
    """A :data:`PipelineFactory` for a registered tracker: every call makes a new tracker
    with the stages :func:`laserpeople.pipeline.build` gives it for a recording."""
    from laserpeople.pipeline.recording import leg_reid_stage, tracker_stages
    from laserpeople.tracking import registry

    entry = registry.get(tracker)

    def make(frames: Iterable[Frame], sinks: Sequence[Sink]) -> Pipeline:
        made = entry.make(params)
        preprocess, observe, hide = tracker_stages(
            made,
            detector=detector,
            leg_fusion=leg_fusion,
            background=background,
            map_path=map_path,
            static_world=static_world,
        )
        identify = [s for s in (hide, leg_reid_stage(made, static_world)) if s is not None]
        return Pipeline(
            frames,
            preprocess=preprocess,
            observe=observe,
            tracker=made,
            identify=identify,
            sinks=sinks,
        )

    return make


@dataclass
class LiveRun:
    """Tracks live scans until stopped (see the module notes).

    Args:
        scans: The live scans (fed by a :class:`Receiver`).
        make_pipeline: Makes the pipeline of each run (:func:`tracker_pipelines`).
        sinks: Outputs (the publisher's sink first); kept open across resets.
        frame: ``world``, ``sensor`` or ``auto`` (decided as the frames come, see
            :mod:`laserpeople.live.choice`).
        grouping: Grouping of several lasers.
        decide_within: ``auto``: seconds after the first scan to wait for a sensor pose [s].
        on_reset: Told the reason of each reset.
        on_choice: Told the frame ``auto`` chose, why, and after how many frames and seconds.

    Attributes:
        stats: Counts, timings and latencies of the whole run.
        decision: The frame chosen and why.
        frames: The frames of the current pipeline (grouping and frame choice figures).
        pipeline: The current pipeline.
    """

    scans: LiveScans
    make_pipeline: PipelineFactory
    sinks: Sequence[Sink] = ()
    frame: FrameChoice = "auto"
    grouping: GroupingParams | None = None
    decide_within: float = DECIDE_WITHIN
    on_reset: Callable[[str], None] = lambda reason: None
    on_choice: Callable[[str], None] = lambda message: None
    stats: LiveStats = field(default_factory=LiveStats)
    decision: FrameDecision = field(init=False)
    frames: LiveFrames | None = None
    pipeline: Pipeline | None = None
    last_step: Step | None = None
    _ready: tuple[LiveFrames, Pipeline] | None = None

    def __post_init__(self) -> None:
        self.decision = FrameDecision(self.frame, self.decide_within)
        self.scans.lookup_poses = self.scans.transforms is not None and self.frame != "sensor"
        self._kept = [KeepOpen(s) for s in self.sinks]
        self._ready = self._new_pipeline()  # built before scans arrive, not on the first

    def _new_pipeline(self, carry: Sequence[Frame] = ()) -> tuple[LiveFrames, Pipeline]:
        frames = LiveFrames(
            self.scans,
            self.decision,
            grouping=self.grouping,
            carry=carry,
            on_choice=self.on_choice,
        )
        pipeline = self.make_pipeline(frames, self._kept)
        if len(self.stats.stage_cpu) != len(pipeline.stages):  # the first pipeline
            self.stats.stage_cpu = [0.0] * len(pipeline.stages)
        pipeline.stats = self.stats  # one run's counts over the pipelines of its time jumps
        return frames, pipeline

    def steps(self) -> Iterable[Step]:
        """Run until the scans end (:meth:`LiveScans.finish` / :meth:`LiveScans.close`),
        giving each step as its frame is done."""
        try:
            carry: Sequence[Frame] = ()
            again = True
            while again:
                again = False
                ready, self._ready = self._ready, None
                self.frames, self.pipeline = ready or self._new_pipeline(carry)
                try:
                    for step in self.pipeline:
                        self.last_step = step
                        yield step
                except TimeJump as jump:
                    self.on_reset(str(jump))
                    again, carry = True, ()
                    if self.scans.transforms is not None:
                        self.scans.transforms.reset()
                except FrameSwitch as switch:  # (said by on_choice when it was chosen)
                    again, carry = True, (switch.frame,)
        finally:
            for sink in self._kept:
                sink.close_now()

    def run(self) -> LiveStats:
        """Run to the end; returns the statistics."""
        deque(self.steps(), maxlen=0)  # (each step is published by the sinks as it goes)
        return self.stats


@dataclass
class LiveSession:
    """Everything a ``live`` command opens: the Zenoh session, subscriptions, publishers,
    the scans, and the :class:`LiveRun` over them. Close with :meth:`close`.

    Args:
        topics: Topics in and out.
        settings: Zenoh session settings.
        transport: ``bridge`` or ``rmw``.
        make_pipeline: See :class:`LiveRun`.
        domain: ROS domain id (rmw).
        hashes: ``rihs01`` or ``none`` (rmw type hashes).
        key_prefix: Prefix of every key (bridge).
        world_frame: World frame id (None: ``map``, else ``odom``, else the lasers' root).
        mounts: Fixed laser mounts (``--mount``).
        use_poses: Subscribe to the transforms (False: sensor frame, one laser).
        frame: See :class:`LiveRun`.
        depth: Scans kept per laser before the oldest is dropped (None: see
            :class:`~laserpeople.live.source.LiveScans`).
        tf_wait: Longest wait for a transform covering a scan [s].
        order_wait: Several lasers: longest wait of a frame for the others' scans of its
            instant [s] (None: one scan period of the slowest other laser, measured).
        grouping: Grouping of several lasers.
        extra_sinks: More outputs after the publisher (e.g. the Foxglove server).
        record: An ``.mcap`` to record the scans and the published tracks into (see
            :class:`~laserpeople.live.sinks.RecordSink`; None: no recording).
        block: Publishers block on congestion instead of dropping.
        on_reset: Told the reason of each reset (a time jump).
        on_choice: Told the frame ``auto`` chose and why (see :class:`LiveRun`).
        decide_within: See :class:`LiveRun`.
        warm: Run :func:`warm_up` before subscribing.
    """

    topics: LiveTopics
    settings: ZenohSettings
    transport: Transport
    make_pipeline: PipelineFactory
    domain: int = 0
    hashes: str = "rihs01"
    key_prefix: str = ""
    world_frame: str | None = None
    mounts: dict[str, tuple[str, Pose2D]] = field(default_factory=dict)
    use_poses: bool = True
    frame: FrameChoice = "auto"
    depth: int | None = None
    tf_wait: float = 0.1
    order_wait: float | None = None
    grouping: GroupingParams | None = None
    extra_sinks: Sequence[Sink] = ()
    record: Path | None = None
    block: bool = False
    on_reset: Callable[[str], None] = lambda reason: None
    on_choice: Callable[[str], None] = lambda message: None
    decide_within: float = DECIDE_WITHIN
    warm: bool = True

    def __post_init__(self) -> None:
        typestore = ros2_typestore()
        self.warm_up_seconds = (
            warm_up(self.make_pipeline, TrackEncoder(typestore, self.topics.output_prefix))
            if self.warm
            else 0.0
        )
        self.keys = key_style(self.transport, self.domain, self.hashes, self.key_prefix, typestore)
        self.session = open_session(self.settings)
        try:
            self.transforms = (
                LiveTransforms(self.world_frame, self.mounts) if self.use_poses else None
            )
            self.scans = LiveScans(
                self.topics.lasers,
                self.transforms,
                depth=self.depth,
                tf_wait=self.tf_wait,
                order_wait=self.order_wait,
            )
            self.publishers = Publishers(self.session, self.keys, block=self.block)
            self.publishers.declare(output_topics(self.topics.output_prefix))
            self.subscriptions = Subscriptions(self.session, self.keys)
            self.receiver = Receiver(
                self.subscriptions,
                self.topics,
                self.scans,
                self.transforms,
                RosDecoder(typestore),
            )
            self.encoder = TrackEncoder(typestore, self.topics.output_prefix)
            stats = LiveStats()
            publish = PublishSink(self.publishers.publish, self.encoder, self.scans, stats)
            sinks: list[Sink] = [publish, *self.extra_sinks]
            if self.record is not None:
                sinks.append(RecordSink(self.record, self.encoder))
            self.run = LiveRun(
                self.scans,
                self._with_frame_ids(self.make_pipeline),
                sinks,
                frame=self.frame,
                grouping=self.grouping,
                decide_within=self.decide_within,
                on_reset=self.on_reset,
                on_choice=self.on_choice,
                stats=stats,
            )
        except BaseException:
            self.session.close()
            raise

    def _with_frame_ids(self, make: PipelineFactory) -> PipelineFactory:
        """Before each frame, name the frames in the published headers: the world frame
        in use and each laser's own frame id."""
        names = self.encoder.sink.frame_ids

        def named(frames: Iterable[Frame]) -> Iterable[Frame]:
            for frame in frames:
                if self.transforms is not None and self.transforms.world_frame:
                    names["world"] = self.transforms.world_frame
                for topic, frame_id in self.receiver.frame_ids.items():
                    names[sensor_frame_id(topic)] = frame_id
                yield frame

        def make_named(frames: Iterable[Frame], sinks: Sequence[Sink]) -> Pipeline:
            return make(named(frames), sinks)

        return make_named

    def close(self) -> None:
        """Stop receiving, undeclare everything, close the session (once; later calls do
        nothing)."""
        if self.session.is_closed():
            return
        self.scans.close()
        try:
            self.subscriptions.close()
            self.publishers.close()
        finally:
            self.session.close()


class _Encode:
    """A sink encoding each frame's tracks (the first encoding of each message type is
    slow: its serialiser is made then)."""

    def __init__(self, encoder: TrackEncoder) -> None:
        self.encoder = encoder
        self.frames = 0

    def write(self, frame: Frame, tracks: Any) -> None:
        if tracks is not None:
            self.encoder.encode(frame.scans, tracks)
            self.frames += 1

    def close(self) -> None:
        """Nothing to close."""


def warm_up(
    make_pipeline: PipelineFactory, encoder: TrackEncoder | None = None, scans: int = 5
) -> float:
    """Run a throwaway pipeline over a few synthetic scans (a wall at 3 m, two leg-sized
    bumps at 1.5 m), so that lazy imports and first-call set-up do not delay the first
    real scans; returns the seconds it took.

    Args:
        make_pipeline: Makes the pipeline.
        encoder: A throwaway encoder on the run's typestore: the warm-up's tracks are encoded
            too (the first encoding took about 0.2 s, the first frame's latency).
        scans: Synthetic scans to run.
    """
    import numpy as np

    from laserpeople.pipeline.sources import laser_frames

    start = time.monotonic()
    angles = np.linspace(-np.pi / 2, np.pi / 2, 361)
    ranges = np.full(angles.size, 3.0)
    for centre in (-0.1, 0.1):
        ranges[np.abs(angles - centre) < 0.04] = 1.5
    fake = [
        Scan.from_angles(i * 0.1, float(angles[0]), float(angles[-1]), float(angles[1] - angles[0]),
                         ranges, sensor="warm-up", index=i)
        for i in range(scans)
    ]  # fmt: skip
    frames = (f.with_fields(frame="sensor") for f in laser_frames(fake))
    make_pipeline(frames, [_Encode(encoder)] if encoder is not None else []).run()
    return time.monotonic() - start


class StatusMeter:
    """Figures for a one-line status: scans/s over the last seconds, people now, latency,
    dropped.

    Args:
        session: The live session.
        span: Seconds over which the scan rate is measured.
    """

    def __init__(self, session: LiveSession, span: float = 2.0) -> None:
        self.session = session
        self.span = span
        # The first mark is taken now, so that the first line (10 s in when the output is
        # not a terminal) gives the rate since the start instead of 0.
        self._marks: list[tuple[float, int]] = [(time.monotonic(), self._received())]

    def _received(self) -> int:
        """Scans received so far, all lasers."""
        return sum(self.session.scans.counts.received.values())

    def line(self) -> str:
        """The status line now."""
        counts = self.session.scans.counts
        received = self._received()
        now = time.monotonic()
        self._marks.append((now, received))
        while len(self._marks) > 2 and self._marks[0][0] < now - self.span:
            self._marks.pop(0)
        t0, n0 = self._marks[0]
        rate = (received - n0) / (now - t0) if now > t0 else 0.0
        run = self.session.run
        step = run.last_step
        people = len(step.tracks.of_kind("person")) if step and step.tracks else 0
        recent = run.stats.arrival_ms.recent(50)
        latency = sorted(recent)[len(recent) // 2] if recent else 0.0
        return (
            f"{rate:5.1f} scans/s  {people} people  latency {latency:6.1f} ms  "
            f"dropped {sum(counts.dropped.values())}  frames {run.stats.frames}"
        )


__all__ = [
    "LiveRun",
    "LiveSession",
    "LiveTopics",
    "PipelineFactory",
    "Receiver",
    "StatusMeter",
    "key_style",
    "tracker_pipelines",
    "warm_up",
]
