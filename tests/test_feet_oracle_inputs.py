"""benchmarks/feet_oracle_inputs.py: the returns it takes for a person's legs, the truth in the
frame of the tracker's points, and its one birth per free shown person."""

from __future__ import annotations

import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

from laserpeople.frame import Frame
from laserpeople.scan import Pose2D
from laserpeople.tracking.particle.feet import FeetParams, FeetTracker

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


def _oracle() -> ModuleType:
    sys.path.insert(0, str(BENCH))
    try:
        import feet_oracle_inputs
    finally:
        sys.path.remove(str(BENCH))
    return feet_oracle_inputs


LEGS = np.array([[[1.0, 0.0], [1.2, 0.0]]])


def test_near_legs_takes_returns_within_the_reach_of_a_leg_centre() -> None:
    mod = _oracle()
    reach = mod.NEAR_LEG
    pts = np.array(
        [
            [1.0 - reach + 0.001, 0.0],  # just inside the left leg's reach
            [1.0 - reach - 0.001, 0.0],  # just outside
            [1.2, reach - 0.001],  # inside the right leg's
            [1.1, 0.2],  # 0.2 m from both: outside
        ]
    )
    assert mod.near_legs(pts, LEGS).tolist() == [True, False, True, False]
    assert mod.near_legs(pts, np.empty((0, 2, 2))).tolist() == [False] * 4


def test_truth_moved_into_the_sensor_frame_of_the_points() -> None:
    mod = _oracle()
    pose = Pose2D(2.0, 1.0, np.pi / 2)
    frame = Frame(index=0, stamp=0.0, scans=(), topic="t", frame="sensor", sensor_pose=pose)
    local = mod._in_frame(frame, LEGS)
    # the laser at (2, 1) facing +y: the world point (1, 0) lies 1 m behind-left, at (-1, 1)
    np.testing.assert_allclose(local[0, 0], [-1.0, 1.0], atol=1e-12)
    back = pose.transform_points(local.reshape(-1, 2))
    np.testing.assert_allclose(back, LEGS.reshape(-1, 2), atol=1e-12)
    world = Frame(index=0, stamp=0.0, scans=(), topic="t", frame="world", sensor_pose=pose)
    np.testing.assert_allclose(mod._in_frame(world, LEGS), LEGS)


def test_oracle_births_start_one_filter_per_shown_person_without_one_near() -> None:
    mod = _oracle()
    tracker = FeetTracker(FeetParams(particles=50))
    legs = np.array(
        [
            [[0.0, 0.0], [0.2, 0.0]],  # shown, no filter: born
            [[3.0, 0.0], [3.2, 0.0]],  # not shown (no return within reach): not born
        ]
    )
    shown = np.array([[0.05, 0.0]])
    mod._oracle_births(tracker, legs, shown, 0.0)
    assert len(tracker.bank) == 1
    mid = np.einsum("fp,fpc->fc", tracker.bank.weights, tracker.midpoints())[0]
    np.testing.assert_allclose(mid, [0.1, 0.0], atol=0.05)
    # a filter within BIRTH_GAP of the person: no second birth
    mod._oracle_births(tracker, legs, shown, 0.1)
    assert len(tracker.bank) == 1


def test_unknown_mode_is_refused(tmp_path: Path) -> None:
    mod = _oracle()
    with pytest.raises(ValueError, match="oracle-births"):
        mod.track_with_oracle(tmp_path / "x.npz", tmp_path / "x.csv", "oracle-tracks")
