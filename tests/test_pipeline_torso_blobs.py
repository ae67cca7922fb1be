"""Torso-shaped runs of foreground points (pipeline/torso_blobs.py) and their use at
torso height by the ``auto`` static world model's narrowing (``[leg_foreground]
torso_blobs``)."""

from __future__ import annotations

import numpy as np

from laserpeople.pipeline.background import AutoBackground, at_torso_height, set_laser_height
from laserpeople.pipeline.leg_foreground import LegForegroundParams, wants_torso_runs
from laserpeople.pipeline.torso_blobs import MAX_WIDTH, MIN_BULGE, MIN_WIDTH, torso_blobs
from laserpeople.tracking import registry
from laserpeople.tracking.csa import ClusterSortingTracker
from laserpeople.tracking.nearest import NearestNeighbourTracker

LASER = np.zeros(2)


def _fan(shape: np.ndarray, step: float = np.radians(1.0)) -> tuple[np.ndarray, np.ndarray]:
    """Points where beams from the laser at the origin, ``step`` [rad] apart, first hit the
    closed polygon ``shape`` (M, 2) [m], and their beam indices (a ray cast by hand)."""
    pts, beams = [], []
    for b, a in enumerate(np.arange(-np.pi, np.pi, step)):
        d = np.array([np.cos(a), np.sin(a)])
        best = np.inf
        for p, q in zip(shape, np.roll(shape, -1, axis=0), strict=True):
            m = np.array([d, p - q]).T
            if abs(np.linalg.det(m)) < 1e-12:
                continue
            t, u = np.linalg.solve(m, p)
            if t > 0 and 0 <= u <= 1:
                best = min(best, t)
        if np.isfinite(best):
            pts.append(best * d)
            beams.append(b)
    return np.array(pts).reshape(-1, 2), np.array(beams, dtype=np.int64)


def _ellipse(centre: tuple[float, float], across: float, depth: float) -> np.ndarray:
    """A polygon of an ellipse with semi-axes ``across`` (along y) and ``depth`` (along x)."""
    a = np.linspace(0, 2 * np.pi, 90, endpoint=False)
    return np.c_[centre[0] + depth * np.cos(a), centre[1] + across * np.sin(a)]


def _box(x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=float)


def _kept(shape: np.ndarray) -> tuple[int, int]:
    pts, beams = _fan(shape)
    keep = torso_blobs(pts, beams, np.ones(len(pts), dtype=bool), LASER)
    return int(keep.sum()), len(pts)


def test_a_torso_seen_from_the_front_is_kept_at_2_and_4_m() -> None:
    """The simulator's torso (semi-axes 0.2 m across, 0.14 m deep) 2 m and 4 m in front of
    a 1° laser: every point of its arc is kept (0.4 m wide, bulging 0.1 m or more)."""
    for x in (2.0, 4.0):
        kept, seen = _kept(_ellipse((x, 0.0), 0.2, 0.14))
        assert seen >= 5
        assert kept == seen


def test_a_straight_piece_of_wall_of_torso_width_is_not_kept() -> None:
    """A flat face 0.4 m wide (a piece of wall or a box's side, 0.3 m deep) 3 m away: as
    wide as a torso, but its points lie on the chord (no bulge)."""
    assert _kept(_box(3.0, -0.2, 3.3, 0.2))[0] == 0


def test_runs_too_narrow_or_too_wide_are_not_kept() -> None:
    """A leg (0.07 m radius) and a round table 1 m across bulge towards the laser but are
    narrower than MIN_WIDTH / wider than MAX_WIDTH; a torso seen from the side (0.3 m
    across, 0.4 m deep: an arc 0.27 m wide at 2 m) is kept."""
    assert 0.14 < MIN_WIDTH <= 0.27 < 1.0 and 0.4 < MAX_WIDTH < 1.0
    assert _kept(_ellipse((2.0, 0.0), 0.07, 0.07))[0] == 0
    assert _kept(_ellipse((3.0, 0.0), 0.5, 0.5))[0] == 0
    kept, seen = _kept(_ellipse((2.0, 0.0), 0.15, 0.2))
    assert kept == seen > 0


def test_a_run_bulging_away_from_the_laser_is_not_kept() -> None:
    """The inside of a corner 0.4 m wide, 0.1 m deep, opening towards the laser (a niche):
    its middle lies farther than its ends, so it bulges away."""
    niche = np.array([[3.0, -0.2], [3.1, 0.0], [3.0, 0.2], [4.0, 0.2], [4.0, -0.2]])
    kept, seen = _kept(niche)
    assert seen >= 5 and kept == 0


def test_a_gap_or_skipped_beams_cut_a_run() -> None:
    """Two torsos side by side 0.2 m apart are two runs (each kept); the points of one
    torso outside the mask (background) are not kept, and with every other beam of an arc
    missing (skips of 2 beams are allowed) it is still one run, with 3 skipped it is cut."""
    pts_a, beams_a = _fan(_ellipse((3.0, -0.3), 0.2, 0.14))
    keep = torso_blobs(pts_a, beams_a, np.ones(len(pts_a), dtype=bool), LASER)
    assert keep.all()
    half = np.ones(len(pts_a), dtype=bool)
    half[: len(pts_a) // 2] = False
    assert not torso_blobs(pts_a, beams_a, half, LASER)[: len(pts_a) // 2].any()
    sparse = torso_blobs(pts_a, beams_a * 2, np.ones(len(pts_a), dtype=bool), LASER)
    assert sparse.all()
    cut = torso_blobs(pts_a, beams_a * 4, np.ones(len(pts_a), dtype=bool), LASER)
    assert not cut.any()


def test_the_bulge_threshold_tells_a_torso_from_noise() -> None:
    """Three points bulging MIN_BULGE + 1 mm towards the laser are kept, MIN_BULGE - 1 mm
    not (a run 0.24 m wide, 3 m away)."""
    for bulge, kept in ((MIN_BULGE + 0.001, True), (MIN_BULGE - 0.001, False)):
        pts = np.array([[3.0, -0.12], [3.0 - bulge, 0.0], [3.0, 0.12]])
        out = torso_blobs(pts, np.arange(3), np.ones(3, dtype=bool), LASER)
        assert out.all() == kept and out.any() == kept


def test_only_a_laser_stated_at_torso_height_keeps_torso_runs() -> None:
    """at_torso_height: 0.7 m or higher (UPPER_BODY_MIN_HEIGHT); unknown is not.
    set_laser_height reaches the auto model among the stages; --preset paper turns the
    runs off (002, 004); only the CSA asks for them. set_laser_height also tells the CSA,
    behind its point guard, whether the laser is at torso height (torso_count_seconds)."""
    assert at_torso_height(1.1) and at_torso_height(0.7)
    assert not at_torso_height(0.3) and not at_torso_height(None)
    auto = AutoBackground()
    set_laser_height([object(), auto], 1.2)
    assert auto.laser_height == 1.2
    guarded = registry.get("csa").make()  # the CSA behind the point guard, as build makes it
    for height, torso in ((1.2, True), (0.5, False), (None, False)):
        set_laser_height([auto, guarded], height)
        assert guarded.tracker.at_torso_height is torso
    assert LegForegroundParams().torso_blobs
    assert LegForegroundParams.paper_preset["torso_blobs"] is False
    assert wants_torso_runs(ClusterSortingTracker())
    assert not wants_torso_runs(NearestNeighbourTracker())
    assert not wants_torso_runs(None)


def test_three_skipped_beams_cut_a_run() -> None:
    """Every third beam of a torso's arc (two beams missing between neighbours, skip 3):
    each point is a run of its own, none kept; with every second beam (skip 2) it is one
    run, kept (the arc 2 m away, its neighbours under RUN_GAP apart either way)."""
    pts, beams = _fan(_ellipse((2.0, 0.0), 0.2, 0.14))
    every = np.ones(len(pts), dtype=bool)
    assert np.hypot(*np.diff(pts, axis=0).T).max() < 0.15 / 3
    assert torso_blobs(pts, beams * 2, every, LASER).all()
    assert not torso_blobs(pts, beams * 3, every, LASER).any()


def test_two_torsos_0_2_m_apart_on_neighbouring_beams_are_two_runs() -> None:
    """Two arcs of five points each, 0.24 m wide and bulging 0.07 m towards the laser, on
    beams 0-9 with 0.2 m (over RUN_GAP 0.15 m) between the last point of one and the first
    of the other: two runs, both kept. Taken as one run they would span 0.68 m between its
    ends, over MAX_WIDTH (0.65 m), and nothing would be kept."""
    depth = np.array([3.0, 2.95, 2.93, 2.95, 3.0])
    across = np.arange(5) * 0.06
    a = np.c_[depth, -0.54 + across]
    b = np.c_[depth, -0.10 + across]
    pts = np.vstack([a, b])
    np.testing.assert_allclose(np.hypot(*(b[0] - a[-1])), 0.2, atol=1e-12)
    np.testing.assert_allclose(np.hypot(*(b[-1] - a[0])), 0.68, atol=1e-12)
    out = torso_blobs(pts, np.arange(10), np.ones(10, dtype=bool), LASER)
    assert out.all()


def test_the_stage_measures_the_bulge_towards_the_lasers_pose_in_the_world_frame() -> None:
    """LegForeground at torso height in the world frame, the laser at (10, 0) facing -x,
    no legs: an arc at x = 8 m bulging 0.07 m towards the laser (x up to 8.07) is kept; its
    mirror, bulging towards the world's origin (x down to 7.93, a niche seen from the laser),
    is not. Measured from the origin instead of the laser's pose the two would swap. Off
    torso height, or in the sensor frame, no run is kept."""
    from laserpeople.frame import Frame
    from laserpeople.pipeline.leg_foreground import LegForeground
    from laserpeople.scan import PointSet, Pose2D, Scan
    from laserpeople.tracks import Detections

    bulge = np.array([0.0, 0.05, 0.07, 0.05, 0.0])
    across = -0.12 + 0.06 * np.arange(5)
    torso = np.c_[8.0 + bulge, across + 2.0]
    niche = np.c_[8.0 - bulge, across - 2.0]
    pts = np.vstack([torso, niche])
    beams = np.r_[np.arange(5), 40 + np.arange(5)]  # two runs (35 beams between them)

    def frame(kind: str) -> Frame:
        points = PointSet(0.0, pts, np.zeros(10, dtype=np.int64), beams, ("l",), kind)  # type: ignore[arg-type]
        legs = Detections(0.0, 0, np.empty((0, 2)), np.empty((0, 2, 2)), np.empty(0), kind)  # type: ignore[arg-type]
        scan = Scan(0.0, 0.0, 0.01, np.full(4, 2.0), sensor="l")
        return Frame(0, 0.0, (scan,), "l", kind, Pose2D(10.0, 0.0, np.pi), points, legs=legs)  # type: ignore[arg-type]

    stage = LegForeground(LegForegroundParams(memory=0.0, person_memory=0.0))
    stage.torso = True
    out = stage(frame("world"))
    assert out.foreground is not None
    assert out.foreground.tolist() == [True] * 5 + [False] * 5
    assert stage.points_torso == 5
    assert not stage(frame("sensor")).foreground.any()  # type: ignore[union-attr]
    stage.torso = False
    assert not stage(frame("world")).foreground.any()  # type: ignore[union-attr]


def test_build_tells_the_group_tracker_the_lasers_torso_height(tmp_path: object) -> None:
    """``build`` on a simulated recording whose laser is stated at 1.19 m (random-groups
    seed 7): the group tracker counts without leg pairs, while the foreground's ``auto``
    model is not told (the group tracker takes no torso runs); at 0.27 m (seed 0) the
    tracker pairs legs."""
    from pathlib import Path

    from laserpeople.pipeline import build
    from laserpeople.pipeline.background import background_of
    from laserpeople.sim.scenarios import run_scenario

    for seed, torso in ((7, True), (0, False)):
        rec = Path(str(tmp_path)) / f"g{seed}.npz"
        run_scenario("random-groups", seconds=1.0, seed=seed).write(rec)
        pipe = build(rec, tracker="group-mht", max_frames=2)
        assert pipe.tracker is not None
        assert pipe.tracker.counting.torso is torso
        model = background_of(pipe.stages)
        assert isinstance(model, AutoBackground) and model.laser_height is None
        pipe.run()
