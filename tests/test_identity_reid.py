"""Colour re-identification after crossings (002 Sec. 2) and the simulated camera."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np
import pytest

from laserpeople.frame import Frame
from laserpeople.identity.appearance import hue_histogram
from laserpeople.identity.reid import ColourReidentifier, ReidParams
from laserpeople.sim.camera import CameraParams, SimulatedCamera
from laserpeople.tracks import Track, Tracks

HUES = np.array([0.0, 240.0])  # person 0 red, person 1 blue


def _truth_xy(t: float) -> np.ndarray:
    """Two people 6 m apart walk through each other along x (crossing at t = 5 s) and on."""
    x = -3.0 + 0.6 * t
    return np.array([[x, 2.0 + 0.2 * np.exp(-((t - 5) ** 2))], [-x, 2.0]])


def _run(
    track_ids: Callable[[float], tuple[int, int]],
    group_window: tuple[float, float] | None = None,
    seconds: float = 12.0,
    params: ReidParams | None = None,
    unseen: Callable[[float], tuple[int, ...]] = lambda t: (),
) -> tuple[list[Tracks], list[np.ndarray], ColourReidentifier]:
    """``unseen(t)``: the people whose tracks the tracker does not report at ``t``."""
    cam = SimulatedCamera(CameraParams(miss_probability=0.0), seed=3)
    reid = ColourReidentifier(params)
    outs, truths = [], []
    for k in range(int(seconds * 10)):
        t = k / 10
        xy = _truth_xy(t)
        obs = cam.observe(t, np.array([0, 1]), xy, HUES)
        ids = track_ids(t)
        grouped = group_window is not None and group_window[0] <= t < group_window[1]
        tracks: tuple[Track, ...]
        if grouped:
            tracks = (Track(99, "group", xy.mean(axis=0), np.zeros(2), np.eye(2), 2, members=ids),)
        else:
            tracks = tuple(
                Track(ids[i], "person", xy[i], np.zeros(2), np.eye(2) * 0.01)
                for i in range(2)
                if i not in unseen(t)
            )
        frame = Frame(k, t, (), "synthetic", "world", appearance=obs)
        outs.append(reid.update(Tracks(t, k, tracks), frame))
        truths.append(xy)
    return outs, truths, reid


def _identity_of_person(out: Tracks, xy: np.ndarray, person: int) -> int:
    d = [np.linalg.norm(t.position - xy[person]) for t in out.of_kind("person")]
    return out.of_kind("person")[int(np.argmin(d))].track_id


def test_swapped_tracks_get_their_identities_back() -> None:
    """The tracker swaps its ids while the two cross; the stage restores them."""
    outs, truths, reid = _run(lambda t: (0, 1) if t < 5.0 else (1, 0))
    before = [_identity_of_person(outs[20], truths[20], p) for p in (0, 1)]
    after = [_identity_of_person(outs[-1], truths[-1], p) for p in (0, 1)]
    assert after == before
    # early, while the two are still closer than separation_distance, then the final one
    # once they are apart (002's); both give each track the same identity
    early, final = reid.reassignments
    apart = ReidParams().separation_distance
    assert np.linalg.norm(np.subtract(*_truth_xy(early.stamp))) < apart
    assert np.linalg.norm(np.subtract(*_truth_xy(final.stamp))) > apart
    assert early.assignment == final.assignment == {1: 0, 0: 1}
    # the learnt colours peak where the clothes are: red bin 0, blue bin 4
    assert reid.models[before[0]].mean.argmax() == 0
    assert reid.models[before[1]].mean.argmax() == 4


def test_without_a_swap_nothing_changes() -> None:
    outs, truths, _ = _run(lambda t: (0, 1))
    for k in (20, len(outs) - 1):
        assert [_identity_of_person(outs[k], truths[k], p) for p in (0, 1)] == [0, 1]


def test_new_track_ids_after_the_crossing_take_the_old_identities() -> None:
    """A tracker that loses both people in the crossing and starts new tracks (as the leg
    MHT may): the new tracks are candidates and get the identities back by colour."""
    outs, truths, _ = _run(lambda t: (0, 1) if t < 5.0 else (8, 7))
    before = [_identity_of_person(outs[20], truths[20], p) for p in (0, 1)]
    after = [_identity_of_person(outs[-1], truths[-1], p) for p in (0, 1)]
    assert after == before


def test_a_group_track_holds_its_members_until_it_splits() -> None:
    """A CSA cluster reported as one group track between 4 and 6 s; after it the tracker
    hands the ids out the wrong way round, and colour fixes it."""
    outs, truths, reid = _run(lambda t: (0, 1) if t < 5.0 else (1, 0), group_window=(4.0, 6.0))
    assert any(o.of_kind("group") and o.of_kind("group")[0].members for o in outs)
    before = [_identity_of_person(outs[20], truths[20], p) for p in (0, 1)]
    after = [_identity_of_person(outs[-1], truths[-1], p) for p in (0, 1)]
    assert after == before
    # early re-assignment: at the first clean observation after the group ends (6 s; the
    # colours differ by far more than decision_margin), not only once the two are 3 m
    # apart (7.5 s; the final one, on the next scan, confirms it)
    assert [round(r.stamp, 1) for r in reid.reassignments] == [6.0, 7.6]
    assert reid.reassignments[0].assignment == reid.reassignments[1].assignment


def test_without_the_margin_only_the_final_reassignment_acts() -> None:
    """A decision margin no evidence reaches: no early re-assignment; 002's final one
    once the two are 3 m apart (7.5 s) restores the identities."""
    params = ReidParams(decision_margin=1e12)
    outs, truths, reid = _run(lambda t: (0, 1) if t < 5.0 else (1, 0), params=params)
    assert [round(r.stamp, 1) for r in reid.reassignments] == [7.6]
    k = 70  # 7.0 s: still swapped
    assert [_identity_of_person(outs[k], truths[k], p) for p in (0, 1)] == [1, 0]
    assert [_identity_of_person(outs[-1], truths[-1], p) for p in (0, 1)] == [0, 1]


def test_a_track_seen_alone_is_reidentified_while_the_other_is_missing() -> None:
    """The tracker swaps the two at 5 s and loses person 1 from 5.7 s to 9 s. The track on
    person 0 is re-identified from its own observations (the other identity goes to the
    missing track), and person 1's track comes back with its identity."""
    outs, truths, reid = _run(
        lambda t: (0, 1) if t < 5.0 else (1, 0),
        unseen=lambda t: (1,) if 5.7 <= t < 9.0 else (),
    )
    first = reid.reassignments[0]
    assert 5.7 <= first.stamp < 6.0
    assert first.assignment == {1: 0, 0: 1}
    for k in (60, 85):  # person 0 alone on screen, its identity restored
        assert [t.track_id for t in outs[k].of_kind("person")] == [0]
    assert [_identity_of_person(outs[95], truths[95], p) for p in (0, 1)] == [0, 1]


def test_camera_observations_show_the_clothing_hue() -> None:
    cam = SimulatedCamera(CameraParams(lighting_std=0.0, miss_probability=0.0), seed=0)
    obs = cam.observe(0.0, np.array([4, 5]), np.array([[0.0, 0.0], [5.0, 0.0]]), HUES)
    assert [o.person_hint for o in obs] == [4, 5]
    for o, hue in zip(obs, HUES, strict=True):
        hist = hue_histogram(o.hues, 6)
        assert hist.argmax() == int(hue // 60) and hist.max() > 0.7
        assert np.linalg.norm(o.position - (0.0 if hue == 0 else 5.0) * np.array([1, 0])) < 0.5


def test_camera_misses_leaks_and_lighting() -> None:
    cam = SimulatedCamera(CameraParams(miss_probability=0.5), seed=1)
    seen = sum(
        len(cam.observe(float(k), np.array([0]), np.zeros((1, 2)), HUES[:1])) for k in range(400)
    )
    assert 150 < seen < 250
    # a neighbour at 0.1 m leaks into the region
    close = SimulatedCamera(CameraParams(miss_probability=0.0, lighting_std=0.0), seed=2)
    o = close.observe(0.0, np.array([0, 1]), np.array([[0.0, 0.0], [0.1, 0.0]]), HUES)[0]
    assert hue_histogram(o.hues, 6)[4] > 0.2
    # strong lighting shifts the mean hue of a yellow shirt
    params = CameraParams(miss_probability=0.0, lighting_std=0.4, clutter_fraction=0.0)
    shifts = []
    for seed in range(5):
        c = SimulatedCamera(params, seed=seed)
        h = c.observe(0.0, np.array([0]), np.zeros((1, 2)), np.array([60.0]))[0].hues
        shifts.append(abs(np.rad2deg(np.angle(np.mean(np.exp(1j * h)))) - 60.0))
    assert max(shifts) > 3.0
    assert replace(params, lighting_std=0.0).lighting_std == 0.0


def test_camera_rejects_bad_parameters() -> None:
    with pytest.raises(ValueError):
        CameraParams(miss_probability=1.5)


@pytest.mark.parametrize("crowded_views", [True, False])
def test_a_view_next_to_an_untracked_person_is_not_learnt(crowded_views: bool) -> None:
    """Person 0 (red) is tracked; person 1 (blue) stands 0.5 m away, seen by the camera
    but not tracked. No other track is near, yet the view of person 0 carries blue: with
    ``crowded_views`` it is not clean (nothing learnt); without it, it is learnt."""
    cam = SimulatedCamera(CameraParams(miss_probability=0.0, lighting_std=0.0), seed=5)
    reid = ColourReidentifier(ReidParams(crowded_views=crowded_views))
    xy = np.array([[0.0, 3.0], [0.5, 3.0]])
    for k in range(10):
        obs = cam.observe(k / 10, np.array([0, 1]), xy, HUES)
        frame = Frame(k, k / 10, (), "synthetic", "world", appearance=obs)
        track = Track(7, "person", xy[0], np.zeros(2), np.eye(2) * 0.01)
        reid.update(Tracks(k / 10, k, (track,)), frame)
    model = reid.models[0]
    if crowded_views:
        assert model.k == 0
    else:
        assert model.k == 10
        assert model.mean[4] > 0.1  # the neighbour's blue leaked into what was learnt


def test_an_early_decision_uses_only_identities_with_a_colour_model() -> None:
    """Track 10 holds identity 1 and fits identity 0 better (summed log-likelihoods -20
    against -80: margin 60). Identity 2 has no colour model (no evidence, a log-likelihood
    of 0 would beat both) and is not a candidate. Track 12, not seen, held identity 0 and
    takes the one left over (1); track 11 keeps identity 2."""
    from laserpeople.identity.reid import _Crossing

    reid = ColourReidentifier()
    for _ in range(3):
        reid._fresh()
    for ident in (0, 1):
        for y in (hue_histogram(np.array([0.0]), 6), hue_histogram(np.array([0.1]), 6)):
            reid.models[ident].add(y)
    reid._identity.update({10: 1, 11: 2, 12: 0})
    c = _Crossing({0, 1, 2}, {10, 11, 12}, np.zeros(2))
    c.loglik[10] = {0: -20.0, 1: -80.0}
    c.n_obs[10] = 1
    reid._decide_early(c, [10, 11], 1.0)
    assert reid._identity == {10: 0, 11: 2, 12: 1}
    assert reid.reassignments[-1].assignment == {10: 0, 12: 1}
