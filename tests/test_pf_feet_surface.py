"""The feet tracker's reported body moved beyond the leg surfaces its laser sees
(``feet_pf.report_offset``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.background.beam_histogram import BeamHistogramBackground, BeamHistogramParams
from laserpeople.evaluation.schenk_scenes import lasers_of, simulate_scene
from laserpeople.frame import Frame
from laserpeople.scan import PointSet, Pose2D, Scan
from laserpeople.tracking.particle.feet import FeetParams, FeetTracker, beyond_surface
from laserpeople.tracking.particle.frames import beam_directions, fused_frames

TOL = 1e-9
"""Tolerance of the exact shifts [m]."""


def test_shift_is_the_offset_times_the_mean_beam_direction() -> None:
    feet = np.array([[[2.0, 0.0], [2.0, 0.3]], [[5.0, 5.0], [5.2, 5.0]]])
    pts = np.array([[1.95, 0.0], [1.95, 0.3], [2.0, 0.6], [9.0, 9.0]])
    # the third point is 0.3 m from the second foot: outside radius 0.25
    rays = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, -1.0], [1.0, 0.0]])
    shift = beyond_surface(pts, rays, feet, 0.25, 0.06)
    # mean of (1, 0) and (0, 1), not its normalisation (0.0424 each) nor their sum (0.06)
    assert shift[0] == pytest.approx([0.03, 0.03], abs=TOL)
    assert shift[1] == pytest.approx([0.0, 0.0], abs=TOL)  # no point near the second filter


def test_beams_from_opposite_lasers_cancel() -> None:
    feet = np.array([[[2.0, 0.0], [2.0, 0.3]]])
    pts = np.array([[1.95, 0.0], [2.05, 0.3]])
    rays = np.array([[1.0, 0.0], [-1.0, 0.0]])
    assert beyond_surface(pts, rays, feet, 0.25, 0.06)[0] == pytest.approx([0.0, 0.0], abs=TOL)


def test_a_point_near_two_filters_moves_both() -> None:
    feet = np.array([[[2.0, 0.0], [2.0, 0.2]], [[2.0, 0.4], [2.0, 0.6]]])
    pts = np.array([[2.0, 0.3]])  # 0.1 m from a foot of each
    rays = np.array([[0.6, 0.8]])
    shift = beyond_surface(pts, rays, feet, 0.25, 0.1)
    assert shift == pytest.approx(np.array([[0.06, 0.08], [0.06, 0.08]]), abs=TOL)


def test_beam_directions_point_from_each_laser() -> None:
    # a laser at (1, 1) looking along +x (beams at 0 and 90 deg), one at (10, 0) facing -x
    a = Scan(0.0, 0.0, math.pi / 2, np.array([2.0, 3.0]), 0.05, 30.0, sensor="a")
    b = Scan(0.0, 0.0, 1.0, np.array([4.0]), 0.05, 30.0, sensor="b")
    a, b = a.with_pose(Pose2D(1.0, 1.0, 0.0)), b.with_pose(Pose2D(10.0, 0.0, math.pi))
    pts = PointSet.from_scans([a, b], "world")
    fg = np.array([True, False, True])
    frame = Frame(0, 0.0, (a, b), "fused", "world", points=pts, foreground=fg)
    assert beam_directions(frame, "test") == pytest.approx(
        np.array([[1.0, 0.0], [-1.0, 0.0]]), abs=TOL
    )
    unposed = Frame(0, 0.0, (a.with_pose(None), b), "fused", "world", points=pts, foreground=fg)
    assert beam_directions(unposed, "test") == pytest.approx(np.zeros((2, 2)), abs=TOL)


def test_the_tracker_reports_its_person_beyond_the_one_laser() -> None:
    """One feet laser: the same run (same seed) with and without the offset reports each
    track that has points near its feet moved by the offset, away from the laser."""
    rec, bg = simulate_scene("speed-normal", 3, rate=25.0)
    laser = lasers_of(rec, "feet")[0]
    model = BeamHistogramBackground(BeamHistogramParams()).learn_scans(
        s for s in bg.scans if s.sensor == laser
    )
    frames = fused_frames(rec.scans, [laser], model)
    plain, moved = FeetTracker(FeetParams(report_offset=0.0)), FeetTracker()
    assert moved.params.report_offset == pytest.approx(0.06)
    compared = coasting = 0
    for frame in frames:
        a, b = plain.update(frame), moved.update(frame)
        assert [t.track_id for t in a] == [t.track_id for t in b]
        origin = np.array([frame.scans[0].pose.x, frame.scans[0].pose.y])
        for ta, tb in zip(a, b, strict=True):
            d = np.asarray(tb.position) - np.asarray(ta.position)
            away = (np.asarray(ta.position) - origin) / np.hypot(*(ta.position - origin))
            if np.hypot(*d) < TOL:  # reported while coasting: no point near its feet
                coasting += 1
                continue
            # the points lie within 0.25 m of feet 2-4 m from the laser: beams within 8 deg
            assert np.hypot(*d) == pytest.approx(0.06, abs=0.003)
            assert d @ away > 0.055
            compared += 1
    assert compared > 20 and coasting < compared / 4


def test_a_point_near_both_feet_of_a_filter_counts_once() -> None:
    """A at (0.02, 0) lies within 0.1 m of both feet, B at (0.14, 0) of the second only:
    their mean direction is ((1, 0) + (0, 1)) / 2, not (2 (1, 0) + (0, 1)) / 3."""

    points = np.array([[0.02, 0.0], [0.14, 0.0]])
    rays = np.array([[1.0, 0.0], [0.0, 1.0]])
    feet = np.array([[[0.0, 0.0], [0.05, 0.0]]])
    np.testing.assert_allclose(
        beyond_surface(points, rays, feet, 0.1, 0.06), [[0.03, 0.03]], atol=1e-12
    )
