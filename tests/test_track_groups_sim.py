"""End to end: the group tracker on simulated laser scans (ray-cast legs, the simulator's
per-beam labels as a perfect background model) of 000's Fig. 18 scene, scored with the
clustering error and the group-size error against memory-less single linkage."""

from __future__ import annotations

import math

import numpy as np

from laserpeople.evaluation.groups import _classify, _mixed_clusters, run_groups
from laserpeople.scan import Pose2D
from laserpeople.sim.motion import Route
from laserpeople.sim.people import random_person
from laserpeople.sim.sensors import SensorSpec
from laserpeople.sim.simulator import Scene, simulate
from laserpeople.sim.world import World, room
from laserpeople.tracking.groups import GroupTrackerParams


def pair_and_passer(seed: int, pair: list[Route], passer: Route) -> Scene:
    """Two people of one group following ``pair`` and one alone following ``passer`` in a
    14 m x 6 m room; scanner 30 cm high at the south wall, 10 scans/s."""
    rng = np.random.default_rng(seed)
    people = [random_person(rng, i, r, groups=((-math.inf, 0),)) for i, r in enumerate(pair)]
    people.append(random_person(rng, 2, passer))
    sensor = SensorSpec("laser", "sick-lms200", 0.30, Pose2D(7.0, 0.2, math.pi / 2), rate_hz=10.0)
    return Scene(World(room(0.0, 0.0, 14.0, 6.0)), people, [sensor])


def fig18_scene(seed: int) -> Scene:
    """A pair walks east, 1.2 m apart (one group); a person walks west between them (000
    Fig. 18)."""
    pair = [
        Route(1.0, 2.4, 0.0).walk_to(13.0, 2.4, 1.0),
        Route(1.0, 3.6, 0.0).walk_to(13.0, 3.6, 1.0),
    ]
    return pair_and_passer(seed, pair, Route(13.0, 3.0, math.pi).walk_to(1.0, 3.0, 1.1))


def test_group_tracker_keeps_passing_groups_apart_on_simulated_scans() -> None:
    """Seed 7: tracker 0.000, memory-less 0.070. (Seed 8 is harder: after the pass the
    person's track takes a member of the pair for a while, tracker 0.066 vs 0.074.)"""
    result = simulate(fig18_scene(7), 12.0, seed=7)
    run = run_groups(result.scans, GroupTrackerParams(cluster_distance=1.3))  # 000's d_P
    # the person and the pair come within d_P: memory-less clustering joins them
    assert run.memoryless.under_segmented >= 8
    # the tracker keeps them apart by velocity and re-clustering (a tracker that merges
    # or does not re-cluster is as bad as memory-less clustering)
    assert run.clustering.error <= 0.5 * run.memoryless.error
    assert run.clustering.over_rate <= 0.05
    # sizes: counted as blobs at d_hs = 0.3 m (000), the legs of a walker are often two
    # blobs, so walkers are over-counted (docs/groups.md); never by more than one here
    assert run.size.within_one_share >= 0.9
    assert run.size.mean_error <= 1.2
    assert run.merges == 0


def test_under_segmentation_is_split_into_transitions_and_distinct_groups() -> None:
    """A cluster holding people 1 and 2 (true groups 0 and 1) at scan 5 is a transition
    when they are one group within the window (scan 7), distinct otherwise; a cluster of
    one true group is not under-segmented at all."""
    true_group = np.array([0, 0, 1, 1, 2])
    true_person = np.array([1, 1, 2, 2, 3])
    est = np.array([4, 4, 4, 4, 5])
    mixed = _mixed_clusters(true_group, true_person, est)
    assert [m.tolist() for m in mixed] == [[1, 2]]
    apart = {1: 0, 2: 1, 3: 2}
    group_of = [apart] * 7 + [{1: 9, 2: 9, 3: 2}] + [apart] * 4
    assert _classify([(5, mixed[0])], group_of, window=2).transition == 1
    assert _classify([(5, mixed[0])], group_of, window=1).distinct == 1
