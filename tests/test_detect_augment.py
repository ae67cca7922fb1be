"""Resampling labelled scans to other scanners (detection/augment.py), by hand."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from laserpeople.detection.augment import (
    Variant,
    beam_classes,
    resample_scan,
    segment_labels_from_beams,
    variants,
)
from laserpeople.detection.training import (
    all_negative_classes,
    augmented_segments,
    classed_segments,
    leg_tracker_positive,
    leg_tracker_positive_classes,
    neko_classes,
    neko_segments,
)
from laserpeople.errors import RecordingError
from laserpeople.scan import Scan
from laserpeople.segmentation import JumpDistanceParams, jump_distance_table

DEG = math.radians(1.0)


def five_beams() -> Scan:
    # beams at 0..4 deg; a surface at ~1 m, a jump to ~2 m, one beam without return
    return Scan(0.0, 0.0, DEG, np.array([1.0, 1.02, 2.0, 2.01, np.nan]), range_max=10.0)


def test_finer_increment_interpolates_on_surfaces_and_keeps_edges() -> None:
    classes = np.array([1, 1, -1, -1, 0])
    new, cls = resample_scan(five_beams(), 0.5 * DEG, beam_class=classes)
    # (5 - 1) / 0.5 + 1 = 9 beams at 0, 0.5, ..., 4 deg
    assert new.n_beams == 9 and new.angle_increment == pytest.approx(0.5 * DEG)
    # 1.01 = mean of 1 and 1.02 (same surface); between 1.02 and 2 (a jump of 0.98 m) and
    # between 2.01 and no return the nearest beam is taken (f = 0.5 rounds up)
    expect = [1.0, 1.01, 1.02, 2.0, 2.0, 2.005, 2.01, np.nan, np.nan]
    np.testing.assert_allclose(new.ranges, expect)
    np.testing.assert_array_equal(cls, [1, 1, 1, -1, -1, -1, -1, 0, 0])


def test_coarser_increment_and_world_scale() -> None:
    new, cls = resample_scan(five_beams(), 2.0 * DEG, range_scale=2.0)
    # beams at 0, 2, 4 deg: source beams 0, 2, 4; every range doubled, limits too
    np.testing.assert_allclose(new.ranges, [2.0, 4.0, np.nan])
    np.testing.assert_array_equal(cls, [-1, -1, -1])
    assert new.range_max == 20.0
    # the points of a scaled scan are the source points times s
    same, _ = resample_scan(five_beams(), DEG, range_scale=1.5)
    src = five_beams()
    np.testing.assert_allclose(same.points()[:4], 1.5 * src.points()[:4])


def test_same_increment_is_the_identity_and_sign_is_kept() -> None:
    src = Scan(0.0, 1.0, -DEG, np.array([3.0, 3.1, np.inf, 0.5]))
    new, _ = resample_scan(src, DEG)
    assert new.angle_increment == -DEG and new.angle_min == 1.0
    np.testing.assert_allclose(new.ranges[[0, 1, 3]], src.ranges[[0, 1, 3]])
    assert not new.valid[2]


def test_full_circle_wraps_between_last_and_first_beam() -> None:
    # 8 beams at 45 deg: ranges 1..1.035 (one surface); 12 beams at 30 deg
    ranges = 1.0 + 0.005 * np.arange(8)
    src = Scan(0.0, -math.pi, math.radians(45.0), ranges)
    new, _ = resample_scan(src, math.radians(30.0))
    assert new.n_beams == 12
    # beam 11 at u = 11 * 2/3 = 7.333 source beams: between beam 7 (1.035) and beam 0 (1.0)
    assert new.ranges[11] == pytest.approx(1.035 + (1.0 - 1.035) / 3.0)
    # beam 3 at u = 2: exactly source beam 2
    assert new.ranges[3] == pytest.approx(1.01)


def test_bad_arguments_raise() -> None:
    with pytest.raises(ValueError, match="increment"):
        resample_scan(five_beams(), 0.0)
    with pytest.raises(ValueError, match="range_scale"):
        resample_scan(five_beams(), DEG, range_scale=-1.0)
    with pytest.raises(ValueError, match="classes"):
        resample_scan(five_beams(), DEG, beam_class=np.zeros(3, dtype=np.int64))


def table_of(n_beams: int, beams: list[int], offsets: list[int]) -> object:
    pts = np.zeros((len(beams), 2))
    pts[:, 0] = np.arange(len(beams))
    from laserpeople.segmentation import SegmentTable

    return SegmentTable(np.array(beams), pts, np.array(offsets), n_beams)


def test_beam_classes_and_back() -> None:
    # 8 beams; segments [0, 1, 2], [4, 5], [6, 7, 0'] (beam 3 had no return)
    from laserpeople.segmentation import SegmentTable

    table = table_of(8, [0, 1, 2, 4, 5, 6, 7], [0, 3, 5, 7])
    assert isinstance(table, SegmentTable)
    classes = beam_classes(table, np.array([1, 0, -1]))
    np.testing.assert_array_equal(classes, [1, 1, 1, 0, 0, 0, -1, -1])
    np.testing.assert_array_equal(segment_labels_from_beams(table, classes), [1, 0, -1])
    # mixed segments: 2 of 3 leg beams -> leg; 1 of 2 leg beams is not more than half and
    # both are known -> not a leg; one unknown beam among non-legs -> unknown
    mixed = np.array([1, 1, -1, -1, 1, 0, -1, -1])
    t2 = table_of(8, [0, 1, 2, 3, 4, 5, 6, 7], [0, 3, 5, 8])
    assert isinstance(t2, SegmentTable)
    np.testing.assert_array_equal(segment_labels_from_beams(t2, mixed), [1, -1, 0])


def test_variants_grid() -> None:
    vs = variants([0.5, 1.0], [1.0, 2.0])
    assert len(vs) == 4 and vs[3] == Variant(math.radians(1.0), 2.0)
    assert vs[1].name == "0.50deg x2"


def test_classed_segments_of_resampled_legs_are_labelled() -> None:
    # a "leg": 0.12 m arc of points at 1 m in front of a far wall, 0.5 deg beams
    inc = math.radians(0.5)
    angles = np.arange(-40, 41) * inc
    ranges = np.full(angles.size, 4.0)
    leg = np.abs(angles) < 0.06
    ranges[leg] = 1.0
    scan = Scan(0.0, float(angles[0]), inc, ranges)
    classes = np.where(leg, 1, -1)
    data = augmented_segments(
        [(scan, classes)], "toy", variants([0.25, 0.5, 1.0], [1.0, 2.0]), JumpDistanceParams(0.1)
    )
    legs = data.select(data.labels > 0)
    # one leg per variant; its point count follows the increment, its range the scale
    assert legs.n_positive == 6
    n = legs.features[:, 0]
    # (variants run increment by increment: 0.25 x1, 0.25 x2, 0.5 x1, ...)
    np.testing.assert_array_equal(n[0::2], n[1::2])
    assert n[0] > n[2] > n[4]
    np.testing.assert_allclose(legs.distance, np.tile([1.0, 2.0], 3), rtol=0.02)
    assert data.n_negative >= 6


def test_classed_scans_reproduce_the_real_labels(shared_data: Path) -> None:
    # the identity variant of the beam-class form gives exactly the segment labels
    frames = range(0, 10)
    got = classed_segments(
        neko_classes(shared_data / "neko7055", frames),
        "neko7055",
        JumpDistanceParams(threshold=0.1, wrap_around=True),
    )
    want = neko_segments(shared_data / "neko7055", frames)
    np.testing.assert_array_equal(got.labels, want.labels)
    np.testing.assert_allclose(got.features, want.features)
    bag = shared_data / "leg_tracker/rosbags/training_scans_res=0.33/positive_2_extracted.bag"
    got_lt = classed_segments(leg_tracker_positive_classes(bag), "p2", JumpDistanceParams(0.13))
    want_lt = leg_tracker_positive(bag)
    assert got_lt.n_positive == want_lt.n_positive and got_lt.n_negative == 0
    neg = all_negative_classes(
        shared_data / "leg_tracker/rosbags/training_scans_res=0.33/negative_2.bag", ["/rear_scan"]
    )
    assert all(set(np.unique(c)) <= {-1, 0} for _, c in neg[:20])


def test_jump_table_helper_used_in_toys_is_consistent() -> None:
    # the toy leg above is its own segment under a 0.1 m jump distance
    pts = np.array([[1.0, 0.0], [1.0, 0.01], [4.0, 0.0]])
    t = jump_distance_table(pts, np.arange(3), 3, 0.1)
    assert len(t) == 2


def test_cli_train_augment(tmp_path: Path) -> None:
    from typer.testing import CliRunner

    from laserpeople.cli import app

    sim = pytest.importorskip("laserpeople.sim")
    rec = tmp_path / "office.npz"
    sim.run_scenario("office", seconds=2, seed=3).write(rec)
    counts = {}
    for flag in ([], ["--augment"]):
        out = tmp_path / f"m{len(flag)}.json"
        res = CliRunner().invoke(
            app, ["--quiet", "train", str(rec), "--rounds", "5", "-o", str(out), *flag]
        )
        assert res.exit_code == 0, res.output
        import json

        doc = json.loads(out.read_text())
        counts[len(flag)] = (doc["training"]["legs"], doc["training"]["non_legs"])
        assert ("augmentation" in doc["training"]) == bool(flag)
    # 20 variants: many more legs and non-legs than the recorded scans alone
    assert counts[1][0] > 5 * counts[0][0] and counts[1][1] > 5 * counts[0][1]


def test_truth_classes_mark_leg_beams() -> None:
    from laserpeople.detection.training import truth_classes

    sim = pytest.importorskip("laserpeople.sim")
    scan = sim.run_scenario("office", seconds=0.2, seed=3).scans[0]
    assert scan.labels is not None
    ((same, classes),) = truth_classes([scan])
    assert same is scan
    np.testing.assert_array_equal(classes[scan.labels.is_leg & scan.valid], 1)
    np.testing.assert_array_equal(classes[~scan.valid], 0)
    np.testing.assert_array_equal(classes[~scan.labels.is_leg & scan.valid], -1)
    with pytest.raises(RecordingError, match="ground truth"):
        truth_classes([Scan(0.0, 0.0, DEG, np.ones(3))])
