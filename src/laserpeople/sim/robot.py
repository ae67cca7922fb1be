"""A mobile robot carrying scanners: its true path and its drifting wheel odometry."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.scan import wrap_angle
from laserpeople.sim.motion import BodyTrack

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class OdometryParams:
    """Systematic and random errors of wheel odometry."""

    config_section = "sim_odometry"

    scale_error: float = param(0.02, "assumed", "relative error of travelled distance", "")
    heading_bias: float = param(0.01, "assumed", "heading drift per metre travelled", "rad/m")
    heading_scale_error: float = param(0.01, "assumed", "relative error of turned angle", "")
    translation_noise: float = param(
        0.005, "assumed", "random translation error per sqrt(metre)", "m/sqrt(m)"
    )
    heading_noise: float = param(
        0.002, "assumed", "random heading error per sqrt(metre)", "rad/sqrt(m)"
    )


@dataclass(frozen=True, eq=False)
class RobotSpec:
    """The robot of a scenario: its true base trajectory (x ahead, y left)."""

    track: BodyTrack
    odometry: OdometryParams = OdometryParams()


def integrate_odometry(
    track: BodyTrack, params: OdometryParams, rng: np.random.Generator
) -> FloatArray:
    """Odometry poses (T, 3) ``x, y, theta`` along ``track``, starting at the true pose.

    Each step's true motion in the robot frame is corrupted by a scale error, a heading
    bias proportional to distance and random noise, and the corrupted steps are chained
    (cumulative sums, no loop), so the error grows with distance as real odometry does.
    """
    xy = track.xy
    th = np.unwrap(track.heading)
    d = np.diff(xy, axis=0)
    c, s = np.cos(th[:-1]), np.sin(th[:-1])
    local_x = c * d[:, 0] + s * d[:, 1]
    local_y = -s * d[:, 0] + c * d[:, 1]
    dist = np.hypot(local_x, local_y)
    dth = np.diff(th)
    sqrt_d = np.sqrt(dist)
    dth_odo = (
        dth * (1.0 + params.heading_scale_error)
        + params.heading_bias * dist
        + params.heading_noise * sqrt_d * rng.standard_normal(dist.size)
    )
    th_odo = th[0] + np.concatenate([[0.0], np.cumsum(dth_odo)])
    scale = 1.0 + params.scale_error
    lx = local_x * scale + params.translation_noise * sqrt_d * rng.standard_normal(dist.size)
    ly = local_y * scale
    co, so = np.cos(th_odo[:-1]), np.sin(th_odo[:-1])
    wx = co * lx - so * ly
    wy = so * lx + co * ly
    x = xy[0, 0] + np.concatenate([[0.0], np.cumsum(wx)])
    y = xy[0, 1] + np.concatenate([[0.0], np.cumsum(wy)])
    return np.column_stack([x, y, wrap_angle(th_odo)])
