"""Leg motion: a footstep planner with stance/swing alternation, and a pivot walk.

Walking is modelled as a sequence of steps. During a step one foot (the stance foot) is
planted and does not move while the other swings from where it stood to its next
footprint along a minimum-jerk profile. A new step begins once the double-support time
has passed and a foot has drifted more than ``rest_tolerance`` from where it ought to
be: half a step length ahead of the body's predicted position at touch-down, offset
sideways by the hip half-width. The foot farther from its target steps, which makes the
feet alternate while walking, brings them side by side when the person stops, and makes
the person step round when turning on the spot. Step frequency grows with speed (a
linear cadence law for walking, a steeper one for running), so step length grows with
speed as well.

The footprints are stored as swing events, and leg positions at any set of times are
evaluated from them without a loop over times.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.sim.motion import BodyTrack

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class GaitParams:
    """Parameters of the footstep planner."""

    config_section = "sim_gait"

    cadence_at_rest: float = param(
        1.4, "assumed: stepping on the spot at ~1.4 steps/s", "step frequency at speed 0", "1/s"
    )
    cadence_per_speed: float = param(
        0.45,
        "assumed: gives ~2 steps/s and 0.65 m steps at 1.3 m/s, typical adult walking",
        "increase of step frequency per unit speed while walking",
        "1/m",
    )
    run_speed: float = param(
        2.0, "assumed walk-run transition", "speed above which people run", "m/s"
    )
    cadence_running: float = param(
        2.6, "assumed: running cadence ~2.6-3 steps/s", "step frequency at run_speed", "1/s"
    )
    cadence_per_speed_running: float = param(
        0.2, "assumed", "increase of step frequency per unit speed while running", "1/m"
    )
    swing_fraction: float = param(
        0.8,
        "assumed: swing ~40% of a gait cycle (two steps) when walking",
        "swing duration as a fraction of the step period (running uses 1.0)",
    )
    rest_tolerance: float = param(
        0.05, "assumed", "a foot farther than this from its target takes a step", "m"
    )


def cadence(speed: float, p: GaitParams) -> float:
    """Step frequency [steps/s] at body ``speed`` [m/s]."""
    if speed >= p.run_speed:
        return p.cadence_running + p.cadence_per_speed_running * (speed - p.run_speed)
    return p.cadence_at_rest + p.cadence_per_speed * speed


@dataclass(frozen=True, eq=False)
class FootSteps:
    """The swings of both feet of one person.

    Attributes:
        initial: (2, 2) positions of foot 0 (left) and foot 1 (right) at the start [m].
        foot: (K,) which foot swings in each event (0 or 1).
        t0: (K,) lift-off time [s].
        t1: (K,) touch-down time [s].
        p0: (K, 2) position at lift-off [m].
        p1: (K, 2) position at touch-down [m].
        bulge: (K, 2) sideways excursion at mid-swing [m] that keeps the swinging leg
            clear of the planted one (zero when the straight path is clear).
    """

    initial: FloatArray
    foot: NDArray[np.int64]
    t0: FloatArray
    t1: FloatArray
    p0: FloatArray
    p1: FloatArray
    bulge: FloatArray | None = None
    linear: bool = False

    def positions(self, times: NDArray[np.floating]) -> FloatArray:
        """Leg positions (T, 2, 2) at ``times`` (T,): time, leg (0 left, 1 right), xy [m]."""
        times = np.asarray(times, dtype=np.float64)
        out = np.empty((times.size, 2, 2))
        for leg in (0, 1):
            sel = np.flatnonzero(self.foot == leg)
            if sel.size == 0:
                out[:, leg] = self.initial[leg]
                continue
            t0, t1 = self.t0[sel], self.t1[sel]
            p0, p1 = self.p0[sel], self.p1[sel]
            bulge = np.zeros_like(p0) if self.bulge is None else self.bulge[sel]
            k = np.searchsorted(t0, times, side="right") - 1  # last lift-off at or before t
            before = k < 0
            kk = np.clip(k, 0, None)
            tau = np.clip((times - t0[kk]) / np.maximum(t1[kk] - t0[kk], 1e-9), 0.0, 1.0)
            s = tau if self.linear else tau**3 * (10.0 - 15.0 * tau + 6.0 * tau**2)
            pos = p0[kk] + s[:, None] * (p1[kk] - p0[kk])
            pos += np.sin(np.pi * tau)[:, None] * bulge[kk]
            pos[before] = self.initial[leg]
            out[:, leg] = pos
        return out


def plan_footsteps(
    track: BodyTrack,
    hip_half_width: float,
    params: GaitParams | None = None,
    clearance: float = 0.16,
) -> FootSteps:
    """Plan the footsteps of a body following ``track`` (one loop over its time steps);
    a swinging leg passes at least ``clearance`` [m] (centre to centre) from the planted one."""
    p = params or GaitParams()
    times = track.times
    xy = track.xy
    heading = track.heading
    speed = track.speed
    n = times.size
    dt = float(times[1] - times[0]) if n > 1 else 0.01
    cos_h, sin_h = np.cos(heading), np.sin(heading)

    def target(k: int, leg: int, step_length: float) -> tuple[float, float]:
        side = hip_half_width if leg == 0 else -hip_half_width  # left = +normal
        ahead = 0.5 * step_length
        return (
            float(xy[k, 0] + ahead * cos_h[k] - side * sin_h[k]),
            float(xy[k, 1] + ahead * sin_h[k] + side * cos_h[k]),
        )

    feet = [list(target(0, 0, 0.0)), list(target(0, 1, 0.0))]
    initial = np.array(feet, dtype=np.float64)
    ev_foot: list[int] = []
    ev_t0: list[float] = []
    ev_t1: list[float] = []
    ev_p0: list[tuple[float, float]] = []
    ev_p1: list[tuple[float, float]] = []
    ev_bulge: list[tuple[float, float]] = []
    swing_end = -math.inf
    swing_leg = -1
    last_land = float(times[0]) - 10.0
    for k in range(n):
        t = float(times[k])
        if swing_leg >= 0:
            if t < swing_end:
                continue
            feet[swing_leg] = list(ev_p1[-1])
            swing_leg = -1
        v = float(speed[k])
        f = cadence(v, p)
        t_step = 1.0 / f
        t_swing = t_step * (1.0 if v >= p.run_speed else p.swing_fraction)
        if t - last_land < t_step - t_swing - 1e-9:
            continue
        k_land = min(k + round(t_swing / dt), n - 1)
        v_land = float(speed[k_land])
        length = v_land / cadence(v_land, p)
        best_leg, best_dev, best_target = -1, p.rest_tolerance, (0.0, 0.0)
        for leg in (0, 1):
            tx, ty = target(k_land, leg, length)
            dev = math.hypot(feet[leg][0] - tx, feet[leg][1] - ty)
            if dev > best_dev:
                best_leg, best_dev, best_target = leg, dev, (tx, ty)
        if best_leg < 0:
            continue
        other = feet[1 - best_leg]
        gx, gy = best_target[0] - other[0], best_target[1] - other[1]
        gap = math.hypot(gx, gy)
        if gap < clearance:  # never put a foot on (or into) the planted one
            if gap < 1e-9:
                gx, gy, gap = -sin_h[k_land], cos_h[k_land], 1.0
            best_target = (other[0] + clearance * gx / gap, other[1] + clearance * gy / gap)
        ev_foot.append(best_leg)
        ev_t0.append(t)
        ev_t1.append(t + t_swing)
        ev_p0.append((feet[best_leg][0], feet[best_leg][1]))
        ev_p1.append(best_target)
        ev_bulge.append(_clearance(feet[best_leg], best_target, feet[1 - best_leg], clearance))
        swing_leg = best_leg
        swing_end = t + t_swing
        last_land = t + t_swing
    return FootSteps(
        initial=initial,
        foot=np.asarray(ev_foot, dtype=np.int64),
        t0=np.asarray(ev_t0, dtype=np.float64),
        t1=np.asarray(ev_t1, dtype=np.float64),
        p0=np.asarray(ev_p0, dtype=np.float64).reshape(-1, 2),
        p1=np.asarray(ev_p1, dtype=np.float64).reshape(-1, 2),
        bulge=np.asarray(ev_bulge, dtype=np.float64).reshape(-1, 2),
    )


def _clearance(
    a: list[float], b: tuple[float, float], stance: list[float], clearance: float
) -> tuple[float, float]:
    """Mid-swing sideways excursion so that the swing from ``a`` to ``b`` passes at least
    ``clearance`` [m] from the ``stance`` foot (centre to centre)."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    length2 = dx * dx + dy * dy
    if length2 < 1e-12:
        return (0.0, 0.0)
    u = max(0.0, min(1.0, ((stance[0] - a[0]) * dx + (stance[1] - a[1]) * dy) / length2))
    cx, cy = a[0] + u * dx - stance[0], a[1] + u * dy - stance[1]
    d = math.hypot(cx, cy)
    if d >= clearance:
        return (0.0, 0.0)
    if d < 1e-9:  # straight through the stance foot: go round on the left of the swing
        cx, cy, d = -dy, dx, math.sqrt(length2)
    push = clearance - math.hypot(cx, cy) if d > 1e-9 else clearance
    return (push * cx / d, push * cy / d)


def pivot_walk(
    start: tuple[float, float],
    direction: float,
    n_steps: int,
    leg_separation: float = 0.3,
    swing_time: float = 0.7,
    pause: float = 0.25,
    t_start: float = 0.0,
    dt: float = 0.01,
) -> tuple[FootSteps, BodyTrack]:
    """The walk of 000 Sec. 3.4.2: moving along a line while turning 180 deg round the stance
    leg at every step, so the swinging leg passes behind the planted one.

    Foot 1 starts ``leg_separation`` [m] behind foot 0 on the line through ``start`` at
    angle ``direction`` [rad]; each step swings the rear foot on a half circle round the
    planted foot (always on the same side) to ``leg_separation`` ahead of it. The body is
    the midpoint of the legs, facing perpendicular to the line joining them.
    """
    ux, uy = math.cos(direction), math.sin(direction)
    sx, sy = start
    planted = [np.array([sx, sy]), np.array([sx - leg_separation * ux, sy - leg_separation * uy])]
    initial = np.array(planted)
    feet_ev, t0s, t1s, p0s, p1s = [], [], [], [], []
    t = t_start + pause
    mover = 1
    for _ in range(n_steps):
        stance = 1 - mover
        p0 = planted[mover]
        p1 = planted[stance] + leg_separation * np.array([ux, uy])
        feet_ev.append(mover)
        t0s.append(t)
        t1s.append(t + swing_time)
        p0s.append(p0)
        p1s.append(p1)
        planted[mover] = p1
        t += swing_time + pause
        mover = stance
    steps = FootSteps(
        initial,
        np.asarray(feet_ev, dtype=np.int64),
        np.asarray(t0s),
        np.asarray(t1s),
        np.asarray(p0s).reshape(-1, 2),
        np.asarray(p1s).reshape(-1, 2),
    )
    # The swing is a half circle round the stance foot, not a straight line: evaluate it
    # on a fine grid here and store it as a chain of short straight swings.
    arcs = _arc_swings(steps)
    return arcs, _pivot_body(arcs, t_start, t, dt)


def _arc_swings(steps: FootSteps) -> FootSteps:
    """Replace each straight swing of a pivot walk by 24 short ones along a half circle
    (minimum-jerk in angle)."""
    n_sub = 24
    foot, t0, t1, p0, p1 = [], [], [], [], []
    for i in range(steps.foot.size):
        a, b = steps.p0[i], steps.p1[i]
        centre = 0.5 * (a + b)
        r = 0.5 * float(np.linalg.norm(b - a))
        ang0 = math.atan2(a[1] - centre[1], a[0] - centre[0])
        # rear foot at angle direction + pi round the stance foot; increasing the angle by
        # pi passes it on the right-hand side of the line of travel, every step alike
        tau = np.linspace(0.0, 1.0, n_sub + 1)
        angs = ang0 + math.pi * tau**3 * (10.0 - 15.0 * tau + 6.0 * tau**2)
        pts = centre + r * np.column_stack([np.cos(angs), np.sin(angs)])
        ts = np.linspace(steps.t0[i], steps.t1[i], n_sub + 1)
        for j in range(n_sub):
            foot.append(int(steps.foot[i]))
            t0.append(ts[j])
            t1.append(ts[j + 1])
            p0.append(pts[j])
            p1.append(pts[j + 1])
    return FootSteps(
        steps.initial,
        np.asarray(foot, dtype=np.int64),
        np.asarray(t0),
        np.asarray(t1),
        np.asarray(p0).reshape(-1, 2),
        np.asarray(p1).reshape(-1, 2),
        linear=True,
    )


def _pivot_body(steps: FootSteps, t_start: float, t_end: float, dt: float) -> BodyTrack:
    n = math.ceil((t_end - t_start) / dt) + 1
    times = np.asarray(t_start + np.arange(n) * dt, dtype=np.float64)
    legs = steps.positions(times)
    xy = legs.mean(axis=1)
    d = legs[:, 0] - legs[:, 1]
    heading = np.arctan2(d[:, 1], d[:, 0]) - math.pi / 2  # leg 0 is on the left
    vel = np.gradient(xy, dt, axis=0)
    return BodyTrack(times, xy, np.arctan2(np.sin(heading), np.cos(heading)), vel)
