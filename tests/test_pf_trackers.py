"""End to end: the feet and upper-body trackers of 004 on simulated 004 scenes."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from laserpeople.evaluation.schenk_scenes import run_tracker, simulate_scene
from laserpeople.frame import Frame
from laserpeople.scan import PointSet
from laserpeople.tracking import registry
from laserpeople.tracking.particle.feet import FeetParams, FeetTracker
from laserpeople.tracking.particle.upper_body import UpperBodyParams, UpperBodyTracker


@pytest.fixture(scope="module")
def walk() -> tuple:
    """One person walking line (a) at normal speed, at 25 Hz to keep the test short."""
    return simulate_scene("speed-normal", 3, rate=25.0)


@pytest.fixture(scope="module")
def cross() -> tuple:
    return simulate_scene("cross", 4, rate=25.0)


def test_upper_body_tracker_follows_one_person(walk: tuple) -> None:
    rec, bg = walk
    run = run_tracker(rec, bg, "torso", UpperBodyTracker())
    assert run.motp > 0.85  # 004 Table 1 "normal": 1.0
    assert run.tracks == 1


def test_feet_tracker_follows_one_person(walk: tuple) -> None:
    rec, bg = walk
    run = run_tracker(rec, bg, "feet", FeetTracker())
    assert run.motp > 0.7  # 004 Table 1 "normal": 0.84
    assert run.tracks <= 2


def test_a_broken_model_misses_the_threshold(walk: tuple) -> None:
    """The thresholds above mean something: with eq. 9 made flat (huge zeta) or the walking
    model fed a wrong stride and step width (feet pulled apart along and across the walking
    direction), the same scene scores far lower."""
    rec, bg = walk
    flat = run_tracker(rec, bg, "torso", UpperBodyTracker(UpperBodyParams(zeta=50.0)))
    assert flat.motp < 0.85
    wrong = run_tracker(
        rec, bg, "feet", FeetTracker(FeetParams(h=0.005, stride_range=(0.9, 1.0), step_width=0.6))
    )
    assert wrong.motp < 0.7


def test_two_crossing_people_keep_two_tracks(cross: tuple) -> None:
    rec, bg = cross
    ubt = run_tracker(rec, bg, "torso", UpperBodyTracker())
    assert ubt.motp > 0.8  # 004 Table 5 "cross": 0.97
    ft = run_tracker(rec, bg, "feet", FeetTracker())
    assert ft.motp > 0.6  # 004 Table 5 "cross": 0.81


@pytest.mark.parametrize("draws", [0, 1])
def test_crossing_people_whose_filters_merge_keep_their_identities(draws: int) -> None:
    """004's cross scene, seed 3 (50 Hz): the two filters come within ``merge_distance``
    where the people pass, and the survivor is the filter of the person who entered later.
    It keeps its own identity and the other person's comes back by the handover, so two
    tracks cover the run (with ``keep_identity_age`` 0 these draws of the filters swapped
    the two people there: 3 tracks, MOTP 0.49)."""
    rec, bg = simulate_scene("cross", 3)
    ft = run_tracker(rec, bg, "feet", FeetTracker(FeetParams(seed=draws)))
    assert ft.tracks == 2
    assert ft.motp > 0.9  # 004 Table 5 "cross": 0.81


def test_seeded_and_reproducible(walk: tuple) -> None:
    rec, bg = walk
    a = run_tracker(rec, bg, "feet", FeetTracker(FeetParams(seed=5)))
    b = run_tracker(rec, bg, "feet", FeetTracker(FeetParams(seed=5)))
    assert a.motp == b.motp and a.tracks == b.tracks


def test_filters_die_when_the_points_go(walk: tuple) -> None:
    rec, _ = walk
    torso = [s for s in rec.scans if s.sensor.startswith("torso") and s.index < 60]
    tracker = UpperBodyTracker(UpperBodyParams(miss_time=0.2))
    for k in range(60):
        scans = [s for s in torso if s.index == k]
        pts = PointSet.from_scans(scans, "world")
        frame = Frame(k, scans[0].stamp, tuple(scans), "fused", "world", points=pts)
        # no background model: everything is foreground; make only the last 20 frames empty
        fg = np.zeros(len(pts), bool) if k >= 40 else _near_person(pts, rec, k)
        out = tracker.update(dataclasses.replace(frame, foreground=fg))
        if k == 39:
            assert len(out) >= 1
    assert len(out) == 0 and len(tracker.bank) == 0


def _near_person(pts: PointSet, rec, k: int) -> np.ndarray:
    truth = rec.truth[k]
    if len(truth) == 0:
        return np.zeros(len(pts), bool)
    d = np.hypot(*(pts.points[:, None, :] - truth.positions[None]).transpose(2, 0, 1))
    return d.min(axis=1) < 0.4


def test_registered_as_frame_trackers() -> None:
    for name, cls in (("feet-pf", FeetTracker), ("upper-body-pf", UpperBodyTracker)):
        entry = registry.get(name)
        tracker = entry.factory(entry.params_cls())
        assert isinstance(tracker, cls)
        assert tracker.consumes == frozenset({"points", "foreground"})


def test_a_person_standing_while_the_background_learns_is_tracked_once_walking() -> None:
    """The histogram background learns online over the first 2 s while the person stands
    at the start of line (a); once they walk, the upper-body tracker follows them (the
    beams they hid relearn the wall behind them; no track stays at the start)."""
    from laserpeople.background.beam_histogram import BeamHistogramBackground
    from laserpeople.evaluation.schenk_motp import SchenkMotp
    from laserpeople.evaluation.schenk_scenes import lasers_of
    from laserpeople.sim.motion import Route
    from laserpeople.sim.people import random_person
    from laserpeople.sim.scenarios.schenk import LINE_Y, schenk_sensors, schenk_world
    from laserpeople.sim.simulator import Scene, simulate
    from laserpeople.tracking.particle.frames import fused_frames

    rng = np.random.default_rng(7)
    route = Route(3.0, LINE_Y, 0.0).wait(3.0).walk_to(9.0, LINE_Y, 1.2)
    scene = Scene(schenk_world(), [random_person(rng, 0, route)], schenk_sensors())
    rec = simulate(scene, 8.0, seed=7, rate=25.0, name="stand-then-walk")
    model = BeamHistogramBackground()
    frames = fused_frames(rec.scans, lasers_of(rec, "torso"), model)
    truth = {t.scan_index: t for t in rec.truth}
    tracker, motp = UpperBodyTracker(), SchenkMotp(keep_frames=False)
    left_behind = 0
    for frame in frames:
        tracks = tracker.update(frame)
        if frame.stamp >= 4.0:  # walking, 1 s after learning ended
            motp.accumulate(truth[frame.index], tracks)
            left_behind += sum(abs(t.position[0] - 3.0) < 0.3 for t in tracks)
    assert sum(model.relearned(s) for s in model.sensors) > 0
    assert motp.result().motp > 0.9
    assert left_behind == 0
