"""The feet tracker's counts scaled to what a coarse scanner shows of a leg (``leg_width``):
hand-computed caps, the beam spacing of a frame, and a standing person seen by a 1 deg
laser 4 m away (one beam per leg) found only with the scaling."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.frame import Frame
from laserpeople.scan import PointSet, Scan
from laserpeople.tracking.particle.feet import (
    FeetParams,
    FeetTracker,
    foreground_spacing,
    scaled_to_beams,
)


@pytest.mark.parametrize(
    ("spacing", "leg_points", "still_points", "link"),
    [
        # b = 0.12 / 0.05 = 2.4 -> 2 beams (floor, not round or ceil: 3 would keep 3 / 4)
        (0.05, 2, 4, 0.075),
        # b = 1.2 -> 1: one point a leg, two a person, link 1.5 x 0.1
        (0.1, 1, 2, 0.15),
        # b = 0.6 -> still 1 (at least one beam), link 0.3
        (0.2, 1, 2, 0.3),
        # b = 4: counts as set (3, 4); link 1.5 x 0.03 = 0.045 < 0.06 stays 0.06
        (0.03, 3, 4, 0.06),
    ],
)
def test_counts_capped_at_the_beams_on_a_leg(
    spacing: float, leg_points: int, still_points: int, link: float
) -> None:
    p = scaled_to_beams(FeetParams(), spacing)
    assert p.blob_leg_points == leg_points
    assert p.still_points == still_points
    assert p.segment_link == pytest.approx(link, rel=1e-9)


def test_fine_scanners_the_paper_and_unknown_spacing_keep_the_parameters() -> None:
    base = FeetParams()
    # a 0.5 deg LMS151 2 m away (004's setup): 0.0175 m, b = 6.9
    assert scaled_to_beams(base, 2.0 * math.radians(0.5)) is base
    off = FeetParams(leg_width=0.0)
    assert scaled_to_beams(off, 0.1) is off
    assert scaled_to_beams(base, float("nan")) is base
    from laserpeople.config import load_config

    assert load_config(FeetParams, None, "paper").leg_width == 0.0


def _scan_frame(ranges: np.ndarray, increment: float, angle_min: float = 0.0) -> Frame:
    scan = Scan(0.0, angle_min, increment, ranges, range_max=20.0, sensor="laser", index=0)
    points = PointSet.from_scans([scan], "sensor")
    return Frame(0, 0.0, (scan,), "laser", "sensor", points=points)


def test_foreground_spacing_is_range_times_angular_step() -> None:
    ranges = np.full(100, np.inf)
    ranges[10:13] = 2.0  # 0.02 m apart at 0.01 rad
    ranges[50:53] = 6.0  # 0.06 m apart
    ranges[80] = 4.0
    frame = _scan_frame(ranges, 0.01)
    # median of 0.02 x 3, 0.04, 0.06 x 3
    assert foreground_spacing(frame) == pytest.approx(0.04, rel=1e-9)
    assert frame.points is not None
    near = np.zeros(len(frame.points.points), dtype=np.bool_)
    near[:3] = True  # the foreground: the three points at 2 m
    fg = Frame(0, 0.0, frame.scans, "laser", "sensor", points=frame.points, foreground=near)
    assert foreground_spacing(fg) == pytest.approx(0.02, rel=1e-9)
    no_scans = Frame(0, 0.0, (), "laser", "sensor", points=frame.points)
    assert math.isnan(foreground_spacing(no_scans))


def _person_at_4m() -> np.ndarray:
    """Ranges of a 1 deg scanner (181 beams from +x) seeing two legs 4 m ahead, one beam
    each, 0.14 m apart (two beams of 0.07 m: linked as one object at ``link_distance``)."""
    ranges = np.full(181, np.inf)
    ranges[88] = 4.0
    ranges[90] = 4.0
    return ranges


@pytest.mark.parametrize(("leg_width", "found"), [(0.12, True), (0.0, False)])
def test_a_person_standing_4m_from_a_1_deg_scanner_starts_a_filter(
    leg_width: float, found: bool
) -> None:
    """One beam on each leg (spacing 0.07 m, b = 1.7): two points, below ``still_points`` 4 as set;
    capped at 2 x 1 beams the standing person starts a filter after ``still_time``."""
    increment = math.radians(1.0)
    tracker = FeetTracker(FeetParams(particles=50, leg_width=leg_width))
    for k in range(20):  # 15 Hz, 1.3 s
        ranges = _person_at_4m()
        scan = Scan(k / 15.0, 0.0, increment, ranges, range_max=20.0, index=k)
        points = PointSet.from_scans([scan], "sensor")
        tracker.update(Frame(k, k / 15.0, (scan,), "laser", "sensor", points=points))
    assert (len(tracker.bank) > 0) is found


def _standing(x: float) -> np.ndarray:
    """A person standing 3 m ahead at ``x``: two legs 0.2 m apart, five points each."""
    a = np.linspace(-2.4, -0.8, 5)
    legs = [
        np.column_stack([c + 0.06 * np.cos(a), 3.0 + 0.06 * np.sin(a)]) for c in (x - 0.1, x + 0.1)
    ]
    return np.vstack(legs)


@pytest.mark.parametrize(("exclusion", "filters"), [(0.6, 2), (0.85, 1)])
def test_a_person_standing_beside_a_tracked_one_gets_a_filter(
    exclusion: float, filters: int
) -> None:
    """Two people 0.75 m apart (a group's spacing in random-groups), one tracked: the other
    stands still for ``still_time`` and starts a filter only when ``birth_exclusion`` is
    below their distance (0.6 m, not 0.85 m). Without the split of a filter whose cell
    holds two people (``split_distance``), which would start it at either exclusion, and
    without the births at the first scan (``first_scan_births``), which start it at once."""
    from test_pf_feet_cells import frame_of

    params = FeetParams(
        particles=100, birth_exclusion=exclusion, split_distance=0.0, first_scan_births=False
    )
    tracker = FeetTracker(params)
    tracker.bank.add(np.stack([tracker._initial(np.array([[-0.1, 3.0], [0.1, 3.0]]))]), 0.0)
    pts = np.vstack([_standing(0.0), _standing(0.75)])
    for k in range(1, 21):  # 15 Hz, 1.3 s
        tracker.update(frame_of(pts, k / 15.0, k))
    assert len(tracker.bank) == filters
