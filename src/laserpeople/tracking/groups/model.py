"""Group tracks and their equations (000 Sec. 4.2-4.3): G = <x, C, P, L>.

State x = (x, y, vx, vy, n) [m, m, m/s, m/s, people] with covariance C (5, 5); the contour P
is a set of points relative to the position (x, y); the labels L are the group's history
(:mod:`.labels`). Every function here is one numbered equation of 000 and is tested
against hand-computed values.

:class:`GroupModel` is the MHT core's :class:`~laserpeople.tracking.mht.protocols.
TrackModel` for groups: constant-velocity prediction with constant size, the
Hausdorff-based gate and likelihood (eqs. 19-24), the Kalman update with the group size as
observation (eqs. 28-31) and initiation from a cluster (eq. 16).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracking.groups.observations import GroupObservations, size_reading
from laserpeople.tracking.mht.tracktree import TrackNode

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]
SCORE_BLOCK = 400_000
"""Most Mahalanobis distances (observed points x contour points) :class:`GroupModel` holds
in memory at once when scoring (larger problems are scored in blocks of tracks)."""
_ORIGIN = np.zeros((1, 2))
_LOG_2PI_NEG = -math.log(2.0 * math.pi)
_NO_TRAIL = np.empty((0, 3))


@dataclass(eq=False, slots=True)
class GroupPayload:
    """What a group track carries besides x and C. Treated as immutable (nodes share
    payloads and their arrays); not a frozen dataclass only because some 60 are made per
    scan and a frozen one's ``__init__`` costs eight times as much.

    Attributes:
        contour: P, points (K, 2) [m] relative to the position of the state.
        labels: L, the label set (e.g. ``("0-1", "2")``); empty for a group not named yet
            (the tracker names it by its family when first needed).
        members: Frame point indices (K,) of the observation the contour came from (empty
            when the contour was not observed this scan).
        must_match: A split or merged track of this scan: it must be matched (000 Sec. 4.4).
        event: How the track's family began: "split" or "merge" when a model made it, ""
            when it was born from an observation.
        trail: The observed centroids of the track since its birth, split or merge, at
            most ``GroupModelSettings.trail_window`` seconds back: rows (stamp [s], x [m],
            y [m]), (R, 3); empty when the window is 0 (see :func:`trail_velocity`).
    """

    contour: FloatArray
    labels: tuple[str, ...] = ()
    members: IntArray = field(default_factory=lambda: np.empty(0, dtype=np.int64))
    must_match: bool = False
    event: str = ""
    trail: FloatArray = field(default_factory=lambda: _NO_TRAIL)


def transition(dt: float) -> FloatArray:
    """A of 000 Sec. 4.2.3 (5, 5): constant velocity, constant size."""
    a = np.eye(5)
    a[0, 2] = a[1, 3] = dt
    return a


def kalman_update_batch(
    means: FloatArray, covs: FloatArray, centroids: FloatArray, n_hs: FloatArray, r: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """x(k+1|k+1) and C(k+1|k+1) of many tracks from their observations (centroid, n_hs)
    (eqs. 28-31: H~ picks x, y and n): means (T, 5), covs (T, 5, 5), centroids (T, 2) [m],
    n_hs (T,), observation covariance r (3, 3) of (x, y, n)."""
    z = np.column_stack([centroids, n_hs])
    hc = covs[:, [0, 1, 4], :]  # H~ C (T, 3, 5)
    s = hc[:, :, [0, 1, 4]] + r  # H~ C H~^T + R (T, 3, 3)
    gain_t = np.linalg.solve(s, hc)  # K^T = S^-1 H~ C (S and C symmetric), eq. 30
    innov = z - means[:, [0, 1, 4]]
    new_means = means + np.einsum("tij,ti->tj", gain_t, innov)  # eq. 28
    new_covs = covs - np.einsum("tij,tik->tjk", gain_t, hc)  # eq. 29: C - K H~ C
    return new_means, 0.5 * (new_covs + new_covs.transpose(0, 2, 1))


def initial_states(
    obs: GroupObservations, js: Sequence[int], c0: FloatArray, stamp: float | None = None
) -> list[tuple[FloatArray, FloatArray, GroupPayload]]:
    """State, covariance and payload (contour and members) of a new group from each of
    the clusters ``js`` of ``obs`` (eq. 16): position at the centroid, zero velocity,
    n = n_hs, C = C_0, P = the points minus the centroid; the states, covariances and
    contours of all made in one array each. With ``stamp`` [s] the trail starts at the
    centroid (:attr:`GroupPayload.trail`)."""
    idx = np.asarray(js, dtype=np.intp)
    sizes = obs.sizes[idx]
    starts = obs.offsets[idx]
    bounds = zip(starts.tolist(), (starts + sizes).tolist(), strict=True)
    # ndarray.mean is add.reduce divided by the count; called directly (no Python wrapper)
    add = np.add.reduce
    centroids = np.array([add(obs.points[a:b], axis=0) / (b - a) for a, b in bounds])
    centroids = centroids.reshape(-1, 2)
    means = np.zeros((idx.size, 5))
    means[:, :2] = centroids
    means[:, 4] = obs.n_hs[idx]
    covs = np.broadcast_to(c0, (idx.size, 5, 5)).copy()
    rows = _ranges(starts, sizes)
    contours = obs.points[rows] - np.repeat(centroids, sizes, axis=0)
    members = obs.members[rows]
    ends = np.cumsum(sizes).tolist()
    trails = (
        [_NO_TRAIL] * idx.size
        if stamp is None
        else [np.array([[stamp, c[0], c[1]]]) for c in centroids.tolist()]
    )
    return [
        (means[k], covs[k], GroupPayload(contours[a:b], (), members[a:b], trail=trails[k]))
        for k, (a, b) in enumerate(zip([0, *ends[:-1]], ends, strict=True))
    ]


def merge_state(
    mean_i: FloatArray,
    cov_i: FloatArray,
    n_points_i: int,
    mean_j: FloatArray,
    cov_j: FloatArray,
    n_points_j: int,
) -> tuple[FloatArray, FloatArray]:
    """State and covariance of two merging groups (eqs. 17-18).

    Position and velocity are the mean weighted by the contour sizes w = |P_i| / |P_ij|,
    their covariance the weighted sum with squared weights (independent tracks); the sizes
    add, and so do their variances (000 Sec. 4.2.3). The cross-covariances of size and
    kinematics follow the same rule (w_i C_i + w_j C_j), the covariance of
    (w_i x_i + w_j x_j, n_i + n_j) for independent tracks.
    """
    total = n_points_i + n_points_j
    w_i, w_j = n_points_i / total, n_points_j / total
    mean = np.empty(5)
    mean[:4] = w_i * mean_i[:4] + w_j * mean_j[:4]  # eq. 17
    mean[4] = mean_i[4] + mean_j[4]
    cov = np.empty((5, 5))
    cov[:4, :4] = w_i**2 * cov_i[:4, :4] + w_j**2 * cov_j[:4, :4]  # eq. 18
    cross = w_i * cov_i[:4, 4] + w_j * cov_j[:4, 4]
    cov[:4, 4] = cov[4, :4] = cross
    cov[4, 4] = cov_i[4, 4] + cov_j[4, 4]
    return mean, cov


def split_state(mean: FloatArray, c0: FloatArray) -> tuple[FloatArray, FloatArray]:
    """State and covariance of each of the two tracks a group splits into (Sec. 4.2.3):
    the predicted state with n/2 people, and the covariance re-initialised to C_0."""
    out = np.asarray(mean, dtype=np.float64).copy()
    out[4] = 0.5 * out[4]
    return out, c0.copy()


def group_distance_sq(
    contour_i: FloatArray,
    mean_i: FloatArray,
    cov_i: FloatArray,
    contour_j: FloatArray,
    mean_j: FloatArray,
    cov_j: FloatArray,
    d_p: float,
) -> float:
    """d_min^2(G_i, G_j) (eqs. 25-26): over all pairs of contour points (absolute
    positions), the squared Mahalanobis distance of (dx', vx_i - vx_j, vy_i - vy_j) with
    C_i + C_j (upper-left 4x4 blocks), where dx' is the point difference shortened by d_P
    along itself and zero when the points are within d_P."""
    pi = np.asarray(contour_i, dtype=np.float64) + mean_i[:2]
    pj = np.asarray(contour_j, dtype=np.float64) + mean_j[:2]
    # star (4, pairs): rows dx', dy', vx_i - vx_j, vy_i - vy_j, written in place
    star = np.empty((4, pi.shape[0], pj.shape[0]))
    dx = np.subtract(pi[:, None, 0], pj[None, :, 0], out=star[0])
    dy = np.subtract(pi[:, None, 1], pj[None, :, 1], out=star[1])
    # the shortening 1 - d_P / |dx| beyond d_P, 0 within (1 - d_P / d_P is exactly 0)
    scale = np.hypot(dx, dy)
    np.maximum(scale, d_p, out=scale)
    np.divide(d_p, scale, out=scale)
    np.subtract(1.0, scale, out=scale)
    dx *= scale  # max(0, dx - d_P u)
    dy *= scale
    star[2] = mean_i[2] - mean_j[2]  # eq. 25
    star[3] = mean_i[3] - mean_j[3]
    flat = star.reshape(4, -1)
    s = cov_i[:4, :4] + cov_j[:4, :4]
    sol = np.linalg.solve(s, flat)
    return float(np.einsum("ji,ji->i", flat, sol).min())  # eq. 26


def trail_velocity(
    trail: FloatArray, min_span: float, centroid_std: float
) -> tuple[FloatArray, float] | None:
    """A group's velocity over its trail of observed centroids (the velocity of eqs.
    25-26 from a longer memory than the Kalman filter's): the least-squares slope of x and
    of y on time, (2,) [m/s], and its variance [m^2/s^2] per component,
    s^2 / sum_k (t_k - mean t)^2, where s^2 is the larger of ``centroid_std``^2 [m^2]
    and the residual variance of the straight-line fits (the sum of both coordinates'
    squared residuals over 2 (R - 2)): a group that turned or stopped within the trail
    fits a line badly, and its slope is known less. None when the trail (R, 3) of rows
    (stamp [s], x, y [m]) has fewer than three rows or spans less than ``min_span``
    [s]."""
    if trail.shape[0] < 3:
        return None
    t = trail[:, 0]
    if t[-1] - t[0] < min_span or t[-1] - t[0] <= 0.0:
        return None
    dt = t - t.mean()
    stt = float(dt @ dt)
    xy = trail[:, 1:] - trail[:, 1:].mean(axis=0)
    slope = dt @ xy / stt
    residual = xy - np.outer(dt, slope)
    s2 = float(np.sum(residual * residual)) / (2.0 * (trail.shape[0] - 2))
    return np.asarray(slope, dtype=np.float64), max(centroid_std**2, s2) / stt


def with_trail_velocity(
    mean: FloatArray, cov: FloatArray, velocity: FloatArray, variance: float
) -> tuple[FloatArray, FloatArray]:
    """A state (5,) and covariance (5, 5) with the velocity replaced by ``velocity`` (2,)
    [m/s] of independent ``variance`` per component (no correlation with the rest)."""
    out_mean = np.array(mean, dtype=np.float64)
    out_mean[2:4] = velocity
    out_cov = np.array(cov, dtype=np.float64)
    out_cov[2:4, :] = 0.0
    out_cov[:, 2:4] = 0.0
    out_cov[2, 2] = out_cov[3, 3] = variance
    return out_mean, out_cov


def merge_log_likelihood(d_min_sq: float, cov_i: FloatArray, cov_j: FloatArray) -> float:
    """log N_ij of eq. 27: log of exp(-d_min^2 / 2) / ((2 pi)^2 sqrt(det(C_i + C_j)))."""
    det = float(np.linalg.det(cov_i[:4, :4] + cov_j[:4, :4]))
    return -2.0 * math.log(2.0 * math.pi) - 0.5 * math.log(det) - 0.5 * d_min_sq


@dataclass(frozen=True)
class GroupModelSettings:
    """The numbers :class:`GroupModel` needs (from the tracker's parameters).

    Attributes:
        c0: Initial covariance C_0 (5, 5).
        q: Process noise Q (5, 5) per ``period``.
        period: Scan period Q is given for [s]; Q scales with dt / period.
        max_dt: Longest prediction step [s].
        r_point: Observation covariance R_l (2, 2) of a point [m^2].
        r_update: Observation covariance (3, 3) of (centroid, n_hs).
        gate_sq: Gate on d_HD^2.
        max_gap: Contour-to-cluster distance beyond which no gate is computed [m].
        log_p_match: log p_M (a part of a re-clustered observation counts as its share of
            one matched observation, see :meth:`GroupModel.score`).
        rms: Root mean square instead of the mean in eq. 20.
        share_parts: Parts count their share (False: each part a whole observation, 000).
        trail_window: Seconds of observed centroids a track keeps (0: none).
        stride_speed: Predicted speed [m/s] from which a group's size may be read at the
            low end of its cluster's range of counts (slower: at the count; see
            :func:`size_reading`).
    """

    c0: FloatArray
    q: FloatArray
    period: float
    max_dt: float
    r_point: FloatArray
    r_update: FloatArray
    gate_sq: float
    max_gap: float
    log_p_match: float = 0.0
    rms: bool = False
    share_parts: bool = True
    trail_window: float = 0.0
    stride_speed: float = 0.0


class GroupModel:
    """The MHT core's track model for groups (see the module doc)."""

    def __init__(self, settings: GroupModelSettings) -> None:
        self.s = settings
        self._rows: dict[tuple[int, int], tuple[BoolArray, FloatArray]] = {}
        self._pred_row: dict[int, int] = {}  # node id -> row of the last predict's arrays
        self._pred: tuple[FloatArray, FloatArray] = (np.empty((0, 5)), np.empty((0, 5, 5)))
        self.scan: GroupObservations | None = None
        """The scan's observations (set before each MHT step); re-clustered observation
        sets refer to its points."""

    # -- prediction
    def predict_one(
        self, mean: FloatArray, cov: FloatArray, dt: float
    ) -> tuple[FloatArray, FloatArray]:
        """x(k+1|k) = A x, C(k+1|k) = A C A^T + Q (000 Sec. 4.2.3)."""
        a = transition(dt)
        q = self.s.q * (dt / self.s.period)
        return a @ mean, a @ cov @ a.T + q

    def predict(self, nodes: Sequence[TrackNode], stamp: float) -> None:
        """Predict every node to ``stamp`` [s] (batched)."""
        self._rows.clear()
        self._pred_row = {n.node_id: i for i, n in enumerate(nodes)}
        if not nodes:
            return
        means = np.array([n.mean for n in nodes])  # np.stack's rows, without its checks
        covs = np.array([n.cov for n in nodes])
        dt = np.clip(stamp - np.array([n.stamp for n in nodes]), 0.0, self.s.max_dt)
        a = np.broadcast_to(np.eye(5), (len(nodes), 5, 5)).copy()
        a[:, 0, 2] = a[:, 1, 3] = dt
        pm = np.einsum("nij,nj->ni", a, means)
        pc = a @ covs @ a.transpose(0, 2, 1) + self.s.q[None] * (dt / self.s.period)[:, None, None]
        self._pred = (pm, pc)
        for n, m_i, c_i in zip(nodes, pm, pc, strict=True):
            n.pred_mean = m_i
            n.pred_cov = c_i

    def _predictions(self, nodes: Sequence[TrackNode]) -> tuple[FloatArray, FloatArray]:
        """Predicted means (T, 5) and covariances (T, 5, 5) of ``nodes``: rows of the
        last :meth:`predict`'s arrays when it predicted them all (the nodes' own
        ``pred_mean`` and ``pred_cov`` are views of these rows), else stacked."""
        rows = self._pred_row
        idx = [rows.get(n.node_id, -1) for n in nodes]
        if -1 not in idx:
            take = np.array(idx, dtype=np.intp)
            return self._pred[0][take], self._pred[1][take]
        preds = [node_prediction(n) for n in nodes]
        return np.stack([p[0] for p in preds]), np.stack([p[1] for p in preds])

    # -- gating and likelihood
    def score(
        self, nodes: Sequence[TrackNode], measurements: GroupObservations
    ) -> tuple[BoolArray, FloatArray]:
        """Gate d_HD^2 <= gate and log N_i (eq. 24) of every (node, cluster) (T, M); rows
        are remembered per node and observation set until the next :meth:`predict`.

        A part of a re-clustered observation with share w of its points scores
        w (log p_M + log N_i) - log p_M, so that the parts of one observation matched to
        their tracks contribute p_M once and the point-weighted geometric mean of their
        N_i: one observation counts as one, however a model divides it (a departure from
        000, where dividing an observation always adds a factor p_M N_i > 1 and a merge
        could never explain one observation better than the tracks re-clustered; see
        docs/groups.md)."""
        t, m = len(nodes), len(measurements)
        if t == 0 or m == 0:
            return np.zeros((t, m), dtype=bool), np.full((t, m), -np.inf)
        key = id(measurements)
        rows = self._rows
        todo = [n for n in nodes if (n.node_id, key) not in rows]
        if todo:
            batch = measurements.source is None and len(todo) > 1 and not self.s.rms
            gated, loglik = self._score_nodes(todo, measurements, batch)
            for node, g_row, ll_row in zip(todo, gated, loglik, strict=True):
                rows[(node.node_id, key)] = (g_row, ll_row)
            if len(todo) == t:
                return gated, loglik
        made = [rows[(n.node_id, key)] for n in nodes]
        if t == 1:  # a remembered row as a (1, M) view (callers do not write into rows)
            return made[0][0][None], made[0][1][None]
        return np.stack([r[0] for r in made]), np.stack([r[1] for r in made])

    def score_apart(self, nodes: Sequence[TrackNode], measurements: GroupObservations) -> None:
        """Remember the rows of ``nodes`` against ``measurements`` as :meth:`score` of each
        node alone would make them (the same roundings), in one pass."""
        key = id(measurements)
        todo = [n for n in nodes if (n.node_id, key) not in self._rows]
        if not todo or len(measurements) == 0:
            return
        # nodes with the same prediction and contour (the two halves of a split) are
        # scored once: a row depends only on its own node
        first: dict[tuple[int, int, int], TrackNode] = {}
        same = [
            first.setdefault((id(group_payload(n).contour), id(n.pred_mean), id(n.pred_cov)), n)
            for n in todo
        ]
        unique = list(first.values())
        gated, loglik = self._score_nodes(unique, measurements, False)
        rows = {n.node_id: r for n, r in zip(unique, zip(gated, loglik, strict=True), strict=True)}
        for node, twin in zip(todo, same, strict=True):
            self._rows[(node.node_id, key)] = rows[twin.node_id]

    def _score_nodes(
        self, nodes: Sequence[TrackNode], obs: GroupObservations, batch: bool
    ) -> tuple[BoolArray, FloatArray]:
        """Gate and log N_i (T, M) of ``nodes`` against every cluster of ``obs`` (eqs.
        19-24), in blocks of at most :data:`SCORE_BLOCK` distances."""
        contours = [group_payload(n).contour for n in nodes]
        sizes = [len(c) or 1 for c in contours]
        n_points = max(len(obs.points), 1)
        if n_points * sum(sizes) <= SCORE_BLOCK:
            return self._score_block(nodes, obs, batch, contours)
        blocks: list[tuple[BoolArray, FloatArray]] = []
        start, width = 0, 0
        for end, k in enumerate(sizes):
            if width and (width + k) * n_points > SCORE_BLOCK:
                blocks.append(self._score_block(nodes[start:end], obs, batch))
                start, width = end, 0
            width += k
        blocks.append(self._score_block(nodes[start:], obs, batch))
        return np.concatenate([b[0] for b in blocks]), np.concatenate([b[1] for b in blocks])

    def _score_block(
        self,
        nodes: Sequence[TrackNode],
        obs: GroupObservations,
        batch: bool,
        contours: Sequence[FloatArray] | None = None,
    ) -> tuple[BoolArray, FloatArray]:
        """Gate and log N_i (T, M) of ``nodes`` against every cluster of ``obs`` in one
        pass (eqs. 19-24): the Mahalanobis distances D (eq. 21) of every point of the
        clusters near some node to every predicted contour point of the nodes near some
        cluster, one dense matrix, and segment reductions (``reduceat``) over contour
        points (nearest contour point of each observed point, per node) and over
        observed points (nearest observed point of each contour point, per cluster) for
        the two directed averages of eq. 20.

        Only (node, cluster) pairs within reach are scored: no point of a cluster whose
        bounding circle is more than sqrt(gate * largest eigenvalue of S) from the
        contour's can be gated, as every distance of eq. 21 and so both averages of eq.
        20 exceed the gate (exact, not an approximation; ``max_gap`` caps the reach). For
        a model's re-clustered observations (``obs.source`` set) the reach is that of the
        scan's clusters the points came from, so a part scores exactly when its
        observation would. ``contours``: the nodes' contours (taken from their payloads
        when None)."""
        t, m = len(nodes), len(obs)
        gated = np.zeros((t, m), dtype=bool)
        loglik = np.full((t, m), -np.inf)
        means, covs = self._predictions(nodes)
        pos = means[:, :2]
        s = covs[:, :2, :2] + self.s.r_point  # eq. 23
        s00, s01, s11 = s[:, 0, 0], s[:, 0, 1], s[:, 1, 1]
        det = s00 * s11 - s01**2
        if contours is None:
            contours = [group_payload(n).contour for n in nodes]
        k_t = np.array([len(c) or 1 for c in contours], dtype=np.int64)
        owner = np.repeat(np.arange(t), k_t)
        rel = np.concatenate([c if c.shape[0] else _ORIGIN for c in contours])
        c_abs = rel + pos[owner]  # the predicted contours, absolute (eq. 22)
        c_start = np.cumsum(k_t) - k_t
        r_t = np.maximum.reduceat(np.hypot(*(c_abs - pos[owner]).T), c_start)
        half_trace = 0.5 * (s00 + s11)
        lam_max = half_trace + np.sqrt(np.maximum(half_trace**2 - det, 0.0))
        reach = np.minimum(self.s.max_gap, np.sqrt(self.s.gate_sq * lam_max))
        base = self.scan if obs.source is not None and self.scan is not None else obs
        gap = (
            np.hypot(
                base.centroids[None, :, 0] - pos[:, None, 0],
                base.centroids[None, :, 1] - pos[:, None, 1],
            )
            - base.radii[None, :]
            - r_t[:, None]
        )
        near = gap <= reach[:, None]  # (T, M) of the scan's clusters
        counts = obs.sizes
        if base is not obs:  # a part is near when every point's scan cluster is
            assert obs.source is not None
            near = np.logical_and.reduceat(
                near[:, base.point_cluster[obs.source]], obs.offsets[:-1], axis=1
            )
        near &= counts[None, :] > 0
        row_near: BoolArray = np.any(near, axis=1)
        col_near: BoolArray = np.any(near, axis=0)
        rows_t = np.flatnonzero(row_near)
        cols_m = np.flatnonzero(col_near)
        if rows_t.size == 0:
            return gated, loglik
        # the observed points of the clusters near some node
        if cols_m.size == m:
            points, n_z = obs.points, counts
        else:
            n_z = counts[cols_m]
            points = obs.points[col_near[obs.point_cluster]]
        # the contour points of the nodes near some cluster
        if rows_t.size == t:
            n_c, cols_c = k_t, c_abs
            ds00, ds01, ds11, ddet = s00, s01, s11, det
        else:
            n_c = k_t[rows_t]
            cols_c = c_abs[row_near[owner]]
            ds00, ds01, ds11, ddet = s00[rows_t], s01[rows_t], s11[rows_t], det[rows_t]
        sub_near = near if cols_m.size == m and rows_t.size == t else near[rows_t][:, cols_m]
        coef = (ds00, ds01, ds11, ddet)
        d_hd = self._hausdorff(points, n_z, cols_c, n_c, coef, batch)
        ok = sub_near & (d_hd**2 <= self.s.gate_sq)
        w = obs.share[cols_m][None, :] if self.s.share_parts else np.ones((1, cols_m.size))
        lpm = self.s.log_p_match
        if batch:  # eq. 24, a part counting its share
            log_norm = _LOG_2PI_NEG - 0.5 * np.log(ddet)
            sub_ll = w * (lpm + log_norm[:, None] - 0.5 * d_hd**2) - lpm
        else:
            log_norm = np.array([_LOG_2PI_NEG - 0.5 * math.log(d) for d in ddet.tolist()])
            sub_ll = w * (lpm + (log_norm[:, None] - 0.5 * d_hd**2)) - lpm
        sub_ll = np.where(ok, sub_ll, -np.inf)
        if rows_t.size == t and cols_m.size == m:
            return ok, sub_ll
        gated[np.ix_(rows_t, cols_m)] = ok
        loglik[np.ix_(rows_t, cols_m)] = sub_ll
        return gated, loglik

    def _hausdorff(
        self,
        points: FloatArray,
        n_z: IntArray,
        cols_c: FloatArray,
        n_c: IntArray,
        coef: tuple[FloatArray, FloatArray, FloatArray, FloatArray],
        batch: bool,
    ) -> FloatArray:
        """d_HD (T', M') (eqs. 19-21) of the nodes whose predicted contours (absolute,
        ``n_c`` (T',) points each, ``cols_c`` (K, 2)) and innovation covariances S
        (``coef``: s00, s01, s11, det S, each (T',)) are given against the clusters of
        ``points`` (Z, 2) (``n_z`` (M',) points each), from one dense matrix of the
        Mahalanobis distances D (eq. 21); ``batch`` chooses how d(P, Z) is summed (see
        :meth:`_score_block`)."""
        ds00, ds01, ds11, ddet = coef
        z_start = np.cumsum(n_z) - n_z
        col_owner = np.repeat(np.arange(n_c.size), n_c)
        n_start = np.cumsum(n_c) - n_c
        dx = np.subtract.outer(points[:, 0], cols_c[:, 0])
        dy = np.subtract.outer(points[:, 1], cols_c[:, 1])
        # D^2 det S (eq. 21) = s11 dx dx - 2 s01 dx dy + s00 dy dy, in place (the same
        # operations in the same order); the square root and the division are monotonic,
        # so they are taken after the minima (the same numbers as before the minima)
        q = np.multiply(dx, ds11[col_owner])
        q *= dx
        tmp = np.multiply(dx, (2.0 * ds01)[col_owner], out=dx)
        tmp *= dy
        q -= tmp
        tmp = np.multiply(dy, ds00[col_owner], out=tmp)
        tmp *= dy
        q += tmp
        z_min = np.sqrt(np.minimum.reduceat(q, n_start, axis=1) / ddet[None, :])  # (Z, T')
        c_min = np.sqrt(_row_block_min(q, z_start, n_z) / ddet[col_owner])  # (M', K)
        if self.s.rms:  # root mean square of the nearest distances
            z_min, c_min = z_min**2, c_min**2
        z_to_p = np.add.reduceat(z_min, z_start, axis=0) / n_z[:, None]  # d(Z, P), eq. 20
        if batch:
            p_to_z = np.add.reduceat(c_min, n_start, axis=1) / n_c[None, :]  # d(P, Z)
        elif n_c.size == 1:  # the same mean, summed in numpy's order for a row
            p_to_z = (np.add.reduce(c_min, axis=1) / c_min.shape[1])[:, None]
        else:  # each node's own mean (ndarray.mean is add.reduce divided by the count)
            ends = (n_start + n_c).tolist()
            p_to_z = np.column_stack(
                [
                    np.add.reduce(c_min[:, a:b], axis=1) / (b - a)
                    for a, b in zip(n_start.tolist(), ends, strict=True)
                ]
            )
        if self.s.rms:
            z_to_p, p_to_z = np.sqrt(z_to_p), np.sqrt(p_to_z)
        return np.asarray(np.minimum(z_to_p, p_to_z).T)  # eq. 19, (T', M')

    # -- update, coast, initiate
    def update(
        self,
        nodes: Sequence[TrackNode],
        measurements: GroupObservations,
        js: Sequence[int],
        stamp: float,
    ) -> list[tuple[FloatArray, FloatArray, Any]]:
        """Kalman update of each node with cluster ``js[i]`` (eqs. 28-31; the size read
        is :func:`size_reading`'s: the predicted size within the cluster's range of counts,
        the count for a track a split or merge made this scan);
        the contour is replaced by the cluster's points relative to the new position (Sec.
        4.3)."""
        out: list[tuple[FloatArray, FloatArray, Any]] = []
        if not nodes:
            return out
        idx = np.asarray(js, dtype=np.intp)
        predicted, predicted_covs = self._predictions(nodes)
        n_range = None if measurements.n_range is None else measurements.n_range[idx]
        fresh = np.fromiter((group_payload(n).must_match for n in nodes), bool, len(nodes))
        reading = size_reading(
            predicted, measurements.n_hs[idx], n_range, fresh, self.s.stride_speed
        )
        means, covs = kalman_update_batch(
            predicted,
            predicted_covs,
            measurements.centroids[idx],
            reading,
            self.s.r_update,
        )
        # every contour (cluster points minus the new position) and member list at once
        sizes = measurements.sizes[idx]
        rows = _ranges(measurements.offsets[idx], sizes)
        contours = measurements.points[rows] - np.repeat(means[:, :2], sizes, axis=0)
        members = measurements.members[rows]
        ends = np.cumsum(sizes).tolist()
        starts = [0, *ends[:-1]]
        window = self.s.trail_window
        seen = measurements.centroids[idx].tolist()
        for node, a, b, new_mean, new_cov, c in zip(
            nodes, starts, ends, means, covs, seen, strict=True
        ):
            old = group_payload(node)
            trail = _NO_TRAIL
            if window > 0.0:
                kept = old.trail[old.trail[:, 0] > stamp - window]
                trail = np.concatenate([kept, [[stamp, c[0], c[1]]]])
            payload = GroupPayload(
                contours[a:b], old.labels, members[a:b], event=old.event, trail=trail
            )
            out.append((new_mean, new_cov, payload))
        return out

    def coast(self, node: TrackNode, stamp: float) -> tuple[FloatArray, FloatArray, Any]:
        """The prediction (an occluded group keeps its contour)."""
        mean, cov = node_prediction(node)
        old = group_payload(node)
        return mean, cov, GroupPayload(old.contour, old.labels, event=old.event, trail=old.trail)

    def initiate(
        self, measurements: GroupObservations, js: Sequence[int], stamp: float
    ) -> list[tuple[FloatArray, FloatArray, Any]]:
        """New groups from clusters ``js`` (eq. 16)."""
        if not len(js):
            return []
        return initial_states(measurements, js, self.s.c0, stamp if self.s.trail_window else None)


def _row_block_min(q: FloatArray, starts: IntArray, lengths: IntArray) -> FloatArray:
    """``np.minimum.reduceat(q, starts, axis=0)`` (B, K) of ``q`` (N, K) cut into the
    consecutive, non-empty row blocks ``starts[b] .. starts[b] + lengths[b] - 1`` that
    cover it: one ``min`` per block, several times faster than ``reduceat`` along the
    rows (the minimum is exact, so the same numbers)."""
    least = np.minimum.reduce
    if starts.size == 1:
        return least(q, axis=0, keepdims=True)
    ends = (starts + lengths).tolist()
    return np.stack([least(q[a:b], axis=0) for a, b in zip(starts.tolist(), ends, strict=True)])


def _ranges(starts: IntArray, lengths: IntArray) -> IntArray:
    """The concatenated ranges ``starts[i] .. starts[i] + lengths[i] - 1`` (sum of lengths,)."""
    total = int(lengths.sum())
    shift = starts - (np.cumsum(lengths) - lengths)
    return np.asarray(np.repeat(shift, lengths) + np.arange(total), dtype=np.int64)


def node_prediction(node: TrackNode) -> tuple[FloatArray, FloatArray]:
    """Predicted mean (5,) and covariance (5, 5) of a group track node."""
    if node.pred_mean is None or node.pred_cov is None:
        raise RuntimeError(f"group track node {node.node_id} was not predicted before use")
    return node.pred_mean, node.pred_cov


def group_payload(node: TrackNode) -> GroupPayload:
    """The group payload (contour, labels, members) a track node carries."""
    payload = node.payload
    if not isinstance(payload, GroupPayload):
        raise TypeError(f"track node {node.node_id} carries no GroupPayload")
    return payload


def with_payload(payload: GroupPayload, **changes: Any) -> GroupPayload:
    """A copy of ``payload`` with fields changed."""
    return replace(payload, **changes)
