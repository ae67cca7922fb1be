"""Constant-velocity Kalman filter on (x, y, vx, vy) with position measurements (000 Sec. 3.1).

State x = (x, y, vx, vy) [m, m, m/s, m/s]; measurement z = (x, y) [m], so H = [I 0].
The process noise is the continuous white-noise acceleration model (Bar-Shalom & Li):
acceleration power spectral density ``q`` [m^2/s^3] per axis, integrated over the step
``dt`` [s], so that tracks stay consistent at any scan rate. All functions work on stacks of
tracks: means (T, 4), covariances (T, 4, 4), with one ``dt`` per track.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.extensions import load_extension

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

SOURCE = Path(__file__).with_name("_ckalman.c")
"""The C extension's source, beside this module (in an installed package as well)."""

_extension, IMPLEMENTATION = load_extension(
    "laserpeople.tracking._ckalman", SOURCE, "Kalman steps of the track nodes"
)
"""The optional C extension of the Kalman steps of many tracks at once (None: their numpy
code, the reference, runs), and which runs: ``"compiled (C extension)"`` or ``"pure Python
(...)"`` with the reason. :func:`predict`, :func:`coast`, :func:`predict_and_coast`,
:func:`predict_rows`, :func:`mahalanobis_and_loglik`, :func:`gate_and_loglik`,
:func:`update_batch` and :func:`update_rows` use it: the same floats as numpy's (its
products are OpenBLAS's fused sums in order; numpy's ``pow``, ``exp`` and ``log`` are
passed in or taken after)."""

H = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]])
"""Measurement matrix: positions are observed directly (000 Sec. 3.1)."""

LOG_2PI = float(np.log(2.0 * np.pi))


def chi2_quantile_2dof(p: float) -> float:
    """The ``p`` quantile of the chi-square distribution with 2 degrees of freedom: the
    squared Mahalanobis distance of a 2-D Gaussian's gate holding probability ``p``.

    With 2 dof the CDF is ``1 - exp(-x / 2)``, so the quantile is ``-2 ln(1 - p)`` in closed
    form (no ``scipy.stats``, whose import costs a start-up of half a second).

    Example:
        >>> round(chi2_quantile_2dof(0.99), 4)
        9.2103
    """
    if not 0.0 <= p < 1.0:
        raise ValueError(f"a gate probability must be in [0, 1), got {p}")
    return -2.0 * math.log1p(-p)


@dataclass(frozen=True)
class KalmanParams:
    """Motion and measurement model of one tracked point (a leg, a person)."""

    config_section = "kalman"

    accel_psd: float = param(
        32.0,
        "assumption (000 gives no value): a swinging leg gains ~1.5 m/s in ~0.1 s; chosen "
        "from 8/16/24/32/48/64 on the simulated 000 Sec. 3.4 scenes, seeds 0-2",
        "process noise: white-acceleration power spectral density per axis",
        "m^2/s^3",
    )
    init_velocity_std: float = param(
        1.0,
        "assumption; 000 Sec. 4.6 uses 0.5 m/s for groups, legs move faster",
        "standard deviation of the unobserved initial velocity (initialised as 0)",
        "m/s",
    )
    measurement_std: float = param(
        0.05,
        "assumption: leg centre from a few beams of a 0.5 deg scanner",
        "position noise used when a detection has no positive-definite covariance",
        "m",
    )
    gate_probability: float = param(
        0.999,
        "assumption; 0.999 kept more leg tracks than 0.99 on the simulated 000 Sec. 3.4 scenes",
        "probability mass of the Mahalanobis gate; chi-square with 2 degrees of freedom",
    )
    max_gate_distance: float = param(
        1.0,
        "assumption: a leg moves at most ~1 m between two detections (bounds the gate of "
        "long-occluded tracks, whose covariance grows without limit)",
        "Euclidean cap on the gate around a predicted position",
        "m",
    )
    coast_velocity_time: float = param(
        0.35,
        "departure from 000 Sec. 3.1 (inf: constant velocity; the leg tracker's --preset "
        "paper), an assumption: a leg's velocity does not persist while it is unseen "
        "(a foot in stance stands still; a real walker turns). From 0.1/0.15/0.2/0.25/0.35/"
        "0.5/0.7/1/2/inf (inf = 000's constant velocity) on the demo seeds 0-4: person MOTA "
        "0.67 (inf) -> 0.78-0.79 over 0.1-0.35; 0.35 best on the narrow-corridor scene",
        "tau: while a track is occluded its velocity decays as exp(-dt / tau), so it "
        "coasts at most tau * speed past where it was last seen (inf: no decay)",
        "s",
    )
    max_dt: float = param(
        1.0,
        "assumption",
        "longest prediction step; a longer gap between scans is clipped to this",
        "s",
    )

    def __post_init__(self) -> None:
        if not 0 < self.accel_psd < math.inf:
            raise ValueError("accel_psd must be positive and finite")
        if not (0 < self.init_velocity_std < math.inf and 0 < self.measurement_std < math.inf):
            raise ValueError("init_velocity_std and measurement_std must be positive and finite")
        if not 0.0 < self.gate_probability < 1.0:
            raise ValueError("gate_probability must be in (0, 1)")
        if not (
            self.init_velocity_std > 0
            and self.measurement_std > 0
            and self.max_dt > 0
            and self.max_gate_distance > 0
            and self.coast_velocity_time > 0
        ):
            raise ValueError(
                "init_velocity_std, measurement_std, max_dt, max_gate_distance and "
                "coast_velocity_time must be positive"
            )

    @property
    def gate(self) -> float:
        """Squared Mahalanobis distance of the gate (chi-square quantile, 2 dof)."""
        return chi2_quantile_2dof(self.gate_probability)


def transition(dt: FloatArray) -> FloatArray:
    """Constant-velocity transition matrices (T, 4, 4) for steps ``dt`` (T,) [s]."""
    dt = np.asarray(dt, dtype=np.float64).reshape(-1)
    f = np.zeros((dt.size, 16))
    f[:, ::5] = 1.0  # the diagonal
    f[:, 2] = dt  # (0, 2)
    f[:, 7] = dt  # (1, 3)
    return f.reshape(-1, 4, 4)


def process_noise(dt: FloatArray, accel_psd: float) -> FloatArray:
    """White-acceleration process noise (T, 4, 4) for steps ``dt`` (T,) [s]."""
    dt = np.asarray(dt, dtype=np.float64).reshape(-1)
    q = np.zeros((dt.size, 16))
    pp = accel_psd * dt**3 / 3.0
    pv = accel_psd * dt**2 / 2.0
    vv = accel_psd * dt
    q[:, 0] = q[:, 5] = pp  # (0, 0), (1, 1)
    q[:, 2] = q[:, 7] = q[:, 8] = q[:, 13] = pv  # (0, 2), (1, 3) and their mirrors
    q[:, 10] = q[:, 15] = vv  # (2, 2), (3, 3)
    return q.reshape(-1, 4, 4)


SMALL_BATCH = 6
"""Up to this many tracks :func:`predict` and :func:`predict_and_coast` build their
transition and noise matrices from plain floats (:func:`_few_predict_and_coast`: the
same arrays bit for bit, with about half the numpy calls; the leg MHT of a sparse scene
predicts one node in most scans). Measured ``predict_and_coast``: 24 / 27 / 33 / 38 us
against 45 / 46 / 49 / 53 us for 1 / 2 / 4 / 6 tracks, even at 8."""


SMALL_PAIRS = 12
"""Up to this many (track, measurement) pairs :func:`mahalanobis_and_loglik` works in
plain floats (:func:`_few_mahalanobis_and_loglik`, the same values bit for bit).
Measured: 9 / 12 / 14 / 19 us against 15 / 22 / 22 / 26 us for 1 / 4 / 9 / 16 pairs, even
at 24."""

SMALL_UPDATE = 3
"""Up to this many states :func:`update_batch` forms ``S^-1`` and ``I - K H`` from plain
floats (:func:`_few_update`, the same arrays bit for bit). Measured: 26 / 30 / 44 us
against 37 / 38 / 44 us for 1 / 2 / 4 states."""


def predict(
    means: FloatArray, covs: FloatArray, dt: FloatArray, accel_psd: float
) -> tuple[FloatArray, FloatArray]:
    """Predict means (T, 4) and covariances (T, 4, 4) over steps ``dt`` (T,) [s]."""
    dt = np.asarray(dt, dtype=np.float64).reshape(-1)
    means = np.asarray(means, dtype=np.float64).reshape(-1, 4)
    covs = np.asarray(covs, dtype=np.float64).reshape(-1, 4, 4)
    got = _compiled_arrays(means, covs, dt, accel_psd, math.inf)
    if got is not None:
        return got[0], got[1]
    step = _one_step(dt)
    if step is not None:
        pm, pc, _, _ = _one_step_predict_and_coast(means, covs, step, accel_psd, math.inf)
        return pm, pc
    if 0 < dt.size <= SMALL_BATCH:
        pm, pc, _, _ = _few_predict_and_coast(means, covs, dt, accel_psd, math.inf)
        return pm, pc
    return _predict(means, covs, dt, process_noise(dt, accel_psd))


def _one_step(dt: FloatArray) -> float | None:
    """The step [s] every track of ``dt`` (T,) shares, or None (no tracks, or steps that
    differ). Every live track was last updated at the previous scan in most scans."""
    steps = dt.tolist()
    if not steps:
        return None
    d = steps[0]
    return d if steps.count(d) == len(steps) else None


def _one_step_predict_and_coast(
    means: FloatArray, covs: FloatArray, d: float, accel_psd: float, tau: float
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """:func:`predict_and_coast` of tracks that share one step ``d`` [s]: one transition
    matrix and one process noise (4, 4) for all, built from plain floats by the array
    path's IEEE operations (as :func:`_few_predict_and_coast`), and the stacked
    covariances multiplied by them broadcast; the same means and covariances as the
    per-track matrices with a fraction of their construction and product cost."""
    key = (d, accel_psd, tau)
    mats = _STEP_MATRICES.get(key)
    if mats is None:
        mats = _step_matrices(d, accel_psd, tau)
        if len(_STEP_MATRICES) >= STEP_MATRICES_KEPT:
            _STEP_MATRICES.clear()
        _STEP_MATRICES[key] = mats
    f, ft, q, pair, pair_t = mats
    pm = means.copy()
    pm[:, :2] += means[:, 2:] * d
    if pair is None or pair_t is None:
        pc = f @ covs @ ft + q
        return pm, pc, pm, pc
    # (both covariance products in one set of calls: each matrix of a stacked product is
    # the same gemm on the same operands, so the same floats as two separate products)
    both = pair @ covs @ pair_t + q  # (2, T, 4, 4): predicted, coasted
    cm = np.einsum("ij,tj->ti", pair[1, 0], means)
    return pm, both[0], cm, both[1]


STEP_MATRICES_KEPT = 16
"""Most step matrices :func:`_one_step_predict_and_coast` keeps (by step, process noise
and coasting time; all are forgotten when full). A simulation or a laser with steady stamps
steps by one ``dt``, shared by every tracker of the run (legs, people), so their matrices
are built once; a recording whose stamps jitter builds them per scan (in one array)."""

_STEP_MATRICES: dict[
    tuple[float, float, float],
    tuple[FloatArray, FloatArray, FloatArray, FloatArray | None, FloatArray | None],
] = {}


def _step_matrices(
    d: float, accel_psd: float, tau: float
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray | None, FloatArray | None]:
    """The transition matrix (4, 4) of a step ``d`` [s], its transpose, the process noise
    (4, 4), and the transition and coasting transition matrices stacked (2, 1, 4, 4) and
    their transposes (None when ``tau`` is infinite), built from plain floats by the array
    path's IEEE operations (as :func:`_few_predict_and_coast`); read-only."""
    a = accel_psd
    pp, pv, vv = a * d**3 / 3.0, a * (d * d) / 2.0, a * d
    rows = [1.0, 0.0, d, 0.0, 0.0, 1.0, 0.0, d, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]
    if not math.isinf(tau):
        k = float(np.exp(np.array((-d / tau,)))[0])  # (numpy's exp, as the array path's)
        g = tau * (1.0 - k)
        rows += (1.0, 0.0, g, 0.0, 0.0, 1.0, 0.0, g, 0.0, 0.0, k, 0.0, 0.0, 0.0, 0.0, k)
    rows += (pp, 0.0, pv, 0.0, 0.0, pp, 0.0, pv, pv, 0.0, vv, 0.0, 0.0, pv, 0.0, vv)
    # (one array for the two or three matrices, transition, coasting, noise: a scan of a
    # recording whose stamps jitter builds them every time)
    mats = np.array(rows).reshape(-1, 4, 4)
    mats.setflags(write=False)
    f, q = mats[0], mats[-1]
    if mats.shape[0] == 2:
        return f, f.T, q, None, None
    pair = mats[:2, None]  # (a view: the transition and the coasting one, (2, 1, 4, 4))
    return f, f.T, q, pair, pair.transpose(0, 1, 3, 2)


def _few_predict_and_coast(
    means: FloatArray, covs: FloatArray, dt: FloatArray, accel_psd: float, tau: float
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """:func:`predict_and_coast` of a few tracks (``means`` (T, 4) and ``covs`` (T, 4, 4)
    float64, ``dt`` (T,)) with the process noise, the transition matrices and the predicted
    means formed in plain floats: each element by the same IEEE operations as the array
    functions (``dt**2`` as ``dt * dt``, numpy's square; ``dt**3`` by ``pow`` in both), the
    matrix products and ``exp`` left to numpy, so the results are the same bit for bit."""
    a = accel_psd
    q_rows: list[float] = []
    f_rows: list[float] = []
    m_rows: list[float] = []
    dts = dt.tolist()
    for d, (x, y, vx, vy) in zip(dts, means.tolist(), strict=True):
        pp, pv, vv = a * d**3 / 3.0, a * (d * d) / 2.0, a * d
        q_rows += (pp, 0.0, pv, 0.0, 0.0, pp, 0.0, pv, pv, 0.0, vv, 0.0, 0.0, pv, 0.0, vv)
        f_rows += (1.0, 0.0, d, 0.0, 0.0, 1.0, 0.0, d, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0)
        m_rows += (x + vx * d, y + vy * d, vx, vy)
    t = len(dts)
    q = np.array(q_rows).reshape(t, 4, 4)
    f = np.array(f_rows).reshape(t, 4, 4)
    pm = np.array(m_rows).reshape(t, 4)
    pc = f @ covs @ f.transpose(0, 2, 1) + q
    if math.isinf(tau):
        return pm, pc, pm, pc
    decay = np.exp(-dt / tau).tolist()
    c_rows: list[float] = []
    for k in decay:
        g = tau * (1.0 - k)
        c_rows += (1.0, 0.0, g, 0.0, 0.0, 1.0, 0.0, g, 0.0, 0.0, k, 0.0, 0.0, 0.0, 0.0, k)
    fc = np.array(c_rows).reshape(t, 4, 4)
    cm = np.einsum("tij,tj->ti", fc, means)
    cc = fc @ covs @ fc.transpose(0, 2, 1) + q
    return pm, pc, cm, cc


def _predict(
    means: FloatArray, covs: FloatArray, dt: FloatArray, q: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """:func:`predict` with the process noise ``q`` (T, 4, 4) given."""
    pred_means = means.copy()
    pred_means[:, :2] += means[:, 2:] * dt[:, None]
    f = transition(dt)
    pred_covs = f @ covs @ f.transpose(0, 2, 1) + q
    return pred_means, pred_covs


def coast(
    means: FloatArray, covs: FloatArray, dt: FloatArray, accel_psd: float, tau: float
) -> tuple[FloatArray, FloatArray]:
    """Predict occluded tracks over ``dt`` (T,) [s] with their velocity decaying with time
    constant ``tau`` [s] (an Ornstein-Uhlenbeck velocity mean): v' = a v, p' = p + tau (1 - a)
    v with a = exp(-dt / tau); covariance F P F^T + Q with that F and the white-acceleration
    Q. ``tau = inf`` is :func:`predict`."""
    if math.isinf(tau):
        return predict(means, covs, dt, accel_psd)
    dt = np.asarray(dt, dtype=np.float64).reshape(-1)
    means = np.asarray(means, dtype=np.float64).reshape(-1, 4)
    covs = np.asarray(covs, dtype=np.float64).reshape(-1, 4, 4)
    got = _compiled_arrays(means, covs, dt, accel_psd, tau)
    if got is not None:
        return got[2], got[3]
    return _coast(means, covs, dt, process_noise(dt, accel_psd), tau)


def _coast(
    means: FloatArray, covs: FloatArray, dt: FloatArray, q: FloatArray, tau: float
) -> tuple[FloatArray, FloatArray]:
    """:func:`coast` (finite ``tau``) with the process noise ``q`` (T, 4, 4) given."""
    a = np.exp(-dt / tau)
    gain = tau * (1.0 - a)
    f = transition(gain)
    f[:, 2, 2] = a
    f[:, 3, 3] = a
    pred_means = np.einsum("tij,tj->ti", f, means)
    pred_covs = f @ covs @ f.transpose(0, 2, 1) + q
    return pred_means, pred_covs


def predict_and_coast(
    means: FloatArray, covs: FloatArray, dt: FloatArray, accel_psd: float, tau: float
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """:func:`predict` and :func:`coast` of the same tracks at once (the process noise is
    computed once): predicted means (T, 4), covariances (T, 4, 4), then the coasted ones.
    Compiled where the extension is built (:func:`predict_rows`: the same floats)."""
    dt = np.asarray(dt, dtype=np.float64).reshape(-1)
    means = np.asarray(means, dtype=np.float64).reshape(-1, 4)
    covs = np.asarray(covs, dtype=np.float64).reshape(-1, 4, 4)
    got = _compiled_arrays(means, covs, dt, accel_psd, tau)
    if got is not None:
        return got
    step = _one_step(dt)
    if step is not None:
        return _one_step_predict_and_coast(means, covs, step, accel_psd, tau)
    if 0 < dt.size <= SMALL_BATCH:
        return _few_predict_and_coast(means, covs, dt, accel_psd, tau)
    q = process_noise(dt, accel_psd)
    pm, pc = _predict(means, covs, dt, q)
    if math.isinf(tau):
        return pm, pc, pm, pc
    cm, cc = _coast(means, covs, dt, q, tau)
    return pm, pc, cm, cc


def innovation_covariances(covs: FloatArray, meas_covs: FloatArray) -> FloatArray:
    """S (T, M, 2, 2) = H P_t H^T + R_m for every track t and measurement m."""
    hph = covs[:, :2, :2]
    return hph[:, None, :, :] + meas_covs[None, :, :, :]


def mahalanobis_and_loglik(
    means: FloatArray, covs: FloatArray, z: FloatArray, meas_covs: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Squared Mahalanobis distances and Gaussian log-likelihoods log N(z_m; H x_t, S_tm).

    Args:
        means: Predicted states (T, 4).
        covs: Predicted covariances (T, 4, 4).
        z: Measurements (M, 2) [m].
        meas_covs: Measurement covariances (M, 2, 2) [m^2].

    Returns:
        ``(d2, loglik)``, both (T, M); loglik is a density per m^2 in log space.

    Compiled where the extension is built (the same floats, the logarithm numpy's).
    """
    t, m = covs.shape[0], z.shape[0]
    if _extension is not None and t * m:
        d2, loglik, det = np.empty((3, t, m))
        _extension.score(
            *_contiguous(means, covs, z, meas_covs),
            0.0,
            0.0,
            LOG_2PI,
            None,
            loglik,
            det,
            d2,
        )
        return d2, _finish_loglik(loglik, det)
    if 0 < covs.shape[0] * z.shape[0] <= SMALL_PAIRS:
        return _few_mahalanobis_and_loglik(means, covs, z, meas_covs)
    s = innovation_covariances(covs, meas_covs)  # (T, M, 2, 2)
    a, b, d = s[..., 0, 0], s[..., 0, 1], s[..., 1, 1]
    det = a * d - b * b
    v = z[None, :, :] - means[:, None, :2]  # (T, M, 2)
    vx, vy = v[..., 0], v[..., 1]
    d2 = (d * vx * vx - 2.0 * b * vx * vy + a * vy * vy) / det
    loglik = -0.5 * d2 - LOG_2PI - 0.5 * np.log(det)
    return d2, loglik


def _few_mahalanobis_and_loglik(
    means: FloatArray, covs: FloatArray, z: FloatArray, meas_covs: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """:func:`mahalanobis_and_loglik` of a few (track, measurement) pairs in plain floats,
    each element by the array path's IEEE operations in its order (``log`` left to
    numpy): the same values bit for bit."""
    t, m = covs.shape[0], z.shape[0]
    hph = covs[:, :2, :2].reshape(t, 4).tolist()
    rm = meas_covs.reshape(m, 4).tolist()
    zs = z.tolist()
    d2s: list[float] = []
    dets: list[float] = []
    for (mx, my), (p00, p01, _, p11) in zip(means[:, :2].tolist(), hph, strict=True):
        for (zx, zy), (r00, r01, _, r11) in zip(zs, rm, strict=True):
            a, b, d = p00 + r00, p01 + r01, p11 + r11
            det = a * d - b * b
            vx, vy = zx - mx, zy - my
            d2s.append((d * vx * vx - 2.0 * b * vx * vy + a * vy * vy) / det)
            dets.append(det)
    d2 = np.array(d2s).reshape(t, m)
    loglik = -0.5 * d2 - LOG_2PI - 0.5 * np.log(np.array(dets).reshape(t, m))
    return d2, loglik


def euclidean_sq(means: FloatArray, z: FloatArray) -> FloatArray:
    """Squared distances (T, M) [m^2] between predicted positions and measurements."""
    v = z[None, :, :] - means[:, None, :2]
    return np.einsum("tmi,tmi->tm", v, v)


def update(
    mean: FloatArray, cov: FloatArray, z: FloatArray, meas_cov: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Kalman update of one state (4,), (4, 4) with measurement z (2,), covariance (2, 2).

    Uses the Joseph form so the covariance stays symmetric positive definite.
    """
    s = cov[:2, :2] + meas_cov
    det = s[0, 0] * s[1, 1] - s[0, 1] * s[1, 0]
    s_inv = np.array([[s[1, 1], -s[0, 1]], [-s[1, 0], s[0, 0]]]) / det
    k = cov[:, :2] @ s_inv  # (4, 2) = P H^T S^-1
    new_mean = mean + k @ (z - mean[:2])
    ikh = np.eye(4) - k @ H
    new_cov = ikh @ cov @ ikh.T + k @ meas_cov @ k.T
    return new_mean, 0.5 * (new_cov + new_cov.T)


def update_batch(
    means: FloatArray, covs: FloatArray, z: FloatArray, meas_covs: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Kalman updates of K states (K, 4), (K, 4, 4) with measurements (K, 2), (K, 2, 2) at
    once (Joseph form). Compiled where the extension is built (the same floats)."""
    k = covs.shape[0]
    if _extension is not None and k:
        every = list(range(k))
        return _compiled_update(means, covs, every, z, meas_covs, every)
    if 0 < covs.shape[0] <= SMALL_UPDATE:
        return _few_update(means, covs, z, meas_covs)
    s = covs[:, :2, :2] + meas_covs
    det = s[:, 0, 0] * s[:, 1, 1] - s[:, 0, 1] * s[:, 1, 0]
    s_inv = np.empty_like(s)
    s_inv[:, 0, 0] = s[:, 1, 1]
    s_inv[:, 1, 1] = s[:, 0, 0]
    s_inv[:, 0, 1] = -s[:, 0, 1]
    s_inv[:, 1, 0] = -s[:, 1, 0]
    s_inv /= det[:, None, None]
    k = covs[:, :, :2] @ s_inv  # (K, 4, 2)
    new_means = means + np.einsum("kij,kj->ki", k, z - means[:, :2])
    eye = np.zeros((covs.shape[0], 16))
    eye[:, ::5] = 1.0
    ikh = eye.reshape(-1, 4, 4)  # I - K H (K H fills the first two columns)
    ikh[:, :, :2] -= k
    new_covs = ikh @ covs @ ikh.transpose(0, 2, 1) + k @ meas_covs @ k.transpose(0, 2, 1)
    return new_means, 0.5 * (new_covs + new_covs.transpose(0, 2, 1))


def _few_update(
    means: FloatArray, covs: FloatArray, z: FloatArray, meas_covs: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """:func:`update_batch` of a few states with the inverse innovation covariances and
    ``I - K H`` formed in plain floats (the same IEEE operations element by element; the
    products left to numpy): the same arrays bit for bit, with fewer numpy calls."""
    inv: list[float] = []
    for (a, b), (c, d) in (covs[:, :2, :2] + meas_covs).tolist():
        det = a * d - b * c
        inv += (d / det, -b / det, -c / det, a / det)
    k = covs[:, :, :2] @ np.array(inv).reshape(-1, 2, 2)  # (K, 4, 2)
    new_means = means + np.einsum("kij,kj->ki", k, z - means[:, :2])
    rows: list[float] = []
    for (k00, k01), (k10, k11), (k20, k21), (k30, k31) in k.tolist():
        rows += (1.0 - k00, 0.0 - k01, 0.0, 0.0, 0.0 - k10, 1.0 - k11, 0.0, 0.0)
        rows += (0.0 - k20, 0.0 - k21, 1.0, 0.0, 0.0 - k30, 0.0 - k31, 0.0, 1.0)
    ikh = np.array(rows).reshape(-1, 4, 4)
    new_covs = ikh @ covs @ ikh.transpose(0, 2, 1) + k @ meas_covs @ k.transpose(0, 2, 1)
    return new_means, 0.5 * (new_covs + new_covs.transpose(0, 2, 1))


def predict_rows(
    means: list[FloatArray],
    covs: list[FloatArray],
    dts: list[float],
    accel_psd: float,
    tau: float,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """:func:`predict_and_coast` of N tracks given as rows: ``means`` a list of N arrays
    (4,), ``covs`` of N arrays (4, 4), ``dts`` N steps [s] as plain floats; the rows read
    where they are where the extension is built, else stacked."""
    got = _compiled_predict(means, covs, dts, accel_psd, tau)
    if got is not None:
        return got
    return predict_and_coast(
        np.array(means, dtype=np.float64).reshape(-1, 4),
        np.array(covs, dtype=np.float64).reshape(-1, 4, 4),
        np.array(dts, dtype=np.float64),
        accel_psd,
        tau,
    )


def _compiled_arrays(
    means: FloatArray, covs: FloatArray, dt: FloatArray, accel_psd: float, tau: float
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray] | None:
    """:func:`_compiled_predict` of stacked tracks (None: the extension is not built)."""
    if _extension is None or not dt.size:
        return None
    return _compiled_predict(
        np.ascontiguousarray(means), np.ascontiguousarray(covs), dt.tolist(), accel_psd, tau
    )


def _compiled_predict(
    means: list[FloatArray] | FloatArray,
    covs: list[FloatArray] | FloatArray,
    dts: list[float],
    accel_psd: float,
    tau: float,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray] | None:
    """:func:`predict_and_coast` by the extension, of rows (lists of arrays) or stacked
    contiguous arrays (the same floats: the cubes and decays as :func:`_step_powers`
    gives them, the products as numpy's); None where the extension is not built or does
    not take them (rows that are not 4 and 16 float64 each)."""
    if _extension is None or not dts:
        return None
    n = len(dts)
    pm, cm = np.empty((2, n, 4))
    pc, cc = np.empty((2, n, 4, 4))
    cubes, decays = _step_powers(dts, tau)
    try:
        _extension.predict(
            means, covs, dts, cubes, decays, float(accel_psd), float(tau), pm, pc, cm, cc
        )
    except (ValueError, TypeError):
        return None
    if decays is None:
        return pm, pc, pm, pc
    return pm, pc, cm, cc


def _step_powers(dts: list[float], tau: float) -> tuple[list[float], list[float] | None]:
    """``dt**3`` and ``exp(-dt / tau)`` (None for an infinite ``tau``) of each step, as
    :func:`predict_and_coast`'s numpy path for these steps computes them: steps that are
    all the same and a few steps (:data:`SMALL_BATCH`) cube by Python's ``pow`` (the C
    library's), more steps that differ by numpy's power (SIMD code on AVX-512 that differs
    from the C library's in the last bit of some values); the decay always by numpy's
    ``exp``."""
    d = dts[0]
    n = len(dts)
    if dts.count(d) == n:
        return [d**3] * n, None if math.isinf(tau) else [_decay(d, tau)] * n
    steps = np.array(dts)
    cubes: list[float] = [e**3 for e in dts] if n <= SMALL_BATCH else (steps**3).tolist()
    if math.isinf(tau):
        return cubes, None
    decays: list[float] = np.exp(-steps / tau).tolist()
    return cubes, decays


def _decay(d: float, tau: float) -> float:
    """``exp(-d / tau)`` by numpy's ``exp``, kept by step (as the step matrices are)."""
    key = (d, tau)
    k = _DECAYS.get(key)
    if k is None:
        k = float(np.exp(np.array((-d / tau,)))[0])
        if len(_DECAYS) >= STEP_MATRICES_KEPT:
            _DECAYS.clear()
        _DECAYS[key] = k
    return k


_DECAYS: dict[tuple[float, float], float] = {}


def _contiguous(*arrays: FloatArray) -> list[FloatArray]:
    """The arrays as C-contiguous float64 (themselves where they are)."""
    return [np.ascontiguousarray(a, dtype=np.float64) for a in arrays]


def _finish_loglik(partial: FloatArray, det: FloatArray) -> FloatArray:
    """The log-likelihoods from the extension's ``-0.5 d2 - log(2 pi)`` and ``det S``, in
    place: ``partial - 0.5 log(det)`` by numpy's ``log``, in the reference's order."""
    np.log(det, out=det)
    det *= 0.5
    partial -= det
    return partial


def gate_and_loglik(
    means: FloatArray,
    covs: FloatArray,
    z: FloatArray,
    meas_covs: FloatArray,
    gate: float,
    max_gate_sq: float,
) -> tuple[BoolArray, FloatArray]:
    """Which (track, measurement) pairs are gated, (T, M): squared Mahalanobis distance at
    most ``gate`` and squared distance at most ``max_gate_sq`` [m^2]; and their Gaussian
    log-likelihoods (T, M) (:func:`mahalanobis_and_loglik`, :func:`euclidean_sq`).
    Compiled where the extension is built (the same floats, the logarithm numpy's)."""
    t, m = means.shape[0], z.shape[0]
    if _extension is None or t * m == 0:
        d2, ll = mahalanobis_and_loglik(means, covs, z, meas_covs)
        return (d2 <= gate) & (euclidean_sq(means, z) <= max_gate_sq), ll
    gated = np.empty((t, m), dtype=np.bool_)
    loglik, det = np.empty((2, t, m))
    _extension.score(
        *_contiguous(means, covs, z, meas_covs),
        float(gate),
        float(max_gate_sq),
        LOG_2PI,
        gated,
        loglik,
        det,
        None,
    )
    return gated, _finish_loglik(loglik, det)


def update_rows(
    means: FloatArray,
    covs: FloatArray,
    rows: list[int],
    z: FloatArray,
    meas_covs: FloatArray,
    js: list[int],
) -> tuple[FloatArray, FloatArray]:
    """:func:`update_batch` of the states at ``rows`` of ``means`` (N, 4) and ``covs``
    (N, 4, 4) with the measurements at ``js`` of ``z`` (M, 2) and ``meas_covs`` (M, 2, 2);
    the rows read where they are where the extension is built, else taken."""
    if _extension is not None and rows:
        return _compiled_update(means, covs, rows, z, meas_covs, js)
    idx = np.asarray(js, dtype=np.intp)
    return update_batch(
        means.take(rows, axis=0),
        covs.take(rows, axis=0),
        z.take(idx, axis=0),
        meas_covs.take(idx, axis=0),
    )


def _compiled_update(
    means: FloatArray,
    covs: FloatArray,
    rows: list[int],
    z: FloatArray,
    meas_covs: FloatArray,
    js: list[int],
) -> tuple[FloatArray, FloatArray]:
    """:func:`update_rows` by the extension (the same floats as :func:`update_batch`)."""
    assert _extension is not None
    k = len(rows)
    out_m = np.empty((k, 4))
    out_c = np.empty((k, 4, 4))
    _extension.update(*_contiguous(means, covs), rows, *_contiguous(z, meas_covs), js, out_m, out_c)
    return out_m, out_c


def initiate(
    z: FloatArray, meas_cov: FloatArray, init_velocity_std: float
) -> tuple[FloatArray, FloatArray]:
    """A new track at measurement z (2,) with zero velocity (000 Sec. 3.1)."""
    mean = np.array([z[0], z[1], 0.0, 0.0])
    cov = np.zeros((4, 4))
    cov[:2, :2] = meas_cov
    cov[2, 2] = cov[3, 3] = init_velocity_std**2
    return mean, cov


def initiate_batch(
    z: FloatArray, meas_covs: FloatArray, init_velocity_std: float
) -> tuple[FloatArray, FloatArray]:
    """New tracks (K, 4), (K, 4, 4) at measurements z (K, 2) with covariances (K, 2, 2):
    :func:`initiate` for each at once."""
    k = z.shape[0]
    means = np.zeros((k, 4))
    means[:, :2] = z
    covs = np.zeros((k, 4, 4))
    covs[:, :2, :2] = meas_covs
    covs[:, 2, 2] = covs[:, 3, 3] = init_velocity_std**2
    return means, covs


def measurement_covariances(raw: FloatArray, measurement_std: float) -> FloatArray:
    """Detector covariances (M, 2, 2), replaced by ``measurement_std^2 I`` where not positive
    definite (rule-based detectors may report zeros)."""
    raw = np.asarray(raw, dtype=np.float64).reshape(-1, 2, 2)
    if raw.shape[0] <= SMALL_BATCH:  # (a few detections: the same test in plain floats)
        out = raw.copy()
        for i, (xx, xy, yx, yy) in enumerate(raw.reshape(-1, 4).tolist()):
            finite = math.isfinite(xx) and math.isfinite(xy) and math.isfinite(yx)
            if not (xx > 0 and xx * yy - xy * xy > 0 and finite and math.isfinite(yy)):
                out[i] = np.eye(2) * measurement_std**2
        return out
    a, b, d = raw[:, 0, 0], raw[:, 0, 1], raw[:, 1, 1]
    ok = (a > 0) & (a * d - b * b > 0) & np.isfinite(raw).all(axis=(1, 2))
    out = raw.copy()
    out[~ok] = np.eye(2) * measurement_std**2
    return out
