"""The segments of a block of scans at once (``segmentation.segment_block``) and the jump
rule it decides by (``at_least``, compiled as ``_cfeatures.jumps``).

A block gives every scan the table segmenting it alone gives (the same beams, points and
offsets; integers and the scans' own coordinates, so compared exactly), full circles
merged where they wrap, scans without valid points empty; the jump rule decides as
``np.hypot(dx, dy) >= threshold`` at every step, also at thresholds equal to a step's
length and one float either side, where comparing squared lengths alone goes wrong.
"""

from __future__ import annotations

import dataclasses
import math
from types import ModuleType

import numpy as np
import pytest

from laserpeople import segmentation
from laserpeople.scan import Scan, Segment
from laserpeople.segmentation import (
    JumpDistanceParams,
    JumpDistanceSegmenter,
    at_least,
    segment_block,
)


def _walk(seed: int, n: int = 4000) -> tuple[np.ndarray, np.ndarray, list[float]]:
    """Points of a random walk (n, 2) [m], their steps (n - 1, 2) and thresholds [m]: the
    length of every 40th step and the floats just below and above it."""
    rng = np.random.default_rng(seed)
    points = np.cumsum(rng.normal(size=(n, 2)) * rng.choice([1e-3, 0.1, 1.0, 100.0]), axis=0)
    steps = points[1:] - points[:-1]
    lengths = np.hypot(steps[:, 0], steps[:, 1])[::40]
    near = [np.nextafter(lengths, 0.0), lengths, np.nextafter(lengths, np.inf)]
    return points, steps, [float(t) for t in np.concatenate(near)]


def test_at_least_decides_as_hypot_where_squares_alone_do_not() -> None:
    told = 0
    for seed in range(6):
        _, steps, thresholds = _walk(seed)
        hypot = np.hypot(steps[:, 0], steps[:, 1])
        for threshold in [*thresholds, 1e-200, 1e200, 0.1]:
            want = hypot >= threshold
            assert np.array_equal(at_least(steps, threshold), want)
            squares = steps[:, 0] * steps[:, 0] + steps[:, 1] * steps[:, 1]
            told += int(np.count_nonzero((squares >= threshold * threshold) != want))
    assert told > 100  # (the thresholds do tell the rule from squared lengths alone)


def test_compiled_jumps_decide_as_at_least(cfeatures: ModuleType) -> None:
    for seed in range(6):
        points, steps, thresholds = _walk(seed)
        for threshold in [*thresholds, 1e-200, 1e200, math.nan]:
            out = np.empty(points.shape[0] - 1, dtype=bool)
            cfeatures.jumps(points, threshold, out)
            assert np.array_equal(out, at_least(steps, threshold))
    with pytest.raises(ValueError, match="out"):
        cfeatures.jumps(np.zeros((3, 2)), 0.1, np.empty(3, dtype=bool))


def _scans(rng: np.random.Generator, count: int) -> list[Scan]:
    """Random scans: full circles (which wrap) and partial fans, both sweep directions,
    dropped beams, a few without any valid beam or with a single one."""
    scans = []
    for k in range(count):
        n = int(rng.integers(1, 60))
        ranges = rng.uniform(0.5, 3.0, n)
        ranges[rng.random(n) < 0.1] = ranges[0]  # (a wall: runs of close points)
        ranges[rng.random(n) < 0.3] = np.nan
        if rng.random() < 0.08:
            ranges[:] = np.nan
        step = 2.0 * math.pi / n if rng.random() < 0.5 else 0.01
        step = -step if rng.random() < 0.3 else step
        scans.append(Scan(0.1 * k, float(rng.uniform(-3.0, 3.0)), step, ranges, index=k))
    return scans


@pytest.mark.parametrize("wrap", [True, False])
@pytest.mark.parametrize("pure", [True, False])
def test_a_block_gives_each_scan_its_own_table(
    wrap: bool, pure: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    if pure:
        monkeypatch.setattr(segmentation, "_extension", None)
    rng = np.random.default_rng(7)
    wrapped = segments = 0
    for _ in range(300):
        scans = _scans(rng, int(rng.integers(1, 6)))
        params = JumpDistanceParams(threshold=float(rng.uniform(0.05, 1.0)), wrap_around=wrap)
        block = segment_block(scans, params)
        alone = JumpDistanceSegmenter(params)
        assert len(block.tables) == len(scans)
        for scan, table in zip(scans, block.tables, strict=True):
            want = alone(scan)
            assert table.offsets.tolist() == want.offsets.tolist()
            assert table.beams.tolist() == want.beams.tolist()
            assert np.array_equal(table.points, want.points)  # (the scan's own floats)
            assert (table.n_beams, table.n_invalid) == (want.n_beams, want.n_invalid)
            wrapped += int(len(want) and want.segment(0).stop > scan.n_beams)
            segments += len(want)
        assert (
            block.table_starts.tolist() == np.cumsum([0] + [len(t) for t in block.tables]).tolist()
        )
        for a in (block.points, block.beams, block.offsets, block.table_starts):
            assert not a.flags.writeable
    assert segments > 3000
    assert (wrapped > 50) == wrap


def test_block_segments_are_the_tables_segments() -> None:
    rng = np.random.default_rng(11)
    params = JumpDistanceParams(threshold=0.3)
    for _ in range(100):
        scans = _scans(rng, 4)
        block = segment_block(scans, params)
        got = block.segments_at(np.arange(block.offsets.size - 1))
        want = [s for t in block.tables for s in t.segments_at(np.arange(len(t)))]
        assert len(got) == len(want)
        for s, t in zip(got, want, strict=True):
            assert (s.start, s.stop) == (t.start, t.stop)
            assert s.beams.tolist() == t.beams.tolist()
            assert np.array_equal(s.points, t.points)
            assert not s.points.flags.writeable and not s.beams.flags.writeable
            assert not np.shares_memory(s.points, block.points)  # (the scans' own arrays)


def test_segment_of_is_the_dataclass_built_by_hand() -> None:
    beams, points = np.array([7, 8, 10]), np.array([[1.0, 2.0], [1.5, 2.5], [2.0, 3.0]])
    got, want = Segment.of(7, 11, beams, points), Segment(7, 11, beams, points)
    assert vars(got).keys() == vars(want).keys()  # (the same fields, in the same order)
    assert (got.start, got.stop, len(got)) == (want.start, want.stop, len(want)) == (7, 11, 3)
    assert got.beams is beams and got.points is points
    assert got.centre.tolist() == [1.5, 2.5]
    with pytest.raises(dataclasses.FrozenInstanceError):
        got.start = 8  # type: ignore[misc]
