"""The streaming pipeline: source -> preprocess -> observe -> track -> identify -> sinks."""

from __future__ import annotations

import time
from collections.abc import Iterable, Iterator, Sequence
from contextlib import suppress
from dataclasses import dataclass, field
from os import PathLike

from laserpeople.distinct_ids import DistinctIds
from laserpeople.errors import LaserPeopleError
from laserpeople.frame import Frame, FrameField, FrameTracker
from laserpeople.pipeline.stages import Identifier, Sink, Stage, check_feeds
from laserpeople.samples import Samples
from laserpeople.scan import Scan
from laserpeople.tracks import TrackKind, Tracks

_MAKE_FRAMES = (
    "make frames of a recording's scans first, "
    "FrameChooser()(laser_frames(open_recording(path).scans())), or use build(path)"
)


@dataclass(frozen=True)
class Step:
    """What one frame produced.

    Attributes:
        frame: The frame after every stage.
        tracks: The tracks after it (None without a tracker).
        track_seconds: Time the tracker took on it [s].
    """

    frame: Frame
    tracks: Tracks | None
    track_seconds: float = 0.0


@dataclass
class PipelineStats:
    """Counts and timings of a run.

    Attributes:
        frames: Frames processed.
        rows: Tracks reported, summed over frames.
        track_ids: Distinct track ids per kind (runs of consecutive ids, see
            :class:`~laserpeople.distinct_ids.DistinctIds`).
        track_ms: Tracking time per frame [ms] (every frame's up to
            :data:`~laserpeople.samples.CAPACITY`, then a sample of the run).
        stage_cpu: Process CPU time [s] each stage of the pipeline (preprocess and
            observe, in order) took over all frames.
    """

    frames: int = 0
    rows: int = 0
    track_ids: dict[str, DistinctIds] = field(default_factory=dict)
    track_ms: Samples = field(default_factory=Samples)
    stage_cpu: list[float] = field(default_factory=list)

    def count(self, kind: TrackKind) -> int:
        """Distinct track ids of one kind."""
        return len(self.track_ids.get(kind, ()))

    @property
    def median_ms(self) -> float:
        """Median tracking time per frame [ms]."""
        return self.track_ms.quantile(0.5)

    @property
    def mean_ms(self) -> float:
        """Mean tracking time per frame [ms]."""
        return self.track_ms.mean


class Pipeline:
    """One frame in, tracks out: a streaming composition of stages.

    Built once; iterating runs it (each :class:`Step` as it comes, constant memory) and
    :meth:`run` runs it to the end. The sinks are closed when the iteration ends, also on
    an error (a CSV then holds the frames done so far).

    Args:
        source: Frames with ``scans`` (see :mod:`laserpeople.pipeline.sources`).
        preprocess: Stages run first (fusion, static world model).
        observe: Stages run next (segmentation, clustering, leg detection).
        tracker: The tracker, or None for a pipeline that only observes (``detect``).
        identify: Identity stages run on the tracks (e.g. colour re-identification).
        sinks: Outputs.
        source_fields: What the source fills (``appearance`` for a camera or simulator).
        lookahead: Frames read ahead from the source at a time (1: none). A stage with a
            ``prefetch(frames)`` method before which no stage provides ``scans`` (leg
            detection) is then given each block first and works on all its scans at once;
            the results are the same, the fixed cost of its array operations is paid once
            per block. For recordings, not for a live source (it waits for the block).
            An error of the source is raised after the frames read before it; an error of
            a stage's ``prefetch`` leaves the stage to work frame by frame, where it meets
            the error at its frame.

    Raises:
        ConfigError: A stage, the tracker or an identifier consumes a field that nothing
            before it provides (at construction, not at frame 5,000).
    """

    def __init__(
        self,
        source: Iterable[Frame],
        *,
        preprocess: Sequence[Stage] = (),
        observe: Sequence[Stage] = (),
        tracker: FrameTracker | None = None,
        identify: Sequence[Identifier] = (),
        sinks: Sequence[Sink] = (),
        source_fields: frozenset[FrameField] = frozenset({"scans"}),
        lookahead: int = 1,
    ) -> None:
        if isinstance(source, Scan | Frame | str | PathLike):
            got = (
                f"one {type(source).__name__}"
                if isinstance(source, Scan | Frame)
                else f"the path {str(source)!r}"
            )
            raise TypeError(
                f"Pipeline(): source must be an iterable of Frame, got {got}: {_MAKE_FRAMES}"
            )
        self.source = source
        self.lookahead = max(1, int(lookahead))
        self.stages: tuple[Stage, ...] = (*preprocess, *observe)
        self.tracker = tracker
        self.identify = tuple(identify)
        self.sinks = tuple(sinks)
        consumers: list[tuple[str, object]] = []
        if tracker is not None:
            consumers.append((f"tracker {type(tracker).__name__}", tracker))
        consumers += [(f"identifier {type(i).__name__}", i) for i in self.identify]
        self.fields = check_feeds(source_fields, self.stages, consumers)
        self.stats = PipelineStats(stage_cpu=[0.0] * len(self.stages))
        self._ahead: list[int] = []  # stages given each block of frames first
        for i, stage in enumerate(self.stages):
            if "scans" in getattr(stage, "provides", ()):
                break
            if callable(getattr(stage, "prefetch", None)):
                self._ahead.append(i)

    def stage_cpu(self, stage: object) -> float:
        """Process CPU time [s] ``stage`` (one of :attr:`stages`) took so far."""
        return sum(
            cpu for s, cpu in zip(self.stages, self.stats.stage_cpu, strict=True) if s is stage
        )

    def __iter__(self) -> Iterator[Step]:
        stats = self.stats
        try:
            clock, stage_cpu = time.process_time, stats.stage_cpu
            for frame in self._frames():
                if isinstance(frame, Scan):  # (an iterable of scans: not caught by a stage)
                    raise TypeError(
                        "Pipeline(): source must be an iterable of Frame, got an item of type "
                        f"Scan: {_MAKE_FRAMES}"
                    )
                before = clock()
                for i, stage in enumerate(self.stages):
                    frame = stage(frame)
                    after = clock()
                    stage_cpu[i] += after - before
                    before = after
                tracks: Tracks | None = None
                seconds = 0.0
                if self.tracker is not None:
                    t0 = time.perf_counter()
                    tracks = self.tracker.update(frame)
                    seconds = time.perf_counter() - t0
                    for ident in self.identify:
                        tracks = ident.update(tracks, frame)
                    stats.track_ms.append(1e3 * seconds)
                    stats.rows += len(tracks)
                    by_kind = stats.track_ids
                    for t in tracks.tracks:
                        ids = by_kind.get(t.kind)
                        if ids is None:  # (not setdefault: it would build one per row)
                            ids = by_kind[t.kind] = DistinctIds()
                        ids.add(t.track_id)
                for sink in self.sinks:
                    sink.write(frame, tracks)
                stats.frames += 1
                yield Step(frame, tracks, seconds)
        except GeneratorExit:  # the caller stopped taking frames: no failure
            raise
        except BaseException as exc:
            self.close(failed=exc)
            raise
        finally:
            self.close()

    def _frames(self) -> Iterator[Frame]:
        """The source's frames, read ``lookahead`` at a time; the stages of ``_ahead`` get
        each block first (their CPU time counted as theirs)."""
        if self.lookahead <= 1 or not self._ahead:
            yield from self.source
            return
        frames = iter(self.source)
        clock, stage_cpu = time.process_time, self.stats.stage_cpu
        while True:
            block: list[Frame] = []
            error: Exception | None = None
            try:
                while len(block) < self.lookahead:
                    block.append(next(frames))
            except StopIteration:
                pass
            except Exception as exc:  # raised once the frames before it are through
                error = exc
            if block:
                for i in self._ahead:
                    t0 = clock()
                    with suppress(Exception):  # (the stage meets it again at its frame)
                        self.stages[i].prefetch(block)  # type: ignore[attr-defined]
                    stage_cpu[i] += clock() - t0
            yield from block
            if error is not None:
                raise error
            if len(block) < self.lookahead:
                return

    def close(self, failed: BaseException | None = None) -> None:
        """Close the sinks (and the source, when it can be closed); once (a second call,
        as after an interruption, does nothing).

        ``failed``: the error that stopped the run. Sinks with an ``abandon()`` method are
        then abandoned instead (a CSV no scan came to stays as it was), and what they say
        about it is added to the error's message (a :class:`LaserPeopleError`) or shown
        as a note.
        """
        if getattr(self, "_closed", False):
            return
        self._closed = True
        for sink in self.sinks:
            abandon = getattr(sink, "abandon", None) if failed is not None else None
            if not callable(abandon):
                sink.close()
                continue
            said = abandon()
            if said and isinstance(failed, LaserPeopleError):
                failed.noted(said)
            elif said:
                failed.add_note(said)  # type: ignore[union-attr]
        close = getattr(self.source, "close", None)
        if callable(close):
            close()

    def run(self) -> PipelineStats:
        """Run to the end; returns the counts and timings."""
        for _ in self:
            pass
        return self.stats


__all__ = ["Pipeline", "PipelineStats", "Step"]
