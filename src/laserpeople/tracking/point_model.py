"""Point targets (legs, people) for the MHT core: constant-velocity Kalman filter, Mahalanobis
gate, Gaussian measurement likelihood (000 Sec. 3.1 and eq. 3)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracking import kalman
from laserpeople.tracking.kalman import KalmanParams
from laserpeople.tracking.mht.tracktree import TrackNode
from laserpeople.tracks import Detections

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


@dataclass(frozen=True, eq=False)
class PointMeasurements:
    """Position measurements of one scan.

    Attributes:
        positions: (M, 2) [m] in the tracking frame.
        covariances: (M, 2, 2) [m^2], positive definite.
    """

    positions: FloatArray
    covariances: FloatArray

    def __len__(self) -> int:
        return int(self.positions.shape[0])

    @classmethod
    def from_detections(cls, detections: Detections, measurement_std: float) -> PointMeasurements:
        """Positions and covariances of ``detections`` (covariances floored where the
        detector gave none)."""
        return cls(
            detections.positions,
            kalman.measurement_covariances(detections.covariances, measurement_std),
        )


class KalmanPointModel:
    """The :class:`~laserpeople.tracking.mht.protocols.TrackModel` of a point moving with
    constant velocity, state (x, y, vx, vy).

    Every state it hands out (updated, coasted, new) is a row of one of its batches, and
    the state's payload is that row's number in the model's store: the batches handed out
    since the last :meth:`predict`, numbered on from one prediction to the next. The next
    prediction takes the states of the nodes it predicts from the store by their rows, in
    two ``take`` calls, instead of stacking one array per node (the nodes a scan predicts
    are the children the last scan made, so their rows are all in the store)."""

    def __init__(self, params: KalmanParams) -> None:
        self.params = params
        self.gate = params.gate
        self.max_gate_sq = params.max_gate_distance**2
        # the store: batches of states (R_i, 4), (R_i, 4, 4) handed out since the last
        # predict(), their first row's number, and the rows in it
        self._store: list[tuple[FloatArray, FloatArray]] = []
        self._store_base = 0
        self._store_rows = 0
        self._store_stamp = math.nan  # the scan [s] whose states the store holds
        self._coast_base = 0  # the store's row of the last predict()'s first coasted state
        # the occluded states of the last predict() call (N, 4), (N, 4, 4)
        self._coast_batch: tuple[FloatArray, FloatArray] = (np.empty((0, 4)), np.empty((0, 4, 4)))
        self._rows: dict[int, int] = {}  # node id -> row of the last predict() call
        # the node list of the last predict() call and its predictions (N, 4), (N, 4, 4)
        self._predicted: tuple[Sequence[TrackNode], FloatArray, FloatArray] = (
            (),
            np.empty((0, 4)),
            np.empty((0, 4, 4)),
        )

    def _dt(self, nodes: Sequence[TrackNode], stamp: float) -> FloatArray:
        """Steps (N,) [s] from each node's stamp to ``stamp``, clipped to [0, max_dt] (in
        plain floats: ``np.clip``'s values at a fraction of its cost on a few nodes)."""
        top = self.params.max_dt
        return np.array([min(max(stamp - n.stamp, 0.0), top) for n in nodes], dtype=np.float64)

    def _hand_out(
        self, means: FloatArray, covs: FloatArray, stamp: float
    ) -> list[tuple[FloatArray, FloatArray, Any]]:
        """The states (K, 4), (K, 4, 4) at ``stamp`` [s] as ``(mean, cov, payload)``,
        each a row of the batch, its payload its row number in the store (the batch is
        added to it). States of another scan than the store's go with the store: no
        prediction took them, so no node holds them any more (a scan without live
        nodes is not predicted)."""
        if stamp != self._store_stamp:
            self._empty_store(stamp)
        first = self._store_base + self._store_rows
        self._store.append((means, covs))
        self._store_rows += means.shape[0]
        return list(zip(means, covs, range(first, first + means.shape[0]), strict=True))

    def _stacked(self, nodes: Sequence[TrackNode]) -> tuple[FloatArray, FloatArray, bool]:
        """The states (N, 4), (N, 4, 4) of ``nodes``: taken from the store by their rows
        when every node's state is in it, stacked node by node otherwise (the same
        floats either way); and whether they came from the store (then every node's
        stamp is the store's: the core stamps a node with the scan its state was made
        for)."""
        store, base, count = self._store, self._store_base, self._store_rows
        try:
            rows = np.fromiter((n.payload for n in nodes), dtype=np.intp, count=len(nodes))
        except (TypeError, ValueError):  # a state this model did not hand out (a test's)
            rows = None
        if rows is not None and store and rows.min() >= base and rows.max() < base + count:
            rows -= base
            if len(store) == 1:
                all_means, all_covs = store[0]
            else:
                all_means = np.concatenate([b[0] for b in store])
                all_covs = np.concatenate([b[1] for b in store])
            return all_means.take(rows, axis=0), all_covs.take(rows, axis=0), True
        means = np.array([n.mean for n in nodes], dtype=np.float64).reshape(-1, 4)
        covs = np.array([n.cov for n in nodes], dtype=np.float64).reshape(-1, 4, 4)
        return means, covs, False

    def _empty_store(self, stamp: float) -> None:
        """Start the store of the states of scan ``stamp`` [s] (rows numbered on)."""
        self._store_base += self._store_rows
        self._store, self._store_rows, self._store_stamp = [], 0, stamp

    def predict(self, nodes: Sequence[TrackNode], stamp: float) -> None:
        """Predict all nodes to ``stamp`` at once."""
        if not nodes:
            return
        means, covs, stored = self._stacked(nodes)
        tau, psd = self.params.coast_velocity_time, self.params.accel_psd
        # the occluded children's states come from the same batch (used by coast)
        if stored:  # one step for all: from the scan of the store to this one
            step = min(max(stamp - self._store_stamp, 0.0), self.params.max_dt)
            pm, pc, cm, cc = kalman.predict_and_coast_step(means, covs, step, psd, tau)
        else:
            pm, pc, cm, cc = kalman.predict_and_coast(means, covs, self._dt(nodes, stamp), psd, tau)
        self._empty_store(stamp)
        self._coast_base = self._store_base
        self._store.append((cm, cc))  # (each coasted state's row: its node's)
        self._store_rows = len(nodes)
        for n, mean, cov in zip(nodes, pm, pc, strict=True):
            n.pred_mean = mean
            n.pred_cov = cov
        self._predicted = (nodes, pm, pc)
        # where each node's prediction is in the batch (update and coast take their rows
        # from there)
        self._rows = dict(zip([n.node_id for n in nodes], range(len(nodes)), strict=True))
        self._coast_batch = (cm, cc)

    def score(
        self, nodes: Sequence[TrackNode], measurements: PointMeasurements
    ) -> tuple[BoolArray, FloatArray]:
        """Chi-square gate (capped at ``max_gate_distance``) and Gaussian log-likelihood for
        every (node, measurement)."""
        done, pm, pc = self._predicted
        if nodes is done:  # the nodes just predicted: their stacked predictions
            means, covs = pm, pc
        else:
            means = np.stack([_pred(n)[0] for n in nodes])
            covs = np.stack([_pred(n)[1] for n in nodes])
        d2, ll = kalman.mahalanobis_and_loglik(
            means, covs, measurements.positions, measurements.covariances
        )
        near = kalman.euclidean_sq(means, measurements.positions) <= self.max_gate_sq
        return (d2 <= self.gate) & near, ll

    def update(
        self,
        nodes: Sequence[TrackNode],
        measurements: PointMeasurements,
        js: Sequence[int],
        stamp: float,
    ) -> list[tuple[FloatArray, FloatArray, Any]]:
        """Kalman updates of ``nodes[i]`` with measurement ``js[i]``, all at once."""
        if not nodes:
            return []
        idx = np.asarray(js, dtype=np.intp)
        done, pm, pc = self._predicted
        rows = [self._rows.get(n.node_id, -1) for n in nodes]
        fresh = (
            r >= 0 and done[r] is n and n.pred_mean is not None
            for r, n in zip(rows, nodes, strict=True)
        )
        if all(fresh):  # all predicted in the last batch (and not cleared since): its rows
            pred_means, pred_covs = pm.take(rows, axis=0), pc.take(rows, axis=0)
        else:
            preds = [_pred(n) for n in nodes]
            pred_means = np.stack([p[0] for p in preds])
            pred_covs = np.stack([p[1] for p in preds])
        means, covs = kalman.update_batch(
            pred_means,
            pred_covs,
            measurements.positions.take(idx, axis=0),
            measurements.covariances.take(idx, axis=0),
        )
        return self._hand_out(means, covs, stamp)

    def coast(self, node: TrackNode, stamp: float) -> tuple[FloatArray, FloatArray, Any]:
        """The prediction, with the velocity decaying while occluded when
        ``coast_velocity_time`` is finite (:func:`kalman.coast`)."""
        row = self._rows.get(node.node_id)
        done = self._predicted[0]
        if row is not None and done[row] is node:  # (coasted with the prediction)
            cm, cc = self._coast_batch
            return cm[row], cc[row], self._coast_base + row
        tau = self.params.coast_velocity_time
        if math.isinf(tau):
            mean, cov = _pred(node)
            return self._hand_out(mean[None, :], cov[None], stamp)[0]
        means, covs = kalman.coast(
            node.mean[None, :], node.cov[None], self._dt([node], stamp), self.params.accel_psd, tau
        )
        return self._hand_out(means, covs, stamp)[0]

    def initiate(
        self, measurements: PointMeasurements, js: Sequence[int], stamp: float
    ) -> list[tuple[FloatArray, FloatArray, Any]]:
        """New tracks at measurements ``js`` with zero velocity (000 Sec. 3.1), at once."""
        idx = np.asarray(js, dtype=np.intp)
        means, covs = kalman.initiate_batch(
            measurements.positions.take(idx, axis=0),
            measurements.covariances.take(idx, axis=0),
            self.params.init_velocity_std,
        )
        return self._hand_out(means, covs, stamp)


def _pred(node: TrackNode) -> tuple[FloatArray, FloatArray]:
    if node.pred_mean is None or node.pred_cov is None:
        raise RuntimeError(f"track node {node.node_id} was not predicted before use")
    return node.pred_mean, node.pred_cov
