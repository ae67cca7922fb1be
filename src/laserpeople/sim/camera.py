"""A simulated colour camera: noisy hue observations of every person (002 Sec. 2).

002 finds people in a CCD image with an infrared camera and reads the hue of their
pixels. Here each visible person yields a region of ``pixels`` RGB pixels: most from the
clothing (the person's hue from ``TruthFrame.hues`` with a fabric spread), some from skin,
hair or background (random hue, low saturation), and, when another person stands close,
some from that person (partial occlusion). The whole image is tinted by a slowly drifting
illumination (per-channel gains, an AR(1) process in log space), which shifts the measured
hue. A person is missed with ``miss_probability`` per frame. The regions are turned back
into hue samples through :func:`laserpeople.colour.region_hues`, exactly as a real camera
region would be.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from laserpeople.colour import hsv_to_rgb, region_hues
from laserpeople.config import param
from laserpeople.frame import AppearanceObservation, Frame
from laserpeople.scan import PointSet, Scan
from laserpeople.sim.simulator import SimResult

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class CameraParams:
    """The simulated camera (all values assumptions: 002 gives no camera model)."""

    config_section = "sim_camera"

    pixels: int = param(150, "assumption", "pixels per person region")
    fabric_hue_std: float = param(
        8.0, "assumption: folds and shading of one garment", "hue spread of clothing", "deg"
    )
    clutter_fraction: float = param(
        0.15, "assumption: skin, hair, background in the region", "share of non-clothing pixels"
    )
    occlusion_distance: float = param(
        0.9,
        "assumption",
        "another person closer than this leaks into the region (linearly more when nearer)",
        "m",
    )
    max_occlusion_fraction: float = param(
        0.5, "assumption", "share of the region from a neighbour standing at distance 0"
    )
    lighting_std: float = param(
        0.1,
        "assumption: indoor colour temperature changes of ~10 % per channel",
        "stationary std of the log gain of each RGB channel",
    )
    lighting_time: float = param(
        4.0, "assumption", "correlation time of the illumination drift", "s"
    )
    miss_probability: float = param(
        0.1, "assumption: occasional missing views", "chance a person is not observed"
    )
    position_std: float = param(
        0.1, "assumption", "error of the observed position on the floor", "m"
    )

    def __post_init__(self) -> None:
        if self.pixels < 1:
            raise ValueError("pixels must be positive")
        for name in ("clutter_fraction", "max_occlusion_fraction", "miss_probability"):
            if not 0.0 <= getattr(self, name) <= 1.0:
                raise ValueError(f"{name} must be in [0, 1]")
        if self.lighting_std < 0 or self.lighting_time <= 0:
            raise ValueError("lighting_std must be >= 0 and lighting_time > 0")


class SimulatedCamera:
    """Streams :class:`AppearanceObservation` s from ground truth, one call per frame."""

    def __init__(self, params: CameraParams | None = None, seed: int = 0) -> None:
        self.params = params or CameraParams()
        self._rng = np.random.default_rng([seed, 0xCA3E])
        self._log_gain = self._rng.normal(0.0, self.params.lighting_std, 3)
        self._last_stamp: float | None = None

    def _drift(self, stamp: float) -> None:
        p = self.params
        if self._last_stamp is not None:
            dt = max(stamp - self._last_stamp, 0.0)
            a = math.exp(-dt / p.lighting_time)
            self._log_gain = a * self._log_gain + math.sqrt(1.0 - a * a) * self._rng.normal(
                0.0, p.lighting_std, 3
            )
        self._last_stamp = stamp

    def observe(
        self, stamp: float, ids: NDArray[np.int64], positions: FloatArray, hues_deg: FloatArray
    ) -> tuple[AppearanceObservation, ...]:
        """Observations at ``stamp`` [s] of people ``ids`` (P,) at ``positions`` (P, 2) [m]
        wearing ``hues_deg`` (P,)."""
        p = self.params
        rng = self._rng
        self._drift(stamp)
        n = len(ids)
        if n == 0:
            return ()
        pos = np.asarray(positions, dtype=np.float64).reshape(n, 2)
        hues = np.asarray(hues_deg, dtype=np.float64).reshape(n)
        d = np.linalg.norm(pos[:, None] - pos[None], axis=-1) + np.diag(np.full(n, np.inf))
        gain = np.exp(self._log_gain)
        out = []
        for i in range(n):
            if rng.random() < p.miss_probability:
                continue
            k = p.pixels
            src = np.full(k, i)
            if n > 1:
                j = int(np.argmin(d[i]))
                leak = p.max_occlusion_fraction * max(0.0, 1.0 - d[i, j] / p.occlusion_distance)
                src[rng.random(k) < leak] = j
            hue = hues[src] + rng.normal(0.0, p.fabric_hue_std, k)
            sat = rng.uniform(0.45, 1.0, k)
            val = rng.uniform(0.35, 1.0, k)
            clutter = rng.random(k) < p.clutter_fraction
            hue[clutter] = rng.uniform(0.0, 360.0, int(clutter.sum()))
            sat[clutter] = rng.uniform(0.0, 0.4, int(clutter.sum()))
            rgb = np.clip(hsv_to_rgb(hue, sat, val) * gain, 0.0, 1.0)
            out.append(
                AppearanceObservation(
                    pos[i] + rng.normal(0.0, p.position_std, 2),
                    region_hues(rgb),
                    person_hint=int(ids[i]),
                )
            )
        return tuple(out)


def simulated_frames(
    result: SimResult,
    camera: SimulatedCamera | None = None,
    hues_deg: dict[int, float] | None = None,
) -> list[Frame]:
    """Frames of a :class:`~laserpeople.sim.simulator.SimResult`: the k-th scan of every
    sensor together, all points in the world frame, foreground = beams that hit a person
    (the simulator's labels), truth, and the camera's observations when ``camera`` is given.

    ``hues_deg`` overrides the clothing hue of person ids (the laser does not see colour, so
    one simulation serves every colour setting).
    """
    sensors = [s["name"] for s in result.meta["sensors"]]
    by_index: dict[int, dict[str, Scan]] = {}
    for scan in result.scans:
        by_index.setdefault(scan.index, {})[scan.sensor] = scan
    frames = []
    for k, truth in enumerate(result.truth):
        got = by_index.get(k, {})
        scans = tuple(got[s] for s in sensors if s in got)
        if not scans:
            continue
        points = PointSet.from_scans(list(scans), "world")
        fg = np.concatenate([_person_beams(s)[s.valid_points("world")[1]] for s in scans])
        if hues_deg:
            truth = replace(
                truth,
                hues=np.array(
                    [
                        hues_deg.get(int(i), h)
                        for i, h in zip(truth.person_ids, truth.hues, strict=True)
                    ]
                ),
            )
        obs = (
            camera.observe(truth.stamp, truth.person_ids, truth.positions, truth.hues)
            if camera is not None
            else ()
        )
        frames.append(
            Frame(
                index=k,
                stamp=points.stamp,
                scans=scans,
                topic="fused" if len(scans) > 1 else scans[0].sensor,
                frame="world",
                sensor_pose=scans[0].pose,
                points=points,
                foreground=fg,
                appearance=obs,
                truth=truth,
                missing=tuple(s for s in sensors if s not in got),
            )
        )
    return frames


def _person_beams(scan: Scan) -> NDArray[np.bool_]:
    """(N,) True for beams that hit a person (all False without labels)."""
    if scan.labels is None:
        return np.zeros(scan.ranges.size, dtype=bool)
    return np.asarray(scan.labels.person >= 0)
