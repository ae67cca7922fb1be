"""The swappable parts of the MHT core (Stone Soup style): what a track is and how it moves
(:class:`TrackModel`), how likely each label is (:class:`LabelModel`), and which
interaction models branch off a parent hypothesis (:class:`BranchGenerator`).

The leg tracker plugs in a constant-velocity Kalman point model and the free/approved label
probabilities of 000 Sec. 3.3.1; the group tracker (000 Sec. 4) plugs in its group model
(contour, size) and a branch generator that re-predicts tracks for split/merge models.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Sequence, Sized
from dataclasses import dataclass
from typing import Any, Protocol, TypeVar

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracking.mht.tracktree import TrackNode

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

M = TypeVar("M", bound=Sized, contravariant=True)


class TrackModel(Protocol[M]):
    """Prediction, gating/likelihood, update and initiation of tracks.

    The model works on measurement sets of type ``M`` (``len(measurements)`` = M).
    """

    def predict(self, nodes: Sequence[TrackNode], stamp: float) -> None:
        """Predict every node to time ``stamp`` [s] (setting its ``pred_mean``/``pred_cov``,
        or keeping the predictions in the model, as :class:`~..point_model.KalmanPointModel`
        does)."""
        ...

    def score(self, nodes: Sequence[TrackNode], measurements: M) -> tuple[BoolArray, FloatArray]:
        """Gate (T, M) and log-likelihoods log N(z_m | track t) (T, M) of predicted nodes."""
        ...

    def update(
        self, nodes: Sequence[TrackNode], measurements: M, js: Sequence[int], stamp: float
    ) -> list[tuple[FloatArray, FloatArray, Any]]:
        """Mean, covariance and payload of each ``nodes[i]`` corrected by measurement
        ``js[i]`` (batched: one call per cluster and scan)."""
        ...

    def coast(self, node: TrackNode, stamp: float) -> tuple[FloatArray, FloatArray, Any]:
        """Mean, covariance and payload of an occluded ``node`` (its prediction)."""
        ...

    def initiate(
        self, measurements: M, js: Sequence[int], stamp: float
    ) -> list[tuple[FloatArray, FloatArray, Any]]:
        """Mean, covariance and payload of a new track from each measurement ``js[i]``."""
        ...


class LabelModel(Protocol[M]):
    """Label probabilities of tracks and measurements (000 eqs. 9-15)."""

    def track_log_probs(self, nodes: Sequence[TrackNode]) -> FloatArray:
        """(T, 3) log p(detected), log p(occluded), log p(deleted) of each track."""
        ...

    def measurement_log_rates(self, measurements: M) -> tuple[FloatArray, FloatArray]:
        """log lambda_new (M,) and log lambda_fal (M,) [log 1/m^2]."""
        ...


@dataclass(frozen=True, eq=False)
class BranchObservations:
    """A model's own observations of a cluster, replacing the cluster's measurements in
    that branch (000 Sec. 4.3: re-clustering an observation that several tracks gate).

    Attributes:
        measurements: The branch's measurement set (same type as the scan's), m' items.
        keys: Identity (m',) of each item: items with equal keys in different branches are
            the same observation and share the children made from them. Use the scan index
            (an int) for an item the model took over unchanged and any other hashable for a
            new one (e.g. ``(j, point ids)`` for a part of measurement ``j``).
        origin: Index (m',) into the scan's measurements of the item each was made from
            (ties a track born from it to that measurement when clustering).
    """

    measurements: Any
    keys: tuple[Hashable, ...]
    origin: tuple[int, ...]

    def __post_init__(self) -> None:
        m = len(self.measurements)
        if len(self.keys) != m or len(self.origin) != m:
            raise ValueError(f"{len(self.keys)} keys, {len(self.origin)} origins for {m} items")


@dataclass(frozen=True, eq=False)
class Branch:
    """One model branch of a parent hypothesis (000 Sec. 4.5: models between parent and
    children).

    Attributes:
        log_prior: log P(model | parent) (0 for the plain MHT's single model).
        tracks: The (re-predicted) track nodes the model postulates, with ``pred_mean`` and
            ``pred_cov`` set, sorted by family.
        model: An index that identifies the model among the parent's branches.
        observations: The model's own partition of the cluster's observations, or None to
            use the cluster's measurements as they are.
    """

    log_prior: float
    tracks: tuple[TrackNode, ...]
    model: int = 0
    observations: BranchObservations | None = None


class BranchGenerator(Protocol):
    """Which models branch off a parent hypothesis."""

    def branches(
        self,
        tracks: tuple[TrackNode, ...],
        gate_row: Callable[[TrackNode], BoolArray],
        meas_idx: NDArray[np.intp],
    ) -> list[Branch]:
        """Branches of a parent with ``tracks``; ``gate_row(node)`` is the (m,) gate of one
        of the parent's nodes over the cluster's measurements, whose scan indices are
        ``meas_idx`` (m,) (data-driven model generation, 000 Sec. 4.4)."""
        ...


class SingleModel:
    """The plain MHT: one branch per parent, the parent's own tracks, prior 1."""

    def branches(
        self,
        tracks: tuple[TrackNode, ...],
        gate_row: Callable[[TrackNode], BoolArray],
        meas_idx: NDArray[np.intp],
    ) -> list[Branch]:
        """One branch with the parent's tracks."""
        return [Branch(0.0, tracks, 0)]
