"""The oracle bound of benchmarks/visible_people.py on small ray-cast scans: person-sized
clusters, seeing through a place, walkers against posts and walls, people from legs, and
the MOTA arithmetic."""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from laserpeople.scan import Pose2D, Scan

INC = math.radians(0.5)  # rad per beam
MIN = -math.radians(135.0)  # rad, 270 degrees of view
N = 541  # beams
BESIDE = (-1.3, 0.4, -2.3, -0.6)  # m, the lobby's box in the laser frame
GATE = 0.75  # m


def vp() -> Any:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    import visible_people

    return visible_people


def cast(
    pose: Pose2D,
    circles: list[tuple[float, float, float]],
    walls: list[tuple[float, float, float, float]] = (),  # type: ignore[assignment]
    index: int = 0,
) -> Scan:
    """A scan from ``pose`` of circles (x, y, radius) and wall segments (x0, y0, x1, y1),
    world frame [m]; +inf where a beam hits nothing."""
    ranges = np.full(N, np.inf)
    origin = np.array([pose.x, pose.y])
    for k in range(N):
        a = pose.theta + MIN + k * INC
        d = np.array([math.cos(a), math.sin(a)])
        for cx, cy, r in circles:
            f = origin - (cx, cy)
            b = float(f @ d)
            disc = b * b - (float(f @ f) - r * r)
            if disc >= 0.0 and -b - math.sqrt(disc) > 0.0:
                ranges[k] = min(ranges[k], -b - math.sqrt(disc))
        for x0, y0, x1, y1 in walls:
            e = np.array([x1 - x0, y1 - y0])
            m = np.array([[d[0], -e[0]], [d[1], -e[1]]])
            if abs(np.linalg.det(m)) < 1e-12:
                continue
            t, u = np.linalg.solve(m, np.array([x0, y0]) - origin)
            if t > 0.0 and 0.0 <= u <= 1.0:
                ranges[k] = min(ranges[k], t)
    return Scan(0.1 * index, MIN, INC, ranges, 0.03, 11.0, pose=pose, index=index)


def test_clusters_keep_leg_sized_near_objects_only() -> None:
    m = vp()
    scan = cast(
        Pose2D(0.0, 0.0, 0.0),
        [
            (2.0, 0.0, 0.06),  # a leg at 2 m: kept
            (4.0, 1.5, 0.06),  # a leg beyond RANGE (4.3 m): left out
            (1.5, -1.5, 0.005),  # a wire: one or two returns, left out
        ],
        [(-3.0, -3.0, 3.0, -3.0)],  # a wall: wider than MAX_WIDTH, left out
    )
    centres = m.clusters(scan)
    assert centres.shape == (1, 2)
    # the arc's returns lie on the near side of the circle: centre 1.94-1.96 m
    assert centres[0] == pytest.approx([1.95, 0.0], abs=0.02)


def test_seen_through() -> None:
    m = vp()
    wall = [(5.0, -5.0, 5.0, 5.0)]  # x = 5 m
    scan = cast(Pose2D(0.0, 0.0, 0.0), [], wall)
    assert m.seen_through(scan, np.array([2.0, 0.0]))  # wall 3 m behind
    assert not m.seen_through(scan, np.array([4.8, 0.0]))  # wall 0.2 m behind < MARGIN
    assert m.seen_through(scan, np.array([4.65, 0.0]))  # 0.35 m behind >= MARGIN
    assert not m.seen_through(scan, np.array([-2.0, 0.0]))  # behind the laser, not in view
    shifted = cast(Pose2D(1.0, 0.0, 0.0), [], wall)
    assert not m.seen_through(shifted, np.array([4.8, 0.0]))  # the pose is applied
    assert m.seen_through(shifted, np.array([2.0, 0.0]))
    beam = round((0.0 - MIN) / INC)
    for value, through in ((math.nan, True), (math.inf, True), (0.0, False), (1.0, False)):
        ranges = scan.ranges.copy()
        ranges[beam] = value
        assert (
            m.seen_through(
                Scan(0.0, MIN, INC, ranges, 0.03, 11.0, pose=scan.pose), np.array([2.0, 0.0])
            )
            is through
        )


def test_walked_needs_distance_and_places_seen_through() -> None:
    m = vp()
    wall = [(-1.0, -1.0, 3.0, -1.0)]  # y = -1 m, seen at a grazing angle
    open_scans = {i: cast(Pose2D(0.0, 0.0, 0.0), [], index=i) for i in range(12)}
    wall_scans = {i: cast(Pose2D(0.0, 0.0, 0.0), [], wall, index=i) for i in range(12)}

    def path(step: float) -> Any:
        idx = list(range(4, 8))
        world = [np.array([0.5 + step * k, -1.0]) for k in range(4)]
        return m.Path(idx, world, world)

    assert path(0.2).walked(open_scans)  # 0.6 m, its places empty half a second apart
    assert not path(0.2).walked(wall_scans)  # slides along a wall: never seen through
    assert not path(0.16).walked(open_scans)  # 0.48 m < WALKED


def test_people_single_linkage() -> None:
    m = vp()
    one = m.people(np.array([[0.0, 0.0], [0.5, 0.0]]))
    assert len(one) == 1 and one[0] == pytest.approx([0.25, 0.0], abs=1e-12)
    assert len(m.people(np.array([[0.0, 0.0], [1.0, 0.0]]))) == 2
    chain = m.people(np.array([[0.0, 0.0], [0.7, 0.0], [1.4, 0.0]]))
    assert len(chain) == 1 and chain[0] == pytest.approx([0.7, 0.0], abs=1e-12)


def test_walker_beside_a_moving_robot_counted_post_not() -> None:
    """A robot drives along +x at 0.1 m per scan; a companion walks beside it (1 m to its
    right), a post stands 2 m to the right of its path, and a labelled person walks
    towards it. Only the companion is unlabelled, on every labelled scan."""
    m = vp()
    scans = []
    for i in range(32):
        x = 0.1 * i
        scans.append(
            cast(
                Pose2D(x, 0.0, 0.0),
                [
                    (x - 0.2, -1.0, 0.06),  # the companion's leg
                    (2.0, -2.0, 0.06),  # a post, in the box from about scan 16 on
                    (6.0 - 0.1 * i, 0.8, 0.06),  # the labelled walker
                ],
                index=i,
            )
        )
    labels = {i: {1: np.array([6.0 - 0.2 * i, 0.8])} for i in range(6, 30)}
    seen = m.unlabelled_people(scans, labels, BESIDE, GATE)
    assert [u.scan for u in seen] == list(range(6, 30))
    for u in seen:
        assert u.others == ()
        assert len(u.beside) == 1
        # the mean of the returns on the leg's near side, 0.05 m short of its centre
        assert u.beside[0] == pytest.approx((-0.190, -0.954), abs=0.005)
    o = m.oracle(labels, m.labels_shown(scans, labels, 0.5), seen)
    # the labelled walker is seen from scan 6 on (at 4.8 m, beyond RANGE, too)
    assert (o.labels, o.shown, o.scans, o.beside, o.unlabelled) == (24, 24, 24, 24, 24)
    # labels 0.6 m off their walker are not shown
    off = {i: {1: p[1] + (0.0, 0.6)} for i, p in labels.items()}
    assert m.labels_shown(scans, off, 0.5) == 0
    # the post alone passes through the box and is never counted
    still = [cast(Pose2D(0.1 * i, 0.0, 0.0), [(2.0, -2.0, 0.06)], index=i) for i in range(32)]
    assert all(
        not u.beside and not u.others for u in m.unlabelled_people(still, labels, BESIDE, GATE)
    )


def test_oracle_arithmetic() -> None:
    m = vp()
    o = m.Oracle(labels=57, shown=57, scans=43, beside=23, unlabelled=38)
    assert o.mota == pytest.approx(1 - 38 / 57, abs=1e-12)
    # recall 0.70 of 57 needs 40 matches (39.9 rounded up): 17 misses
    assert o.mota_at_recall(0.70) == pytest.approx(1 - (17 + 38) / 57, abs=1e-12)
    assert o.mota_at_recall(0.71) == pytest.approx(1 - (16 + 38) / 57, abs=1e-12)  # 41
    # MOTA 0.50 allows 28 misses + false positives (28.5 rounded down)
    assert o.max_false_positives(0.70, 0.50) == 11
    assert o.min_recall(0.50) == pytest.approx(67 / 57, abs=1e-12)  # above 1: none
    fewer = m.Oracle(labels=57, shown=57, scans=43, beside=13, unlabelled=24)
    assert fewer.min_recall(0.50) == pytest.approx(53 / 57, abs=1e-12)
