"""A block's segmentation and sparse legs by the C extension (``_cfeatures.segment`` and
``_cfeatures.sparse``) against their Python references (``segmentation._block_starts`` and
``sparse._sparse``) on random blocks of scans, and a scan's validity and points
(``_cfeatures.scan_points``) against numpy's.

Both are integers and decisions (segment starts, reordered rows of the scans' own
coordinates, segment indices), so they are compared exactly; the random scans are coarse
(1-4 degrees a beam), full circles and fans, both sweep directions, with dropped beams,
readings repeated on neighbouring beams and thresholds equal to a step's length, where a
rule decided by another operation goes the other way.
"""

from __future__ import annotations

import math
from types import ModuleType

import numpy as np
import pytest

from laserpeople import scan as scan_module
from laserpeople import segmentation
from laserpeople.detection import sparse
from laserpeople.detection.sparse import SparseLegParams, sparse_legs_of_block
from laserpeople.scan import Scan
from laserpeople.segmentation import JumpDistanceParams, segment_block


def _scans(rng: np.random.Generator, count: int) -> list[Scan]:
    """Random coarse scans: legs of one to three beams before walls, walls, repeated
    readings, dropped beams, full circles (which wrap) and fans, either sweep direction,
    now and then a scan without valid beams."""
    scans = []
    for k in range(count):
        full = rng.random() < 0.4
        step = math.radians(float(rng.choice([1.0, 2.0, 3.0, 4.0])))
        n = round(2.0 * math.pi / step) if full else int(rng.integers(3, 120))
        ranges = rng.uniform(2.0, 12.0, n)
        walls = rng.random(n) < 0.5
        ranges[walls] = np.repeat(rng.uniform(3.0, 12.0), np.count_nonzero(walls))
        for at in rng.integers(0, n, int(rng.integers(0, 6))):  # (legs of 1-3 beams)
            width = min(int(rng.integers(1, 4)), n - at)
            ranges[at : at + width] = rng.uniform(1.0, 8.0) + rng.uniform(0.0, 0.05, width)
        twice = np.flatnonzero(rng.random(n - 1) < 0.15)
        ranges[twice + 1] = ranges[twice]  # (one reading on two beams)
        ranges[rng.random(n) < 0.15] = np.nan
        if rng.random() < 0.05:
            ranges[:] = np.nan
        step = -step if rng.random() < 0.3 else step
        scans.append(Scan(0.1 * k, float(rng.uniform(-3.0, 3.0)), step, ranges, 0.05, 30.0))
    return scans


def _thresholds(rng: np.random.Generator, scans: list[Scan]) -> list[float]:
    """A random jump distance, the length of a step of the block and the distance between
    the ends of a full circle (and the floats either side of each), where the rules decide
    by a hair."""
    pts = np.concatenate([s.valid_points("sensor")[0] for s in scans])
    out = [float(rng.uniform(0.05, 1.0))]
    lengths = []
    if pts.shape[0] > 1:
        d = pts[1:] - pts[:-1]
        lengths.append(float(np.hypot(*d[int(rng.integers(0, d.shape[0]))])))
    for scan in scans:
        ends = scan.valid_points("sensor")[0]
        if segmentation.covers_full_circle(scan) and ends.shape[0] > 1:
            lengths.append(float(np.hypot(*(ends[0] - ends[-1]))))  # (where it wraps)
            break
    for x in lengths:
        if x > 0.0:
            out += [x, float(np.nextafter(x, 0.0)), float(np.nextafter(x, np.inf))]
    return out


def test_compiled_segmentation_of_a_block_is_the_reference(
    cfeatures: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    rng = np.random.default_rng(3)
    wrapped = segments = most = 0
    for _ in range(150):
        scans = _scans(rng, int(rng.integers(2, 18)))
        for threshold in _thresholds(rng, scans):
            params = JumpDistanceParams(threshold=threshold, wrap_around=bool(rng.random() < 0.8))
            monkeypatch.setattr(segmentation, "_extension", None)
            want = segment_block(scans, params)
            monkeypatch.setattr(segmentation, "_extension", cfeatures)
            got = segment_block(scans, params)
            for name in ("beams", "offsets", "table_starts", "point_starts"):
                assert getattr(got, name).tolist() == getattr(want, name).tolist(), name
            assert np.array_equal(got.points, want.points)
            for a, b in zip(got.tables, want.tables, strict=True):
                assert a.offsets.tolist() == b.offsets.tolist()
                assert a.beams.tolist() == b.beams.tolist()
                assert np.array_equal(a.points, b.points)
                wrapped += int(len(a) > 0 and a.segment(0).stop > a.n_beams)
            segments += got.offsets.size - 1
            most = max(most, got.offsets.size - 1)
    assert segments > 100000 and wrapped > 300
    assert most > 1024  # (a block with more segments than the extension's first buffer)


def test_compiled_segmentation_checks_its_arguments(cfeatures: ModuleType) -> None:
    points, beams = np.zeros((4, 2)), np.arange(4, dtype=np.int64)
    wrap = np.zeros(2, dtype=np.int64)
    with pytest.raises(ValueError, match="bounds do not cover"):
        cfeatures.segment(points, beams, np.array([0, 2, 3]), wrap, 0.1)
    with pytest.raises(ValueError, match="bounds do not increase"):
        cfeatures.segment(points, beams, np.array([0, 3, 2, 4]), np.zeros(3, np.int64), 0.1)


@pytest.mark.parametrize("min_points", [1, 2])
def test_compiled_sparse_legs_are_the_reference(
    cfeatures: ModuleType, min_points: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    rng = np.random.default_rng(5 + min_points)
    found = candidates = 0
    for _ in range(400):
        scans = _scans(rng, int(rng.integers(1, 18)))
        jump = float(rng.uniform(0.05, 0.5))
        block = segment_block(scans, JumpDistanceParams(threshold=jump))
        width = float(rng.choice([0.05, 0.12, 0.3, 1.0]))
        params = SparseLegParams(leg_width=width, min_points=min_points)
        monkeypatch.setattr(sparse, "_extension", None)
        want = sparse_legs_of_block(block, scans, jump, params)
        monkeypatch.setattr(sparse, "_extension", cfeatures)
        got = sparse_legs_of_block(block, scans, jump, params)
        assert got.tolist() == want.tolist()
        sizes = np.diff(block.offsets)
        candidates += int(np.count_nonzero((sizes >= min_points) & (sizes < 3)))
        found += want.size
    assert found > 300 and candidates > 3 * found  # (the rules keep some, not all)


def test_compiled_sparse_legs_check_their_arguments(cfeatures: ModuleType) -> None:
    offsets, beams = np.array([0, 2], dtype=np.int64), np.array([0, 5], dtype=np.int64)
    points, starts = np.zeros((2, 2)), np.array([0, 1], dtype=np.int64)
    ranges, valid = [np.ones(3)], [np.ones(3, dtype=bool)]
    args = (np.ones(1), np.zeros(1, dtype=np.int64), 2, 0.12, 0.1)
    with pytest.raises(ValueError, match="outside its scan"):
        cfeatures.sparse(offsets, beams, points, starts, ranges, valid, *args)
    with pytest.raises(ValueError, match="lists"):
        cfeatures.sparse(offsets, beams, points, starts, ranges, [], *args)


def test_compiled_sparse_legs_decide_at_the_rules_edges_as_the_reference(
    cfeatures: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    # a leg of two beams (5.0 and 5.0625 m, 2^-6 rad apart) between walls exactly the jump
    # distance (0.25 m) farther: a sparse leg, as ">=" decides; with a leg width of exactly
    # three beam spacings (5.03125 * 2^-6 m; every value a binary fraction) none, as "<"
    # decides, and one again a float narrower; with a leg width of exactly the leg's two
    # points' distance one, as "<=" decides, and none a float narrower
    ranges = np.array([5.25] * 10 + [5.0, 5.0625] + [5.3125] * 10)
    jump, increment = 0.25, 2.0**-6
    scans = [Scan(0.0, -0.2, increment, ranges, 0.05, 30.0)] * 2
    block = segment_block(scans, JumpDistanceParams(threshold=jump))
    exactly_three = 3.0 * (0.5 * (5.0 + 5.0625) * increment)
    below = float(np.nextafter(exactly_three, 0.0))
    points = scans[0].valid_points("sensor")[0]
    span = float(np.hypot(*(points[11] - points[10])))
    legs = []
    for width in (0.12, exactly_three, below, span, float(np.nextafter(span, 0.0))):
        params = SparseLegParams(leg_width=width)
        monkeypatch.setattr(sparse, "_extension", None)
        want = sparse_legs_of_block(block, scans, jump, params)
        monkeypatch.setattr(sparse, "_extension", cfeatures)
        assert sparse_legs_of_block(block, scans, jump, params).tolist() == want.tolist()
        legs.append(want.size)
    assert legs == [2, 0, 2, 2, 0]  # (a leg in each scan, or none)


def test_compiled_scan_points_are_numpys(
    cfeatures: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    # random ranges round the limits (NaN, inf, 0, negative, exactly range_min and
    # range_max) and angles; the same masks and indices, the same floats within 1e-12 m
    # and 1e-15 relative (ranges up to 1e300; a product of a range and a cosine: the same
    # IEEE operation, but no test relies on the last bit) and NaN rows where invalid
    rng = np.random.default_rng(13)
    valid_beams = 0
    for _ in range(300):
        n = int(rng.integers(0, 400))
        lo, hi = float(rng.uniform(0.0, 0.5)), float(rng.choice([10.0, 30.0, math.inf]))
        pool = np.array([math.nan, math.inf, -math.inf, 0.0, -1.0, lo, hi, 1e300])
        ranges = rng.uniform(-1.0, 40.0, n)
        odd = rng.random(n) < 0.2
        ranges[odd] = rng.choice(pool, int(np.count_nonzero(odd)))
        step = float(rng.choice([-1.0, 1.0]) * rng.uniform(1e-4, 0.1))
        args = (0.1, float(rng.uniform(-4.0, 4.0)), step, ranges, lo, hi)
        arrays = []
        for extension in (None, cfeatures):  # (the arrays are computed when first asked)
            monkeypatch.setattr(scan_module, "_extension", extension)
            scan = Scan(*args)
            arrays.append((scan.valid, scan.points("sensor"), scan.valid_points("sensor")))
        (want_valid, want_points, (wv, wb)), (valid, got_points, (gv, gb)) = arrays
        assert valid.tolist() == want_valid.tolist()
        assert valid.flags.writeable and not got_points.flags.writeable
        assert got_points.shape == want_points.shape
        np.testing.assert_allclose(got_points, want_points, rtol=1e-15, atol=1e-12)  # NaN rows
        assert gb.tolist() == wb.tolist() and gb.dtype == wb.dtype == np.int64
        assert gv.shape == wv.shape
        np.testing.assert_allclose(gv, wv, rtol=1e-15, atol=1e-12)
        assert not gv.flags.writeable and not gb.flags.writeable
        valid_beams += gb.size
    assert valid_beams > 20000
