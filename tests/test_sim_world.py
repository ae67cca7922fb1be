"""World geometry, routes, odometry drift, accessories and sensor models against hand values."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from laserpeople.sim.accessories import accessory_geometry
from laserpeople.sim.groups import circle_slots, line_offsets
from laserpeople.sim.motion import Route, sample_route
from laserpeople.sim.robot import OdometryParams, integrate_odometry
from laserpeople.sim.sensors import LASER_MODELS
from laserpeople.sim.world import World, chair, room, round_bin, table


def test_room_doors_leave_gaps() -> None:
    walls = room(0.0, 0.0, 10.0, 4.0, doors=(("south", 5.0, 2.0),))
    south = walls[0].segments
    np.testing.assert_allclose(south, [[0.0, 0.0, 4.0, 0.0], [6.0, 0.0, 10.0, 0.0]])
    assert sum(len(w.segments) for w in walls) == 5


def test_furniture_heights_and_static_map() -> None:
    world = World([*room(0, 0, 5, 5), *table(2, 2), *chair(4, 4), round_bin(1, 4)])
    assert world.n_objects == 4 + 5 + 1  # table legs, chair legs + back, bin
    feet = world.primitives(0.2)
    assert feet.circle_radii.size == 4 + 4 + 1  # table and chair legs, the bin
    upper = world.primitives(1.1)
    assert upper.circle_radii.size == 0  # nothing but walls at upper-body height
    assert upper.segment_starts.shape[0] == 4
    smap = world.static_map()
    json.dumps(smap)
    assert len(smap["circles"]) == 9 and smap["kinds"]["9"] == "bin"


def test_route_timing_and_headings() -> None:
    route = Route(0.0, 0.0, 0.0).walk_to(3.0, 4.0, 1.0).wait(2.0).turn_by(math.pi / 2, 1.0)
    assert route.end_time == pytest.approx(8.0)  # 5 m at 1 m/s, 2 s, 1 s
    track = sample_route(route, 10.0)
    xy, heading, vel = track.at(np.array([2.5, 6.5, 9.5]))
    np.testing.assert_allclose(xy[0], [1.5, 2.0], atol=0.01)  # mid-walk
    np.testing.assert_allclose(vel[0], [0.6, 0.8], atol=0.01)
    assert heading[0] == pytest.approx(math.atan2(4, 3), abs=0.01)  # facing the motion
    assert heading[2] == pytest.approx(math.atan2(4, 3) + math.pi / 2, abs=0.01)  # turned
    np.testing.assert_allclose(vel[2], [0.0, 0.0], atol=1e-6)


def test_odometry_scale_error_and_heading_drift() -> None:
    route = Route(0.0, 0.0, 0.0).walk_to(10.0, 0.0, 1.0)
    track = sample_route(route, 12.0, smoothing=0.0)
    rng = np.random.default_rng(0)
    scale_only = OdometryParams(0.02, 0.0, 0.0, 0.0, 0.0)
    odo = integrate_odometry(track, scale_only, rng)
    assert odo[-1, 0] == pytest.approx(10.2)  # 2 % too far
    assert odo[-1, 1] == pytest.approx(0.0) and odo[-1, 2] == pytest.approx(0.0)
    drift_only = OdometryParams(0.0, 0.01, 0.0, 0.0, 0.0)
    odo = integrate_odometry(track, drift_only, rng)
    assert odo[-1, 2] == pytest.approx(0.1)  # 0.01 rad/m over 10 m
    # heading grows linearly with distance, so the path bends to y = 0.01 x^2 / 2
    assert odo[-1, 1] == pytest.approx(0.5, rel=0.01)


def test_formations_keep_neighbours_apart() -> None:
    slots = circle_slots((0.0, 0.0), 5, spacing=0.75)
    d = np.linalg.norm(slots - np.roll(slots, 1, axis=0), axis=1)
    np.testing.assert_allclose(d, 0.75)
    offs = line_offsets(4)
    np.testing.assert_allclose(offs[:3, 1], [-0.75, 0.0, 0.75])
    assert offs[3, 0] < 0.0  # the fourth walks behind


def test_accessories_sit_where_they_are_carried() -> None:
    xy = np.array([[1.0, 2.0]])
    heading = np.array([math.pi / 2])  # facing +y: right-hand side is +x
    legs = np.array([[[0.9, 2.0], [1.1, 2.0]]])
    suitcase = accessory_geometry("suitcase-carried", xy, heading, legs, 0.07).segments[0]
    centre = suitcase[:, :2].mean(axis=0)
    np.testing.assert_allclose(centre, [1.32, 2.0], atol=1e-9)
    cart = accessory_geometry("baggage-cart", xy, heading, legs, 0.07).segments[0]
    np.testing.assert_allclose(cart[:, :2].mean(axis=0), [1.0, 2.85], atol=1e-9)
    skirt = accessory_geometry("long-skirt", xy, heading, legs, 0.07).ellipses[0, 0]
    assert skirt[0] == pytest.approx(1.0) and skirt[2] >= 0.1 + 0.07  # encloses both legs
    with pytest.raises(ValueError):
        accessory_geometry("jetpack", xy, heading, legs, 0.07)


def test_laser_models_have_the_datasheet_geometry() -> None:
    lms151 = LASER_MODELS["sick-lms151"]
    assert (lms151.n_beams, lms151.rate_hz) == (541, 50.0)
    fan = lms151.fan()
    assert fan.angle_min == pytest.approx(-math.radians(135.0))
    assert fan.angles[-1] == pytest.approx(math.radians(135.0))
    assert LASER_MODELS["sick-lms200"].n_beams == 361
    assert LASER_MODELS["hokuyo-utm-30lx"].n_beams == 1081
    assert LASER_MODELS["hokuyo-urg-04lx"].n_beams == 682
