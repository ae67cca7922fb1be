"""Identity and recall of the followed person on the real dev recording of the leg_tracker
benchmark (Leigh et al. 2015): a robot follows one person outdoors for 6 minutes.

Tracks ``/scan_base2`` of ``person_following_outdoor_1_first.bag`` with the shipped leg
detector and the leg MHT (sensor frame: the bag has no poses), then scores the labelled
person against the person tracks (each label belongs to the scan whose index it carries;
a track matches within 0.75 m, the benchmark's own gate). Only that person is labelled, so
other tracks are not false positives. Printed:

- identity recall: the fraction of labelled scans that the person's single best track id
  (the id within the gate in the most scans) covers (the recall half of IDF1);
- recall: the fraction of labelled scans with any person track within the gate;
- ids: the distinct person ids that were the nearest track within the gate at least once,
  and how many of them covered at least 1 s;
- best id elsewhere: scans in which the best id is on a track more than 0.75 m from the
  label, or while the person is out of view (between stretches): that id given to someone
  else, which identity recall cannot see (a re-identification through strangers);
- per stretch: the labels split where none is given for more than 5 s (the person out of
  view); the identity recall when each stretch may have its own id, and the largest
  stretch's share of the labels (the identity recall a tracker reaches at best if it cannot
  recognise a person who comes back after leaving the view: on the dev recording the person
  leaves the 86 deg view at scan 1842 and comes back at scan 2702, 86 s later).

    PYTHONPATH=src .venv/bin/python benchmarks/followed_person.py [--people-policy arras]
        [--preset paper] [--no-reid] [--background auto|histogram|occupancy|none] [--tracker csa]
        [--bag PATH] [--labels PATH] [--plot timeline.png] [--model MODEL.json]
"""

from __future__ import annotations

import argparse
import csv
import os
import time
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from laserpeople.config import load_config
from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.pipeline import build
from laserpeople.pipeline.background import StaticWorldParams, load_static_world
from laserpeople.pipeline.static_people import describe_people_model
from laserpeople.tracking import registry
from laserpeople.tracking.legs import LegTrackerParams
from laserpeople.tracks import TrackKind, Tracks

GATE = 0.75  # m, the benchmark's matching distance
TOPIC = "/scan_base2"


def default_paths() -> tuple[Path, Path]:
    """The dev bag and its label CSV under ``$LASERPEOPLE_SHARED_DATA`` (or ../shared/data)."""
    root = Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "../shared/data"))
    base = root / "leg_tracker_benchmarks" / "person_following_outdoor_1_first"
    return base.with_suffix(".bag"), Path(f"{base}.people.csv")


def read_labels(path: Path) -> dict[int, np.ndarray]:
    """Scan index -> labelled position (2,) [m] of the followed person (laser frame)."""
    out: dict[int, np.ndarray] = {}
    with path.open(newline="") as fh:
        for row in csv.DictReader(fh):
            out[int(row["scan"])] = np.array([float(row["x"]), float(row["y"])])
    return out


@dataclass(frozen=True)
class FollowedScore:
    """Scores of the followed person.

    Attributes:
        labels: Labelled scans.
        identity_recall: Fraction covered by the person's best single track id.
        recall: Fraction with any person track within the gate.
        ids: Distinct ids that were the nearest match at least once.
        ids_1s: Of those, ids that were the nearest match in at least ``rate`` scans (1 s).
        best_id: The best single id.
        stretch_identity_recall: Identity recall with one best id per stretch.
        single_id_ceiling: Share of the labels in the largest stretch.
        stretches: Number of stretches.
        best_id_elsewhere: Scans in which the best id is reported more than ``GATE`` from the
            labelled person, or while the person is not labelled (outside a stretch: out of
            view), i.e. on someone else.
    """

    labels: int
    identity_recall: float
    recall: float
    ids: int
    ids_1s: int
    best_id: int | None
    stretch_identity_recall: float = 0.0
    single_id_ceiling: float = 0.0
    stretches: int = 0
    best_id_elsewhere: int = 0


def stretches(scans: Sequence[int], max_gap: int) -> list[list[int]]:
    """Sorted labelled scan indices split where consecutive ones are more than ``max_gap``
    scans apart."""
    out: list[list[int]] = []
    for s in sorted(scans):
        if out and s - out[-1][-1] <= max_gap:
            out[-1].append(s)
        else:
            out.append([s])
    return out


def score_followed(
    tracks: Sequence[Tracks],
    labels: dict[int, np.ndarray],
    scans_per_second: float = 10.0,
    kind: TrackKind = "person",
) -> FollowedScore:
    """Score the tracks of ``kind`` of every scan (``tracks[i]`` for scan index i) against
    ``labels``."""
    covering: Counter[int] = Counter()
    nearest: Counter[int] = Counter()
    per_scan: dict[int, set[int]] = {}
    hit = 0
    for scan, truth in labels.items():
        if scan >= len(tracks):
            continue
        people = tracks[scan].of_kind(kind)
        if not people:
            continue
        pos = np.stack([t.position for t in people])
        d = np.hypot(*(pos - truth).T)
        inside = np.flatnonzero(d <= GATE)
        if inside.size == 0:
            continue
        hit += 1
        per_scan[scan] = {people[i].track_id for i in inside}
        covering.update(per_scan[scan])
        nearest[people[int(inside[np.argmin(d[inside])])].track_id] += 1
    n = len(labels)
    best = covering.most_common(1)
    parts = stretches(list(labels), round(5.0 * scans_per_second))
    covered = 0
    for part in parts:
        c: Counter[int] = Counter()
        for s in part:
            c.update(per_scan.get(s, ()))
        covered += c.most_common(1)[0][1] if c else 0
    elsewhere = 0
    if best:
        for scan, t in enumerate(tracks):
            mine = [p for p in t.of_kind(kind) if p.track_id == best[0][0]]
            if not mine:
                continue
            truth = labels.get(scan)
            if truth is None:
                elsewhere += int(not any(part[0] <= scan <= part[-1] for part in parts))
            elif float(np.hypot(*(mine[0].position - truth))) > GATE:
                elsewhere += 1
    return FollowedScore(
        labels=n,
        identity_recall=(best[0][1] / n) if best else 0.0,
        recall=hit / n if n else 0.0,
        ids=len(nearest),
        ids_1s=sum(1 for c in nearest.values() if c >= scans_per_second),
        best_id=best[0][0] if best else None,
        stretch_identity_recall=covered / n if n else 0.0,
        single_id_ceiling=max(len(p) for p in parts) / n if n else 0.0,
        stretches=len(parts),
        best_id_elsewhere=elsewhere,
    )


def scored_kind(tracks: Sequence[Tracks]) -> TrackKind:
    """``person`` if any scan holds a person track, else ``group`` if any holds a group
    (``group-mht`` reports groups only; its group holding the person is scored, as
    ``laserpeople evaluate --kind group`` does), else ``person``."""
    kinds: tuple[TrackKind, ...] = ("person", "group")
    for kind in kinds:
        if any(t.of_kind(kind) for t in tracks):
            return kind
    return "person"


def track_bag(
    bag: Path,
    params: Any,
    background: str = "auto",
    model: str | None = None,
    tracker_name: str = "leg-mht",
    static_world: StaticWorldParams | None = None,
    detector_params: LegDetectorParams | None = None,
) -> tuple[list[Tracks], float, str]:
    """Person/leg tracks of every scan of the bag's ``/scan_base2`` through the pipeline
    (as ``laserpeople track --tracker tracker_name`` runs it, static world model
    ``background``), the mean CPU time per scan [ms] (detection included) and the line
    naming the static world model (leg model: the shipped default, or the model file
    ``model``). ``params``: the tracker's parameters; ``static_world``: the static world
    models' (None: defaults); ``detector_params``: the leg detector's (None: defaults)."""
    tracker = registry.get(tracker_name).make(params)
    det = detector_params if detector_params is not None else LegDetectorParams()
    pipe = build(
        bag,
        tracker=tracker,
        topics=[TOPIC],
        detector=(
            AdaBoostLegDetector.default(det)
            if model is None
            else AdaBoostLegDetector.from_file(model, det)
        ),
        background=background if getattr(params, "people_policy", "tracks") == "tracks" else "none",
        static_world=static_world,
    )
    out: list[Tracks] = []
    t0 = time.process_time()
    for step in pipe:
        assert step.tracks is not None
        out.append(step.tracks)
    spent = time.process_time() - t0
    return out, 1e3 * spent / max(len(out), 1), describe_people_model(tracker, pipe.stages)


def main() -> None:
    bag_default, labels_default = default_paths()
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bag", type=Path, default=bag_default)
    ap.add_argument("--labels", type=Path, default=labels_default)
    ap.add_argument("--people-policy", default=None, help="arras or the default")
    ap.add_argument("--model", default=None, help="leg model file (default: the shipped model)")
    ap.add_argument("--no-reid", action="store_true", help="tracks without re-identification")
    ap.add_argument("--background", default="auto", help="static world model (track --background)")
    ap.add_argument(
        "--config",
        type=Path,
        help="TOML whose [leg_tracker], [leg_detector] and static world models' sections are used",
    )
    ap.add_argument(
        "--preset",
        default=None,
        help="paper: every section starts from the papers' values (track --preset), "
        "--config is read over them",
    )
    ap.add_argument(
        "--tracker",
        default="leg-mht",
        help="registered tracker (its --config section or defaults; the options above "
        "other than --background and --model are the leg MHT's)",
    )
    args = ap.parse_args()
    static = load_static_world(args.config, args.preset)
    detector = load_config(LegDetectorParams, args.config, args.preset)
    if args.tracker != "leg-mht":
        entry = registry.get(args.tracker)
        other = load_config(entry.params_cls, args.config, args.preset)
        tracks, ms, model = track_bag(
            args.bag, other, args.background, args.model, args.tracker, static, detector
        )
        kind = scored_kind(tracks)
        s = score_followed(tracks, read_labels(args.labels), kind=kind)
        print(f"tracker              {args.tracker} (its {kind} tracks scored)")
        _print_score(s, ms, model)
        return
    params = load_config(LegTrackerParams, args.config, args.preset)
    if args.people_policy is not None:
        params = replace(params, people_policy=args.people_policy)
    if args.no_reid:
        people = params.people
        params = replace(params, people=replace(people, reid=replace(people.reid, enabled=False)))
    tracks, ms, model = track_bag(
        args.bag, params, args.background, args.model, "leg-mht", static, detector
    )
    s = score_followed(tracks, read_labels(args.labels))
    reid = params.people_policy == "tracks" and params.people.reid.enabled
    print(f"people_policy        {params.people_policy}{' + re-identification' * reid}")
    _print_score(s, ms, model)


def _print_score(s: FollowedScore, ms: float, model: str) -> None:
    """Print the scores of the followed person."""
    print(f"labelled scans       {s.labels}")
    print(f"identity recall      {s.identity_recall:.3f}")
    print(f"recall               {s.recall:.3f}")
    print(f"person ids           {s.ids} ({s.ids_1s} matched for at least 1 s)")
    print(
        f"per stretch          {s.stretches} stretches (gaps > 5 s): identity recall "
        f"{s.stretch_identity_recall:.3f}; one id can cover at most {s.single_id_ceiling:.3f}"
    )
    print(
        f"best id elsewhere    {s.best_id_elsewhere} scans (on someone else: away from the "
        "label, or while the person is out of view)"
    )
    print(f"ms/scan (with det.)  {ms:.2f}")
    print(model)


if __name__ == "__main__":
    main()
