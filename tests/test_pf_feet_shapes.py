"""The feet tracker's point shapes (departures from 004): points on a surface segment
longer than a leg weigh ``long_weight`` in eqs. 3-4 (a carried suitcase's face), and a
filter on a blob without legs reports the blob's centre (``blob_body``, a long skirt)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.evaluation.schenk_scenes import run_tracker, simulate_scene
from laserpeople.frame import Frame
from laserpeople.scan import PointSet
from laserpeople.tracking.particle.feet import (
    FeetParams,
    FeetTracker,
    _leg_segments,
    blob_centres,
    foot_likelihood,
)


def arc(cx: float, cy: float, r: float, a0: float, a1: float, n: int) -> np.ndarray:
    """n points on a circle's arc from angle a0 to a1 [rad]."""
    t = np.linspace(a0, a1, n)
    return np.column_stack([cx + r * np.cos(t), cy + r * np.sin(t)])


def segment(x0: float, x1: float, y: float, n: int) -> np.ndarray:
    """n points on a line y = const from x0 to x1."""
    return np.column_stack([np.linspace(x0, x1, n), np.full(n, y)])


def test_eq3_4_with_point_weights() -> None:
    """Each point's kernel times its weight: exp(-0.5) 0.1 + exp(-2) 1 (delta 0.1); the
    floor is applied to the weighted sum."""
    feet = np.array([[[0.0, 0.0], [5.0, 5.0]]])
    pts = np.array([[[0.1, 0.0], [0.0, 0.2]]])
    mask = np.ones((1, 2), dtype=bool)
    w = np.array([[0.1, 1.0]])
    o = foot_likelihood(feet, pts, mask, 0.1, 0.05, w)
    assert o[0, 0] == pytest.approx(0.1 * math.exp(-0.5) + math.exp(-2.0), rel=1e-5)
    assert o[0, 1] == 0.05
    ones = foot_likelihood(feet, pts, mask, 0.1, 0.05, np.ones((1, 2)))
    assert np.allclose(ones, foot_likelihood(feet, pts, mask, 0.1, 0.05))


def test_leg_segments_keep_a_leg_and_drop_a_suitcase_face_and_strays() -> None:
    """A leg's arc (radius 0.06 m, 7 points) is leg-shaped; a 0.45 m face at 0.017 m
    spacing (largest eigenvalue 0.45^2 / 12 = 0.017 m^2 > 0.007) is not, nor are two
    stray points (fewer than 3)."""
    leg = arc(0.0, 0.0, 0.06, -2.5, -0.6, 7)
    face = segment(1.0, 1.45, 0.0, 27)
    stray = np.array([[3.0, 0.0], [3.02, 0.0]])
    legs = _leg_segments(np.vstack([leg, face, stray]), 0.06, 0.007, 3)
    assert legs[:7].all() and not legs[7:].any()


def test_long_segments_weigh_less_in_the_tracker() -> None:
    """``long_weight`` on the points of the face, 1 on the leg's; 1 everywhere when
    ``long_weight`` is 1 (004)."""
    pts = np.vstack([arc(0.0, 0.0, 0.06, -2.5, -0.6, 7), segment(1.0, 1.45, 0.0, 27)])
    w = FeetTracker(FeetParams(particles=10, long_weight=0.1))._leg_weights(pts)
    assert np.all(w[:7] == 1.0) and np.allclose(w[7:], 0.1)
    assert np.all(FeetTracker(FeetParams(particles=10, long_weight=1.0))._leg_weights(pts) == 1)


def test_blob_centre_is_the_middle_of_the_extent_along_the_heading() -> None:
    """A skirt's two sides seen by two lasers: the left side from x = -0.1 to 0.3 m
    (y = 0.2, 21 points), the right side from -0.3 to 0.2 m (y = -0.2, 26 points) with a
    rear cap (a half circle of radius 0.2 m about (-0.3, 0), reaching x = -0.5) linked to
    it. Heading +x: along, the extent is -0.5 .. 0.3 -> -0.1; across, the mean of the
    points. A second filter 2 m away has no blob (NaN)."""
    left = segment(-0.1, 0.3, 0.2, 21)
    right = segment(-0.3, 0.2, -0.2, 26)
    cap = arc(-0.3, 0.0, 0.2, 1.7, 4.6, 30)
    pts = np.vstack([left, right, cap])
    legs = np.zeros(len(pts), dtype=bool)
    anchors = np.array([[0.0, 0.0], [2.0, 0.0]])
    heading = np.array([[1.0, 0.0], [1.0, 0.0]])
    c = blob_centres(pts, legs, anchors, heading, 0.15, 0.3)
    assert c[0, 0] == pytest.approx(-0.1, abs=1e-4)
    assert c[0, 1] == pytest.approx(pts[:, 1].mean(), abs=1e-9)
    assert np.isnan(c[1]).all()


def test_a_blob_with_a_leg_is_no_blob() -> None:
    """The same sides with one leg-shaped point set linked to them: no blob (the walking
    model stays in charge); with zero heading the blob centre is the plain mean."""
    pts = np.vstack([segment(-0.1, 0.3, 0.2, 21), segment(-0.3, 0.2, 0.05, 26)])
    legs = np.zeros(len(pts), dtype=bool)
    legs[:3] = True
    anchor = np.array([[0.0, 0.1]])
    assert np.isnan(blob_centres(pts, legs, anchor, np.ones((1, 2)), 0.15, 0.3)).all()
    c = blob_centres(pts, np.zeros(len(pts), bool), anchor, np.zeros((1, 2)), 0.15, 0.3)
    assert np.allclose(c[0], pts.mean(axis=0))


@pytest.fixture(scope="module")
def carried() -> tuple:
    """004 Exp. 6 "carry case": a suitcase carried at the right hand, seed 5 (not a table
    seed), at 25 Hz to keep the test short."""
    return simulate_scene("suitcase-carried", 5, rate=25.0)


@pytest.fixture(scope="module")
def skirt() -> tuple:
    """004 Exp. 6 "skirt": a long skirt enclosing both legs, seed 5, at 25 Hz."""
    return simulate_scene("long-skirt", 5, rate=25.0)


def test_carried_suitcase_weighs_less_than_the_legs(carried: tuple) -> None:
    """Mean adapted MOTP over seven filter seeds: measured 0.75 with ``long_weight`` 0.1,
    0.52-0.55 with 1 (004): the filter's feet settled on the right leg and the suitcase's
    face. (One seed is not enough: seed 0 with 0.1 gave 0.76 on AVX-512 and 0.56 with
    OpenBLAS's Nehalem kernels and numpy's baseline loops.)"""
    rec, bg = carried

    def mean_motp(long_weight: float) -> float:
        runs = [
            run_tracker(
                rec, bg, "feet", FeetTracker(FeetParams(long_weight=long_weight, seed=s))
            ).motp
            for s in range(7)
        ]
        return float(np.mean(runs))

    on = mean_motp(0.1)
    assert on > 0.68
    assert on > mean_motp(1.0) + 0.12


def test_skirt_reports_the_blob_centre(skirt: tuple) -> None:
    """Measured 0.81 with ``blob_body``, 0.61 without (004): the filter's feet
    ride at the rear of the skirt's sides."""
    rec, bg = skirt
    on = run_tracker(rec, bg, "feet", FeetTracker()).motp
    off = run_tracker(rec, bg, "feet", FeetTracker(FeetParams(blob_body=False))).motp
    assert on > 0.7 and on > off + 0.05


@pytest.mark.parametrize("rescue", [True, False])
def test_a_foot_touching_a_cart_still_supports_its_filter(rescue: bool) -> None:
    """A cart's side (1 m, 41 points at y = 0.3, largest eigenvalue 0.083 m^2 > 0.065)
    with a foot's arc (radius 0.06 m about (0, 0.12), 7 points) 0.1 m from it: linked at
    ``link_distance`` 0.15 m the two are one too-big object, apart at ``segment_link``
    0.06 m the arc is leg-shaped. A filter with feet at (0, +-0.12) is supported (within
    ``support_radius`` 0.1 m) by the arc with ``rescue_legs`` only; the cart's side lies
    0.18 m from the foot and supports it in neither case."""
    cart = segment(-0.5, 0.5, 0.3, 41)
    foot = arc(0.0, 0.12, 0.06, 0.3, 2.8, 7)
    tracker = FeetTracker(FeetParams(particles=20, seed=1, rescue_legs=rescue, support_radius=0.1))
    init = np.zeros((1, 20, 8))
    init[..., 5] = 1.0  # period; stride 0: the walking model moves no foot
    init[0, :, 0:4] = [0.0, 0.12, 0.0, -0.12]
    tracker.bank.add(init, 0.0)
    tracker.bank.hits[:] = 0
    pts = np.vstack([cart, foot])
    n = len(pts)
    frame = Frame(
        0,
        0.0,
        (),
        "fused",
        "world",
        points=PointSet(0.0, pts, np.zeros(n, np.int64), np.arange(n), ("laser",), "world", 0),
    )
    tracker.update(frame)
    assert len(tracker.bank) == 1
    assert tracker.bank.hits[0] == (1 if rescue else 0)
