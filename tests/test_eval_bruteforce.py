"""Trajectory-level metrics against brute force over every one-to-one matching, plus
invariants that hold for any input, and the metric protocol."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from laserpeople.errors import LaserPeopleError
from laserpeople.evaluation import (
    ClearMot,
    IdentityF1,
    Metric,
    SchenkMotp,
    TrackingEvaluation,
)
from laserpeople.evaluation.synthetic import synthetic_sequence
from laserpeople.scan import Pose2D
from laserpeople.tracks import Track, Tracks
from laserpeople.truth import TruthFrame


def random_small(rng, frames=12):
    n_people = int(rng.integers(1, 4))
    n_tracks = int(rng.integers(0, 5))
    people = {}
    for pid in range(n_people):
        xy = rng.uniform(0, 2, 2) + np.cumsum(rng.normal(0, 0.2, (frames, 2)), axis=0)
        xy[rng.random(frames) < 0.2] = np.nan
        people[pid] = xy
    tracks = {}
    for tid in range(n_tracks):
        xy = rng.uniform(0, 2, 2) + np.cumsum(rng.normal(0, 0.2, (frames, 2)), axis=0)
        xy[rng.random(frames) < 0.2] = np.nan
        tracks[10 + tid] = xy
    return people, tracks


def all_matchings(track_ids, person_ids):
    """Every partial one-to-one matching between tracks and people."""
    k_max = min(len(track_ids), len(person_ids))
    for k in range(k_max + 1):
        for ts in itertools.combinations(track_ids, k):
            for ps in itertools.permutations(person_ids, k):
                yield list(zip(ts, ps, strict=True))


def brute_force(people, tracks, gate=0.75, h=0.008):
    """IDTP and 004's numerator straight from the definitions, frame by frame."""
    frames = next(iter(people.values())).shape[0]
    best_idtp, best_m = 0, 0.0
    for matching in all_matchings(list(tracks), list(people)):
        idtp, m_sum = 0, 0.0
        for k in range(frames):
            for tid, pid in matching:
                a, b = tracks[tid][k], people[pid][k]
                if np.isnan(a).any() or np.isnan(b).any():
                    continue
                d = math.dist(a, b)
                idtp += d <= gate
                m_sum += 1.0 if d == 0 else min(1.0, h / d**3)
        best_idtp = max(best_idtp, idtp)
        best_m = max(best_m, m_sum)
    present = lambda s, k: sum(not np.isnan(xy[k]).any() for xy in s.values())  # noqa: E731
    denominator = sum(max(present(people, k), present(tracks, k)) for k in range(frames))
    n_truth = sum(present(people, k) for k in range(frames))
    n_tracks = sum(present(tracks, k) for k in range(frames))
    return best_idtp, best_m, denominator, n_truth, n_tracks


@pytest.mark.parametrize("seed", range(25))
def test_idf1_and_schenk_motp_equal_brute_force(seed):
    people, tracks = random_small(np.random.default_rng(seed))
    ev = TrackingEvaluation()
    for truth, frame_tracks in zip(*synthetic_sequence(people, tracks), strict=True):
        ev.accumulate(truth, frame_tracks)
    idtp, m_sum, denominator, n_truth, n_tracks = brute_force(people, tracks)
    ident, schenk = ev.identity.result(), ev.schenk.result()
    assert ident.idtp == idtp
    assert ident.idfn == n_truth - idtp and ident.idfp == n_tracks - idtp
    assert schenk.numerator == pytest.approx(m_sum)
    assert schenk.denominator == denominator
    if denominator:
        assert schenk.motp == pytest.approx(m_sum / denominator)
    table = ev.frames()
    assert table.column("idtp").sum() == idtp
    assert table.column("schenk_m_sum").sum() == pytest.approx(m_sum, abs=1e-6)


@pytest.mark.parametrize("seed", range(25))
def test_invariants_and_id_relabelling(seed):
    rng = np.random.default_rng(100 + seed)
    people, tracks = random_small(rng)
    ev = TrackingEvaluation()
    for truth, frame_tracks in zip(*synthetic_sequence(people, tracks), strict=True):
        ev.accumulate(truth, frame_tracks)
    r = ev.result()
    c = r.clear_mot
    assert c.matches + c.misses == c.num_truth
    assert c.matches + c.false_positives == c.num_tracks
    assert c.id_switches <= c.matches
    if c.num_truth:
        assert c.mota <= 1.0
    if c.matches:
        assert 0.0 <= c.motp <= 0.75
    assert r.identity.idtp <= min(c.num_truth, c.num_tracks)
    if r.schenk.denominator:
        assert 0.0 <= r.schenk.motp <= 1.0
    # Renaming ids changes nothing.
    renamed_people = {1000 - k: v for k, v in people.items()}
    renamed_tracks = {7 * k + 3: v for k, v in tracks.items()}
    ev2 = TrackingEvaluation()
    for truth, frame_tracks in zip(
        *synthetic_sequence(renamed_people, renamed_tracks), strict=True
    ):
        ev2.accumulate(truth, frame_tracks)
    r2 = ev2.result()
    assert r2.summary() == pytest.approx(r.summary(), nan_ok=True)


def test_every_metric_follows_the_protocol():
    for metric in (ClearMot(), IdentityF1(), SchenkMotp(), TrackingEvaluation()):
        assert isinstance(metric, Metric)


def test_tracks_are_moved_into_the_frame_the_truth_states():
    pose = Pose2D(1.0, 3.0, math.pi / 2)  # sensor at (1, 3) looking along +y
    # The person is 1 m in front of the sensor: sensor-frame (1, 0), world (1, 4).
    world = TruthFrame.from_positions(0.0, 0, np.array([1]), np.array([[1.0, 4.0]]), "world")
    track = Track(5, "person", [1.0, 0.0], [0.0, 0.0], np.eye(2))
    metric = ClearMot()
    metric.accumulate(world, Tracks(0.0, 0, (track,), frame="sensor", sensor_pose=pose))
    assert metric.result().matches == 1 and metric.result().motp == pytest.approx(0.0, abs=1e-12)
    # world-frame tracks against labels in the laser frame: moved the other way
    laser = TruthFrame.from_positions(1.0, 1, np.array([1]), np.array([[1.0, 0.0]]), "sensor")
    in_world = Track(5, "person", [1.0, 4.0], [0.0, 0.0], np.eye(2))
    metric.accumulate(laser, Tracks(1.0, 1, (in_world,), frame="world", sensor_pose=pose))
    assert metric.result().matches == 2 and metric.result().motp == pytest.approx(0.0, abs=1e-12)
    # no pose: refused against truth that states another frame
    with pytest.raises(LaserPeopleError, match="sensor frame with no sensor pose"):
        metric.accumulate(world, Tracks(0.0, 0, (track,), frame="sensor"))
    # truth that states no frame: compared as they are, with or without a pose (labels in
    # the laser frame against sensor-frame tracks; moved into the world frame, the track
    # would lie at (1, 4), 3.9 m from the label)
    labels = TruthFrame.from_positions(2.0, 2, np.array([1]), np.array([[1.0, 0.1]]))
    metric.accumulate(labels, Tracks(2.0, 2, (track,), frame="sensor", sensor_pose=pose))
    labels = TruthFrame.from_positions(3.0, 3, np.array([1]), np.array([[1.0, 0.1]]))
    metric.accumulate(labels, Tracks(3.0, 3, (track,), frame="sensor"))
    assert metric.result().matches == 4


def test_without_frames_the_numbers_are_the_same_and_the_table_is_refused():
    from laserpeople.errors import EvaluationError

    people, tracks = random_small(np.random.default_rng(7))
    full, lean = TrackingEvaluation(), TrackingEvaluation(keep_frames=False)
    for truth, frame_tracks in zip(*synthetic_sequence(people, tracks), strict=True):
        full.accumulate(truth, frame_tracks)
        lean.accumulate(truth, frame_tracks)
    assert lean.result().summary() == full.result().summary()
    with pytest.raises(EvaluationError, match="without per-frame detail"):
        lean.frames()
