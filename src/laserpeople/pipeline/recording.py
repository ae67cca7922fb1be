"""Frames from a recording file, and a whole pipeline for one in a single call.

:class:`RecordingFrames` reads one laser (frames = its scans) or several (grouped by time,
:class:`~laserpeople.pipeline.sources.LaserGrouper`) and fixes the coordinate frame for the
run (:class:`~laserpeople.pipeline.sources.FrameChooser`). :func:`build` adds the stages a
registered tracker consumes and the sinks named by file extension.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from laserpeople.errors import ConfigError
from laserpeople.frame import Frame, FrameField
from laserpeople.io import RecordingSource, is_rosbag, open_recording
from laserpeople.io.damage import check_on_error
from laserpeople.io.paths import check_outputs, path_argument
from laserpeople.io.topics import no_laser_topic
from laserpeople.pipeline.background import (
    StaticWorldParams,
    background_of,
    background_stage,
    set_laser_height,
    static_model_used,
)
from laserpeople.pipeline.core import Pipeline
from laserpeople.pipeline.duplicate_scans import DuplicateScanCheck
from laserpeople.pipeline.empty_scans import EmptyScanCheck
from laserpeople.pipeline.laser_height import laser_heights
from laserpeople.pipeline.layout import LayoutCheck
from laserpeople.pipeline.leg_foreground import wants_torso_runs
from laserpeople.pipeline.observe import ClusterPoints, DetectLegs, LegDetector, LegFusionParams
from laserpeople.pipeline.prelearn import ShowProgress, prelearn
from laserpeople.pipeline.preprocess import Fuse
from laserpeople.pipeline.sinks import TracksBagSink, TracksCsvSink
from laserpeople.pipeline.sources import (
    FUSED,
    FrameChoice,
    FrameChooser,
    GroupingParams,
    LaserGrouper,
    laser_frames,
)
from laserpeople.pipeline.stages import Identifier, Sink, Stage
from laserpeople.pipeline.stamps import Restamp, StampCheck
from laserpeople.pipeline.static_people import (
    PeopleStaticModel,
    people_static_model,
    reads_foreground,
    uses_static_model,
)
from laserpeople.pipeline.static_tracks import StaticTrackFilter

if TYPE_CHECKING:
    from laserpeople.identity.leg_width import LegWidthReidentifier
    from laserpeople.identity.reid import ReidParams

ALL_TOPICS = "all"


def open_source(
    path: str | Path,
    world_frame: str | None = None,
    mounts: Sequence[str] = (),
    on_error: str = "stop",
) -> RecordingSource:
    """Open a recording; for ROS bags, ``world_frame`` and laser ``mounts``
    (``CHILD=PARENT:x,y,theta`` or a known robot such as ``mir100``) give sensor poses.
    ``on_error`` is the reader's policy for a damaged scan (``stop`` or ``skip``,
    :mod:`laserpeople.io.damage`); skipped scans are counted in the reader's ``damaged``."""
    policy = check_on_error(on_error)
    if not (world_frame or mounts):
        return open_recording(path, on_error=policy)
    if not is_rosbag(path):
        raise ConfigError(
            "--world-frame and --mount apply to ROS bags only",
            path=path,
            hint="drop them, or give a .bag, .mcap, .db3 or ROS 2 bag folder",
        )
    from laserpeople.io.poses import parse_mounts

    return open_recording(
        path, world_frame=world_frame, mounts=parse_mounts(list(mounts)), on_error=policy
    )


def check_recording_map(recording: RecordingSource, map_path: str | Path) -> None:
    """Read the map ``map_path`` (a ``map.yaml`` or ``BAG:/topic``) and refuse it when it
    names a frame other than the one ``recording``'s sensor poses are given in (ROS bags
    say which; other recordings and ``map.yaml`` files are not checked).

    Raises:
        MapFileError: the map cannot be read, or its frame is not the poses' frame.
    """
    from laserpeople.background.bag_map import check_map_frame, load_map

    grid = load_map(map_path)
    pose_frame = getattr(recording, "pose_frame", None)
    check_map_frame(grid, pose_frame() if callable(pose_frame) else None)


def resolve_topics(recording: RecordingSource, topics: Sequence[str] | None) -> list[str]:
    """The laser topics to read: ``topics`` as given (``["all"]``: every laser topic; a
    leading ``/`` is optional for bags), default the first laser topic."""
    names = [t.name for t in recording.topics()]
    if not names:
        no_laser_topic(recording, recording.path)
    if not topics:
        return names[:1]
    if list(topics) == [ALL_TOPICS]:
        return names
    if ALL_TOPICS in topics:
        raise ConfigError("--topics all cannot be combined with named topics")
    resolve = getattr(recording, "resolve_topics", None)
    if callable(resolve):
        return list(resolve(list(topics)))
    return list(topics)  # the reader raises TopicNotFoundError naming the topics it has


class RecordingFrames:
    """The frames of one or several lasers of a recording (iterate once).

    Args:
        recording: An open recording (closed with this object).
        topics: Laser topics; several are grouped into ``fused`` frames.
        frame: ``auto`` (world when most frames have sensor poses), ``world`` or ``sensor``.
        grouping: Tolerance and missing-laser policy for several lasers.
        window: Frames looked at before choosing the coordinate frame.
        max_frames: Stop after this many frames (None: all).
        restamp: Track at this fixed rate [Hz] instead of the recorded stamps
            (:class:`~laserpeople.pipeline.stamps.Restamp`). Without it, stamps that stay
            put for many scans are an error (:class:`~laserpeople.pipeline.stamps.StampCheck`).

    Attributes:
        chooser: The frame choice and what it dropped (``chooser.stats``).
        grouper: The grouping and its counts (None for one laser).
        restamper: The re-stamping and its counts (None without ``restamp``).
        layouts: The changes of a laser's beam layout seen so far.
        empty: The scans without a valid beam seen so far.
        duplicates: The scans dropped as copies of the scan before them so far.
    """

    def __init__(
        self,
        recording: RecordingSource,
        topics: Sequence[str],
        *,
        frame: FrameChoice = "auto",
        grouping: GroupingParams | None = None,
        window: int = 200,
        max_frames: int | None = None,
        restamp: float | None = None,
    ) -> None:
        self.recording = recording
        self.restamper = Restamp(restamp) if restamp is not None else None
        self.topics = list(topics)
        self.topic = self.topics[0] if len(self.topics) == 1 else FUSED
        self.grouper = LaserGrouper(self.topics, grouping) if len(self.topics) > 1 else None
        self.chooser = FrameChooser(frame, window)
        self.max_frames = max_frames
        self.layouts = LayoutCheck()
        self.empty = EmptyScanCheck()
        self.duplicates = DuplicateScanCheck()

    @property
    def total(self) -> int | None:
        """Frames to expect (the first laser's scan count), when the reader knows it."""
        count = next((t.count for t in self.recording.topics() if t.name == self.topics[0]), None)
        if count is not None and self.max_frames is not None:
            return min(count, self.max_frames)
        return count

    def __iter__(self) -> Iterator[Frame]:
        scans = self.duplicates(self.recording.scans(self.topics))
        scans = self.restamper(scans) if self.restamper is not None else StampCheck()(scans)
        scans = self.empty(self.layouts(scans))
        frames = laser_frames(scans, self.topic) if self.grouper is None else self.grouper(scans)
        for n, frame in enumerate(self.chooser(frames)):
            if self.max_frames is not None and n >= self.max_frames:
                return
            yield frame

    def summary(self) -> list[str]:
        """Lines for the user: given laser mounts left out; what the reader took other than
        as written (``read_notes``: zero stamps, a changed frame id); the frame used and why; the
        grouping figures; changes of a laser's beam layout; scans without a valid beam;
        scans dropped as copies."""
        lines = list(getattr(self.recording, "mount_notes", []))
        notes = getattr(self.recording, "read_notes", None)
        if callable(notes):
            lines.extend(notes())
        lines.append(self.chooser.stats.summary())
        if self.restamper is not None:
            lines.append(self.restamper.summary())
        if self.grouper is not None:
            lines.append(self.grouper.stats.summary())
        if self.layouts.changes:
            lines.append(self.layouts.summary())
        if self.empty.empty:
            lines.append(self.empty.summary())
        if self.duplicates.dropped:
            lines.append(self.duplicates.summary())
        return lines

    def close(self) -> None:
        """Close the recording."""
        self.recording.close()


def observe_stages_for(
    consumes: frozenset[FrameField],
    detector: LegDetector | None,
    leg_fusion: LegFusionParams | None = None,
    background: str | Stage | None = "auto",
    map_path: str | Path | None = None,
    static_world: StaticWorldParams | None = None,
    *,
    steady: bool = False,
    behind_people: bool = False,
) -> tuple[list[Stage], list[Stage]]:
    """The preprocess and observe stages that provide what a tracker ``consumes``.

    A consumer of ``foreground`` or ``clusters`` gets the static world model ``background``
    after :class:`Fuse` (see :func:`~laserpeople.pipeline.background.background_stage`:
    ``auto``, ``histogram``, ``occupancy``, ``none`` or a model object; ``map_path`` seeds
    the occupancy grid; ``static_world`` the models' parameters), so that walls and
    furniture are not foreground; ``auto`` narrows it to the points near legs found with
    ``detector`` on a moving laser (:mod:`laserpeople.pipeline.leg_foreground`; ``steady``:
    for a tracker that dies without points for a few scans, see
    :func:`~laserpeople.pipeline.leg_foreground.needs_steady_points`; ``behind_people``:
    the per-beam histogram of ``auto`` leaves out the legs detected while it learns, see
    :func:`~laserpeople.pipeline.leg_foreground.learns_behind_people`).
    """
    preprocess: list[Stage] = []
    observe: list[Stage] = []
    legs: DetectLegs | None = None
    if "legs" in consumes:
        if detector is None:
            from laserpeople.detection.detector import AdaBoostLegDetector

            detector = AdaBoostLegDetector.default()
        legs = DetectLegs(detector, leg_fusion)
    if consumes & {"points", "foreground", "clusters"}:
        preprocess.append(Fuse())
    if consumes & {"foreground", "clusters"}:
        model = background_stage(
            background,
            map_path,
            static_world,
            detector,
            steady=steady,
            behind_people=behind_people,
            legs_stage=legs,  # its legs of a frame are the narrowing's: detected once
        )
        if model is not None:
            preprocess.append(model)
    if "clusters" in consumes:
        observe.append(ClusterPoints())
    if legs is not None:
        observe.append(legs)
    return preprocess, observe


def add_people_static_model(
    tracker: object,
    preprocess: list[Stage],
    background: str | Stage | None,
    map_path: str | Path | None = None,
    static_world: StaticWorldParams | None = None,
) -> PeopleStaticModel | None:
    """For a tracker that asks a static world model (the leg MHT with people policy
    ``tracks``): append to ``preprocess`` (after a :class:`Fuse`, added when missing) the
    :class:`~laserpeople.pipeline.static_people.PeopleStaticModel` of ``background`` and
    hand it to the tracker; returns it (None: the tracker asks none, or ``none``).
    ``static_world`` holds the models' parameters (None: defaults)."""
    if not uses_static_model(tracker):
        return None
    model = people_static_model(background, map_path, static=static_world)
    tracker.use_static_model(model)
    if model is None:
        return None
    # a tracker that reads the foreground of its own background stage (the group tracker)
    # asks this model only how long places have been static
    model.fill_foreground = reads_foreground(tracker) and background_of(preprocess) is None
    _add_before_background(preprocess, model)
    return model


def add_static_track_filter(
    tracker: object,
    preprocess: list[Stage],
    background: str | Stage | None,
    map_path: str | Path | None = None,
    static_world: StaticWorldParams | None = None,
) -> StaticTrackFilter | None:
    """For a tracker without a static world model of its own (one that has no
    ``use_static_model``: ``nn``, ``csa``, ``feet-pf``, ``upper-body-pf``): append to
    ``preprocess`` (after a :class:`Fuse`, added when missing) the people's
    :class:`~laserpeople.pipeline.static_people.PeopleStaticModel` of ``background`` and
    return the identify stage that leaves out its person tracks on static places (None:
    ``static_tracks.hide`` is false, the tracker has a model of its own, or ``none``). A
    tracker that runs people of its own (``use_people_static_model``: the CSA's leg MHT of
    ``[csa] moving_people``) is handed the same model."""
    static_world = static_world if static_world is not None else StaticWorldParams()
    if callable(getattr(tracker, "use_static_model", None)):
        return None
    hide = static_world.static_tracks.hide
    asks = getattr(tracker, "use_people_static_model", None)
    if not hide and not callable(asks):
        return None
    model = people_static_model(background, map_path, static=static_world)
    if callable(asks):
        asks(model)
    if model is None:
        return None
    model.fill_foreground = False  # asked only how long places have been static
    _add_before_background(preprocess, model)
    return StaticTrackFilter(model, static_world.static_tracks) if hide else None


def leg_reid_stage(
    tracker: object, static_world: StaticWorldParams | None = None
) -> LegWidthReidentifier | None:
    """The identify stage that gives people who come back their old ids by their leg
    widths (:class:`~laserpeople.identity.leg_width.LegWidthReidentifier`, ``[leg_reid]`` of
    ``static_world``), for a tracker whose parameters switch it on (``leg_reid`` of
    ``[csa]``, ``[feet_pf]``, ``[upper_body_pf]``); None for any other tracker (the leg MHT
    re-identifies people itself) or when switched off. :func:`build`, the live runner and
    the benchmarks take their stage from here."""
    if not getattr(getattr(tracker, "params", None), "leg_reid", False):
        return None
    from laserpeople.identity.leg_width import LegWidthReidentifier

    static_world = static_world if static_world is not None else StaticWorldParams()
    return LegWidthReidentifier(static_world.leg_reid)


def _add_before_background(preprocess: list[Stage], model: PeopleStaticModel) -> None:
    """Add the people's ``model`` to ``preprocess``: after a :class:`Fuse` (added when
    missing) and before the static world model that fills the trackers' foreground, so that
    the people's model, which once dropped marks every point foreground, does not undo
    that foreground (:mod:`laserpeople.pipeline.leg_foreground`)."""
    if not any(isinstance(s, Fuse) for s in preprocess):
        preprocess.append(Fuse())
    background = background_of(preprocess)
    if background is None or model.fill_foreground:
        preprocess.append(model)
        return
    preprocess.insert(next(i for i, s in enumerate(preprocess) if s is background), model)


def tracker_stages(
    tracker: Any,
    *,
    consumes: frozenset[FrameField] | None = None,
    detector: LegDetector | None = None,
    leg_fusion: LegFusionParams | None = None,
    background: str | Stage | None = "auto",
    map_path: str | Path | None = None,
    static_world: StaticWorldParams | None = None,
) -> tuple[list[Stage], list[Stage], StaticTrackFilter | None]:
    """Everything :func:`build` puts between the frames and ``tracker``: the preprocess and
    observe stages of what it ``consumes`` (None: ``tracker.consumes``; a caller whose
    frames already hold some fields leaves them out, see :func:`observe_stages_for`), the
    people's static model of the leg MHT (:func:`add_people_static_model`) and the filter
    of person tracks on static places (:func:`add_static_track_filter`, None when not
    used)."""
    from laserpeople.pipeline.leg_foreground import learns_behind_people, needs_steady_points

    preprocess, observe = observe_stages_for(
        frozenset(tracker.consumes if consumes is None else consumes),
        detector,
        leg_fusion,
        background,
        map_path,
        static_world,
        steady=needs_steady_points(tracker),
        behind_people=learns_behind_people(tracker),
    )
    add_people_static_model(tracker, preprocess, background, map_path, static_world)
    hide = add_static_track_filter(tracker, preprocess, background, map_path, static_world)
    if map_path is not None and not static_model_used(preprocess):
        raise ConfigError(
            "--map seeds the static world model, but this run uses none",
            hint="drop --map; "
            + (
                "the leg MHT's arras people policy has no static world model "
                "(--people-policy tracks has)"
                if callable(getattr(tracker, "use_static_model", None))
                else "with static_tracks.hide = false nothing asks one"
            ),
        )
    return preprocess, observe, hide


def output_sink(path: str | Path) -> Sink:
    """A tracks sink by extension: ``.csv`` tracks CSV, ``.bag``/``.mcap``/``.db3`` a bag
    with the scans and the tracks as ROS messages."""
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix == ".csv":
        return TracksCsvSink(p)
    if suffix in (".bag", ".mcap", ".db3"):
        return TracksBagSink(p)
    from laserpeople.spelling import did_you_mean

    guess = did_you_mean(suffix, (".csv", ".bag", ".mcap", ".db3"), lead="; ") if suffix else ""
    raise ConfigError(
        f"cannot write tracks to {p.name!r}{guess}",
        hint="use .csv, .bag, .mcap or .db3",
    )


LOOKAHEAD = 16
"""Frames of a recording read ahead at a time, their legs detected at once
(:class:`~laserpeople.pipeline.Pipeline` ``lookahead``; measured on the real demo bag:
features and AdaBoost of 16 scans at once cost about a sixth per scan of one at a time,
64 no less than 16)."""


def build(
    recording: str | Path,
    *,
    tracker: str | Any = "leg-mht",
    params: Any = None,
    topics: Sequence[str] | None = None,
    detector: LegDetector | None = None,
    outputs: Sequence[str | Path | Sink] = (),
    frame: FrameChoice = "auto",
    world_frame: str | None = None,
    mounts: Sequence[str] = (),
    grouping: GroupingParams | None = None,
    leg_fusion: LegFusionParams | None = None,
    background: str | Stage | None = "auto",
    map_path: str | Path | None = None,
    static_world: StaticWorldParams | None = None,
    identify: Sequence[Identifier] = (),
    reidentify: bool = False,
    reid: ReidParams | None = None,
    max_frames: int | None = None,
    on_error: str = "stop",
    restamp: float | None = None,
    show_progress: ShowProgress | None = None,
) -> Pipeline:
    """A pipeline that tracks ``recording`` with a registered tracker (by name) or a
    tracker object, feeding it what it consumes (a consumer of ``foreground`` gets the
    static world model ``background``, see :func:`observe_stages_for`; the leg MHT's
    people get theirs too; ``static_world``: the models' parameters; ``auto`` on still
    lasers learns its histogram from the whole recording first, read once more before the
    pipeline is returned, :mod:`~laserpeople.pipeline.prelearn`). ``reidentify``
    adds colour re-identification (002,
    :class:`~laserpeople.identity.reid.ColourReidentifier`) fed by the simulated camera
    (:func:`~laserpeople.pipeline.appearance.with_appearance`; an
    ``AppearanceUnavailableError`` for a recording without ground-truth hues) with the
    parameters ``reid`` (``[reid]`` and ``[reid.appearance]``; defaults when None).
    ``on_error`` (``stop``/``skip``) is the reader's policy for a damaged scan (see
    :func:`open_source`). ``restamp`` [Hz] tracks at a fixed scan rate instead of the
    recorded stamps (see :class:`RecordingFrames`). ``show_progress`` wraps the frames of
    the pass over the whole recording to show its progress (e.g.
    :func:`laserpeople.cli.common.progress`; None: nothing shown).

    Example:
        >>> from laserpeople.pipeline import build  # doctest: +SKIP
        >>> stats = build("run.bag", outputs=["tracks.csv", "tracks.mcap"]).run()
    """
    from laserpeople.tracking import registry

    for name, given in (("topics", topics), ("outputs", outputs), ("mounts", mounts)):
        refuse_one_for_many(name, given)
    recording = path_argument(recording, "recording", "build")
    # (a bag output named as the recording would replace it with the tracks written)
    check_outputs(
        {f"outputs[{i}]": o for i, o in enumerate(outputs) if isinstance(o, str | Path)},
        [recording],
    )
    if isinstance(tracker, str):
        tracker = registry.get(tracker).make(params)
    rec = open_source(recording, world_frame, mounts, on_error)
    try:
        lasers = resolve_topics(rec, topics)
        source = RecordingFrames(
            rec,
            lasers,
            frame=frame,
            grouping=grouping,
            max_frames=max_frames,
            restamp=restamp,
        )
        frames: Any = source
        source_fields: set[FrameField] = {"scans"}
        identifiers = list(identify)
        if reidentify:
            from laserpeople.identity.reid import ColourReidentifier
            from laserpeople.pipeline.appearance import with_appearance

            frames = with_appearance(source, rec)
            source_fields.add("appearance")
            identifiers.append(ColourReidentifier(reid))
        preprocess, observe, hide_static = tracker_stages(
            tracker,
            detector=detector,
            leg_fusion=leg_fusion,
            background=background,
            map_path=map_path,
            static_world=static_world,
        )
        leg_reid = leg_reid_stage(tracker, static_world)
        if leg_reid is not None:
            identifiers.insert(0, leg_reid)
        if hide_static is not None:
            identifiers.insert(0, hide_static)
        # one laser of a stated height (a fused frame's beams are no one scan's); the
        # foreground keeps torso-shaped runs only for a tracker that takes them
        if len(lasers) == 1:
            told = [*preprocess, tracker] if wants_torso_runs(tracker) else [tracker]
            set_laser_height(told, laser_heights(rec).get(lasers[0]))
        if map_path is not None:
            check_recording_map(rec, map_path)
        prelearn(
            preprocess,
            lambda: RecordingFrames(
                open_source(recording, world_frame, mounts, on_error),
                lasers,
                frame=frame,
                grouping=grouping,
                max_frames=max_frames,
                restamp=restamp,
            ),
            show=show_progress,
        )
        sinks = [o if not isinstance(o, str | Path) else output_sink(o) for o in outputs]
        return Pipeline(
            frames,
            preprocess=preprocess,
            observe=observe,
            tracker=tracker,
            identify=identifiers,
            sinks=sinks,
            source_fields=frozenset(source_fields),
            lookahead=LOOKAHEAD,
        )
    except BaseException:
        rec.close()
        raise


def refuse_one_for_many(name: str, given: object) -> None:
    """Refuse a single name where a list of them is asked for: ``topics="/scan"`` would be
    read letter by letter (topic ``/``, then ``s``, ...).

    Raises:
        ConfigError: ``given`` is a string or a path; names the argument and how to write it.
    """
    if isinstance(given, str | Path):
        raise ConfigError(
            f"{name} takes a list, got the single {type(given).__name__} {str(given)!r}",
            hint=f"write {name}=[{str(given)!r}]",
        )


__all__ = [
    "ALL_TOPICS",
    "LOOKAHEAD",
    "RecordingFrames",
    "add_people_static_model",
    "add_static_track_filter",
    "build",
    "leg_reid_stage",
    "observe_stages_for",
    "open_source",
    "output_sink",
    "refuse_one_for_many",
    "resolve_topics",
    "tracker_stages",
]
