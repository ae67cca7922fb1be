"""Colour appearance (002 Sec. 2): hue, histograms, eqs. 1-8."""

from __future__ import annotations

import colorsys
import itertools

import numpy as np
import pytest
from scipy.stats import multivariate_normal

from laserpeople.colour import hsv_to_rgb, region_hues, rgb_to_hue
from laserpeople.identity.appearance import (
    TABLE1_HUES_DEG,
    AppearanceParams,
    OnlineGaussian,
    assign_identities,
    assignment_margin,
    hue_histogram,
    log_likelihoods,
    measurement,
)


def test_rgb_to_hue_matches_colorsys() -> None:
    rng = np.random.default_rng(0)
    rgb = rng.random((500, 3))
    hue, sat, val = rgb_to_hue(rgb)
    for k in range(rgb.shape[0]):
        h, s, v = colorsys.rgb_to_hsv(*rgb[k])
        assert hue[k] == pytest.approx(360.0 * h % 360.0, abs=1e-9)
        assert sat[k] == pytest.approx(s) and val[k] == pytest.approx(v)


def test_table1_colours_have_their_hue_and_bin() -> None:
    pure = {
        "red": (255, 0, 0),
        "yellow": (255, 255, 0),
        "green": (0, 255, 0),
        "cyan": (0, 255, 255),
        "blue": (0, 0, 255),
        "magenta": (255, 0, 255),
    }
    for b, (name, deg) in enumerate(TABLE1_HUES_DEG.items()):
        hue, _, _ = rgb_to_hue(np.array([pure[name]], dtype=np.uint8))
        assert hue[0] == pytest.approx(deg)
        hist = hue_histogram(np.deg2rad(np.array([deg])), 6)
        assert hist.argmax() == b and hist.sum() == pytest.approx(1.0)


def test_histogram_bin_edges_lie_halfway_between_table1_colours() -> None:
    deg = np.array([29.0, 31.0, 350.0, 329.0, 89.0, 91.0, 200.0])
    hist = hue_histogram(np.deg2rad(deg), 6)
    # red: 29, 350; yellow: 31, 89; green: 91; cyan: 200; magenta: 329
    assert hist.tolist() == pytest.approx(np.array([2, 2, 1, 1, 0, 1]) / 7)
    fine = hue_histogram(np.deg2rad(np.array([0.0, 14.0, 16.0])), 12)  # 30 deg bins
    assert fine[0] == pytest.approx(2 / 3) and fine[1] == pytest.approx(1 / 3)


def test_hsv_round_trip() -> None:
    rng = np.random.default_rng(1)
    h, s, v = rng.uniform(0, 360, 300), rng.uniform(0.1, 1, 300), rng.uniform(0.1, 1, 300)
    h2, s2, v2 = rgb_to_hue(hsv_to_rgb(h, s, v))
    assert np.allclose(np.angle(np.exp(1j * np.deg2rad(h2 - h))), 0.0, atol=1e-9)
    assert np.allclose(s2, s) and np.allclose(v2, v)


def test_region_ignores_grey_and_dark_pixels() -> None:
    img = np.zeros((4, 4, 3))
    img[:2, :, 0] = 1.0  # red rows
    img[2, :, 2] = 1.0  # blue row
    img[3, :] = 0.5  # grey row: no hue
    y = measurement(region_hues(img), AppearanceParams(min_hue_samples=1))
    assert y is not None
    assert y.tolist() == pytest.approx([2 / 3, 0, 0, 0, 1 / 3, 0])
    mask = np.zeros((4, 4), dtype=bool)
    mask[2] = True
    assert np.rad2deg(region_hues(img, mask)) == pytest.approx([-120.0] * 4)
    assert measurement(np.zeros(3), AppearanceParams(min_hue_samples=4)) is None


def test_online_mean_and_covariance_equal_the_batch_estimates() -> None:
    """002 eqs. 3-5 reproduce eqs. 1-2 (numpy's mean and unbiased covariance) at every k."""
    rng = np.random.default_rng(2)
    ys = rng.dirichlet(np.ones(6), size=40)
    g = OnlineGaussian(6)
    for k in range(1, ys.shape[0] + 1):
        g.add(ys[k - 1])
        assert g.k == k
        assert np.allclose(g.mean, ys[:k].mean(axis=0))
        if k >= 2:
            assert np.allclose(g.covariance, np.cov(ys[:k].T, ddof=1))


def test_log_likelihood_is_the_gaussian_density_of_eq6() -> None:
    rng = np.random.default_rng(3)
    mu = rng.random((3, 4))
    a = rng.normal(size=(3, 4, 4))
    sig = a @ a.transpose(0, 2, 1) * 0.1
    y = rng.random((5, 4))
    ll = log_likelihoods(y, mu, sig, floor=0.01)
    for i in range(3):
        expect = multivariate_normal(mu[i], sig[i] + 0.01 * np.eye(4)).logpdf(y)
        assert np.allclose(ll[i], expect)


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5, 6])
def test_reassignment_equals_brute_force_over_permutations(n: int) -> None:
    """The Hungarian assignment maximises eq. 8 (the product of eq. 7 over people)."""
    rng = np.random.default_rng(10 + n)
    for _ in range(20):
        loglik = rng.normal(0.0, 5.0, (n, n))  # log p_{i,j,k1:k2}
        rows, cols = assign_identities(-loglik)
        got = loglik[rows, cols].sum()
        best = max(sum(loglik[i, s[i]] for i in range(n)) for s in itertools.permutations(range(n)))
        assert got == pytest.approx(best)
        assert sorted(cols.tolist()) == list(range(n))


def test_eq7_product_of_observations_picks_the_right_person() -> None:
    """Two learnt people; the sum of log eq. 6 over a window (eq. 7) assigns each track to
    the person whose colours it shows."""
    rng = np.random.default_rng(4)
    red = OnlineGaussian(6)
    blue = OnlineGaussian(6)
    for _ in range(30):
        red.add(hue_histogram(np.deg2rad(rng.normal(0, 10, 100)), 6))
        blue.add(hue_histogram(np.deg2rad(rng.normal(240, 10, 100)), 6))
    mu = np.array([red.mean, blue.mean])
    sig = np.array([red.covariance, blue.covariance])
    track_blue = [hue_histogram(np.deg2rad(rng.normal(240, 10, 100)), 6) for _ in range(5)]
    track_red = [hue_histogram(np.deg2rad(rng.normal(0, 10, 100)), 6) for _ in range(5)]
    cost = np.zeros((2, 2))
    for j, obs in enumerate((track_blue, track_red)):
        cost[:, j] = -log_likelihoods(np.array(obs), mu, sig, 1e-3).sum(axis=1)
    rows, cols = assign_identities(cost)
    assert dict(zip(rows.tolist(), cols.tolist(), strict=True)) == {0: 1, 1: 0}


def test_assignment_margin_is_the_gap_to_the_second_best_assignment() -> None:
    """By hand: the six permutations of this cost cost 17, 13, 11.5 (1->0, 0->1, 2->2),
    12, 11 (0->2, 1->0, 2->1) and 16; the best is 11, the second best 11.5. Greedy (the
    smallest entry first: 0 at (0, 0), then 6 at (2, 1), then 7) would give 13."""
    cost = np.array([[0.0, 1.0, 4.0], [1.0, 8.0, 7.0], [4.0, 6.0, 9.5]])
    rows, cols, margin = assignment_margin(cost)
    assert dict(zip(rows.tolist(), cols.tolist(), strict=True)) == {0: 2, 1: 0, 2: 1}
    assert margin == pytest.approx(0.5, abs=1e-9)


def test_assignment_margin_rectangular_and_single() -> None:
    """Three identities, two tracks: (0, 2) costs 1 + 0, the next (1, 2) 2 + 0, so the
    margin is 1; one identity and one track have no rival: inf."""
    cost = np.array([[1.0, 5.0], [2.0, 3.0], [9.0, 0.0]])
    rows, cols, margin = assignment_margin(cost)
    assert dict(zip(rows.tolist(), cols.tolist(), strict=True)) == {0: 0, 2: 1}
    assert margin == pytest.approx(1.0, abs=1e-9)
    assert assignment_margin(np.array([[3.0]]))[2] == np.inf


@pytest.mark.parametrize("n", [2, 3, 4])
def test_assignment_margin_equals_brute_force(n: int) -> None:
    rng = np.random.default_rng(20 + n)
    for _ in range(20):
        cost = rng.normal(0.0, 5.0, (n, n))
        totals = sorted(
            sum(cost[i, s[i]] for i in range(n)) for s in itertools.permutations(range(n))
        )
        assert assignment_margin(cost)[2] == pytest.approx(totals[1] - totals[0])
