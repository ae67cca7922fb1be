"""The group tracker end to end on a random-groups scene (a tuning seed, a torso-height
laser of 0.82 deg with ten people): the size counted from what the laser resolves, and the
group CLEAR MOT against the true groups."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from laserpeople.config import load_config
from laserpeople.evaluation.groups import (
    ALONE_ID,
    JOINED_ID,
    PROXEMIC_SPEED,
    group_truth,
    near_and_alike,
    proxemic_truth,
    run_groups,
)
from laserpeople.sim.scenarios import run_scenario
from laserpeople.tracking.groups import GroupTrackerParams
from laserpeople.truth import TruthFrame

AT_000_D_P = GroupTrackerParams(cluster_distance=1.3)
"""The figures measured below are at 000's d_P (1.3 m); the default's 1.0 m:
:func:`test_groups_within_1_m_score_above_000s_d_p`."""


@pytest.fixture(scope="module")
def scene():  # type: ignore[no-untyped-def]
    return run_scenario("random-groups", seed=7, seconds=15.0)


def test_resolved_size_counting_end_to_end(scene) -> None:  # type: ignore[no-untyped-def]
    # measured: resolved 93.4 % exact, 0.081 people off (a torso-height scene; without
    # surface_gap 94.7 %, 0.068: on this scene the rule costs, on tuning seeds 0-19 torso
    # height it gains 91.5 -> 93.3 %); without pair_arc (leg-sized blobs that cover two legs
    # paired) 91.3 %, 0.103; resolved as before the matching, pair_arc and person_width
    # 92.4 %, 0.090 (with size std 0.15 as well: 89.3 %, 0.127); the leg pairs of "legs"
    # 81.7 %, 0.25; 000's blobs 84.5 %, 0.21 (a counter that ignores the beams' arc is one
    # of those). These are the counting rules of one scan: measured without the range of
    # counts (stride_near = stride_far = 0). With it (the default) this scene, a torso
    # laser not told its height, counts 93.2 %, 0.0825 people off; told its height the
    # range is not used (no pairs at torso height).
    base = replace(AT_000_D_P, stride_near=0.0, stride_far=0.0)
    r = run_groups(scene.scans, base, truth=scene.truth)
    assert r.size.count > 400
    assert r.size.exact_share >= 0.93
    assert r.size.mean_error <= 0.082
    before = {"pair_arc": 0.0, "person_width": 0.0}  # (and mutual nearest legs: 92.4 %)
    others: list[dict[str, object]] = [
        {"size_count": "legs"},
        {"size_count": "blobs"},
        {"pair_arc": 0.0},
        before,
        {**before, "size_std": 0.15},
    ]
    for change in others:
        other = run_groups(scene.scans, replace(base, **change))  # type: ignore[arg-type]
        assert other.size.exact_share < 0.93 or other.size.mean_error > 0.082, change
    m = r.group_mot
    assert m.num_truth > 0 and math.isfinite(m.mota)
    assert m.matches + m.misses == m.num_truth
    # measured: group MOTA 0.487, proxemic 0.723, 11 id switches; without the id handover
    # (id_memory 0) 0.439 / 0.595, 15. Measured on this scene before its people stepped
    # aside for each other (pass_distance 0): 0.478 / 0.684, 11 (without vanished groups
    # coasted, coast_time 0: 0.480 / 0.684, 9; without the id handover, id_memory 0: 0.429 /
    # 0.559, 17, and without coasting as well 0.468 / 0.667, 24; without groups in the
    # shadow kept as well (and no coasting),
    # shadow_occlusion false, 0.470 / 0.669; 0.472 / 0.681 with the Kalman velocity
    # in eqs. 25-27, velocity_window 0); the earlier eq. 32 prior and N-scan 8
    # ("choice", 8) 0.463 / 0.647, d_P 2.0 0.424 / 0.606, velocities unknown (eps_vel 3
    # m/s) 0.720 / 0.503: each misses one of the two
    assert 0.475 <= m.mota < 1.0
    assert r.proxemic_mot.mota >= 0.68
    assert m.id_switches <= 12
    plain = run_groups(scene.scans, replace(AT_000_D_P, id_memory=0.0), truth=scene.truth)
    assert plain.group_mot.mota < 0.475 and plain.proxemic_mot.mota < 0.68
    assert plain.group_mot.id_switches > 12


def test_groups_within_1_m_score_above_000s_d_p(scene) -> None:  # type: ignore[no-untyped-def]
    # measured on this scene: group MOTA 0.596 with 3 id switches at the default d_P of
    # 1.0 m, 0.487 with 11 at 000's 1.3 m (two parties standing 0.75 m apart, and a walker
    # passing at 0.6 m, joined for longer); 000's value stays reachable as the paper preset
    default = GroupTrackerParams()
    assert default.cluster_distance == 1.0
    assert load_config(GroupTrackerParams, None, "paper").cluster_distance == 1.3
    ours = run_groups(scene.scans, default, truth=scene.truth).group_mot
    theirs = run_groups(scene.scans, AT_000_D_P, truth=scene.truth).group_mot
    assert ours.mota >= 0.56 and ours.id_switches <= 6
    assert theirs.mota < 0.52 and theirs.id_switches > 6


def test_a_laser_told_at_torso_height_counts_bodies_not_leg_pairs(scene) -> None:  # type: ignore[no-untyped-def]
    # measured on this 1.19 m laser: told its height, 99.3 % exact and 0.014 people off
    # (the same groups: group MOTA 0.487 either way); not told, or with torso_pairs, 95.9 %
    # and 0.048 (the neighbours' torsos closer than a stride paired as one person's legs)
    told = run_groups(scene.scans, AT_000_D_P, truth=scene.truth, laser_height=1.188)
    assert told.size.exact_share >= 0.985 and told.size.mean_error <= 0.025
    pairs = replace(AT_000_D_P, torso_pairs=True)
    kept = run_groups(scene.scans, pairs, truth=scene.truth, laser_height=1.188)
    assert kept.size.exact_share < 0.975 and kept.size.mean_error > 0.035
    assert told.group_mot.mota == kept.group_mot.mota


def test_group_truth_puts_each_group_at_its_members_mean() -> None:
    frame = TruthFrame(
        stamp=1.0,
        scan_index=4,
        person_ids=np.array([0, 1, 2, 5]),
        positions=np.array([[0.0, 0.0], [1.0, 0.0], [5.0, 5.0], [2.0, 2.0]]),
        velocities=np.zeros((4, 2)),
        group_ids=np.array([3, 3, -1, 3]),
        leg_positions=np.zeros((4, 2, 2)),
        hues=np.zeros(4),
    )
    groups = group_truth(frame)
    assert groups.scan_index == 4
    got = dict(zip(groups.person_ids.tolist(), groups.positions.tolist(), strict=True))
    assert set(got) == {3, ALONE_ID + 2}
    np.testing.assert_allclose(got[3], [1.0, 2.0 / 3.0], atol=1e-12)
    np.testing.assert_allclose(got[ALONE_ID + 2], [5.0, 5.0], atol=1e-12)


def _frame(
    positions: list[list[float]], velocities: list[list[float]], groups: list[int]
) -> TruthFrame:
    pos = np.asarray(positions, dtype=float)
    side = np.array([0.0, 0.1])
    legs = np.stack([pos + side, pos - side], axis=1)  # legs 0.1 m either side
    return TruthFrame(
        stamp=0.0,
        scan_index=0,
        person_ids=np.arange(len(pos)),
        positions=pos,
        velocities=np.asarray(velocities, dtype=float),
        group_ids=np.asarray(groups),
        leg_positions=legs,
        hues=np.zeros(len(pos)),
    )


def test_proxemic_truth_joins_groups_within_d_p_that_move_alike() -> None:
    # groups 0 (people 0, 1) and 1 (person 2) stand 1.0 m apart (legs 1.0 m apart): joined
    # at d_P 1.3 m, at the mean of all three; person 3 alone, 5 m away, stays on its own
    frame = _frame(
        [[0.0, 0.0], [0.5, 0.0], [1.5, 0.0], [6.5, 0.0]],
        [[0.0, 0.0]] * 4,
        [0, 0, 1, -1],
    )
    out = proxemic_truth(frame, 1.3)
    got = dict(zip(out.person_ids.tolist(), out.positions.tolist(), strict=True))
    assert set(got) == {JOINED_ID + 0, ALONE_ID + 3}
    np.testing.assert_allclose(got[JOINED_ID], [2.0 / 3.0, 0.0], atol=1e-12)
    # at d_P 0.9 m the legs (1.0 m apart) are too far: the scene's groups
    apart = proxemic_truth(frame, 0.9)
    assert sorted(apart.person_ids.tolist()) == [0, 1, ALONE_ID + 3]


def test_proxemic_truth_keeps_groups_apart_that_move_differently() -> None:
    # a person passes a pair 0.6 m away at 1.2 m/s against them (000 Fig. 18): two groups;
    # at 0.4 m/s apart (below PROXEMIC_SPEED) they are one
    fast = _frame([[0.0, 0.0], [0.5, 0.0], [1.1, 0.0]], [[0, 0.6], [0, 0.6], [0, -0.6]], [4, 4, -1])
    assert sorted(proxemic_truth(fast, 1.3).person_ids.tolist()) == [4, ALONE_ID + 2]
    slow = _frame([[0.0, 0.0], [0.5, 0.0], [1.1, 0.0]], [[0, 0.6], [0, 0.6], [0, 0.2]], [4, 4, -1])
    assert proxemic_truth(slow, 1.3).person_ids.tolist() == [JOINED_ID + 4]
    assert pytest.approx(0.5) == PROXEMIC_SPEED


def test_proxemic_truth_measures_from_leg_to_leg() -> None:
    # person 0 (group 0) at x = 0 with legs at -0.3 and 0.3 (a long stride along x) and
    # person 1 (group 1) at x = 1.2 with legs at 0.9 and 1.5, both standing: bodies 1.2 m
    # apart, nearest legs 0.6 m, farthest 1.8 m. At d_P 0.8 m one leg pair is within it:
    # joined at the mean (0.6, 0); at d_P 0.5 m none is
    pos = np.array([[0.0, 0.0], [1.2, 0.0]])
    legs = np.array([[[-0.3, 0.0], [0.3, 0.0]], [[0.9, 0.0], [1.5, 0.0]]])
    frame = TruthFrame(0.0, 0, np.arange(2), pos, np.zeros((2, 2)), np.array([0, 1]), legs,
                       np.zeros(2))  # fmt: skip
    near, alike = near_and_alike(frame, np.array([0]), np.array([1]), 0.8)
    assert near.tolist() == [[True]] and alike.tolist() == [[True]]
    out = proxemic_truth(frame, 0.8)
    assert out.person_ids.tolist() == [JOINED_ID + 0]
    np.testing.assert_allclose(out.positions, [[0.6, 0.0]], atol=1e-12)
    assert sorted(proxemic_truth(frame, 0.5).person_ids.tolist()) == [0, 1]
    # without legs (NaN) the body centres, 1.2 m apart: joined at d_P 1.3 m, not at 0.8 m
    blind = replace(frame, leg_positions=np.full((2, 2, 2), np.nan))
    assert proxemic_truth(blind, 1.3).person_ids.tolist() == [JOINED_ID + 0]
    assert sorted(proxemic_truth(blind, 0.8).person_ids.tolist()) == [0, 1]
