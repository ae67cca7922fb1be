"""People who keep out of each other's way.

Scenes plan each party's route on its own, so two parties may cross one spot at one time.
Real people do not walk through each other: they step aside, the faster one the more.
:func:`keep_apart` bends planned routes just enough that no two people come closer than a
given distance (members of one group may stand closer than strangers), spreading every
sidestep over the seconds around the encounter so that the motion stays a walk.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import gaussian_filter1d

from laserpeople.sim.gait import plan_footsteps
from laserpeople.sim.motion import BodyTrack, facing, sample_route
from laserpeople.sim.people import PersonSpec, group_at

FloatArray = NDArray[np.float64]

_STEP = 0.05
"""Time step [s] on which encounters are resolved."""
_REACH = 2.0
"""Pairs whose planned paths never come within the distance plus this much [m] are left
alone (sidesteps are shorter than this)."""
_PASSING = 0.2
"""Relative speed [m/s] above which two people pass each other sideways."""


def _directions(d: FloatArray, dist: FloatArray, rel_v: FloatArray) -> FloatArray:
    """Unit vectors (P, T, 2) along which the first of each pair gives way: across the
    relative motion while the two pass each other (to the side each is already on), along
    the line between them while they stand or walk alike, and in between below
    :data:`_PASSING`."""
    rel_speed = np.hypot(rel_v[..., 0], rel_v[..., 1])
    along = rel_v / np.maximum(rel_speed, 1e-9)[..., None]
    side = np.stack([-along[..., 1], along[..., 0]], axis=-1)
    sideways = np.where((np.sum(d * side, axis=-1) < 0)[..., None], -side, side)
    apart = np.where((dist < 1e-6)[..., None], side, d / np.maximum(dist, 1e-9)[..., None])
    passing = np.clip(rel_speed / _PASSING, 0.0, 1.0)[..., None]
    mixed = passing * sideways + (1.0 - passing) * apart
    return mixed / np.maximum(np.hypot(mixed[..., 0], mixed[..., 1]), 1e-9)[..., None]


def _shifted(track: BodyTrack, grid: FloatArray, shift: FloatArray) -> BodyTrack:
    """``track`` moved by ``shift`` (T, 2) [m] given on ``grid`` (T,) [s], its velocity and
    (while walking) its heading following the new path."""
    times = track.times
    xy = track.xy + np.column_stack(
        [np.interp(times, grid, shift[:, 0]), np.interp(times, grid, shift[:, 1])]
    )
    vel = np.gradient(xy, float(times[1] - times[0]), axis=0)
    return BodyTrack(times, xy, facing(vel, track.heading), vel)


def keep_apart(
    people: Sequence[PersonSpec],
    t_end: float,
    *,
    distance: float,
    group_distance: float,
    bounds: tuple[float, float, float, float],
    lead: float = 1.0,
    iterations: int = 400,
    tolerance: float = 0.01,
) -> list[PersonSpec]:
    """``people`` (with routes) whose paths are bent so that body centres stay at least
    ``distance`` [m] apart, and ``group_distance`` [m] within one group
    (:attr:`PersonSpec.groups`), from the start of each route until ``t_end`` [s].

    Each sidestep is shared by speed (a person standing gives way least) and smoothed
    with a Gaussian of ``lead`` [s], so people start to step aside before they meet.
    Positions stay inside ``bounds`` ``(x_min, y_min, x_max, y_max)`` [m]. The people
    come back with their motion fixed (:attr:`PersonSpec.gait`, footsteps planned on the
    bent path); people that never come too close keep their planned paths.
    """
    if len(people) < 2:
        return list(people)
    tracks = [sample_route(p.route, t_end) for p in people if p.route is not None]
    if len(tracks) != len(people):
        raise ValueError("keep_apart needs every person's route")
    grid = np.arange(0.0, t_end + _STEP, _STEP)
    states = [tr.at(grid) for tr in tracks]
    base = np.stack([s[0] for s in states])
    vel = np.stack([s[2] for s in states])
    speed = np.hypot(vel[..., 0], vel[..., 1])
    present = np.stack([grid >= tr.times[0] for tr in tracks])
    group = np.stack([group_at(p.groups, grid) for p in people])
    i, j = np.triu_indices(len(people), 1)
    gap = np.hypot(*np.moveaxis(base[i] - base[j], -1, 0))
    near = np.any((gap < distance + _REACH) & present[i] & present[j], axis=1)
    i, j = i[near], j[near]
    same = (group[i] == group[j]) & (group[i] >= 0)
    least = np.where(same, group_distance, distance)
    both = present[i] & present[j]
    # the first's part of each sidestep; two people standing share it equally
    share = ((speed[i] + 0.05) / (speed[i] + speed[j] + 0.1))[..., None]
    rel_v = vel[i] - vel[j]
    lo, hi = np.array(bounds[:2]), np.array(bounds[2:])
    members = [(i == k, j == k) for k in range(len(people))]
    shift = np.zeros_like(base)
    for _ in range(iterations):
        pos = np.clip(base + shift, lo, hi)
        d = pos[i] - pos[j]
        dist = np.hypot(d[..., 0], d[..., 1])
        need = np.where(both, np.clip(least - dist, 0.0, None), 0.0)
        if float(need.max(initial=0.0)) < tolerance:
            break
        step = need[..., None] * _directions(d, dist, rel_v)
        mine, theirs = share * step, (1.0 - share) * step
        push = np.stack([mine[k].sum(axis=0) - theirs[m].sum(axis=0) for k, m in members])
        shift += gaussian_filter1d(push, lead / _STEP, axis=1, mode="constant")
    shift = np.clip(base + shift, lo, hi) - base
    out = []
    for person, track, moved in zip(people, tracks, shift, strict=True):
        if not np.any(np.abs(moved) > 1e-4):
            out.append(person)
            continue
        bent = _shifted(track, grid, moved)
        steps = plan_footsteps(bent, person.hip_half_width, person.gait_params)
        out.append(replace(person, gait=(steps, bent)))
    return out
