"""The laser people simulator: worlds, walking people, ray-cast scanners, ground truth.

Entry points::

    from laserpeople.sim import run_scenario, scenario_names, describe_scenario
    result = run_scenario("demo", seconds=5, seed=1)
    result.write("demo.npz")

For scenes of your own, build a :class:`Scene` (``World``, ``PersonSpec`` list,
``SensorSpec`` list) and call :func:`simulate`.
"""

from laserpeople.sim.scenarios import (
    UnknownScenarioError,
    build_scene,
    describe_scenario,
    get_scenario,
    run_scenario,
    scenario_names,
)
from laserpeople.sim.simulator import Scene, SimResult, simulate

__all__ = [
    "Scene",
    "SimResult",
    "UnknownScenarioError",
    "build_scene",
    "describe_scenario",
    "get_scenario",
    "run_scenario",
    "scenario_names",
    "simulate",
]
