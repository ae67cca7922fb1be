"""The randomised scene family, odometry-frame recordings and the seen-truth filter."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from laserpeople.scan import Pose2D
from laserpeople.sim.scenarios import build_scene, run_scenario
from laserpeople.sim.scenarios.randomised import (
    HELD_BACK_SEEDS,
    TUNING_SEEDS,
    RandomisedParams,
)
from laserpeople.sim.simulator import seen_truth, simulate
from laserpeople.truth import BeamLabels, TruthFrame


def test_seeds_split_tuning_from_held_back() -> None:
    assert not set(TUNING_SEEDS) & set(HELD_BACK_SEEDS)
    assert list(HELD_BACK_SEEDS) == list(range(100, 120))


def test_same_seed_same_scene_other_seed_other_scene() -> None:
    a = build_scene("randomised", seed=7, seconds=5.0)
    b = build_scene("randomised", seed=7, seconds=5.0)
    c = build_scene("randomised", seed=8, seconds=5.0)
    assert a.notes == b.notes
    assert [p.leg_radius for p in a.people] == [p.leg_radius for p in b.people]
    assert a.notes != c.notes


def test_drawn_values_stay_in_their_ranges() -> None:
    p = RandomisedParams()
    radii, spacing, res, fov, moving, families = [], [], [], [], [], set()
    for seed in range(40):
        scene = build_scene("randomised", seed=seed, seconds=5.0)
        radii += [q.leg_radius for q in scene.people]
        spacing += [q.hip_half_width for q in scene.people]
        laser = scene.sensors[0].laser
        res.append(laser.resolution_deg)
        fov.append(laser.fov_deg)
        moving.append(scene.robot is not None)
        families |= {k for k, n in scene.notes["clutter"].items() if n}
        assert len(scene.people) in range(1, p.people_max + 1)
        assert p.height_min <= scene.sensors[0].height <= p.height_max
        assert scene.poses_from_odometry == (scene.robot is not None)
    assert p.leg_radius_min <= min(radii) and max(radii) <= p.leg_radius_max
    assert max(radii) - min(radii) > 0.03  # the range is really used
    assert p.hip_half_width_min <= min(spacing) and max(spacing) <= p.hip_half_width_max
    assert min(res) >= 0.25 and max(res) <= 1.0 and max(res) - min(res) > 0.5
    assert min(fov) >= 180.0 - 1.0 and max(fov) < 360.0 and max(fov) - min(fov) > 120.0
    assert 10 <= sum(moving) <= 30
    assert families == {"chairs", "tables", "bins", "plants", "railings", "pillars", "poles"}


def test_scan_geometry_follows_the_drawn_scanner() -> None:
    result = run_scenario("randomised", seed=3, seconds=1.0)
    laser = build_scene("randomised", seed=3, seconds=1.0).sensors[0].laser
    scan = result.scans[0]
    assert scan.n_beams == laser.n_beams
    assert math.degrees(scan.angle_increment) == pytest.approx(laser.resolution_deg)
    period = float(np.median(np.diff([s.stamp for s in result.scans])))
    assert period == pytest.approx(1.0 / laser.rate_hz)


def test_furniture_only_scenes_have_nobody() -> None:
    result = run_scenario("randomised-furniture", seed=3, seconds=2.0)
    assert result.meta["people"] == []
    assert all(len(f) == 0 for f in result.truth)
    labels = result.scans[5].labels
    assert labels is not None and (labels.person < 0).all() and (labels.obj >= 0).any()


def _moving_seed() -> int:
    return next(s for s in range(20) if build_scene("randomised", seed=s).robot is not None)


def test_odometry_frame_moves_scans_and_truth_by_the_same_rigid_error() -> None:
    """The scene run twice, with true and with odometry poses: per scan, the rigid motion that
    takes the true sensor pose to the odometry one also takes the true people to the truth
    written in the odometry frame (independent of how the simulator composes it)."""
    seed = _moving_seed()
    scene = build_scene("randomised", seed=seed, seconds=8.0)
    odo = simulate(scene, 8.0, seed=seed)
    true = simulate(replace(scene, poses_from_odometry=False), 8.0, seed=seed)
    assert odo.meta["frame"] == "odometry" and true.meta["frame"] == "world"
    drift = []
    for k in (0, 40, len(odo.truth) - 1):
        p_true, p_odo = true.scans[k].pose, odo.scans[k].pose
        assert p_true is not None and p_odo is not None
        # C = P_odo * P_true^-1 as a 2D rigid transform
        dth = p_odo.theta - p_true.theta
        rot = np.array([[math.cos(dth), -math.sin(dth)], [math.sin(dth), math.cos(dth)]])
        shift = np.array([p_odo.x, p_odo.y]) - rot @ np.array([p_true.x, p_true.y])
        expect = true.truth[k].positions @ rot.T + shift
        np.testing.assert_allclose(odo.truth[k].positions, expect, atol=1e-6)
        np.testing.assert_array_equal(odo.scans[k].ranges, true.scans[k].ranges)
        drift.append(math.hypot(p_odo.x - p_true.x, p_odo.y - p_true.y))
    assert drift[0] == pytest.approx(0.0, abs=1e-6) and drift[-1] > 1e-3


def _labels(people: list[int]) -> BeamLabels:
    person = np.full(4, -1, dtype=np.int32)
    person[: len(people)] = people
    none = np.full(4, -1, dtype=np.int32)
    return BeamLabels(person, none.copy(), none.copy(), none.copy())


def test_seen_truth_keeps_people_hit_within_the_window() -> None:
    """Person 1 is hit at t = 0 and 5 s, person 2 never. With a 2 s window every frame is
    within 2 s of a hit of person 1; with 1 s, frames 2 and 3 are not. Person 2 never counts."""
    from laserpeople.scan import Scan

    scans = [
        Scan(
            float(t),
            -0.1,
            0.05,
            np.ones(4),
            pose=Pose2D(0, 0, 0),
            index=t,
            labels=_labels([1] if t in (0, 5) else []),
        )
        for t in range(6)
    ]
    truth = [
        TruthFrame.from_positions(float(t), t, np.array([1, 2]), np.zeros((2, 2))) for t in range(6)
    ]
    wide = seen_truth(scans, truth, 2.0)
    assert [f.person_ids.tolist() for f in wide] == [[1]] * 6
    narrow = seen_truth(scans, truth, 1.0)
    assert [f.person_ids.tolist() for f in narrow] == [[1], [1], [], [], [1], [1]]
