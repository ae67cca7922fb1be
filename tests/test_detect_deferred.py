"""Leg detection's deferred features: features 3 and 8 (the vector of medians, the circle
residuals) computed only for the segments whose AdaBoost margin can still pass the
threshold, judged by the margin's upper bound with their stumps at their best.

The bound (``AdaBoostLegClassifier.margin_bounds``) is checked by hand on a small model
and against the margins on random models and rows (never below, exactly: rounded addition
is monotone: margin and bound are summed by the same code in the same order); the
deferred features against the full ones and the detections against those of the full
classification on simulated scenes, compiled and in pure Python: the same legs, floats
within TOL (the same code on this machine gives the same bits; no test relies on it).
"""

from __future__ import annotations

from types import ModuleType

import numpy as np
import pytest

from laserpeople import extensions
from laserpeople.detection import adaboost, compiled, features
from laserpeople.detection.adaboost import AdaBoostLegClassifier, Stump
from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.scan import Scan
from laserpeople.segmentation import covers_full_circle

TOL = 1e-12
"""Tolerance of float comparisons: features [m, rad and their products], margins."""


@pytest.fixture(params=["compiled", "python"])
def path(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> str:
    """Both paths: the extension where built, and the Python references."""
    if request.param == "python":
        monkeypatch.setattr(adaboost, "_extension", None)
        monkeypatch.setattr(features, "_extension", None)
    elif compiled.EXTENSION is None:
        pytest.skip("the C extension is not built")
    return str(request.param)


def _small_model() -> AdaBoostLegClassifier:
    return AdaBoostLegClassifier.from_stumps(
        [
            Stump(0, 1.0, 1, 0.5, 0.5),
            Stump(0, 2.0, -1, 0.25, 0.25),
            Stump(1, 0.0, 1, 1.0, 0.7),
            Stump(1, 3.0, 1, 0.125, 0.1),
        ],
        2,
    )


def test_margin_bounds_by_hand(path: str) -> None:
    """x = (0.5, 5): margin 0.5 - 0.25 - 1 - 0.125 = -0.875. Column 1 unknown: its group
    at its best (x < 0: 1 + 0.125) gives 0.25 + 1.125 = 1.375 (not the margin, not its
    worst -0.875 nor 0.25 without it); column 0 unknown: 0.5 + 0.25 - 1.125 = -0.375.
    x = (3, -1): margin -0.5 + 0.25 + 1 + 0.125 = 0.875, already at its best in column 1."""
    clf = _small_model()
    X = np.array([[0.5, 5.0], [3.0, -1.0]])
    np.testing.assert_allclose(clf.decision_function(X), [-0.875, 0.875], rtol=0.0, atol=TOL)
    np.testing.assert_allclose(clf.margin_bounds(X, (1,)), [1.375, 0.875], rtol=0.0, atol=TOL)
    np.testing.assert_allclose(clf.margin_bounds(X, (0,)), [-0.375, 1.875], rtol=0.0, atol=TOL)
    np.testing.assert_allclose(
        clf.margin_bounds(X, ()), clf.decision_function(X), rtol=0.0, atol=TOL
    )
    np.testing.assert_allclose(clf.margin_bounds(X, (0, 1)), [1.875, 1.875], rtol=0.0, atol=TOL)
    # the unknown columns are not read
    Y = X.copy()
    Y[:, 1] = [-7.0, 9.0]
    np.testing.assert_allclose(
        clf.margin_bounds(Y, (1,)), clf.margin_bounds(X, (1,)), rtol=0.0, atol=TOL
    )


@pytest.mark.parametrize("seed", range(3))
def test_margins_never_exceed_their_bounds(path: str, seed: int) -> None:
    """On a model of 60 rounds over 5 features and 400 random rows, whatever the unknown
    column holds: margin <= bound, exactly (no tolerance); some bounds are below 0 (the
    bound decides), and a second unknown column raises some."""
    rng = np.random.default_rng(seed)
    X = rng.normal(size=(300, 5))
    y = np.where(X[:, 0] + 0.5 * X[:, 2] - X[:, 4] + 0.3 * rng.normal(size=300) > 0, 1, -1)
    clf = AdaBoostLegClassifier(n_rounds=60).fit(X, y)
    rows = rng.normal(size=(400, 5))
    unknown = (2,)
    bounds = clf.margin_bounds(rows, unknown)
    for _ in range(20):
        filled = rows.copy()
        filled[:, 2] = rng.normal(scale=3.0, size=400)
        assert np.all(clf.decision_function(filled) <= bounds)
    assert np.count_nonzero(bounds < 0.0) > 40
    assert np.count_nonzero(bounds < clf.margin_bounds(rows, (2, 4))) > 40


def _block(
    seed: int,
) -> tuple[list[Scan], list[Scan | None], AdaBoostLegDetector]:
    from laserpeople.sim import run_scenario

    scans = run_scenario("crossing-3", seconds=2.0, seed=seed).scans[:32]
    previous: list[Scan | None] = [None, *scans[:-1]]
    return scans, previous, AdaBoostLegDetector.default()


def test_deferred_features_complete_to_the_full_ones(cfeatures: ModuleType) -> None:
    """Compiled: the deferred block's features are the full ones (within TOL) but for
    columns 3 and 8 (NaN: all of column 3, column 8 where there is a circle); completing
    some rows gives those rows' full features and leaves the others NaN."""
    if extensions.forced_pure_python():
        pytest.skip(f"{extensions.PURE_PYTHON} forces the Python features")
    scans, previous, det = _block(4)
    block = det.segmenter.block(scans)
    args = (
        block.tables,
        scans,
        previous,
        det.feature_params,
        [covers_full_circle(s) for s in scans],
        (block.points, block.offsets),
    )
    full = features.compute_features_joined(*args)
    deferred = features.compute_features_deferred(*args)
    got = deferred.features
    keep = [c for c in range(features.N_FEATURES) if c not in features.DEFERRED]
    np.testing.assert_allclose(got.values[:, keep], full.values[:, keep], rtol=0.0, atol=TOL)
    for name in ("max_beam_motion", "centres", "circle_centres"):
        np.testing.assert_allclose(getattr(got, name), getattr(full, name), rtol=0.0, atol=TOL)
    circle = ~np.isnan(full.circle_centres[:, 0])
    assert circle.any() and (~circle).any()
    # (which features are left out, NaN, compared with where the full pass found a circle:
    # a yes/no per row, not a float)
    assert np.isnan(got.values[:, 2]).all()
    np.testing.assert_array_equal(np.isnan(got.values[:, 7]), circle)
    rows = np.arange(0, len(full), 3)
    deferred.complete(rows)
    np.testing.assert_allclose(got.values[rows], full.values[rows], rtol=0.0, atol=TOL)
    rest = np.setdiff1d(np.arange(len(full)), rows)
    assert np.isnan(got.values[rest, 2]).all()
    np.testing.assert_array_equal(np.isnan(got.values[rest, 7]), circle[rest])


@pytest.mark.parametrize("seed", [1, 7])
def test_the_same_detections_as_the_full_classification(path: str, seed: int) -> None:
    """What the user sees: the legs of blocks of 16 scans (detect_many, the deferred
    features) are those of the full classification, positions and scores within TOL;
    and the bound rules out many segments, none of them a leg."""
    scans, _, det = _block(seed)
    full = AdaBoostLegDetector.default()
    ruled_out = classifiable = legs = 0
    for start in (0, 16):
        part = scans[start : start + 16]
        got = det.detect_many(part)
        for scan, result, dets in zip(part, full.classify_many(part), got, strict=True):
            want = full.detections_from(scan, result)
            assert len(dets.scores) == len(want.scores)  # (the same legs)
            np.testing.assert_allclose(dets.positions, want.positions, rtol=0.0, atol=TOL)
            np.testing.assert_allclose(dets.scores, want.scores, rtol=0.0, atol=TOL)
            legs += len(want.scores)
            rows = np.flatnonzero(result.features.classifiable)
            passes = det._may_pass(result.features, rows)
            assert not np.any(~passes & result.is_leg[rows])
            ruled_out += int(np.count_nonzero(~passes))
            classifiable += rows.size
    assert legs > 50
    assert ruled_out > classifiable // 4


def test_a_threshold_above_the_bounds_finds_no_leg(path: str) -> None:
    """The bound is compared with the detector's own threshold: at 1e9 nothing passes and
    no leg is found; at -1e9 every classifiable segment passes."""
    scans, _, _ = _block(2)
    high = AdaBoostLegDetector.default(LegDetectorParams(score_threshold=1e9))
    low = AdaBoostLegDetector.default(LegDetectorParams(score_threshold=-1e9))
    assert sum(len(d.scores) for d in high.detect_many(scans[:16])) == 0
    result = low.classify_many(scans[:16])[0]
    rows = np.flatnonzero(result.features.classifiable)
    assert low._may_pass(result.features, rows).all()
    assert not high._may_pass(result.features, rows).any()
