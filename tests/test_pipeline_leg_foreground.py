"""The foreground of moving lasers: the points near leg detections
(``pipeline/leg_foreground.py``), on hand-made frames, and when ``--background auto`` uses it.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from laserpeople.frame import Frame
from laserpeople.pipeline import AutoBackground, Fuse, background_of, observe_stages_for
from laserpeople.pipeline.background import StaticWorldParams, describe_foreground
from laserpeople.pipeline.leg_foreground import (
    LegForeground,
    LegForegroundParams,
    near_legs,
    needs_steady_points,
    stage_leg_tracker,
)
from laserpeople.scan import PointSet, Pose2D, Scan
from laserpeople.tracks import Detections


def _legs(positions: list[tuple[float, float]], frame: str = "sensor") -> Detections:
    pos = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
    n = len(pos)
    return Detections(0.0, 0, pos, np.tile(np.eye(2) * 0.01, (n, 1, 1)), np.ones(n), frame)  # type: ignore[arg-type]


def _points_frame(
    points: list[tuple[float, float]],
    stamp: float = 0.0,
    legs: list[tuple[float, float]] | None = None,
    foreground: list[bool] | None = None,
) -> Frame:
    pts = np.asarray(points, dtype=np.float64)
    scan = Scan(stamp, 0.0, 0.01, np.full(4, 2.0), sensor="l")
    return Frame(
        0,
        stamp,
        (scan,),
        "l",
        points=PointSet(stamp, pts, np.zeros(len(pts)), np.arange(len(pts)), ("l",), "sensor"),
        foreground=None if foreground is None else np.asarray(foreground),
        legs=None if legs is None else _legs(legs),
    )


# ------------------------------------------------------------------ the rule by hand


def test_near_legs_by_hand() -> None:
    points = np.array([[0.0, 0.0], [0.3, 0.0], [0.0, 0.35], [0.36, 0.0], [2.0, 2.0], [2.1, 2.2]])
    # |(2.1, 2.2) - (2, 2)| = sqrt(0.05) = 0.224 <= 0.35; (0, 0.35) lies on the circle
    keep = near_legs(points, np.array([[0.0, 0.0], [2.0, 2.0]]), 0.35)
    assert keep.tolist() == [True, True, True, False, True, True]
    assert near_legs(points, np.empty((0, 2)), 0.35).tolist() == [False] * 6
    assert near_legs(np.empty((0, 2)), np.zeros((1, 2)), 0.35).shape == (0,)


def test_stage_keeps_foreground_points_near_the_frames_legs() -> None:
    stage = LegForeground(LegForegroundParams(radius=0.35, memory=0.0))
    frame = _points_frame(
        [(1.0, 0.0), (1.2, 0.1), (1.0, 1.0), (3.0, 0.0), (1.1, -0.1)],
        legs=[(1.05, 0.0)],
        foreground=[True, True, True, True, False],  # the last is background
    )
    out = stage(frame)
    assert out.foreground is not None
    assert out.foreground.tolist() == [True, True, False, False, False]
    assert stage.points_in == 4 and stage.points_kept == 2 and stage.kept_share == 0.5
    assert stage.detected == 0  # the frame held its legs
    # without a foreground every point counts as foreground
    again = stage(replace(frame, foreground=None))
    assert again.foreground is not None
    assert again.foreground.tolist() == [True, True, False, False, True]


def test_only_legs_scoring_above_min_score_keep_points() -> None:
    stage = LegForeground(LegForegroundParams(radius=0.2, memory=0.0, min_score=0.4))
    frame = _points_frame([(1.0, 0.0), (2.0, 0.0)], legs=[(1.0, 0.0), (2.0, 0.0)])
    assert frame.legs is not None
    scored = replace(frame, legs=replace(frame.legs, scores=np.array([0.3, 0.5])))
    out = stage(scored)
    assert out.foreground is not None and out.foreground.tolist() == [False, True]


def test_held_legs_keep_their_points_for_memory_seconds() -> None:
    """A leg missed by the detector keeps its points for ``memory`` s at its last position;
    one detected again moves (its old place is not kept)."""
    stage = LegForeground(LegForegroundParams(radius=0.3, memory=0.5))
    points = [(0.0, 0.0), (2.0, 0.0), (2.25, 0.0)]
    out = stage(_points_frame(points, 0.0, legs=[(0.0, 0.0), (2.0, 0.0)]))
    assert out.foreground is not None and out.foreground.tolist() == [True, True, True]
    # 0.4 s later only the second leg is seen, moved 0.25 m: the first is held, and the
    # second's old place (2.0, 0) is replaced by its new one (2.25, 0)
    out = stage(_points_frame([(0.0, 0.0), (1.8, 0.0), (2.5, 0.0)], 0.4, legs=[(2.25, 0.0)]))
    assert out.foreground is not None and out.foreground.tolist() == [True, False, True]
    # 0.6 s after it was last seen the first leg is forgotten
    out = stage(_points_frame([(0.0, 0.0), (2.3, 0.0)], 0.6, legs=[]))
    assert out.foreground is not None and out.foreground.tolist() == [False, True]
    # without memory only the frame's own legs count
    plain = LegForeground(LegForegroundParams(radius=0.3, memory=0.0))
    plain(_points_frame(points, 0.0, legs=[(0.0, 0.0)]))
    out = plain(_points_frame(points, 0.1, legs=[]))
    assert out.foreground is not None and not out.foreground.any()


def test_legs_of_people_are_held_for_person_memory() -> None:
    """A leg flagged as a person's is held ``person_memory`` s (inclusive), the others
    ``memory`` s; a person's leg seen again is replaced by its new place."""
    stage = LegForeground(LegForegroundParams(radius=0.3, memory=0.2, person_memory=1.0))
    legs = np.array([[0.0, 0.0], [2.0, 0.0]])
    held = stage.remembered(0.0, legs, np.array([True, False]))
    assert held.tolist() == [[0.0, 0.0], [2.0, 0.0]]
    # 0.5 s later nothing is detected: the person's leg (age 0.5 <= 1.0) is held, the
    # other (0.5 > 0.2) is not
    assert stage.remembered(0.5, np.empty((0, 2))).tolist() == [[0.0, 0.0]]
    # at 1.0 s exactly it is still held; at 1.1 s it is gone
    assert stage.remembered(1.0, np.empty((0, 2))).tolist() == [[0.0, 0.0]]
    assert stage.remembered(1.1, np.empty((0, 2))).shape == (0, 2)
    # seen again 0.25 m away (within radius): the old place is dropped at once
    stage.remembered(2.0, np.array([[0.0, 0.0]]), np.array([True]))
    assert stage.remembered(2.1, np.array([[0.25, 0.0]]), np.array([False])).tolist() == [
        [0.25, 0.0]
    ]
    # no longer a person's leg: held memory = 0.2 s only (0.35 - 0.1 = 0.25 > 0.2)
    assert stage.remembered(2.35, np.empty((0, 2))).shape == (0, 2)
    # a person_memory below memory holds for memory
    short = LegForeground(LegForegroundParams(radius=0.3, memory=0.5, person_memory=0.1))
    short.remembered(0.0, legs[:1], np.array([True]))
    assert short.remembered(0.4, np.empty((0, 2))).tolist() == [[0.0, 0.0]]


def _walking_pair(stage: LegForeground, scans: int) -> list[list[bool] | None]:
    """Feed ``stage`` two legs of a person walking at 0.5 m/s along x (their steps 0.1 m
    apart) and a lone still leg at (3, 2), 10 scans per second; each scan's person flags."""
    flags: list[list[bool] | None] = []
    for k in range(scans):
        t = 0.1 * k
        swing = 0.1 * np.sin(2 * np.pi * t)
        x = 1.0 + 0.5 * t
        frame = _points_frame([(x + swing, 0.15), (x - swing, -0.15), (3.0, 2.0)], t,
                              legs=[(x + swing, 0.15), (x - swing, -0.15), (3.0, 2.0)])  # fmt: skip
        assert frame.legs is not None
        legs = replace(frame.legs, stamp=t, scan_index=k)
        got = stage.people_flags(replace(frame, index=k, legs=legs), legs, legs.positions)
        flags.append(None if got is None else got.tolist())
    return flags


def test_the_leg_mht_tells_which_legs_are_a_persons() -> None:
    """The leg MHT run on the detections confirms the walking pair as a person within a
    second; the lone still leg never is. With person_memory 0 no MHT runs."""
    stage = LegForeground(LegForegroundParams(steady_person_memory=1.0), steady=True)
    flags = _walking_pair(stage, 20)
    assert flags[0] == [False, False, False]
    assert all(f == [True, True, False] for f in flags[10:]), flags
    off = LegForeground(LegForegroundParams(person_memory=0.0, steady_person_memory=1.0))
    assert _walking_pair(off, 3) == [None, None, None]
    assert off.person_memory == 0.0 and stage.person_memory == 1.0


def test_scans_the_leg_mht_could_not_process_in_full_are_said() -> None:
    model = _auto("moving")
    model.static = replace(
        model.static,
        leg_foreground=LegForegroundParams(memory=0.0, person_memory=1.0),
    )
    for i in range(25):
        model(_frame(_rotating_scan(i, 0)))
    for i in range(25, 40):
        model(_frame(_rotating_scan(i, 3 * (i - 24))))
    assert model.legs is not None and model.legs.degraded_scans == 0
    assert "could not process" not in model.describe_foreground()
    model.legs._tracker.tracker.guard.degraded(7)  # as the MHT does over max_cluster_size
    assert model.legs.degraded_scans == 1
    assert "could not process 1 scans in full" in model.describe_foreground()


def test_the_hold_is_described() -> None:
    params = LegForegroundParams(memory=0.0, steady_memory=0.0, person_memory=0.0,
                                 steady_person_memory=1.0)  # fmt: skip
    assert LegForeground(params).describe_hold() == ""
    said = LegForeground(params, steady=True).describe_hold()
    assert said == ", missed legs of the people a leg MHT tracks held 1 s"
    both = LegForeground(replace(params, memory=0.2, person_memory=1.0)).describe_hold()
    assert both == ", missed legs held 0.2 s (1 s those of the people a leg MHT tracks)"
    same = LegForeground(replace(params, memory=0.5, person_memory=0.5)).describe_hold()
    assert same == ", missed legs held 0.5 s"


def test_a_stamp_going_back_forgets_the_held_legs() -> None:
    stage = LegForeground(LegForegroundParams(radius=0.3, memory=0.5))
    stage(_points_frame([(0.0, 0.0)], 5.0, legs=[(0.0, 0.0)]))
    out = stage(_points_frame([(0.0, 0.0)], 1.0, legs=[]))
    assert out.foreground is not None and out.foreground.tolist() == [False]


class _FixedDetector:
    """A leg detector that finds one leg (or more) at fixed sensor-frame positions in every
    scan."""

    def __init__(self, where: tuple[float, float], *more: tuple[float, float]) -> None:
        self.where = where
        self.more = more
        self.calls = 0

    def detect(self, scan: Scan) -> Detections:
        self.calls += 1
        found = _legs([self.where, *self.more])
        return replace(found, stamp=scan.stamp, scan_index=scan.index, sensor_pose=scan.pose)


def test_stage_detects_legs_itself_when_the_frame_has_none() -> None:
    detector = _FixedDetector((1.0, 0.0))
    stage = LegForeground(LegForegroundParams(radius=0.2, memory=0.0), detector)
    out = stage(_points_frame([(1.1, 0.0), (0.5, 0.0)]))
    assert out.foreground is not None and out.foreground.tolist() == [True, False]
    assert detector.calls == 1 and stage.detected == 1
    assert out.legs is None  # it fills only the foreground


def test_trackers_that_die_without_points_hold_legs_longer() -> None:
    from laserpeople.tracking import registry

    params = LegForegroundParams(memory=0.0, steady_memory=0.5)
    assert LegForeground(params).memory == 0.0
    assert LegForeground(params, steady=True).memory == 0.5
    steady = {name: needs_steady_points(registry.get(name).make()) for name in registry.TRACKERS}
    assert {n for n, s in steady.items() if s} == {"feet-pf", "upper-body-pf"}


def test_params_are_checked() -> None:
    with pytest.raises(ValueError, match="use must be one of"):
        LegForegroundParams(use="sometimes")
    with pytest.raises(ValueError, match="radius"):
        LegForegroundParams(radius=0.0)
    with pytest.raises(ValueError, match="memory"):
        LegForegroundParams(memory=-1.0)
    with pytest.raises(ValueError, match="steady_memory"):
        LegForegroundParams(steady_memory=float("inf"))
    with pytest.raises(ValueError, match="person_memory"):
        LegForegroundParams(person_memory=-0.1)
    with pytest.raises(ValueError, match="steady_person_memory"):
        LegForegroundParams(steady_person_memory=float("nan"))


# ------------------------------------------------------------------ when auto uses it


def _rotating_scan(index: int, turn: int, pose: Pose2D | None = None) -> Scan:
    """A room whose wall ranges change with the beam, turned by ``turn`` beams (a laser
    turning on the spot, as in test_track_foreground_e2e)."""
    ranges = 3.0 + 2.0 * np.abs(np.sin(np.arange(90) * np.pi / 30.0))
    return Scan(
        0.1 * index, -np.pi / 4, np.pi / 180, np.roll(ranges, turn), 0.1, 10.0,
        sensor="l", index=index, pose=pose,
    )  # fmt: skip


def _frame(scan: Scan) -> Frame:
    frame = "world" if scan.pose is not None else "sensor"
    return Fuse()(Frame(scan.index, scan.stamp, (scan,), "l", frame, scan.pose))


def _auto(use: str, where: tuple[float, float] = (3.0, 0.0)) -> AutoBackground:
    static = StaticWorldParams(leg_foreground=LegForegroundParams(use=use, memory=0.0))
    return AutoBackground(static=static, detector=_FixedDetector(where))


def _near(frame: Frame, where: tuple[float, float], radius: float = 0.35) -> np.ndarray:
    assert frame.points is not None
    return np.hypot(*(frame.points.points - np.asarray(where)).T) <= radius


def test_auto_without_poses_keeps_points_near_legs_once_the_laser_moves() -> None:
    """Sensor frame: while the laser stands the histogram's foreground; once it moves (the
    model is dropped) only the points near legs, and the user is told from which frame."""
    model = _auto("moving")
    for i in range(25):
        model(_frame(_rotating_scan(i, 0)))
    assert model.legs is None and "did not move" in describe_foreground(model)
    for i in range(25, 80):
        frame = _frame(_rotating_scan(i, 3 * (i - 24)))
        out = model(frame)
    assert model.chosen == "none" and model.legs_from == model.switched_at
    assert out.foreground is not None and out.foreground.any()
    np.testing.assert_array_equal(out.foreground, _near(frame, (3.0, 0.0)))
    said = model.describe_foreground()
    assert f"foreground from frame {model.switched_at}:" in said and "no poses" in said
    assert "every point" not in model.describe()


def test_auto_with_use_never_keeps_every_point_as_the_papers() -> None:
    model = _auto("never")
    for i in range(25):
        model(_frame(_rotating_scan(i, 0)))
    for i in range(25, 80):
        out = model(_frame(_rotating_scan(i, 3 * (i - 24))))
    assert model.chosen == "none" and model.legs is None
    assert out.foreground is not None and out.foreground.all()
    assert "the papers' setting" in model.describe_foreground()
    assert "every point is foreground" in model.describe()


def test_auto_with_poses_narrows_the_grid_once_the_laser_moves() -> None:
    """World frame: the grid's foreground (every point at first sight) narrowed to the
    points near legs from the frame the laser moved on (``moving``); ``no-poses`` leaves
    the grid's foreground as it is."""
    for use, narrowed in (("moving", True), ("no-poses", False)):
        model = _auto(use, where=(5.0, 0.0))  # beam 45 returns at 5 m straight ahead
        for i in range(6):
            pose = Pose2D(0.03 * i, 0.0, 0.0)
            out = model(_frame(_rotating_scan(i, 0, pose)))
        assert model.chosen == "occupancy" and model.switched_at == 2
        assert out.foreground is not None and out.points is not None
        legs_world = pose.transform_points(np.array([[5.0, 0.0]]))[0]
        if narrowed:
            assert model.legs_from == 2 and out.foreground.any()
            assert not (out.foreground & ~_near(out, tuple(legs_world))).any()
        else:
            assert model.legs is None
            assert (out.foreground & ~_near(out, tuple(legs_world))).any()


def test_auto_on_a_still_laser_narrows_only_with_always() -> None:
    for use, narrowed in (("moving", False), ("always", True)):
        model = _auto(use)
        for i in range(30):
            frame = _frame(_rotating_scan(i, 0))
            out = model(frame)
        assert model.chosen == "histogram"
        assert (model.legs is not None) == narrowed
        assert out.foreground is not None
        if narrowed:
            assert model.legs_from == 0 and "use = always" in model.describe_foreground()
            assert not (out.foreground & ~_near(frame, (3.0, 0.0))).any()


def test_observe_stages_hand_the_detector_to_auto() -> None:
    detector = _FixedDetector((1.0, 0.0))
    pre, _ = observe_stages_for(frozenset({"points", "foreground"}), detector)
    model = background_of(pre)
    assert isinstance(model, AutoBackground) and model._detector is detector
    assert model._legs_stage is None
    # a tracker that also consumes legs gets DetectLegs with the detector, whose
    # detections of each frame auto's narrowing takes (each frame detected once)
    pre, observe = observe_stages_for(frozenset({"points", "foreground", "legs"}), detector)
    model = background_of(pre)
    assert type(observe[0]).__name__ == "DetectLegs" and observe[0].detector is detector
    assert isinstance(model, AutoBackground) and model._legs_stage is observe[0]


def test_build_gives_each_point_tracker_its_foreground(tmp_path: object) -> None:
    """``build``: the particle filters' ``auto`` holds missed legs, csa's does not, and the
    people's model of the static-track filter runs before it (so that, once dropped, its
    every-point foreground does not undo the narrowing)."""
    from pathlib import Path

    from laserpeople.pipeline import build
    from laserpeople.pipeline.static_people import PeopleStaticModel
    from laserpeople.sim.scenarios import run_scenario

    rec = Path(str(tmp_path)) / "cross.npz"
    run_scenario("crossing-3-p3", seconds=1.0, seed=1).write(rec)
    for tracker, steady in (("csa", False), ("feet-pf", True), ("upper-body-pf", True)):
        pipe = build(rec, tracker=tracker, topics=["all"], max_frames=2)
        model = background_of(pipe.stages)
        assert isinstance(model, AutoBackground) and model._steady is steady
        people = [i for i, s in enumerate(pipe.stages) if isinstance(s, PeopleStaticModel)]
        assert people and people[0] < pipe.stages.index(model)
        pipe.run()


def test_the_stages_leg_mht_uses_the_leg_tracker_section(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """``[leg_tracker]`` of ``--config`` reaches the leg MHT the stage runs (before, it ran
    with the shipped parameters whatever the file said)."""
    from laserpeople.pipeline.background import load_static_world

    path = tmp_path / "p.toml"
    path.write_text('[leg_tracker]\npeople_policy = "arras"\nmht.k_best = 3\n')
    model = _auto("moving")
    model.static = replace(
        load_static_world(path), leg_foreground=LegForegroundParams(memory=0.0, person_memory=1.0)
    )
    for i in range(25):
        model(_frame(_rotating_scan(i, 0)))
    for i in range(25, 30):
        model(_frame(_rotating_scan(i, 3 * (i - 24))))
    assert model.legs is not None and model.legs._tracker is not None
    used = model.legs._tracker.tracker.params
    assert used.people_policy == "arras" and used.mht_params().k == 3
    assert used.mht_params().depth == 8  # unset: the stage's own 8
    assert load_static_world(None).leg_tracker == StaticWorldParams().leg_tracker


def test_the_stages_leg_mht_keeps_000s_k_and_depth_where_unset() -> None:
    from laserpeople.tracking.legs import LegTrackerParams
    from laserpeople.tracking.mht.core import MHTParams

    mht = stage_leg_tracker(None).mht_params()
    assert (mht.k, mht.depth, mht.ratio) == (20, 8, 1e-2)  # the tracks policy's ratio
    assert LegTrackerParams().mht_params().k == 5  # the tracker's own default differs
    mine = stage_leg_tracker(LegTrackerParams(mht=MHTParams(k_best=7, n_scan=2)))
    assert (mine.mht_params().k, mine.mht_params().depth) == (7, 2)


# ------------------------------------------------------ the people of the learning period


def test_person_legs_are_those_of_a_pair_the_leg_mht_confirms() -> None:
    """Two legs standing 0.3 m apart and a lone leg 2 m off: the leg MHT run by
    ``person_legs`` confirms the pair as a person within a few scans (whatever
    ``person_memory`` says), never the lone leg."""
    stage = LegForeground(LegForegroundParams(person_memory=0.0))
    where = [(2.0, 0.15), (2.0, -0.15), (3.0, 2.0)]
    flags = []
    for k in range(15):
        frame = _points_frame(where, 0.1 * k, legs=where)
        assert frame.legs is not None
        legs = replace(frame.legs, stamp=0.1 * k, scan_index=k)
        positions, people = stage.person_legs(replace(frame, index=k, legs=legs))
        assert positions.tolist() == [list(w) for w in where]
        flags.append(people.tolist())
    assert flags[0] == [False, False, False]
    assert all(f == [True, True, False] for f in flags[5:]), flags


def _learning_scan(index: int) -> Scan:
    """A wall at 5 m (90 beams, 1 deg from -45 deg, 10 Hz); a person's two legs at 2 m on
    beams 40-41 and 47-48 (0.24 m apart) and a bin at 3 m on beams 70-71."""
    ranges = np.full(90, 5.0)
    ranges[[40, 41, 47, 48]] = 2.0
    ranges[[70, 71]] = 3.0
    return Scan(0.1 * index, -np.pi / 4, np.pi / 180, ranges, 0.1, 10.0, sensor="l", index=index)


def _centre(scan: Scan, beams: list[int]) -> tuple[float, float]:
    a = scan.angle_min + scan.angle_increment * np.asarray(beams)
    r = scan.ranges[beams]
    return float(np.mean(r * np.cos(a))), float(np.mean(r * np.sin(a)))


def _learned_foreground() -> list[tuple[int, int]]:
    """``auto`` learning with ``[csa] background_people`` on :func:`_learning_scan`, the
    detector firing on both legs and the bin in every scan: per scan, the foreground
    points on the person and on the bin."""
    scan = _learning_scan(0)
    detector = _FixedDetector(_centre(scan, [40, 41]), _centre(scan, [47, 48]),
                              _centre(scan, [70, 71]))  # fmt: skip
    model = AutoBackground(detector=detector, learn_people=True)
    out = []
    for i in range(30):
        frame = model(_frame(_learning_scan(i)))
        assert frame.foreground is not None and frame.points is not None
        fg = frame.points.beams[frame.foreground]
        out.append((int(np.isin(fg, [40, 41, 47, 48]).sum()), int(np.isin(fg, [70, 71]).sum())))
    assert model.chosen == "histogram" and not model.model.learning  # type: ignore[union-attr]
    return out


def test_while_learning_only_the_people_of_the_leg_mht_stay_foreground() -> None:
    """The person is foreground from the first scan (every leg in the first
    ``learn_people_warmup`` scans, then the legs the leg MHT confirmed) and after
    learning; the bin the detector also fires on is foreground only in the first 4 scans,
    then static (marking every leg detection as people kept it out of the static world)."""
    people = _learned_foreground()
    assert all(p == 4 for p, _ in people), people
    assert [b for _, b in people[:4]] == [2] * 4
    assert all(b == 0 for _, b in people[6:]), people


def test_learn_people_warmup_is_checked() -> None:
    with pytest.raises(ValueError, match="learn_people_warmup"):
        LegForegroundParams(learn_people_warmup=-1)


# ------------------------------------------------------------------ what it costs


class _BlockDetector(_FixedDetector):
    """A :class:`_FixedDetector` that also detects blocks of scans (``detect_many``),
    counting the blocks and the scans given."""

    def __init__(self, where: tuple[float, float]) -> None:
        super().__init__(where)
        self.blocks: list[int] = []

    def detect_many(self, scans: list[Scan]) -> list[Detections]:
        self.blocks.append(len(scans))
        found = [self.detect(s) for s in scans]
        self.calls -= len(scans)  # counted as a block, not as scans
        return found


def test_auto_detects_the_narrowing_s_legs_in_blocks_once_it_narrows() -> None:
    """Before the narrowing starts nothing is detected ahead (its detector sees its first
    scan at the frame it starts); from then on a block of frames is detected at once, and
    the foreground is that of one frame at a time."""
    detector = _BlockDetector((3.0, 0.0))
    static = StaticWorldParams(leg_foreground=LegForegroundParams(use="moving", memory=0.0))
    model = AutoBackground(static=static, detector=detector)
    twin = _auto("moving")
    frames = [_frame(_rotating_scan(i, 0 if i < 25 else 3 * (i - 24))) for i in range(100)]
    done = 0
    while done < len(frames):
        block = frames[done : done + 16]
        model.prefetch(block)
        for frame in block:
            out, alone = model(frame), twin(frame)
            assert out.foreground is not None and alone.foreground is not None
            assert out.points is not None
            # the same points kept, but for a point within 1e-9 m of the narrowing's radius
            # around the leg (where a last-bit difference could flip it)
            differ = out.foreground != alone.foreground
            reach = np.hypot(*(out.points.points[differ] - (3.0, 0.0)).T)
            assert np.all(np.abs(reach - static.leg_foreground.radius) < 1e-9), reach
        done += len(block)
    assert model.legs_from == 29  # in the block of frames 16-31
    # frames 29-31 one at a time; then each block ahead: 32-47, 48-63, 64-79, 80-95, 96-99
    assert detector.calls == 3
    assert detector.blocks == [16, 16, 16, 16, 4]


def test_a_frame_is_detected_once_however_many_stages_ask() -> None:
    """The pipeline's DetectLegs, shared with the narrowing: asked twice for a frame it
    detects it once (the same legs); a frame of other scans is detected anew."""
    from laserpeople.pipeline import DetectLegs

    detector = _BlockDetector((1.0, 0.0))
    shared = DetectLegs(detector)
    stage = LegForeground(LegForegroundParams(radius=0.2, memory=0.0), legs_stage=shared)
    frame = _points_frame([(1.1, 0.0), (0.5, 0.0)])
    stage.prefetch([frame])  # the pipeline prefetches its own stage: nothing here
    assert detector.blocks == []
    out = stage(frame)
    assert out.foreground is not None and out.foreground.tolist() == [True, False]
    legs = shared(out).legs
    assert detector.calls == 1 and stage.detected == 1
    assert legs is not None and legs.positions.tolist() == [[1.0, 0.0]]
    other = _points_frame([(1.1, 0.0)], stamp=0.1)
    shared(other)
    assert detector.calls == 2
