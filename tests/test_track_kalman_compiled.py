"""The Kalman steps of many tracks, compiled (the C extension ``_ckalman``): ``kalman``'s
predictions, gates, likelihoods and updates of rows and of stacked arrays against its numpy
code (the reference, ``kalman._extension`` None) on random tracks, by hand and in a leg MHT
stepped side by side; what goes to numpy; the stale guard of the buffer helpers' header the
extensions share.

On x86-64 with FMA the compiled steps give numpy's floats to the bit (numpy's products of
these small matrices are OpenBLAS's fused sums in order, which the C code repeats; the
tracks CSVs of the real recordings are the same); another CPU's BLAS may sum otherwise, so
the tests compare floats within :data:`TOL` (relative) and decisions exactly, except gate
decisions within :data:`GATE_BAND` of the gate."""

from __future__ import annotations

import math
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np
import pytest

from laserpeople import extensions
from laserpeople.tracking import kalman
from laserpeople.tracking.synthetic import walkers_scene

TOL = 1e-12
"""Relative tolerance of the compiled floats against numpy's (they agree to the bit here)."""

GATE_BAND = 1e-9
"""Squared Mahalanobis distances this close (relative) to the gate may be decided either
way by floats that differ in the last bits."""


@pytest.fixture(scope="module")
def ckalman() -> ModuleType:
    """The built extension; skips when it is not built or stale (nothing to compare)."""
    try:
        from laserpeople.tracking import _ckalman
    except ImportError:
        pytest.skip("the C extension is not built (`pip install -e .` with a C compiler)")
    if extensions.source_hash(kalman.SOURCE) != _ckalman.SOURCE_HASH:
        pytest.skip("the C extension is stale (`pip install -e .` rebuilds it)")
    return _ckalman


@pytest.fixture
def compiled(ckalman: ModuleType, monkeypatch: pytest.MonkeyPatch) -> ModuleType:
    """The extension in use by kalman.py for the test."""
    monkeypatch.setattr(kalman, "_extension", ckalman)
    return ckalman


def _numpy(monkeypatch: pytest.MonkeyPatch, fn: Any, *args: Any) -> Any:
    """``fn(*args)`` by kalman's numpy code."""
    with monkeypatch.context() as m:
        m.setattr(kalman, "_extension", None)
        return fn(*args)


def _close(got: Any, want: Any) -> None:
    np.testing.assert_allclose(got, want, rtol=TOL, atol=TOL * np.max(np.abs(want), initial=1.0))


def _covariances(rng: np.random.Generator, n: int, scale: float) -> Any:
    a = rng.standard_normal((n, 4, 4)) * scale
    return a @ a.transpose(0, 2, 1) + np.eye(4) * 1e-4


def _steps(rng: np.random.Generator, n: int, trial: int) -> list[float]:
    """One shared step, a few or many different ones (numpy's power), zeros, a long one."""
    kind = trial % 4
    if kind == 0:
        return [0.025] * n
    if kind == 1:
        return rng.uniform(0.0, 1.0, n).tolist()
    if kind == 2:
        return rng.choice([0.0, 0.025, 0.05, 1.0], n).tolist()
    return [float(rng.uniform(0.01, 0.1))] * n


def test_compiled_prediction_is_numpy_on_random_nodes(
    compiled: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    """1200 random batches of 1-40 nodes (one step, a few and many different steps, zero
    and long steps; coasting with tau 0.1, 0.35 and without): the predicted and coasted
    means and covariances of numpy's ``predict_and_coast``, from rows and from arrays
    (also ``predict`` and ``coast``)."""
    rng = np.random.default_rng(35)
    for trial in range(1200):
        n = int(rng.integers(1, 41))
        means = rng.standard_normal((n, 4)) * rng.choice([0.1, 1.0, 10.0])
        covs = _covariances(rng, n, float(rng.choice([0.01, 0.1, 1.0])))
        dts = _steps(rng, n, trial)
        tau = (0.35, math.inf, 0.1)[trial % 3]
        want = _numpy(monkeypatch, kalman.predict_and_coast, means, covs, np.array(dts), 32.0, tau)
        got = kalman.predict_rows(list(means), list(covs), dts, 32.0, tau)
        for g, w in zip(got, want, strict=True):
            _close(g, w)
        got = kalman.predict_and_coast(means, covs, np.array(dts), 32.0, tau)
        for g, w in zip(got, want, strict=True):
            _close(g, w)
        for fn, args, rows in [
            (kalman.predict, (means, covs, np.array(dts), 32.0), want[:2]),
            (kalman.coast, (means, covs, np.array(dts), 32.0, tau), want[2:]),
        ]:
            for g, w in zip(fn(*args), rows, strict=True):
                _close(g, w)


def test_compiled_gates_and_likelihoods_are_numpy_on_random_pairs(
    compiled: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    """1200 random sets of 1-40 predicted nodes and 1-30 measurements around them: the
    same gated pairs (but within GATE_BAND of the gate), squared Mahalanobis distances and
    log-likelihoods as numpy's ``mahalanobis_and_loglik`` and ``euclidean_sq``; the trials
    gate some pairs and leave others."""
    rng = np.random.default_rng(36)
    gate, cap = kalman.KalmanParams().gate, 1.0
    seen = np.zeros(2, dtype=int)
    for _ in range(1200):
        n, m = int(rng.integers(1, 41)), int(rng.integers(1, 31))
        pm = rng.standard_normal((n, 4))
        pc = _covariances(rng, n, float(rng.choice([0.05, 0.2, 1.0])))
        z = pm[rng.integers(0, n, m), :2] + rng.standard_normal((m, 2)) * 0.5
        r = _covariances(rng, m, 0.05)[:, :2, :2]
        gated, ll = kalman.gate_and_loglik(pm, pc, z, r, gate, cap)
        d2, want_ll = _numpy(monkeypatch, kalman.mahalanobis_and_loglik, pm, pc, z, r)
        want_gated = (d2 <= gate) & (kalman.euclidean_sq(pm, z) <= cap)
        clear = np.abs(d2 - gate) > GATE_BAND * gate
        assert np.array_equal(gated[clear], want_gated[clear])
        _close(ll, want_ll)
        got_d2, got_ll = kalman.mahalanobis_and_loglik(pm, pc, z, r)
        _close(got_d2, d2)
        _close(got_ll, want_ll)
        seen += [int(gated.sum()), int((~gated).sum())]
    assert seen.min() > 1000


def test_compiled_updates_are_numpy_on_random_states(
    compiled: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    """1200 random sets of 1-40 updates of rows of a predicted batch with measurements
    (rows and measurements repeated): numpy's ``update_batch`` of the rows taken, from
    rows and from arrays."""
    rng = np.random.default_rng(37)
    for _ in range(1200):
        n, m, k = (int(v) for v in rng.integers(1, 41, 3))
        pm = rng.standard_normal((n, 4))
        pc = _covariances(rng, n, float(rng.choice([0.05, 0.2, 1.0])))
        z = rng.standard_normal((m, 2))
        r = _covariances(rng, m, 0.05)[:, :2, :2]
        rows, js = rng.integers(0, n, k).tolist(), rng.integers(0, m, k).tolist()
        taken = (pm[rows], pc[rows], z[js], r[js])
        want = _numpy(monkeypatch, kalman.update_batch, *taken)
        for got in (kalman.update_rows(pm, pc, rows, z, r, js), kalman.update_batch(*taken)):
            for g, w in zip(got, want, strict=True):
                _close(g, w)


@pytest.mark.parametrize("path", ["compiled", "numpy"])
def test_kalman_steps_by_hand(
    request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch, path: str
) -> None:
    """One node at the origin moving at 1 m/s along x, P = I, over 0.5 s with q = 2
    m^2/s^3: F P F^T + Q by hand (q dt^3 / 3 = 1/12, q dt^2 / 2 = 1/4, q dt = 1), coasted
    with tau = 0.5 (k = e^-1, g = 0.5 (1 - k)); gated and updated with z = (1, 0), R = I:
    S = (4/3 + 1) I, d2 = 0.25 / S, K = P H^T S^-1."""
    ext = request.getfixturevalue("ckalman") if path == "compiled" else None
    monkeypatch.setattr(kalman, "_extension", ext)
    x = np.array([0.0, 0.0, 1.0, 0.0])
    pm, pc, cm, cc = kalman.predict_rows([x], [np.eye(4)], [0.5], 2.0, 0.5)
    np.testing.assert_allclose(pm[0], [0.5, 0.0, 1.0, 0.0], rtol=0, atol=1e-15)
    s = 1.25 + 1.0 / 12.0  # P + dt^2 (the velocity's variance) + q dt^3 / 3
    want = np.array(
        [[s, 0.0, 0.75, 0.0], [0.0, s, 0.0, 0.75], [0.75, 0.0, 2.0, 0.0], [0.0, 0.75, 0.0, 2.0]]
    )
    np.testing.assert_allclose(pc[0], want, rtol=1e-14, atol=1e-15)
    k = math.exp(-1.0)
    g = 0.5 * (1.0 - k)
    np.testing.assert_allclose(cm[0], [g, 0.0, k, 0.0], rtol=1e-14, atol=1e-15)
    assert cc[0, 0, 0] == pytest.approx(1.0 + g * g + 1.0 / 12.0, rel=1e-14)
    assert cc[0, 2, 2] == pytest.approx(k * k + 1.0, rel=1e-14)
    assert cc[0, 0, 2] == pytest.approx(g * k + 0.25, rel=1e-14)
    z, r = np.array([[1.0, 0.0], [0.5, 3.0]]), np.array([np.eye(2), np.eye(2)])
    gated, ll = kalman.gate_and_loglik(pm, pc, z, r, 0.2, 4.0)
    d2 = 0.25 / (s + 1.0)
    assert gated.tolist() == [[True, False]]  # (the second: d2 = 9 / S > 0.2)
    want_ll = -0.5 * d2 - math.log(2.0 * math.pi) - math.log(s + 1.0)
    assert ll[0, 0] == pytest.approx(want_ll, rel=1e-14)
    means, covs = kalman.update_rows(pm, pc, [0], z, r, [0])
    gain = np.array([s, 0.0, 0.75, 0.0]) / (s + 1.0)  # K's first column
    np.testing.assert_allclose(
        means[0], [0.5 + 0.5 * gain[0], 0.0, 1.0 + 0.5 * gain[2], 0.0], rtol=1e-14
    )
    assert covs[0, 0, 0] == pytest.approx(s - s * s / (s + 1.0), rel=1e-13)  # (1 - K) P
    assert covs[0, 2, 2] == pytest.approx(2.0 - 0.75 * 0.75 / (s + 1.0), rel=1e-13)
    assert np.array_equal(covs[0], covs[0].T)


def test_rows_that_are_not_float64_go_to_numpy(compiled: ModuleType) -> None:
    """Rows the extension does not take (float32, three elements) are predicted by numpy
    (the float32 ones as numpy casts them; the others raise as numpy does)."""
    rng = np.random.default_rng(38)
    means = list(rng.standard_normal((3, 4)).astype(np.float32))
    covs = list(_covariances(rng, 3, 1.0))
    got = kalman.predict_rows(means, covs, [0.025] * 3, 32.0, 0.35)
    want = kalman.predict_and_coast(
        np.array(means, dtype=np.float64), np.array(covs), np.full(3, 0.025), 32.0, 0.35
    )
    for g, w in zip(got, want, strict=True):
        assert np.array_equal(g, w)
    with pytest.raises(ValueError):
        kalman.predict_rows([np.zeros(3)], [np.eye(4)], [0.025], 32.0, 0.35)


def test_bad_arguments_raise(ckalman: ModuleType) -> None:
    """Rows or measurements out of range, arrays of the wrong size or type: an error, no
    read out of bounds."""
    pm, pc = np.zeros((2, 4)), np.tile(np.eye(4), (2, 1, 1))
    z, r = np.zeros((1, 2)), np.eye(2)[None]
    out_m, out_c = np.empty((1, 4)), np.empty((1, 4, 4))
    with pytest.raises(IndexError):
        ckalman.update(pm, pc, [2], z, r, [0], out_m, out_c)
    with pytest.raises(IndexError):
        ckalman.update(pm, pc, [0], z, r, [-1], out_m, out_c)
    with pytest.raises(ValueError):
        ckalman.update(pm, pc, [0], z, r, [0], np.empty((2, 4)), out_c)
    gated, part, det = np.empty((2, 1), bool), np.empty((2, 1)), np.empty((2, 1))
    with pytest.raises(ValueError):
        ckalman.score(pm, pc[:1], z, r, 9.0, 1.0, 1.8, gated, part, det, None)
    with pytest.raises(ValueError):
        ckalman.score(pm, pc, z, r, 9.0, 1.0, 1.8, np.empty((2, 1)), part, det, None)
    with pytest.raises(ValueError):
        ckalman.predict([pm[0]], [pc[0]], [0.1, 0.2], [0.001], None, 1.0, 1.0, pm, pc, None, None)


def test_leg_trackers_with_and_without_the_compiled_steps_track_the_same(
    ckalman: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Two leg MHTs stepped side by side over a scene of six walkers with clutter, one with
    the compiled Kalman steps, one with numpy's: after every scan the same reported tracks
    (ids), at the same positions within TOL. (What the user sees: where numpy's products
    round otherwise than C's fused ones, on another CPU, a hypothesis at the pruning
    threshold may be kept by one and not the other.)"""
    from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams

    fast, slow = LegMHTTracker(LegTrackerParams()), LegMHTTracker(LegTrackerParams())
    calls = {"n": 0}

    def counted(*args: Any) -> Any:
        calls["n"] += 1
        return ckalman.update(*args)

    wrapper = type("Counted", (), {"predict": ckalman.predict, "score": ckalman.score})()
    wrapper.update = counted  # type: ignore[attr-defined]

    for d in walkers_scene(21, 1.5).detections:
        monkeypatch.setattr(kalman, "_extension", wrapper)
        out_fast = fast.update(d)
        monkeypatch.setattr(kalman, "_extension", None)
        out_slow = slow.update(d)
        assert [t.track_id for t in out_fast] == [t.track_id for t in out_slow]
        for g, w in zip(out_fast, out_slow, strict=True):
            np.testing.assert_allclose(g.position, w.position, rtol=0.0, atol=TOL)
    assert calls["n"] > 100


def test_a_changed_shared_header_makes_the_extensions_stale(
    ckalman: ModuleType, monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """The checksum covers the buffer helpers' header too: with one byte more in it, every
    extension is stale (the numpy or Python references run, with a warning naming the
    rebuild command); with the header as built, the extension runs."""
    monkeypatch.delenv(extensions.PURE_PYTHON, raising=False)
    edited = tmp_path / "_cbuffers.h"
    edited.write_bytes(extensions.HEADER.read_bytes() + b"\n")
    monkeypatch.setattr(extensions, "HEADER", edited)
    name = "laserpeople.tracking._ckalman"
    with pytest.warns(extensions.StaleExtensionWarning, match=r"pip install -e \."):
        module, which = extensions.load_extension(name, kalman.SOURCE, "Kalman steps")
    assert module is None and "stale" in which
    edited.write_bytes(edited.read_bytes()[:-1])
    assert extensions.load_extension(name, kalman.SOURCE, "Kalman steps") == (
        ckalman,
        "compiled (C extension)",
    )


def test_step_powers_are_those_of_the_reference_path() -> None:
    """The cubes and decays handed to the extension are the ones the numpy path for the
    same steps computes: one shared step or a few steps cubed by Python's ``pow``, more
    steps that differ by numpy's power (which can differ in the last bit); every decay by
    numpy's ``exp``; None without coasting."""
    rng = np.random.default_rng(39)
    tau = 0.35
    for _ in range(200):
        d = float(rng.uniform(0.0, 1.0))
        cubes, decays = kalman._step_powers([d] * 9, tau)
        assert cubes == [d**3] * 9
        assert decays == [float(np.exp(np.array([-d / tau]))[0])] * 9
        few = rng.uniform(0.0, 1.0, kalman.SMALL_BATCH).tolist()
        cubes, decays = kalman._step_powers(few, tau)
        assert cubes == [e**3 for e in few]
        assert decays == np.exp(-np.array(few) / tau).tolist()
        many = rng.uniform(0.0, 1.0, kalman.SMALL_BATCH + 5).tolist()
        cubes, decays = kalman._step_powers(many, tau)
        assert cubes == (np.array(many) ** 3).tolist()
        assert decays == np.exp(-np.array(many) / tau).tolist()
        assert kalman._step_powers(many, math.inf)[1] is None


def test_point_model_steps_are_clipped_to_zero_and_max_dt() -> None:
    """A node's step to the scan is clipped to [0, max_dt], whether the nodes share one
    step (the fast path) or not."""
    from laserpeople.tracking.mht.tracktree import TrackNode
    from laserpeople.tracking.point_model import KalmanPointModel

    model = KalmanPointModel(kalman.KalmanParams(max_dt=1.0))

    def steps(stamps: list[float], stamp: float) -> list[float]:
        nodes = [
            TrackNode(i, i, -1, np.zeros(4), np.eye(4), s, "new") for i, s in enumerate(stamps)
        ]
        return model._steps(nodes, stamp)

    assert steps([2.0, 2.0], 1.5) == [0.0, 0.0]  # (stamped after the scan)
    assert steps([0.0, 0.0], 3.0) == [1.0, 1.0]  # (longer than max_dt)
    assert steps([0.5, 0.5], 0.75) == [0.25, 0.25]
    assert steps([2.0, 0.0, 0.5], 1.5) == [0.0, 1.0, 1.0]
    assert steps([1.0, 0.5], 1.25) == [0.25, 0.75]
