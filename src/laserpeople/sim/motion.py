"""Body motion from waypoints: :class:`Route` (keyframes) and :class:`BodyTrack` (sampled).

A route is a list of keyframes ``(t, x, y, heading)`` built by chaining
``walk_to``/``walk_path``/``arc``/``wait``/``turn_by``. Sampling it on a fine time grid
and smoothing with a Gaussian of ``smoothing`` seconds gives a body trajectory with
finite acceleration: corners are rounded and starts and stops take a few tenths of a
second, as they do for people. The heading is the direction of motion while walking and
the keyframes' heading when standing (so a person can turn on the spot).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import gaussian_filter1d

from laserpeople.scan import wrap_angle

FloatArray = NDArray[np.float64]

DEFAULT_DT = 0.01
"""Time step [s] of sampled body tracks and of the footstep planner."""


class Route:
    """Keyframes of a body path; every method returns ``self`` so calls chain.

    Example:
        >>> r = Route(0.0, 0.0, heading=0.0).walk_to(2.0, 0.0, speed=1.0).wait(1.0)
        >>> r.end_time
        3.0
    """

    def __init__(self, x: float, y: float, heading: float = 0.0, start: float = 0.0) -> None:
        self.t: list[float] = [float(start)]
        self.xy: list[tuple[float, float]] = [(float(x), float(y))]
        self.heading: list[float] = [float(heading)]  # NaN while walking
        self._last_heading = float(heading)

    @property
    def end_time(self) -> float:
        """Time of the last keyframe [s]."""
        return self.t[-1]

    @property
    def end(self) -> tuple[float, float]:
        """Position of the last keyframe [m]."""
        return self.xy[-1]

    @property
    def last_heading(self) -> float:
        """Heading at the last keyframe [rad]."""
        return self._last_heading

    def _add(self, t: float, x: float, y: float, heading: float) -> None:
        self.t.append(t)
        self.xy.append((x, y))
        self.heading.append(heading)

    def walk_to(self, x: float, y: float, speed: float) -> Route:
        """Walk in a straight line to (x, y) [m] at ``speed`` [m/s]."""
        if speed <= 0.0:
            raise ValueError("speed must be positive")
        x0, y0 = self.xy[-1]
        dist = math.hypot(x - x0, y - y0)
        if dist < 1e-9:
            return self
        self._last_heading = math.atan2(y - y0, x - x0)
        self._add(self.t[-1] + dist / speed, x, y, math.nan)
        return self

    def move_to(self, x: float, y: float, seconds: float) -> Route:
        """Walk in a straight line to (x, y) [m] arriving after ``seconds`` [s] (used to keep
        the members of a group in step)."""
        if seconds <= 0.0:
            raise ValueError("seconds must be positive")
        x0, y0 = self.xy[-1]
        if math.hypot(x - x0, y - y0) < 1e-9:
            return self.wait(seconds)
        self._last_heading = math.atan2(y - y0, x - x0)
        self._add(self.t[-1] + seconds, x, y, math.nan)
        return self

    def wait_until(self, t: float) -> Route:
        """Stand still until time ``t`` [s] (nothing if ``t`` has passed)."""
        if t > self.t[-1] + 1e-9:
            self.wait(t - self.t[-1])
        return self

    def walk_path(self, points: NDArray[np.floating], speed: float) -> Route:
        """Walk along the polyline ``points`` (N, 2) [m] at ``speed`` [m/s]."""
        for x, y in np.asarray(points, dtype=np.float64).reshape(-1, 2):
            self.walk_to(float(x), float(y), speed)
        return self

    def arc(self, cx: float, cy: float, sweep: float, speed: float, steps: int = 48) -> Route:
        """Walk round the circle centred at (cx, cy) [m] through ``sweep`` [rad] (+ = CCW)."""
        x0, y0 = self.xy[-1]
        r = math.hypot(x0 - cx, y0 - cy)
        a0 = math.atan2(y0 - cy, x0 - cx)
        n = max(2, int(steps * abs(sweep) / (2 * math.pi)) + 1)
        ang = a0 + np.linspace(0.0, sweep, n + 1)[1:]
        pts = np.column_stack([cx + r * np.cos(ang), cy + r * np.sin(ang)])
        return self.walk_path(pts, speed)

    def wait(self, seconds: float) -> Route:
        """Stand still for ``seconds`` [s], keeping the current heading."""
        x, y = self.xy[-1]
        h = self._last_heading
        if math.isnan(self.heading[-1]):
            self.heading[-1] = h
        self._add(self.t[-1] + seconds, x, y, h)
        return self

    def turn_by(self, angle: float, seconds: float) -> Route:
        """Turn on the spot by ``angle`` [rad] (+ = CCW) in ``seconds`` [s]."""
        x, y = self.xy[-1]
        if math.isnan(self.heading[-1]):
            self.heading[-1] = self._last_heading
        self._last_heading = self._last_heading + angle
        self._add(self.t[-1] + seconds, x, y, self._last_heading)
        return self

    def shifted(self, dt: float) -> Route:
        """A copy of this route that starts ``dt`` [s] later."""
        out = Route(0.0, 0.0)
        out.t = [t + dt for t in self.t]
        out.xy = list(self.xy)
        out.heading = list(self.heading)
        out._last_heading = self._last_heading
        return out


@dataclass(frozen=True, eq=False)
class BodyTrack:
    """A body trajectory sampled every ``dt`` seconds from ``times[0]``.

    Attributes:
        times: (T,) [s].
        xy: (T, 2) body centre [m].
        heading: (T,) facing direction [rad], wrapped.
        velocity: (T, 2) [m/s].
    """

    times: FloatArray
    xy: FloatArray
    heading: FloatArray
    velocity: FloatArray

    @property
    def speed(self) -> FloatArray:
        """(T,) [m/s]."""
        return np.hypot(self.velocity[:, 0], self.velocity[:, 1])

    def at(self, t: NDArray[np.floating]) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Position (K, 2), heading (K,) and velocity (K, 2) at times ``t`` (K,), linearly
        interpolated (held constant outside the sampled span)."""
        t = np.asarray(t, dtype=np.float64)
        x = np.interp(t, self.times, self.xy[:, 0])
        y = np.interp(t, self.times, self.xy[:, 1])
        h_un = np.unwrap(self.heading)
        h = wrap_angle(np.interp(t, self.times, h_un))
        vx = np.interp(t, self.times, self.velocity[:, 0])
        vy = np.interp(t, self.times, self.velocity[:, 1])
        return np.column_stack([x, y]), h, np.column_stack([vx, vy])


def facing(
    velocity: NDArray[np.floating], heading: NDArray[np.floating], walking_speed: float = 0.15
) -> FloatArray:
    """The direction a body faces (T,) [rad]: its direction of motion (``velocity`` (T, 2)
    [m/s]) above ``walking_speed`` [m/s], ``heading`` (T,) [rad] when standing, blended in
    between."""
    speed = np.hypot(velocity[:, 0], velocity[:, 1])
    motion = np.arctan2(velocity[:, 1], velocity[:, 0])
    w = np.clip((speed - 0.5 * walking_speed) / walking_speed, 0.0, 1.0)
    hx = w * np.cos(motion) + (1 - w) * np.cos(heading)
    hy = w * np.sin(motion) + (1 - w) * np.sin(heading)
    return np.asarray(np.arctan2(hy, hx), dtype=np.float64)


def sample_route(
    route: Route,
    t_end: float,
    *,
    dt: float = DEFAULT_DT,
    smoothing: float = 0.25,
    walking_speed: float = 0.15,
) -> BodyTrack:
    """Sample ``route`` every ``dt`` [s] from its start until ``t_end`` [s] and smooth it.

    ``smoothing`` is the standard deviation [s] of the Gaussian applied to the positions;
    ``walking_speed`` [m/s] is the speed above which the heading follows the motion.
    """
    kt = np.asarray(route.t)
    t0 = float(kt[0])
    n = max(2, math.ceil((max(t_end, t0 + dt) - t0) / dt) + 1)
    times = np.asarray(t0 + np.arange(n) * dt, dtype=np.float64)
    kxy = np.asarray(route.xy)
    x = np.interp(times, kt, kxy[:, 0])
    y = np.interp(times, kt, kxy[:, 1])
    sigma = smoothing / dt
    if sigma > 0:
        x = gaussian_filter1d(x, sigma, mode="nearest")
        y = gaussian_filter1d(y, sigma, mode="nearest")
    vx = np.gradient(x, dt)
    vy = np.gradient(y, dt)
    # explicit headings (standing, turning); keyframes while walking carry NaN
    kh = np.asarray(route.heading)
    known = ~np.isnan(kh)
    kh_known = np.unwrap(kh[known]) if known.any() else np.zeros(1)
    kt_known = kt[known] if known.any() else kt[:1]
    h_explicit = np.interp(times, kt_known, kh_known)
    heading = np.unwrap(facing(np.column_stack([vx, vy]), h_explicit, walking_speed))
    if sigma > 0:
        heading = gaussian_filter1d(heading, 0.4 * sigma, mode="nearest")
    return BodyTrack(times, np.column_stack([x, y]), wrap_angle(heading), np.column_stack([vx, vy]))
