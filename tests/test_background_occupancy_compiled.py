"""The occupancy grid's learning of the cells a frame hits, compiled (``grid_frame``,
``grid_hits`` and ``grid_mark`` of the MHT's C extension), against its Python reference:
the same distances, cells, and the same evidence, stamps and first-sight flags to the bit
(the same IEEE operations in the same order, and numpy's ``exp`` in both)."""

from __future__ import annotations

from collections.abc import Callable, Iterator

import numpy as np
import pytest

from laserpeople.background import occupancy, still_cast
from laserpeople.background.occupancy import OccupancyGrid, OccupancyParams

Learn = tuple[np.ndarray, float, np.ndarray | None, np.ndarray | None]
"""One call of ``learn``: points (N, 2), stamp, sensor position, beam ids."""


def _compiled() -> tuple[Callable[..., object], Callable[..., object]]:
    grid = occupancy._compiled_grid()
    if grid is None:
        pytest.skip("the C extension is not built, or stale")
    return grid


def _still_room(seed: int) -> Iterator[Learn]:
    """A laser standing still at the origin (beam ids: the still cast and its live cells)
    sees walls from the start (occupied at first sight), a box put down after 2 s (it
    arrives in space seen free), a walker, NaN returns, a pause longer than the decay and
    a stamp going back."""
    rng = np.random.default_rng(seed)
    n = 181
    angles = np.linspace(-np.pi / 2, np.pi / 2, n)
    walls = rng.uniform(3.0, 6.0) / np.maximum(np.abs(np.cos(angles)), 0.3)
    stamps = [0.05 * k for k in range(80)]
    stamps += [stamps[-1] + 40.0 + 0.05 * k for k in range(20)]  # back after the decay
    stamps += [stamps[-1] - 0.02, stamps[-1] + 0.05]  # a stamp going back, then on
    for k, stamp in enumerate(stamps):
        r = walls + rng.normal(scale=0.01, size=n)
        if k >= 40:
            r[60:70] = 1.5  # the box
        walker = 20 + (k % 120)
        r[walker : walker + 6] = rng.uniform(0.8, 2.5)
        if k % 9 == 4:
            r[rng.integers(0, n, 4)] = np.nan
        pts = np.column_stack([r * np.cos(angles), r * np.sin(angles)])
        yield pts, stamp, np.zeros(2), np.arange(n)


def _wobbly_room(seed: int) -> Iterator[Learn]:
    """:func:`_still_room` with the directions of beams 20-79 off by about 1e-9 rad in
    every other frame (beyond the still cast's tolerance: their lists are computed again,
    their old samples lost)."""
    rng = np.random.default_rng(seed + 50)
    for k, (pts, stamp, sensor, beams) in enumerate(_still_room(seed)):
        if k % 2:
            turn = rng.normal(scale=1e-9, size=60)
            x, y = pts[20:80, 0].copy(), pts[20:80, 1].copy()
            pts[20:80, 0] = x * np.cos(turn) - y * np.sin(turn)
            pts[20:80, 1] = x * np.sin(turn) + y * np.cos(turn)
        yield pts, stamp, sensor, beams


def _far_room(seed: int) -> Iterator[Learn]:
    """:func:`_still_room` seen from (0.7, -0.3) with returns beyond ``max_range`` in
    some frames (they are left out), beam ids that go back in others (no still cast: the
    beams are cast one by one), both in some, and frames without a return."""
    rng = np.random.default_rng(seed + 90)
    at = np.array([0.7, -0.3])
    for k, (pts, stamp, _, beams) in enumerate(_still_room(seed)):
        pts = pts + at
        if k % 4 == 1:
            far = rng.integers(0, len(pts), 5)
            pts[far] = at + rng.uniform(31.0, 60.0, size=(5, 1)) * [[0.6, 0.8]]
        if k % 6 == 3:
            beams = beams.copy()
            beams[[10, 11]] = beams[[11, 10]]
        if k % 25 == 24:
            pts, beams = pts[:0], beams[:0]
        yield pts, stamp, at, beams


def _moving_room(seed: int) -> Iterator[Learn]:
    """Returns from a sensor that drifts (the grid grows; no still cast), then frames
    without a sensor position (no casting)."""
    rng = np.random.default_rng(seed)
    posts = rng.uniform(-4.0, 4.0, size=(30, 2))
    for k in range(60):
        walkers = rng.uniform(-4.0, 4.0, size=(12, 2))
        pts = np.vstack([posts + rng.normal(scale=0.01, size=posts.shape), walkers])
        sensor = np.array([0.03 * k, -0.01 * k]) if k < 45 else None
        yield pts, 0.1 * k, sensor, None


def _blind_room(seed: int) -> Iterator[Learn]:
    """The returns of :func:`_moving_room` without a sensor position: no free space is ever
    cast (nothing is occupied at first sight)."""
    for pts, stamp, _, _ in _moving_room(seed):
        yield pts, stamp, None, None


def _arrays(g: OccupancyGrid) -> list[bytes]:
    """The grid's learnt arrays, as bytes (NaN compared by its bits)."""
    arrays = (g._evidence, g._touched, g._since, g._first_sight, g._seen_free_now())
    return [g._origin.tobytes()] + [a.tobytes() for a in arrays]


@pytest.mark.regression  # two code paths: CI runs it again on another CPU path
@pytest.mark.parametrize("scene", [_still_room, _wobbly_room, _far_room, _moving_room, _blind_room])
@pytest.mark.parametrize("free_period", [0.0, 0.2])
def test_compiled_learning_is_the_python_one_to_the_bit(
    monkeypatch: pytest.MonkeyPatch,
    scene: Callable[[int], Iterator[Learn]],
    free_period: float,
) -> None:
    """Two grids learn the same frames, one compiled and one in Python: after every frame
    their evidence, stamps, occupied-since times, first-sight flags and seen-free times are
    the same bits (exact: each float is the same IEEE operation on the same operands, and
    the decay's exp is numpy's in both). The frames reach every branch: cells occupied at
    first sight and arrived ones, cells that stay occupied and cells decayed free, the
    still laser's live cells."""
    hits, mark = _compiled()
    cast, apply = still_cast._compiled_cast(), still_cast._compiled_cast_apply()
    look = occupancy._compiled_look()
    calls = {"hits": 0, "mark": 0, "cast": 0, "apply": 0, "look": 0}

    def counted(name: str, f: Callable[..., object]) -> Callable[..., object]:
        def call(*args: object) -> object:
            out = f(*args)
            calls[name] += out is not NotImplemented
            return out

        return call

    monkeypatch.setattr(occupancy, "_grid_compiled", (counted("hits", hits), counted("mark", mark)))
    monkeypatch.setattr(still_cast, "_cast_compiled", counted("cast", cast))
    monkeypatch.setattr(still_cast, "_cast_apply_compiled", counted("apply", apply))
    monkeypatch.setattr(occupancy, "_look_compiled", counted("look", look))
    params = OccupancyParams(free_period=free_period)
    for seed in range(3):
        fast, slow = OccupancyGrid(params), OccupancyGrid(params)
        first_seen = arrived_seen = live_seen = False
        for pts, stamp, sensor, beams in scene(seed):
            fast.learn(pts, stamp, sensor, beams)
            live_seen = live_seen or fast._still.live() is not None
            with monkeypatch.context() as m:
                m.setattr(occupancy, "_grid_compiled", None)
                m.setattr(still_cast, "_cast_compiled", None)
                m.setattr(still_cast, "_cast_apply_compiled", None)
                m.setattr(occupancy, "_look_compiled", None)
                slow.learn(pts, stamp, sensor, beams)
            assert _arrays(fast) == _arrays(slow)
            occupied = np.isfinite(fast._since)
            first_seen = first_seen or bool((fast._first_sight & occupied).any())
            arrived_seen = arrived_seen or bool((~fast._first_sight & occupied).any())
        assert first_seen == (scene is not _blind_room) and arrived_seen
        assert live_seen == (scene in (_still_room, _wobbly_room, _far_room))
    assert calls["hits"] > 100 and calls["mark"] == calls["hits"]
    # (one sensor position with beam ids and every return finite: one pass in C)
    assert calls["look"] > 200 if scene in (_still_room, _wobbly_room, _far_room) else True
    if scene in (_moving_room, _blind_room):
        assert calls["look"] == 0
    # (the usual frames take still_cast_usual, those with beams listed again (their old
    # samples lost) or not listed yet still_cast_apply)
    assert calls["cast"] > 20 if scene is _still_room else True
    assert calls["apply"] > 40 if scene is _wobbly_room else True
    if scene in (_moving_room, _blind_room):
        assert calls["cast"] == calls["apply"] == 0


@pytest.mark.parametrize("refusing", [0, 1, 2, 3, 4])
def test_a_refusal_of_the_compiled_learning_leaves_it_to_python(
    monkeypatch: pytest.MonkeyPatch, refusing: int
) -> None:
    """Where ``grid_hits``, ``grid_mark``, ``still_cast_usual``, ``still_cast_apply`` or
    ``grid_frame`` returns NotImplemented, the Python one does that part: the same grid as
    Python alone."""
    parts = [*_compiled(), still_cast._compiled_cast(), still_cast._compiled_cast_apply()]
    parts.append(occupancy._compiled_look())
    parts[refusing] = lambda *args: NotImplemented
    fast, slow = OccupancyGrid(), OccupancyGrid()
    for pts, stamp, sensor, beams in _still_room(1):
        with monkeypatch.context() as m:
            m.setattr(occupancy, "_grid_compiled", tuple(parts[:2]))
            m.setattr(still_cast, "_cast_compiled", parts[2])
            m.setattr(still_cast, "_cast_apply_compiled", parts[3])
            m.setattr(occupancy, "_look_compiled", parts[4])
            fast.learn(pts, stamp, sensor, beams)
            m.setattr(occupancy, "_grid_compiled", None)
            m.setattr(still_cast, "_cast_compiled", None)
            m.setattr(still_cast, "_cast_apply_compiled", None)
            m.setattr(occupancy, "_look_compiled", None)
            slow.learn(pts, stamp, sensor, beams)
        assert _arrays(fast) == _arrays(slow)
    assert np.isfinite(fast._since).any()


def test_cells_hit_are_sorted_once_each_and_their_decay_exponents() -> None:
    """``grid_hits``: the flat indices of the returns' cells, sorted, each once (many
    returns share a cell; indices above 2^8 and 2^16, sorted byte by byte), and
    ``-max(stamp - touched, 0) / decay_time`` of each (0 where touched later than the
    stamp)."""
    hits, _ = _compiled()
    rng = np.random.default_rng(5)
    for h, w in ((3, 4), (40, 50), (700, 900)):
        touched = rng.uniform(0.0, 20.0, size=(h, w))
        touched[0, :] = np.inf  # later than the stamp: no decay (exponent -0.0 / tau)
        touched[1, :] = -np.inf  # never: exponent -inf
        o0, o1, res = -7, 3, 0.05
        n = 2000
        cells = np.column_stack([rng.integers(0, h, n), rng.integers(0, w, n)])
        pts = (cells + np.array([o0, o1]) + rng.uniform(0.1, 0.9, size=(n, 2))) * res
        hit, exponent = np.empty(n, dtype=np.int64), np.empty(n)
        k = hits(pts, touched, o0, o1, res, 10.0, 2.5, hit, exponent)
        assert isinstance(k, int)
        want = np.unique(np.floor(pts / res).astype(np.int64) @ [w, 1] - (o0 * w + o1))
        assert hit[:k].tolist() == want.tolist()
        dt = np.maximum(10.0 - touched.reshape(-1)[want], 0.0)
        # (one IEEE division each, correctly rounded on every CPU; stated within 1e-15)
        np.testing.assert_allclose(exponent[:k], -dt / 2.5, rtol=1e-15, atol=0.0)
        assert np.isneginf(exponent[:k]).sum() == np.isin(want, np.arange(w, 2 * w)).sum()
    assert hits(np.zeros((0, 2)), touched, 0, 0, 0.05, 1.0, 2.5, hit, exponent) == 0


def test_compiled_learning_leaves_to_python_what_it_cannot_read() -> None:
    """NotImplemented, nothing written, for a return outside the arrays or not finite, an
    output too short, arrays of another dtype or not C-contiguous, or arrays of another
    size than the grid's."""
    hits, mark = _compiled()
    touched = np.zeros((10, 10))
    hit, exponent = np.full(3, 7, dtype=np.int64), np.full(3, 7.0)
    pts = np.array([[0.01, 0.01], [0.2, 0.3], [0.45, 0.05]])
    assert hits(pts, touched, 0, 0, 0.05, 1.0, 2.5, hit, exponent) == 3
    outside, below = pts + np.array([0.5, 0.0]), pts - np.array([0.0, 0.05])
    for bad in (outside, below, np.where(pts > 0.3, np.nan, pts)):
        assert hits(bad, touched, 0, 0, 0.05, 1.0, 2.5, hit, exponent) is NotImplemented
    assert hits(pts, touched, 0, 0, 0.05, 1.0, 2.5, hit[:2], exponent) is NotImplemented
    assert hits(pts, touched[:, ::2], 0, 0, 0.05, 1.0, 2.5, hit, exponent) is NotImplemented
    assert hits(pts, touched, 0, 0, 0.05, 1.0, 2.5, hit.astype(np.int32), exponent) is (
        NotImplemented
    )
    ev, tt, since = np.zeros((10, 10)), np.zeros((10, 10)), np.full((10, 10), np.nan)
    first, seen = np.zeros((10, 10), dtype=bool), np.full((10, 10), -np.inf)
    tail = (1.0, 2.0, 1.0, 10.0, 0.5, True, None, None, 0, 0.0)
    for cells in (np.array([5, 100]), np.array([-1, 5])):
        assert mark(ev, tt, since, first, seen, cells, np.ones(2), *tail) is NotImplemented
    assert mark(ev, tt, since, first, seen, hit, np.ones(2), *tail) is NotImplemented
    assert mark(ev, tt, since.astype(np.float32), first, seen, hit, np.ones(3), *tail) is (
        NotImplemented
    )
    cover = np.zeros(99, dtype=np.int32)
    live = (*tail[:6], cover, np.zeros(100, dtype=np.int64), 0, 0.0)
    assert mark(ev, tt, since, first, seen, hit, np.ones(3), *live) is NotImplemented
    assert not ev.any() and not tt.any() and np.isnan(since).all() and not first.any()
    assert mark(ev, tt, since, first, seen, hit, np.ones(3), *tail) is None
    assert ev.reshape(-1)[hit].tolist() == [1.0] * 3 and tt.reshape(-1)[hit].tolist() == [1.0] * 3


def test_a_cell_by_hand_compiled() -> None:
    """One cell through ``grid_mark``, by hand (evidence 1.5 decayed by 0.5, plus 2, at
    most 3; occupied from 2): 1.5 * 0.5 + 2 = 2.75 occupied since the stamp; again with
    factor 1, 3 (the maximum), still occupied since the first stamp; its first sight
    True only where it was not seen free within the arrival window, and kept while
    occupied."""
    _, mark = _compiled()
    ev, tt = np.full((1, 2), 1.5), np.zeros((1, 2))
    since, first = np.full((1, 2), np.nan), np.zeros((1, 2), dtype=bool)
    seen = np.array([[-np.inf, 9.8]])  # cell 1 seen free 0.2 s before the stamp 10
    hit = np.array([0, 1])
    args = (2.0, 2.0, 3.0, 0.5, True, None, None, 0, 0.0)
    assert mark(ev, tt, since, first, seen, hit, np.full(2, 0.5), 10.0, *args) is None
    assert ev.tolist() == [[2.75, 2.75]] and tt.tolist() == [[10.0, 10.0]]
    assert since.tolist() == [[10.0, 10.0]] and first.tolist() == [[True, False]]
    seen[0, 0] = 10.5  # seen free since: the flag is kept while the cell stays occupied
    assert mark(ev, tt, since, first, seen, hit, np.ones(2), 11.0, *args) is None
    assert ev.tolist() == [[3.0, 3.0]] and since.tolist() == [[10.0, 10.0]]
    assert first.tolist() == [[True, False]]
    # decayed below 2 before this return: occupied anew, since the stamp; the still
    # laser's live cell counts as seen free at the cast's stamp 11.9
    cover, frames = np.array([0, 1], dtype=np.int32), np.array([3, 3], dtype=np.int64)
    live = (2.0, 2.0, 3.0, 0.5, True, cover, frames, 4, 11.9)
    assert mark(ev, tt, since, first, seen, hit, np.full(2, 0.1), 12.0, *live) is None
    assert ev.reshape(-1).tolist() == pytest.approx([2.3, 2.3], abs=1e-12)
    assert since.tolist() == [[12.0, 12.0]] and first.tolist() == [[True, False]]


def test_the_compiled_still_cast_leaves_to_python_what_is_not_the_usual_frame() -> None:
    """``still_cast_usual`` returns NotImplemented, and writes nothing, for a beam not
    listed, beams not increasing, a direction beyond the tolerance, a changed direction of
    an unsafe list, a NaN direction or a sample count beyond the lists; and casts a frame
    by hand: beam 0 shortens from 3 samples to 1 (its cells 11 and 12 lose them: 12 had only
    that one and was live, so it gets the last frame's stamp 5.0; 11 keeps one from beam 1),
    beam 1 reaches 1 farther (cell 13 gains), beam 2 is not in the frame (cell 14 loses
    its sample but had a return in the last frame: no stamp), the return in cell 11 (live:
    stamped) and in cell 15 (not covered) get frame number 8."""
    cast = still_cast._compiled_cast()
    if cast is None:
        pytest.skip("the C extension is not built, or stale")
    listed, u_listed = np.array([3, 5, 9]), np.array([[1.0, 0.0], [0.0, 1.0], [0.6, 0.8]])
    cells = np.array([[10, 11, 12, 0], [11, 13, 0, 0], [14, 0, 0, 0]])
    safe = np.array([True, False, True])

    def state() -> tuple[np.ndarray, ...]:
        cover = np.zeros(20, dtype=np.int32)
        cover[[10, 11, 12, 11, 14]] += 1
        cover[11] = 2
        hit_frame = np.full(20, -1, dtype=np.int64)
        hit_frame[14] = 7
        return np.array([3, 1, 1]), cover, hit_frame, np.full(20, -np.inf)

    ids, n, hit = np.array([3, 5]), np.array([1, 2]), np.array([11, 15])
    u = u_listed[:2] + np.array([[1e-13, 0.0], [0.0, 0.0]])
    refused = [
        (np.array([3, 4]), u, n),  # beam 4 is not listed
        (np.array([5, 3]), u, n),  # not increasing
        (ids, u_listed[:2] + 2e-12, n),  # beyond the tolerance
        (ids, u_listed[:2] + np.array([[0.0, 0.0], [1e-13, 0.0]]), n),  # beam 5: unsafe list
        (ids, np.array([[np.nan, 0.0], [0.0, 1.0]]), n),
        (ids, u, np.array([1, 5])),  # more samples than listed
    ]
    for frame_ids, frame_u, frame_n in refused:
        ln, cover, hit_frame, seen = state()
        before = [a.copy() for a in (ln, cover, hit_frame, seen)]
        args = (frame_ids, listed, frame_u, u_listed, frame_n, ln, cells, cover, hit_frame, seen)
        assert cast(*args, hit, safe, 7, 5.0, 1e-12) is NotImplemented
        after = (ln, cover, hit_frame, seen)
        assert all(np.array_equal(a, b) for a, b in zip(after, before, strict=True))
    ln, cover, hit_frame, seen = state()
    args = (ids, listed, u, u_listed, n, ln, cells, cover, hit_frame, seen, hit, safe, 7, 5.0)
    assert cast(*args, 1e-12) is None
    assert ln.tolist() == [1, 2, 0]
    assert {c: int(cover[c]) for c in range(10, 16)} == {10: 1, 11: 1, 12: 0, 13: 1, 14: 0, 15: 0}
    assert np.flatnonzero(np.isfinite(seen)).tolist() == [11, 12] and seen[11] == seen[12] == 5.0
    assert hit_frame[[11, 15]].tolist() == [8, 8] and hit_frame[14] == 7


def test_the_compiled_coverage_of_relisted_beams_by_hand() -> None:
    """``still_cast_apply`` once the beams are listed: list 0 goes from 2 samples to 3
    (cell 12 gains), list 1 was listed again (its counts start from 0: cells 13 and 14
    gain) and its old samples, cells 11 and 15, are lost: cell 15 had only that sample and
    was live (stamped with the last frame's 4.0), cell 11 keeps list 0's. The return in
    cell 13 (not covered before) gets frame number 3. A cell outside the arrays, in the
    lists or the lost ones: NotImplemented, nothing written."""
    apply = still_cast._compiled_cast_apply()
    if apply is None:
        pytest.skip("the C extension is not built, or stale")
    cells = np.array([[10, 11, 12], [13, 14, 0]])
    cover = np.zeros(20, dtype=np.int32)
    cover[[10, 11, 15]] = [1, 2, 1]
    hit_frame, seen = np.full(20, -1, dtype=np.int64), np.full(20, -np.inf)
    n_new, n_old = np.array([3, 2]), np.array([2, 0])
    hit, lost = np.array([13]), np.array([11, 15])
    for bad_lost, bad_hit in ((np.array([11, 20]), hit), (lost, np.array([-1]))):
        args = (n_new, n_old, cells, cover, hit_frame, seen, bad_hit, bad_lost, 2, 4.0)
        assert apply(*args) is NotImplemented
    assert cover[[10, 11, 15]].tolist() == [1, 2, 1] and np.isneginf(seen).all()
    assert apply(n_new, n_old, cells, cover, hit_frame, seen, hit, lost, 2, 4.0) is None
    assert cover[10:16].tolist() == [1, 1, 1, 1, 1, 0]
    assert np.flatnonzero(np.isfinite(seen)).tolist() == [15] and seen[15] == 4.0
    assert np.flatnonzero(hit_frame >= 0).tolist() == [13] and hit_frame[13] == 3
    assert n_old.tolist() == [2, 0]  # (the caller keeps n_new)


def test_a_frame_looked_at_in_one_pass() -> None:
    """``grid_frame``: each return's distance from the sensor is numpy's ``hypot`` of the
    same differences (within 1e-15 relative: the C library's and numpy's hypot need not
    agree to the last bit on every CPU); the largest of them (0.0 without returns);
    whether the ids increase strictly (an equal pair does not); NotImplemented (r_out not
    to be read) for a return or a position not finite and for a position not given as
    floats."""
    _compiled()
    look = occupancy._compiled_look()
    rng = np.random.default_rng(3)
    for n in (0, 1, 2, 7, 361, 1081):
        pts = rng.normal(scale=rng.choice([1e-3, 5.0, 1e5]), size=(n, 2))
        ox, oy = rng.normal(scale=3.0, size=2).tolist()
        ids = np.arange(n, dtype=np.int64) * 2
        r = np.empty(n)
        reach, increasing = look(pts, ids, ox, oy, r)
        d = pts - np.array([ox, oy])
        expected = np.hypot(d[:, 0], d[:, 1])
        np.testing.assert_allclose(r, expected, rtol=1e-15, atol=0.0)
        assert reach == (float(r.max()) if n else 0.0)  # (the largest of its own distances)
        assert increasing is True
        if n > 2:
            ids[n // 2] = ids[n // 2 - 1]  # equal: not increasing
            assert look(pts, ids, ox, oy, r)[1] is False
            ids[n // 2] = ids[n // 2 - 1] - 1
            assert look(pts, ids, ox, oy, r)[1] is False
            for bad in (np.nan, np.inf):
                broken = pts.copy()
                broken[n - 1, 1] = bad
                assert look(broken, ids, ox, oy, r) is NotImplemented
    pts, ids, r = np.ones((3, 2)), np.arange(3), np.empty(3)
    assert look(pts, ids, np.nan, 0.0, r) is NotImplemented
    assert look(pts, ids, 0, 0.0, r) is NotImplemented  # (an int: the Python one)
    assert look(pts, ids[:2], 0.0, 0.0, r) is NotImplemented
    assert look(pts.astype(np.float32), ids, 0.0, 0.0, r) is NotImplemented
