"""Score many recordings at once: per recording and pooled CLEAR MOT, IDF1 and HOTA.

Each recording's tracks file (CSV, Parquet or a tracks bag) is scored against its truth
(a recording with truth, a truth CSV, or ``BAG[:TOPIC]``) with
:func:`~laserpeople.evaluation.report.evaluate` and :class:`~laserpeople.evaluation.hota.Hota`.
Truth can be named per recording or found by name (:func:`find_truth`: ``X.people.csv``
beside the recording ``X.bag``, else the recording itself when it holds truth, as a
simulated ``.npz`` does). A batch output folder names its recordings in its summary
(:func:`batch_pairs`).

Pooling over recordings (:func:`pool`): CLEAR MOT sums its counts (misses, false positives,
switches, matches, distances), IDF1 sums IDTP, IDFP and IDFN of each recording's own
trajectory matching (ids are never matched across recordings), HOTA combines as TrackEval
does (:func:`~laserpeople.evaluation.hota.combine_hota`).
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from laserpeople.errors import EvaluationError
from laserpeople.evaluation.hota import Hota, HotaParams, HotaResult, combine_hota
from laserpeople.evaluation.params import EvaluationParams
from laserpeople.evaluation.report import EvaluationReport, evaluate
from laserpeople.scan import CoordinateFrame
from laserpeople.tracks import Tracks
from laserpeople.truth import TruthFrame

TRUTH_SUFFIX = ".people.csv"
"""Truth CSV found beside a recording ``X.bag`` as ``X.people.csv``."""


def truth_frames(
    spec: str | Path,
    laser_topic: str | None = None,
    notes: list[str] | None = None,
    on_error: str = "stop",
    on_damage: Callable[[object], None] | None = None,
) -> Iterator[TruthFrame]:
    """Ground-truth frames from a recording with truth, a truth CSV or a bag topic
    (``BAG[:TOPIC]``); a line about a bag's truth is appended to ``notes``. ``on_error`` is
    the recording reader's policy for damaged scans; ``on_damage`` is called with the
    reader when done (to report skipped scans)."""
    from laserpeople.io.truth_bag import is_bag_path, read_truth_bag, split_truth_spec

    path, topic = split_truth_spec(str(spec))
    if is_bag_path(path):
        bag = read_truth_bag(path, topic, laser_topic)
        if notes is not None:
            notes.append(bag.summary())
        yield from bag.frames
        return
    if topic is not None:
        raise EvaluationError(
            f"a topic ({topic!r}) can only be given for a bag",
            path=path,
            hint="use BAG:TOPIC with a .bag/.mcap/.db3, or a .npz/.csv without a topic",
        )
    if path.suffix.lower() == ".csv":
        from laserpeople.io.truth_csv import read_truth_csv

        yield from read_truth_csv(path)
        return
    from laserpeople.io import open_recording
    from laserpeople.io.damage import check_on_error

    recording = open_recording(path, on_error=check_on_error(on_error))
    try:
        if not recording.has_truth:
            raise EvaluationError(
                "the recording has no ground truth",
                path=path,
                hint="use a simulated .npz recording or a truth CSV scan,stamp,person_id,x,y",
            )
        yield from recording.truth()
    finally:
        if on_damage is not None:
            on_damage(recording)
        recording.close()


def unstated_tracks_frame(truth: str | Path | None) -> CoordinateFrame:
    """The frame a tracks CSV without a ``frame`` column is taken to be in when scored
    against ``truth``: the laser frame against labels in a bag (``BAG[:TOPIC]``, whose
    labels are in the laser frame, as the leg_tracker benchmark's), else the world frame."""
    from laserpeople.io.truth_bag import is_bag_path, split_truth_spec

    if truth is not None and is_bag_path(split_truth_spec(str(truth))[0]):
        return "sensor"
    return "world"


def track_frames(
    path: str | Path, kind: str, names: Any = None, truth: str | Path | None = None
) -> Iterator[Tracks]:
    """The tracks of ``kind`` per scan from a tracks CSV, Parquet file or tracks bag
    (``names``: a :class:`~laserpeople.io.tracks_csv.TrackIdNames` for text ids; a CSV
    without a ``frame`` column is in :func:`unstated_tracks_frame` of ``truth``)."""
    from laserpeople.io.tracks_files import read_tracks_file

    kinds: Any = (kind,)
    return read_tracks_file(path, unstated_tracks_frame(truth), kinds=kinds, ids=names)


def find_truth(recording: str | Path) -> str | None:
    """The truth of ``recording`` found by name: ``X.people.csv`` beside ``X.bag``, else the
    recording itself when it is a ``.npz`` (simulated, with truth); None when neither."""
    p = Path(recording)
    beside = p.with_name(p.name.split(".")[0] + TRUTH_SUFFIX)
    if beside.is_file():
        return str(beside)
    if p.suffix.lower() == ".npz":
        return str(p)
    return None


@dataclass(frozen=True)
class RecordingScore:
    """The scores of one recording's tracks.

    Attributes:
        name: The recording's name (and topic).
        tracks: The tracks file.
        truth: The truth it was scored against.
        report: CLEAR MOT, IDF1 and 004's MOTP (None when scoring failed).
        hota: HOTA (None when scoring failed).
        error: Why scoring failed (empty when it did not).
    """

    name: str
    tracks: str
    truth: str
    report: EvaluationReport | None = None
    hota: HotaResult | None = None
    error: str = ""


def score_recording(
    name: str,
    tracks: str | Path,
    truth: str | Path,
    params: EvaluationParams | None = None,
    hota_params: HotaParams | None = None,
    *,
    laser_topic: str | None = None,
    on_error: str = "stop",
) -> RecordingScore:
    """Score one tracks file against its truth; an error becomes the score's ``error``."""
    from laserpeople.errors import LaserPeopleError

    params = params or EvaluationParams()
    hota_params = hota_params or HotaParams(kind=params.kind)
    try:
        hota = Hota(hota_params, keep_frames=False)
        frames = truth_frames(truth, laser_topic, on_error=on_error)
        run = evaluate(
            frames,
            track_frames(tracks, params.kind, truth=truth),
            params,
            keep_frames=False,
            also=[hota],
        )
        report = run.result()
        apart = report.pairing.disjoint() if report.pairing is not None else None
        if apart is not None:
            raise apart
        return RecordingScore(name, str(tracks), str(truth), report, hota.result())
    except LaserPeopleError as exc:
        return RecordingScore(name, str(tracks), str(truth), error=str(exc))


@dataclass(frozen=True)
class PooledScore:
    """Scores pooled over recordings (see the module docstring).

    Attributes:
        recordings: Recordings pooled (scored without error).
        mota, motp, idf1, recall, precision: Pooled CLEAR MOT and IDF1.
        id_switches, false_positives, misses, num_truth: Summed counts.
        hota: Pooled HOTA.
    """

    recordings: int
    mota: float
    motp: float
    idf1: float
    recall: float
    precision: float
    id_switches: int
    false_positives: int
    misses: int
    num_truth: int
    hota: HotaResult


def pool(scores: Sequence[RecordingScore]) -> PooledScore | None:
    """Pool the scores that have no error (None when none has)."""
    ok = [s for s in scores if s.report is not None and s.hota is not None]
    if not ok:
        return None
    cm = [s.report.clear_mot for s in ok if s.report is not None]
    ids = [s.report.identity for s in ok if s.report is not None]
    n_truth = sum(c.num_truth for c in cm)
    n_tracks = sum(c.num_tracks for c in cm)
    matches = sum(c.matches for c in cm)
    errors = sum(c.misses + c.false_positives + c.id_switches for c in cm)
    idtp = sum(i.idtp for i in ids)
    total = sum(i.num_truth + i.num_tracks for i in ids)
    return PooledScore(
        recordings=len(ok),
        mota=1.0 - errors / n_truth if n_truth else math.nan,
        motp=sum(c.distance_sum for c in cm) / matches if matches else math.nan,
        idf1=2.0 * idtp / total if total else math.nan,
        recall=matches / n_truth if n_truth else math.nan,
        precision=matches / n_tracks if n_tracks else math.nan,
        id_switches=sum(c.id_switches for c in cm),
        false_positives=sum(c.false_positives for c in cm),
        misses=sum(c.misses for c in cm),
        num_truth=n_truth,
        hota=combine_hota([s.hota for s in ok if s.hota is not None]),
    )


SCORE_COLUMNS = (
    "recording",
    "mota",
    "motp_m",
    "idf1",
    "hota",
    "deta",
    "assa",
    "loca",
    "recall",
    "precision",
    "id_switches",
    "false_positives",
    "misses",
    "error",
)
"""Columns of :func:`score_rows` (one row per recording, then ``pooled``)."""


def score_rows(scores: Sequence[RecordingScore]) -> list[dict[str, Any]]:
    """One row per recording and a last ``pooled`` row, under :data:`SCORE_COLUMNS`
    (undefined numbers are NaN)."""
    rows = []
    for s in scores:
        if s.report is None or s.hota is None:
            rows.append(
                {**dict.fromkeys(SCORE_COLUMNS, math.nan), "recording": s.name, "error": s.error}
            )
            continue
        c, i, h = s.report.clear_mot, s.report.identity, s.hota
        rows.append(
            {
                "recording": s.name,
                "mota": c.mota,
                "motp_m": c.motp,
                "idf1": i.idf1,
                "hota": h.hota,
                "deta": h.deta,
                "assa": h.assa,
                "loca": h.loca,
                "recall": c.recall,
                "precision": c.precision,
                "id_switches": c.id_switches,
                "false_positives": c.false_positives,
                "misses": c.misses,
                "error": "",
            }
        )
    pooled = pool(scores)
    if pooled is not None:
        h = pooled.hota
        rows.append(
            {
                "recording": f"pooled ({pooled.recordings})",
                "mota": pooled.mota,
                "motp_m": pooled.motp,
                "idf1": pooled.idf1,
                "hota": h.hota,
                "deta": h.deta,
                "assa": h.assa,
                "loca": h.loca,
                "recall": pooled.recall,
                "precision": pooled.precision,
                "id_switches": pooled.id_switches,
                "false_positives": pooled.false_positives,
                "misses": pooled.misses,
                "error": "",
            }
        )
    return rows


def batch_pairs(out: str | Path) -> list[tuple[str, Path, str | None, str | None]]:
    """From a batch output folder's ``summary.csv``: per tracked row, its name (recording
    and topic), tracks file, truth found by name (:func:`find_truth`, None when none) and
    the laser topic (for a bag's truth).

    Raises:
        EvaluationError: The folder has no ``summary.csv``.
    """
    folder = Path(out)
    summary = folder / "summary.csv"
    if not summary.is_file():
        raise EvaluationError(
            "not a batch output folder (no summary.csv)",
            path=folder,
            hint="give tracks files, or the --out folder of `laserpeople batch`",
        )
    pairs = []
    with summary.open(newline="", encoding="utf-8") as f:
        for row in csv.DictReader(f):
            if row["status"] not in ("done", "skipped") or not row["output"]:
                continue
            topic = row["topic"] if row["topic"] not in ("", "fused") else None
            name = row["name"] + (f" {row['topic']}" if row["topic"] else "")
            pairs.append((name, folder / row["output"], find_truth(row["recording"]), topic))
    return pairs


__all__ = [
    "SCORE_COLUMNS",
    "TRUTH_SUFFIX",
    "PooledScore",
    "RecordingScore",
    "batch_pairs",
    "find_truth",
    "pool",
    "score_recording",
    "score_rows",
    "track_frames",
    "truth_frames",
]
