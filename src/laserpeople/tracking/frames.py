"""The frame a tracker works in: the world frame when the sensor pose is known, else the
sensor frame, fixed by the first scan so that a track never changes frame."""

from __future__ import annotations

from laserpeople.errors import PoseUnavailableError
from laserpeople.scan import CoordinateFrame
from laserpeople.tracks import Detections


def tracking_frame(detections: Detections) -> CoordinateFrame:
    """The frame to track in, chosen from a recording's first scan of detections."""
    return (
        "world" if detections.sensor_pose is not None or detections.frame == "world" else "sensor"
    )


def in_frame(detections: Detections, frame: CoordinateFrame) -> Detections:
    """``detections`` expressed in the tracking ``frame``.

    Raises:
        PoseUnavailableError: a world-frame tracker gets a scan without a sensor pose, or a
            sensor-frame tracker gets world-frame detections.
    """
    if frame == "world":
        if detections.sensor_pose is None and detections.frame != "world":
            raise PoseUnavailableError(
                "tracking in the world frame but this scan has no sensor pose",
                scan=detections.scan_index,
                hint="every scan of a moving sensor needs a pose; check /tf or odometry",
            )
        return detections.to_world()
    if detections.frame != "sensor":
        raise PoseUnavailableError(
            "tracking in the sensor frame but got world-frame detections",
            scan=detections.scan_index,
        )
    return detections
