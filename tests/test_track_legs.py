"""The leg tracker end to end on synthetic leg detections and simulated scenes (000 Sec. 3.4)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from laserpeople.config import load_config, to_toml
from laserpeople.errors import PoseUnavailableError
from laserpeople.scan import Pose2D
from laserpeople.tracking import synthetic as syn
from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams
from laserpeople.tracks import Detections, Tracks


def run(tracker: LegMHTTracker, dets: list[Detections]) -> list[Tracks]:
    return [tracker.update(d) for d in dets]


def person_mota(truth_legs: np.ndarray, outs: list[Tracks], gate: float = 0.5) -> float:
    """A small CLEAR-MOT count for people: truth = midpoint of the legs (T, P, 2, 2)."""
    misses = fps = switches = total = 0
    last: dict[int, int] = {}
    for k, out in enumerate(outs):
        people = truth_legs[k].mean(axis=1)
        tracks = out.of_kind("person")
        pos = np.array([t.position for t in tracks]).reshape(-1, 2)
        d = (
            np.linalg.norm(people[:, None] - pos[None], axis=2)
            if len(pos)
            else np.empty((len(people), 0))
        )
        used: set[int] = set()
        for p in np.argsort(d.min(axis=1) if d.shape[1] else np.zeros(len(people))):
            total += 1
            cand = (
                [j for j in np.argsort(d[p]) if d[p, j] < gate and j not in used]
                if d.shape[1]
                else []
            )
            if not cand:
                misses += 1
                continue
            j = int(cand[0])
            used.add(j)
            if int(p) in last and last[int(p)] != tracks[j].track_id:
                switches += 1
            last[int(p)] = tracks[j].track_id
        fps += len(tracks) - len(used)
    return 1.0 - (misses + fps + switches) / total


@pytest.mark.parametrize("policy", ["arras", "tracks"])
def test_two_walkers_tracked_as_people(policy: str) -> None:
    scene = syn.make_scene(
        [syn.line_path((2.0, -2.0), (0.05, 0.8)), syn.line_path((5.0, 2.0), (0.0, -0.6))],
        12.0,
        seed=2,
    )
    tracker = LegMHTTracker(LegTrackerParams(people_policy=policy))
    outs = run(tracker, scene.detections)
    assert all(o.frame == "sensor" for o in outs)
    assert len(outs[-1].of_kind("person")) == 2
    for person in outs[-1].of_kind("person"):
        assert len(person.members) == 2 if policy == "arras" else 1 <= len(person.members) <= 2
        assert set(person.members) <= {t.track_id for t in outs[-1].of_kind("leg")}
    assert person_mota(scene.legs[30:], outs[30:]) > 0.8
    layer = tracker.people if tracker.person_tracks is None else tracker.person_tracks
    assert tracker.labels.approved == layer.approved_legs
    assert len(tracker.labels.approved) == 4


def test_world_frame_with_moving_sensor() -> None:
    """Detections from a sensor moving along x: tracks in the world frame stay put."""
    scene = syn.make_scene([syn.line_path((3.0, 0.0), (0.0, 0.0))], 6.0, seed=1)
    dets = []
    for k, d in enumerate(scene.detections):
        pose = Pose2D(0.1 * k * 0.1, 0.2, 0.1)
        world = d.positions  # the scene is in the world frame; express it in the sensor's
        local = pose.inverse_transform_points(world)
        dets.append(
            Detections(d.stamp, d.scan_index, local, d.covariances, d.scores, "sensor", pose)
        )
    tracker = LegMHTTracker()
    outs = run(tracker, dets)
    assert outs[-1].frame == "world" and outs[-1].sensor_pose == dets[-1].sensor_pose
    legs = outs[-1].of_kind("leg")
    assert len(legs) >= 2
    truth = scene.legs[-1].reshape(-1, 2)
    for t in legs[:2]:
        assert np.min(np.linalg.norm(truth - t.position, axis=1)) < 0.1
    bad = Detections.empty(99.0, 999)
    with pytest.raises(PoseUnavailableError):
        tracker.update(bad)


def test_non_finite_detections_are_counted_and_left_out() -> None:
    tracker = LegMHTTracker()
    pos = np.array([[1.0, 0.0], [np.nan, 1.0]])
    tracker.update(Detections(0.0, 0, pos, np.tile(np.eye(2) * 1e-3, (2, 1, 1)), np.ones(2)))
    assert tracker.dropped_detections == 1


def test_detections_made_non_finite_by_the_sensor_pose_stay_counted() -> None:
    """A scan whose sensor pose holds a NaN: its detections are left out in the world frame
    and stay counted after later scans (the count used to be reset by the next scan)."""
    tracker = LegMHTTracker()
    pos = np.array([[1.0, 0.0], [1.3, 0.0]])
    cov = np.tile(np.eye(2) * 1e-3, (2, 1, 1))
    good, bad = Pose2D(0.0, 0.0, 0.0), Pose2D(math.nan, 0.0, 0.0)
    tracker.update(Detections(0.0, 0, pos, cov, np.ones(2), sensor_pose=good))
    tracker.update(Detections(0.1, 1, pos, cov, np.ones(2), sensor_pose=bad))
    assert tracker.dropped_detections == 2
    tracker.update(Detections(0.2, 2, pos, cov, np.ones(2), sensor_pose=good))
    assert tracker.dropped_detections == 2


def test_nonadaptive_modes_use_one_class() -> None:
    free = LegMHTTracker(LegTrackerParams(adaptive=False))
    appr = LegMHTTracker(LegTrackerParams(adaptive=False, nonadaptive_class="approved"))
    free.labels.approved = appr.labels.approved = frozenset({0})
    from laserpeople.tracking.mht.tracktree import TrackNode

    node = TrackNode(0, 0, -1, np.zeros(4), np.eye(4), 0.0, "new")
    np.testing.assert_allclose(np.exp(free.labels.track_log_probs([node])), [[0.3, 0.63, 0.07]])
    np.testing.assert_allclose(np.exp(appr.labels.track_log_probs([node])), [[0.2, 0.79, 0.01]])
    adaptive = LegMHTTracker()
    other = TrackNode(1, 1, -1, np.zeros(4), np.eye(4), 0.0, "new")
    adaptive.labels.approved = frozenset({0})
    np.testing.assert_allclose(
        np.exp(adaptive.labels.track_log_probs([node, other])),
        [[0.2, 0.79, 0.01], [0.3, 0.63, 0.07]],
    )


def test_every_parameter_settable_from_toml(tmp_path) -> None:  # type: ignore[no-untyped-def]
    text = to_toml(LegTrackerParams())
    path = tmp_path / "p.toml"
    path.write_text(
        text.replace("p_occ_approved = 0.79", "p_occ_approved = 0.8")
        .replace("p_del_approved = 0.01", "p_del_approved = 0.0")
        .replace("p_del_approved = 0.0", "p_del_approved = 0.005")
        .replace("p_det_approved = 0.2", "p_det_approved = 0.195")
        .replace("# mht.k_best unset", "mht.k_best = 7  #")
        .replace("person.window = 10", "person.window = 12")
    )
    p = load_config(LegTrackerParams, path)
    assert p.p_occ_approved == 0.8 and p.mht.k_best == 7 and p.person.window == 12
    assert (
        dataclasses.replace(
            p,
            p_occ_approved=0.79,
            p_del_approved=0.01,
            p_det_approved=0.2,
            mht=LegTrackerParams().mht,
            person=LegTrackerParams().person,
        )
        == LegTrackerParams()
    )


# ----------------------------------------------------------------- simulated scenes (000 Sec. 3.4)


def _sim(name: str, seconds: float) -> tuple[list[Detections], object]:
    from laserpeople.sim.scenarios import run_scenario

    result = run_scenario(name, seconds=seconds, seed=0)
    dets = syn.detections_from_sim(result.scans, result.truth, clutter_probability=0.9)
    return dets, result


def _run_modes(dets: list[Detections], truth: list, modes: dict[str, LegTrackerParams]) -> dict:
    """Per mode: leg tracks created (all, and those born on a person's leg, not on clutter),
    persons created, mean hypotheses, person MOTA (laserpeople.evaluation)."""
    from laserpeople.evaluation import evaluate

    out = {}
    for label, params in modes.items():
        tracker = LegMHTTracker(params)
        tracks, hyps = [], []
        born_on_leg: dict[int, bool] = {}
        for k, d in enumerate(dets):
            frame = tracker.update(d)
            tracks.append(frame)
            hyps.append(tracker.n_hypotheses)
            legs_true = truth[k].leg_positions.reshape(-1, 2)
            for t in frame.of_kind("leg"):
                if t.track_id not in born_on_leg:
                    near = len(legs_true) and np.linalg.norm(legs_true - t.position, axis=1).min()
                    born_on_leg[t.track_id] = bool(len(legs_true)) and float(near) < 0.3
        summary = evaluate(truth, tracks).result().summary()
        out[label] = {
            "legs_created": len(tracker.leg_ids_reported),
            "person_legs_created": sum(born_on_leg.values()),
            "persons_created": tracker.persons_created,
            "mean_hypotheses": float(np.mean(hyps)),
            "max_hypotheses": int(np.max(hyps)),
            "mota": float(summary["mota"]),  # type: ignore[arg-type]
        }
    return out


# the experiments of 000 Sec. 3.4 with 000's people (policy arras)
MODES = {
    "adaptive": LegTrackerParams(people_policy="arras"),
    "free": LegTrackerParams(adaptive=False, people_policy="arras"),
    "approved": LegTrackerParams(
        adaptive=False, nonadaptive_class="approved", people_policy="arras"
    ),
}


@pytest.mark.slow
def test_figure_eight_adaptive_keeps_tracks() -> None:
    """000 Fig. 5: the same two leg tracks over the whole walk (plus clutter tracks); without
    adaptation legs are lost at the turns."""
    dets, result = _sim("figure-eight", 30.0)
    res = _run_modes(dets, result.truth, {k: MODES[k] for k in ("adaptive", "free")})  # type: ignore[attr-defined]
    a, f = res["adaptive"], res["free"]
    assert a["person_legs_created"] == 2 and a["persons_created"] == 1
    assert f["person_legs_created"] > 2 and f["persons_created"] > 1
    assert a["mota"] > 0.9 and a["mota"] > f["mota"] + 0.1


@pytest.mark.slow
def test_turn_on_stance_leg_adaptive_keeps_tracks() -> None:
    """000 Fig. 6: heavy mutual occlusion; the adaptive tracker keeps a near-constant number
    of leg tracks, the non-adaptive one keeps creating new ones."""
    dets, result = _sim("turn-on-stance-leg", 20.0)
    res = _run_modes(dets, result.truth, {k: MODES[k] for k in ("adaptive", "free")})  # type: ignore[attr-defined]
    a, f = res["adaptive"], res["free"]
    assert a["person_legs_created"] <= 3
    assert f["person_legs_created"] >= 3 * a["person_legs_created"]
    assert a["mota"] > 0.6 and a["mota"] > f["mota"] + 0.4


@pytest.mark.slow
def test_narrow_corridor_adaptive_beats_nonadaptive() -> None:
    """000 Figs. 8-9: fewer created tracks than without adaptation, far fewer hypotheses than
    the non-adaptive tracker with the approved probabilities, and a better MOTA."""
    dets, result = _sim("narrow-corridor", 40.0)
    res = _run_modes(dets, result.truth, MODES)  # type: ignore[attr-defined]
    a, f, ap = res["adaptive"], res["free"], res["approved"]
    assert a["mota"] > f["mota"] + 0.03  # non-adaptive = free probabilities (000 Sec. 3.4)
    assert a["persons_created"] < f["persons_created"]
    assert a["legs_created"] < f["legs_created"]  # Fig. 8
    assert a["mean_hypotheses"] < ap["mean_hypotheses"]
    assert a["max_hypotheses"] < ap["max_hypotheses"]
    # Fig. 9 with 000's pruning alone (no deletion of tracks unseen for long, issue 16):
    # with the approved probabilities everywhere, clutter tracks then live on for ever
    n_scan_only = {
        k: dataclasses.replace(MODES[k], mht=dataclasses.replace(MODES[k].mht, existence_ratio=0.0))
        for k in ("adaptive", "approved")
    }
    res0 = _run_modes(dets, result.truth, n_scan_only)  # type: ignore[attr-defined]
    assert res0["adaptive"]["mean_hypotheses"] < 0.5 * res0["approved"]["mean_hypotheses"]
    assert ap["mean_hypotheses"] < 0.6 * res0["approved"]["mean_hypotheses"]


def _leg_walks_then_vanishes(tau: float) -> tuple[float, float]:
    """One leg walks along +x at 1 m/s for 2 s (10 Hz), then is unseen for 1 s. Returns the
    last seen x [m] and the reported x of its track at the end [m]. The leg uses the
    *approved* probabilities (as a person's leg would), so it is kept while occluded."""
    kal = dataclasses.replace(LegTrackerParams().kalman, coast_velocity_time=tau)
    params = LegTrackerParams(adaptive=False, nonadaptive_class="approved", kalman=kal)
    tracker = LegMHTTracker(params)
    cov = np.eye(2)[None] * 0.03**2
    last_x = 0.0
    for k in range(21):
        last_x = 1.0 + 0.1 * k
        tracker.update(Detections(0.1 * k, k, np.array([[last_x, 0.5]]), cov, np.ones(1)))
    out = None
    for k in range(21, 31):
        out = tracker.update(
            Detections(0.1 * k, k, np.empty((0, 2)), np.empty((0, 2, 2)), np.empty(0))
        )
    assert out is not None
    legs = out.of_kind("leg")
    assert len(legs) == 1, "the occluded approved leg is kept"
    return last_x, float(legs[0].position[0])


def test_occluded_leg_coasts_at_most_tau_times_speed() -> None:
    tau = LegTrackerParams().kalman.coast_velocity_time
    last_x, x = _leg_walks_then_vanishes(tau)
    # the track's speed is ~1 m/s: it stops about tau * 1 m/s past the last detection
    assert last_x < x < last_x + 1.5 * tau
    # the constant-velocity model of 000 (tau = inf) coasts on for the whole second
    last_x, x_cv = _leg_walks_then_vanishes(float("inf"))
    assert x_cv > last_x + 0.8


def test_leg_unseen_too_long_is_kept_but_not_reported() -> None:
    params = LegTrackerParams(adaptive=False, nonadaptive_class="approved", max_report_unseen=0.5)
    tracker = LegMHTTracker(params)
    cov = np.eye(2)[None] * 0.03**2
    empty = (np.empty((0, 2)), np.empty((0, 2, 2)), np.empty(0))
    for k in range(10):
        out = tracker.update(Detections(0.1 * k, k, np.array([[2.0, 0.5]]), cov, np.ones(1)))
    (leg,) = out.of_kind("leg")
    for k in range(10, 14):  # unseen for 0.1 .. 0.4 s: still reported
        out = tracker.update(Detections(0.1 * k, k, *empty))
        assert [t.track_id for t in out.of_kind("leg")] == [leg.track_id]
    out = tracker.update(Detections(1.5, 15, *empty))  # unseen for 0.6 s
    assert out.of_kind("leg") == () and tracker.hidden_tracks == 1
    assert [n.family for n in tracker.mht.best_tracks()] == [leg.track_id]  # still tracked
    out = tracker.update(Detections(1.6, 16, np.array([[2.0, 0.5]]), cov, np.ones(1)))
    assert [t.track_id for t in out.of_kind("leg")] == [leg.track_id]  # back, same id
    assert tracker.hidden_tracks == 0
