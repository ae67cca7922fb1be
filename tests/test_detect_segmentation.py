"""Jump-distance segmentation (000 Sec. 2.2)."""

from __future__ import annotations

import math

import numpy as np

from laserpeople.scan import Scan
from laserpeople.segmentation import JumpDistanceParams, JumpDistanceSegmenter


def test_splits_at_jumps_and_keeps_beam_order() -> None:
    ranges = np.array([2.0, 2.0, 2.0, 1.0, 1.0, 1.0, 1.0, 2.0, 2.0])
    scan = Scan(0.0, 0.0, 0.01, ranges)
    table = JumpDistanceSegmenter(JumpDistanceParams(threshold=0.1))(scan)
    assert table.sizes.tolist() == [3, 4, 2]
    segs = table.segments()
    assert [(s.start, s.stop) for s in segs] == [(0, 3), (3, 7), (7, 9)]
    np.testing.assert_array_equal(segs[1].beams, [3, 4, 5, 6])
    np.testing.assert_allclose(segs[1].points, scan.points()[3:7])


def test_invalid_beams_are_skipped_not_breaking() -> None:
    ranges = np.array([1.0, 1.0, np.nan, 1.0, 0.0, 1.0, 5.0, 5.0])
    scan = Scan(0.0, 0.0, 0.01, ranges)
    table = JumpDistanceSegmenter()(scan)
    assert table.n_invalid == 2
    assert table.sizes.tolist() == [4, 2]
    np.testing.assert_array_equal(table.segment(0).beams, [0, 1, 3, 5])
    assert table.segment(0).stop == 6


def test_threshold_is_inclusive_like_the_label_rule() -> None:
    inc = 0.1
    # two points exactly 'threshold' apart start a new segment
    r = 1.0
    gap = 2 * r * math.sin(inc / 2)
    scan = Scan(0.0, 0.0, inc, np.array([r, r, r]))
    assert len(JumpDistanceSegmenter(JumpDistanceParams(threshold=gap * 1.0000001))(scan)) == 1
    assert len(JumpDistanceSegmenter(JumpDistanceParams(threshold=gap * 0.9999999))(scan)) == 3


def test_full_circle_merges_last_into_first() -> None:
    n = 720
    ranges = np.full(n, 3.0)
    ranges[100:110] = 1.0  # an object splits the ring
    scan = Scan(0.0, -math.pi, 2 * math.pi / n, ranges)
    table = JumpDistanceSegmenter()(scan)
    assert len(table) == 2  # wall before and after the object are one wrapped segment
    wrapped = table.segment(0)
    assert wrapped.beams[0] == 110 and wrapped.beams[-1] == 99
    assert wrapped.stop == 100 + n
    off = JumpDistanceSegmenter(JumpDistanceParams(wrap_around=False))(scan)
    assert len(off) == 3


def test_empty_and_all_invalid() -> None:
    scan = Scan(0.0, 0.0, 0.01, np.full(5, np.nan))
    table = JumpDistanceSegmenter()(scan)
    assert len(table) == 0 and table.n_invalid == 5
    assert table.segments() == []


def test_many_scans_at_once_give_each_scans_own_table() -> None:
    """``many`` segments scans as one at a time does: a jump between the last point of one
    scan and the first of the next is no segment start of either, and a scan whose first
    point is far from the last scan's last point starts no extra segment."""
    rng = np.random.default_rng(5)
    n = 720
    scans = []
    for k in range(6):
        ranges = np.full(n, 3.0) + 0.5 * (rng.random(n) < 0.02)
        ranges[rng.random(n) < 0.05] = np.nan
        ranges[100 + 10 * k : 120 + 10 * k] = 1.0
        scans.append(Scan(0.01 * k, -math.pi, 2 * math.pi / n, ranges))  # full circle: wraps
    scans.insert(2, Scan(0.02, 0.0, 0.01, np.full(9, np.nan)))  # no valid point
    scans.insert(4, Scan(0.03, 0.0, 0.01, np.array([9.0, 1.0, 1.0, 1.0, 2.0])))  # far first
    seg = JumpDistanceSegmenter()
    many = seg.many(scans)
    assert len(many) == len(scans)
    for scan, table in zip(scans, many, strict=True):
        alone = seg(scan)
        # the segments as a user sees them: which beams start each one (integers; the
        # scans' gaps lie at least 4 mm from the 0.1 m threshold, so no rounding decides)
        assert table.offsets.tolist() == alone.offsets.tolist()
        assert table.beams.tolist() == alone.beams.tolist()
        np.testing.assert_allclose(table.points, alone.points, rtol=0.0, atol=1e-12)  # m
        assert (table.n_beams, table.n_invalid) == (alone.n_beams, alone.n_invalid)
    assert many[4].sizes.tolist() == [1, 3, 1]
