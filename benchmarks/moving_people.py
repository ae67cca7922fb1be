"""People seen from a moving robot, scored on the real dev recording of the leg_tracker
benchmark (Leigh et al. 2015, ``general_tracking_moving_1_first.bag``, issue 29).

A robot drives through the hallways and a lobby among people; 57 labels of 6 people on
scans 133-257 (laser frame; each label carries the index of the scan it belongs to). The
recording is tracked as ``laserpeople track`` runs it (world frame from ``/tf``, the
shipped AdaBoost detector, the leg MHT, the default static world model, ``--map`` when
given), every person track is moved into the laser frame of its scan, and each labelled
scan is scored with CLEAR MOT at the benchmark's 0.75 m gate: every person track on a
labelled scan that matches no label is a false positive (the benchmark's rule; the labels
are sparse, so a person in view but not labelled on that scan counts against the tracker
too). Scans without any label are not scored.

Printed: MOTA, recall, false positives, misses, id switches, the distinct person ids
matched to the labelled people (and per person), and with ``--per-scan`` a row per labelled
scan (labels, tracks, matches, false positives, the nearest track to each label).
``--ceiling`` also prints the labels with a leg detection within 0.5 m
(:func:`detection_ceiling`) and an oracle bound that needs neither our detector nor our
tracker (:func:`oracle_bound`, benchmarks/visible_people.py): the unlabelled people that
the raw returns show walking on the labelled scans (beside the robot, in :data:`BESIDE`,
and elsewhere), which the benchmark counts as false positives for any tracker that
reports them, and the MOTA of a tracker that reports every label and every one of them
(with ``--per-scan``, where they are on each scan).

Two more scores are printed after the benchmark's: CLEAR MOT with the companion's person
tracks left out (:func:`companion_tracks`: on the labelled scans far from every label,
inside :data:`BESIDE` grown by :data:`NEAR`, and once near an unlabelled leg detection
there; not the benchmark's score, the box is drawn for this recording), and the recall of
the detected labels (CLEAR MOT against the labels with a leg detection within :data:`NEAR`
only, :func:`detected_labels`). ``--diagnose`` prints, for each detected label, the stage
at which the pipeline loses it (:data:`STAGES`, :func:`diagnose`) and the count per stage.

    PYTHONPATH=src .venv/bin/python benchmarks/moving_people.py [--people-policy arras]
        [--background auto|occupancy|none] [--map BAG:/map | --map map.yaml]
        [--config params.toml] [--per-scan] [--ceiling] [--diagnose] [--bag PATH]
        [--labels PATH]
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import time
from collections import defaultdict
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from laserpeople.config import load_config
from laserpeople.detection.detector import AdaBoostLegDetector
from laserpeople.evaluation.clear_mot import ClearMot
from laserpeople.evaluation.params import EvaluationParams
from laserpeople.io import open_recording
from laserpeople.io.tracks_csv import convert_tracks
from laserpeople.pipeline import build
from laserpeople.pipeline.background import StaticWorldParams, load_static_world
from laserpeople.scan import Pose2D, Scan
from laserpeople.tracking import registry
from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams
from laserpeople.tracks import Detections, Tracks
from laserpeople.truth import TruthFrame
from visible_people import Oracle, Unlabelled, labels_shown, oracle, unlabelled_people

GATE = 0.75  # m, the benchmark's matching distance
TOPIC = "/scan"
NEAR = 0.5  # m, a label "has a detection" within this
BESIDE = (-1.3, 0.4, -2.3, -0.6)
"""x_min, x_max, y_min, y_max [m] in the laser frame: where a person walks beside the robot,
unlabelled, through the labelled part of the dev recording (seen in the pictures)."""


def default_paths() -> tuple[Path, Path]:
    """The dev bag and its label CSV under ``$LASERPEOPLE_SHARED_DATA`` (or ../shared/data)."""
    root = Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "../shared/data"))
    base = root / "leg_tracker_benchmarks" / "general_tracking_moving_1_first"
    return base.with_suffix(".bag"), Path(f"{base}.people.csv")


def read_labels(path: Path) -> dict[int, dict[int, np.ndarray]]:
    """Scan index -> {person id: position (2,) [m], laser frame}."""
    out: dict[int, dict[int, np.ndarray]] = defaultdict(dict)
    with path.open(newline="") as fh:
        for row in csv.DictReader(fh):
            out[int(row["scan"])][int(row["person_id"])] = np.array(
                [float(row["x"]), float(row["y"])]
            )
    return dict(out)


def in_sensor_frame(tracks: Tracks) -> Tracks:
    """``tracks`` with positions in the laser frame of their scan, marked as the frame the
    scorer compares in (``world``, without a pose: the labels are in the same frame)."""
    if tracks.frame != "sensor":
        tracks = convert_tracks(tracks, "sensor")
    return replace(tracks, frame="world", sensor_pose=None)


@dataclass(frozen=True)
class MovingScore:
    """CLEAR MOT of the labelled scans and the ids per labelled person.

    Attributes:
        mota: 1 - (misses + false positives + id switches) / labels.
        recall: Matched labels / labels.
        labels: Labels scored.
        scans: Labelled scans scored.
        matches: Matched labels.
        false_positives: Person tracks on labelled scans matched to no label.
        misses: Labels without a track.
        id_switches: CLEAR MOT id switches.
        ids: Distinct person track ids matched to a label.
        ids_per_person: Labelled person id -> distinct track ids matched to it.
        rows: Per labelled scan: (scan, labels, tracks, matches, false positives).
    """

    mota: float
    recall: float
    labels: int
    scans: int
    matches: int
    false_positives: int
    misses: int
    id_switches: int
    ids: int
    ids_per_person: dict[int, int]
    rows: tuple[tuple[int, int, int, int, int], ...]


def score_moving(tracks: Sequence[Tracks], labels: dict[int, dict[int, np.ndarray]]) -> MovingScore:
    """Score the person tracks (``tracks[i]`` of scan i, any frame with a sensor pose, or
    the sensor frame) against the laser-frame ``labels`` on the labelled scans."""
    metric = ClearMot(EvaluationParams(gate=GATE))
    by_scan = {t.scan_index: t for t in tracks}
    per_person: dict[int, set[int]] = defaultdict(set)
    rows: list[tuple[int, int, int, int, int]] = []
    for scan in sorted(labels):
        people = labels[scan]
        ids = np.array(sorted(people), dtype=np.int64)
        xy = np.array([people[i] for i in ids.tolist()], dtype=np.float64)
        stamp = by_scan[scan].stamp if scan in by_scan else float(scan)
        truth = TruthFrame(
            stamp,
            scan,
            ids,
            xy,
            np.zeros_like(xy),
            np.full(len(ids), -1),
            np.repeat(xy[:, None, :], 2, axis=1),
            np.zeros(len(ids)),
        )
        frame_tracks = by_scan.get(scan)
        sensor = None if frame_tracks is None else in_sensor_frame(frame_tracks)
        before = metric.result()
        metric.accumulate(truth, sensor)
        after = metric.result()
        n_tracks = 0 if sensor is None else len(sensor.of_kind("person"))
        rows.append(
            (
                scan,
                len(ids),
                n_tracks,
                after.matches - before.matches,
                after.false_positives - before.false_positives,
            )
        )
        if sensor is not None:
            persons = sensor.of_kind("person")
            for pid, pos in zip(ids.tolist(), xy, strict=True):
                d = [float(np.hypot(*(t.position - pos))) for t in persons]
                if d and min(d) <= GATE:
                    per_person[pid].add(persons[int(np.argmin(d))].track_id)
    r = metric.result()
    matched_ids = set().union(*per_person.values()) if per_person else set()
    return MovingScore(
        mota=r.mota,
        recall=r.recall,
        labels=r.num_truth,
        scans=r.num_frames,
        matches=r.matches,
        false_positives=r.false_positives,
        misses=r.misses,
        id_switches=r.id_switches,
        ids=len(matched_ids),
        ids_per_person={p: len(v) for p, v in sorted(per_person.items())},
        rows=tuple(rows),
    )


@dataclass(frozen=True)
class Ceiling:
    """What the shipped detector finds of the labelled people.

    Attributes:
        labels: Labels.
        detected: Labels with a leg detection within :data:`NEAR`.
        scans: Labelled scans.
    """

    labels: int
    detected: int
    scans: int


def detection_ceiling(
    legs: dict[int, np.ndarray], labels: dict[int, dict[int, np.ndarray]]
) -> Ceiling:
    """:class:`Ceiling` from the leg detections (scan -> (M, 2) [m], laser frame) and the
    laser-frame ``labels``."""
    detected = 0
    for scan, people in labels.items():
        xy = legs.get(scan, np.empty((0, 2))).reshape(-1, 2)
        truth = np.array(list(people.values()), dtype=np.float64)
        d = np.hypot(*(xy[:, None, :] - truth[None, :, :]).transpose(2, 0, 1))  # (M, P)
        detected += int((d <= NEAR).any(axis=0).sum()) if len(xy) else 0
    return Ceiling(sum(len(p) for p in labels.values()), detected, len(labels))


def raw_scans(bag: Path) -> list[Scan]:
    """Every scan of :data:`TOPIC` with its sensor pose (as ``track`` reads them), each
    with its own copy of the ranges."""
    recording = open_recording(bag)
    try:
        return [replace(s, ranges=s.ranges.copy()) for s in recording.scans([TOPIC])]
    finally:
        recording.close()


def oracle_bound(
    bag: Path, labels: dict[int, dict[int, np.ndarray]]
) -> tuple[Oracle, list[Unlabelled]]:
    """What a tracker that reports every person the raw scans show can score on the
    labelled scans (:mod:`visible_people`: walkers farther than :data:`GATE` from every
    label, those in :data:`BESIDE` apart), and the unlabelled people per labelled scan."""
    scans = raw_scans(bag)
    seen = unlabelled_people(scans, labels, BESIDE, GATE)
    return oracle(labels, labels_shown(scans, labels, NEAR), seen), seen


def print_oracle(o: Oracle, seen: Sequence[Unlabelled], per_scan: bool) -> None:
    """The oracle's figures (and with ``per_scan`` the unlabelled people of each scan)."""
    if per_scan:
        print("scan  unlabelled people [m, laser frame]: beside the robot | others")
        for u in seen:
            if u.beside or u.others:
                b = " ".join(f"({x:+.2f},{y:+.2f})" for x, y in u.beside) or "-"
                r = " ".join(f"({x:+.2f},{y:+.2f})" for x, y in u.others) or "-"
                print(f"{u.scan:4d}  {b} | {r}")
    print(f"labels with a person-sized raw cluster within {NEAR} m: {o.shown} of {o.labels}")
    print(f"unlabelled walkers on the labelled scans (raw returns): {o.unlabelled}")
    print(f"labelled scans with an unlabelled walker beside the robot: {o.beside} of {o.scans}")
    print(f"MOTA reporting every label and every walker shown: {o.mota:.3f}")
    print(f"MOTA at recall 0.70 reporting every walker shown: {o.mota_at_recall(0.7):.3f}")
    print(
        f"false positives allowed at recall 0.70 for MOTA 0.50: {o.max_false_positives(0.7, 0.5)}"
    )
    need = o.min_recall(0.5)
    print(
        f"recall needed for MOTA 0.50 reporting every walker: {need:.3f}"
        if need <= 1.0
        else "recall needed for MOTA 0.50 reporting every walker: none reaches it"
    )


STAGES = (
    "left out as static",
    "no leg track",
    "no person candidate",
    "candidate not confirmed",
    "confirmed, not reported",
    "reported, too far",
    "tracked",
)
"""Where the pipeline loses a detected label (:func:`diagnose_label`), in pipeline order:
every leg detection within :data:`NEAR` left out of the leg MHT as furniture (static
world); no leg track of the best hypothesis within :data:`NEAR`; no person (candidate or
confirmed) with such a leg as a member or within :data:`GATE`; only unconfirmed
candidates; a confirmed person not in the output (unseen for longer than
``max_report_unseen``); person tracks in the output but none within :data:`GATE`; a
person track within :data:`GATE` (tracked)."""


@dataclass(frozen=True)
class LabelStage:
    """Where one detected label is lost (:data:`STAGES`).

    Attributes:
        scan: Scan index.
        person: Labelled person id.
        distance: Range of the label from the laser [m].
        stage: One of :data:`STAGES`.
        llr: Existence score of the nearest person candidate (NaN without one).
        score: Highest detector score of the leg detections within :data:`NEAR`.
    """

    scan: int
    person: int
    distance: float
    stage: str
    llr: float
    score: float


def _to_sensor(pose: Pose2D | None, xy: np.ndarray) -> np.ndarray:
    xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
    return xy if pose is None else pose.inverse_transform_points(xy)


def diagnose_label(
    tracker: LegMHTTracker, step_tracks: Tracks, legs: Detections, pos: np.ndarray
) -> LabelStage | None:
    """The stage (:data:`STAGES`) at which ``tracker`` (people policy ``tracks``, just
    updated with ``legs``; output ``step_tracks``) loses the label at ``pos`` (2,) [m],
    laser frame; None when no leg detection lies within :data:`NEAR` of it."""
    assert tracker.person_tracks is not None
    pose = legs.sensor_pose if legs.frame != "sensor" else None
    det = _to_sensor(pose, legs.positions)
    near = np.nonzero(np.hypot(*(det - pos).T) <= NEAR)[0] if len(det) else np.empty(0, int)
    if near.size == 0:
        return None
    score = float(legs.scores[near].max())
    best = tracker.mht.best_tracks()
    leg_xy = _to_sensor(pose, np.array([n.mean[:2] for n in best]))
    fams = {n.family for n, q in zip(best, leg_xy, strict=True) if np.hypot(*(q - pos)) <= NEAR}
    people = list(tracker.person_tracks.persons.values())
    cands = [
        q
        for q, c in zip(
            people, _to_sensor(pose, np.array([q.mean[:2] for q in people])), strict=True
        )
        if np.hypot(*(c - pos)) <= GATE or fams & set(q.members)
    ]
    shown = in_sensor_frame(step_tracks).of_kind("person")
    dist = [float(np.hypot(*(t.position - pos))) for t in shown]
    llr = max((q.llr for q in cands), default=math.nan)
    if dist and min(dist) <= GATE:
        stage = "tracked"
    elif not np.isin(near, tracker._kept).any():
        stage = "left out as static"
    elif not fams:
        stage = "no leg track"
    elif not cands:
        stage = "no person candidate"
    elif not any(q.confirmed for q in cands):
        stage = "candidate not confirmed"
    elif not any(t.track_id in {q.public_id for q in cands} for t in shown):
        stage = "confirmed, not reported"
    else:
        stage = "reported, too far"
    return LabelStage(step_tracks.scan_index, 0, float(np.hypot(*pos)), stage, llr, score)


def diagnose(
    bag: Path,
    params: LegTrackerParams,
    labels: dict[int, dict[int, np.ndarray]],
    background: str = "auto",
    map_path: str | None = None,
    static_world: StaticWorldParams | None = None,
) -> list[LabelStage]:
    """Track ``bag`` as :func:`track_bag` does and tell, for every label with a leg
    detection within :data:`NEAR`, where the pipeline loses it (:func:`diagnose_label`)."""
    out: list[LabelStage] = []

    def look(tracker: LegMHTTracker, tracks: Tracks, legs: Detections | None) -> None:
        scan = tracks.scan_index
        if scan not in labels or legs is None:
            return
        for pid, pos in sorted(labels[scan].items()):
            row = diagnose_label(tracker, tracks, legs, pos)
            if row is not None:
                out.append(replace(row, person=pid))

    track_bag_with_legs(bag, params, background, map_path, look, static_world)
    return out


def companion_tracks(
    tracks: Sequence[Tracks],
    legs: dict[int, np.ndarray],
    labels: dict[int, dict[int, np.ndarray]],
) -> set[int]:
    """Ids of the person tracks that follow the unlabelled companion beside the robot: on
    the labelled scans every row of the track lies farther than :data:`GATE` from every
    label and inside :data:`BESIDE` grown by :data:`NEAR`, and at least one row lies within
    :data:`NEAR` of an unlabelled leg detection in :data:`BESIDE` (farther than :data:`GATE`
    from every label; ``legs``: scan -> (M, 2) [m], laser frame). A track that ever comes
    near a label, or leaves the place beside the robot, is not one of them."""
    x0, x1, y0, y1 = BESIDE
    ok: dict[int, bool] = {}
    seen: set[int] = set()
    for t in tracks:
        if t.scan_index not in labels:
            continue
        truth = np.array(list(labels[t.scan_index].values()), dtype=np.float64)
        xy = legs.get(t.scan_index, np.empty((0, 2))).reshape(-1, 2)
        free = xy[np.hypot(*(xy[:, None, :] - truth[None]).transpose(2, 0, 1)).min(axis=1) > GATE]
        free = free[(free[:, 0] > x0) & (free[:, 0] < x1) & (free[:, 1] > y0) & (free[:, 1] < y1)]
        for row in in_sensor_frame(t).of_kind("person"):
            (x, y), tid = row.position.tolist(), row.track_id
            inside = x0 - NEAR < x < x1 + NEAR and y0 - NEAR < y < y1 + NEAR
            apart = bool(np.hypot(*(truth - row.position).T).min() > GATE)
            ok[tid] = ok.get(tid, True) and inside and apart
            if len(free) and np.hypot(*(free - row.position).T).min() <= NEAR:
                seen.add(tid)
    return {tid for tid, good in ok.items() if good and tid in seen}


def without_tracks(tracks: Sequence[Tracks], ids: set[int]) -> list[Tracks]:
    """``tracks`` with the person tracks ``ids`` left out."""
    return [
        replace(
            t, tracks=tuple(r for r in t.tracks if not (r.kind == "person" and r.track_id in ids))
        )
        for t in tracks
    ]


def detected_labels(
    legs: dict[int, np.ndarray], labels: dict[int, dict[int, np.ndarray]]
) -> dict[int, dict[int, np.ndarray]]:
    """The labels with a leg detection within :data:`NEAR` (scans without any left out)."""
    out: dict[int, dict[int, np.ndarray]] = {}
    for scan, people in labels.items():
        xy = legs.get(scan, np.empty((0, 2))).reshape(-1, 2)
        kept = {
            pid: pos
            for pid, pos in people.items()
            if len(xy) and float(np.hypot(*(xy - pos).T).min()) <= NEAR
        }
        if kept:
            out[scan] = kept
    return out


def track_bag(
    bag: Path,
    params: LegTrackerParams,
    background: str = "auto",
    map_path: str | None = None,
    static_world: StaticWorldParams | None = None,
) -> tuple[list[Tracks], float]:
    """Every scan's tracks of ``/scan`` through the pipeline (as ``laserpeople track``
    runs it; ``static_world``: the static world models' parameters, None: defaults) and
    the mean CPU time per scan [ms] (detection included)."""
    out, _, ms = track_bag_with_legs(bag, params, background, map_path, None, static_world)
    return out, ms


def track_bag_with_legs(
    bag: Path,
    params: LegTrackerParams,
    background: str = "auto",
    map_path: str | None = None,
    look: Callable[[LegMHTTracker, Tracks, Detections | None], None] | None = None,
    static_world: StaticWorldParams | None = None,
) -> tuple[list[Tracks], dict[int, np.ndarray], float]:
    """:func:`track_bag`, with each scan's leg detections (scan -> (M, 2) [m], laser
    frame) between the tracks and the CPU time; ``look(tracker, tracks, detections)`` is
    called after every scan (the leg MHT, its output, the leg detections it was given)."""
    tracker = registry.get("leg-mht").make(params)
    pipe = build(
        bag,
        tracker=tracker,
        topics=[TOPIC],
        detector=AdaBoostLegDetector.default(),
        background=background,
        map_path=map_path,
        static_world=static_world,
    )
    out: list[Tracks] = []
    legs: dict[int, np.ndarray] = {}
    t0 = time.process_time()
    for step in pipe:
        assert step.tracks is not None
        out.append(step.tracks)
        det = step.frame.legs
        if det is not None:
            xy = det.positions
            if det.frame != "sensor" and det.sensor_pose is not None:
                xy = det.sensor_pose.inverse_transform_points(xy)
            legs[step.frame.index] = xy
        if look is not None:
            look(tracker.tracker, step.tracks, det)
    return out, legs, 1e3 * (time.process_time() - t0) / max(len(out), 1)


def print_diagnosis(rows: Sequence[LabelStage]) -> None:
    """A row per detected label, then the count per stage."""
    print("scan person range_m  score    llr  stage")
    for r in rows:
        print(f"{r.scan:4d} {r.person:6d} {r.distance:7.1f} {r.score:6.2f} {r.llr:6.2f}  {r.stage}")
    counts = {st: sum(r.stage == st for r in rows) for st in STAGES}
    print(f"detected labels: {len(rows)}")
    for st, n in counts.items():
        print(f"  {st:26s} {n:3d}")


def main() -> None:
    bag_default, labels_default = default_paths()
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bag", type=Path, default=bag_default)
    ap.add_argument("--labels", type=Path, default=labels_default)
    ap.add_argument("--people-policy", default=None, help="arras or the default")
    ap.add_argument("--background", default="auto", help="static world model (track --background)")
    ap.add_argument("--map", default=None, help="map.yaml or BAG:/topic (track --map)")
    ap.add_argument(
        "--config",
        type=Path,
        help="TOML whose [leg_tracker] section and static world models' sections are used",
    )
    ap.add_argument("--per-scan", action="store_true", help="a row per labelled scan")
    ap.add_argument("--ceiling", action="store_true", help="what the detections allow")
    ap.add_argument(
        "--diagnose", action="store_true", help="where each detected label is lost (a table)"
    )
    args = ap.parse_args()
    params = load_config(LegTrackerParams, args.config)
    static = load_static_world(args.config)
    if args.people_policy is not None:
        params = replace(params, people_policy=args.people_policy)
    if args.diagnose:
        print_diagnosis(
            diagnose(args.bag, params, read_labels(args.labels), args.background, args.map, static)
        )
    tracks, legs, ms = track_bag_with_legs(
        args.bag, params, args.background, args.map, None, static
    )
    labels = read_labels(args.labels)
    s = score_moving(tracks, labels)
    if args.per_scan:
        print("scan  labels  tracks  matches  fp")
        for scan, n, t, m, fp in s.rows:
            print(f"{scan:4d} {n:7d} {t:7d} {m:8d} {fp:3d}")
    print(f"people_policy        {params.people_policy}")
    print(f"labelled scans       {s.scans} ({s.labels} labels)")
    print(f"MOTA                 {s.mota:.3f}")
    print(f"recall               {s.recall:.3f} ({s.matches} of {s.labels})")
    print(f"false positives      {s.false_positives}")
    print(f"misses               {s.misses}")
    print(f"id switches          {s.id_switches}")
    per = ", ".join(f"{p}: {n}" for p, n in s.ids_per_person.items())
    print(f"person ids matched   {s.ids} (per labelled person: {per or 'none'})")
    print(f"ms/scan (with det.)  {ms:.2f}")
    masked = companion_tracks(tracks, legs, labels)
    m = score_moving(without_tracks(tracks, masked), labels)
    d = score_moving(tracks, detected_labels(legs, labels))
    ids = ", ".join(f"P{i}" for i in sorted(masked)) or "none"
    print(f"companion masked     MOTA {m.mota:.3f}, false positives {m.false_positives} ({ids})")
    print(f"detected labels      recall {d.recall:.3f} ({d.matches} of {d.labels})")
    if args.ceiling:
        c = detection_ceiling(legs, labels)
        print(f"labels with a leg detection within {NEAR} m: {c.detected} of {c.labels}")
        print_oracle(*oracle_bound(args.bag, labels), args.per_scan)


if __name__ == "__main__":
    main()
