"""Runs of foreground points as wide as a leg (pipeline/leg_runs.py), the blobs holding a few
of their points (far legs), and their use by the ``auto`` static world model's narrowing on a
moving laser (``[leg_foreground] leg_run_points``)."""

from __future__ import annotations

import numpy as np

from laserpeople.frame import Frame
from laserpeople.pipeline.leg_foreground import LegForeground, LegForegroundParams
from laserpeople.pipeline.leg_runs import JUMP, MAX_WIDTH, MIN_WIDTH, far_leg_blobs, leg_runs
from laserpeople.scan import PointSet, Pose2D, Scan
from laserpeople.tracks import Detections

LASER = np.zeros(2)
STEP = np.radians(0.5)
"""Beam spacing of the tests' laser [rad]."""


def _arc(centre_x: float, beams: np.ndarray, chord: float) -> np.ndarray:
    """Points on beams ``beams`` (of a laser at the origin, STEP apart, beam 0 along +x) at
    range ``centre_x``, spread evenly so that the first and last lie ``chord`` [m] apart
    (their angles are ignored: the tests place them by hand)."""
    n = len(beams)
    ys = np.linspace(-chord / 2, chord / 2, n) if n > 1 else np.zeros(1)
    return np.c_[np.full(n, centre_x), ys]


def _kept(pts: np.ndarray, beams: np.ndarray, mask: np.ndarray | None = None) -> np.ndarray:
    mask = np.ones(len(pts), dtype=bool) if mask is None else mask
    return leg_runs(pts, beams, mask, LASER, STEP)


def test_the_width_is_the_chord_plus_one_beam_at_the_runs_range() -> None:
    """At 4 m one 0.5 deg beam covers 0.0349 m. Two points 0.05 m apart: width 0.0849 m,
    over MIN_WIDTH (0.08 m), kept; the chord alone (0.05 m) or the chord plus half a beam
    (0.067 m) would drop it. Two points 0.17 m apart: 0.2049 m, over MAX_WIDTH (0.2 m), not
    kept; the chord alone (0.17 m) would keep it."""
    assert (MIN_WIDTH, MAX_WIDTH) == (0.08, 0.2)
    spacing = 4.0 * STEP
    np.testing.assert_allclose(spacing, 0.034907, atol=1e-6)
    beams = np.array([10, 11])
    assert _kept(_arc(4.0, beams, 0.05), beams).all()
    assert not _kept(_arc(4.0, beams, 0.17), beams).any()
    # the same two points 2 m nearer: a beam covers 0.0175 m, 0.0675 m in all, too thin
    assert not _kept(_arc(2.0, beams, 0.05), beams).any()


def test_one_point_or_a_skipped_beam_is_no_run() -> None:
    """A single return has no width; two returns on beams 10 and 12 (beam 11 missing or
    background) are two runs of one point each, none kept; outside the mask nothing is
    kept."""
    assert not _kept(_arc(4.0, np.array([10]), 0.0), np.array([10])).any()
    skipped = np.array([10, 12])
    assert not _kept(_arc(4.0, skipped, 0.08), skipped).any()
    beams = np.array([10, 11, 12])
    pts = _arc(4.0, beams, 0.1)
    assert _kept(pts, beams).all()
    assert not _kept(pts, beams, np.zeros(3, dtype=bool)).any()


def test_a_run_must_stand_apart_from_the_returns_beside_it() -> None:
    """A leg (three beams, 0.1 m chord) 4 m away with the returns of the beams either side
    (background) 1 m farther is kept; as a piece of wall, with those returns as far as its
    ends or JUMP - 1 mm farther, it is not; JUMP + 1 mm farther, it is kept again. One
    side near and the other far is not apart either."""
    beams = np.array([10, 11, 12])
    leg = _arc(4.0, beams, 0.1)
    fg = np.r_[np.ones(3, dtype=bool), False, False]
    all_beams = np.r_[beams, 9, 13]

    def beside(end: np.ndarray, farther: float) -> np.ndarray:
        r = float(np.hypot(*end))
        return end * (r + farther) / r

    for farther, kept in ((1.0, True), (0.0, False), (JUMP - 0.001, False), (JUMP + 0.001, True)):
        pts = np.vstack([leg, beside(leg[0], farther), beside(leg[-1], farther)])
        out = _kept(pts, all_beams, fg)
        assert out[:3].all() == kept and out[:3].any() == kept
        assert not out[3:].any()
    pts = np.vstack([leg, beside(leg[0], 0.0), beside(leg[-1], 1.0)])
    assert not _kept(pts, all_beams, fg).any()


def _frame(pts: np.ndarray, beams: np.ndarray, kind: str = "world") -> Frame:
    points = PointSet(0.0, pts, np.zeros(len(pts), dtype=np.int64), beams, ("l",), kind)  # type: ignore[arg-type]
    legs = Detections(0.0, 0, np.empty((0, 2)), np.empty((0, 2, 2)), np.empty(0), kind)  # type: ignore[arg-type]
    scan = Scan(0.0, -np.pi, STEP, np.full(720, 5.0), sensor="l")
    return Frame(0, 0.0, (scan,), "l", kind, Pose2D(0.0, 0.0, 0.0), points, legs=legs)  # type: ignore[arg-type]


def test_the_stage_keeps_the_whole_blob_of_a_leg_run_on_a_moving_laser() -> None:
    """A person 4 m away, no leg detection: one leg a run of three beams (0.1 m chord), the
    other one return 0.2 m beside it (one blob at 0.35 m single linkage). A chair's two legs
    as single returns 1.5 m off are a blob without a run. For a tracker that needs steady
    points on a moving laser, the person's four points are kept and the chair's not; not
    for other trackers, not on a still laser, not at torso height, not in the sensor
    frame, and not with --preset paper (leg_run_points 0)."""
    leg = _arc(4.0, np.array([100, 101, 102]), 0.1)
    other = np.array([[4.0, 0.25]])
    chair = np.array([[4.0, 1.5], [4.0, 1.9]])
    pts = np.vstack([leg, other, chair])
    beams = np.array([100, 101, 102, 104, 120, 126])
    person = [True] * 4 + [False] * 2
    params = LegForegroundParams(memory=0.0, person_memory=0.0, moving_travel=0.0)

    def kept(steady: bool, moving: bool, torso: bool, kind: str, p: LegForegroundParams) -> list:
        stage = LegForeground(p, steady=steady)
        stage.moving, stage.torso = moving, torso
        out = stage(_frame(pts, beams, kind)).foreground
        assert out is not None
        return list(out)

    stage = LegForeground(params, steady=True)
    stage.moving = True
    assert list(stage(_frame(pts, beams)).foreground) == person  # type: ignore[arg-type]
    assert stage.points_leg_runs == 4
    nothing = [False] * 6
    assert kept(False, True, False, "world", params) == nothing
    assert kept(True, False, False, "world", params) == nothing
    assert kept(True, True, True, "world", params) == nothing
    assert kept(True, True, False, "sensor", params) == nothing
    paper = LegForegroundParams(**{**dict(LegForegroundParams.paper_preset), "memory": 0.0})
    assert kept(True, True, False, "world", paper) == nothing
    assert LegForegroundParams().leg_run_points == 4
    three = LegForegroundParams(memory=0.0, person_memory=0.0, moving_travel=0.0, leg_run_points=2)
    assert kept(True, True, False, "world", three) == nothing  # 3 run points > 2


def _legs(n_left: int, n_right: int) -> tuple[np.ndarray, np.ndarray]:
    """A person 6 m away on the tests' laser: a left leg of ``n_left`` beams and a right leg
    of ``n_right`` beams (0.05 m between neighbours, about one beam's spacing at 6 m, 0.0524
    m; 0.25 m apart: one blob), nothing beside them."""
    left = _arc(6.0, np.arange(n_left), 0.05 * (n_left - 1))
    right = _arc(6.0, np.arange(n_right), 0.05 * (n_right - 1)) + np.array([0.0, 0.25])
    beams = np.r_[np.arange(100, 100 + n_left), np.arange(110, 110 + n_right)]
    return np.vstack([left, right]), beams


def test_a_blob_is_kept_only_with_one_to_max_points_run_points() -> None:
    """Two legs of two beams (4 run points) are kept with max_points 4 and not with 3; legs
    of two and three beams (5) are kept with 5 and not with 4; a blob of one single return
    per leg holds no run and is never kept (nor with max_points 0: the rule is off)."""
    for n_left, n_right, bound, kept in (
        (2, 2, 4, True),
        (2, 2, 3, False),
        (2, 3, 5, True),
        (2, 3, 4, False),
        (2, 2, 0, False),
    ):
        pts, beams = _legs(n_left, n_right)
        out = far_leg_blobs(pts, beams, np.ones(len(pts), dtype=bool), LASER, STEP, bound)
        assert out.all() == kept and out.any() == kept, (n_left, n_right, bound)
    pts = np.array([[6.0, 0.0], [6.0, 0.2]])
    beams = np.array([100, 110])
    assert not far_leg_blobs(pts, beams, np.ones(2, dtype=bool), LASER, STEP, 4).any()


def test_the_bound_counts_every_run_of_the_blob_not_each_run() -> None:
    """Two legs of three beams (6 run points, 3 per run) are not kept with max_points 4,
    though each run alone holds fewer; two blobs 2 m apart are counted apart (one of two
    legs of two beams kept, the other of two legs of three beams not)."""
    pts, beams = _legs(3, 3)
    assert not far_leg_blobs(pts, beams, np.ones(6, dtype=bool), LASER, STEP, 4).any()
    near, near_beams = _legs(2, 2)
    far, far_beams = _legs(3, 3)
    pts = np.vstack([near, far + np.array([0.0, 2.0])])
    beams = np.r_[near_beams, far_beams + 100]
    out = far_leg_blobs(pts, beams, np.ones(len(pts), dtype=bool), LASER, STEP, 4)
    assert out[:4].all() and not out[4:].any()
