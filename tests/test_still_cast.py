"""The casting of a laser that stands still (background/still_cast.py) gives the occupancy
grid the same seen-free stamps, first sights and static times as casting every sample."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.background.occupancy import OccupancyGrid, OccupancyParams, sorted_unique
from laserpeople.background.still_cast import BOUNDARY_MARGIN, StillCast

# two code paths giving the same bits may hold on one CPU only: CI runs these again on
# another CPU path (.ci/run)
pytestmark = pytest.mark.regression

EVERY_FRAME = OccupancyParams(free_period=0.0)
"""Free space cast in every frame (the casting these tests compare; not the default)."""


def _at(g: OccupancyGrid, values: np.ndarray, cells: list[tuple[int, int]]) -> list[float]:
    """Values of the grid-shaped array ``values`` at absolute ``cells``."""
    return [float(values[i - g._origin[0], j - g._origin[1]]) for i, j in cells]


def test_a_beam_that_shortens_keeps_the_stamp_of_its_last_frame_by_hand() -> None:
    """Sensor at (0.03, 0.02), one beam along +x. Returns at x = 1.03 at t = 0, 1 (reach
    1.0 - 0.2 = 0.8: samples 0.05 ... 0.75, x = 0.08 ... 0.78, cells 0-7), at x = 0.53 at
    t = 2 (reach 0.3: cells 0-2), at 1.03 again at t = 3 with a return in cell 5 from a
    second beam (not free at t = 3). seen_free: t = 0: cells 0-7 at 0; t = 1 (the cache
    starts): 1; t = 2: cells 0-2 at 2, 3-7 keep 1; t = 3: 0-4, 6, 7 at 3, cell 5 keeps 1."""
    g = OccupancyGrid(EVERY_FRAME)
    sensor = np.array([0.03, 0.02])
    beam = np.array([7])

    def frame(x: float, t: float, extra: bool = False) -> None:
        pts = np.array([[x, 0.02]])
        ids = beam
        if extra:  # a second beam (id 9, to the side) with its return in cell (5, 0)
            pts = np.vstack([pts, [0.55, 0.05]])
            ids = np.array([7, 9])
        g.learn(pts, t, sensor=sensor, beams=ids)

    cells = [(i, 0) for i in range(8)]
    frame(1.03, 0.0)
    assert not g._still.active  # the first frame: where the laser stands is not known yet
    assert _at(g, g._seen_free_now(), cells) == [0.0] * 8
    frame(1.03, 1.0)
    assert g._still.active
    assert _at(g, g._seen_free_now(), cells) == [1.0] * 8
    frame(0.53, 2.0)
    assert _at(g, g._seen_free_now(), cells) == [2.0] * 3 + [1.0] * 5
    frame(1.03, 3.0, extra=True)
    assert _at(g, g._seen_free_now(), cells) == [3.0] * 5 + [1.0] + [3.0] * 2


def _room(seed: int) -> list[tuple[np.ndarray, float, np.ndarray | None, np.ndarray]]:
    """Frames (points, stamp, sensor, beam ids) of a room seen by a 0.5-degree laser that
    stands still, moves for three frames, stands still elsewhere, loses returns (NaN, too
    close, too far), has a frame without a pose, and sees a far return that grows the grid;
    walkers cross the beams."""
    rng = np.random.default_rng(seed)
    angles = np.linspace(-np.pi, np.pi, 720, endpoint=False)
    wall = 4.0 + rng.uniform(-0.5, 2.5, size=angles.size)
    frames = []
    sensor = np.array([0.31, -0.17])
    for k in range(60):
        if 20 <= k < 23:
            sensor = sensor + np.array([0.05, 0.02])
        ranges = wall + rng.normal(scale=0.02, size=angles.size)
        for w in range(3):  # walkers: a few beams much shorter
            c = (k * 7 + w * 240) % angles.size
            ranges[c : c + 6] = 1.0 + 0.5 * w + 0.03 * k
        if k % 9 == 4:
            ranges[rng.integers(0, angles.size, 20)] = np.nan
        if k % 11 == 5:
            ranges[rng.integers(0, angles.size, 5)] = 0.1  # within free_margin
        if k == 40:
            ranges[100] = 25.0  # grows the grid
        pts = sensor + ranges[:, None] * np.stack([np.cos(angles), np.sin(angles)], axis=1)
        beams = np.arange(angles.size)
        frames.append((pts, 0.1 * k, None if k == 30 else sensor.copy(), beams))
    return frames


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_still_casting_equals_casting_every_sample(seed: int) -> None:
    """After every frame the grid fed beam ids (still casting) and the grid fed none (every
    sample cast) hold the same seen-free stamps, first sights, occupied-since times and
    evidence, cell for cell."""
    fast, slow = OccupancyGrid(EVERY_FRAME), OccupancyGrid(EVERY_FRAME)
    used = 0
    for pts, stamp, sensor, beams in _room(seed):
        fast.learn(pts, stamp, sensor=sensor, beams=beams)
        slow.learn(pts, stamp, sensor=sensor)
        used += fast._still.active
        assert np.array_equal(fast._origin, slow._origin)
        assert np.array_equal(fast._seen_free_now(), slow._seen_free)
        assert np.array_equal(fast._first_sight, slow._first_sight)
        assert np.array_equal(fast._since, slow._since, equal_nan=True)
        assert np.array_equal(fast._evidence, slow._evidence)
    assert used > 40  # the still casting did the work in most frames
    probe = np.random.default_rng(seed).uniform(-6.0, 6.0, size=(200, 2))
    assert np.array_equal(fast.static_time(probe), slow.static_time(probe))


def test_two_lasers_or_unordered_beams_take_the_sampling_path() -> None:
    """Two sensor positions in one frame, or beam ids that do not increase: every sample is
    cast (the still casting is not used)."""
    g = OccupancyGrid(EVERY_FRAME)
    pts = np.array([[1.0, 0.3], [2.0, -0.4]])
    for t in (0.0, 0.1, 0.2):
        g.learn(pts, t, sensor=np.array([[0.0, 0.0], [0.5, 0.0]]), beams=np.array([0, 1]))
    assert not g._still.active
    for t in (0.3, 0.4, 0.5):
        g.learn(pts, t, sensor=np.zeros(2), beams=np.array([1, 0]))
    assert not g._still.active


def test_still_cast_lists_follow_the_casting_arithmetic() -> None:
    """A listed beam's cells are floor((u s_k + o) / res) - origin, flattened, for every
    step; a sample within BOUNDARY_MARGIN of a boundary makes the beam unsafe."""
    res = 0.1
    steps = np.arange(0.5 * res, 2.0 + res, res)
    cast = StillCast(res, steps)
    u = np.array([[0.6, 0.8], [1.0, 0.0]])
    origin = np.array([0.33, 0.27])
    lists, safe = cast._lists(origin, u, (0.33, 0.27, -5, -4, 20, 400))
    for b in range(2):
        clear = True
        for k, s in enumerate(steps):
            x, y = (u[b, 0] * s + origin[0]) / res, (u[b, 1] * s + origin[1]) / res
            assert lists[b, k] == (int(np.floor(x)) + 5) * 20 + int(np.floor(y)) + 4
            for q in (x, y):
                clear &= min(q - np.floor(q), np.floor(q) + 1 - q) * res >= BOUNDARY_MARGIN
        assert safe[b] == clear
    # beam 0 reaches x = 0.33 + 0.6 * 0.45 = 0.6, on a boundary; beam 1 stays at y = 0.27
    assert safe.tolist() == [False, True]
    on_line = np.array([[1.0, 0.0]])
    _, safe = cast._lists(np.array([0.33, 0.2]), on_line, (0.33, 0.2, -5, -4, 20, 400))
    assert safe.tolist() == [False]  # y = 0.2 lies on a cell boundary


def test_sorted_unique_is_numpys_unique() -> None:
    rng = np.random.default_rng(3)
    for n in (0, 1, 2, 5, 700):
        v = rng.integers(-50, 50, size=n)
        assert sorted_unique(v).tolist() == np.unique(v).tolist()


def test_still_casting_with_free_space_off_casts_nothing() -> None:
    g = OccupancyGrid(OccupancyParams(free_range=0.0))
    for t in (0.0, 0.1, 0.2):
        g.learn(np.array([[1.0, 0.0]]), t, sensor=np.zeros(2), beams=np.array([0]))
    assert not g.casting and not g._still.active
    assert not np.isfinite(g._seen_free_now()).any()


@pytest.mark.parametrize("seed", [0, 1])
def test_one_sensor_row_broadcast_equals_one_row_per_return(seed: int) -> None:
    """A sensor given as one row broadcast to all returns (what sensor_positions gives for
    one laser), as a full (N, 2) copy, or as (2,) leaves the same grid, NaN returns and
    returns beyond max_range included."""
    grids = [OccupancyGrid(OccupancyParams(max_range=6.0)) for _ in range(3)]
    for pts, stamp, sensor, beams in _room(seed)[:30]:
        if sensor is None:
            continue
        rows = np.broadcast_to(sensor, pts.shape)
        for g, sen in zip(grids, (rows, np.array(rows), sensor), strict=True):
            g.learn(pts, stamp, sensor=sen, beams=beams)
    for g in grids[1:]:
        assert np.array_equal(g._origin, grids[0]._origin)
        assert np.array_equal(g._seen_free_now(), grids[0]._seen_free_now())
        assert np.array_equal(g._first_sight, grids[0]._first_sight)
        assert np.array_equal(g._since, grids[0]._since, equal_nan=True)
