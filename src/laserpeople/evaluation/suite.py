"""A fixed benchmark of simulated scenes for people trackers (``benchmarks/people_suite.py``,
``benchmarks/peers.py``): simulate, detect legs with the real detector, track, score.

Every tracker runs on the same scans and the same leg detections; per scene it gets CLEAR
MOT, IDF1 and the person-track-seconds on static objects (:func:`static_track_seconds`),
and the CPU time of its ``update`` per scan (``time.process_time``: the time this process
spent computing, not the wall clock, which other processes on the machine stretch).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from laserpeople.evaluation.params import EvaluationParams
from laserpeople.evaluation.report import evaluate
from laserpeople.io.tracks_csv import convert_tracks
from laserpeople.scan import Scan
from laserpeople.tracks import Detections, Tracks
from laserpeople.truth import TruthFrame

STATIC_NEAR = 0.3
"""A person track within this distance [m] of a return from a static object sits on it."""
PERSON_CLEARANCE = 0.75
"""... unless it is within this distance [m] of a true person (the CLEAR MOT gate)."""


@dataclass(frozen=True)
class SuiteScene:
    """One scene of the suite: a scenario of the library, a seed and a length.

    Attributes:
        family: The row of the report the scene counts towards.
        scenario: Scenario name (``laserpeople scenarios``).
        seed: Seed.
        seconds: Length [s]; the scenario's default when None.
    """

    family: str
    scenario: str
    seed: int
    seconds: float | None = None


@dataclass(frozen=True, eq=False)
class PreparedScene:
    """A simulated scene with its leg detections, ready to be tracked by any tracker.

    Attributes:
        scene: What was simulated.
        scans: The scans of the first sensor (with beam labels and poses).
        detections: The leg detections of each scan.
        truth: One truth frame per scan.
        period: Median time between scans [s].
        detect_ms: CPU time of the detector per scan [ms].
        laser_height: Mount height [m] of the first sensor (None: not stated).
    """

    scene: SuiteScene
    scans: list[Scan]
    detections: list[Detections]
    truth: list[TruthFrame]
    period: float
    detect_ms: float
    laser_height: float | None = None


def prepare(scene: SuiteScene, detector: Any) -> PreparedScene:
    """Simulate ``scene`` and run ``detector`` (``detect(scan) -> Detections``) on it."""
    from laserpeople.pipeline.laser_height import laser_heights
    from laserpeople.sim.scenarios import run_scenario

    result = run_scenario(scene.scenario, seconds=scene.seconds, seed=scene.seed)
    first = result.scans[0].sensor
    scans = [s for s in result.scans if s.sensor == first]
    t0 = time.process_time()
    dets = [detector.detect(s) for s in scans]
    cpu = time.process_time() - t0
    stamps = np.array([s.stamp for s in scans])
    period = float(np.median(np.diff(stamps))) if stamps.size > 1 else 0.1
    return PreparedScene(
        scene,
        scans,
        dets,
        result.truth,
        period,
        1e3 * cpu / max(len(scans), 1),
        laser_heights(result).get(first),
    )


@dataclass(frozen=True)
class StaticTracks:
    """Person tracks sitting on static objects.

    Attributes:
        seconds: Person-track-seconds on static objects (track-scans x scan period).
        track_scans: Person-track-scans on static objects.
        ids: Distinct person track ids that were ever on a static object.
    """

    seconds: float
    track_scans: int
    ids: int


def static_track_seconds(
    scans: Sequence[Scan],
    tracks: Sequence[Tracks],
    truth: Sequence[TruthFrame],
    period: float,
    *,
    near: float = STATIC_NEAR,
    clearance: float = PERSON_CLEARANCE,
) -> StaticTracks:
    """Person-track-seconds on static objects in a simulated recording.

    A person track of scan k is *on a static object* when a return of that scan from
    something that is not a person (beam label ``person < 0``: walls, furniture, clutter)
    lies within ``near`` of it and no true person of the scan is within ``clearance``.
    Positions are compared in the scan's world frame (its pose; odometry poses for a robot
    with odometry, which is also the frame the tracker worked in).

    Args:
        scans: The scans, with labels and poses, one per element of ``tracks``/``truth``.
        tracks: The tracker's output per scan.
        truth: Ground truth per scan.
        period: Scan period [s].
    """
    from scipy.spatial import cKDTree

    on = 0
    ids: set[int] = set()
    for scan, out, frame in zip(scans, tracks, truth, strict=True):
        persons = out.of_kind("person")
        if not persons or scan.labels is None:
            continue
        world = convert_tracks(out, "world") if out.frame != "world" else out
        xy = np.array([t.position for t in world.of_kind("person")]).reshape(-1, 2)
        pts = scan.points("world")
        static = scan.valid & (scan.labels.person < 0)
        if not static.any():
            continue
        dist, _ = cKDTree(pts[static]).query(xy)
        hit = dist <= near
        if len(frame):
            d = np.hypot(*(xy[:, None, :] - frame.positions[None, :, :]).transpose(2, 0, 1))
            hit &= d.min(axis=1) > clearance
        on += int(hit.sum())
        ids.update(int(t.track_id) for t, h in zip(persons, hit.tolist(), strict=True) if h)
    return StaticTracks(on * period, on, len(ids))


@dataclass(frozen=True)
class SceneScore:
    """One tracker on one scene.

    Attributes:
        scene: The scene.
        tracker: Tracker label.
        mota, idf1, motp: CLEAR MOT accuracy, identity F1, mean match distance [m] (NaN when
            the scene has no people).
        recall, precision: Of people-frames / person-track-frames.
        id_switches: CLEAR MOT identity switches.
        false_positives: Unmatched person-track-frames.
        person_ids: Distinct person track ids reported.
        static: Person tracks on static objects.
        cpu_ms: Mean CPU time of ``update`` per scan [ms].
        scans: Scans tracked.
        seconds: Length of the scene [s].
    """

    scene: SuiteScene
    tracker: str
    mota: float
    idf1: float
    motp: float
    recall: float
    precision: float
    id_switches: int
    false_positives: int
    person_ids: int
    static: StaticTracks
    cpu_ms: float
    scans: int
    seconds: float


def track_scene(
    prepared: PreparedScene,
    make_tracker: Callable[[], Any],
    label: str,
    params: EvaluationParams | None = None,
) -> tuple[SceneScore, list[Tracks]]:
    """Run a fresh tracker over the prepared detections and score it (a tracker behind
    stages, ``tracker.stages``, with the ``auto`` static world model has its histogram
    learned from the whole scene first, as :func:`laserpeople.pipeline.build` does)."""
    from laserpeople.pipeline.prelearn import prelearn

    tracker = make_tracker()
    inputs: Sequence[Any] = prepared.detections
    if hasattr(tracker, "consumes"):  # a FrameTracker: one Frame per scan
        frames = frames_for(prepared, frozenset(tracker.consumes))
        prelearn(getattr(tracker, "stages", ()), lambda: frames)
        inputs = frames
    outs: list[Tracks] = []
    cpu = 0.0
    for item in inputs:
        t0 = time.process_time()
        out = tracker.update(item)
        cpu += time.process_time() - t0
        outs.append(out)
    return score_tracks(prepared, outs, label, cpu, params), outs


def frames_for(prepared: PreparedScene, consumes: frozenset[str]) -> list[Any]:
    """One :class:`~laserpeople.frame.Frame` per scan with ``scans`` and ``legs`` (in the
    world frame when the scan has a pose) filled, for trackers that take frames.

    Raises:
        ValueError: the tracker consumes a field the suite does not fill.
    """
    from laserpeople.frame import Frame

    missing = set(consumes) - {"scans", "legs"}
    if missing:
        raise ValueError(
            f"the suite fills only scans and legs; the tracker also needs {sorted(missing)}"
        )
    out = []
    for scan, dets in zip(prepared.scans, prepared.detections, strict=True):
        world = scan.pose is not None
        out.append(
            Frame(
                index=scan.index,
                stamp=scan.stamp,
                scans=(scan,),
                topic=scan.sensor,
                frame="world" if world else "sensor",
                sensor_pose=scan.pose,
                legs=dets.to_world() if world else dets,
            )
        )
    return out


def score_tracks(
    prepared: PreparedScene,
    outs: list[Tracks],
    label: str,
    cpu_seconds: float,
    params: EvaluationParams | None = None,
) -> SceneScore:
    """Score one tracker's output on a prepared scene."""
    n = len(prepared.scans)
    static = static_track_seconds(prepared.scans, outs, prepared.truth, prepared.period)
    people = sum(len(f) for f in prepared.truth)
    if people:
        report = evaluate(prepared.truth, outs, params, keep_frames=False).result()
        c, i = report.clear_mot, report.identity
        mota, idf1, motp = c.mota, i.idf1, c.motp
        recall, precision = c.recall, c.precision
        switches, fps = c.id_switches, c.false_positives
    else:
        mota = idf1 = motp = recall = precision = math.nan
        switches = 0
        fps = sum(len(o.of_kind("person")) for o in outs)
    ids = {t.track_id for o in outs for t in o.of_kind("person")}
    return SceneScore(
        prepared.scene,
        label,
        mota,
        idf1,
        motp,
        recall,
        precision,
        switches,
        fps,
        len(ids),
        static,
        1e3 * cpu_seconds / max(n, 1),
        n,
        n * prepared.period,
    )


@dataclass
class FamilySummary:
    """Means over the scenes of one family for one tracker.

    Attributes:
        family, tracker: Row keys.
        scenes: Scenes averaged.
        mota, idf1: Mean over the scenes that have people (NaN if none).
        id_switches: Mean per scene.
        static_seconds: Person-track-seconds on static objects, mean per scene.
        static_per_minute: Person-track-seconds on static objects per minute of recording.
        cpu_ms: Mean CPU time per scan over all scans of the family [ms].
    """

    family: str
    tracker: str
    scenes: int = 0
    mota: float = math.nan
    idf1: float = math.nan
    id_switches: float = 0.0
    static_seconds: float = 0.0
    static_per_minute: float = 0.0
    cpu_ms: float = 0.0
    extra: dict[str, float] = field(default_factory=dict)


def summarise(scores: Iterable[SceneScore]) -> list[FamilySummary]:
    """One :class:`FamilySummary` per (family, tracker), in order of first appearance."""
    groups: dict[tuple[str, str], list[SceneScore]] = {}
    for s in scores:
        groups.setdefault((s.scene.family, s.tracker), []).append(s)
    out = []
    for (family, tracker), items in groups.items():
        with_people = [s for s in items if math.isfinite(s.mota)]
        scans = sum(s.scans for s in items)
        seconds = sum(s.seconds for s in items)
        static = sum(s.static.seconds for s in items)
        out.append(
            FamilySummary(
                family,
                tracker,
                len(items),
                float(np.mean([s.mota for s in with_people])) if with_people else math.nan,
                float(np.mean([s.idf1 for s in with_people])) if with_people else math.nan,
                float(np.mean([s.id_switches for s in items])),
                static / len(items),
                60.0 * static / seconds if seconds else math.nan,
                sum(s.cpu_ms * s.scans for s in items) / scans if scans else math.nan,
            )
        )
    return out


def format_table(rows: Sequence[FamilySummary]) -> str:
    """The summaries as a fixed-width text table."""
    head = (
        f"{'family':22s} {'tracker':15s} {'scenes':>6s} {'MOTA':>7s} {'IDF1':>7s} "
        f"{'IDsw/scene':>10s} {'static s/scene':>14s} {'static s/min':>12s} {'CPU ms/scan':>11s}"
    )
    lines = [head, "-" * len(head)]
    for r in rows:
        lines.append(
            f"{r.family:22s} {r.tracker:15s} {r.scenes:6d} {r.mota:7.3f} {r.idf1:7.3f} "
            f"{r.id_switches:10.1f} {r.static_seconds:14.1f} {r.static_per_minute:12.1f} "
            f"{r.cpu_ms:11.2f}"
        )
    return "\n".join(lines)
