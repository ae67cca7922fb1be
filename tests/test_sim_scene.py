"""Whole-scene simulation: legs and torso where they should be, occlusion, labels, noise."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from laserpeople.scan import Pose2D, Scan
from laserpeople.sim import Scene, simulate
from laserpeople.sim.motion import Route
from laserpeople.sim.people import PersonSpec, with_feet_apart
from laserpeople.sim.sensors import SensorSpec
from laserpeople.sim.world import World, pole, room, wall
from laserpeople.truth import BeamLabels


def _standing(pid: int, x: float, y: float, heading: float, **kw: object) -> PersonSpec:
    return PersonSpec(
        pid,
        Route(x, y, heading).wait(5.0),
        hue=0.0,
        leg_radius=0.06,
        hip_half_width=0.1,
        torso_axes=(0.14, 0.2),
        **kw,  # type: ignore[arg-type]
    )


def _sensor(height: float, **kw: object) -> SensorSpec:
    # one beam every 0.5 deg over 180 deg, facing +x from the origin, noise-free
    return SensorSpec(
        "s",
        "sick-lms200",
        height,
        Pose2D(0.0, 0.0, 0.0),
        sigma=0.0,
        dropout=0.0,
        **kw,  # type: ignore[arg-type]
    )


def _first_scan(scene: Scene) -> Scan:
    return simulate(scene, 0.1, seed=0).scans[0]


def _labels(scan: Scan) -> BeamLabels:
    assert scan.labels is not None
    return scan.labels


def test_standing_legs_are_hit_where_hand_computation_puts_them() -> None:
    # facing +x at (3, 0): left leg (0) at (3, 0.1), right leg (1) at (3, -0.1), r = 0.06
    scene = Scene(World([]), [_standing(7, 3.0, 0.0, 0.0)], [_sensor(0.2)])
    scan = _first_scan(scene)
    labels = _labels(scan)
    ranges = scan.ranges
    angles = scan.angles
    for leg, (cx, cy) in ((0, (3.0, 0.1)), (1, (3.0, -0.1))):
        a = angles
        proj = cx * np.cos(a) + cy * np.sin(a)
        disc = 0.06**2 - (cx**2 + cy**2 - proj**2)
        expected_beams = np.flatnonzero(disc >= 0)
        beams = np.flatnonzero(labels.leg == leg)
        np.testing.assert_array_equal(beams, expected_beams)
        assert np.all(labels.person[beams] == 7)
        expected = proj[beams] - np.sqrt(disc[beams])
        np.testing.assert_allclose(ranges[beams], expected, atol=1e-9)
    assert np.all(labels.person[labels.leg < 0] == -1)  # nothing else of the person
    assert np.all(np.isinf(ranges[labels.person < 0]))  # nothing else in this world


def test_one_leg_hides_the_other() -> None:
    # facing +y at (3, 0): the right leg (3.1, 0) stands straight behind the left (2.9, 0)
    scan = _first_scan(Scene(World([]), [_standing(1, 3.0, 0.0, math.pi / 2)], [_sensor(0.2)]))
    labels = _labels(scan)
    assert np.count_nonzero(labels.leg == 0) == 5  # |angle| <= asin(0.06 / 2.9) = 1.19 deg
    assert np.count_nonzero(labels.leg == 1) == 0


def test_torso_is_hit_at_upper_body_height_and_legs_are_not() -> None:
    scene = Scene(World([]), [_standing(2, 3.0, 0.0, math.pi / 2)], [_sensor(1.1)])
    scan = _first_scan(scene)
    labels = _labels(scan)
    centre = scan.n_beams // 2
    # facing +y, the torso's across semi-axis (0.2) lies along x: hit at 3 - 0.2
    assert scan.ranges[centre] == pytest.approx(2.8)
    assert labels.person[centre] == 2
    assert np.all(labels.leg == -1)
    # seen from the sensor the torso is 2 x 0.14 m wide (its depth semi-axis lies across
    # the beams): beams within asin(0.14 / 3) = 2.67 deg hit, i.e. -2.5 ... +2.5 deg
    assert np.count_nonzero(labels.person == 2) == 11


def test_person_behind_another_is_not_hit() -> None:
    front = _standing(0, 2.0, 0.0, math.pi / 2)
    back = _standing(1, 5.0, 0.0, math.pi / 2)
    scene = Scene(World([]), [front, back], [_sensor(1.1)])
    scan = _first_scan(scene)
    assert np.count_nonzero(_labels(scan).person == 0) > 0
    assert np.count_nonzero(_labels(scan).person == 1) == 0
    # move the front person aside and the back one appears
    aside = _standing(0, 2.0, 1.5, math.pi / 2)
    scan2 = _first_scan(Scene(World([]), [aside, back], [_sensor(1.1)]))
    assert np.count_nonzero(_labels(scan2).person == 1) > 0


def test_walls_and_max_range() -> None:
    world = World(room(-1.0, -5.0, 4.0, 5.0))
    scan = _first_scan(Scene(world, [], [_sensor(0.2)]))
    centre = scan.n_beams // 2
    assert scan.ranges[centre] == pytest.approx(4.0)
    assert np.all(_labels(scan).obj == -1)
    # a wall beyond the LMS 200's 8 m range returns nothing (inf), or 0 on request
    far = World(room(-1.0, -50.0, 20.0, 50.0))
    s_inf = _first_scan(Scene(far, [], [_sensor(0.2)]))
    assert np.isinf(s_inf.ranges[centre])
    s_zero = _first_scan(Scene(far, [], [_sensor(0.2, no_return="zero")]))
    assert s_zero.ranges[centre] == 0.0
    assert not s_zero.valid[centre]


def test_noise_and_dropouts_follow_the_sensor_model() -> None:
    world = World(room(-1.0, -20.0, 3.0, 20.0))
    spec = SensorSpec("s", "sick-lms200", 0.2, Pose2D(), sigma=0.02, dropout=0.1)
    result = simulate(Scene(world, [], [spec]), 10.0, seed=1, rate=10.0)
    ranges = np.stack([s.ranges for s in result.scans])
    clean = np.stack(
        [simulate(Scene(world, [], [_sensor(0.2)]), 0.1).scans[0].ranges] * len(result.scans)
    )
    dropped = ~np.isfinite(ranges) & np.isfinite(clean)
    assert dropped.sum() / np.isfinite(clean).sum() == pytest.approx(0.1, abs=0.01)
    both = np.isfinite(ranges) & np.isfinite(clean)
    err = ranges[both] - clean[both]
    assert err.std() == pytest.approx(0.02, rel=0.05)
    assert abs(err.mean()) < 0.002
    # dropped beams carry no labels
    labels_obj = np.stack([_labels(s).obj for s in result.scans])
    labels_person = np.stack([_labels(s).person for s in result.scans])
    assert np.all(labels_obj[dropped] == -1) and np.all(labels_person[dropped] == -1)


def test_beam_labels_match_the_objects_hit() -> None:
    from laserpeople.sim import run_scenario

    result = run_scenario("office", seconds=2.0, seed=5)
    smap = result.meta["static_map"]
    circles = {int(c[5]): c for c in smap["circles"]}
    for scan, frame in zip(result.scans[::5], result.truth[::5], strict=True):
        pts = scan.points("world")
        lab = _labels(scan)
        legs = np.flatnonzero(lab.leg >= 0)
        assert legs.size > 0
        for b in legs:
            j = int(np.flatnonzero(frame.person_ids == lab.person[b])[0])
            centre = frame.leg_positions[j, int(lab.leg[b])]
            radius = result.meta["people"][int(lab.person[b])]["leg_radius_m"]
            assert abs(np.hypot(*(pts[b] - centre)) - radius) < 0.05  # 5 sigma of the 0.01 m noise
        for b in np.flatnonzero(lab.obj >= 0):
            oid = int(lab.obj[b])
            if oid in circles:
                x, y, r = circles[oid][:3]
                assert abs(np.hypot(pts[b, 0] - x, pts[b, 1] - y) - r) < 0.05


def test_feet_apart_raises_a_narrow_hip_to_leg_radius_plus_half_the_gap() -> None:
    narrow = PersonSpec(0, Route(0.0, 0.0, 0.0), 0.0, leg_radius=0.09, hip_half_width=0.08)
    wide = PersonSpec(1, Route(0.0, 0.0, 0.0), 0.0, leg_radius=0.06, hip_half_width=0.12)
    # 0.09 + 0.03 / 2 = 0.105 (not 0.12 = r + gap, not 0.09 = r): legs 3 cm apart at rest
    assert with_feet_apart(narrow).hip_half_width == pytest.approx(0.105, abs=1e-12)
    assert with_feet_apart(narrow, gap=0.05).hip_half_width == pytest.approx(0.115, abs=1e-12)
    assert with_feet_apart(wide).hip_half_width == pytest.approx(0.12, abs=1e-12)
    assert with_feet_apart(narrow).leg_radius == narrow.leg_radius


def _in_view_scene(dropout: float, in_view: bool = True) -> Scene:
    """Facing +x from the origin, 180 deg, 8 m: person 1 in the open at 3 m; person 2 at
    (4, 2.5) behind a wall from (2, 0.6) to (2, 3.5); person 3 behind the scanner at
    (-3, 0); person 4 at 9.0 m, beyond the 8 m range; person 5 at (3, -2) with one leg
    (3, -1.9) hidden behind a pole on its beam, the other (3, -2.1) in the open."""
    people = [
        _standing(1, 3.0, 0.0, 0.0),
        _standing(2, 4.0, 2.5, 0.0),
        _standing(3, -3.0, 0.0, 0.0),
        _standing(4, 8.5, -math.sqrt(9.0**2 - 8.5**2), 0.0),
        _standing(5, 3.0, -2.0, 0.0),
    ]
    pole_xy = np.array([3.0, -1.9]) / 2.0
    world = World([wall(2.0, 0.6, 2.0, 3.5), pole(*pole_xy, radius=0.03)])
    sensor = replace(_sensor(0.2), dropout=dropout)
    return Scene(world, people, [sensor], truth_in_view=in_view)


def test_truth_in_view_counts_only_people_the_scanner_can_see() -> None:
    everyone = simulate(_in_view_scene(0.0, in_view=False), 0.3, seed=0).truth
    assert [f.person_ids.tolist() for f in everyone] == [[1, 2, 3, 4, 5]] * len(everyone)
    result = simulate(_in_view_scene(0.0), 0.3, seed=0)
    assert len(result.truth) >= 2
    for frame in result.truth:
        # behind the wall, outside the field of view and out of range are not counted; a
        # person with one leg hidden is
        assert frame.person_ids.tolist() == [1, 5]
        np.testing.assert_allclose(frame.positions, [[3.0, 0.0], [3.0, -2.0]], atol=1e-9)
    labels = _labels(result.scans[0])
    assert not np.any(labels.leg[labels.person == 5] == 0)  # its left leg is hidden
    assert np.any(labels.leg[labels.person == 5] == 1)


def test_truth_in_view_is_geometry_not_the_sensor_noise() -> None:
    # every beam dropped: nothing returns, but who could be seen is still counted
    result = simulate(_in_view_scene(1.0), 0.3, seed=0)
    assert np.all(_labels(result.scans[0]).person == -1)
    assert [f.person_ids.tolist() for f in result.truth] == [[1, 5]] * len(result.truth)


def test_a_scene_truth_is_in_view_or_seen_within_not_both() -> None:
    with pytest.raises(ValueError, match="not both"):
        Scene(World([]), [], [_sensor(0.2)], truth_seen_within=2.0, truth_in_view=True)
