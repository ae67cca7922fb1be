"""Whether the lasers of a recording sit where a tracker expects them: ``upper-body-pf``
(Schenk et al. 2011) models the torso cut by a laser at upper-body height (1.1 m in their
setup), not legs. A LaserScan and a planar mount carry no height, so it is known only for
recordings that state it: the simulator's ``.npz`` metadata (``sensors[].height_m``) and a
ROS bag whose ``/tf_static`` (or first ``/tf``) chains the laser frame to its robot frame
(:meth:`~laserpeople.io.rosbag.RosbagRecording.laser_heights`)."""

from __future__ import annotations

from typing import Any

UPPER_BODY_MIN_HEIGHT = 0.7
"""Lowest mount [m] taken as upper-body height: assumption, between the legs' lasers of
000 / 004 (0.2-0.4 m) and 004's upper-body laser (1.1 m, Schenk et al. 2011 Sec. 5)."""


def laser_heights(recording: Any) -> dict[str, float]:
    """Mount height [m] per laser topic where the recording states it (else absent): a
    recording with a ``laser_heights()`` method (a ROS bag) answers it, else the ``.npz``
    metadata does."""
    method = getattr(recording, "laser_heights", None)
    if callable(method):
        return dict(method())
    meta = getattr(recording, "meta", None)
    sensors = meta.get("sensors", []) if isinstance(meta, dict) else []
    out: dict[str, float] = {}
    for s in sensors if isinstance(sensors, list) else []:
        if isinstance(s, dict) and isinstance(s.get("height_m"), int | float):
            out[str(s.get("name"))] = float(s["height_m"])
    return out


def upper_body_warning(tracker: str, topics: list[str], heights: dict[str, float]) -> str:
    """A warning when ``upper-body-pf`` tracks lasers below upper-body height or of unknown
    height ("" otherwise, and for every other tracker)."""
    if tracker != "upper-body-pf":
        return ""
    low = [t for t in topics if t in heights and heights[t] < UPPER_BODY_MIN_HEIGHT]
    unknown = [t for t in topics if t not in heights]
    advice = "at leg height use feet-pf or leg-mht"
    if low:
        where = ", ".join(f"{t} at {heights[t]:.2f} m" for t in low)
        return (
            f"upper-body-pf models a laser at upper-body height (Schenk et al. 2011: "
            f"1.1 m), but the recording mounts {where} (leg height): {advice}"
        )
    if unknown:
        return (
            f"upper-body-pf models a laser at upper-body height (Schenk et al. 2011: "
            f"1.1 m); the height of {', '.join(unknown)} is not recorded (a LaserScan has "
            f"none, and no /tf_static links its frame to the robot's): {advice}"
        )
    return ""


def feet_warning(tracker: str, topics: list[str], heights: dict[str, float]) -> str:
    """A warning when ``feet-pf`` tracks lasers at upper-body height ("" otherwise, for
    lasers of unknown height and for every other tracker): 004's feet tracker (Schenk et al.
    2011 Sec. 2.1) models two feet cut by a laser at 0.2 m, and at torso height a person is
    one blob that makes no steps."""
    if tracker != "feet-pf":
        return ""
    high = [t for t in topics if t in heights and heights[t] >= UPPER_BODY_MIN_HEIGHT]
    if not high:
        return ""
    where = ", ".join(f"{t} at {heights[t]:.2f} m" for t in high)
    return (
        f"feet-pf models a laser at feet height (Schenk et al. 2011: 0.2 m), but the "
        f"recording mounts {where} (upper-body height): there use upper-body-pf"
    )


def mount_warning(tracker: str, topics: list[str], heights: dict[str, float]) -> str:
    """The warning of :func:`upper_body_warning` or :func:`feet_warning` for ``tracker``
    ("" when its lasers sit where it expects them)."""
    return upper_body_warning(tracker, topics, heights) or feet_warning(tracker, topics, heights)
