"""People seen from a moving robot: when the robot counts as moved, the map from a bag
topic, one-leg confirmation from consistent motion, a miss on a moving robot, and the real
lobby recording end to end."""

from __future__ import annotations

import math
import sys
from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from laserpeople.background.bag_map import (
    check_map_frame,
    load_map,
    occupancy_grid_map,
    read_bag_map,
    split_bag_spec,
    world_frame_with_map,
)
from laserpeople.background.occupancy import MapFileError
from laserpeople.pipeline import build
from laserpeople.scan import Pose2D
from laserpeople.tracking.person_tracks import (
    LegObservation,
    PersonTracker,
    PersonTrackParams,
    moves_consistently,
)
from laserpeople.tracking.robot_motion import MotionWatch


def grid_msg(data: list[int], width: int, height: int, yaw: float = 0.0) -> SimpleNamespace:
    q = SimpleNamespace(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2))
    origin = SimpleNamespace(position=SimpleNamespace(x=-1.0, y=2.0, z=0.0), orientation=q)
    info = SimpleNamespace(width=width, height=height, resolution=0.5, origin=origin)
    return SimpleNamespace(info=info, data=np.array(data, dtype=np.int8))


def test_occupancy_grid_message_rows_flip_and_threshold() -> None:
    # 3 wide, 2 high; data row 0 is the origin's row (lowest y): cells (0,0)=100, (2,0)=65,
    # (1,1)=64 (below occupied_thresh 65), (0,1) = -1 unknown
    m = occupancy_grid_map(grid_msg([100, 0, 65, -1, 64, 0], 3, 2), "x.bag:/map")
    assert m.occupied.tolist() == [[False, False, False], [True, False, True]]
    assert m.resolution == pytest.approx(0.5)
    assert m.origin == pytest.approx((-1.0, 2.0, 0.0))
    # the world point in cell (0, 0) (x -1..-0.5, y 2..2.5) is an obstacle, (1, 1) is not
    assert m.contains_obstacle(np.array([[-0.75, 2.25], [-0.25, 2.75]])).tolist() == [
        True,
        False,
    ]
    rotated = occupancy_grid_map(grid_msg([0] * 6, 3, 2, yaw=0.3))
    assert rotated.origin[2] == pytest.approx(0.3)


def test_occupancy_grid_message_that_does_not_fit_is_refused() -> None:
    with pytest.raises(MapFileError, match="3 x 2 cells but holds 5"):
        occupancy_grid_map(grid_msg([0] * 5, 3, 2), "x.bag:/map")


def test_motion_watch() -> None:
    watch = MotionWatch()
    assert not watch(Pose2D(1.0, 1.0, 0.0))
    assert not watch(None)
    assert not watch(Pose2D(1.04, 1.0, 0.019))  # 0.04 m, 0.019 rad: within 0.05 m, 0.02 rad
    assert watch(Pose2D(1.0, 1.0, -0.021))  # turned 0.021 rad
    assert watch(Pose2D(1.0, 1.0, 0.0))  # for good


def test_a_map_in_another_frame_than_the_poses_is_refused() -> None:
    msg = grid_msg([0] * 6, 3, 2)
    msg.header = SimpleNamespace(frame_id="/map")
    grid = occupancy_grid_map(msg, "x.bag:/map")
    assert grid.frame == "map"
    with pytest.raises(MapFileError, match="in frame 'map', but the scans' poses are in 'odom'"):
        check_map_frame(grid, "odom")
    check_map_frame(grid, "map")
    check_map_frame(grid, "/map")
    check_map_frame(grid, None)  # no poses, or a recording that does not say
    check_map_frame(occupancy_grid_map(grid_msg([0] * 6, 3, 2)), "odom")  # no frame given


def test_map_spec_tells_bag_topics_from_yaml() -> None:
    assert split_bag_spec("run.bag:/map") == (Path("run.bag"), "/map")
    assert split_bag_spec("maps/office.yaml") is None
    assert split_bag_spec("C:/maps/office.yaml") is None


def test_map_from_the_lobby_recording(shared_data: Path) -> None:
    bag = shared_data / "leg_tracker_benchmarks" / "general_tracking_moving_1_first.bag"
    grid = read_bag_map(bag, "/map")
    assert grid.frame == "map"
    assert grid.occupied.shape == (1984, 1984)
    assert grid.resolution == pytest.approx(0.05)
    assert int(grid.occupied.sum()) == 1194
    with pytest.raises(MapFileError, match="no topic '/nomap'"):
        read_bag_map(bag, "/nomap")
    assert load_map(f"{bag}:/map") is load_map(f"{bag}:/map")  # one copy for a run's stages
    # a live run takes the map's frame unless told another, which is refused
    assert world_frame_with_map(f"{bag}:/map", None) == "map"
    assert world_frame_with_map(f"{bag}:/map", "map") == "map"
    assert world_frame_with_map(None, "odom") == "odom"
    with pytest.raises(MapFileError, match="in frame 'map', but the scans' poses are in 'odom'"):
        world_frame_with_map(f"{bag}:/map", "odom")
    # the bag's /tf has no map -> odom: tracking in odom with that map is refused up front
    with pytest.raises(MapFileError, match="poses are in 'odom'"):
        build(bag, map_path=f"{bag}:/map")
    with pytest.raises(MapFileError, match="not nav_msgs/msg/OccupancyGrid"):
        read_bag_map(bag, "/scan")


# ------------------------------------------------------------------ confirmation rule


P = PersonTrackParams()


def test_moves_consistently_by_hand() -> None:
    # 0.3 m in 0.5 s (0.6 m/s >= 0.4), straight: consistent
    assert moves_consistently([(0.0, 0.0, 0.0), (0.25, 0.15, 0.0), (0.5, 0.3, 0.0)], P)
    # spans 0.49 s < moving_time 0.5 s: not yet
    assert not moves_consistently([(0.01, 0.0, 0.0), (0.5, 0.3, 0.0)], P)
    # 0.175 m in 0.5 s = 0.35 m/s < 0.4
    assert not moves_consistently([(0.0, 0.0, 0.0), (0.5, 0.175, 0.0)], P)
    # zigzag: net 0.3 m, path 2 * hypot(0.15, 0.3) = 0.671 m; 0.3 / 0.671 = 0.447 < 0.6
    zigzag = [(0.0, 0.0, 0.0), (0.25, 0.15, 0.3), (0.5, 0.3, 0.0)]
    assert not moves_consistently(zigzag, P)
    assert moves_consistently(zigzag, replace(P, moving_straightness=0.4))
    # the window starts at the last position at least moving_time before the newest
    old = [(0.0, 5.0, 5.0), (0.2, 0.0, 0.0), (0.7, 0.3, 0.0)]
    assert moves_consistently(old, P)  # from t = 0.2: 0.3 m in 0.5 s


def test_a_young_leg_track_is_judged_over_its_whole_path() -> None:
    """A leg track younger than moving_time (its whole path is 0.26 s) is judged over that
    path once it has moving_min_detections (3) detections, and only when ``young`` (its
    place not static for long): 0.2 m in 0.26 s = 0.77 m/s >= 0.4, straight."""
    path = [(0.0, 0.0, 0.0), (0.13, 0.1, 0.0), (0.26, 0.2, 0.0)]
    assert moves_consistently(path, P, young=True)
    assert not moves_consistently(path, P)  # an old place: the full 0.5 s as before
    assert not moves_consistently(path[:2], P, young=True)  # two detections: not yet
    assert not moves_consistently(path, replace(P, moving_min_detections=4), young=True)
    assert not moves_consistently(path, replace(P, moving_min_detections=0), young=True)
    # 0.1 m in 0.26 s = 0.38 m/s < 0.4: too slow even when young
    slow = [(0.0, 0.0, 0.0), (0.13, 0.05, 0.0), (0.26, 0.1, 0.0)]
    assert not moves_consistently(slow, P, young=True)
    # zigzag: net 0.2 m, path 2 * hypot(0.1, 0.2) = 0.447 m; 0.2 / 0.447 = 0.447 < 0.6
    zigzag = [(0.0, 0.0, 0.0), (0.13, 0.1, 0.2), (0.26, 0.2, 0.0)]
    assert not moves_consistently(zigzag, P, young=True)


def one_leg(x: float, y: float, detected: bool = True) -> dict[int, LegObservation]:
    return {
        7: LegObservation(
            7,
            np.array([x, y]),
            detected,
            0.0 if detected else 0.1,
            0 if detected else -1,
            False,
            score=0.8 if detected else math.nan,
        )
    }


def run_one_leg(params: PersonTrackParams, speed: float, scans: int) -> list[int]:
    """Confirmed people per scan of one leg walking along x at ``speed`` (10 Hz)."""
    tracker = PersonTracker(params)
    tracker.moving = True  # (one-leg births on a moving robot in the world frame only)
    out = []
    for k in range(scans):
        out.append(len(tracker.update(one_leg(speed * 0.1 * k, 0.0), 0.1 * k, 1.0)))
    return out


def test_one_walking_leg_is_confirmed_only_with_one_leg_birth() -> None:
    walking = run_one_leg(P, 1.0, 15)
    # a young track judged over its whole path from its third detection (scan 2, 0.2 m from
    # its first: young_credit; evidence as both legs for scans 0, 1 and 2, 4.83 >= 4):
    # reported from scan 2 on
    assert walking.index(1) == 2
    assert all(walking[2:])
    # without the credit: +1.61 per scan from 0 at birth, scans 2, 3, 4 reach 4.83
    assert run_one_leg(replace(P, young_credit=False), 1.0, 15).index(1) == 4
    # judged only over moving_time (0.5 s): moving from scan 5, reported from scan 7
    assert run_one_leg(replace(P, moving_min_detections=0), 1.0, 15).index(1) == 7
    assert run_one_leg(replace(P, one_leg_birth=False), 1.0, 15) == [0] * 15
    static_laser = PersonTracker(P)  # moving False: as before issue 29
    assert [len(static_laser.update(one_leg(0.1 * k, 0.0), 0.1 * k, 1.0)) for k in range(15)] == [
        0
    ] * 15
    # a leg that stands still (a chair post) or creeps at 0.2 m/s is never confirmed
    assert run_one_leg(P, 0.0, 30) == [0] * 30
    assert run_one_leg(P, 0.2, 30) == [0] * 30


def scores_of_one_leg(
    params: PersonTrackParams, xs: list[float | None], dt: float = 0.1, static: float = 0.0
) -> list[float]:
    """Existence score per scan (NaN before the birth) of the one person a single leg gives
    birth to, the leg at x = ``xs[k]`` (y = 0) in scan k, ``dt`` apart (None: not
    detected), every place static for ``static`` seconds."""
    tracker = PersonTracker(params, StaticFor(static))
    tracker.moving = True
    out = []
    for k, x in enumerate(xs):
        last = next((v for v in reversed(xs[: k + 1]) if v is not None), 0.0)
        tracker.update(one_leg(last, 0.0, detected=x is not None), dt * k, 1.0)
        people = list(tracker.persons.values())
        assert len(people) <= 1
        out.append(people[0].llr if people else math.nan)
    return out


def test_a_young_walker_is_credited_both_legs_for_its_earlier_scans() -> None:
    both = math.log(0.5 / 0.1)  # p_two / q_two; one leg: log(0.4 / 0.4) = 0
    # 1 m/s at 10 Hz: one leg at birth (scan 0) and scan 1; at scan 2 the young path (3
    # detections, 0.2 s) is first seen moving and is 0.2 m = moving_speed * moving_time
    # from its start: both legs for scans 0, 1 and 2; later scans add one step each
    llr = scores_of_one_leg(P, [0.0, 0.1, 0.2, 0.3])
    assert llr[:2] == pytest.approx([0.0, 0.0], abs=1e-12)
    assert llr[2] == pytest.approx(3 * both, abs=1e-9)
    assert llr[3] == pytest.approx(4 * both, abs=1e-9)
    # near misses: 0.18 m by scan 2 (< 0.2 m, though 0.9 m/s moves consistently): the
    # step of scan 2 only, as without the credit
    late = scores_of_one_leg(P, [0.0, 0.09, 0.18, 0.27])
    assert late[2] == pytest.approx(both, abs=1e-9)
    # the credit is given when first seen moving only: 0.27 m by scan 3 adds one step
    assert late[3] == pytest.approx(2 * both, abs=1e-9)
    assert scores_of_one_leg(replace(P, young_credit=False), [0.0, 0.1, 0.2])[2] == (
        pytest.approx(both, abs=1e-9)
    )
    # the distance is moving_speed * moving_time: 0.6 m/s * 0.5 s = 0.3 m > 0.2 m
    fast = replace(P, moving_speed=0.6)
    assert scores_of_one_leg(fast, [0.0, 0.1, 0.2])[2] == pytest.approx(both, abs=1e-9)
    assert scores_of_one_leg(fast, [0.0, 0.15, 0.3])[2] == pytest.approx(3 * both, abs=1e-9)
    # a miss at scan 1 (none: log(0.1 / 0.5)) is not credited: scans 0 and 2 counted as one
    # leg, scan 3 (the third detection, 0.3 s) is the first seen moving: +3 steps
    none = math.log(0.1 / 0.5)
    llr = scores_of_one_leg(P, [0.0, None, 0.2, 0.3])
    assert llr[1] == pytest.approx(none, abs=1e-9)
    assert llr[3] == pytest.approx(none + 3 * both, abs=1e-9)
    # only young paths: judged over moving_time (moving_min_detections 0) the first moving
    # scan is scan 5 (0.5 s) and adds one step, whatever the scans before it counted
    mature = scores_of_one_leg(replace(P, moving_min_detections=0), [0.1 * k for k in range(6)])
    assert mature[4] == pytest.approx(0.0, abs=1e-12)
    assert mature[5] == pytest.approx(both, abs=1e-9)
    # only where the leg has just come: its place static for at most the time since the
    # detection before (0.1 s); a leg track sliding along a wall stands where the grid has
    # seen returns for longer (0.15 s: not even since the path's first detection, 0.2 s)
    assert scores_of_one_leg(P, [0.0, 0.1, 0.2], static=0.1)[2] == pytest.approx(3 * both, abs=1e-9)
    assert scores_of_one_leg(P, [0.0, 0.1, 0.2], static=0.15)[2] == pytest.approx(both, abs=1e-9)
    # misses are not one-leg scans: a pair (legs 7 and 9, 0.3 m apart) gives birth at scan 0
    # (both legs: +1.61); scan 1 sees leg 7 only (one leg: 0), scan 2 nothing (none), scan 3
    # leg 7 again, whose path (scans 0, 1, 3: 0.3 m in 0.3 s) is first seen moving: credit
    # for scan 1 only (1 of its 2 earlier detections), not for the miss
    tracker = PersonTracker(P)
    tracker.moving = True
    for k, seen in enumerate([(7, 9), (7,), (), (7,)]):
        legs = {
            tid: replace(
                one_leg(0.1 * k if tid == 7 else 0.0, 0.0 if tid == 7 else 0.3, tid in seen)[7],
                track_id=tid,
            )
            for tid in (7, 9)
        }
        tracker.update(legs, 0.1 * k, 1.0)
    (person,) = tracker.persons.values()
    assert person.llr == pytest.approx(both + none + 2 * both, abs=1e-9)
    # at most the young path's earlier detections: a candidate that stood on leg track 7 for
    # scans 0-3 (one leg: 0 each) takes leg track 8 from scan 4, which walks at 1 m/s; at
    # scan 6 its path (3 detections, 0.2 m) is first seen moving: +3 steps, not 1 + 6
    tracker = PersonTracker(P)
    tracker.moving = True
    for k in range(7):
        leg = one_leg(0.0 if k < 4 else 0.1 * (k - 4), 0.0)[7]
        tid = 7 if k < 4 else 8
        tracker.update({tid: replace(leg, track_id=tid)}, 0.1 * k, 1.0)
        (person,) = tracker.persons.values()
        assert person.members == [tid]
        assert person.llr == pytest.approx(0.0 if k < 6 else 3 * both, abs=1e-9)


def test_a_miss_on_a_moving_robot_lowers_the_score_by_none() -> None:
    tracker = PersonTracker(P)
    tracker.moving = True
    k = 0
    for k in range(10):  # walks along x at 1 m/s, 1.5..2.4 m ahead: confirmed
        tracker.update(one_leg(1.5 + 0.1 * k, 0.0), 0.1 * k, 1.0)
    person = next(iter(tracker.persons.values()))
    assert person.confirmed
    before = person.llr
    tracker.update(one_leg(2.4, 0.0, detected=False), 0.1 * (k + 1), 1.0)
    # no member leg detected: evidence "none", log(p_none / q_none) (not neutral, not one leg)
    assert person.llr - before == pytest.approx(math.log(0.1 / 0.5))


class StaticFor:
    """A static world model whose every place has been static for ``seconds``."""

    consumes = frozenset({"points"})

    def __init__(self, seconds: float) -> None:
        self.seconds = seconds

    def __call__(self, frame: Any) -> Any:
        return frame

    def static_time(self, positions: np.ndarray) -> np.ndarray:
        return np.full(positions.shape[0], self.seconds)


def miss_after_zigzag(
    params: PersonTrackParams,
    reach: float,
    dt: float,
    static: float | None = None,
    start: float = 0.0,
) -> float:
    """Existence change of a one-leg candidate for a scan without its leg, after the leg
    zigzagged (never moving consistently: straightness 0.16) from (0, 0.3) to (reach, 0.3)
    in 10 scans ``dt`` apart from ``start`` [s] (every place static for ``static`` seconds;
    None: no model)."""
    tracker = PersonTracker(params, None if static is None else StaticFor(static))
    tracker.moving = True
    for k in range(11):
        tracker.update(one_leg(reach * k / 10, 0.3 * (-1) ** k), start + dt * k, 1.0)
    person = next(iter(tracker.persons.values()))
    assert not person.confirmed and person.llr == pytest.approx(0.0, abs=1e-12)  # one leg: +0
    tracker.update(one_leg(reach, 0.3, detected=False), start + dt * 11, 1.0)
    return person.llr


def test_a_candidate_whose_leg_walked_loses_nothing_for_a_miss() -> None:
    # 0.7 m from its first detection in 1.0 s (0.7 m/s >= moving_speed 0.4): walked, a miss
    # costs walked_miss (0.0) instead of log(p_none / q_none) = log(0.1 / 0.5) = -1.609
    assert miss_after_zigzag(P, 0.7, 0.1) == pytest.approx(0.0, abs=1e-9)
    assert miss_after_zigzag(replace(P, walked_miss=-0.5), 0.7, 0.1) == pytest.approx(-0.5)
    # near misses: 0.65 m (< walked_distance 0.7), or 0.7 m by the miss at 2.2 s (0.32 m/s)
    assert miss_after_zigzag(P, 0.65, 0.1) == pytest.approx(math.log(0.1 / 0.5))
    assert miss_after_zigzag(P, 0.7, 0.2) == pytest.approx(math.log(0.1 / 0.5))
    # the speed is over the time since the first detection, not since time 0: first seen at
    # 100 s, 0.7 m by the miss at 101.1 s is 0.64 m/s (walked); 0.7 / 101.1 s would not be
    assert miss_after_zigzag(P, 0.7, 0.1, start=100.0) == pytest.approx(0.0, abs=1e-9)
    # with moving_speed 0 any 0.7 m has walked, however slowly (0.7 m in 2.2 s)
    assert miss_after_zigzag(replace(P, moving_speed=0.0), 0.7, 0.2) == pytest.approx(0.0, abs=1e-9)
    # its place static for at most arrival_slack (2 s): walked; longer (a leg track that
    # swapped onto a chair post after following a passer-by): the full miss
    assert miss_after_zigzag(P, 0.7, 0.1, static=2.0) == pytest.approx(0.0, abs=1e-9)
    assert miss_after_zigzag(P, 0.7, 0.1, static=2.1) == pytest.approx(math.log(0.1 / 0.5))
    # a static laser (moving False) keeps the miss
    tracker = PersonTracker(P)
    tracker.update(one_leg(0.0, 0.0), 0.0, 1.0)
    assert not tracker.persons  # (no one-leg birth there at all)


# ------------------------------------------------------------------ real recording


def test_lobby_recording_recall(shared_data: Path) -> None:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from laserpeople.tracking.legs import LegTrackerParams
    from moving_people import read_labels, score_moving, track_bag

    base = shared_data / "leg_tracker_benchmarks" / "general_tracking_moving_1_first"
    tracks, _ = track_bag(base.with_suffix(".bag"), LegTrackerParams())
    score = score_moving(tracks, read_labels(Path(f"{base}.people.csv")))
    # before issue 29 the default found 1 of the 57 labels (recall 0.018); today 17 of 57,
    # MOTA -0.123 with 24 false positives (most of them real people the labels leave out):
    # a tracker without people, or one that follows every leg, misses these bounds
    assert score.labels == 57
    assert score.recall >= 0.2
    assert score.mota >= -0.3
    assert score.false_positives <= 30
    assert score.ids >= 3
    assert score.id_switches <= 2


def benchmarks_module() -> Any:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    import moving_people

    return moving_people


def test_detection_ceiling_by_hand() -> None:
    mp = benchmarks_module()
    labels = {
        1: {7: np.array([3.0, 0.0]), 8: np.array([5.0, 1.0])},
        2: {7: np.array([2.0, 0.0])},
        3: {8: np.array([0.0, -1.0])},
    }
    legs = {
        # label 7 detected 0.4 m off (<= 0.5), label 8 0.6 m off (not)
        1: np.array([[3.4, 0.0], [5.6, 1.0], [0.0, -1.5]]),
        # nothing near label 7
        2: np.array([[0.5, -1.5]]),
        # 0.5 m from the label: detected
        3: np.array([[0.0, -1.5]]),
    }
    c = mp.detection_ceiling(legs, labels)
    assert (c.labels, c.detected, c.scans) == (4, 2, 3)


def test_companion_mask_and_detected_labels_by_hand() -> None:
    from laserpeople.tracks import Track, Tracks

    mp = benchmarks_module()

    def person(tid: int, x: float, y: float) -> Track:
        return Track(tid, "person", np.array([x, y]), np.zeros(2), np.eye(2) * 0.01)

    def frame(scan: int, *rows: Track) -> Tracks:
        return Tracks(0.1 * scan, scan, rows, "sensor")

    labels = {1: {7: np.array([3.0, 0.0])}, 2: {7: np.array([2.5, 0.0])}}
    legs = {
        1: np.array([[3.2, 0.0], [-0.5, -1.5]]),  # label 7 and a leg beside the robot
        2: np.array([[2.5, 0.6]]),  # label 7 only 0.6 m off: not detected
    }
    tracks = [
        frame(0, person(4, 0.0, 0.0)),  # unlabelled scan: not asked
        # P1 beside the robot, near the unlabelled leg; P2 beside too but never near a
        # leg there; P3 near the leg, then near the label on scan 2; P5 on the label
        frame(1, person(1, -0.6, -1.4), person(2, 0.7, -2.6), person(3, -0.4, -1.6)),
        frame(2, person(1, -0.2, -1.0), person(3, 2.2, 0.0), person(5, 2.5, 0.1)),
    ]
    assert mp.companion_tracks(tracks, legs, labels) == {1}
    assert [len(t.tracks) for t in mp.without_tracks(tracks, {1})] == [1, 2, 2]
    detected = mp.detected_labels(legs, labels)
    assert list(detected) == [1] and list(detected[1]) == [7]


def test_lobby_recording_ceiling(shared_data: Path) -> None:
    from laserpeople.tracking.legs import LegTrackerParams

    mp = benchmarks_module()
    base = shared_data / "leg_tracker_benchmarks" / "general_tracking_moving_1_first"
    bag, labels = base.with_suffix(".bag"), mp.read_labels(Path(f"{base}.people.csv"))
    _, legs, _ = mp.track_bag_with_legs(bag, LegTrackerParams())
    c = mp.detection_ceiling(legs, labels)
    assert c.labels == 57 and c.scans == 43
    assert 40 <= c.detected <= 46  # measured 43
    o, seen = mp.oracle_bound(bag, labels)
    # measured from the raw returns: 38 unlabelled walkers on the labelled scans, beside
    # the robot on 23 of the 43: reporting every label and every walker gives MOTA 0.333,
    # at recall 0.70 0.035; the goal (0.50 at recall 0.70) allows 11 false positives
    assert (o.labels, o.shown, o.scans, len(seen)) == (57, 57, 43, 43)
    assert 20 <= o.beside <= 26
    assert 33 <= o.unlabelled <= 43
    assert o.mota < 0.45
    assert o.mota_at_recall(0.7) < 0.2
    assert o.max_false_positives(0.7, 0.5) == 11


def test_lobby_recording_diagnosis_and_masked_score(shared_data: Path) -> None:
    from laserpeople.tracking.legs import LegTrackerParams

    mp = benchmarks_module()
    base = shared_data / "leg_tracker_benchmarks" / "general_tracking_moving_1_first"
    bag, labels = base.with_suffix(".bag"), mp.read_labels(Path(f"{base}.people.csv"))
    rows = mp.diagnose(bag, LegTrackerParams(), labels)
    stages = [r.stage for r in rows]
    assert set(stages) <= set(mp.STAGES)
    # measured: 43 detected labels; 17 tracked, 10 without a leg track (first detections,
    # legs seen in turn), 16 candidates not yet confirmed, none lost elsewhere
    assert 40 <= len(rows) <= 46
    assert 12 <= stages.count("tracked") <= 22
    assert 12 <= stages.count("candidate not confirmed") <= 20
    assert 6 <= stages.count("no leg track") <= 14
    assert stages.count("left out as static") + stages.count("reported, too far") <= 2
    tracks, legs, _ = mp.track_bag_with_legs(bag, LegTrackerParams())
    masked = mp.companion_tracks(tracks, legs, labels)
    plain = mp.score_moving(tracks, labels)
    score = mp.score_moving(mp.without_tracks(tracks, masked), labels)
    # measured: the companion's track P0 masked, false positives 24 -> 11, MOTA -0.123 ->
    # 0.105, the matches unchanged; detected labels: recall 16 of 43
    assert len(masked) >= 1
    assert score.matches == plain.matches
    assert score.false_positives <= plain.false_positives - 8
    detected = mp.score_moving(tracks, mp.detected_labels(legs, labels))
    assert 40 <= detected.labels <= 46
    assert detected.recall == pytest.approx(detected.matches / detected.labels, abs=1e-12)
    assert 0.2 <= detected.recall <= 0.5


# ------------------------------------------------------------------ simulated family


def test_moving_robot_family_is_drawn_from_the_seed() -> None:
    from laserpeople.sim.scenarios import build_scene

    a = build_scene("moving-robot", seconds=10.0, seed=3)
    b = build_scene("moving-robot", seconds=10.0, seed=3)
    c = build_scene("moving-robot", seconds=10.0, seed=4)
    assert a.notes == b.notes and a.notes != c.notes
    assert a.robot is not None and a.notes["family"] == "moving-robot"
    # the module's draws: 1-3 walk towards the robot, 0-2 overtake it, 1-2 groups of 2-3
    # stand, 0-2 wander: 3 to 13 people, and the seed changes how many
    counts = [len(build_scene("moving-robot", seconds=10.0, seed=s).people) for s in range(8)]
    assert all(3 <= n <= 13 for n in counts), counts
    assert len(set(counts)) > 1, counts
    fov = a.sensors[0].laser_model.fov_deg
    assert fov == pytest.approx(270.0, abs=0.5)


SIM_SEED = 6
"""A tuning seed of the moving-robot family (0-9; 100-119 are held back)."""
SIM_MOTA, SIM_IDF1 = 0.58, 0.75
"""Measured 20 s of seed 6, people scored while the scanner sees them: MOTA 0.600, IDF1
0.767 (one_leg_birth false, the earlier default: 0.557, 0.735; a tracker that loses people
scores far lower)."""


def test_moving_robot_seed_end_to_end() -> None:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from laserpeople.detection.detector import AdaBoostLegDetector
    from laserpeople.evaluation.suite import SuiteScene, prepare, track_scene
    from people_suite import make_factory

    prepared = prepare(
        SuiteScene("moving-robot", "moving-robot", SIM_SEED, 20.0), AdaBoostLegDetector.default()
    )
    score, _ = track_scene(prepared, make_factory("leg-mht", None), "leg-mht")
    assert score.mota >= SIM_MOTA
    assert score.idf1 >= SIM_IDF1


def test_moving_robot_truth_counts_people_while_the_scanner_sees_them() -> None:
    """The family is scored as the lobby's labels: a person only while in view (the
    randomised family keeps its 2 s window)."""
    from laserpeople.sim.scenarios import build_scene

    scene = build_scene("moving-robot", seconds=5.0, seed=3)
    assert scene.truth_in_view and scene.truth_seen_within is None
    other = build_scene("randomised", seconds=5.0, seed=3)
    assert not other.truth_in_view and other.truth_seen_within == pytest.approx(2.0, abs=1e-12)
