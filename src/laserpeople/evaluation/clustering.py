"""Clustering error of group tracking (000 Sec. 4.6.1, Fig. 17).

000 scores how well tracked groups recover the true groups "on a per-beam basis": a track
whose point set P "contains too many or wrong points" is an under-segmentation, a track
whose P "is missing points" an over-segmentation, and the clustering error is their sum.
The same measure scores a memory-less clustering (single linkage per scan, no tracking),
which is how 000 shows that tracking halves the error (3.1 % vs 7.0 %).

Our reading, per frame, with every point (a beam, or a person when scoring partitions of
people) carrying a true group label (-1: not a person) and an estimated cluster label
(-1: in no track/cluster):

* under-segmentation: a cluster holds points of two or more true groups, or any non-person
  point ("too many or wrong points");
* over-segmentation: the cluster's dominant true group (most points; ties to the smaller
  label) has points outside the cluster ("missing points");
* the rates divide these counts by the number of true groups summed over frames (000
  reports its data sets by their labelled groups), and the clustering error is
  under rate + over rate. True groups no cluster touches at all are counted separately as
  ``missed_groups`` and are not part of the error (000 does not count them).

People walking alone are groups of one (:func:`beam_group_labels`).
"""

from __future__ import annotations

import math
from collections.abc import Collection, Mapping, Sequence
from dataclasses import astuple, dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.errors import EvaluationError
from laserpeople.evaluation.detail import FrameTable
from laserpeople.truth import NONE_ID, BeamLabels

IntArray = NDArray[np.int64]

CLUSTERING_COLUMNS = (
    "frame",
    "stamp",
    "true_groups",
    "clusters",
    "under_segmented",
    "over_segmented",
    "missed_groups",
)


@dataclass(frozen=True)
class ClusteringFrame:
    """Counts of one frame (see the module docstring)."""

    true_groups: int
    clusters: int
    under_segmented: int
    over_segmented: int
    missed_groups: int


@dataclass(frozen=True)
class ClusteringErrorResult:
    """Clustering error over all frames.

    Attributes:
        error: under_rate + over_rate (000 Fig. 17), NaN without true groups.
        under_rate: Under-segmented clusters per true group.
        over_rate: Over-segmented clusters per true group.
        under_segmented: Under-segmented clusters summed over frames.
        over_segmented: Over-segmented clusters summed over frames.
        missed_groups: True groups without any clustered point, summed over frames.
        true_groups: True groups summed over frames.
        clusters: Estimated clusters summed over frames.
        num_frames: Frames scored.
    """

    error: float
    under_rate: float
    over_rate: float
    under_segmented: int
    over_segmented: int
    missed_groups: int
    true_groups: int
    clusters: int
    num_frames: int


def beam_group_labels(labels: BeamLabels) -> IntArray:
    """True group label (N,) of every beam: the group id for people in a group, a label of its
    own (above every group id) for a person walking alone, -1 for beams on no person."""
    person = labels.person.astype(np.int64)
    group = labels.group.astype(np.int64)
    out = np.full(person.shape, NONE_ID, dtype=np.int64)
    grouped = (person >= 0) & (group >= 0)
    alone = (person >= 0) & (group < 0)
    out[grouped] = group[grouped]
    offset = int(group[grouped].max()) + 1 if grouped.any() else 0
    out[alone] = offset + person[alone]
    return out


def partition_labels(
    true_groups: Sequence[Collection[int]], estimated_groups: Sequence[Collection[int]]
) -> tuple[IntArray, IntArray]:
    """Per-person labels from two partitions of person ids, for :func:`frame_counts`.

    Each person is one point. A person only in the estimate is a non-person point (a false
    member); a person only in the truth is in no cluster.

    Raises:
        EvaluationError: a person is in two sets of the same partition.
    """
    true_of = _label_of(true_groups, "true")
    est_of = _label_of(estimated_groups, "estimated")
    people = sorted(set(true_of) | set(est_of))
    t = np.array([true_of.get(p, NONE_ID) for p in people], dtype=np.int64)
    e = np.array([est_of.get(p, NONE_ID) for p in people], dtype=np.int64)
    return t, e


def _label_of(groups: Sequence[Collection[int]], which: str) -> dict[int, int]:
    out: dict[int, int] = {}
    for k, members in enumerate(groups):
        for person in members:
            if int(person) in out:
                raise EvaluationError(
                    f"person {person} is in two {which} groups",
                    hint="a partition puts every person in at most one group",
                )
            out[int(person)] = k
    return out


def frame_counts(true_labels: IntArray, estimated_labels: IntArray) -> ClusteringFrame:
    """Under/over-segmentation counts of one frame.

    Args:
        true_labels: True group (N,) of each point, -1 for a non-person point.
        estimated_labels: Estimated cluster (N,) of each point, -1 for a point in no cluster.
    """
    t = np.asarray(true_labels, dtype=np.int64).reshape(-1)
    e = np.asarray(estimated_labels, dtype=np.int64).reshape(-1)
    if t.shape != e.shape:
        raise EvaluationError(f"{t.size} true labels but {e.size} estimated labels")
    groups, t_idx = np.unique(t, return_inverse=True)
    person = groups >= 0
    n_groups = int(person.sum())
    clustered = e >= 0
    clusters, c_idx = np.unique(e[clustered], return_inverse=True)
    n_clusters = clusters.size
    if n_clusters == 0:
        return ClusteringFrame(n_groups, 0, 0, 0, n_groups)
    # Contingency table: points of each true label (incl. -1) in each cluster.
    table = np.zeros((n_clusters, groups.size), dtype=np.int64)
    np.add.at(table, (c_idx, t_idx[clustered]), 1)
    wrong = table[:, ~person].sum(axis=1) > 0
    people_table = table[:, person]
    groups_in_cluster = (people_table > 0).sum(axis=1)
    under = wrong | (groups_in_cluster > 1)
    totals = np.bincount(t_idx, minlength=groups.size)[person]
    has_people = people_table.sum(axis=1) > 0
    dominant = np.argmax(people_table, axis=1) if people_table.shape[1] else np.zeros(0, int)
    over = np.zeros(n_clusters, dtype=bool)
    if people_table.shape[1]:
        rows = np.arange(n_clusters)
        over = has_people & (people_table[rows, dominant] < totals[dominant])
    missed = int((people_table.sum(axis=0) == 0).sum())
    return ClusteringFrame(n_groups, int(n_clusters), int(under.sum()), int(over.sum()), missed)


class ClusteringError:
    """Accumulates the clustering error frame by frame (per-beam labels or partitions)."""

    def __init__(self) -> None:
        self._rows: list[tuple[int, float, int, int, int, int, int]] = []

    def accumulate_labels(
        self, true_labels: IntArray, estimated_labels: IntArray, stamp: float = math.nan
    ) -> ClusteringFrame:
        """Score one frame given per-point labels (see :func:`frame_counts`)."""
        counts = frame_counts(true_labels, estimated_labels)
        self._rows.append((len(self._rows), float(stamp), *astuple(counts)))
        return counts

    def accumulate_partitions(
        self,
        true_groups: Sequence[Collection[int]],
        estimated_groups: Sequence[Collection[int]],
        stamp: float = math.nan,
    ) -> ClusteringFrame:
        """Score one frame given the true and estimated groups as sets of person ids."""
        return self.accumulate_labels(*partition_labels(true_groups, estimated_groups), stamp)

    def result(self) -> ClusteringErrorResult:
        """The clustering error over the frames so far."""
        sums = np.array([r[2:] for r in self._rows], dtype=np.int64).reshape(-1, 5).sum(axis=0)
        true_groups, clusters, under, over, missed = (int(v) for v in sums)
        under_rate = under / true_groups if true_groups else math.nan
        over_rate = over / true_groups if true_groups else math.nan
        return ClusteringErrorResult(
            error=under_rate + over_rate,
            under_rate=under_rate,
            over_rate=over_rate,
            under_segmented=under,
            over_segmented=over,
            missed_groups=missed,
            true_groups=true_groups,
            clusters=clusters,
            num_frames=len(self._rows),
        )

    def frames(self) -> FrameTable:
        """Per-frame counts: columns :data:`CLUSTERING_COLUMNS`."""
        return FrameTable(CLUSTERING_COLUMNS, tuple(self._rows))


def clustering_error(
    true_partitions: Sequence[Sequence[Collection[int]]],
    estimated_partitions: Sequence[Sequence[Collection[int]]],
) -> ClusteringErrorResult:
    """Clustering error of a sequence of frames given as partitions of person ids.

    Args:
        true_partitions: Per frame, the true groups (sets of person ids; people alone are
            sets of one).
        estimated_partitions: Per frame, the estimated groups (a tracker's or a memory-less
            clustering's).
    """
    if len(true_partitions) != len(estimated_partitions):
        raise EvaluationError(
            f"{len(true_partitions)} true frames but {len(estimated_partitions)} estimated"
        )
    metric = ClusteringError()
    for truth, estimate in zip(true_partitions, estimated_partitions, strict=True):
        metric.accumulate_partitions(truth, estimate)
    return metric.result()


@dataclass(frozen=True)
class GroupSizeErrorResult:
    """Group-size error over all frames (000 Sec. 4.6.3).

    Attributes:
        mean_error: Mean of |estimated n - true n| over all (track, frame) [people].
        std_error: Its standard deviation [people].
        exact_share: Share of estimates that, rounded, equal the true size.
        within_one_share: Share of rounded estimates at most one person off.
        count: (track, frame) pairs scored.
    """

    mean_error: float
    std_error: float
    exact_share: float
    within_one_share: float
    count: int


def group_size_errors(
    true_person: IntArray, estimated_labels: IntArray, sizes: Mapping[int, float]
) -> NDArray[np.float64]:
    """Absolute size errors (K,) of the groups ``sizes`` (label -> estimated n) of one
    frame: the true size of a group is the number of distinct people among the points it
    holds (``true_person`` -1 for non-person points). Groups holding no point are skipped.

    Args:
        true_person: Person id (N,) of each point, -1 for none.
        estimated_labels: Estimated group (N,) of each point, -1 for none.
        sizes: Estimated size of each group label.
    """
    t = np.asarray(true_person, dtype=np.int64).reshape(-1)
    e = np.asarray(estimated_labels, dtype=np.int64).reshape(-1)
    if t.shape != e.shape:
        raise EvaluationError(f"{t.size} true labels but {e.size} estimated labels")
    out = []
    for label, n in sizes.items():
        sel = e == label
        if not sel.any():
            continue
        people = np.unique(t[sel])
        out.append(abs(float(n) - float(np.count_nonzero(people >= 0))))
    return np.asarray(out, dtype=np.float64)


class GroupSizeError:
    """Accumulates the group-size error frame by frame (:func:`group_size_errors`)."""

    def __init__(self) -> None:
        self._errors: list[NDArray[np.float64]] = []
        self._rounded: list[NDArray[np.float64]] = []

    def accumulate(
        self, true_person: IntArray, estimated_labels: IntArray, sizes: Mapping[int, float]
    ) -> NDArray[np.float64]:
        """Score one frame; returns its errors."""
        err = group_size_errors(true_person, estimated_labels, sizes)
        rounded = {k: float(np.round(v)) for k, v in sizes.items()}
        self._errors.append(err)
        self._rounded.append(group_size_errors(true_person, estimated_labels, rounded))
        return err

    def result(self) -> GroupSizeErrorResult:
        """Mean, std and shares over the frames so far (NaN without groups)."""
        err = np.concatenate(self._errors) if self._errors else np.empty(0)
        rnd = np.concatenate(self._rounded) if self._rounded else np.empty(0)
        if err.size == 0:
            return GroupSizeErrorResult(math.nan, math.nan, math.nan, math.nan, 0)
        return GroupSizeErrorResult(
            mean_error=float(err.mean()),
            std_error=float(err.std()),
            exact_share=float(np.mean(rnd < 0.5)),
            within_one_share=float(np.mean(rnd < 1.5)),
            count=int(err.size),
        )
