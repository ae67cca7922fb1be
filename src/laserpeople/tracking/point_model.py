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

    Args:
        params: The filter's parameters.
        node_predictions: Whether :meth:`predict` sets every node's ``pred_mean`` and
            ``pred_cov`` (views of its batch) as the protocol says, for branch generators
            that copy them; False keeps them in the batch only (read by row, the same
            arrays): an MHT of one model per parent reads nothing else, and a view per node
            costs about a fifth of the prediction with a few hundred nodes.
    """

    def __init__(self, params: KalmanParams, node_predictions: bool = True) -> None:
        self.params = params
        self.node_predictions = node_predictions
        self.gate = params.gate
        self.max_gate_sq = params.max_gate_distance**2
        # the occluded states of the last predict() call (N, 4), (N, 4, 4), rows as _rows
        self._coast_batch: tuple[FloatArray, FloatArray] = (np.empty((0, 4)), np.empty((0, 4, 4)))
        self._rows: dict[int, int] = {}  # id(node) -> row of the last predict() call
        # the node list of the last predict() call and its predictions (N, 4), (N, 4, 4)
        self._predicted: tuple[Sequence[TrackNode], FloatArray, FloatArray] = (
            (),
            np.empty((0, 4)),
            np.empty((0, 4, 4)),
        )

    def _steps(self, nodes: Sequence[TrackNode], stamp: float) -> list[float]:
        """Steps [s] from each node's stamp to ``stamp``, clipped to [0, max_dt] (in plain
        floats: ``np.clip``'s values at a fraction of its cost on a few nodes)."""
        top = self.params.max_dt
        steps = [stamp - n.stamp for n in nodes]
        d = steps[0] if steps else 0.0
        if 0.0 <= d <= top and steps.count(d) == len(steps):  # (most scans: one step)
            return steps
        return [min(max(s, 0.0), top) for s in steps]

    def predict(self, nodes: Sequence[TrackNode], stamp: float) -> None:
        """Predict all nodes to ``stamp`` at once."""
        if not nodes:
            return
        tau = self.params.coast_velocity_time
        # the occluded children's states come from the same batch (used by coast)
        pm, pc, cm, cc = kalman.predict_rows(
            [n.mean for n in nodes],
            [n.cov for n in nodes],
            self._steps(nodes, stamp),
            self.params.accel_psd,
            tau,
        )
        if self.node_predictions:
            for n, mean, cov in zip(nodes, pm, pc, strict=True):
                n.pred_mean = mean
                n.pred_cov = cov
        self._predicted = (nodes, pm, pc)
        # where each node's prediction is in the batch (update takes its rows from there)
        self._rows = dict(zip(map(id, nodes), range(len(nodes)), strict=True))
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
            means = np.stack([self._pred(n)[0] for n in nodes])
            covs = np.stack([self._pred(n)[1] for n in nodes])
        return kalman.gate_and_loglik(
            means,
            covs,
            measurements.positions,
            measurements.covariances,
            self.gate,
            self.max_gate_sq,
        )

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
        done, pm, pc = self._predicted
        rows = [self._rows.get(id(n), -1) for n in nodes]
        fresh = (r >= 0 and done[r] is n for r, n in zip(rows, nodes, strict=True))
        if not all(fresh):  # not all predicted in the last batch: their own predictions
            preds = [self._pred(n) for n in nodes]
            pm = np.stack([p[0] for p in preds])
            pc = np.stack([p[1] for p in preds])
            rows = list(range(len(nodes)))
        means, covs = kalman.update_rows(
            pm, pc, rows, measurements.positions, measurements.covariances, list(js)
        )
        return [(mean, cov, None) for mean, cov in zip(means, covs, strict=True)]

    def coast(self, node: TrackNode, stamp: float) -> tuple[FloatArray, FloatArray, Any]:
        """The prediction, with the velocity decaying while occluded when
        ``coast_velocity_time`` is finite (:func:`kalman.coast`)."""
        tau = self.params.coast_velocity_time
        if math.isinf(tau):
            mean, cov = self._pred(node)
            return mean, cov, None
        done = self._predicted[0]
        row = self._rows.get(id(node), -1)
        if row >= 0 and done[row] is node:  # predicted in the last batch: its coasted row
            cm, cc = self._coast_batch
            return cm[row], cc[row], None
        means, covs = kalman.coast(
            node.mean[None, :],
            node.cov[None],
            np.array(self._steps([node], stamp)),
            self.params.accel_psd,
            tau,
        )
        return means[0], covs[0], None

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
        return [(means[i], covs[i], None) for i in range(idx.size)]

    def _pred(self, node: TrackNode) -> tuple[FloatArray, FloatArray]:
        """The prediction of ``node``: its row of the last :meth:`predict` batch, else
        the node's own ``pred_mean`` and ``pred_cov`` (set by whoever predicted it)."""
        done, pm, pc = self._predicted
        row = self._rows.get(id(node), -1)
        if row >= 0 and done[row] is node:
            return pm[row], pc[row]
        if node.pred_mean is None or node.pred_cov is None:
            raise RuntimeError(f"track node {node.node_id} was not predicted before use")
        return node.pred_mean, node.pred_cov
