"""Simulated people: body sizes, appearance, group membership over time, planned motion.

A :class:`PersonSpec` says who a person is (id, leg radius, hip width, torso size, clothing
hue, accessory), where they go (a :class:`~laserpeople.sim.motion.Route`, or a ready-made
gait such as the pivot walk) and which group they belong to when. :func:`plan_person`
turns it into a :class:`PlannedPerson` whose state at any times is evaluated at once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.sim.gait import FootSteps, GaitParams, plan_footsteps
from laserpeople.sim.motion import BodyTrack, Route, sample_route

FloatArray = NDArray[np.float64]

LEG_Z_MAX = 0.85
"""Legs are seen by scanners mounted below this height [m]."""
TORSO_Z = (0.9, 1.5)
"""Height range [m] in which a scanner sees the torso (arms included)."""

BASIC_HUES = (0.0, 60.0, 120.0, 180.0, 240.0, 300.0)
"""The six basic clothing hues of 002 Table 1 [deg]: red, yellow, green, cyan, blue, magenta."""


@dataclass(frozen=True)
class BodyParams:
    """Ranges from which body sizes are drawn (uniformly) for each person."""

    config_section = "sim_body"

    leg_radius_min: float = param(
        0.065,
        "calibrated: segment widths of leg_tracker's labelled legs (benchmarks/sim_vs_real.py)",
        "smallest leg radius at scanner height (trousers included)",
        "m",
    )
    leg_radius_max: float = param(
        0.09,
        "calibrated: segment widths of leg_tracker's labelled legs (benchmarks/sim_vs_real.py)",
        "largest leg radius at scanner height (trousers included)",
        "m",
    )
    hip_half_width_min: float = param(
        0.08, "assumed", "smallest lateral offset of a foot from the body centre", "m"
    )
    hip_half_width_max: float = param(
        0.11, "assumed", "largest lateral offset of a foot from the body centre", "m"
    )
    torso_half_width: float = param(
        0.2, "assumed (shoulders incl. arms)", "torso semi-axis across", "m"
    )
    torso_half_depth: float = param(0.14, "assumed", "torso semi-axis along the heading", "m")
    torso_scale_spread: float = param(0.1, "assumed", "relative spread of torso size", "")
    hue_spread: float = param(
        10.0, "assumed", "spread of a person's hue round a basic colour of 002 Table 1", "deg"
    )


@dataclass(frozen=True, eq=False)
class PersonSpec:
    """One person of a scenario.

    Attributes:
        person_id: Non-negative id.
        route: Body path; ignored when ``gait`` is given.
        hue: Clothing hue [deg].
        leg_radius: Radius of each leg at scanner height [m].
        hip_half_width: Lateral offset of each foot from the body centre at rest [m].
        torso_axes: Torso semi-axes (along the heading, across) [m].
        groups: ``(from_time, group_id)`` pairs in time order; -1 = walking alone.
        accessory: Accessory kind (see :data:`~laserpeople.sim.accessories.ACCESSORIES`).
        leave_at_end: Whether the person disappears once the route ends (walked out of a
            door) instead of standing at its last point.
        gait: Ready-made (footsteps, body track), e.g. from
            :func:`~laserpeople.sim.gait.pivot_walk`.
        gait_params: This person's footstep planner parameters (cadence, swing); the
            defaults when None.
    """

    person_id: int
    route: Route | None
    hue: float
    leg_radius: float = 0.075
    hip_half_width: float = 0.1
    torso_axes: tuple[float, float] = (0.14, 0.2)
    groups: tuple[tuple[float, int], ...] = ((-math.inf, -1),)
    accessory: str | None = None
    leave_at_end: bool = False
    gait: tuple[FootSteps, BodyTrack] | None = field(default=None, repr=False)
    gait_params: GaitParams | None = None


def random_person(
    rng: np.random.Generator,
    person_id: int,
    route: Route | None,
    *,
    hue: float | None = None,
    params: BodyParams | None = None,
    **kwargs: object,
) -> PersonSpec:
    """A person with body sizes drawn from ``params`` and a hue near a basic colour."""
    p = params or BodyParams()
    if hue is None:
        hue = float(rng.choice(BASIC_HUES))
    hue = float((hue + rng.normal(0.0, p.hue_spread)) % 360.0)
    scale = 1.0 + p.torso_scale_spread * rng.uniform(-1.0, 1.0)
    return PersonSpec(
        person_id=person_id,
        route=route,
        hue=hue,
        leg_radius=float(rng.uniform(p.leg_radius_min, p.leg_radius_max)),
        hip_half_width=float(rng.uniform(p.hip_half_width_min, p.hip_half_width_max)),
        torso_axes=(p.torso_half_depth * scale, p.torso_half_width * scale),
        **kwargs,  # type: ignore[arg-type]
    )


def with_feet_apart(person: PersonSpec, gap: float = 0.03) -> PersonSpec:
    """``person`` with the hip half-width [m] raised, where needed, to the leg radius [m]
    plus ``gap`` / 2, so that the legs stand at least ``gap`` [m] apart at rest and never
    interpenetrate; everything else unchanged."""
    hip = max(person.hip_half_width, person.leg_radius + 0.5 * gap)
    return replace(person, hip_half_width=hip)


@dataclass(frozen=True, eq=False)
class PersonState:
    """A person's state at T instants.

    Attributes:
        present: (T,) whether the person is in the scene.
        xy: (T, 2) body centre [m].
        heading: (T,) [rad].
        velocity: (T, 2) [m/s].
        legs: (T, 2, 2) leg centres [m].
        group: (T,) group id (-1 alone).
    """

    present: NDArray[np.bool_]
    xy: FloatArray
    heading: FloatArray
    velocity: FloatArray
    legs: FloatArray
    group: NDArray[np.int64]


@dataclass(frozen=True, eq=False)
class PlannedPerson:
    """A person whose motion has been planned: body track plus footsteps."""

    spec: PersonSpec
    track: BodyTrack
    steps: FootSteps
    enter: float
    leave: float

    def state(self, times: NDArray[np.floating]) -> PersonState:
        """The state at ``times`` (T,) [s]."""
        times = np.asarray(times, dtype=np.float64)
        xy, heading, vel = self.track.at(times)
        legs = self.steps.positions(times)
        present = (times >= self.enter) & (times <= self.leave)
        return PersonState(present, xy, heading, vel, legs, group_at(self.spec.groups, times))


def group_at(
    groups: tuple[tuple[float, int], ...], times: NDArray[np.floating]
) -> NDArray[np.int64]:
    """The group id (-1 alone) at each of ``times`` (T,) [s] of a history of
    ``(from_time, group_id)`` pairs (:attr:`PersonSpec.groups`)."""
    starts = np.array([g[0] for g in groups])
    ids = np.array([g[1] for g in groups], dtype=np.int64)
    k = np.searchsorted(starts, times, side="right") - 1
    return np.where(k >= 0, ids[np.clip(k, 0, None)], -1)


def plan_person(spec: PersonSpec, t_end: float, gait: GaitParams | None = None) -> PlannedPerson:
    """Plan the body track and footsteps of ``spec`` up to ``t_end`` [s]."""
    if spec.gait is not None:
        steps, track = spec.gait
        enter = float(track.times[0])
        leave = float(track.times[-1]) if spec.leave_at_end else math.inf
        if not spec.leave_at_end and track.times[-1] < t_end:
            track = _extend_standing(track, t_end)
        return PlannedPerson(spec, track, steps, enter, leave)
    if spec.route is None:
        raise ValueError(f"person {spec.person_id} has neither a route nor a gait")
    track = sample_route(spec.route, t_end)
    steps = plan_footsteps(track, spec.hip_half_width, gait or spec.gait_params)
    enter = float(spec.route.t[0])
    leave = spec.route.end_time if spec.leave_at_end else math.inf
    return PlannedPerson(spec, track, steps, enter, leave)


def _extend_standing(track: BodyTrack, t_end: float) -> BodyTrack:
    dt = float(track.times[1] - track.times[0])
    extra = math.ceil((t_end - track.times[-1]) / dt)
    times = np.concatenate([track.times, track.times[-1] + dt * np.arange(1, extra + 1)])
    xy = np.concatenate([track.xy, np.repeat(track.xy[-1:], extra, axis=0)])
    heading = np.concatenate([track.heading, np.repeat(track.heading[-1:], extra)])
    vel = np.concatenate([track.velocity, np.zeros((extra, 2))])
    return BodyTrack(times, xy, heading, vel)
