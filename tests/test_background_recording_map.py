"""The map of what stayed put in a whole recording (``background/recording_map.py``)."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.background.recording_map import RecordingMapCounter, RecordingMapRule

WALL_X = np.arange(-2.0, 2.0, 0.02) + 0.005  # (no return on a cell's edge)
WALL_Y = 3.01
FRAMES = 20


def _frame(extra: list[tuple[float, float]], origin: tuple[float, float] = (0.0, 0.0)) -> tuple:
    """(origins, points) of one frame: a wall along y = 3 m seen from ``origin``, and the
    returns ``extra``; every beam to the wall runs from ``origin``."""
    wall = np.column_stack([WALL_X, np.full(WALL_X.size, WALL_Y)])
    points = np.vstack([wall, np.array(extra, dtype=np.float64).reshape(-1, 2)])
    return np.broadcast_to(np.array(origin, dtype=np.float64), points.shape).copy(), points


def _counted(rule: RecordingMapRule) -> RecordingMapCounter:
    """Twenty frames: the wall; a post at (1, 1.5) in every frame; a person at (0, 1.5)
    in frames 0-9, then the beam to the wall at (0, 3) passes their place; a bin at
    (-1, 1.5) in frames 0-3 only, with no beam through it otherwise (the beams to the
    wall behind it end on it in frames 0-3 and are left out later, as if out of view)."""
    counter = RecordingMapCounter(rule)
    for k in range(FRAMES):
        extra = [(1.01, 1.51)]
        if k < 10:
            extra.append((0.01, 1.51))
        if k < 4:
            extra.append((-1.01, 1.51))
        origins, points = _frame(extra)
        if k >= 4:  # no beam reaches the wall behind the bin's place
            keep = ~((points[:, 1] == WALL_Y) & (np.abs(points[:, 0] + 2.0) < 0.15))
            origins, points = origins[keep], points[keep]
        counter.add(origins, points)
    return counter


def _static_at(counter: RecordingMapCounter, xy: list[tuple[float, float]]) -> list[bool]:
    grid = counter.static_map()
    return grid.contains_obstacle(np.array(xy, dtype=np.float64)).tolist()


def test_walls_and_a_post_are_static_a_person_who_left_and_a_brief_bin_are_not() -> None:
    counter = _counted(RecordingMapRule())
    assert counter.frames == FRAMES
    # wall, post: hit in all 20 frames, never seen through
    assert _static_at(counter, [(-1.5, WALL_Y), (0.5, WALL_Y), (1.01, 1.51)]) == [True, True, True]
    # person: 10 hits, 10 frames seen free (0.5 < 0.97); bin: 4 hits (< 5); free floor
    assert _static_at(counter, [(0.01, 1.51), (-1.01, 1.51), (0.01, 0.81)]) == [False, False, False]


def test_the_share_and_the_fewest_hits_decide() -> None:
    """The near misses: a share of 0.5 takes the person who stood half the time as static,
    four hits take the bin."""
    half = _counted(RecordingMapRule(hit_share=0.5))
    assert _static_at(half, [(0.01, 1.51), (-1.01, 1.51)]) == [True, False]
    four = _counted(RecordingMapRule(min_hits=4))
    assert _static_at(four, [(0.01, 1.51), (-1.01, 1.51)]) == [False, True]


def test_a_cell_hit_and_passed_in_one_frame_counts_as_hit() -> None:
    """A leg at (0, 1.5) in every frame with the wall seen beside it through the same cell
    (a return 0.02 m past the leg's centre on the beam to (0, 3)): hit in all 20, never
    free, so static; free in every frame where it is not hit."""
    counter = RecordingMapCounter(RecordingMapRule())
    for _ in range(FRAMES):
        counter.add(*_frame([(0.01, 1.51)]))
    assert _static_at(counter, [(0.01, 1.51)]) == [True]
    passed = RecordingMapCounter(RecordingMapRule())
    for k in range(FRAMES):
        passed.add(*_frame([(0.01, 1.51)] if k == 0 else []))
    assert _static_at(passed, [(0.01, 1.51)]) == [False]


def test_the_map_lies_where_the_returns_are_from_any_origin() -> None:
    """The arrays grow as a robot drives 30 m; the map's cells lie where the returns were
    (within one 0.05 m cell) in every part of the drive, with the image's rows from the
    largest y down."""
    counter = RecordingMapCounter(RecordingMapRule())
    for k in range(FRAMES):
        x = 1.5 * k
        origins, points = _frame([(1.01 + x, 1.51)], origin=(x, 0.0))
        counter.add(origins, points + np.array([x, 0.0]) * (points[:, 1:] < WALL_Y))
    grid = counter.static_map("the test")
    assert grid.path == "the test" and grid.resolution == pytest.approx(0.05)
    posts = np.array([(1.01 + 1.5 * k, 1.51) for k in range(FRAMES)])
    # each post hit in one frame only: not static; the wall from every origin: static
    assert not grid.contains_obstacle(posts).any()
    wall = np.array([(x, WALL_Y) for x in np.arange(-1.9, 1.9, 0.1)])
    assert grid.contains_obstacle(wall).all()
    assert not grid.contains_obstacle(wall - [0.0, 0.1]).any()
    assert grid.occupied.shape[0] * grid.resolution > 3.0


def _drifting_post(rule: RecordingMapRule) -> RecordingMapCounter:
    """A post seen where the poses put it: at x = 1.03 m in the even frames, 1.07 m in the
    odd ones (0.04 m of drift, the next cell); in each frame a beam to the wall passes the
    middle of the cell where the other frames see it."""
    counter = RecordingMapCounter(rule)
    for k in range(FRAMES):
        if k % 2 == 0:
            post, through = (1.03, 1.52), (2.1218, 3.01)
        else:
            post, through = (1.07, 1.52), (2.0231, 3.01)
        counter.add(*_frame([post, through]))
    return counter


def test_a_post_seen_a_few_centimetres_apart_is_static_within_the_hit_reach() -> None:
    # each place is hit in 10 frames and passed by a beam in the other 10: share 0.5, not
    # static; a beam within 0.2 m of a return of its own frame does not see the cell
    places = [(1.03, 1.52), (1.07, 1.52)]
    assert _static_at(_drifting_post(RecordingMapRule(hit_reach=0.0)), places) == [False, False]
    assert _static_at(_drifting_post(RecordingMapRule(hit_reach=0.2)), places) == [True, True]


def test_the_hit_reach_keeps_a_person_who_left_free() -> None:
    """The person of :func:`_counted` at (0, 1.5) for frames 0-9: after they left no return
    lies within 0.2 m of their place, so its cells are seen free, as with no reach."""
    counter = _counted(RecordingMapRule(hit_reach=0.2))
    assert _static_at(counter, [(0.01, 1.51), (0.01, 0.81)]) == [False, False]
    assert _static_at(counter, [(1.01, 1.51), (0.5, WALL_Y)]) == [True, True]


def test_reach_offsets_are_the_cells_within_the_reach() -> None:
    assert RecordingMapRule(hit_reach=0.0).reach_offsets().tolist() == [[0, 0]]
    got = {tuple(o) for o in RecordingMapRule(hit_reach=0.1).reach_offsets().tolist()}
    # two cells of 0.05 m: the disc of radius 2 cells, 13 offsets (not the 5 x 5 square)
    assert len(got) == 13 and (2, 0) in got and (1, 1) in got and (2, 1) not in got
