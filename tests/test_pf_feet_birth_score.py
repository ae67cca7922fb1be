"""Births of the feet tracker only on confident legs (``feet_pf.birth_score``): on a moving
laser the foreground keeps the points near every leg detection, and a new filter starts only
where a point near its feet is not near weak legs alone (the leg MHT's people's legs count
as certain, handed on by the leg foreground at +inf)."""

from __future__ import annotations

import numpy as np

from laserpeople.pipeline.leg_foreground import LegForeground, LegForegroundParams
from laserpeople.tracking.particle.feet import FeetParams, FeetTracker, weak_points, weak_start
from laserpeople.tracks import Detections
from test_pf_feet_cells import frame_of
from test_pf_feet_independent import _person


def _legs(positions: list[tuple[float, float]], scores: list[float]) -> Detections:
    pos = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
    n = len(pos)
    return Detections(0.0, 0, pos, np.zeros((n, 2, 2)), np.asarray(scores), "world")


def test_weak_points_lie_near_weak_legs_only() -> None:
    """Legs at (0, 0) scoring 0.2 and (1, 0) scoring 0.6, reach 0.35 m, threshold 0.6:
    (0.3, 0) is near the weak leg alone (weak); (0.7, 0) is near the leg scoring exactly
    the threshold (not weak); (0.5, 0.3) is near neither (not weak: kept for another reason,
    it may start a filter); (0.34, 0) lies within reach of the weak leg, (0.36, 0) not."""
    points = np.array([[0.3, 0.0], [0.7, 0.0], [0.5, 0.3], [0.34, 0.0], [-0.36, 0.0]])
    legs = _legs([(0.0, 0.0), (1.0, 0.0)], [0.2, 0.6])
    weak = weak_points(points, legs, 0.6, 0.35)
    assert weak is not None
    assert weak.tolist() == [True, False, False, True, False]
    # a point near a weak and a strong leg is not weak
    both = weak_points(np.array([[0.5, 0.0]]), _legs([(0.3, 0), (0.7, 0)], [0.1, 0.9]), 0.6, 0.35)
    assert both is not None and both.tolist() == [False]
    # threshold 0.2 (inclusive) makes the first leg strong too; 0 or no legs: off
    low = weak_points(points, legs, 0.2, 0.35)
    assert low is not None and not low.any()
    assert weak_points(points, legs, 0.0, 0.35) is None
    assert weak_points(points, None, 0.6, 0.35) is None


def test_a_start_is_weak_when_all_its_points_are() -> None:
    """Points within 0.25 m of either foot decide; none near: not weak."""
    feet = np.array([[0.0, 0.0], [0.2, 0.0]])
    points = np.array([[0.0, 0.1], [0.2, -0.24], [1.0, 1.0]])
    assert weak_start(feet, points, np.array([True, True, False]), 0.25)
    assert not weak_start(feet, points, np.array([True, False, True]), 0.25)
    # (0.2, -0.24) lies 0.24 m from a foot: at radius 0.23 only the first point decides
    assert weak_start(feet, points, np.array([True, False, False]), 0.23)
    assert not weak_start(feet, points, np.array([False, True, True]), 0.25)
    assert not weak_start(feet + 5.0, points, np.ones(3, dtype=bool), 0.25)


def _standing(score: float, birth_score: float, scans: int = 20) -> int:
    """Filters started on a person standing at (0, 2) for ``scans`` scans at 10 Hz (the
    still detector starts one after ``still_time`` 1 s), with legs handed on scoring
    ``score``."""
    tracker = FeetTracker(FeetParams(particles=50, birth_score=birth_score, seed=1))
    legs = _legs([(-0.1, 2.0), (0.1, 2.0)], [score, score])
    for k in range(scans):
        frame = frame_of(_person(0.0, 2.0), k / 10.0, k).with_fields(legs=legs)
        tracker.update(frame)
    return len(tracker.bank)


def test_no_filter_starts_on_weak_legs_alone() -> None:
    """A person on legs scoring 0.5: with ``birth_score`` 0.6 no filter; 0.5 (inclusive)
    or 0 one; legs of the leg MHT's people (+inf) always one."""
    assert _standing(0.5, 0.6) == 0
    assert _standing(0.5, 0.5) == 1
    assert _standing(0.5, 0.0) == 1
    assert _standing(np.inf, 0.6) == 1


def test_the_leg_foreground_hands_on_scored_legs() -> None:
    """A tracker that needs steady points gets the legs whose points were kept: the frame's
    own by the detector's score, a person's (the leg MHT's) at +inf, held ones too; the
    frame's own detections are left as they are when it held them."""
    stage = LegForeground(LegForegroundParams(radius=0.3), steady=True)
    dets = _legs([(0.0, 0.0), (2.0, 0.0), (4.0, 0.0)], [0.5, 0.9, -0.1])
    mine = stage.remembered(0.0, dets.positions[dets.scores > 0], np.array([True, False]))
    handed = stage.handed_legs(dets, mine)
    assert handed.positions.tolist() == [[0.0, 0.0], [2.0, 0.0]]
    assert handed.scores.tolist() == [np.inf, 0.9]
    # 0.5 s on, nothing detected: the person's leg is held (steady_person_memory 1 s)
    empty = _legs([], [])
    held = stage.remembered(0.5, np.empty((0, 2)))
    assert stage.handed_legs(empty, held).scores.tolist() == [np.inf]
