"""The detector on real labelled legs and through the command line."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.detection.features import FEATURE_NAMES
from laserpeople.detection.training import (
    LabelledSegments,
    leg_tracker_positive,
    neko_segments,
    read_pose_arrays,
)
from laserpeople.io import open_recording
from laserpeople.io.detections_csv import HEADER, SEGMENT_COLUMNS, iter_detections_csv
from laserpeople.io.neko import read_neko
from laserpeople.segmentation import JumpDistanceParams, JumpDistanceSegmenter

FEATURE_COLUMNS = tuple(f"f{i + 1}_{name}" for i, name in enumerate(FEATURE_NAMES))

LT = "leg_tracker/rosbags/training_scans_res=0.33"


def test_neko_segmentation_reproduces_the_label_rule(shared_data: Path) -> None:
    data = read_neko(shared_data / "neko7055")
    assert len(data.scans) == 120 and data.scans[0].n_beams == 720
    seg = JumpDistanceSegmenter(JumpDistanceParams(threshold=0.1, wrap_around=True))
    counts = [len(seg(s)) for s in data.scans]
    legs = sum(len(v) for v in data.leg_segments.values())
    # README: 231 legs among 2919 segments; every labelled index must exist
    assert sum(counts) == 2919 and legs == 231
    assert all(max(v, default=-1) < counts[int(k)] for k, v in data.leg_segments.items())


def test_adaboost_on_neko_held_out_frames(shared_data: Path) -> None:
    from laserpeople.detection.report import Confusion, heuristic_predictions, train_model

    data = neko_segments(shared_data / "neko7055")
    train, test = data.select(data.scan < 60), data.select(data.scan >= 60)
    model = train_model(train, tuple(range(1, 14)), 10, 0.1)
    c = Confusion.of(model.classifier.predict(test.features[:, :13]), test.labels)
    h = Confusion.of(heuristic_predictions(test), test.labels)
    assert c.overall_error < 5.0 and c.detection_rate > 95.0
    assert c.overall_error < h.overall_error


def test_leg_tracker_labels_match_segments(shared_data: Path) -> None:
    part = leg_tracker_positive(shared_data / LT / "positive_2_extracted.bag")
    # 116 labelled leg centres in 83 scans; with the 0.13 m rule nearly every one is the
    # centre of one segment of >= 3 points; unlabelled segments are dropped by default
    assert 105 <= part.n_positive <= 120
    assert part.n_negative == 0
    old = leg_tracker_positive(
        shared_data / LT / "positive_2_extracted.bag",
        unlabelled="negative",
        segmentation=JumpDistanceParams(threshold=0.1),
    )
    assert old.n_negative > 10 * old.n_positive
    both = LabelledSegments.concat([part, old])
    assert both.groups == ("positive_2_extracted.bag",)


def test_leg_tracker_labels_are_centres_of_013_segments(shared_data: Path) -> None:
    """The labels are cluster centres under a 0.13 m rule, not under 0.1 m."""
    bag = shared_data / LT / "positive_2_extracted.bag"
    poses = read_pose_arrays(bag, "/leg_cluster_positions")
    rec = open_recording(bag)
    try:
        scans = list(rec.scans(["/training_scan"]))
    finally:
        rec.close()
    exact = {}
    for threshold in (0.1, 0.13):
        seg = JumpDistanceSegmenter(JumpDistanceParams(threshold=threshold))
        hits = 0
        for scan, labels in zip(scans, poses, strict=True):
            c = seg(scan).centres()
            for label in labels:
                hits += int(np.hypot(*(c - label).T).min() < 1e-3)
        exact[threshold] = hits / sum(len(p) for p in poses)
    assert exact[0.13] > 0.9
    assert exact[0.1] < exact[0.13] - 0.05


def test_cli_detect_writes_csv(shared_data: Path, tmp_path: Path) -> None:
    out = tmp_path / "det.csv"
    bag = shared_data / LT / "positive_2_extracted.bag"
    result = CliRunner().invoke(app, ["--quiet", "detect", str(bag), "-o", str(out)])
    assert result.exit_code == 0, result.output
    with out.open() as fh:
        rows = list(csv.reader(fh))
    assert tuple(rows[0]) == (*HEADER, "topic")
    assert len(rows) > 83  # at least about one leg per scan
    parsed = list(iter_detections_csv(out))
    assert {r["scan"] for r in parsed} <= set(range(83))
    assert all(np.isfinite([r["x"], r["y"], r["score"]]).all() for r in parsed)
    allseg = tmp_path / "all.csv"
    result = CliRunner().invoke(
        app, ["--quiet", "detect", str(bag), "-o", str(allseg), "--all-segments"]
    )
    assert result.exit_code == 0, result.output
    rows2 = list(iter_detections_csv(allseg))
    assert set(rows2[0]) == {*HEADER, *SEGMENT_COLUMNS, *FEATURE_COLUMNS, "topic"}
    assert sum(int(r["is_leg"]) for r in rows2) == len(rows) - 1


def test_cli_detect_heuristic_and_bad_model(shared_data: Path, tmp_path: Path) -> None:
    bag = shared_data / LT / "positive_2_extracted.bag"
    out = tmp_path / "det.csv"
    ok = CliRunner().invoke(
        app, ["--quiet", "detect", str(bag), "-o", str(out), "--detector", "heuristic"]
    )
    assert ok.exit_code == 0, ok.output
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"format": "other"}))
    from laserpeople.errors import ModelFileError

    res = CliRunner().invoke(
        app, ["--quiet", "detect", str(bag), "-o", str(out), "--model", str(bad)]
    )
    assert isinstance(res.exception, ModelFileError)


def test_cli_train_and_report(shared_data: Path, tmp_path: Path) -> None:
    out = tmp_path / "model.json"
    lt = shared_data / LT
    result = CliRunner().invoke(
        app,
        [
            "--quiet",
            "train",
            "--positives",
            str(lt / "positive_2_extracted.bag"),
            "--neko",
            str(shared_data / "neko7055"),
            "--neko-frames",
            "0-59",
            "--test-neko-frames",
            "60-119",
            "--rounds",
            "12",
            "--features",
            "1-14",
            "--report",
            "-o",
            str(out),
        ],
    )
    assert result.exit_code == 0, result.output
    doc = json.loads(out.read_text())
    assert doc["features"] == list(range(1, 15)) and len(doc["stumps"]) == 12
    assert doc["training"]["rounds"] == 12
    for text in ("Tables 2-5", "Table 7", "Table 8", "Table 6", "test set", "by distance"):
        assert text in result.stdout
    assert np.isfinite([s["alpha"] for s in doc["stumps"]]).all()


def test_cli_train_and_detect_report_on_simulated_truth(tmp_path: Path) -> None:
    sim = pytest.importorskip("laserpeople.sim")
    rec = tmp_path / "office.npz"
    sim.run_scenario("office", seconds=4, seed=3).write(rec)
    model = tmp_path / "m.json"
    res = CliRunner().invoke(app, ["--quiet", "train", str(rec), "-o", str(model)])
    assert res.exit_code == 0, res.output
    res = CliRunner().invoke(
        app,
        [
            "--quiet",
            "detect",
            str(rec),
            "-o",
            str(tmp_path / "d.csv"),
            "--model",
            str(model),
            "--report",
        ],
    )
    assert res.exit_code == 0, res.output
    assert "Table 7" in res.stdout and "AdaBoost" in res.stdout


def test_cli_detect_config_sets_distance_limits(tmp_path: Path) -> None:
    sim = pytest.importorskip("laserpeople.sim")
    rec = tmp_path / "demo.npz"
    sim.run_scenario("demo", seconds=2, seed=1).write(rec)
    rows = {}
    # one file for every command: detect ignores the tracker's section, not a misspelt one
    shared = "[leg_detector]\nmax_distance = 0.3\n[leg_tracker]\nmax_report_unseen = 2.0\n"
    for name, text in (("none", ""), ("near", shared)):
        cfg = tmp_path / f"{name}.toml"
        cfg.write_text(text)
        out = tmp_path / f"{name}.csv"
        res = CliRunner().invoke(
            app, ["--quiet", "detect", str(rec), "-o", str(out), "--config", str(cfg)]
        )
        assert res.exit_code == 0, res.output
        rows[name] = len(out.read_text().splitlines()) - 1
    assert rows["none"] > 10 and rows["near"] == 0
    from laserpeople.errors import ConfigError

    bad = tmp_path / "bad.toml"
    bad.write_text("[leg_detectr]\nmin_distance = 1.0\n")
    res = CliRunner().invoke(
        app, ["detect", str(rec), "-o", str(tmp_path / "x.csv"), "--config", str(bad)]
    )
    assert isinstance(res.exception, ConfigError) and "leg_detectr" in str(res.exception)
    bad.write_text("[leg_detector]\nmin_distance = -1.0\n")
    res = CliRunner().invoke(
        app, ["detect", str(rec), "-o", str(tmp_path / "x.csv"), "--config", str(bad)]
    )
    assert isinstance(res.exception, ConfigError) and "min_distance" in str(res.exception)
