"""Cluster Sorting (002 Sec. 2) through the code the tracker runs, against computations
written out in the test: the merge rule (one shared measurement), the Mahalanobis gate
with a correlated covariance, the KFA update with the mean of the selected measurements,
and the fragment rule (an extension) against 002's memory of everyone who merged."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import chi2

from laserpeople.frame import Frame
from laserpeople.scan import PointSet
from laserpeople.tracking.csa import ClusterSortingTracker, CSAParams, gate_components, viterbi_step


def _frame(k: int, t: float, xy: np.ndarray) -> Frame:
    ps = PointSet(t, xy, np.zeros(len(xy), dtype=np.int64), np.arange(len(xy)))
    return Frame(k, t, (), "synthetic", "world", None, ps, np.ones(len(xy), dtype=bool))


def test_gate_is_the_chi_square_quantile() -> None:
    for p in (0.9, 0.99):
        assert CSAParams(gate_probability=p).gate == pytest.approx(chi2.ppf(p, 2), rel=1e-12)


def test_objects_sharing_one_measurement_merge() -> None:
    gates = np.zeros((4, 6), dtype=bool)
    gates[0, [0, 1]] = True
    gates[1, [1, 2, 3]] = True  # shares measurement 1 (only) with object 0
    gates[2, [4]] = True
    gates[3, [5]] = True
    assert gate_components(gates) == [[0, 1], [2], [3]]
    gates[3, 4] = True  # object 3 now shares measurement 4 with object 2
    assert gate_components(gates) == [[0, 1], [2, 3]]
    assert gate_components(np.zeros((0, 3), dtype=bool)) == []


def test_viterbi_gate_with_a_correlated_covariance() -> None:
    """One estimate at the origin with position covariance [[0.5, 0.45], [0.45, 0.5]]
    (R = 0.01 I): a measurement along the correlation is inside the gate, the same
    distance across it is outside (d^2 = v^T S^-1 v by hand)."""
    cov = np.zeros((1, 4, 4))
    cov[0, :2, :2] = [[0.5, 0.45], [0.45, 0.5]]
    cov[0, 2:, 2:] = np.eye(2)
    s = cov[0, :2, :2] + 0.01 * np.eye(2)
    along, across = np.array([0.9, 0.9]), np.array([0.9, -0.9])
    d_along = float(along @ np.linalg.solve(s, along))
    d_across = float(across @ np.linalg.solve(s, across))
    gate = 9.21
    assert d_along < gate < d_across
    step = viterbi_step(
        np.zeros((1, 4)), cov, np.zeros(1), np.array([along, across]), 0.01, gate, 10.0
    )
    assert step.selected.tolist() == [True, False]


def test_kfa_updates_with_the_mean_of_the_selected_measurements() -> None:
    """002's KFA: a single target's filter is updated with the unweighted mean of the points
    in its gate (constant velocity, white acceleration of PSD q: Q = q [[dt^3/3, dt^2/2],
    [dt^2/2, dt]] per axis)."""
    p = CSAParams()
    csa = ClusterSortingTracker(p)
    first = np.array([[0.0, 0.0], [0.1, 0.05], [0.2, 0.0], [0.15, -0.1]])
    csa.update(_frame(0, 0.0, first))
    (person,) = csa.update(_frame(0, 0.0, first)).of_kind("person")  # seen twice at dt 0
    second = first + np.array([0.05, 0.02])
    second[0] += [0.1, -0.08]  # the first point is not the mean
    tracks = csa.update(_frame(1, 0.1, second))
    (moved,) = tracks.of_kind("person")
    # the reference: the filter after the first two frames, predicted 0.1 s, updated
    x0 = np.r_[first.mean(axis=0), 0.0, 0.0]
    v = p.init_velocity_std**2
    c = np.diag([p.mean_std**2, p.mean_std**2, v, v])
    r = np.eye(2) * p.mean_std**2
    h = np.eye(2, 4)

    def update(x: np.ndarray, c: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        k = c @ h.T @ np.linalg.inv(h @ c @ h.T + r)
        return x + k @ (z - h @ x), c - k @ h @ c

    x, c = update(x0, c, first.mean(axis=0))  # dt = 0: no prediction
    dt, q = 0.1, p.person_accel_psd
    f = np.eye(4)
    f[0, 2] = f[1, 3] = dt
    qq = np.zeros((4, 4))
    for i in (0, 1):
        qq[i, i], qq[i, i + 2] = q * dt**3 / 3, q * dt**2 / 2
        qq[i + 2, i], qq[i + 2, i + 2] = q * dt**2 / 2, q * dt
    x, c = update(f @ x, f @ c @ f.T + qq, second.mean(axis=0))
    np.testing.assert_allclose(person.position, first.mean(axis=0), atol=1e-9)
    np.testing.assert_allclose(moved.position, x[:2], atol=1e-9)
    np.testing.assert_allclose(moved.velocity, x[2:], atol=1e-9)


def _legs(centre: tuple[float, float]) -> np.ndarray:
    ang = np.linspace(0, np.pi, 5)
    return np.concatenate(
        [
            np.c_[centre[0] + dx + 0.05 * np.cos(ang), centre[1] - 0.05 * np.sin(ang)]
            for dx in (-0.1, 0.1)
        ]
    )


def _fragment_run(params: CSAParams) -> ClusterSortingTracker:
    """Two people walk together into one cluster; then a blob of points appears beside the
    cluster (a target is started there, next to it) and moves into it."""
    csa = ClusterSortingTracker(params)
    for k, t in enumerate(np.arange(0.0, 4.5, 0.1)):
        x = min(-2.5 + 1.5 * t, -0.2)
        pts = [_legs((x, 0.0)), _legs((-x, 0.0))]
        if t >= 3.0:  # the third blob, 1.6 m beside, walking into the cluster
            pts.append(_legs((max(1.8 - 1.5 * (t - 3.0), 0.2), 0.3)))
        csa.update(_frame(k, float(t), np.concatenate(pts)))
    return csa


def test_fragment_rule_and_002s_memory_of_everyone_who_merged() -> None:
    faithful = _fragment_run(CSAParams(fragment_rule=False))
    fragments = _fragment_run(CSAParams(fragment_rule=True))
    merges = [e for e in faithful.events if e.kind == "merge person+cluster"]
    assert merges, [e.kind for e in faithful.events]
    # 002: the cluster remembers the target that merged into it
    assert max(len(m) for m in faithful.clusters.values()) == 3
    # the fragment rule: a target started beside the cluster is a fragment of its people
    assert max(len(m) for m in fragments.clusters.values()) == 2
    assert not math.isnan(merges[0].stamp)


def test_paper_preset_reports_a_new_target_at_once() -> None:
    """002 reports every target from its first scan: ``--preset paper`` sets
    ``confirm_scans`` back to 1 (the default 2 waits for a second scan with points)."""
    from laserpeople.config import load_config

    assert load_config(CSAParams, None, "paper").confirm_scans == 1
    assert CSAParams().confirm_scans == 2
