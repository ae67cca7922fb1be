"""Hypothesis probabilities of 000 eqs. 2-15 against hand computation and enumeration."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from laserpeople.tracking.legs import LegTrackerParams
from laserpeople.tracking.mht.matrix import build_matrix, k_best_children
from laserpeople.tracking.mht.probability import (
    DELETED,
    DETECTED,
    FALSE_ALARM,
    MATCHED,
    NEW,
    OCCLUDED,
    LabelProbabilities,
    assignment_set_probability_combinatorial,
    assignment_set_probability_eq14,
    log_child_weight,
    normalise,
)

FREE = LabelProbabilities(0.3, 0.63, 0.07)
APPROVED = LabelProbabilities(0.2, 0.79, 0.01)


def test_table_10_defaults() -> None:
    p = LegTrackerParams()
    assert (p.p_det_free, p.p_occ_free, p.p_del_free) == (0.3, 0.63, 0.07)
    assert (p.p_det_approved, p.p_occ_approved, p.p_del_approved) == (0.2, 0.79, 0.01)
    assert (p.lambda_new, p.lambda_fal) == (0.001, 0.003)


def test_label_probabilities_must_sum_to_one() -> None:
    with pytest.raises(ValueError):
        LabelProbabilities(0.3, 0.6, 0.2)
    with pytest.raises(ValueError):
        LegTrackerParams(p_det_free=0.5)


@pytest.mark.parametrize("volume", [1.0, 7.5, 30.0])
def test_eq11_to_13_cancel_to_eq14(volume: float) -> None:
    """The product of eqs. 11, 1/12, 1/13 equals eq. 14 with eta' = exp(-(l_n + l_f)V)/M!
    for every combination of label counts."""
    for df, of, xf, da, oa, xa, n_new, n_fal in itertools.product(range(3), repeat=8):
        counts_f, counts_a = (df, of, xf), (da, oa, xa)
        a = assignment_set_probability_combinatorial(
            counts_f, counts_a, n_new, n_fal, FREE, APPROVED, 0.001, 0.003, volume
        )
        b = assignment_set_probability_eq14(
            counts_f, counts_a, n_new, n_fal, FREE, APPROVED, 0.001, 0.003, volume
        )
        assert a == pytest.approx(b, rel=1e-12)


def test_eq15_hand_computation() -> None:
    """A free track matched with likelihood N = 12.5, an approved track occluded, a third
    (free) deleted, one false alarm, one new track:
    p = 0.3 * 12.5 * 0.79 * 0.07 * 0.003 * 0.001 * p(parent)."""
    parent = math.log(0.4)
    lp = np.log(np.array([[0.3, 0.63, 0.07], [0.2, 0.79, 0.01], [0.3, 0.63, 0.07]]))
    got = log_child_weight(
        parent, [math.log(12.5)], [DETECTED, OCCLUDED, DELETED], lp, 1, 1,
        math.log(0.001), math.log(0.003),
    )  # fmt: skip
    assert math.exp(got) == pytest.approx(0.3 * 12.5 * 0.79 * 0.07 * 0.003 * 0.001 * 0.4)


def _enumerate(
    tm_loglik: np.ndarray, gated: np.ndarray, lp: np.ndarray, l_new: float, l_fal: float
) -> list[tuple[float, tuple[int, ...], tuple[int, ...], tuple[int, ...]]]:
    """All labelled assignments and their unnormalised log eq. 15 (parent 1)."""
    n, m = tm_loglik.shape
    out = []
    choices = [
        [("d", j) for j in range(m) if gated[i, j]] + [("o", -1), ("x", -1)] for i in range(n)
    ]
    for combo in itertools.product(*choices):
        used = [j for kind, j in combo if kind == "d"]
        if len(used) != len(set(used)):
            continue
        free_meas = [j for j in range(m) if j not in used]
        for meas_labels in itertools.product((NEW, FALSE_ALARM), repeat=len(free_meas)):
            labels = tuple({"d": DETECTED, "o": OCCLUDED, "x": DELETED}[k] for k, _ in combo)
            meas = tuple(j for _, j in combo)
            ml = [MATCHED] * m
            for j, lab in zip(free_meas, meas_labels, strict=True):
                ml[j] = lab
            w = log_child_weight(
                0.0,
                [tm_loglik[i, j] for i, (k, j) in enumerate(combo) if k == "d"],
                labels,
                lp,
                sum(1 for x in ml if x == NEW),
                sum(1 for x in ml if x == FALSE_ALARM),
                math.log(l_new),
                math.log(l_fal),
            )
            out.append((w, labels, meas, tuple(ml)))
    out.sort(key=lambda x: -x[0])
    return out


def test_k_best_children_matches_enumeration_of_eq15() -> None:
    rng = np.random.default_rng(4)
    n, m = 3, 3
    tm_ll = rng.normal(1.0, 1.5, (n, m))
    gated = rng.random((n, m)) < 0.7
    lp = np.log(np.array([[0.3, 0.63, 0.07], [0.2, 0.79, 0.01], [0.3, 0.63, 0.07]]))
    l_new, l_fal = 0.001, 0.003
    truth = _enumerate(tm_ll, gated, lp, l_new, l_fal)
    tm_cost = np.where(gated, -(lp[:, DETECTED, None] + tm_ll), np.inf)
    for limit in (0, 10_000):  # Murty and direct enumeration of matchings
        mat = build_matrix(tm_cost, lp, np.full(m, math.log(l_new)), np.full(m, math.log(l_fal)))
        got = k_best_children([0.0], [mat], k=len(truth) + 3, enumerate_limit=limit)
        assert len(got) == len(truth)
        np.testing.assert_allclose([-g[2] for g in got], [t[0] for t in truth], atol=1e-9)
        seen = {
            (tuple(g[1].track_label), g[1].track_measurement, tuple(g[1].measurement_label))
            for g in got
        }
        assert seen == {(t[1], t[2], t[3]) for t in truth}


def test_multi_parent_children_include_parent_probability() -> None:
    lp = np.log(np.array([[0.3, 0.63, 0.07]]))
    mat = build_matrix(np.array([[-(math.log(0.3) + 2.0)]]), lp, np.log([0.001]), np.log([0.003]))
    priors = [-math.log(0.7), -math.log(0.3)]
    got = k_best_children(priors, [mat, mat], k=100)
    assert len(got) == 2 * 5  # det; occ/del x new/fal, for both parents
    totals = [g[2] for g in got]
    assert totals == sorted(totals)
    best = got[0]
    assert best[0] == 0 and -best[2] == pytest.approx(math.log(0.7) + math.log(0.3) + 2.0)


def test_normalise_sums_to_one() -> None:
    w = normalise(np.array([-3.0, -1000.0, 5.0, 0.0]))
    assert np.exp(w).sum() == pytest.approx(1.0)


def test_lower_bound_never_exceeds_best_matching() -> None:
    from laserpeople.tracking.mht.matrix import enumerate_matchings

    rng = np.random.default_rng(9)
    for _ in range(200):
        n, m = int(rng.integers(0, 4)), int(rng.integers(0, 4))
        tm = rng.normal(0.0, 3.0, (n, m))
        tm[rng.random((n, m)) < 0.3] = np.inf
        lp = np.log(rng.dirichlet([1, 1, 1], n)) if n else np.empty((0, 3))
        mat = build_matrix(tm, lp, rng.normal(0, 2, m), rng.normal(0, 2, m))
        every = enumerate_matchings(mat, limit=10**6)
        assert every is not None
        assert mat.lower_bound() <= every[0].cost + 1e-9
