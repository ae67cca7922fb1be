"""All tracking metrics at once: CLEAR MOT, IDF1 and 004's MOTP over one sequence."""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import asdict, dataclass
from os import PathLike
from typing import Any, TypeVar

from laserpeople.errors import EvaluationError
from laserpeople.evaluation.clear_mot import ClearMot, ClearMotResult
from laserpeople.evaluation.detail import FrameTable
from laserpeople.evaluation.group_truth import group_truth
from laserpeople.evaluation.identity import IdentityF1, IdentityResult
from laserpeople.evaluation.pairing import PairingCounts, pair_by_scan
from laserpeople.evaluation.params import EvaluationParams
from laserpeople.evaluation.protocol import Metric
from laserpeople.evaluation.schenk_motp import SchenkMotp, SchenkMotpResult
from laserpeople.tracks import Tracks
from laserpeople.truth import TruthFrame

SUMMARY_KEYS = (
    "mota",
    "motp_m",
    "motp_schenk",
    "idf1",
    "recall",
    "precision",
    "id_switches",
    "false_positives",
    "misses",
)
"""The keys of :meth:`EvaluationReport.summary`, in order (the JSON of ``evaluate --json``)."""


@dataclass(frozen=True)
class EvaluationReport:
    """Every tracking metric of one sequence.

    Attributes:
        clear_mot: CLEAR MOT (MOTA, MOTP in metres, misses, false positives, switches).
        identity: IDF1, IDP, IDR.
        schenk: The adapted MOTP of 004 (eqs. 10-11).
        pairing: How truth frames and track scans were paired (None when frames were fed
            to :class:`TrackingEvaluation` directly).
        params: The parameters used.
    """

    clear_mot: ClearMotResult
    identity: IdentityResult
    schenk: SchenkMotpResult
    pairing: PairingCounts | None
    params: EvaluationParams

    def summary(self) -> dict[str, float | int | None]:
        """The headline numbers under :data:`SUMMARY_KEYS` (undefined values are None)."""
        c = self.clear_mot
        values: dict[str, float | int] = {
            "mota": c.mota,
            "motp_m": c.motp,
            "motp_schenk": self.schenk.motp,
            "idf1": self.identity.idf1,
            "recall": c.recall,
            "precision": c.precision,
            "id_switches": c.id_switches,
            "false_positives": c.false_positives,
            "misses": c.misses,
        }
        return {k: _finite_or_none(values[k]) for k in SUMMARY_KEYS}

    def nothing_matched(self) -> bool:
        """True when there were tracks and people to score and no track came within the
        gate of anybody: most often truth and tracks in different frames (labels in each
        scan's laser frame, tracks in the world frame), not a tracker that missed everyone."""
        c = self.clear_mot
        return c.matches == 0 and c.num_tracks > 0 and c.num_truth > 0

    def to_json_dict(self) -> dict[str, Any]:
        """:meth:`summary` plus everything else under ``"detail"`` (JSON-safe: NaN -> None)."""
        detail: dict[str, Any] = {
            "clear_mot": _json_safe(asdict(self.clear_mot)),
            "identity": _json_safe(
                {k: v for k, v in asdict(self.identity).items() if k != "matched"}
            ),
            "identity_matching": [list(p) for p in self.identity.matched],
            "schenk": _json_safe({k: v for k, v in asdict(self.schenk).items() if k != "matched"}),
            "schenk_matching": [list(p) for p in self.schenk.matched],
            "params": asdict(self.params),
        }
        if self.pairing is not None:
            detail["pairing"] = _json_safe(asdict(self.pairing))
        return {**self.summary(), "detail": detail}


def _finite_or_none(value: float | int) -> float | int | None:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _json_safe(values: dict[str, Any]) -> dict[str, Any]:
    """``values`` with every float that is not finite as None, also within tuples and lists
    (a pairing's stamp range is (nan, nan) when no track of the scored kind was written)."""

    def safe(v: Any) -> Any:
        if isinstance(v, float | int):
            return _finite_or_none(v)
        if isinstance(v, tuple | list):
            return [safe(x) for x in v]
        return v

    return {k: safe(v) for k, v in values.items()}


class TrackingEvaluation:
    """CLEAR MOT, IDF1 and 004's MOTP fed together, one frame at a time (a :class:`Metric`)."""

    def __init__(self, params: EvaluationParams | None = None, *, keep_frames: bool = True) -> None:
        self.params = params or EvaluationParams()
        self.clear_mot = ClearMot(self.params, keep_frames=keep_frames)
        self.identity = IdentityF1(self.params, keep_frames=keep_frames)
        self.schenk = SchenkMotp(self.params, keep_frames=keep_frames)
        self.pairing: PairingCounts | None = None

    def accumulate(self, truth_frame: TruthFrame, tracks: Tracks | None) -> None:
        """Score one frame with every metric."""
        self.clear_mot.accumulate(truth_frame, tracks)
        self.identity.accumulate(truth_frame, tracks)
        self.schenk.accumulate(truth_frame, tracks)

    def result(self) -> EvaluationReport:
        """All metrics over the frames so far."""
        return EvaluationReport(
            self.clear_mot.result(),
            self.identity.result(),
            self.schenk.result(),
            self.pairing,
            self.params,
        )

    def frames(self) -> FrameTable:
        """One row per frame with the columns of all three metrics."""
        return self.clear_mot.frames().join(self.identity.frames()).join(self.schenk.frames())


TRUTH_READERS = (
    "read it first: read_truth_csv(path), or open_recording(path).truth() for a recording"
)
TRACKS_READERS = "read it first: read_tracks_file(path)"

_Item = TypeVar("_Item")


def _checked_items(given: object, name: str, kind: type[_Item], readers: str) -> Iterator[_Item]:
    """The items of ``given`` (an argument of :func:`evaluate`), each checked to be a
    ``kind`` as it is taken (the check costs a type test per frame).

    Raises:
        TypeError: ``given`` is a path or no iterable (at once), or an item is no ``kind``
            (when it is reached); names the argument, what it takes and what to do.
    """
    expects = f"evaluate(): {name} must be an iterable of {kind.__name__}"
    if isinstance(given, str | bytes | PathLike):
        raise TypeError(f"{expects}, got the path {str(given)!r}: {readers}")
    try:
        items = iter(given)  # type: ignore[call-overload]
    except TypeError:
        raise TypeError(f"{expects}, got {type(given).__name__}: {readers}") from None

    def checked() -> Iterator[_Item]:
        for item in items:
            if not isinstance(item, kind):
                swapped = (
                    " (are truth_frames and tracks swapped?)"
                    if isinstance(item, TruthFrame | Tracks)
                    else ""
                )
                raise TypeError(f"{expects}, got an item of type {type(item).__name__}{swapped}")
            yield item

    return checked()


def evaluate(
    truth_frames: Iterable[TruthFrame],
    tracks: Iterable[Tracks],
    params: EvaluationParams | None = None,
    *,
    keep_frames: bool = True,
    also: Sequence[Metric[Any]] = (),
) -> TrackingEvaluation:
    """Score a tracker's output against ground truth, pairing them by scan index.

    With ``params.kind`` "group" the truth's groups are scored (:func:`group_truth`: each
    group at its members' mean, a person alone as a group of one), not its people.

    Only scans that have a truth frame are scored (a sparse annotation scores only its
    scans); a truth frame whose scan has no tracks counts all its people as missed.

    ``also``: more metrics (e.g. :class:`~laserpeople.evaluation.hota.Hota`) fed the same
    pairs of truth frame and tracks.

    ``keep_frames=False`` keeps memory independent of the number of frames (one number per
    pair of track and person ids) but gives no per-frame table.

    Returns:
        The filled :class:`TrackingEvaluation`: ``.result()`` for the numbers, ``.frames()``
        for the per-frame table.

    Raises:
        EvaluationError: no truth frame at all, or scans out of order.
        TypeError: an argument of the wrong type (a path instead of what is read from it,
            the truth and the tracks swapped, parameters as a dict); names it.
    """
    if params is not None and not isinstance(params, EvaluationParams):
        raise TypeError(
            f"evaluate(): params must be an EvaluationParams or None, got {type(params).__name__}",
        )
    truth_frames = _checked_items(truth_frames, "truth_frames", TruthFrame, TRUTH_READERS)
    if params is not None and params.kind == "group":
        truth_frames = map(group_truth, truth_frames)
    tracks = _checked_items(tracks, "tracks", Tracks, TRACKS_READERS)
    evaluation = TrackingEvaluation(params, keep_frames=keep_frames)
    counts = PairingCounts()
    evaluation.pairing = counts
    for truth, frame_tracks in pair_by_scan(truth_frames, tracks, counts):
        evaluation.accumulate(truth, frame_tracks)
        for metric in also:
            metric.accumulate(truth, frame_tracks)
    if counts.frames_scored == 0:
        raise EvaluationError(
            "there is no ground-truth frame to score",
            hint="give a recording with ground truth or a non-empty truth CSV",
        )
    return evaluation
