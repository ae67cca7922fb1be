"""One batch task: track one recording (each laser topic, or fused) and write its tracks.

:func:`track_recording` is what a Dask worker runs; it is a plain function, so that the
same flow runs without Dask (``track_recording(task)``). It never raises for a bad
recording: the error becomes a :class:`TopicRow` with ``status = "failed"``. Tracks are
written to a temporary name beside the final one and renamed when complete, so a killed
worker leaves no file that a rerun would take for done; a start marker per attempt
(:func:`attempt_marker`) lets the client count the attempts of a task whose worker died.
"""

from __future__ import annotations

import os
import time
import traceback
import uuid
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from laserpeople.batch.options import ResolvedTrack
from laserpeople.errors import LaserPeopleError, RecordingError

FAILED = "failed"
DONE = "done"
SKIPPED = "skipped"
UNKNOWN = -1
"""A row's ``detector_used`` / ``static_model_used`` when not known."""


@dataclass(frozen=True)
class RecordingTask:
    """What a worker needs to track one recording.

    Attributes:
        recording: The recording (a path the worker can read).
        name: Unique output stem of this recording in the run.
        out: The output folder (shared by client and workers).
        resolved: The resolved options and parameters.
        input_hash: Content hash of the recording (recorded in the rows).
    """

    recording: Path
    name: str
    out: Path
    resolved: ResolvedTrack
    input_hash: str = ""

    @property
    def key(self) -> str:
        """The task's key (Dask key and manifest key): name and configuration digest."""
        return f"track-{self.name}-{self.resolved.digest[:12]}"


@dataclass(frozen=True)
class TopicRow:
    """One summary row: a recording's laser topic (or ``fused``), tracked or failed.

    Attributes:
        recording: The recording path.
        name: Its output stem.
        topic: The laser topic, ``fused``, or empty when the recording did not open.
        scans: Frames tracked.
        duration_s: Last minus first frame stamp [s].
        people: Most person tracks in one scan.
        ids: Distinct person track ids.
        person_seconds: Person tracks summed over scans, each scan weighted by the time
            since the scan before it [s].
        track_ms_per_scan: Mean tracking time per scan [ms] (detection excluded).
        seconds: Wall time of the whole topic on the worker [s] (reading, detecting,
            tracking, writing).
        rows: Tracks rows written.
        output: The tracks file (relative to the output folder; empty when failed).
        status: ``done``, ``failed`` or ``skipped`` (done by an earlier run).
        error: The error, for a failed row.
        attempts: Times the task was started (> 1: a worker died and it was redone).
        worker: Host name and process id that ran it.
        input_hash: Content hash of the recording.
        config_hash: Digest of the resolved configuration.
        notes: What the read left out or changed, as ``track`` says it (scans skipped
            with ``--on-error skip``, intensities left out, a laser's beam layout
            changing); empty when nothing.
        detector_used: 1 when the leg detector ran on some frame
            (:func:`~laserpeople.pipeline.background.detector_used`), 0 when not, -1 when
            unknown (a failed row, or one done by a version that did not record it).
        static_model_used: 1 when a static world model ran
            (:func:`~laserpeople.pipeline.background.static_model_used`), 0 when not, -1
            when unknown.
    """

    recording: str
    name: str
    topic: str
    scans: int = 0
    duration_s: float = 0.0
    people: int = 0
    ids: int = 0
    person_seconds: float = 0.0
    track_ms_per_scan: float = 0.0
    seconds: float = 0.0
    rows: int = 0
    output: str = ""
    status: str = DONE
    error: str = ""
    attempts: int = 1
    worker: str = ""
    input_hash: str = ""
    config_hash: str = ""
    notes: str = ""
    detector_used: int = UNKNOWN
    static_model_used: int = UNKNOWN


@dataclass
class _Counts:
    """What :func:`_track_topic` gathers frame by frame."""

    first: float | None = None
    last: float | None = None
    people: int = 0
    person_seconds: float = 0.0
    ids: set[int] = field(default_factory=set)

    @property
    def duration(self) -> float:
        """Last minus first stamp [s] (0 without frames)."""
        if self.first is None or self.last is None:
            return 0.0
        return self.last - self.first


def attempt_marker(out: Path, key: str) -> Path:
    """A new start marker of ``key`` (one file per attempt) in ``out``'s work folder."""
    return out / ".batch" / "attempts" / f"{key}.{uuid.uuid4().hex[:8]}"


def count_attempts(out: Path, key: str) -> int:
    """Attempts of ``key`` started since its markers were last cleared."""
    folder = out / ".batch" / "attempts"
    return sum(1 for _ in folder.glob(f"{key}.*")) if folder.is_dir() else 0


def clear_attempts(out: Path, key: str) -> None:
    """Forget the attempts of ``key`` (before it is submitted)."""
    folder = out / ".batch" / "attempts"
    if folder.is_dir():
        for marker in folder.glob(f"{key}.*"):
            marker.unlink(missing_ok=True)


def output_path(task: RecordingTask, topic: str | None) -> Path:
    """The tracks file of ``task`` for ``topic`` (None: the recording's only output)."""
    suffix = ".parquet" if task.resolved.options.format == "parquet" else ".csv"
    stem = task.name if topic is None else f"{task.name}.{_safe(topic)}"
    return task.out / "tracks" / f"{stem}{suffix}"


def _safe(topic: str) -> str:
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in topic.strip("/")) or "topic"


def topic_groups(task: RecordingTask) -> list[list[str]]:
    """The laser topics to track, grouped into runs: every laser on its own (no topics
    given), all fused (``all``), or the named ones fused."""
    from laserpeople.pipeline import open_source, resolve_topics

    options = task.resolved.options
    if options.topics:
        return [list(options.topics)]
    rec = open_source(task.recording, options.world_frame, options.mounts, options.on_error)
    try:
        return [[t] for t in resolve_topics(rec, ["all"])]
    finally:
        rec.close()


def track_recording(task: RecordingTask) -> list[TopicRow]:
    """Track every topic group of ``task``'s recording and write the tracks files.

    Returns one row per topic group; a recording that cannot be opened gives one failed
    row with an empty topic, a topic that fails a failed row (the others still run).
    """
    marker = attempt_marker(task.out, task.key)
    marker.parent.mkdir(parents=True, exist_ok=True)
    marker.touch()
    base = TopicRow(
        recording=str(task.recording),
        name=task.name,
        topic="",
        worker=f"{os.uname().nodename}:{os.getpid()}",
        input_hash=task.input_hash,
        config_hash=task.resolved.digest,
    )
    try:
        groups = topic_groups(task)
    except Exception as exc:  # a bad recording is a row, never a crash of the run
        return [_failed(base, exc)]
    rows = []
    for group in groups:
        topic = group[0] if len(group) == 1 and group != ["all"] else "fused"
        named = dict(base.__dict__, topic=topic)
        try:
            rows.append(_track_topic(task, group, TopicRow(**named), len(groups) > 1))
        except Exception as exc:
            rows.append(_failed(TopicRow(**named), exc))
    return rows


def _failed(row: TopicRow, exc: BaseException) -> TopicRow:
    from laserpeople.errors import LaserPeopleError

    text = str(exc) if isinstance(exc, LaserPeopleError) else f"{type(exc).__name__}: {exc}"
    frames = traceback.extract_tb(exc.__traceback__)
    if frames and not isinstance(exc, LaserPeopleError):
        text += f" (at {Path(frames[-1].filename).name}:{frames[-1].lineno})"
    return TopicRow(**dict(row.__dict__, status=FAILED, error=text))


def _track_topic(task: RecordingTask, topics: list[str], row: TopicRow, several: bool) -> TopicRow:
    from laserpeople.batch.parquet import TracksParquetSink
    from laserpeople.detection.detector import make_leg_detector
    from laserpeople.pipeline import TracksCsvSink, build
    from laserpeople.pipeline.background import detector_used, static_model_used
    from laserpeople.tracking import registry

    start = time.perf_counter()
    resolved = task.resolved
    options = resolved.options
    final = output_path(task, row.topic if several else None)
    final.parent.mkdir(parents=True, exist_ok=True)
    temp = final.with_name(f".{final.name}.{os.getpid()}-{uuid.uuid4().hex[:6]}.tmp")
    frame: Any = options.output_frame
    sink: Any = (
        TracksParquetSink(temp, frame=frame)
        if options.format == "parquet"
        else TracksCsvSink(temp, frame=frame, contours=resolved.contours)
    )
    try:
        pipe = build(
            task.recording,
            tracker=registry.get(options.tracker).make(resolved.tracker_params),
            topics=topics,
            detector=make_leg_detector(options.detector, options.model, resolved.detector_params),
            outputs=[sink],
            world_frame=options.world_frame,
            mounts=options.mounts,
            grouping=resolved.grouping,
            leg_fusion=resolved.leg_fusion,
            background=options.background,
            map_path=options.map_path,
            static_world=resolved.static_world,
            reidentify=options.reidentify,
            on_error=options.on_error,
            restamp=options.restamp,
        )
        topic = getattr(pipe.source, "topic", row.topic)  # the laser, when "all" is one
        counts = _Counts()
        for step in pipe:
            _count(counts, step.frame.stamp, step.tracks)
        os.replace(temp, final)
        notes = read_notes(pipe.source)
    except LaserPeopleError as exc:
        raise unwritten(exc, temp, final) from exc
    finally:
        temp.unlink(missing_ok=True)
    stats = pipe.stats
    return TopicRow(
        **dict(
            row.__dict__,
            topic=topic if isinstance(topic, str) else row.topic,
            scans=stats.frames,
            duration_s=counts.duration,
            people=counts.people,
            ids=len(counts.ids),
            person_seconds=counts.person_seconds,
            track_ms_per_scan=stats.mean_ms,
            seconds=time.perf_counter() - start,
            rows=stats.rows,
            output=str(final.relative_to(task.out)),
            notes=notes,
            detector_used=int(detector_used(pipe.stages)),
            static_model_used=int(static_model_used(pipe.stages)),
        )
    )


def unwritten(exc: LaserPeopleError, temp: Path, final: Path) -> LaserPeopleError:
    """``exc`` when it is not about the staging file ``temp``; otherwise the error of a
    tracks file ``final`` that could not be written (a full disk): named as ``final``, and
    saying that nothing of it is kept (``temp`` is removed, so what the writer says the
    file holds is gone with it) and that the same command again tracks the recording."""
    if exc.path != str(temp):
        return exc
    what = exc.detail.split("; it holds")[0]
    return RecordingError(
        f"{what}; nothing of it is kept (a tracks file is moved into place whole)",
        path=final,
        scan=exc.scan,
        hint="free disk space, then run the same command again: it tracks what is not done",
    )


def read_notes(source: Any) -> str:
    """What reading ``source`` (a :class:`~laserpeople.pipeline.RecordingFrames`) left out
    or changed: its reader's damaged-scan summary and the beam layout changes, one line."""
    damaged = getattr(getattr(source, "recording", None), "damaged", None)
    layouts = getattr(source, "layouts", None)
    parts = [
        damaged.summary() if damaged is not None else "",
        layouts.summary() if layouts is not None else "",
    ]
    return "; ".join(" ".join(p.split()) for p in parts if p)


def _count(counts: _Counts, stamp: float, tracks: Any) -> None:
    people = [] if tracks is None else tracks.of_kind("person")
    if counts.last is not None:
        counts.person_seconds += len(people) * max(stamp - counts.last, 0.0)
    if counts.first is None:
        counts.first = stamp
    counts.last = stamp
    counts.people = max(counts.people, len(people))
    counts.ids.update(t.track_id for t in people)


__all__ = [
    "DONE",
    "FAILED",
    "SKIPPED",
    "UNKNOWN",
    "RecordingTask",
    "TopicRow",
    "attempt_marker",
    "clear_attempts",
    "count_attempts",
    "output_path",
    "topic_groups",
    "track_recording",
]
