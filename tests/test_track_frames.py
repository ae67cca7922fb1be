from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.errors import PoseUnavailableError
from laserpeople.scan import Pose2D
from laserpeople.tracking.frames import in_frame, tracking_frame
from laserpeople.tracks import Detections


def _det(pose: Pose2D | None) -> Detections:
    return Detections(0.0, 0, [[1.0, 0.0]], [np.eye(2) * 0.01], [1.0], "sensor", pose)


def test_world_frame_when_the_pose_is_known() -> None:
    pose = Pose2D(2.0, 1.0, math.pi / 2)
    assert tracking_frame(_det(pose)) == "world"
    assert tracking_frame(_det(None)) == "sensor"
    np.testing.assert_allclose(in_frame(_det(pose), "world").positions, [[2.0, 2.0]], atol=1e-12)
    assert in_frame(_det(None), "sensor").frame == "sensor"


def test_frame_mismatches_are_errors() -> None:
    with pytest.raises(PoseUnavailableError, match="no sensor pose"):
        in_frame(_det(None), "world")
    with pytest.raises(PoseUnavailableError, match="world-frame detections"):
        in_frame(_det(Pose2D()).to_world(), "sensor")
