"""Sparse legs: segments of one or two points a coarse scanner puts on a leg."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.detection.sparse import SparseLegParams, expected_beams, sparse_legs
from laserpeople.scan import Scan
from laserpeople.segmentation import JumpDistanceParams, JumpDistanceSegmenter

JUMP = 0.13  # m, the shipped model's jump distance
ONE_DEG = math.radians(1.0)
N = 121  # beams over -60..60 deg at 1 deg
LEG = 60  # first beam of the leg (straight ahead)


def _scan(
    leg: list[float], increment: float = ONE_DEG, wall: float = 6.0, beam: int = LEG
) -> tuple[Scan, JumpDistanceSegmenter]:
    """A scan of a wall at ``wall`` m with the ranges ``leg`` [m] from beam ``beam`` on."""
    n = round(math.radians(120.0) / abs(increment)) + 1
    ranges = np.full(n, wall)
    ranges[beam : beam + len(leg)] = leg
    start = -math.copysign(math.radians(60.0), increment)  # (a negative one sweeps clockwise)
    scan = Scan(0.0, start, increment, ranges, 0.05, 20.0)
    return scan, JumpDistanceSegmenter(JumpDistanceParams(threshold=JUMP))


def _sparse_beams(scan: Scan, seg: JumpDistanceSegmenter, **kw: object) -> list[list[int]]:
    """The beams of each sparse leg of ``scan``."""
    table = seg(scan)
    rows = sparse_legs(table, scan, JUMP, SparseLegParams(**kw))  # type: ignore[arg-type]
    return [table.beams[table.offsets[i] : table.offsets[i + 1]].tolist() for i in rows]


def test_expected_beams_is_the_width_over_the_beam_spacing() -> None:
    got = expected_beams(np.array([4.0, 2.0]), -ONE_DEG, 0.12)
    np.testing.assert_allclose(got, [0.12 / (4.0 * ONE_DEG), 0.12 / (2.0 * ONE_DEG)], rtol=1e-12)
    assert got[0] == pytest.approx(1.7189, abs=1e-4)


def test_two_points_in_front_of_a_wall_are_a_sparse_leg() -> None:
    scan, seg = _scan([5.0, 5.02])
    assert _sparse_beams(scan, seg) == [[LEG, LEG + 1]]


def test_only_where_a_leg_gets_fewer_than_three_beams() -> None:
    # at 1 deg a 0.12 m leg gets 3 beams at 0.12 / (3 * 1 deg) = 2.292 m
    near, seg = _scan([2.25, 2.25 + 0.01])  # 3.04 beams expected
    far, _ = _scan([2.35, 2.35 + 0.01])  # 2.92
    assert _sparse_beams(near, seg) == []
    assert _sparse_beams(far, seg) == [[LEG, LEG + 1]]
    # a fine scanner (0.25 deg) puts 6.9 beams on a leg at 4 m: left to the classifier
    fine, seg = _scan([4.0, 4.01], increment=math.radians(0.25), beam=240)
    assert _sparse_beams(fine, seg) == []
    wider, _ = _scan([2.25, 2.25 + 0.01])
    assert _sparse_beams(wider, seg, leg_width=0.11) == [[LEG, LEG + 1]]  # 2.80 beams


@pytest.mark.parametrize(
    ("before", "after", "taken"),
    [
        (6.0, 6.0, True),
        (5.0 + 0.16, 6.0, True),  # more than the jump distance behind
        (6.0, 5.02 + 0.16, True),
        (5.0 + 0.10, 6.0, False),  # a separate segment, but less than the jump distance behind
        (6.0, 5.02 + 0.10, False),
        (4.8, 6.0, False),  # a nearer neighbour: an edge's mixed pixel, not a leg before a wall
        (math.inf, math.nan, True),  # no return on either side
    ],
)
def test_both_neighbours_lie_a_jump_distance_behind(
    before: float, after: float, taken: bool
) -> None:
    scan, seg = _scan([before, 5.0, 5.02, after], beam=LEG - 1)
    table = seg(scan)
    assert any(table.sizes == 2)  # (the two points are a segment of their own)
    assert _sparse_beams(scan, seg) == ([[LEG, LEG + 1]] if taken else [])


def test_at_the_end_of_a_scan_there_is_no_neighbour() -> None:
    scan, seg = _scan([5.0, 5.02], beam=N - 2)
    assert _sparse_beams(scan, seg) == [[N - 2, N - 1]]
    scan, seg = _scan([5.0, 5.02], beam=0)
    assert _sparse_beams(scan, seg) == [[0, 1]]


def test_a_full_circle_wraps_to_its_last_beam() -> None:
    ranges = np.full(360, 6.0)
    ranges[:2] = [5.0, 5.02]
    full = Scan(0.0, -math.pi, ONE_DEG, ranges, 0.05, 20.0)
    seg = JumpDistanceSegmenter(JumpDistanceParams(threshold=JUMP))
    assert _sparse_beams(full, seg) == [[0, 1]]
    ranges[-1] = 5.1  # (a segment of its own, 0.133 m away, but not a jump distance behind)
    full = Scan(0.0, -math.pi, ONE_DEG, ranges, 0.05, 20.0)
    assert _sparse_beams(full, seg) == []
    part = Scan(0.0, -math.pi, ONE_DEG, ranges[:-1], 0.05, 20.0)  # (359 deg: no wrap)
    assert _sparse_beams(part, seg) == [[0, 1]]


def test_a_block_of_scans_gives_each_scan_its_own_legs() -> None:
    a, _ = _scan([5.0, 5.02])  # a sparse leg
    b, _ = _scan([5.0, 5.02], increment=math.radians(0.25), beam=240)  # none: fine scanner
    c, _ = _scan([5.0, 5.03], increment=-math.radians(0.5), beam=100)  # one, clockwise
    d, _ = _scan([3.0, 3.02], beam=20)
    one = [AdaBoostLegDetector.default().detect(s) for s in (a, b, c, d)]
    block = AdaBoostLegDetector.default().detect_many([a, b, c, d])
    assert [len(x) for x in one] == [1, 0, 1, 1]
    for x, y in zip(one, block, strict=True):
        np.testing.assert_allclose(x.positions, y.positions, atol=1e-12)
        assert x.scores.tolist() == y.scores.tolist()


def test_no_wider_than_a_leg() -> None:
    # 2 deg apart at 3.58 m with no return between: 0.12496 m, one segment (jump 0.13)
    ranges = np.full(N, 6.0)
    ranges[LEG - 1 : LEG + 4] = [math.inf, 3.58, math.inf, 3.58 + 1e-3, math.inf]
    scan = Scan(0.0, -math.radians(60.0), ONE_DEG, ranges, 0.05, 20.0)
    seg = JumpDistanceSegmenter(JumpDistanceParams(threshold=JUMP))
    width = math.hypot(3.58 - 3.581 * math.cos(2 * ONE_DEG), 3.581 * math.sin(2 * ONE_DEG))
    assert 0.12 < width < JUMP
    assert _sparse_beams(scan, seg) == []
    assert _sparse_beams(scan, seg, leg_width=0.125) == [[LEG, LEG + 2]]


def test_one_reading_repeated_is_one_point() -> None:
    scan, seg = _scan([5.0, 5.0])  # (a scanner that reports each reading on two beams)
    assert _sparse_beams(scan, seg) == []
    assert _sparse_beams(scan, seg, min_points=1) == [[LEG, LEG + 1]]


def test_one_point_only_with_min_points_one() -> None:
    scan, seg = _scan([5.0])
    assert _sparse_beams(scan, seg) == []
    assert _sparse_beams(scan, seg, min_points=1) == [[LEG]]
    three, _ = _scan([5.0, 5.02, 5.04])  # (the classifier's)
    assert _sparse_beams(three, seg, min_points=1) == []


def test_disabled() -> None:
    scan, seg = _scan([5.0, 5.02])
    assert _sparse_beams(scan, seg, enabled=False) == []


def test_the_detector_reports_a_sparse_leg_with_its_score() -> None:
    scan, _ = _scan([5.0, 5.02])
    det = AdaBoostLegDetector.default()
    legs = det.detect(scan)
    assert legs.scores.tolist() == [0.6]
    centroid = scan.points()[LEG : LEG + 2].mean(axis=0)
    want = centroid * (1.0 + 0.045 / np.hypot(*centroid))
    np.testing.assert_allclose(legs.positions[0], want, atol=1e-12)
    assert det.detect_many([scan])[0].scores.tolist() == [0.6]
    off = LegDetectorParams(sparse=SparseLegParams(enabled=False))
    assert len(AdaBoostLegDetector.default(off).detect(scan)) == 0
    strict = LegDetectorParams(score_threshold=0.6)  # (a score must be above the threshold)
    assert len(AdaBoostLegDetector.default(strict).detect(scan)) == 0
    near = LegDetectorParams(max_distance=4.9)
    assert len(AdaBoostLegDetector.default(near).detect(scan)) == 0


@pytest.mark.parametrize(
    "kw",
    [
        {"leg_width": 0.0},
        {"leg_width": math.inf},
        {"min_points": 0},
        {"min_points": 3},
        {"score": math.nan},
    ],
)
def test_bad_values_are_refused(kw: dict[str, float]) -> None:
    with pytest.raises(ValueError):
        SparseLegParams(**kw)  # type: ignore[arg-type]


def test_the_paper_preset_detects_legs_of_three_points_or_more_only() -> None:
    """`--preset paper` (000: features of segments of 3+ points) turns the sparse legs off,
    for `track` and `live` alike (cli.track.make_detector)."""
    from laserpeople.cli.track import make_detector
    from laserpeople.config import load_config

    assert load_config(LegDetectorParams, None).sparse.enabled
    assert not load_config(LegDetectorParams, None, "paper").sparse.enabled
    detector = make_detector("adaboost", None, None, "paper")
    assert isinstance(detector, AdaBoostLegDetector)
    assert not detector.params.sparse.enabled
    assert make_detector("adaboost", None, None).params.sparse.enabled  # type: ignore[attr-defined]
