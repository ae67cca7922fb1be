"""Simulated laser scanners: real models' beam geometry, mounting, noise, dropouts.

A beam that hits nothing within ``range_max`` returns no echo; like the Hokuyo and SICK
ROS drivers the simulated range is then ``inf`` (``no_return="zero"`` writes 0 instead,
as some older drivers do). Both are "invalid" for :class:`~laserpeople.scan.Scan`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.scan import Pose2D
from laserpeople.sim.raycast import BeamFan

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class LaserModel:
    """The geometry and error model of a scanner type.

    Attributes:
        name: Model name.
        fov_deg: Field of view [deg], centred on the sensor's x axis.
        resolution_deg: Angle between beams [deg].
        rate_hz: Scan rate [Hz].
        range_min: Smallest range [m].
        range_max: Largest range [m].
        sigma: Range noise, standard deviation [m].
        sigma_relative: Additional noise proportional to the range (sigma + rel * r).
        dropout: Probability that a beam with a target returns nothing.
        source: Where the numbers come from.
    """

    name: str
    fov_deg: float
    resolution_deg: float
    rate_hz: float
    range_min: float
    range_max: float
    sigma: float
    sigma_relative: float
    dropout: float
    source: str

    @property
    def n_beams(self) -> int:
        """Number of beams of one scan."""
        return round(self.fov_deg / self.resolution_deg) + 1

    def fan(self) -> BeamFan:
        """The beam fan, symmetric about the sensor's x axis."""
        inc = math.radians(self.resolution_deg)
        return BeamFan(-0.5 * (self.n_beams - 1) * inc, inc, self.n_beams)


LASER_MODELS: dict[str, LaserModel] = {
    m.name: m
    for m in (
        LaserModel(
            "sick-lms200",
            180.0,
            0.5,
            37.5,
            0.0,
            8.0,
            0.01,
            0.0,
            0.001,
            "SICK LMS 200 datasheet (180 deg, 0.5 deg, 8 m mode); used in 000",
        ),
        LaserModel(
            "sick-lms151",
            270.0,
            0.5,
            50.0,
            0.5,
            50.0,
            0.012,
            0.0,
            0.001,
            "SICK LMS151 datasheet (270 deg, 0.5 deg, 50 Hz, 12 mm statistical error); 004",
        ),
        LaserModel(
            "hokuyo-utm-30lx",
            270.0,
            0.25,
            40.0,
            0.1,
            30.0,
            0.01,
            0.0,
            0.002,
            "Hokuyo UTM-30LX datasheet (270 deg, 0.25 deg, 40 Hz, +-30 mm)",
        ),
        LaserModel(
            "hokuyo-urg-04lx",
            239.4140625,
            0.3515625,
            10.0,
            0.02,
            5.6,
            0.01,
            0.01,
            0.002,
            "Hokuyo URG-04LX datasheet (682 steps of 360/1024 deg over ~240 deg, 10 Hz, 5.6 m, "
            "+-1% beyond 1 m)",
        ),
    )
}
"""The scanner models, by name."""


@dataclass(frozen=True)
class SensorSpec:
    """One scanner of a scenario.

    Attributes:
        name: Sensor (topic) name, e.g. ``feet_a``.
        model: Key of :data:`LASER_MODELS`.
        height: Mounting height above the floor [m]; decides what the beams hit.
        mount: Pose in the world frame, or on the robot when ``on_robot``.
        on_robot: Whether the sensor rides on the scenario's robot.
        rate_hz: Scan rate [Hz]; the model's rate when None.
        phase: Time of the first scan [s] (sensors are not synchronised).
        no_return: "inf" (default, like the ROS drivers) or "zero".
        sigma: Range noise [m]; the model's when None.
        dropout: Dropout probability; the model's when None.
        laser_model: A scanner model of its own (e.g. drawn at random), used instead of
            ``LASER_MODELS[model]``; ``model`` then only names it.
    """

    name: str
    model: str
    height: float
    mount: Pose2D
    on_robot: bool = False
    rate_hz: float | None = None
    phase: float = 0.0
    no_return: str = "inf"
    sigma: float | None = None
    dropout: float | None = None
    laser_model: LaserModel | None = None

    @property
    def laser(self) -> LaserModel:
        """The scanner model."""
        return self.laser_model if self.laser_model is not None else LASER_MODELS[self.model]

    def rate(self, override: float | None = None) -> float:
        """Scan rate [Hz], ``override`` first."""
        return float(override or self.rate_hz or self.laser.rate_hz)

    def meta(self) -> dict[str, object]:
        """JSON description for the recording's metadata."""
        m = self.laser
        return {
            "name": self.name,
            "model": m.name,
            "height_m": self.height,
            "mount": [self.mount.x, self.mount.y, self.mount.theta],
            "on_robot": self.on_robot,
            "fov_deg": m.fov_deg,
            "resolution_deg": m.resolution_deg,
            "range_max_m": m.range_max,
            "sigma_m": self.sigma if self.sigma is not None else m.sigma,
            "dropout": self.dropout if self.dropout is not None else m.dropout,
        }


def add_range_noise(
    ranges: FloatArray,
    spec: SensorSpec,
    rng: np.random.Generator,
) -> tuple[FloatArray, NDArray[np.bool_]]:
    """Noisy ranges and the mask of beams that returned an echo.

    Beams beyond ``range_max`` and dropped beams return nothing; returned ranges get
    Gaussian noise with standard deviation ``sigma + sigma_relative * r``.
    """
    m = spec.laser
    sigma = spec.sigma if spec.sigma is not None else m.sigma
    dropout = spec.dropout if spec.dropout is not None else m.dropout
    n = ranges.size
    noise = rng.standard_normal(n)
    drop = rng.random(n) < dropout
    echo = np.isfinite(ranges) & (ranges <= m.range_max) & ~drop
    noisy = ranges + noise * (sigma + m.sigma_relative * np.where(echo, ranges, 0.0))
    echo &= noisy >= m.range_min
    fill = 0.0 if spec.no_return == "zero" else math.inf
    return np.where(echo, noisy, fill), echo
