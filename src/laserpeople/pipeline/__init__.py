"""One pipeline for every tracker: source -> preprocess -> observe -> track -> identify -> sinks.

A :class:`~laserpeople.frame.Frame` (the scans of one instant and what the stages add)
flows through :class:`Pipeline`; each tracker declares what it consumes and the pipeline
refuses to build when nothing provides it. Track a recording in three lines::

    from laserpeople.pipeline import build

    stats = build("run.bag", tracker="leg-mht", outputs=["tracks.csv", "tracks.mcap"]).run()
    print(stats.frames, stats.count("person"))

Modules: :mod:`.sources` (one laser, several lasers grouped by time, the frame choice),
:mod:`.preprocess` (fusion into one point set), :mod:`.background` (which static world
model follows it), :mod:`.observe` (legs, clusters),
:mod:`.stages` (protocols and the build-time check), :mod:`.sinks` (CSV, bag),
:mod:`.recording` (frames from a file; :func:`build`).
"""

from laserpeople.pipeline.appearance import (
    AppearanceUnavailableError,
    SimulatedAppearance,
    with_appearance,
)
from laserpeople.pipeline.background import (
    BACKGROUND_CHOICES,
    AutoBackground,
    background_of,
    background_stage,
    describe_background,
    describe_foreground,
)
from laserpeople.pipeline.core import Pipeline, PipelineStats, Step
from laserpeople.pipeline.leg_foreground import LegForeground, LegForegroundParams
from laserpeople.pipeline.observe import ClusterPoints, DetectLegs, LegFusionParams
from laserpeople.pipeline.preprocess import Fuse
from laserpeople.pipeline.recording import (
    ALL_TOPICS,
    RecordingFrames,
    build,
    observe_stages_for,
    open_source,
    output_sink,
    resolve_topics,
)
from laserpeople.pipeline.sinks import DetectionsCsvSink, TracksBagSink, TracksCsvSink
from laserpeople.pipeline.sources import (
    FUSED,
    FrameChooser,
    GroupingParams,
    LaserGrouper,
    laser_frames,
)
from laserpeople.pipeline.stages import Identifier, Sink, Stage, check_feeds
from laserpeople.pipeline.stamps import Restamp, StampCheck

__all__ = [
    "ALL_TOPICS",
    "BACKGROUND_CHOICES",
    "FUSED",
    "AppearanceUnavailableError",
    "AutoBackground",
    "ClusterPoints",
    "DetectLegs",
    "DetectionsCsvSink",
    "FrameChooser",
    "Fuse",
    "GroupingParams",
    "Identifier",
    "LaserGrouper",
    "LegForeground",
    "LegForegroundParams",
    "LegFusionParams",
    "Pipeline",
    "PipelineStats",
    "RecordingFrames",
    "Restamp",
    "SimulatedAppearance",
    "Sink",
    "Stage",
    "StampCheck",
    "Step",
    "TracksBagSink",
    "TracksCsvSink",
    "background_of",
    "background_stage",
    "build",
    "check_feeds",
    "describe_background",
    "describe_foreground",
    "laser_frames",
    "observe_stages_for",
    "open_source",
    "output_sink",
    "resolve_topics",
    "with_appearance",
]
