"""People who pass each other are not a group (:mod:`laserpeople.tracking.groups.passing`):
the blobs' groups, the links cut and the clusters that result, against hand-computed cases."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from laserpeople.tracking.groups import GroupObservations, GroupTrackerParams
from laserpeople.tracking.groups.passing import (
    MovingGroup,
    PassingRule,
    attribute_blobs,
    keep_links,
)


def _group(x: float, vx: float, stamp: float = 0.0) -> MovingGroup:
    """One person at (x, 0) walking at vx along x, seen as two leg points 0.2 m apart."""
    position = np.array([x, 0.0])
    contour = position + np.array([[0.0, -0.1], [0.0, 0.1]])
    return MovingGroup(contour, position, np.array([vx, 0.0]), stamp)


def test_moving_group_is_predicted_at_constant_velocity() -> None:
    g = _group(1.0, 1.2, stamp=2.0)
    # 0.5 s later: 1.0 + 1.2 * 0.5 = 1.6 m
    np.testing.assert_allclose(g.points_at(2.5), [[1.6, -0.1], [1.6, 0.1]], atol=1e-12)
    empty = MovingGroup(np.empty((0, 2)), np.array([0.0, 1.0]), np.array([0.0, -2.0]), 0.0)
    np.testing.assert_allclose(empty.points_at(0.25), [[0.0, 0.5]], atol=1e-12)


def test_blobs_take_the_group_most_of_their_points_are_nearest_to() -> None:
    contours = [np.array([[0.0, 0.0]]), np.array([[1.0, 0.0]])]
    # blob 0: points at x 0.1, 0.45 (nearer 0) and 0.6 (nearer 1): group 0 by 2 votes
    # blob 1: one point at x 1.3, 0.3 m from group 1; blob 2: at x 3.0, 2 m from group 1
    pts = np.array([[0.1, 0.0], [0.45, 0.0], [0.6, 0.0], [1.3, 0.0], [3.0, 0.0]])
    blobs = np.array([0, 0, 0, 1, 2])
    owner = attribute_blobs(pts, blobs, contours, pass_distance=0.8)
    np.testing.assert_array_equal(owner, [0, 0, 0, 1, -1])
    # at 0.25 m blob 1 (0.3 m away) belongs to no group; blob 0's nearest point is 0.1 m
    owner = attribute_blobs(pts, blobs, contours, pass_distance=0.25)
    np.testing.assert_array_equal(owner, [0, 0, 0, -1, -1])


def test_links_between_groups_moving_apart_are_cut() -> None:
    velocities = np.array([[1.0, 0.0], [-0.2, 0.0], [0.9, 0.2]])
    owner = np.array([0, 0, 1, 2, -1])
    links = np.array([[0, 1], [1, 2], [0, 3], [2, 4], [3, 2]])
    # |v0 - v1| = 1.2 > 0.3: cut; |v0 - v2| = hypot(0.1, 0.2) = 0.224 <= 0.3: kept;
    # within group 0 and to the unattributed point 4: kept; |v2 - v1| = hypot(1.1, 0.2)
    keep = keep_links(links, owner, velocities, pass_speed=0.3)
    np.testing.assert_array_equal(keep, [True, False, True, True, False])
    # 0.224 m/s is more than 0.2 m/s: that link goes too
    keep = keep_links(links, owner, velocities, pass_speed=0.2)
    np.testing.assert_array_equal(keep, [True, False, False, True, False])


def test_a_person_passing_a_standing_person_is_a_cluster_of_their_own() -> None:
    """Two people 1.0 m apart (within d_P = 1.3 m): one stands, one walks at 1 m/s. With
    the rule they are two observations; off (000), or when both stand, one."""
    pts = np.array([[0.0, -0.1], [0.0, 0.1], [1.0, -0.1], [1.0, 0.1]])
    idx = np.arange(4)
    groups = [_group(0.0, 0.0), _group(0.9, 1.0)]  # the walker 0.1 s ago: 0.9 m
    rule = PassingRule(groups, 0.1, pass_distance=0.8, pass_speed=0.3)
    obs = GroupObservations.from_points(pts, idx, 1.3, 0.3, passing=rule)
    assert len(obs) == 2
    np.testing.assert_allclose(obs.centroids, [[0.0, 0.0], [1.0, 0.0]], atol=1e-12)
    assert len(GroupObservations.from_points(pts, idx, 1.3, 0.3)) == 1
    off = replace(rule, pass_distance=0.0)
    assert not off.active
    assert len(GroupObservations.from_points(pts, idx, 1.3, 0.3, passing=off)) == 1
    together = PassingRule([_group(0.0, 1.0), _group(0.9, 1.0)], 0.1, 0.8, 0.3)
    assert len(GroupObservations.from_points(pts, idx, 1.3, 0.3, passing=together)) == 1


def test_a_new_person_between_two_groups_still_links_them() -> None:
    """A blob no group claims (2 m from both predictions) keeps its links: it joins the
    two moving-apart groups into one cluster (single linkage through it)."""
    pts = np.array([[0.0, 0.0], [1.2, 0.0], [2.4, 0.0]])
    groups = [
        MovingGroup(np.array([[0.0, 0.0]]), np.zeros(2), np.array([1.0, 0.0]), 0.0),
        MovingGroup(np.array([[2.4, 0.0]]), np.array([2.4, 0.0]), np.array([-1.0, 0.0]), 0.0),
    ]
    rule = PassingRule(groups, 0.0, pass_distance=0.8, pass_speed=0.3)
    np.testing.assert_array_equal(rule.owners(pts, np.arange(3)), [0, -1, 1])
    assert len(GroupObservations.from_points(pts, np.arange(3), 1.3, 0.3, passing=rule)) == 1


def test_parameters_paper_preset_and_checks() -> None:
    p = GroupTrackerParams()
    assert (p.pass_distance, p.pass_speed) == (pytest.approx(0.8), pytest.approx(0.3))
    assert GroupTrackerParams.paper_preset["pass_distance"] == 0.0
    with pytest.raises(ValueError, match="pass_distance"):
        GroupTrackerParams(pass_distance=-0.1)
    with pytest.raises(ValueError, match="pass_speed"):
        GroupTrackerParams(pass_speed=float("inf"))
