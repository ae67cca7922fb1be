"""The feet tracker of 004 Sec. 2.1 through the code it runs: the repelling term in the
weights and the body offset in the reported position, against computations written out in
the test (the walking model of eqs. 1-2 and the repelling factor by hand)."""

from __future__ import annotations

import numpy as np

from laserpeople.frame import Frame
from laserpeople.scan import PointSet
from laserpeople.tracking.particle.feet import (
    ALPHA,
    GAMMA,
    XL,
    XR,
    YL,
    YR,
    FeetParams,
    FeetTracker,
    S,
    T,
)


def _empty(k: int, t: float) -> Frame:
    ps = PointSet(t, np.empty((0, 2)), np.empty(0, dtype=np.int64), np.empty(0, dtype=np.int64))
    return Frame(k, t, (), "synthetic", "world", None, ps, np.empty(0, dtype=bool))


def _states(rng: np.random.Generator, centre: tuple[float, float], n: int) -> np.ndarray:
    """Particles (n, 8) around ``centre`` whose feet satisfy eq. 6 exactly (o_b = 1): feet
    0.2 m apart along alpha, right ahead, stride 0.4 m, gamma = arccos(-s_d / s)."""
    st = np.zeros((n, 8))
    alpha = rng.uniform(-0.3, 0.3, n)
    mid = np.asarray(centre) + rng.normal(0.0, 0.08, (n, 2))
    u = np.column_stack([np.cos(alpha), np.sin(alpha)])
    st[:, XL : YL + 1] = mid - 0.1 * u
    st[:, XR : YR + 1] = mid + 0.1 * u
    st[:, S] = 0.4
    st[:, T] = rng.uniform(0.9, 1.3, n)
    st[:, GAMMA] = np.arccos(-0.2 / 0.4) + 2.0 * np.pi * rng.integers(0, 2, n)
    st[:, ALPHA] = alpha
    return st


def test_weights_carry_the_repelling_term_and_tracks_the_body_offset() -> None:
    """Two filters 0.5 m apart, no points (eqs. 3-4 give P_0 for both feet, eq. 6 gives 1):
    after one update at dt = 0 without resampling, each filter's weights are the repelling
    factor prod_g (1 - exp(-|c_i - e_g|^2 / (2 sigma^2))) normalised, and its reported
    position is the weighted mean of the feet midpoints moved by the body offset
    s (phi / pi - (1 - cos phi) / 2) along alpha, phi = mod(gamma, pi)."""
    p = FeetParams(particles=40, resample_threshold=0.0, h_width=0.0, seed=1)
    tracker = FeetTracker(p)
    tracker.update(_empty(0, 0.0))
    rng = np.random.default_rng(4)
    states = np.stack([_states(rng, (0.0, 0.0), 40), _states(rng, (0.5, 0.1), 40)])
    tracker.bank.add(states, 0.0)
    tracks = tracker.update(_empty(1, 0.0))
    mids = 0.5 * (states[..., XL : YL + 1] + states[..., XR : YR + 1])  # (2, P, 2)
    est = mids.mean(axis=1)  # uniform weights before the update
    rep = np.empty((2, 40))
    for f in range(2):
        d2 = np.sum((mids[f] - est[1 - f]) ** 2, axis=1)
        rep[f] = 1.0 - np.exp(-d2 / (2.0 * p.sigma_repel**2))
    expected = rep / rep.sum(axis=1, keepdims=True)
    assert len(tracker.bank) == 2
    np.testing.assert_allclose(tracker.bank.weights, expected, rtol=1e-6)
    assert np.ptp(expected[0]) > 0.1 / 40  # the term is not flat here (10 % of a weight)
    phi = np.mod(states[..., GAMMA], np.pi)
    ahead = states[..., S] * (phi / np.pi - 0.5 * (1.0 - np.cos(phi)))
    body = mids + ahead[..., None] * np.stack(
        [np.cos(states[..., ALPHA]), np.sin(states[..., ALPHA])], axis=-1
    )
    want = np.einsum("fp,fpc->fc", expected, body)
    got = {t.track_id: t.position for t in tracks.of_kind("person")}
    assert len(got) == 2
    for f, tid in enumerate(tracker.bank.ids.tolist()):
        np.testing.assert_allclose(got[tid], want[f], atol=1e-9)
    assert np.all(np.abs(ahead) > 0.02)  # the offset is not zero here
