"""The decaying occupancy grid of static returns and the ROS map loader."""

from __future__ import annotations

import math

import numpy as np
import pytest
from PIL import Image

from laserpeople.background import StaticWorldModel
from laserpeople.background.occupancy import (
    MapFileError,
    OccupancyGrid,
    OccupancyParams,
    frame_from_scan,
    load_ros_map,
)
from laserpeople.frame import Frame
from laserpeople.scan import Scan

P = OccupancyParams()
POST = np.array([[2.03, 1.07]])  # a return that stays put


def test_evidence_and_static_time_by_hand() -> None:
    """Hits at 0, 0.1, 0.2 s: e = 1, 1 + e^-0.05 = 1.951 (< 2, free), 1 + 1.951 e^-0.05 =
    2.856 (occupied since 0.2 s). Hit every 0.1 s to 5.2 s: static for 5.0 s."""
    g = OccupancyGrid()
    g.learn(POST, 0.0)
    g.learn(POST, 0.1)
    assert g.static_time(POST) == pytest.approx([0.0])
    g.learn(POST, 0.2)
    assert g.static_time(POST) == pytest.approx([0.0])  # became occupied just now
    for k in range(3, 53):
        g.learn(POST, 0.1 * k)
    assert g.static_time(POST) == pytest.approx([5.0])
    i, j = (np.floor(POST[0] / P.resolution).astype(int) - g._origin).tolist()
    assert g._evidence[i, j] == pytest.approx(P.max_evidence)


def test_cell_falls_free_after_the_decay() -> None:
    """From the cap e = 5, free when 5 exp(-dt / 2) < 2: dt > 2 ln 2.5 = 1.833 s."""
    g = OccupancyGrid()
    for k in range(40):
        g.learn(POST, 0.1 * k)
    last = 3.9
    far = np.array([[9.0, 9.0]])
    g.learn(far, last + 1.8)  # advances the clock only
    assert g.static_time(POST)[0] == pytest.approx(1.8 + 3.7)  # occupied since 0.2 s
    g.learn(far, last + 1.85)
    assert g.static_time(POST)[0] == 0.0
    assert 2.0 * math.log(2.5) == pytest.approx(1.8326, abs=1e-4)


def test_neighbourhood_and_unknown_places() -> None:
    g = OccupancyGrid()
    for k in range(30):
        g.learn(POST, 0.1 * k)
    near = POST + np.array([[0.1, 0.0]])  # the next cell: within the neighbourhood of 1 cell
    far = POST + np.array([[0.35, 0.0]])
    out = g.static_time(np.vstack([POST, near, far, [[-50.0, 40.0]]]))
    assert out[0] == pytest.approx(2.7) and out[1] == pytest.approx(2.7)
    assert out[2] == 0.0 and out[3] == 0.0
    tight = OccupancyGrid(OccupancyParams(neighbourhood=0))
    for k in range(30):
        tight.learn(POST, 0.1 * k)
    assert tight.static_time(near)[0] == 0.0


def test_walker_trail_never_becomes_static_for_long() -> None:
    g = OccupancyGrid()
    worst = 0.0
    for k in range(100):  # 1 m/s along x, a return every 0.1 s
        pos = np.array([[0.1 * k, 0.0]])
        g.learn(pos, 0.1 * k)
        worst = max(worst, float(g.static_time(pos)[0]))
    assert worst < 2.0


def test_grid_grows_and_keeps_what_it_learnt() -> None:
    g = OccupancyGrid()
    for k in range(30):
        g.learn(POST, 0.1 * k)
    g.learn(np.array([[-40.0, 55.0]]), 3.0)  # far away: the arrays grow
    assert g.static_time(POST)[0] == pytest.approx(2.8)


def test_grid_grows_for_a_return_just_past_its_arrays() -> None:
    """A laser at the origin has seen posts 7 m away along -x, +y and -y and 1 m away
    along +x, so its arrays end nearest along +x. A new return half a cell past that end
    (and nearer than the arrays reach on every other side): the arrays grow to hold it,
    and it is learnt (the shortcut that skips the check when the disc of the farthest
    return lies inside the arrays must see that this one does not)."""
    g = OccupancyGrid(OccupancyParams(max_range=100.0))
    sensor = np.zeros(2)
    posts = np.array([[-7.03, 0.07], [0.03, 7.07], [0.03, -7.03], [1.03, 0.07]])
    for k in range(30):
        g.learn(posts, 0.1 * k, sensor=sensor)
    res = P.resolution
    edge = (int(g._origin[0]) + g._evidence.shape[0]) * res  # [m] where the arrays end
    past = np.array([[edge + 0.5 * res, 0.0]])
    assert 7.1 < past[0, 0] < 7.7  # the farthest return; the arrays reach 13 m elsewhere
    for k in range(30, 60):
        g.learn(np.vstack([posts, past]), 0.1 * k, sensor=sensor)
    assert g.static_time(past)[0] == pytest.approx(2.7)
    assert g.static_time(posts) == pytest.approx([5.7] * 4)


def test_max_range_skips_far_returns() -> None:
    g = OccupancyGrid(OccupancyParams(max_range=5.0))
    for k in range(30):
        g.learn(np.array([[6.0, 0.0]]), 0.1 * k, sensor=np.zeros(2))
    assert g.static_time(np.array([[6.0, 0.0]]))[0] == 0.0


def test_frame_call_sets_foreground() -> None:
    params = OccupancyParams(background_time=1.0)
    g: StaticWorldModel = OccupancyGrid(params)
    for k in range(30):
        ranges = np.full(11, 3.0)
        ranges[5] = 1.0 + 0.1 * k  # one beam on something moving away
        scan = Scan(
            stamp=0.1 * k, index=k, angle_min=-0.5, angle_increment=0.1, ranges=ranges,
            range_max=10.0,
        )  # fmt: skip
        frame = g(frame_from_scan(scan))
    assert frame.foreground is not None and frame.points is not None
    assert frame.foreground.tolist() == [i == 5 for i in range(11)]


def _write_map(tmp_path, negate: int = 0, image: str = "map.pgm"):  # type: ignore[no-untyped-def]
    pixels = np.full((4, 5), 254, dtype=np.uint8)  # free
    pixels[0, 0] = 0  # top-left obstacle: the largest y, the smallest x
    pixels[3, 4] = 0  # bottom-right obstacle
    if negate:
        pixels = 255 - pixels
    Image.fromarray(pixels).save(tmp_path / image)
    yaml = tmp_path / "map.yaml"
    yaml.write_text(
        f"image: {image}\nresolution: 0.5\norigin: [-1.0, 2.0, 0.0]\n"
        f"negate: {negate}\noccupied_thresh: 0.65\nfree_thresh: 0.196  # comment\n"
    )
    return yaml


@pytest.mark.parametrize(("negate", "image"), [(0, "map.pgm"), (1, "map.png")])
def test_ros_map_loading(tmp_path, negate: int, image: str) -> None:  # type: ignore[no-untyped-def]
    m = load_ros_map(_write_map(tmp_path, negate, image))
    assert m.occupied.shape == (4, 5) and m.occupied.sum() == 2
    # pixel (row 0, col 0) covers x in [-1, -0.5], y in [3.5, 4.0]
    # pixel (row 3, col 4) covers x in [1, 1.5], y in [2, 2.5]
    pts = np.array([[-0.75, 3.75], [1.25, 2.25], [0.25, 3.0], [10.0, 10.0]])
    assert m.contains_obstacle(pts).tolist() == [True, True, False, False]
    g = OccupancyGrid(prior=m)
    assert g.static_time(pts).tolist()[:3] == [math.inf, math.inf, 0.0]


def test_a_seeded_grid_names_its_map(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """`track --map` says which map seeded the grid and how many obstacle cells it holds
    (2 of the 20 pixels), so that a user sees the map was read; a grid without one does
    not mention a map."""
    from laserpeople.pipeline.background import describe_background

    yaml = _write_map(tmp_path)
    said = describe_background(OccupancyGrid(prior=load_ros_map(yaml)), " in the world frame")
    assert said == (
        "static world model: occupancy grid in the world frame, seeded by the map "
        f"{yaml} (2 obstacle cells of 0.5 m)"
    )
    assert "map" not in describe_background(OccupancyGrid(), " in the world frame")


def test_ros_map_errors(tmp_path) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(MapFileError):
        load_ros_map(tmp_path / "none.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("image: missing.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n")
    with pytest.raises(MapFileError, match="cannot read the map image"):
        load_ros_map(bad)
    bad.write_text("image: missing.pgm\n")
    with pytest.raises(MapFileError, match="lacks resolution, origin"):
        load_ros_map(bad)


def test_free_space_cast_by_hand() -> None:
    """A beam from the origin to a return at (1.05, 0.01): cells x = 0..8 (samples 0.05,
    0.15, ..., 0.85 < |(1.05, 0.01)| - free_margin = 0.8500) are seen free, the return's
    cell (10, 0) is not."""
    g = OccupancyGrid()
    ret = np.array([[1.05, 0.01]])
    g.learn(ret, 0.0, sensor=np.zeros(2))
    assert g.casting
    free = g._free_cells(np.zeros((1, 2)), ret)
    assert len(free) == 9 and {tuple(c) for c in free.tolist()} == {(x, 0) for x in range(9)}
    seen = np.isfinite(g._seen_free)
    cells = {
        (int(a) + int(g._origin[0]), int(b) + int(g._origin[1]))
        for a, b in zip(*np.nonzero(seen), strict=True)
    }
    assert cells == {(x, 0) for x in range(9)}


def test_occupied_at_first_sight_is_static_after_the_hold() -> None:
    """A post seen from the start (never seen free): occupied since 0.2 s (third hit); at
    6.1 s static 5.9 s (< hold 6 s); at 6.2 s 6.0 + first_sight_static = 36 s."""
    assert P.first_sight_hold == 6.0
    g = OccupancyGrid()
    for k in range(62):
        g.learn(POST, 0.1 * k, sensor=np.zeros(2))
    assert g.static_time(POST)[0] == pytest.approx(5.9)
    g.learn(POST, 6.2, sensor=np.zeros(2))
    assert g.static_time(POST)[0] == pytest.approx(6.0 + P.first_sight_static)


def test_something_that_arrived_in_seen_free_space_gets_no_head_start() -> None:
    """The post's cell is seen free (a wall behind it) for 1 s, then the post stands there:
    static only for the time it has stood."""
    g = OccupancyGrid()
    wall = POST * 2.0  # on the same beam, behind the post
    for k in range(10):
        g.learn(wall, 0.1 * k, sensor=np.zeros(2))
    for k in range(10, 60):
        g.learn(POST, 0.1 * k, sensor=np.zeros(2))
    assert g.static_time(POST)[0] == pytest.approx(5.9 - 1.2)


def test_walker_leaving_the_sensor_gets_no_head_start() -> None:
    """Walking straight away from the sensor, each footprint lands in cells the walker's own
    legs hid (never seen free), but no footprint stays occupied for first_sight_hold."""
    g = OccupancyGrid()
    worst = 0.0
    for k in range(100):  # 1 m/s along x, feet planted for 0.6 s, a return every 0.1 s
        foot = np.array([[1.0 + 0.6 * (k // 6) * 1.0, 0.0]])
        g.learn(foot, 0.1 * k, sensor=np.zeros(2))
        worst = max(worst, float(g.static_time(foot)[0]))
    assert worst < P.first_sight_hold


def test_free_cells_of_many_beams_match_a_loop_over_beams() -> None:
    """The flat (all beams at once) sampling gives, beam after beam, the cells of a plain
    loop that walks each beam every resolution from half a cell on while the sample is
    closer than min(range - free_margin, free_range); one sensor or one per beam."""
    rng = np.random.default_rng(5)
    g = OccupancyGrid(OccupancyParams(free_range=4.0))
    p = g.params
    for per_beam in (False, True):
        pts = rng.uniform(-7.0, 7.0, size=(60, 2))
        pts[0] = [0.1, 0.0]  # shorter than the margin: no free cell
        sensor = rng.normal(size=(60, 2)) * 0.3 if per_beam else np.tile([0.2, -0.1], (60, 1))
        expected = []
        for o, q in zip(sensor, pts, strict=True):
            r = float(np.hypot(*(q - o)))
            reach = min(r - p.free_margin, p.free_range)
            s = 0.5 * p.resolution
            k = 0
            while s < reach:
                x, y = o + (q - o) / r * s
                expected.append((math.floor(x / p.resolution), math.floor(y / p.resolution)))
                k += 1
                s = 0.5 * p.resolution + k * p.resolution
        got = [tuple(c) for c in g._free_cells(sensor, pts).tolist()]
        assert got == expected


def _learnt_grid(seed: int, params: OccupancyParams | None = None) -> OccupancyGrid:
    """A grid fed 40 frames of a random room (some returns stay, some move) from a sensor
    that drifts, with NaN returns in some frames."""
    rng = np.random.default_rng(seed)
    g = OccupancyGrid(params)
    posts = rng.uniform(-4.0, 4.0, size=(30, 2))
    for k in range(40):
        walkers = rng.uniform(-4.0, 4.0, size=(10, 2))
        pts = np.vstack([posts + rng.normal(scale=0.01, size=posts.shape), walkers])
        if k % 7 == 3:
            pts[rng.integers(0, len(pts), 3)] = np.nan
        g.learn(pts, 0.15 * k, sensor=np.array([0.02 * k, -0.01 * k]))
    return g


def test_static_time_inside_and_at_the_edge_of_the_arrays_matches_a_loop() -> None:
    """static_time (one flat index per neighbour cell inside the arrays, a masked path at
    their edge) equals a plain loop over each position's neighbour cells."""
    p = P
    for seed in range(4):
        g = _learnt_grid(seed)
        h, w = g._evidence.shape
        lo = (g._origin * p.resolution).astype(float)
        hi = ((g._origin + np.array([h, w])) * p.resolution).astype(float)
        rng = np.random.default_rng(100 + seed)
        inside = rng.uniform(-4.0, 4.0, size=(40, 2))
        edge = np.vstack([lo + 0.03, hi - 0.03, [lo[0] - 1.0, 0.0], [0.0, hi[1] + 1.0]])
        for pos in (inside, edge, np.vstack([inside[:5], edge])):
            expected = []
            for x, y in pos:
                ci = math.floor(x / p.resolution) - int(g._origin[0])
                cj = math.floor(y / p.resolution) - int(g._origin[1])
                best = 0.0
                for i in range(ci - 1, ci + 2):
                    for j in range(cj - 1, cj + 2):
                        if not (0 <= i < h and 0 <= j < w):
                            continue
                        dt = max(g.stamp - g._touched[i, j], 0.0)
                        e = g._evidence[i, j] * math.exp(-dt / p.decay_time)
                        since = g._since[i, j]
                        t = g.stamp - since if e >= p.occupied_evidence and since == since else 0.0
                        if g._first_sight[i, j] and t >= p.first_sight_hold:
                            t += p.first_sight_static
                        best = max(best, t)
                expected.append(best)
            assert g.static_time(pos) == pytest.approx(expected, abs=1e-12)


def test_free_flat_indices_are_the_free_cells() -> None:
    """The flat indices of the casting are those of _free_cells, sample by sample."""
    rng = np.random.default_rng(7)
    g = _learnt_grid(1)
    sensor = np.tile([0.3, -0.2], (50, 1))
    pts = rng.uniform(-3.5, 3.5, size=(50, 2))
    cells = g._free_cells(sensor, pts)
    assert len(cells) > 100
    assert g._free_flat(sensor, pts).tolist() == g._flat(cells).tolist()


@pytest.mark.regression  # bits from two code paths: CI runs it again on another CPU path
def test_static_time_of_few_positions_is_the_array_path_bit_for_bit(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The plain-float path for a few positions (``FEW_POSITIONS``) gives the array path's
    values bit for bit, inside the arrays, at their edge (where it hands over to the array
    path), for non-finite positions, and for cells whose decayed evidence lies exactly at
    ``occupied_evidence`` (decided by numpy's exp)."""
    from laserpeople.background import occupancy

    for seed in range(6):
        g = _learnt_grid(seed, OccupancyParams(neighbourhood=seed % 3))
        h, w = g._evidence.shape
        lo = (g._origin * P.resolution).astype(float)
        hi = ((g._origin + np.array([h, w])) * P.resolution).astype(float)
        rng = np.random.default_rng(200 + seed)
        cases = [rng.uniform(-4.5, 4.5, size=(m, 2)) for m in (1, 2, 3, 5, 8, 9)]
        cases += [np.vstack([lo + 0.03, [0.5, 0.5]]), np.vstack([hi - 0.03, [0.5, 0.5]])]
        cases.append(np.array([[np.nan, 0.0], [1.0, 1.0]]))
        # a cell whose decayed evidence is the threshold itself: evidence 2 touched now
        flat = int(np.flatnonzero(np.isfinite(g._touched.reshape(-1)))[0])
        g._evidence.reshape(-1)[flat] = P.occupied_evidence
        g._touched.reshape(-1)[flat] = g.stamp
        g._since.reshape(-1)[flat] = g.stamp - 7.0
        i, j = divmod(flat, w)
        at = (np.array([i, j]) + g._origin + 0.5) * P.resolution
        cases.append(at[None, :])
        with np.errstate(invalid="ignore"):  # (the array path casts the nan position)
            fast = [g.static_time(pos) for pos in cases]
            assert fast[-1][0] >= 7.0  # (the cell at the threshold is occupied)
            monkeypatch.setattr(occupancy, "FEW_POSITIONS", 0)
            slow = [g.static_time(pos) for pos in cases]
            monkeypatch.undo()
        for a, b in zip(fast, slow, strict=True):
            assert a.dtype == b.dtype and a.shape == b.shape
            assert a.tobytes() == b.tobytes()


STATIC_TOL = 1e-9
"""Tolerance [s] of a static time computed by two code paths (times are 0-1000 s)."""


def _same_static_times(got: list[float] | None, want: list[float] | None) -> bool:
    """Both None, or the same positions static (time > 0) with times within STATIC_TOL."""
    if got is None or want is None:
        return got is None and want is None
    return (
        len(got) == len(want)
        and [g > 0.0 for g in got] == [w > 0.0 for w in want]
        and all(abs(g - w) <= STATIC_TOL for g, w in zip(got, want, strict=True))
    )


@pytest.mark.regression  # two code paths: CI runs it again on another CPU path
def test_compiled_static_time_of_few_positions_is_the_python_one(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The compiled static time of a few positions (the MHT's C extension) is the Python
    one on learnt grids (cells free, occupied, first sight held: the same positions
    static, each static time within STATIC_TOL; they are the same IEEE operations, so
    the same floats on one machine, but a C compiler and libm may differ in the last
    bit on another CPU), and leaves
    to it (NotImplemented) the positions it hands to the array path (not finite, cells
    outside the arrays) and a decayed evidence at the threshold (numpy's exp decides);
    without the extension the Python one runs alone, with the same values."""
    from laserpeople.background import occupancy

    compiled = occupancy._compiled_static_few()
    if compiled is None:
        pytest.skip("the C extension is not built, or stale")
    answered = left = 0
    held_seen = False
    for seed in range(8):
        g = _learnt_grid(seed, OccupancyParams(neighbourhood=seed % 3))
        h, w = g._evidence.shape
        hi = ((g._origin + np.array([h, w])) * P.resolution).astype(float)
        rng = np.random.default_rng(300 + seed)
        cases = [rng.uniform(-4.5, 4.5, size=(m, 2)).tolist() for m in (1, 2, 3, 5, 8)]
        cases += [[[0.5, 0.5], (hi - 0.03).tolist()], [[math.nan, 0.0]], [[1.0, math.inf]]]
        # positions on occupied cells (since set), a few at a time; a third of them
        # occupied at first sight, held long enough to count as static from the start
        occupied = np.flatnonzero(np.isfinite(g._since.reshape(-1)))
        chosen = rng.choice(occupied, size=24)
        held = chosen[::3]
        g._first_sight.reshape(-1)[held] = True
        g._since.reshape(-1)[held] = g.stamp - g.params.first_sight_hold - 0.5
        g._evidence.reshape(-1)[held] = g.params.max_evidence
        g._touched.reshape(-1)[held] = g.stamp
        cells = np.column_stack(np.divmod(chosen, w)) + g._origin
        centres = ((cells + 0.5) * P.resolution).tolist()
        cases += [centres[k : k + 3] for k in range(0, 24, 3)]
        for xy in cases:
            want = g._static_few_python(xy)
            got = g._static_few(xy)
            assert _same_static_times(got, want)
            assert got is None or all(type(v) is float for v in got)
            monkeypatch.setattr(occupancy, "_static_few_compiled", None)
            assert _same_static_times(g._static_few(xy), want)
            monkeypatch.undo()
            if want is not None and any(v > 0.0 for v in want):
                answered += 1
                held_seen = held_seen or max(want) >= g.params.first_sight_static
        # a cell whose decayed evidence is the threshold itself: left to Python
        flat = int(np.flatnonzero(np.isfinite(g._touched.reshape(-1)))[0])
        g._evidence.reshape(-1)[flat] = P.occupied_evidence
        g._touched.reshape(-1)[flat] = g.stamp
        g._since.reshape(-1)[flat] = g.stamp - 7.0
        i, j = divmod(flat, w)
        at = ((np.array([i, j]) + g._origin + 0.5) * P.resolution).tolist()
        p = g.params
        args = (g._evidence, g._touched, g._since, g._first_sight, *g._origin.tolist())
        tail = (p.resolution, p.neighbourhood, g.stamp, p.decay_time, p.occupied_evidence)
        tail += (p.first_sight_hold, p.first_sight_static, 1e-9 * p.occupied_evidence)
        if i >= p.neighbourhood and j >= p.neighbourhood:
            assert compiled(*args, [at], *tail) is NotImplemented
            left += 1
            want = g._static_few_python([at])
            assert want is not None and want[0] >= 7.0
            assert _same_static_times(g._static_few([at]), want)
    assert answered > 10 and held_seen and left > 0
    # arrays it cannot read as they are (not C-contiguous, another dtype): left to Python
    ev = g._evidence[:, ::2]
    assert compiled(ev, ev, ev, g._first_sight[:, ::2], *args[4:], [at], *tail) is NotImplemented
    assert compiled(*args[:3], g._evidence, *args[4:], [at], *tail) is NotImplemented


def test_plain_float_exp_agrees_with_numpy_away_from_the_guard() -> None:
    """``math.exp`` and ``np.exp`` of the decay exponents the grid forms differ by at most
    an ulp or two, far inside the 1e-9 guard of the plain-float path."""
    rng = np.random.default_rng(3)
    x = -rng.uniform(0.0, 40.0, size=20_000) / P.decay_time
    ours = np.array([math.exp(v) for v in x.tolist()])
    assert np.allclose(ours, np.exp(x), rtol=1e-14, atol=0.0)


def test_free_period_casts_once_per_period_while_the_laser_stands_still() -> None:
    """``free_period`` 0.5 s with a frame every 0.1 s from a laser standing still: free
    space is cast at 0, 0.5, 1.0 s (the frames in between only add their returns), so the
    beam's free cells hold the stamp of the last cast frame, 1.0 s, after the frames up to
    1.2 s; with 0 (every frame) they hold the last frame's, 1.2 s. The return's cell is
    occupied alike. A laser that moves casts in every frame: the same grid as with 0."""
    ret = np.array([[1.05, 0.01]])
    beam = np.array([0])
    every = OccupancyGrid(OccupancyParams(free_period=0.0))
    sparse = OccupancyGrid(OccupancyParams(free_period=0.5))
    for k in range(13):
        for g in (every, sparse):
            g.learn(ret, 0.1 * k, sensor=np.zeros(2), beams=beam)
    free = every._flat(every._free_cells(np.zeros((1, 2)), ret))
    assert np.all(every._seen_free_now().reshape(-1)[free] == pytest.approx(1.2))
    assert np.all(sparse._seen_free_now().reshape(-1)[free] == pytest.approx(1.0))
    assert np.array_equal(every._evidence, sparse._evidence)
    assert every.static_time(ret)[0] == sparse.static_time(ret)[0] > 0.0
    every = OccupancyGrid(OccupancyParams(free_period=0.0))
    sparse = OccupancyGrid(OccupancyParams(free_period=0.5))
    for k in range(13):
        sensor = np.array([0.0, 0.01 * k])
        for g in (every, sparse):
            g.learn(ret, 0.1 * k, sensor=sensor, beams=beam)
    assert np.array_equal(every._seen_free_now(), sparse._seen_free_now())
    with pytest.raises(ValueError, match="free_period"):
        OccupancyParams(free_period=-1.0)


def _post_frame(stamp: float, sensor: str) -> Frame:
    """A frame of one laser ``sensor`` whose middle beam returns at 1 m (its other beams
    see nothing within range)."""
    ranges = np.full(3, np.inf)
    ranges[1] = 1.0
    scan = Scan(
        stamp=stamp, angle_min=-0.1, angle_increment=0.1, ranges=ranges, range_max=10.0,
        sensor=sensor,
    )  # fmt: skip
    return frame_from_scan(scan)


def test_learn_period_learns_each_sensor_at_most_once_per_period() -> None:
    """``learn_period`` 0.05 s with one laser at 50 Hz: of the frames at 0, 0.02, ..., 0.10 s
    those at 0 and 0.06 s are learned (0.10 - 0.06 < 0.05), 4 are not. The return's cell
    then has two hits, e = 1 + e^(-0.06 / 2) = 1.970 < 2 (free: static 0 s), where learning
    every frame gives it six (1.990 at 0.02 s, occupied since 0.04 s: static 0.06 s at
    0.10 s). Two lasers
    whose frames alternate every 0.02 s are each learned: A at 0 and 0.08, B at 0.02."""
    every = OccupancyGrid(OccupancyParams(learn_period=0.0))
    period = OccupancyGrid(OccupancyParams(learn_period=0.05))
    for k in range(6):
        for g in (every, period):
            g.learn_frame(_post_frame(0.02 * k, "a"))
    post = np.array([[1.0, 0.0]])
    assert (every.skipped, period.skipped) == (0, 4)
    assert period.stamp == every.stamp == pytest.approx(0.10)  # aged to the last frame
    assert every.static_time(post)[0] == pytest.approx(0.06)
    assert period.static_time(post)[0] == 0.0
    i, j = (np.floor(post[0] / P.resolution).astype(int) - period._origin).tolist()
    assert period._evidence[i, j] == pytest.approx(1.0 + math.exp(-0.03))
    two = OccupancyGrid(OccupancyParams(learn_period=0.05))
    for k in range(5):
        two.learn_frame(_post_frame(0.02 * k, "ab"[k % 2]))
    assert two.skipped == 2 and two._learned_at == pytest.approx({"a": 0.08, "b": 0.02})
    with pytest.raises(ValueError, match="learn_period"):
        OccupancyParams(learn_period=-0.1)


def test_frames_not_learned_are_said() -> None:
    from laserpeople.pipeline.background import describe_background

    g = OccupancyGrid(OccupancyParams(learn_period=0.05))
    assert describe_background(g) == "static world model: occupancy grid"
    for k in range(3):
        g.learn_frame(_post_frame(0.02 * k, "a"))
    said = describe_background(g)
    assert said.endswith("grid; 2 frames not learned (each laser at most every 0.05 s)"), said


def test_the_auto_models_grid_says_its_frames_not_learned() -> None:
    from laserpeople.pipeline.background import AutoBackground

    auto = AutoBackground()
    grid = OccupancyGrid(OccupancyParams(learn_period=0.05))
    for k in range(3):
        grid.learn_frame(_post_frame(0.02 * k, "a"))
    auto.model, auto.chosen, auto.switched_at = grid, "occupancy", 4
    said = auto.describe()
    assert said.startswith("static world model: occupancy grid (a laser moved at frame 4")
    assert said.endswith("; 2 frames not learned (each laser at most every 0.05 s)"), said


@pytest.mark.parametrize("yaw", [0.0, 0.4])
def test_obstacles_within_a_radius_as_a_window_around_each_position(yaw: float) -> None:
    """``contains_obstacle(p, r)`` (and the once-dilated map the grid asks) is True where
    an obstacle pixel lies in the (2r + 1)^2 window of pixels around p's, counted here
    pixel by pixel, also for positions off the image next to its edge."""
    from laserpeople.background.occupancy import OccupancyMap

    rng = np.random.default_rng(3)
    occupied = rng.random((12, 9)) < 0.05
    occupied[0, 0] = occupied[11, 8] = True  # obstacles on the corners
    grid = OccupancyMap(occupied=occupied, resolution=0.1, origin=(1.0, -2.0, yaw))
    c, s = np.cos(yaw), np.sin(yaw)
    uv = rng.uniform(-0.5, 1.4, (400, 2))  # in the map's axes, beyond the image too
    pos = np.array([1.0, -2.0]) + uv[:, :1] * [c, s] + uv[:, 1:] * [-s, c]
    col = np.floor(uv[:, 0] / 0.1 + 1e-9).astype(int)
    row = 11 - np.floor(uv[:, 1] / 0.1 + 1e-9).astype(int)
    for radius in (0, 1, 3):
        expect = []
        for r0, c0 in zip(row, col, strict=True):
            window = [
                occupied[r, q]
                for r in range(r0 - radius, r0 + radius + 1)
                for q in range(c0 - radius, c0 + radius + 1)
                if 0 <= r < 12 and 0 <= q < 9
            ]
            expect.append(any(window))
        near = np.array(expect)
        assert (grid.contains_obstacle(pos, radius) == near).mean() > 0.99
        assert (grid.dilated(radius).contains_obstacle(pos) == near).mean() > 0.99
        assert near.sum() > 20 * radius
