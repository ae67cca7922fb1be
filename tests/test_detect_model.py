"""Model files, the detectors and the heuristic baseline."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from laserpeople.detection.adaboost import AdaBoostLegClassifier
from laserpeople.detection.detector import (
    AdaBoostLegDetector,
    HeuristicLegDetector,
    LegDetectorParams,
    default_model,
)
from laserpeople.detection.features import SegmentFeatures
from laserpeople.detection.heuristic import HeuristicLegClassifier
from laserpeople.detection.model_file import (
    MODEL_FORMAT,
    LegModel,
    load_model,
    parse_feature_set,
)
from laserpeople.errors import ModelFileError
from laserpeople.scan import Scan


def leg_scan(stamp: float, leg_x: float, index: int = 0) -> Scan:
    """A wall at 4 m and a 6 cm-radius leg at (leg_x, 0), 0.5 deg beams over 180 deg."""
    inc = math.radians(0.5)
    angles = -math.pi / 2 + np.arange(361) * inc
    ranges = 4.0 / np.maximum(np.cos(angles), 0.05)
    ranges = np.minimum(ranges, 8.0)
    # ray-circle intersection with the leg
    r, d = 0.06, leg_x
    disc = r**2 - (d * np.sin(angles)) ** 2
    hit = (disc > 0) & (np.cos(angles) > 0)
    ranges = np.where(hit, d * np.cos(angles) - np.sqrt(np.where(hit, disc, 0.0)), ranges)
    return Scan(stamp, -math.pi / 2, inc, ranges, index=index, range_max=10.0)


def toy_model() -> LegModel:
    X = np.array([[0.06], [0.07], [0.05], [0.5], [1.0], [2.0]])
    y = np.array([1, 1, 1, -1, -1, -1])
    clf = AdaBoostLegClassifier(3).fit(X, y)
    return LegModel(clf, (9,), 0.1, {"note": "test"})


def test_model_round_trip(tmp_path: Path) -> None:
    model = toy_model()
    path = tmp_path / "m.json"
    model.save(path)
    loaded = load_model(path)
    assert loaded.features == (9,)
    X = np.array([[0.04], [0.3], [3.0]])
    np.testing.assert_allclose(
        loaded.classifier.decision_function(X), model.classifier.decision_function(X)
    )
    assert loaded.training == {"note": "test"}


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("not json", "not JSON"),
        ('{"format": "something-else", "version": 1}', "not a laserpeople leg model"),
        (json.dumps({"format": MODEL_FORMAT, "version": 99}), "newer"),
        (json.dumps({"format": MODEL_FORMAT, "version": 1, "features": [0]}), "features"),
        (
            json.dumps(
                {
                    "format": MODEL_FORMAT,
                    "version": 1,
                    "features": [9],
                    "segmentation": {"threshold": 0.1},
                    "stumps": [{"feature": 3, "threshold": 1, "polarity": 1, "alpha": 1}],
                }
            ),
            "not in 'features'",
        ),
    ],
)
def test_bad_model_files_raise(tmp_path: Path, content: str, message: str) -> None:
    path = tmp_path / "bad.json"
    path.write_text(content)
    with pytest.raises(ModelFileError, match=message) as info:
        load_model(path)
    assert str(path) in str(info.value)


def test_missing_model_file(tmp_path: Path) -> None:
    with pytest.raises(ModelFileError, match="not found"):
        load_model(tmp_path / "nope.json")


def test_feature_sets() -> None:
    assert parse_feature_set("1-13") == tuple(range(1, 14))
    assert parse_feature_set("1-14") == tuple(range(1, 15))
    assert parse_feature_set("9, 4,5") == (9, 4, 5)
    with pytest.raises(ValueError):
        parse_feature_set("0-15")


def test_shipped_default_model_loads_and_is_documented() -> None:
    model = default_model()
    assert model.features == tuple(range(1, 14))
    assert len(model.classifier.stumps) >= 10
    assert "data" in model.training and "created" in model.training
    # leg_tracker label rule and the protocol are recorded
    assert model.segmentation_threshold == pytest.approx(0.13)
    assert "unlabelled segments dropped" in str(model.training["negatives_protocol"])
    # T is the candidate of lowest mean validation error, recorded with the sweep
    sweep = model.training["rounds_selection"]["validation_error_percent"]
    mean = {int(t): float(np.mean(list(e.values()))) for t, e in sweep.items()}
    assert model.training["rounds"] == min(mean, key=mean.__getitem__)
    assert len(model.classifier.stumps) == model.training["rounds"]


def test_adaboost_detector_finds_the_leg_in_sensor_frame() -> None:
    det = AdaBoostLegDetector(toy_model(), LegDetectorParams(leg_position_std=0.2))
    d = det.detect(leg_scan(0.0, 1.5, index=7))
    assert len(d) == 1
    assert d.scan_index == 7 and d.frame == "sensor"
    # the centroid of the visible arc is moved back by centre_offset onto the leg's axis
    assert d.positions[0, 0] == pytest.approx(1.5, abs=0.02)
    assert d.positions[0, 1] == pytest.approx(0.0, abs=0.01)
    np.testing.assert_allclose(d.covariances[0], np.diag([0.04, 0.04]))
    assert d.scores[0] > 0
    assert len(d.segments) == 1 and len(d.segments[0]) >= 3


def test_distance_limits_leave_segments_unclassified() -> None:
    scan = leg_scan(0.0, 1.5)  # the leg's centroid is ~1.46 m from the sensor
    for limits, found in (
        ({"min_distance": 1.4}, 1),
        ({"min_distance": 1.5}, 0),
        ({"max_distance": 1.5}, 1),
        ({"max_distance": 1.4}, 0),
    ):
        det = AdaBoostLegDetector(toy_model(), LegDetectorParams(**limits))
        result = det.classify(scan)
        assert int(result.is_leg.sum()) == found, limits
        if not found:
            assert np.isnan(result.scores[result.features.classifiable]).any()
    with pytest.raises(ValueError, match="min_distance"):
        LegDetectorParams(min_distance=2.0, max_distance=1.0)


def test_default_detector_runs_and_keeps_previous_scan() -> None:
    det = AdaBoostLegDetector.default()
    det.detect(leg_scan(0.0, 1.5))
    result = det.classify(leg_scan(0.1, 1.6, index=1))
    assert result.features.values[:, 13].any()  # motion feature saw the previous scan
    assert np.isnan(result.scores[~result.features.classifiable]).all()


def test_heuristic_rules_of_sec_2_3_3() -> None:
    base = np.zeros((1, 14))
    base[0, [0, 1, 3, 4, 5]] = [5, 0.05, 1.0, 1.0, 0.1]
    motion = np.array([0.05])
    clf = HeuristicLegClassifier()

    def decide(values: np.ndarray, moved: np.ndarray = motion) -> int:
        f = SegmentFeatures(values, moved, np.zeros((1, 2)), np.zeros((1, 2)))
        return int(clf.predict(f)[0])

    assert decide(base) == 1
    for col, value in ((3, 0.2), (4, 0.2), (5, 0.04), (5, 0.6), (0, 3), (1, 0.6)):
        changed = base.copy()
        changed[0, col] = value
        assert decide(changed) == -1, (col, value)
    assert decide(base, np.array([0.01])) == -1  # a person standing still is missed


def test_heuristic_detector_needs_motion() -> None:
    det = HeuristicLegDetector()
    assert len(det.detect(leg_scan(0.0, 1.5))) == 0  # no previous scan: no motion
    d = det.detect(leg_scan(0.1, 1.6, index=1))
    assert len(d) == 1 and d.scores[0] == 1.0


def test_detections_csv_round_trip(tmp_path: Path) -> None:
    from laserpeople.io.detections_csv import DetectionsCsvWriter, iter_detections_csv

    det = AdaBoostLegDetector(toy_model())
    path = tmp_path / "d.csv"
    with DetectionsCsvWriter(path) as writer:
        for i in range(3):
            writer.write(det.detect(leg_scan(0.1 * i, 1.5 + 0.05 * i, index=i)))
    rows = list(iter_detections_csv(path))
    assert [r["scan"] for r in rows] == [0, 1, 2]
    assert rows[2]["x"] == pytest.approx(1.6, abs=0.02)
    assert rows[1]["stamp"] == pytest.approx(0.1)
    assert all(r["score"] > 0 for r in rows)
