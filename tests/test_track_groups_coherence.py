"""The motion-coherence term of the group tracker (groups/coherence.py): each equation
against hand-computed values, the term inside the track model, and end to end on
simulated scans of a pair overtaking a slower pair within d_P."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.spatial import cKDTree

from laserpeople.evaluation.groups import run_groups
from laserpeople.scan import Pose2D
from laserpeople.sim.motion import Route
from laserpeople.sim.people import random_person
from laserpeople.sim.sensors import SensorSpec
from laserpeople.sim.simulator import Scene, simulate
from laserpeople.sim.world import World, room
from laserpeople.tracking.groups import GroupTrackerParams
from laserpeople.tracking.groups.coherence import (
    CoherenceSettings,
    CoherentGroupModel,
    aligned_distance_sq,
    coherence_distance_sq,
    coherence_log_likelihood,
    merge_histories,
    push_snapshot,
    reference_snapshot,
)
from laserpeople.tracking.groups.model import GroupModel, GroupPayload
from laserpeople.tracking.groups.observations import GroupObservations
from laserpeople.tracking.mht.tracktree import TrackNode


def _pts(*xy: float) -> np.ndarray:
    return np.array(xy, dtype=float).reshape(-1, 2)


def test_snapshots_are_kept_once_per_grid_slot_and_for_lag_seconds() -> None:
    h = push_snapshot((), 0.0, _pts(0, 0), lag=0.3, step=0.2)
    h = push_snapshot(h, 0.1, _pts(1, 1), 0.3, 0.2)  # same slot [0, 0.2): not kept
    assert [s for s, _ in h] == [0.0]
    h = push_snapshot(h, 0.2, _pts(2, 2), 0.3, 0.2)
    h = push_snapshot(h, 0.3, _pts(3, 3), 0.3, 0.2)  # slot [0.2, 0.4): not kept
    assert [s for s, _ in h] == [0.0, 0.2]
    h = push_snapshot(h, 0.4, _pts(4, 4), 0.3, 0.2)  # 0.0 is 0.4 s old > lag: dropped
    assert [s for s, _ in h] == [0.2, 0.4]
    assert h[1][1].tolist() == [[4.0, 4.0]]
    # a track seen first at 0.1 keeps the slots' first scans too: 0.1, 0.2, 0.4
    g = push_snapshot((), 0.1, _pts(0, 0), 1.0, 0.2)
    for t in (0.2, 0.3, 0.4):
        g = push_snapshot(g, t, _pts(0, 0), 1.0, 0.2)
    assert [s for s, _ in g] == [0.1, 0.2, 0.4]


def test_reference_snapshot_is_the_oldest_once_old_enough() -> None:
    h = ((1.0, _pts(0, 0)), (1.2, _pts(1, 0)))
    assert reference_snapshot(h, 1.25, 0.3) is None
    ref = reference_snapshot(h, 1.3, 0.3)
    assert ref is not None and ref[0] == 1.0
    assert reference_snapshot((), 5.0, 0.3) is None


def test_merged_history_joins_snapshots_of_the_same_scans() -> None:
    a = ((0.0, _pts(0, 0)), (0.2, _pts(0, 1)), (0.4, _pts(0, 2)))
    b = ((0.2, _pts(5, 1)), (0.45, _pts(5, 2)))
    m = merge_histories(a, b, tolerance=0.1)
    assert [s for s, _ in m] == [0.2, 0.4]  # 0.0: b was not seen then
    assert m[0][1].tolist() == [[0.0, 1.0], [5.0, 1.0]]
    assert m[1][1].tolist() == [[0.0, 2.0], [5.0, 2.0]]


def test_coherence_distance_and_likelihood_by_hand() -> None:
    # points (0,0), (1,0); past (0,0) moved by (0.5, 0): distances 0.5, 0.5 -> d^2 0.25
    assert coherence_distance_sq(_pts(0, 0, 1, 0), _pts(0, 0), np.array([0.5, 0.0])) == (
        pytest.approx(0.25)
    )
    # no shift: distances 0 and 1 -> 0.5
    assert coherence_distance_sq(_pts(0, 0, 1, 0), _pts(0, 0), np.zeros(2)) == pytest.approx(0.5)
    # log c = -1/2 w max(0, d^2 / sigma^2 - 2): 0.09 / 0.0225 = 4 -> -0.5 * 0.5 * 2
    assert coherence_log_likelihood(0.09, 0.15, 0.5) == pytest.approx(-0.5)
    assert coherence_log_likelihood(0.03, 0.15, 1.0) == 0.0  # within 2 sigma^2: no penalty


def test_alignment_finds_the_rigid_translation() -> None:
    past = _pts(0, 0, 2, 0, 0, 2)
    moved = past + np.array([0.3, -0.1])
    assert aligned_distance_sq(past, moved, np.zeros(2), 0) == pytest.approx(0.1)
    assert aligned_distance_sq(past, moved, np.zeros(2), 1) == pytest.approx(0.0, abs=1e-12)
    # two parts moving apart cannot be aligned by one translation: each is 0.5 m off
    half = np.array([0.5, 0.0])
    apart = np.concatenate([past[:1] - half, past[1:] + half])
    d_sq = aligned_distance_sq(past, apart, np.zeros(2), 3)
    assert d_sq == pytest.approx(0.25 * 8 / 9, rel=1e-9)  # best shift (1/6, 0)


def test_alignment_equals_a_kd_tree_icp_both_ways() -> None:
    """The dense distances give what nearest-neighbour queries of a KD-tree give (an
    independent computation of the same ICP), one way and both ways."""
    rng = np.random.default_rng(3)
    for _ in range(20):
        past = rng.normal(size=(int(rng.integers(3, 40)), 2)) * 0.5
        points = past[: int(rng.integers(2, len(past) + 1))] + rng.normal(size=2) * 0.3
        points = points + rng.normal(size=points.shape) * 0.05
        shift0 = rng.normal(size=2) * 0.2
        tree = cKDTree(past)
        s = shift0.copy()
        for _ in range(3):
            _, idx = tree.query(points - s)
            s = np.mean(points - past[idx], axis=0)
        dist, _ = tree.query(points - s)
        back, _ = cKDTree(points).query(past + s)
        one = float(np.mean(dist**2))
        both = 0.5 * (one + float(np.mean(back**2)))
        assert aligned_distance_sq(past, points, shift0, 3) == pytest.approx(one, rel=1e-9)
        assert aligned_distance_sq(past, points, shift0, 3, True) == pytest.approx(both, rel=1e-9)


def _node(history: tuple[tuple[float, np.ndarray], ...], contour: np.ndarray) -> TrackNode:
    mean = np.array([0.0, 0.0, 1.0, 0.0, 2.0])
    return TrackNode(0, 0, -1, mean, np.eye(5) * 0.05, 1.0, "detected",
                     payload=GroupPayload(contour, history=history))  # fmt: skip


def test_model_adds_log_c_to_the_gated_likelihoods() -> None:
    params = GroupTrackerParams()
    settings = CoherenceSettings(lag=1.0, min_age=0.3, step=0.2, sigma=0.15)
    base = GroupModel(params.model_settings())
    model = CoherentGroupModel(params.model_settings(), settings)
    contour = _pts(-0.3, 0, 0.3, 0, 0, 0.3)
    past = contour + np.array([-0.5, 0.0])  # 0.5 s ago, the group at -0.5 m walking at 1 m/s
    node_a, node_b = _node(((0.5, past),), contour), _node(((0.5, past),), contour)
    base.predict([node_a], 1.1)
    model.predict([node_b], 1.1)
    # the observation: the contour moved by 0.1 m, plus a point 0.2 m off the group
    pts = np.concatenate([contour + np.array([0.1, 0.0]), _pts(0.1, 0.5)])
    obs = GroupObservations.from_points(pts, np.arange(4), 1.3, 0.3)
    g0, ll0 = base.score([node_a], obs)
    g1, ll1 = model.score([node_b], obs)
    assert g0.tolist() == g1.tolist() == [[True]]
    # past moved by v tau = (0.6, 0): contour + 0.1 exactly; the extra point is 0.2 m
    # from (0.1, 0.3) -> d^2 = 0.04 / 4
    d_sq = 0.04 / 4
    assert d_sq / 0.15**2 < 2  # within the spread: no penalty
    assert ll1[0, 0] == pytest.approx(ll0[0, 0])
    tight = CoherentGroupModel(params.model_settings(), replace(settings, sigma=0.05))
    node_c = _node(((0.5, past),), contour)
    tight.predict([node_c], 1.1)
    _, ll2 = tight.score([node_c], obs)
    assert ll2[0, 0] - ll0[0, 0] == pytest.approx(-0.5 * (d_sq / 0.05**2 - 2.0))
    # the update keeps the observation in the history
    (_, _, payload), = tight.update([node_c], obs, [0], 1.1)  # fmt: skip
    assert [s for s, _ in payload.history] == [0.5, 1.1]


def overtaking_scene(seed: int) -> Scene:
    """A pair walks east at 1.3 m/s and overtakes a pair walking east at 0.5 m/s beside
    it (nearest members 0.8 m apart, within d_P = 1.3 m for about 4 s). Scanner 30 cm
    high at the south wall of a 16 m x 6 m room, 10 scans/s."""
    rng = np.random.default_rng(seed)
    fast = [Route(0.5, y, 0.0).walk_to(15.5, y, 1.3) for y in (2.0, 2.6)]
    slow = [Route(4.5, y, 0.0).walk_to(15.5, y, 0.5) for y in (3.4, 4.0)]
    people = [random_person(rng, i, r, groups=((-math.inf, 0),)) for i, r in enumerate(fast)]
    people += [random_person(rng, 2 + i, r, groups=((-math.inf, 1),)) for i, r in enumerate(slow)]
    sensor = SensorSpec("laser", "sick-lms200", 0.30, Pose2D(8.0, 0.2, math.pi / 2), rate_hz=10.0)
    return Scene(World(room(0.0, 0.0, 16.0, 6.0)), people, [sensor])


@pytest.mark.slow
def test_coherence_keeps_an_overtaking_pair_apart_on_simulated_scans() -> None:
    """Seed 1 (the same on seeds 2, 3): memory-less 0.151 (36 under-segmented clusters),
    000's likelihood (the default, coherence_lag 0) 0.147: it merges the pairs; with the
    coherence over 2 s 0.008."""
    result = simulate(overtaking_scene(1), 12.0, seed=1)
    paper = run_groups(result.scans, replace(GroupTrackerParams(), coherence_lag=0.0))
    run = run_groups(result.scans, replace(GroupTrackerParams(), coherence_lag=2.0))
    # the pairs come within d_P: memory-less clustering joins them for seconds
    assert run.memoryless.under_segmented >= 25
    # without the term the tracker merges them as well (why the term exists)
    assert paper.clustering.under_segmented >= 0.7 * run.memoryless.under_segmented
    # with it the tracker keeps them apart: a tracker that merges is as bad as memory-less
    assert run.clustering.error <= 0.25 * run.memoryless.error
    assert run.clustering.under_segmented <= 5


def test_merged_only_scores_merged_tracks_over_snapshots_from_before_the_merge() -> None:
    params = GroupTrackerParams()
    settings = CoherenceSettings(lag=1.0, min_age=0.3, step=0.2, sigma=0.05, merged_only=True)
    contour = _pts(-0.3, 0, 0.3, 0, 0, 0.3)
    past = contour + np.array([-0.5, 0.0])
    pts = np.concatenate([contour + np.array([0.1, 0.0]), _pts(0.1, 0.5)])
    obs = GroupObservations.from_points(pts, np.arange(4), 1.3, 0.3)
    base = GroupModel(params.model_settings())
    ref_node = _node(((0.5, past),), contour)
    base.predict([ref_node], 1.1)
    _, ll0 = base.score([ref_node], obs)
    got = []
    for merged in (math.nan, 0.4, 0.7):  # never merged; merged before / after the snapshot
        model = CoherentGroupModel(params.model_settings(), settings)
        node = _node(((0.5, past),), contour)
        node.payload = GroupPayload(contour, history=((0.5, past),), merged_stamp=merged)
        model.predict([node], 1.1)
        got.append(model.score([node], obs)[1][0, 0] - ll0[0, 0])
    # d^2 = 0.01 (see above): -1/2 (0.01 / 0.05^2 - 2) = -1 only for the merge at 0.7
    assert got == pytest.approx([0.0, 0.0, -1.0])
