"""Followed-person scoring: one labelled person, every other track ignored.

Benchmarks such as leg_tracker's person-following recordings label only the person the
robot follows; other people are in view but unlabelled, so their tracks must not count as
false positives. Per scored frame (a frame in which the person is labelled):

- the person keeps last frame's track if it is still within ``gate`` (CLEAR MOT's rule for
  one object); otherwise the nearest track within ``gate`` is taken, and when that is
  another id than the last one matched, it is an ID switch;
- no track within ``gate``: a miss.

recall = matched frames / labelled frames (CLEAR MOT recall of this person);
identity recall = frames in which the single track id that covers the person most often is
within ``gate`` / labelled frames (IDR of Ristani et al. for one person: the trajectory
matching gives the person the one track with the most frames within the gate);
ids = how many distinct track ids were matched to the person over the run.
MOTA for one person without false positives = 1 - (misses + switches) / labelled frames.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from laserpeople.errors import EvaluationError
from laserpeople.evaluation.detail import FrameTable, frames_not_kept
from laserpeople.evaluation.matching import frame_points
from laserpeople.evaluation.pairing import PairingCounts
from laserpeople.evaluation.params import EvaluationParams
from laserpeople.tracks import Tracks
from laserpeople.truth import TruthFrame

FOLLOWED_COLUMNS = ("scan", "stamp", "labelled", "matched_track", "distance_m", "id_switch")


@dataclass(frozen=True)
class FollowedPersonResult:
    """How well one labelled person was tracked.

    Attributes:
        person_id: The person scored.
        frames: Frames in which the person is labelled.
        matched: Of those, frames with a track within the gate.
        recall: matched / frames (NaN without frames).
        identity_recall: Frames covered by the person's best single track / frames.
        ids: Distinct track ids matched to the person.
        id_switches: Changes of the matched track id between matched frames.
        mota: 1 - (misses + switches) / frames; no other track counts as a false positive.
        motp: Mean distance of the matches [m].
        best_track: The id of the track that covers the person most often (None if none).
        track_frames: Frames matched to each track id, largest first.
        gate: Matching distance [m].
    """

    person_id: int
    frames: int
    matched: int
    recall: float
    identity_recall: float
    ids: int
    id_switches: int
    mota: float
    motp: float
    best_track: int | None
    track_frames: tuple[tuple[int, int], ...]
    gate: float

    def summary(self) -> dict[str, float | int | None]:
        """The headline numbers (JSON-safe: NaN -> None)."""
        values: dict[str, float | int | None] = {
            "person_id": self.person_id,
            "frames": self.frames,
            "recall": self.recall,
            "identity_recall": self.identity_recall,
            "ids": self.ids,
            "id_switches": self.id_switches,
            "mota": self.mota,
            "motp_m": self.motp,
            "gate_m": self.gate,
        }
        return {
            k: None if isinstance(v, float) and not math.isfinite(v) else v
            for k, v in values.items()
        }


class FollowedPerson:
    """Accumulates the followed-person scores frame by frame (a metric of the evaluation
    protocol). Frames in which the person is not labelled are skipped."""

    def __init__(
        self, person_id: int, params: EvaluationParams | None = None, *, keep_frames: bool = True
    ) -> None:
        self.person_id = int(person_id)
        self.params = params or EvaluationParams()
        self.keep_frames = keep_frames
        self._last: int | None = None
        self._frames = 0
        self._matched = 0
        self._switches = 0
        self._distance = 0.0
        self._matched_ids: Counter[int] = Counter()
        self._within: Counter[int] = Counter()
        self._rows: list[tuple[int | float, ...]] = []

    def accumulate(self, truth_frame: TruthFrame, tracks: Tracks | None) -> None:
        """Score one frame (skipped when the person is not labelled in it)."""
        pts = frame_points(truth_frame, tracks, self.params.kind)
        rows = np.flatnonzero(pts.truth_ids == self.person_id)
        if rows.size == 0:
            return
        self._frames += 1
        dist = pts.distances[rows[0]]
        ids = pts.track_ids.tolist()
        within = dist <= self.params.gate
        self._within.update(int(ids[j]) for j in np.flatnonzero(within))
        chosen: int | None = None
        if self._last is not None and self._last in ids and within[ids.index(self._last)]:
            chosen = ids.index(self._last)
        elif within.any():
            chosen = int(np.flatnonzero(within)[np.argmin(dist[within])])
        switch = 0
        if chosen is not None:
            tid = int(ids[chosen])
            switch = int(self._last is not None and tid != self._last)
            self._switches += switch
            self._last = tid
            self._matched += 1
            self._distance += float(dist[chosen])
            self._matched_ids[tid] += 1
        if self.keep_frames:
            self._rows.append(
                (
                    pts.scan_index,
                    float(pts.stamp),
                    1,
                    -1 if chosen is None else int(ids[chosen]),
                    math.nan if chosen is None else float(dist[chosen]),
                    switch,
                )
            )

    def result(self) -> FollowedPersonResult:
        """The scores over the frames so far."""
        n = self._frames
        best = self._within.most_common(1)
        return FollowedPersonResult(
            person_id=self.person_id,
            frames=n,
            matched=self._matched,
            recall=self._matched / n if n else math.nan,
            identity_recall=best[0][1] / n if n and best else (0.0 if n else math.nan),
            ids=len(self._matched_ids),
            id_switches=self._switches,
            mota=1.0 - ((n - self._matched) + self._switches) / n if n else math.nan,
            motp=self._distance / self._matched if self._matched else math.nan,
            best_track=best[0][0] if best else None,
            track_frames=tuple(self._matched_ids.most_common()),
            gate=self.params.gate,
        )

    def frames(self) -> FrameTable:
        """Per labelled frame: the matched track (-1 none), its distance, whether it switched."""
        if not self.keep_frames:
            raise frames_not_kept("FollowedPerson")
        return FrameTable(FOLLOWED_COLUMNS, tuple(self._rows))


def most_labelled_person(frames: list[TruthFrame]) -> int:
    """The person labelled in the most frames (the followed one when only it is labelled).

    Raises:
        EvaluationError: nobody is labelled.
    """
    counts: Counter[int] = Counter(int(i) for f in frames for i in f.person_ids)
    if not counts:
        raise EvaluationError(
            "the ground truth labels nobody", hint="give truth with the followed person"
        )
    return counts.most_common(1)[0][0]


def evaluate_followed(
    truth_frames: list[TruthFrame],
    tracks: Iterable[Tracks],
    person_id: int,
    params: EvaluationParams | None = None,
    *,
    keep_frames: bool = True,
) -> tuple[FollowedPerson, PairingCounts]:
    """Score the tracks against one labelled person, pairing frames by scan index.

    Raises:
        EvaluationError: the person is never labelled.
    """
    from laserpeople.evaluation.pairing import pair_by_scan

    metric = FollowedPerson(person_id, params, keep_frames=keep_frames)
    counts = PairingCounts()
    for truth, frame_tracks in pair_by_scan(truth_frames, tracks, counts):
        metric.accumulate(truth, frame_tracks)
    if metric.result().frames == 0:
        known = sorted({int(i) for f in truth_frames for i in f.person_ids})
        raise EvaluationError(
            f"person {person_id} is not labelled in the ground truth",
            hint=f"labelled people: {', '.join(map(str, known[:20])) or 'none'}",
        )
    return metric, counts
