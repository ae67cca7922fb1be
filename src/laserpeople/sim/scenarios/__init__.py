"""The named, seeded scenario library.

Every scenario is a function ``build(rng, duration) -> Scene`` registered under a
kebab-case name with a one-line description, the paper experiment it reproduces and a
default duration. :func:`run_scenario` builds and simulates one::

    >>> from laserpeople.sim import run_scenario
    >>> result = run_scenario("speed-normal", seconds=1.0, seed=3)   # doctest: +SKIP

The same name and seed always give the same recording; another seed changes the people
(sizes, hues, speeds, start times) and the sensor noise.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from laserpeople.errors import LaserPeopleError
from laserpeople.sim.sensors import SensorSpec
from laserpeople.sim.simulator import ProgressWrapper, Scene, SimResult, simulate


class UnknownScenarioError(LaserPeopleError):
    """A scenario name that the library does not have; the message lists the known ones."""


Builder = Callable[[np.random.Generator, float], Scene]


@dataclass(frozen=True)
class ScenarioDef:
    """A registered scenario.

    Attributes:
        name: Kebab-case name.
        description: One line for ``laserpeople scenarios``.
        source: The paper experiment it follows ("004 Exp. 1", ...).
        duration: Default length [s].
        build: ``build(rng, duration) -> Scene``.
    """

    name: str
    description: str
    source: str
    duration: float
    build: Builder


REGISTRY: dict[str, ScenarioDef] = {}


def register(
    name: str, description: str, source: str, duration: float
) -> Callable[[Builder], Builder]:
    """Decorator adding a scene builder to :data:`REGISTRY`."""

    def deco(fn: Builder) -> Builder:
        if name in REGISTRY:
            raise ValueError(f"scenario {name!r} registered twice")
        REGISTRY[name] = ScenarioDef(name, description, source, duration, fn)
        return fn

    return deco


def register_scene(
    name: str,
    description: str,
    source: str,
    duration: float,
    scene: Callable[..., Scene],
    **options: object,
) -> None:
    """Add to :data:`REGISTRY` the builder ``scene(rng, seconds, **options)``: one scene
    function serving several scenarios that differ only in fixed keyword ``options``
    (e.g. ``moving=True``). ``duration`` is the default length [s]."""

    def build(rng: np.random.Generator, seconds: float) -> Scene:
        return scene(rng, seconds, **options)

    register(name, description, source, duration)(build)


def scenario_names() -> list[str]:
    """All scenario names, in library order."""
    return list(REGISTRY)


def get_scenario(name: str) -> ScenarioDef:
    """The scenario called ``name``; :class:`UnknownScenarioError` lists the known names."""
    try:
        return REGISTRY[name]
    except KeyError:
        from laserpeople.spelling import did_you_mean

        raise UnknownScenarioError(
            f"unknown scenario {name!r}{did_you_mean(name, REGISTRY, lead=': ')}",
            hint=f"known scenarios: {', '.join(REGISTRY)} (see `laserpeople scenarios`)",
        ) from None


def describe_scenario(name: str) -> str:
    """One line: what the scenario shows, and which paper experiment it follows."""
    s = get_scenario(name)
    return f"{s.description} [{s.source}; {s.duration:g} s]"


def build_scene(name: str, *, seconds: float | None = None, seed: int = 0) -> Scene:
    """The scene of scenario ``name`` for ``seed`` (not yet simulated)."""
    s = get_scenario(name)
    duration = s.duration if seconds is None else float(seconds)
    return s.build(np.random.default_rng([seed, 0x5CE4E]), duration)


MAX_SECONDS = 1e5
"""Longest simulation [s] (about 28 hours); longer ones cannot be held in memory."""
BYTES_PER_BEAM = 40
"""Memory per simulated beam [bytes]: range, intensity, four label arrays, points."""


def memory_limit() -> int:
    """Half the machine's physical memory [bytes] (8 GiB when it cannot be told)."""
    try:
        return int(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")) // 2
    except (ValueError, OSError, AttributeError):
        return 8 * 2**30


def check_fits_in_memory(
    sensors: Sequence[SensorSpec], duration: float, rate: float | None
) -> None:
    """Refuse a simulation whose scans would not fit in memory (see :func:`memory_limit`).

    Raises:
        LaserPeopleError: naming the estimate, the limit and what to do.
    """
    need = 0.0
    for spec in sensors:
        model = spec.laser
        hz = rate if rate is not None else model.rate_hz
        need += duration * hz * model.n_beams * BYTES_PER_BEAM
    limit = memory_limit()
    if need > limit:
        raise LaserPeopleError(
            f"{duration:g} s of scans would take about {need / 2**30:,.1f} GiB of memory, "
            f"more than the {limit / 2**30:,.1f} GiB allowed (half of this machine's)",
            hint="simulate fewer seconds or a lower --rate",
        )


def run_scenario(
    name: str,
    *,
    seconds: float | None = None,
    seed: int = 0,
    rate: float | None = None,
    progress: ProgressWrapper | None = None,
) -> SimResult:
    """Simulate scenario ``name`` for ``seconds`` (its default when None) with ``seed``;
    ``rate`` [Hz] overrides every sensor's scan rate; ``progress`` may wrap the scan loop."""
    s = get_scenario(name)
    duration = s.duration if seconds is None else float(seconds)
    if not (duration > 0.0 and math.isfinite(duration)):
        raise LaserPeopleError(
            f"--seconds must be positive and finite, got {seconds}", hint="e.g. --seconds 10"
        )
    if seed < 0:
        raise LaserPeopleError(f"--seed must be >= 0, got {seed}", hint="e.g. --seed 0")
    if rate is not None and not (rate > 0.0 and math.isfinite(rate)):
        raise LaserPeopleError(
            f"--rate must be positive and finite, got {rate}", hint="e.g. --rate 10"
        )
    if duration > MAX_SECONDS:
        raise LaserPeopleError(
            f"--seconds {duration:g} is longer than the {MAX_SECONDS:g} s a simulation can hold "
            "in memory",
            hint="simulate a shorter scene, e.g. --seconds 600",
        )
    scene = s.build(np.random.default_rng([seed, 0x5CE4E]), duration)
    check_fits_in_memory(scene.sensors, duration, rate)
    result = simulate(
        scene,
        duration,
        seed=seed,
        rate=rate,
        name=name,
        description=s.description,
        progress=progress,
    )
    result.meta["source"] = s.source
    return result


# the library modules register their scenarios on import
from laserpeople.sim.scenarios import arras as _arras  # noqa: E402,F401
from laserpeople.sim.scenarios import demo as _demo  # noqa: E402,F401
from laserpeople.sim.scenarios import feet_check as _feet_check  # noqa: E402,F401
from laserpeople.sim.scenarios import kraeussling as _kraeussling  # noqa: E402,F401
from laserpeople.sim.scenarios import moving_robot as _moving_robot  # noqa: E402,F401
from laserpeople.sim.scenarios import random_groups as _random_groups  # noqa: E402,F401
from laserpeople.sim.scenarios import randomised as _randomised  # noqa: E402,F401
from laserpeople.sim.scenarios import schenk as _schenk  # noqa: E402,F401
