"""Synthetic leg detections for testing and benchmarking trackers without a detector.

Each person walks along a path; each leg alternates stance (foot planted) and swing (foot
moving at twice the body speed), the two legs half a gait period apart, offset sideways
from the path. A leg is missed when another leg nearer to the sensor covers it (angular
overlap of leg discs) or at random; false alarms are uniform in a box. Detections are in
the sensor frame with the sensor at the origin looking along +x.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.scan import Scan
from laserpeople.tracks import Detections
from laserpeople.truth import TruthFrame

FloatArray = NDArray[np.float64]
Path = Callable[[FloatArray], FloatArray]
"""Body position (T, 2) [m] at times (T,) [s]."""


def line_path(start: tuple[float, float], velocity: tuple[float, float]) -> Path:
    """Straight walk from ``start`` [m] at ``velocity`` [m/s]."""
    s, v = np.asarray(start, float), np.asarray(velocity, float)
    return lambda t: s[None, :] + np.asarray(t, float)[:, None] * v[None, :]


def figure_eight_path(centre: tuple[float, float], size: float, period: float) -> Path:
    """Gerono's lemniscate x = size sin(a), y = size sin(a) cos(a), one loop per ``period``
    [s], round ``centre`` [m]."""
    c = np.asarray(centre, float)
    omega = 2.0 * np.pi / period

    def path(t: FloatArray) -> FloatArray:
        a = omega * np.asarray(t, float)
        return c[None, :] + size * np.stack([np.sin(a), np.sin(a) * np.cos(a)], axis=1)

    return path


@dataclass(frozen=True)
class GaitModel:
    """Two-leg gait: period [s], sideways half-distance between feet [m]."""

    period: float = 1.0
    half_width: float = 0.1


def leg_positions(path: Path, times: FloatArray, gait: GaitModel, phase: float = 0.0) -> FloatArray:
    """Leg centres (T, 2, 2) along ``path`` at ``times`` [s] for the alternating gait."""
    t = np.asarray(times, float)
    out = np.empty((t.size, 2, 2))
    for leg in (0, 1):
        # foot time: frozen in stance, runs at double speed in swing; average rate 1
        u = (t + phase) / gait.period + 0.5 * leg
        k = np.floor(u)
        f = u - k
        foot_u = k + np.where(f < 0.5, 0.0, 2.0 * (f - 0.5))
        foot_t = foot_u * gait.period - phase - 0.5 * leg * gait.period + 0.25 * gait.period
        p = path(foot_t)
        d = path(foot_t + 0.05) - path(foot_t - 0.05)
        n = np.linalg.norm(d, axis=1, keepdims=True)
        tangent = np.where(n > 1e-9, d / np.maximum(n, 1e-9), [[1.0, 0.0]])
        normal = np.stack([-tangent[:, 1], tangent[:, 0]], axis=1)
        out[:, leg] = p + (1.0 if leg == 0 else -1.0) * gait.half_width * normal
    return out


def visible(legs: FloatArray, leg_radius: float = 0.06) -> NDArray[np.bool_]:
    """Which leg discs (K, 2) are seen by a sensor at the origin (not hidden, more than half,
    behind a nearer disc)."""
    r = np.linalg.norm(legs, axis=1)
    ang = np.arctan2(legs[:, 1], legs[:, 0])
    half = np.arcsin(np.clip(leg_radius / np.maximum(r, leg_radius), 0, 1))
    diff = np.abs(np.angle(np.exp(1j * (ang[:, None] - ang[None, :]))))
    covers = (r[None, :] < r[:, None]) & (diff < half[None, :])
    return ~covers.any(axis=1)


@dataclass(frozen=True)
class SensorModel:
    """Detection noise std [m], random miss rate, false alarms per scan in a box."""

    noise: float = 0.02
    miss_rate: float = 0.05
    false_alarms_per_scan: float = 0.2
    box: tuple[float, float, float, float] = (0.5, -3.0, 8.0, 3.0)


def detections_from_legs(
    legs: FloatArray,
    stamp: float,
    scan_index: int,
    sensor: SensorModel,
    rng: np.random.Generator,
) -> Detections:
    """Noisy detections of the visible legs (K, 2) plus false alarms."""
    legs = legs[np.isfinite(legs).all(axis=1)]
    seen = visible(legs) & (rng.random(len(legs)) >= sensor.miss_rate)
    pos = legs[seen] + rng.normal(0.0, sensor.noise, (int(seen.sum()), 2))
    n_fa = rng.poisson(sensor.false_alarms_per_scan)
    x0, y0, x1, y1 = sensor.box
    fa = np.stack([rng.uniform(x0, x1, n_fa), rng.uniform(y0, y1, n_fa)], axis=1)
    allpos = np.vstack([pos, fa])
    m = allpos.shape[0]
    cov = np.tile(np.eye(2) * max(sensor.noise, 1e-3) ** 2, (m, 1, 1))
    return Detections(stamp, scan_index, allpos, cov, np.ones(m))


@dataclass(frozen=True, eq=False)
class SyntheticScene:
    """Per-scan truth leg positions (T, P, 2, 2) and detections."""

    times: FloatArray
    legs: FloatArray
    detections: list[Detections]


def make_scene(
    paths: list[Path],
    seconds: float,
    rate: float = 10.0,
    gait: GaitModel | None = None,
    sensor: SensorModel | None = None,
    seed: int = 0,
) -> SyntheticScene:
    """Walk every path for ``seconds`` at ``rate`` [Hz] and detect the legs."""
    gait = gait or GaitModel()
    sensor = sensor or SensorModel()
    rng = np.random.default_rng(seed)
    times = np.arange(0.0, seconds, 1.0 / rate)
    legs = np.stack(
        [leg_positions(p, times, gait, phase=0.37 * i) for i, p in enumerate(paths)], axis=1
    )
    dets = [
        detections_from_legs(legs[k].reshape(-1, 2), float(t), k, sensor, rng)
        for k, t in enumerate(times)
    ]
    return SyntheticScene(times, legs, dets)


def walkers_scene(seed: int, false_alarms_per_scan: float, walkers: int = 6) -> SyntheticScene:
    """``walkers`` straight walks for 8 s at 37.5 Hz, each from a random start (x 1.5-6 m,
    y -3-3 m) with a random heading, seen with ``false_alarms_per_scan`` clutter in a box
    (0.5, -5) - (8, 5) m: crossings, clutter and misses for the MHT's tests."""
    rng = np.random.default_rng(seed)
    paths = []
    for _ in range(walkers):
        start = (float(rng.uniform(1.5, 6.0)), float(rng.uniform(-3.0, 3.0)))
        heading = float(rng.uniform(-math.pi, math.pi))
        paths.append(line_path(start, (0.3 * math.cos(heading), math.sin(heading))))
    sensor = SensorModel(false_alarms_per_scan=false_alarms_per_scan, box=(0.5, -5.0, 8.0, 5.0))
    return make_scene(paths, 8.0, rate=37.5, sensor=sensor)


def detections_from_sim(
    scans: list[Scan],
    truth: list[TruthFrame],
    noise: float = 0.02,
    min_beams: int = 2,
    clutter_probability: float = 0.3,
    seed: int = 0,
) -> list[Detections]:
    """Leg detections of a simulated recording built from its ground truth, skipping the
    detector: a leg is detected (at its true centre plus noise) when at least ``min_beams``
    beams hit it, so occlusions are those of the ray caster; every static or moving object
    hit by at least ``min_beams`` beams gives a false alarm at its beams' mean with
    probability ``clutter_probability`` per scan. Only the scans of the first sensor (the
    one ``truth`` follows) are used. Detections are in the sensor frame with the pose."""
    rng = np.random.default_rng(seed)
    sensor = scans[0].sensor
    by_index = {f.scan_index: f for f in truth}
    out: list[Detections] = []
    for scan in scans:
        if scan.sensor != sensor:
            continue
        frame = by_index.get(scan.index)
        labels = scan.labels
        if frame is None or labels is None or scan.pose is None:
            raise ValueError(f"scan {scan.index} has no truth, labels or pose")
        pts: list[FloatArray] = []
        hit = labels.person >= 0
        for p, pid in enumerate(frame.person_ids.tolist()):
            for leg in (0, 1):
                n = int(np.count_nonzero(hit & (labels.person == pid) & (labels.leg == leg)))
                if n >= min_beams:
                    pts.append(frame.leg_positions[p, leg] + rng.normal(0.0, noise, 2))
        world = np.array(pts).reshape(-1, 2)
        local = scan.pose.inverse_transform_points(world) if len(world) else world
        xy = scan.points("sensor")
        clutter = []
        for obj in np.unique(labels.obj[labels.obj >= 0]).tolist():
            sel = (labels.obj == obj) & np.isfinite(xy).all(axis=1)
            if np.count_nonzero(sel) >= min_beams and rng.random() < clutter_probability:
                clutter.append(xy[sel].mean(axis=0))
        allpos = np.vstack([local, np.array(clutter).reshape(-1, 2)])
        m = len(allpos)
        cov = np.tile(np.eye(2) * max(noise, 1e-3) ** 2, (m, 1, 1))
        out.append(Detections(scan.stamp, scan.index, allpos, cov, np.ones(m), "sensor", scan.pose))
    return out
