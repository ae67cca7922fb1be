"""Walkers (extension of 000 Sec. 4.1): walker detections from blobs, the Kalman filter
per walker, the rule that cuts links, and the group tracker keeping a person who walks past
a standing pair apart from it, where 000's setting merges them."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.evaluation.groups import run_groups
from laserpeople.sim.motion import Route
from laserpeople.sim.simulator import Scene, simulate
from laserpeople.tracking.groups import GroupTrackerParams
from laserpeople.tracking.groups.observations import GroupObservations
from laserpeople.tracking.groups.walkers import (
    WalkerSettings,
    WalkerTracker,
    moving_apart,
    walker_detections,
)
from test_track_groups_sim import pair_and_passer


def _disc(cx: float, cy: float, r: float, n: int = 6) -> np.ndarray:
    a = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    return np.column_stack([cx + r * np.cos(a), cy + r * np.sin(a)])


def test_two_leg_blobs_close_together_are_one_walker_at_their_midpoint() -> None:
    # legs of one person 0.4 m apart, a lone leg 1.5 m away, a wide blob (a person seen
    # as one blob, radius 0.2 m)
    pts = np.concatenate(
        [_disc(0.0, 0.0, 0.05), _disc(0.4, 0.0, 0.05), _disc(2.0, 0.0, 0.05), _disc(5.0, 0, 0.2)]
    )
    blobs = np.repeat(np.arange(4), 6)
    places, walker = walker_detections(pts, blobs, pair_distance=0.7, leg_radius=0.12)
    assert walker.tolist() == [0, 0, 1, 2]
    np.testing.assert_allclose(places, [[0.2, 0.0], [2.0, 0.0], [5.0, 0.0]], atol=1e-12)
    empty_places, empty_walker = walker_detections(
        np.empty((0, 2)), np.empty(0, dtype=np.int64), 0.7, 0.12
    )
    assert empty_places.shape == (0, 2) and empty_walker.size == 0


@pytest.mark.parametrize(
    ("va", "vb", "apart"),
    [
        ((0.0, 0.0), (1.0, 0.0), True),  # one stands, one walks past
        ((0.2, 0.0), (0.0, 0.9), True),  # 0.2 m/s counts as standing
        ((0.0, 0.0), (0.7, 0.0), False),  # 0.7 m/s is not walking
        ((0.4, 0.0), (1.2, 0.0), False),  # both move, one heading
        ((1.0, 0.0), (0.9, 0.2), False),  # a party walking together, noisy
        ((0.5, 0.0), (-0.5, 0.0), True),  # opposite headings
        ((0.5, 0.0), (0.0, 0.5), False),  # 90 degrees apart: not more than 90
        ((0.5, 0.0), (-0.1, 0.5), True),  # just over 90 degrees
    ],
)
def test_moving_apart_cuts_passing_and_opposing_walkers_only(
    va: tuple[float, float], vb: tuple[float, float], apart: bool
) -> None:
    got = moving_apart(np.array([va]), np.array([vb]), 0.3, 0.8)
    assert got.tolist() == [apart]
    assert moving_apart(np.array([vb]), np.array([va]), 0.3, 0.8).tolist() == [apart]


def test_walker_velocity_converges_and_is_known_after_min_scans() -> None:
    tracker = WalkerTracker(WalkerSettings(on=True, min_scans=10))
    rng = np.random.default_rng(0)
    for k in range(40):
        place = np.array([[0.1 * k, 1.0]]) + rng.normal(0.0, 0.05, (1, 2))
        velocity, known, ids = tracker.update(place, 0.1 * k)
        assert known.tolist() == [k >= 9]  # the 10th detection makes it known
        assert ids.tolist() == [0]
    np.testing.assert_allclose(velocity[0], [1.0, 0.0], atol=0.15)
    # unseen for longer than max_unseen: dropped; the next detection is a new walker
    tracker.update(np.empty((0, 2)), 4.0)
    tracker.update(np.empty((0, 2)), 4.6)
    assert len(tracker) == 0
    _, known, ids = tracker.update(np.array([[4.6, 1.0]]), 4.7)
    assert known.tolist() == [False] and ids.tolist() == [1]


def test_links_of_a_walker_passing_a_standing_one_are_cut() -> None:
    """Single linkage at d_P joins a standing person and one walking past 0.8 m away;
    with the walkers tracked for a second, the observation is two clusters."""
    tracker = WalkerTracker(WalkerSettings(on=True))
    standing = _disc(0.0, 0.0, 0.2)
    counts = []
    for k in range(25):
        walking = _disc(-2.5 + 0.1 * k, 0.8, 0.2)
        pts = np.concatenate([standing, walking])

        def keep(p: np.ndarray, b: np.ndarray, links: np.ndarray, t: float = 0.1 * k) -> np.ndarray:
            return tracker.coherent_links(p, b, links, t)

        obs = GroupObservations.from_points(pts, np.arange(len(pts)), 1.3, 0.3, keep_links=keep)
        counts.append(len(obs))
    plain = GroupObservations.from_points(pts, np.arange(len(pts)), 1.3, 0.3)
    assert len(plain) == 1  # 000: one observation at the end
    assert counts[-1] == 2 and counts[-2] == 2


def test_keep_links_sees_only_the_points_kept() -> None:
    """A wall-sized blob is left out before the links are filtered, and the filter is
    called once with the kept points' own indices."""
    wall = np.column_stack([np.linspace(0.0, 4.0, 41), np.full(41, 3.0)])
    person = _disc(1.0, 2.2, 0.15)
    pts = np.concatenate([wall, person])
    calls: list[tuple[int, int]] = []

    def keep(p: np.ndarray, b: np.ndarray, links: np.ndarray) -> np.ndarray:
        calls.append((len(p), int(links.max()) if len(links) else -1))
        return np.ones(len(links), dtype=bool)

    obs = GroupObservations.from_points(pts, np.arange(len(pts)), 1.3, 0.3, None, 2.0, keep)
    assert calls == [(6, 5)]
    assert len(obs) == 1 and obs.members.tolist() == list(range(41, 47))


def _standing_pair_and_passer(seed: int) -> Scene:
    """Two people stand and talk; a third walks past them at 1.1 m/s, 0.9 m from the
    nearer one (within d_P)."""
    pair = [Route(6.6, 3.4, 0.0).wait(14.0), Route(7.4, 3.4, math.pi).wait(14.0)]
    return pair_and_passer(seed, pair, Route(13.0, 2.5, math.pi).walk_to(1.0, 2.5, 1.1))


def test_walkers_keep_a_person_passing_a_standing_pair_apart() -> None:
    """000's setting merges the passer into the standing pair (0.124, as bad as memory-less
    clustering, 0.132); with walkers the tracker keeps them apart (0.004: one scan's merge
    while the cut waits ``walker_apart_scans``)."""
    scans = simulate(_standing_pair_and_passer(3), 12.0, seed=3).scans
    paper = run_groups(scans, GroupTrackerParams())
    walkers = run_groups(scans, GroupTrackerParams(walkers=True))
    assert paper.memoryless.under_segmented >= 20  # they do come within d_P
    assert paper.clustering.error >= 0.5 * paper.memoryless.error  # 000's setting merges
    assert walkers.clustering.error <= 0.2 * walkers.memoryless.error
    assert walkers.clustering.over_rate <= 0.02
    assert walkers.merges <= 1  # while a cut waits apart_scans scans, one merge may win


def test_walker_settings_are_checked() -> None:
    with pytest.raises(ValueError, match="standing_speed"):
        WalkerSettings(standing_speed=1.0, walking_speed=0.5)
    with pytest.raises(ValueError, match="positive"):
        WalkerSettings(gate=0.0)
    with pytest.raises(ValueError, match="apart_scans"):
        GroupTrackerParams(walker_apart_scans=0)
