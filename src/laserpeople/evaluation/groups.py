"""Scoring the group tracker on simulated recordings (000 Sec. 4.6): the clustering error
of the tracker and of memory-less single-linkage clustering (Fig. 17), the group-size error
(Sec. 4.6.3) and the cycle time.

Frames are built from the simulator directly: every valid point of the first sensor's scan
in the world frame, foreground = the beams the simulator's per-beam labels put on a person
(a perfect static world model). Each point's true group is the simulator's group label
(people alone are groups of one, :func:`~laserpeople.evaluation.clustering.
beam_group_labels`).
"""

from __future__ import annotations

import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering import single_linkage
from laserpeople.evaluation.clear_mot import ClearMot, ClearMotResult
from laserpeople.evaluation.clustering import (
    ClusteringError,
    ClusteringErrorResult,
    GroupSizeError,
    GroupSizeErrorResult,
    beam_group_labels,
)
from laserpeople.evaluation.group_truth import ALONE_ID, group_truth
from laserpeople.evaluation.params import EvaluationParams
from laserpeople.frame import Frame
from laserpeople.pipeline.background import at_torso_height
from laserpeople.scan import PointSet, Scan
from laserpeople.tracking.groups.params import GroupTrackerParams
from laserpeople.tracking.groups.tracker import GroupMHTTracker
from laserpeople.truth import TruthFrame

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True, eq=False)
class LabelledFrame:
    """A frame built from a simulated scan, with the truth of each of its points.

    Attributes:
        frame: Points (world frame) and foreground mask.
        true_group: (N,) true group label of each point, -1 for a non-person point.
        true_person: (N,) person id of each point, -1 for a non-person point.
    """

    frame: Frame
    true_group: IntArray
    true_person: IntArray


def frames_from_scans(scans: list[Scan]) -> Iterator[LabelledFrame]:
    """Frames of the first sensor's scans (which must carry ``labels`` and ``pose``)."""
    first = scans[0].sensor
    for scan in scans:
        if scan.sensor != first:
            continue
        if scan.labels is None:
            raise ValueError(f"scan {scan.index} has no per-beam labels")
        points = PointSet.from_scans([scan], "world")
        beams = points.beams
        person = scan.labels.person.astype(np.int64)[beams]
        group = beam_group_labels(scan.labels)[beams]
        frame = Frame(
            index=scan.index,
            stamp=scan.stamp,
            scans=(scan,),
            topic=scan.sensor,
            frame="world",
            sensor_pose=scan.pose,
            points=points,
            foreground=person >= 0,
        )
        yield LabelledFrame(frame, group, person)


GROUP_GATE = 1.0
"""CLEAR MOT gate of the group tracks [m]: a reported group matches a true group whose
centre is at most this far from its position."""
PROXEMIC_SPEED = 0.5
"""Two people whose velocities differ by less than this are not told apart by motion
[m/s] (:func:`proxemic_truth`): they stand together or walk side by side, where parties
that pass or leave each other differ by 1 m/s and more."""
JOINED_ID = 2_000_000
"""Truth id of true groups joined by :func:`proxemic_truth`: this plus the smallest of
their :func:`group_truth` ids."""


def near_and_alike(
    frame: TruthFrame, a: IntArray, b: IntArray, d_p: float, speed: float = PROXEMIC_SPEED
) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """For the people at rows ``a`` (A,) and ``b`` (B,) of ``frame``: (A, B) whether a leg
    of one is within ``d_p`` [m] of a leg of the other (body centres when the frame has no
    legs), and whether their velocities differ by less than ``speed`` [m/s]."""
    legs = frame.leg_positions
    if not np.all(np.isfinite(legs)):
        legs = np.repeat(frame.positions[:, None, :], 2, axis=1)
    la = legs[a].reshape(-1, 2)  # (2 A, 2): person k's legs at rows 2k, 2k + 1
    lb = legs[b].reshape(-1, 2)
    near = np.hypot(*(la[:, None, :] - lb[None, :, :]).transpose(2, 0, 1)) < d_p
    near = near.reshape(len(a), 2, len(b), 2).any(axis=(1, 3))
    va, vb = frame.velocities[a], frame.velocities[b]
    alike = np.hypot(*(va[:, None, :] - vb[None, :, :]).transpose(2, 0, 1)) < speed
    return near, alike


def proxemic_groups(
    frame: TruthFrame, d_p: float, speed: float = PROXEMIC_SPEED
) -> list[tuple[list[int], IntArray]]:
    """The true groups of ``frame`` joined as 000 Sec. 4.2 can define them
    (:func:`proxemic_truth`): for every joined group, the :func:`group_truth` ids of the
    scene's groups in it and the rows of ``frame`` of its people."""
    groups = list(frame.groups().items())
    ids = [g if g >= 0 else ALONE_ID - g - 1 for g, _ in groups]
    rows = [np.flatnonzero(np.isin(frame.person_ids, people)) for _, people in groups]
    parent = list(range(len(groups)))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for a in range(len(groups)):
        for b in range(a + 1, len(groups)):
            near, alike = near_and_alike(frame, rows[a], rows[b], d_p, speed)
            if np.any(near & alike):
                parent[root(a)] = root(b)
    joined: dict[int, list[int]] = {}
    for k in range(len(groups)):
        joined.setdefault(root(k), []).append(k)
    return [
        ([ids[k] for k in members], np.concatenate([rows[k] for k in members]))
        for members in joined.values()
    ]


def proxemic_truth(frame: TruthFrame, d_p: float, speed: float = PROXEMIC_SPEED) -> TruthFrame:
    """The true groups as 000 Sec. 4.2 can define them from range data: body spacing
    (proxemics, people closer than ``d_p`` [m] are one group) and motion (Fig. 18, a
    person who passes a group at a different velocity is not in it). True groups of the
    scene are joined, by single linkage, while a member of one has a leg within ``d_p``
    of a leg of a member of the other and their velocities differ by less than ``speed``
    [m/s]; joined groups are at the mean of all their members, with id
    :data:`JOINED_ID` plus the smallest of their :func:`group_truth` ids. Every other
    group is as :func:`group_truth` gives it.

    The scene's labels hold the social groups the script made; parties that are not one
    group may stand within d_P of each other for seconds, or walk through each other,
    which no tracker of points that follows 000's definition can tell apart."""
    out_ids: list[int] = []
    centres: list[FloatArray] = []
    for ids, rows in proxemic_groups(frame, d_p, speed):
        out_ids.append(ids[0] if len(ids) == 1 else JOINED_ID + min(ids))
        centres.append(frame.positions[rows].mean(axis=0))
    pos = np.asarray(centres, dtype=np.float64).reshape(-1, 2)
    return TruthFrame.from_positions(
        frame.stamp, frame.scan_index, np.asarray(out_ids, dtype=np.int64), pos
    )


TRANSITION_WINDOW = 3.0
"""Seconds either side of a scan within which the people of an under-segmented cluster
must be one true group for the error to count as a transition error [s]."""


@dataclass(frozen=True)
class UnderSegmentation:
    """Under-segmented clusters (a cluster holding people of two or more true groups) by
    cause, summed over frames.

    Attributes:
        transition: The cluster's people are one true group within
            :data:`TRANSITION_WINDOW` of the scan: the simulator's truth joins two parties
            when the last member arrives and parts them 0.3 s after they start to leave,
            while the points meet or part earlier; no clustering of the points can follow
            that, with or without memory.
        distinct: The cluster's people belong to groups that are not one group anywhere
            near that scan (parties passing each other or a meeting): what tracking can
            keep apart (000 Fig. 18).
    """

    transition: int
    distinct: int


@dataclass(frozen=True)
class GroupRunResult:
    """The scores of one run over a recording.

    Attributes:
        clustering: Clustering error of the tracker's groups (Sec. 4.6.1).
        memoryless: Clustering error of single linkage per frame with the same d_P.
        size: Group-size error (Sec. 4.6.3).
        median_ms: Median cycle time of the tracker [ms per scan], CPU time of the process
            (robust to other processes sharing the machine).
        mean_ms: Mean cycle time [ms per scan], CPU time.
        splits: Splits in the reported hypothesis.
        merges: Merges in the reported hypothesis.
        frames: Frames scored.
        frame_ms: CPU time of every frame [ms] (F,).
        frame_people: People seen (with a foreground point) in every frame (F,).
        tracker_under: The tracker's under-segmentation by cause.
        memoryless_under: Memory-less clustering's under-segmentation by cause.
        group_mot: CLEAR MOT of the reported group tracks against the true groups
            (people alone are groups of one; gate :data:`GROUP_GATE`, :func:`group_truth`);
            NaN scores without truth frames.
        proxemic_mot: The same against :func:`proxemic_truth` (true groups that are
            within d_P and move alike joined, as 000's definition sees them).
    """

    clustering: ClusteringErrorResult
    memoryless: ClusteringErrorResult
    size: GroupSizeErrorResult
    median_ms: float
    mean_ms: float
    splits: int
    merges: int
    frames: int
    frame_ms: NDArray[np.float64]
    frame_people: IntArray
    tracker_under: UnderSegmentation
    memoryless_under: UnderSegmentation
    group_mot: ClearMotResult
    proxemic_mot: ClearMotResult


def _mixed_clusters(true_group: IntArray, true_person: IntArray, est: IntArray) -> list[IntArray]:
    """People (sorted ids) of every cluster of ``est`` (N,) holding points of two or more
    true groups (``true_group`` (N,), ``true_person`` (N,); -1 outside)."""
    out = []
    inside = est >= 0
    for k in np.unique(est[inside]):
        sel = est == k
        groups = np.unique(true_group[sel])
        if np.count_nonzero(groups >= 0) > 1:
            people = np.unique(true_person[sel])
            out.append(people[people >= 0])
    return out


def _classify(
    mixed: list[tuple[int, IntArray]], group_of: list[dict[int, int]], window: int
) -> UnderSegmentation:
    """Split under-segmented clusters ``(frame, people)`` into transitions (one true group
    in some frame within ``window`` frames, from ``group_of[frame]``: person -> group) and
    distinct groups."""
    transition = 0
    for k, people in mixed:
        lo, hi = max(0, k - window), min(len(group_of), k + window + 1)
        for f in range(lo, hi):
            groups = {group_of[f].get(int(p), -1 - int(p)) for p in people}
            if len(groups) == 1:
                transition += 1
                break
    return UnderSegmentation(transition, len(mixed) - transition)


def run_groups(
    scans: list[Scan],
    params: GroupTrackerParams | None = None,
    skip: int = 0,
    truth: Sequence[TruthFrame] = (),
    laser_height: float | None = None,
) -> GroupRunResult:
    """Track the simulated ``scans`` and score the tracker and memory-less clustering over
    the foreground points (frames before ``skip`` are tracked but not scored); with the
    simulation's ``truth`` frames also the reported groups against the true groups. The
    tracker is told the ``laser_height`` [m] (None: unknown) as the pipeline tells it a
    recording's (:meth:`GroupMHTTracker.use_torso_height`)."""
    params = params if params is not None else GroupTrackerParams()
    tracker = GroupMHTTracker(params)
    tracker.use_torso_height(at_torso_height(laser_height))
    tracked, memoryless, size = ClusteringError(), ClusteringError(), GroupSizeError()
    times: list[float] = []
    people: list[int] = []
    group_of: list[dict[int, int]] = []
    mixed_tracker: list[tuple[int, IntArray]] = []
    mixed_memoryless: list[tuple[int, IntArray]] = []
    stamps = [s.stamp for s in scans if s.sensor == scans[0].sensor] if scans else []
    period = float(np.median(np.diff(stamps))) if len(stamps) > 1 else 0.1
    mot = ClearMot(EvaluationParams(gate=GROUP_GATE, kind="group"), keep_frames=False)
    prox = ClearMot(EvaluationParams(gate=GROUP_GATE, kind="group"), keep_frames=False)
    truth_of = {f.scan_index: f for f in truth}
    n = 0
    for k, lf in enumerate(frames_from_scans(scans)):
        t0 = time.process_time()
        reported = tracker.update(lf.frame)
        times.append(time.process_time() - t0)
        seen = lf.true_person[np.asarray(lf.frame.foreground)]
        people.append(int(np.unique(seen[seen >= 0]).size))
        on = lf.true_person >= 0
        pairs = zip(lf.true_person[on].tolist(), lf.true_group[on].tolist(), strict=True)
        group_of.append(dict(pairs))
        if k < skip:
            continue
        n += 1
        if lf.frame.index in truth_of:
            mot.accumulate(group_truth(truth_of[lf.frame.index]), reported)
            joined = proxemic_truth(truth_of[lf.frame.index], params.cluster_distance)
            prox.accumulate(joined, reported)
        fg = np.asarray(lf.frame.foreground)
        assert lf.frame.points is not None
        est = tracker.point_labels(len(lf.frame.points))
        tracked.accumulate_labels(lf.true_group[fg], est[fg], lf.frame.stamp)
        ml = single_linkage(lf.frame.points.points[fg], params.cluster_distance)
        memoryless.accumulate_labels(lf.true_group[fg], ml, lf.frame.stamp)
        tg, tp = lf.true_group[fg], lf.true_person[fg]
        mixed_tracker += [(k, p) for p in _mixed_clusters(tg, tp, est[fg])]
        mixed_memoryless += [(k, p) for p in _mixed_clusters(tg, tp, ml)]
        sizes = {g.family: g.size for g in tracker.last_groups if g.members.size}
        size.accumulate(lf.true_person[fg], est[fg], sizes)
    ms = np.asarray(times) * 1e3
    window = round(TRANSITION_WINDOW / period) if period > 0 else 0
    return GroupRunResult(
        clustering=tracked.result(),
        memoryless=memoryless.result(),
        size=size.result(),
        median_ms=float(np.median(ms)) if ms.size else float("nan"),
        mean_ms=float(np.mean(ms)) if ms.size else float("nan"),
        splits=tracker.event_counts["split"],
        merges=tracker.event_counts["merge"],
        frames=n,
        frame_ms=ms,
        frame_people=np.asarray(people, dtype=np.int64),
        tracker_under=_classify(mixed_tracker, group_of, window),
        memoryless_under=_classify(mixed_memoryless, group_of, window),
        group_mot=mot.result(),
        proxemic_mot=prox.result(),
    )
