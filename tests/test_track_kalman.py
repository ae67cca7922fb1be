"""Constant-velocity Kalman filter and gating against textbook formulas: the numpy code,
the reference (``tests/test_track_kalman_compiled.py`` compares the C extension with it)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import chi2, multivariate_normal

from laserpeople.errors import ConfigError
from laserpeople.tracking import kalman
from laserpeople.tracking.kalman import KalmanParams

PATH_RTOL = 1e-12
"""Relative tolerance between two code paths of the same formula (plain floats against
numpy's arrays, one state against a batch). The paths add the same few products in another
order, and numpy's SIMD loops and OpenBLAS' kernels (which fuse multiply and add) differ
from CPU to CPU: a few units in the last place (1e-16 relative) of the largest term, 1e-13
at most after a covariance's cancellations. A wrong term (a dropped dt^2 / 2, a transposed
F) changes the values by 1e-3 or more."""


@pytest.fixture(autouse=True)
def numpy_reference(monkeypatch: pytest.MonkeyPatch) -> None:
    """The numpy code runs, whether the extension is built or not."""
    monkeypatch.setattr(kalman, "_extension", None)


def assert_paths_agree(got: np.ndarray, want: np.ndarray) -> None:
    """Same shape, dtype and non-finite entries; finite entries within :data:`PATH_RTOL` of
    the largest magnitude in ``want``."""
    assert got.shape == want.shape and got.dtype == want.dtype
    finite = np.isfinite(want)
    np.testing.assert_array_equal(np.isfinite(got), finite)
    np.testing.assert_array_equal(got[~finite], want[~finite])  # same inf, nan
    scale = float(np.max(np.abs(want[finite]), initial=1.0))
    np.testing.assert_allclose(got[finite], want[finite], rtol=PATH_RTOL, atol=PATH_RTOL * scale)


def test_predict_matches_textbook() -> None:
    dt, q = 0.1, 2.0
    mean = np.array([1.0, 2.0, 0.5, -0.3])
    cov = np.diag([0.01, 0.02, 0.3, 0.4])
    f = np.array([[1, 0, dt, 0], [0, 1, 0, dt], [0, 0, 1, 0], [0, 0, 0, 1]], float)
    # white-noise acceleration, continuous: Q = q * [[dt^3/3, dt^2/2], [dt^2/2, dt]] per axis
    qm = q * np.array(
        [
            [dt**3 / 3, 0, dt**2 / 2, 0],
            [0, dt**3 / 3, 0, dt**2 / 2],
            [dt**2 / 2, 0, dt, 0],
            [0, dt**2 / 2, 0, dt],
        ]
    )
    pm, pc = kalman.predict(mean[None], cov[None], np.array([dt]), q)
    np.testing.assert_allclose(pm[0], f @ mean)
    np.testing.assert_allclose(pc[0], f @ cov @ f.T + qm)


def test_update_matches_textbook_and_batch() -> None:
    rng = np.random.default_rng(0)
    a = rng.normal(size=(4, 4))
    cov = a @ a.T + np.eye(4)
    mean = rng.normal(size=4)
    z = rng.normal(size=2)
    r = np.array([[0.02, 0.005], [0.005, 0.03]])
    h = kalman.H
    s = h @ cov @ h.T + r
    k = cov @ h.T @ np.linalg.inv(s)
    want_mean = mean + k @ (z - h @ mean)
    want_cov = (np.eye(4) - k @ h) @ cov
    got_mean, got_cov = kalman.update(mean, cov, z, r)
    np.testing.assert_allclose(got_mean, want_mean, atol=1e-12)
    np.testing.assert_allclose(got_cov, want_cov, atol=1e-10)
    bm, bc = kalman.update_batch(mean[None], cov[None], z[None], r[None])
    np.testing.assert_allclose(bm[0], got_mean, atol=1e-12)
    np.testing.assert_allclose(bc[0], got_cov, atol=1e-12)


def test_mahalanobis_and_loglik_against_scipy() -> None:
    rng = np.random.default_rng(1)
    means = rng.normal(size=(3, 4))
    covs = np.stack([np.diag(rng.uniform(0.01, 0.2, 4)) for _ in range(3)])
    z = rng.normal(size=(5, 2))
    r = np.stack([np.eye(2) * rng.uniform(0.001, 0.01) for _ in range(5)])
    d2, ll = kalman.mahalanobis_and_loglik(means, covs, z, r)
    for t in range(3):
        for m in range(5):
            s = covs[t, :2, :2] + r[m]
            v = z[m] - means[t, :2]
            assert d2[t, m] == pytest.approx(v @ np.linalg.solve(s, v))
            assert ll[t, m] == pytest.approx(multivariate_normal(means[t, :2], s).logpdf(z[m]))


def test_gate_is_chi_square_quantile() -> None:
    assert KalmanParams(gate_probability=0.99).gate == pytest.approx(chi2.ppf(0.99, 2))
    assert KalmanParams(gate_probability=0.99).gate == pytest.approx(9.2103, abs=1e-3)
    # 2 degrees of freedom: the quantile is -2 ln(1 - p)
    assert KalmanParams().gate == pytest.approx(-2 * np.log(1 - 0.999))


def test_chi2_quantile_2dof_closed_form() -> None:
    """The closed form against hand-computed quantiles and near misses: 0.95 -> 5.9915
    (1 dof would give 3.8415, -ln(1 - p) 2.9957, 3 dof 7.8147), and scipy's own to 1e-12."""
    assert kalman.chi2_quantile_2dof(0.95) == pytest.approx(5.991465, abs=1e-6)
    assert kalman.chi2_quantile_2dof(0.99) == pytest.approx(9.210340, abs=1e-6)
    assert kalman.chi2_quantile_2dof(0.0) == 0.0
    for p in (1e-9, 0.1, 0.5, 0.9, 0.999, 1 - 1e-12):
        assert kalman.chi2_quantile_2dof(p) == pytest.approx(chi2.ppf(p, 2), rel=1e-12)
    for bad in (-0.1, 1.0, 1.5):
        with pytest.raises(ValueError, match="gate probability"):
            kalman.chi2_quantile_2dof(bad)


def test_initiate_and_covariance_floor() -> None:
    mean, cov = kalman.initiate(np.array([1.0, 2.0]), np.eye(2) * 0.01, 0.5)
    np.testing.assert_allclose(mean, [1, 2, 0, 0])
    np.testing.assert_allclose(np.diag(cov), [0.01, 0.01, 0.25, 0.25])
    raw = np.stack([np.zeros((2, 2)), np.eye(2) * 0.04])
    out = kalman.measurement_covariances(raw, 0.05)
    np.testing.assert_allclose(out[0], np.eye(2) * 0.0025)
    np.testing.assert_allclose(out[1], np.eye(2) * 0.04)


def test_bad_params_are_config_errors(tmp_path) -> None:  # type: ignore[no-untyped-def]
    from laserpeople.config import load_config

    with pytest.raises(ValueError):
        KalmanParams(gate_probability=1.5)
    path = tmp_path / "c.toml"
    path.write_text("[kalman]\naccel_psd = -1.0\n")
    with pytest.raises(ConfigError):
        load_config(KalmanParams, path)


def test_coast_decays_velocity_hand_computed() -> None:
    dt, tau, q = 0.2, 0.2, 2.0
    mean = np.array([1.0, 2.0, 1.0, -0.5])
    cov = np.diag([0.01, 0.02, 0.3, 0.4])
    a = np.exp(-1.0)  # exp(-dt / tau)
    g = tau * (1.0 - a)  # 0.126424...
    pm, pc = kalman.coast(mean[None], cov[None], np.array([dt]), q, tau)
    np.testing.assert_allclose(pm[0], [1.0 + g, 2.0 - 0.5 * g, a, -0.5 * a])
    np.testing.assert_allclose(g, 0.12642411176571153)
    f = np.array([[1, 0, g, 0], [0, 1, 0, g], [0, 0, a, 0], [0, 0, 0, a]], float)
    qm = kalman.process_noise(np.array([dt]), q)[0]
    np.testing.assert_allclose(pc[0], f @ cov @ f.T + qm)


def test_coast_with_infinite_tau_is_constant_velocity() -> None:
    mean = np.array([[1.0, 2.0, 0.5, -0.3]])
    cov = np.diag([0.01, 0.02, 0.3, 0.4])[None]
    dt = np.array([0.1])
    for got, want in zip(
        kalman.coast(mean, cov, dt, 2.0, np.inf), kalman.predict(mean, cov, dt, 2.0), strict=True
    ):
        assert_paths_agree(got, want)


def test_coast_travels_at_most_tau_times_speed() -> None:
    mean = np.array([[0.0, 0.0, 1.5, 0.0]])
    cov = np.eye(4)[None] * 0.01
    tau = 0.3
    for _ in range(100):  # 10 s of 0.1 s steps; constant velocity would travel 15 m
        mean, cov = kalman.coast(mean, cov, np.array([0.1]), 2.0, tau)
    np.testing.assert_allclose(mean[0], [1.5 * tau, 0.0, 0.0, 0.0], atol=1e-9)
    assert np.all(np.isfinite(cov))


def test_initiate_batch_equals_initiate_one_by_one() -> None:
    from laserpeople.tracking.kalman import initiate, initiate_batch

    rng = np.random.default_rng(5)
    z = rng.normal(size=(4, 2))
    a = rng.normal(size=(4, 2, 2))
    r = a @ a.transpose(0, 2, 1) + 0.01 * np.eye(2)
    means, covs = initiate_batch(z, r, 0.7)
    for i in range(4):
        m, c = initiate(z[i], r[i], 0.7)
        assert_paths_agree(means[i], m)
        assert_paths_agree(covs[i], c)
    empty_m, empty_c = initiate_batch(np.empty((0, 2)), np.empty((0, 2, 2)), 0.7)
    assert empty_m.shape == (0, 4) and empty_c.shape == (0, 4, 4)


def _predict_all(
    cases: list[tuple[np.ndarray, np.ndarray, np.ndarray, float, float]],
) -> list[tuple[np.ndarray, ...]]:
    """:func:`kalman.predict` and :func:`kalman.predict_and_coast` of each case (means,
    covariances, steps, acceleration PSD, tau), in turn."""
    out = []
    for means, covs, dt, q, tau in cases:
        out.append(kalman.predict(means, covs, dt, q))
        out.append(kalman.predict_and_coast(means, covs, dt, q, tau))
    return out


@pytest.mark.regression
def test_few_tracks_predict_and_coast_are_the_array_path(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Up to ``SMALL_BATCH`` tracks, :func:`kalman.predict` and
    :func:`kalman.predict_and_coast` build their matrices from plain floats: the same
    means and covariances as the array path, within :data:`PATH_RTOL` (random states, steps of 0 s,
    scan periods with jitter and long gaps, finite and infinite ``tau``)."""
    rng = np.random.default_rng(11)
    cases = []
    for _ in range(400):
        t = int(rng.integers(1, kalman.SMALL_BATCH + 1))
        means = rng.normal(scale=[5.0, 5.0, 1.0, 1.0], size=(t, 4))
        a = rng.normal(size=(t, 4, 4))
        covs = a @ a.transpose(0, 2, 1) + 0.01 * np.eye(4)
        dt = rng.choice([0.0, 1.0 / 37.5, 0.1, 0.7, 2.0], size=t) + rng.normal(scale=1e-4, size=t)
        dt = np.clip(dt, 0.0, None)
        tau = float(rng.choice([0.8, np.inf]))
        cases.append((means, covs, dt, float(rng.uniform(0.1, 3.0)), tau))

    def run() -> list[tuple[np.ndarray, ...]]:
        return _predict_all(cases)

    few = run()
    monkeypatch.setattr(kalman, "SMALL_BATCH", 0)
    arrays = run()
    for got, want in zip(few, arrays, strict=True):
        assert len(got) == len(want)
        for g, w in zip(got, want, strict=True):
            assert_paths_agree(g, w)


@pytest.mark.regression
def test_one_step_predict_and_coast_is_the_per_track_path(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Tracks that share one step (a scan's usual case) are predicted and coasted with one
    transition matrix and one process noise broadcast: the same means and covariances as
    per-track matrices, within :data:`PATH_RTOL` (1 to 40 tracks, steps of 0 s, a scan
    period, long gaps; finite and infinite ``tau``)."""
    rng = np.random.default_rng(13)
    cases = []
    for _ in range(300):
        t = int(rng.integers(1, 41))
        means = rng.normal(scale=[5.0, 5.0, 1.0, 1.0], size=(t, 4))
        a = rng.normal(size=(t, 4, 4))
        covs = a @ a.transpose(0, 2, 1) + 0.01 * np.eye(4)
        d = float(rng.choice([0.0, 1.0 / 37.5, 0.1, 0.7, 2.0]) + abs(rng.normal(scale=1e-4)))
        tau = float(rng.choice([0.8, np.inf]))
        cases.append((means, covs, np.full(t, d), float(rng.uniform(0.1, 3.0)), tau))

    def run() -> list[tuple[np.ndarray, ...]]:
        return _predict_all(cases)

    # a step that differs for one track takes the per-track path
    assert kalman._one_step(np.array([0.1, 0.1, 0.2])) is None
    assert kalman._one_step(np.array([0.1, 0.1])) == 0.1
    one = run()
    monkeypatch.setattr(kalman, "_one_step", lambda dt: None)
    monkeypatch.setattr(kalman, "SMALL_BATCH", 0)
    per_track = run()
    for got, want in zip(one, per_track, strict=True):
        assert len(got) == len(want)
        for g, w in zip(got, want, strict=True):
            assert_paths_agree(g, w)


def test_one_step_matrices_are_kept_per_step_and_model() -> None:
    """The one-step path keeps its matrices per (step, process noise, coasting time): a
    second scan with the same step gives what a fresh build gives (to 1e-12), a scan with
    another step, noise or ``tau`` its own (a kept matrix of another model would move the
    prediction by its dt or q), the kept matrices are read-only, and no more than
    ``STEP_MATRICES_KEPT`` are kept."""
    rng = np.random.default_rng(17)
    means = rng.normal(scale=[5.0, 5.0, 1.0, 1.0], size=(7, 4))
    a = rng.normal(size=(7, 4, 4))
    covs = a @ a.transpose(0, 2, 1) + 0.01 * np.eye(4)
    kalman._STEP_MATRICES.clear()
    first = kalman.predict_and_coast(means, covs, np.full(7, 0.025), 32.0, 0.8)
    assert len(kalman._STEP_MATRICES) == 1
    again = kalman.predict_and_coast(means, covs, np.full(7, 0.025), 32.0, 0.8)
    for g, w in zip(again, first, strict=True):  # (the same operations: 1e-12 for any CPU)
        np.testing.assert_allclose(g, w, rtol=1e-12, atol=1e-12)
    # the same step of another model: its own matrices (legs and people share a run)
    other_q = kalman.predict_and_coast(means, covs, np.full(7, 0.025), 8.0, 0.8)
    other_tau = kalman.predict_and_coast(means, covs, np.full(7, 0.025), 32.0, np.inf)
    other_dt = kalman.predict_and_coast(means, covs, np.full(7, 0.05), 32.0, 0.8)
    assert len(kalman._STEP_MATRICES) == 4
    kalman._STEP_MATRICES.clear()
    for got, (dt, q, tau) in (
        (other_q, (0.025, 8.0, 0.8)),
        (other_tau, (0.025, 32.0, np.inf)),
        (other_dt, (0.05, 32.0, 0.8)),
    ):
        fresh = kalman.predict_and_coast(means, covs, np.full(7, dt), q, tau)
        kalman._STEP_MATRICES.clear()
        for g, w in zip(got, fresh, strict=True):
            np.testing.assert_allclose(g, w, rtol=1e-12, atol=1e-12)
    assert not np.allclose(other_dt[1], first[1])
    # a coasting time of inf: the predicted states are the coasted ones
    assert other_tau[0] is other_tau[2]
    kalman.predict_and_coast(means, covs, np.full(7, 0.025), 32.0, 0.8)
    (mats,) = kalman._STEP_MATRICES.values()
    for m in mats:
        assert m is not None and not m.flags.writeable
    # a new step each scan: kept until STEP_MATRICES_KEPT are held, then all forgotten
    # and counted again from the new one (1, 2, ..., KEPT, 1, 2, ...)
    kalman._STEP_MATRICES.clear()
    held = []
    for i in range(3 * kalman.STEP_MATRICES_KEPT):
        kalman.predict(means, covs, np.full(7, 0.01 * (i + 1)), 32.0)
        held.append(len(kalman._STEP_MATRICES))
    assert held == [i % kalman.STEP_MATRICES_KEPT + 1 for i in range(len(held))]


@pytest.mark.regression
def test_few_states_update_batch_is_the_array_path(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Up to ``SMALL_UPDATE`` states, :func:`kalman.update_batch` forms the inverse
    innovation covariances and ``I - K H`` in plain floats: the same means and covariances
    as the array path, within :data:`PATH_RTOL` (random states, measurements and covariances)."""
    rng = np.random.default_rng(12)
    cases = []
    for _ in range(400):
        k = int(rng.integers(1, kalman.SMALL_UPDATE + 1))
        means = rng.normal(scale=[5.0, 5.0, 1.0, 1.0], size=(k, 4))
        a = rng.normal(size=(k, 4, 4))
        covs = a @ a.transpose(0, 2, 1) + 0.01 * np.eye(4)
        b = rng.normal(scale=0.1, size=(k, 2, 2))
        meas_covs = b @ b.transpose(0, 2, 1) + 1e-3 * np.eye(2)
        z = means[:, :2] + rng.normal(scale=0.3, size=(k, 2))
        cases.append((means, covs, z, meas_covs))
    few = [kalman.update_batch(*c) for c in cases]
    monkeypatch.setattr(kalman, "SMALL_UPDATE", 0)
    arrays = [kalman.update_batch(*c) for c in cases]
    for got, want in zip(few, arrays, strict=True):
        for g, w in zip(got, want, strict=True):
            assert_paths_agree(g, w)


@pytest.mark.regression
def test_measurement_covariances_of_few_detections_are_the_array_path(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The plain-float test of a few detector covariances replaces the same ones (zero,
    negative, singular, non-finite) as the array path."""
    rng = np.random.default_rng(13)
    bad = [np.zeros((2, 2)), -np.eye(2), np.ones((2, 2)), np.array([[1.0, np.nan], [0.0, 1.0]])]
    bad += [np.array([[np.inf, 0.0], [0.0, 1.0]]), np.array([[1.0, 0.0], [np.nan, 1.0]])]
    cases = []
    for _ in range(300):
        m = int(rng.integers(0, kalman.SMALL_BATCH + 1))
        a = rng.normal(scale=0.05, size=(m, 2, 2))
        raw = a @ a.transpose(0, 2, 1)
        for i in range(m):
            if rng.random() < 0.3:
                raw[i] = bad[int(rng.integers(len(bad)))]
        cases.append(raw)
    few = [kalman.measurement_covariances(r, 0.03) for r in cases]
    monkeypatch.setattr(kalman, "SMALL_BATCH", -1)
    arrays = [kalman.measurement_covariances(r, 0.03) for r in cases]
    for got, want in zip(few, arrays, strict=True):
        assert_paths_agree(got, want)


@pytest.mark.regression
def test_few_pairs_mahalanobis_and_loglik_are_the_array_path(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Up to ``SMALL_PAIRS`` (track, measurement) pairs the squared Mahalanobis distances
    and log-likelihoods are formed in plain floats: the array path's values within
    :data:`PATH_RTOL`."""
    rng = np.random.default_rng(14)
    cases = []
    for _ in range(400):
        t = int(rng.integers(1, 5))
        m = int(rng.integers(1, kalman.SMALL_PAIRS // t + 1))
        means = rng.normal(scale=[5.0, 5.0, 1.0, 1.0], size=(t, 4))
        a = rng.normal(size=(t, 4, 4))
        covs = a @ a.transpose(0, 2, 1) + 0.01 * np.eye(4)
        b = rng.normal(scale=0.1, size=(m, 2, 2))
        meas_covs = b @ b.transpose(0, 2, 1) + 1e-3 * np.eye(2)
        z = rng.normal(scale=5.0, size=(m, 2))
        cases.append((means, covs, z, meas_covs))
    few = [kalman.mahalanobis_and_loglik(*c) for c in cases]
    monkeypatch.setattr(kalman, "SMALL_PAIRS", 0)
    arrays = [kalman.mahalanobis_and_loglik(*c) for c in cases]
    for got, want in zip(few, arrays, strict=True):
        for g, w in zip(got, want, strict=True):
            assert_paths_agree(g, w)
