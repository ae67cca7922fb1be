"""AdaBoost of 000 Table 1 and the weak classifier of 000 eq. 1, against values computed by
hand (exact fractions in the comments); the five best features of Table 6 and the
hand-tuned baseline of Sec. 2.3.3 it is compared with.

Five examples of one feature, x = 1..5 with labels + + - + -: a = 3 positives, b = 2
negatives. The values tell Table 1 from its near misses: equal initial weights 1/N give a
first r of 0.6 (not 2/3), alpha without the 1/2 is log 5 (not log 5 / 2), an update with
the wrong sign or without the normalisation of step 1 gives another second round, and a
tie x = theta falls on the -1 side of eq. 1 for either polarity.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.detection.adaboost import AdaBoostLegClassifier, Stump
from laserpeople.detection.features import SegmentFeatures
from laserpeople.detection.heuristic import HeuristicLegClassifier
from laserpeople.detection.model_file import LegModel
from laserpeople.detection.report import best_features

X = np.array([[1.0], [2.0], [3.0], [4.0], [5.0]])
Y = np.array([1, 1, -1, 1, -1])
TOL = 1e-12


def test_round_one_initial_weights_r_and_alpha() -> None:
    """D_1 = 1/(2a) = 1/6 for positives, 1/(2b) = 1/4 for negatives. The best stump is
    x < 2.5 (p = +1): l h = (1, 1, 1, -1, 1), r = 1/6 + 1/6 + 1/4 - 1/6 + 1/4 = 2/3
    (x < 4.5 gives 1/2, x < 1.5 gives 1/3); alpha = 1/2 log((1 + 2/3) / (1 - 2/3)) =
    1/2 log 5."""
    clf = AdaBoostLegClassifier(n_rounds=1).fit(X, Y)
    (s,) = clf.stumps
    assert (s.feature, s.polarity) == (0, 1)
    assert s.threshold == pytest.approx(2.5, abs=TOL)
    assert s.r == pytest.approx(2.0 / 3.0, abs=TOL)  # equal weights 1/5 would give 0.6
    assert s.alpha == pytest.approx(0.5 * math.log(5.0), abs=TOL)


def test_round_two_after_the_weight_update() -> None:
    """Step 5: D_2 = D_1 exp(-alpha l h): the misclassified x = 4 grows by sqrt 5, the
    others shrink by sqrt 5; their sum is sqrt(5)/3, so after step 1 D_2 = (1/10, 1/10,
    3/20, 1/2, 3/20). The best stump is then x < 4.5: l h = (1, 1, -1, 1, 1), r = 0.1 +
    0.1 - 0.15 + 0.5 + 0.15 = 0.7 (unnormalised weights would give 0.7 sqrt(5)/3 = 0.52);
    alpha_2 = 1/2 log(1.7 / 0.3) = 1/2 log(17/3)."""
    clf = AdaBoostLegClassifier(n_rounds=2).fit(X, Y)
    first, second = clf.stumps
    assert first.threshold == pytest.approx(2.5, abs=TOL)
    assert (second.feature, second.polarity) == (0, 1)
    assert second.threshold == pytest.approx(4.5, abs=TOL)
    assert second.r == pytest.approx(0.7, abs=TOL)
    assert second.alpha == pytest.approx(0.5 * math.log(17.0 / 3.0), abs=TOL)


def test_strong_classifier_is_the_sign_of_the_weighted_vote() -> None:
    """F(e) = sum_t alpha_t h_t(e) with alpha_1 = log(5)/2, alpha_2 = log(17/3)/2: x = 1,
    2 get alpha_1 + alpha_2; x = 3, 4 get alpha_2 - alpha_1 = log(17/15)/2 > 0 (so x = 3
    is called a leg against its label); x = 5 gets -(alpha_1 + alpha_2)."""
    clf = AdaBoostLegClassifier(n_rounds=2).fit(X, Y)
    a1, a2 = 0.5 * math.log(5.0), 0.5 * math.log(17.0 / 3.0)
    want = np.array([a1 + a2, a1 + a2, a2 - a1, a2 - a1, -(a1 + a2)])
    np.testing.assert_allclose(clf.decision_function(X), want, rtol=TOL, atol=TOL)
    np.testing.assert_array_equal(clf.predict(X), [1, 1, 1, 1, -1])


def test_eq1_ties_fall_on_the_minus_side_for_both_polarities() -> None:
    """h(e) = +1 iff p f(e) < p theta: at f = theta it is -1 whether p is +1 or -1."""
    below = AdaBoostLegClassifier.from_stumps([Stump(0, 2.0, 1, 1.0, 0.5)], 1)
    above = AdaBoostLegClassifier.from_stumps([Stump(0, 2.0, -1, 1.0, 0.5)], 1)
    x = np.array([[1.0], [2.0], [3.0]])
    np.testing.assert_array_equal(below.decision_function(x), [1.0, -1.0, -1.0])
    np.testing.assert_array_equal(above.decision_function(x), [-1.0, -1.0, 1.0])
    # both together (two groups of one feature): at the threshold -2, elsewhere 0
    both = AdaBoostLegClassifier.from_stumps(
        [Stump(0, 2.0, 1, 1.0, 0.5), Stump(0, 2.0, -1, 1.0, 0.5)], 1
    )
    np.testing.assert_array_equal(both.decision_function(x), [0.0, -2.0, 0.0])


def test_a_margin_of_exactly_zero_is_not_a_leg() -> None:
    """H = sign(F): F = 0 has no sign; the binary classifier calls it -1 (not a leg), as the
    detector does (``score > score_threshold`` with 000's threshold 0)."""
    clf = AdaBoostLegClassifier.from_stumps(
        [Stump(0, 2.0, 1, 0.75, 0.5), Stump(1, 2.0, 1, 0.75, 0.5)], 2
    )
    x = np.array([[1.0, 3.0], [1.0, 1.0], [3.0, 3.0]])
    np.testing.assert_array_equal(clf.decision_function(x), [0.0, 1.5, -1.5])
    np.testing.assert_array_equal(clf.predict(x), [-1, 1, -1])


def test_polarity_minus_one_stump_is_learned_with_its_direction() -> None:
    """Labels - - + +: the best stump is p = -1 at theta = 2.5 (h = +1 iff x > 2.5), r = 1
    with D_1 = 1/4 each; training stops there (a perfect stump)."""
    x = np.array([[1.0], [2.0], [3.0], [4.0]])
    clf = AdaBoostLegClassifier(n_rounds=3).fit(x, [-1, -1, 1, 1])
    (s,) = clf.stumps
    assert (s.polarity, s.threshold) == (-1, pytest.approx(2.5))
    assert s.r == pytest.approx(1.0)
    np.testing.assert_array_equal(clf.predict(x), [-1, -1, 1, 1])


def test_table_6_best_features_are_the_stumps_of_largest_alpha() -> None:
    """Sec. 2.3.5: the five best features are those of the five weak classifiers of largest
    weight, a feature counted once per stump (Table 6 lists 4 twice for the corridor).
    Columns 0..12 are features 1..13."""
    alphas = {(8, 1.0): 0.9, (3, 1.0): 0.7, (4, 1.0): 0.3, (1, 1.0): 0.5, (3, 2.0): 0.6}
    stumps = [Stump(j, th, 1, a, 0.5) for (j, th), a in alphas.items()]
    stumps.append(Stump(12, 1.0, 1, 0.1, 0.5))
    model = LegModel(AdaBoostLegClassifier.from_stumps(stumps, 13), tuple(range(1, 14)), 0.1)
    assert best_features(model, k=5) == [9, 4, 4, 2, 5]


def _heuristic(**change: float) -> int:
    """The baseline's decision on one segment that passes every rule of Sec. 2.3.3 with
    the values ``change`` put in (``jump_prev``, ``jump_next``, ``width``, ``n``,
    ``motion`` [m], ``std``, ``speed`` [m/s])."""
    v = {"n": 5.0, "std": 0.05, "mad": 0.04, "jump_prev": 0.5, "jump_next": 0.5}
    v.update({"width": 0.12, "motion": 0.05, "speed": 0.0})
    v.update(change)
    row = np.zeros(14)
    row[[0, 1, 2, 3, 4, 5, 13]] = [
        v[k] for k in ("n", "std", "mad", "jump_prev", "jump_next", "width", "speed")
    ]
    feats = SegmentFeatures(
        row[None, :], np.array([v["motion"]]), np.zeros((1, 2)), np.zeros((1, 2))
    )
    return int(HeuristicLegClassifier().predict(feats)[0])


def test_heuristic_baseline_of_section_2_3_3() -> None:
    """Both jumps over 30 cm, width between 5 and 50 cm, at least four points (fewer than
    four are discarded), some beam moved more than 2 cm, standard deviation (feature 2, not
    3) below 0.5 m."""
    assert _heuristic() == 1
    assert _heuristic(n=4.0) == 1 and _heuristic(n=3.0) == -1
    assert _heuristic(jump_prev=0.29) == -1 and _heuristic(jump_next=0.29) == -1
    assert _heuristic(width=0.04) == -1 and _heuristic(width=0.51) == -1
    assert _heuristic(width=0.06) == 1 and _heuristic(width=0.49) == 1
    # the motion of a beam [m], not the mean speed (feature 14, m/s)
    assert _heuristic(motion=0.01, speed=1.0) == -1 and _heuristic(motion=0.03) == 1
    assert _heuristic(std=0.6, mad=0.1) == -1 and _heuristic(std=0.1, mad=0.6) == 1
