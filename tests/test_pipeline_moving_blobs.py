"""Foreground blobs that move in the world frame (``pipeline/moving_blobs.py``) and the leg
foreground keeping them on a moving laser with poses, on hand-made frames."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.config import load_config
from laserpeople.frame import Frame
from laserpeople.pipeline.leg_foreground import LegForeground, LegForegroundParams
from laserpeople.pipeline.moving_blobs import MovingBlobs, blob_labels
from laserpeople.scan import PointSet, Scan
from laserpeople.tracks import Detections

LEGS = np.array([[0.0, 0.0], [0.1, 0.0], [0.3, 0.05], [0.4, 0.05]])
"""Two legs of a person, 0.3 m apart (4 points, extent 0.40 m)."""
WALL = np.column_stack([np.linspace(0.0, 2.0, 21), np.zeros(21)])
"""A wall: 21 points 0.1 m apart (extent 2 m, no person)."""


def test_blobs_are_person_sized_groups_of_two_or_more_points() -> None:
    points = np.vstack([LEGS, WALL + np.array([0.0, 3.0]), [[5.0, 5.0]], [[9.0, 9.0], [9.0, 9.2]]])
    labels = blob_labels(points, np.ones(len(points), dtype=bool))
    assert labels[:4].tolist() == [0] * 4  # the legs 0.2 m apart are linked (< 0.35 m)
    assert (labels[4:25] == -1).all()  # the wall is wider than 0.8 m
    assert labels[25] == -1  # a single point
    assert labels[26:].tolist() == [1, 1]
    masked = blob_labels(points, np.r_[np.zeros(4, bool), np.ones(len(points) - 4, bool)])
    assert (masked[:4] == -1).all()  # points outside the mask are in no blob


def _run(step: float, frames: int, dt: float = 0.1) -> list[bool]:
    """Whether the person-sized blob LEGS, moved ``step`` [m] along x per frame, is kept."""
    blobs = MovingBlobs(travel=0.3, seconds=0.5)
    kept = []
    for k in range(frames):
        pts = np.vstack([LEGS + np.array([step * k, 0.0]), [[5.0, 5.0], [5.1, 5.0]]])
        out = blobs(k * dt, pts, np.ones(len(pts), dtype=bool))
        assert not out[4:].any()  # the still blob nearby is never kept
        assert out[:4].all() == out[:4].any()  # a blob is kept whole or not at all
        kept.append(bool(out[:4].all()))
    return kept


def test_a_blob_that_walks_is_kept_once_it_moved_travel_over_seconds() -> None:
    # 0.1 m per 0.1 s: at 0.5 s it is 0.5 m from where it was at 0 s (>= 0.3 m)
    kept = _run(0.1, 10)
    assert kept == [False] * 5 + [True] * 5


def test_a_still_or_slow_blob_is_dropped() -> None:
    assert _run(0.0, 15) == [False] * 15
    # 0.02 m per 0.1 s: the oldest centre of the last 1 s lies at most 0.2 m away
    assert _run(0.02, 30) == [False] * 30


def test_a_blob_that_jumped_once_is_dropped_and_a_walker_that_stops_too() -> None:
    blobs = MovingBlobs(travel=0.3, seconds=0.5)
    mask = np.ones(len(LEGS), dtype=bool)
    # one jump of 0.4 m (its association switched, or part of it was hidden), then still:
    # 0.4 m from its oldest centre, but its centre halfway in time lies where it is now
    for k in range(12):
        out = blobs(k * 0.1, LEGS + np.array([0.0 if k == 0 else 0.4, 0.0]), mask)
        assert not out.any()
    walker = MovingBlobs(travel=0.3, seconds=0.5)
    for k in range(7):
        out = walker(k * 0.1, LEGS + np.array([0.1 * k, 0.0]), mask)
    assert out.all()
    for k in range(7, 20):  # stands at 0.6 m for 1.3 s: no longer kept
        out = walker(k * 0.1, LEGS + np.array([0.6, 0.0]), mask)
    assert not out.any()
    # a stamp going back forgets the blobs
    for k in range(7):
        out = walker(k * 0.1, LEGS + np.array([0.1 * k, 0.0]), mask)
    assert out.all()
    assert not walker(0.0, LEGS + np.array([0.6, 0.0]), mask).any()


def test_the_nearest_blob_continues_within_the_gate() -> None:
    blobs = MovingBlobs(travel=0.3, seconds=0.5)
    mask = np.ones(len(LEGS), dtype=bool)
    blobs(0.0, LEGS, mask)
    # a jump of 0.6 m (beyond the 0.5 m gate) is a new blob, not a blob that moved
    assert not blobs(0.5, LEGS + np.array([0.6, 0.0]), mask).any()
    assert not blobs(1.0, LEGS + np.array([0.6, 0.0]), mask).any()


def test_the_paper_preset_keeps_only_points_near_legs() -> None:
    assert load_config(LegForegroundParams, None, "paper").moving_travel == 0.0
    assert LegForegroundParams().moving_travel == 0.5


def test_params_are_checked() -> None:
    with pytest.raises(ValueError, match="travel"):
        MovingBlobs(travel=0.0, seconds=0.5)
    with pytest.raises(ValueError, match="moving_travel"):
        LegForegroundParams(moving_travel=-0.1)
    with pytest.raises(ValueError, match="moving_seconds"):
        LegForegroundParams(moving_seconds=0.0)


def _world_frame(points: np.ndarray, stamp: float) -> Frame:
    scan = Scan(stamp, 0.0, 0.01, np.full(4, 2.0), sensor="l")
    n = len(points)
    no_legs = Detections(stamp, 0, np.empty((0, 2)), np.empty((0, 2, 2)), np.empty(0), "world")  # type: ignore[arg-type]
    return Frame(
        0,
        stamp,
        (scan,),
        "l",
        frame="world",
        points=PointSet(stamp, points, np.zeros(n), np.arange(n), ("l",), "world"),
        legs=no_legs,
    )


@pytest.mark.parametrize("moving", [True, False])
def test_leg_foreground_keeps_a_moving_blob_without_legs_only_on_a_moving_laser(
    moving: bool,
) -> None:
    stage = LegForeground(LegForegroundParams(moving_travel=0.3, moving_seconds=0.5))
    stage.moving = moving
    for k in range(8):
        pts = np.vstack([LEGS + np.array([0.1 * k, 0.0]), WALL + np.array([0.0, 3.0])])
        out = stage(_world_frame(pts, 0.1 * k))
    assert out.foreground is not None
    assert out.foreground[:4].all() == moving  # the walker without leg detections
    assert not out.foreground[4:].any()  # the wall
    assert stage.points_moving == (4 * 3 if moving else 0)  # frames at 0.5, 0.6, 0.7 s
    off = LegForeground(LegForegroundParams(moving_travel=0.0))
    off.moving = True
    for k in range(8):
        pts = np.vstack([LEGS + np.array([0.1 * k, 0.0]), WALL + np.array([0.0, 3.0])])
        out = off(_world_frame(pts, 0.1 * k))
    assert out.foreground is not None and not out.foreground.any()


def test_a_blob_that_stood_and_then_moved_fast_is_not_yet_a_walker() -> None:
    """Still for 0.5 s, then 0.15 m per frame: 0.45 m from its first centre at 0.8 s, but
    its centre halfway in time still lies on the first (the halfway check from the first)."""
    blobs = MovingBlobs(travel=0.3, seconds=0.5)
    mask = np.ones(len(LEGS), dtype=bool)
    xs = [0.0] * 6 + [0.15, 0.30, 0.45]
    kept = [bool(blobs(0.1 * k, LEGS + np.array([x, 0.0]), mask).all()) for k, x in enumerate(xs)]
    assert kept == [False] * 9
    # a steady walk from the start is kept: 0.35 m over 0.5 s at the sixth frame
    steady = MovingBlobs(travel=0.3, seconds=0.5)
    walked = [bool(steady(0.1 * k, LEGS + np.array([0.07 * k, 0.0]), mask).all()) for k in range(9)]
    assert walked == [False] * 5 + [True] * 4


def test_a_walker_passes_its_history_to_one_blob_only() -> None:
    """A walking blob, then in the last frame a second blob appears 0.43 m from where the
    walker's centre was (within the 0.5 m gate, apart from its points): only the nearer one
    continues the walker; the newcomer starts its own history and is not kept."""
    blobs = MovingBlobs(travel=0.3, seconds=0.5)
    mask = np.ones(len(LEGS), dtype=bool)
    for k in range(8):
        out = blobs(0.1 * k, LEGS + np.array([0.1 * k, 0.0]), mask)
    assert out.all()
    walker = LEGS + np.array([0.8, 0.0])
    newcomer = np.array([[0.875, 0.45], [0.925, 0.45]])  # 0.43 m from (0.9, 0.025)
    pts = np.vstack([walker, newcomer])
    out = blobs(0.8, pts, np.ones(len(pts), dtype=bool))
    assert out[:4].all()
    assert not out[4:].any()
