"""Resampling labelled scans to other scanners (detection/augment.py), by hand."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from laserpeople.detection.augment import (
    RangeShiftParams,
    Variant,
    beam_classes,
    resample_scan,
    segment_labels_from_beams,
    shift_scan_out,
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
    shifted_segments,
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


# ---------------------------------------------------------------- moving segments out

INC = math.radians(0.3515625)  # the leg_tracker scanner's increment


def plate_scan(x: float, half_width: float, n_side: int = 60) -> Scan:
    """Beams k * INC, k = -n_side..n_side, at a flat plate x = ``x``, |y| <= half_width."""
    k = np.arange(-n_side, n_side + 1)
    phi = k * INC
    r = np.where(np.abs(x * np.tan(phi)) <= half_width, x / np.cos(phi), np.inf)
    return Scan(0.0, -n_side * INC, INC, r, range_max=30.0)


def test_plate_at_2m_recast_at_6m_by_hand() -> None:
    """A 0.2 m plate facing the sensor at 2 m: |k| <= atan(0.05) / INC = 8.18, 17 beams.
    Its surface runs through the outer points (y = +-2 tan(8 INC) = +-0.0978 m) and half a
    beam spacing (0.5 * INC * 2.0024 m = 0.0061 m) beyond: +-0.1040 m. Moved 4 m out, the
    beams with |tan(k INC)| <= 0.1040 / 6 hit it: |k| <= 2.84, 5 beams (the true plate at
    6 m gives 5 too: |k| <= 2.73), each at range 6 / cos(k INC)."""
    scan = plate_scan(2.0, 0.1)
    classes = np.where(scan.valid, 1, 0).astype(np.int64)
    assert int(scan.valid.sum()) == 17
    seg = JumpDistanceParams(threshold=0.13)
    params = RangeShiftParams(range_noise=0.0)
    new, cls = shift_scan_out(scan, classes, 4.0, seg, np.random.default_rng(0), params)
    k = np.flatnonzero(new.valid) - 60
    assert k.tolist() == [-2, -1, 0, 1, 2]  # about a third of 17
    assert np.allclose(new.ranges[new.valid], 6.0 / np.cos(k * INC), atol=1e-9)
    assert cls[new.valid].tolist() == [1] * 5
    assert set(cls[~new.valid].tolist()) == {0}
    # width first -> last point: 4 * 6 tan(INC)... = 0.147 m against 0.196 m at 2 m; the
    # plate's 0.2 m is kept within one beam spacing at 6 m on each side (2 * 0.0368 m)
    pts = new.points()[new.valid]
    width = float(np.hypot(*(pts[-1] - pts[0])))
    assert width == pytest.approx(2 * 6.0 * math.tan(2 * INC), abs=1e-9)
    assert 0.2 - 2 * 6.0 * INC <= width <= 0.2


def test_leg_recast_keeps_its_size_and_loses_beams_like_a_real_leg() -> None:
    """A leg (circle, radius 0.06 m) at 2 m moved out 4 m gets the beams a leg at 6 m gets
    (the circle cast directly), its points within 1 cm of the true circle."""

    def circle(cx: float) -> Scan:
        k = np.arange(-60, 61)
        d = np.column_stack((np.cos(k * INC), np.sin(k * INC)))
        b = d[:, 0] * cx
        disc = b * b - (cx * cx - 0.06**2)
        r = np.where(disc > 0, b - np.sqrt(np.where(disc > 0, disc, 0.0)), np.inf)
        return Scan(0.0, -60 * INC, INC, r, range_max=30.0)

    near, far = circle(2.06), circle(6.06)
    classes = np.where(near.valid, 1, 0).astype(np.int64)
    seg = JumpDistanceParams(threshold=0.13)
    new, _ = shift_scan_out(
        near, classes, 4.0, seg, np.random.default_rng(0), RangeShiftParams(range_noise=0.0)
    )
    assert int(near.valid.sum()) == 9
    assert np.flatnonzero(new.valid).tolist() == np.flatnonzero(far.valid).tolist()
    assert np.allclose(new.ranges[new.valid], far.ranges[far.valid], atol=0.01)


def test_nearer_objects_hide_farther_ones_and_noise_is_the_given_sigma() -> None:
    """Two plates on one bearing, 1 m apart, both moved 3 m out: only the nearer one is
    seen where it covers the other; the noise of many beams has the given deviation."""
    near, back = plate_scan(2.0, 0.1), plate_scan(3.0, 0.6)
    r = np.minimum(near.ranges, back.ranges)
    scan = Scan(0.0, near.angle_min, INC, r, range_max=30.0)
    classes = np.where(np.isfinite(near.ranges), 1, -1).astype(np.int64)
    seg = JumpDistanceParams(threshold=0.13)
    exact = RangeShiftParams(range_noise=0.0)
    new, cls = shift_scan_out(scan, classes, 3.0, seg, np.random.default_rng(0), exact)
    centre = new.ranges[55:66]
    assert cls[58:63].tolist() == [1] * 5 and cls[60] == 1
    assert np.all(centre[cls[55:66] == 1] < 5.1) and np.all(centre[cls[55:66] == -1] > 5.9)
    noisy, _ = shift_scan_out(
        scan, classes, 3.0, seg, np.random.default_rng(1), RangeShiftParams(range_noise=0.02)
    )
    both = new.valid & noisy.valid
    assert np.std(noisy.ranges[both] - new.ranges[both]) == pytest.approx(0.02, rel=0.25)


def test_shifted_segments_drop_legs_under_three_points_and_name_groups() -> None:
    """A leg plate of 0.05 m at 1.5 m (5-6 beams) moved 6 m out keeps 1-2 beams and is not
    a training segment; moved 1 m out it keeps 3-4 and is one leg."""
    scan = plate_scan(1.5, 0.025)
    classes = np.where(scan.valid, 1, 0).astype(np.int64)
    seg = JumpDistanceParams(threshold=0.13)
    data = shifted_segments([(scan, classes)], "toy", (1.0, 6.0), seg)
    assert data.n_positive == 1 and len(data) == 1
    assert data.groups[int(data.group[0])].startswith("toy@+1m")
    assert data.distance[0] == pytest.approx(2.5, abs=0.02)


def test_shift_bad_arguments_raise() -> None:
    scan = plate_scan(2.0, 0.1)
    seg = JumpDistanceParams(threshold=0.13)
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="shift"):
        shift_scan_out(scan, np.zeros(scan.n_beams, dtype=np.int64), 0.0, seg, rng)
    with pytest.raises(ValueError, match="beam classes"):
        shift_scan_out(scan, np.zeros(3, dtype=np.int64), 1.0, seg, rng)
