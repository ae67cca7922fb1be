"""The split driven by a track's own history (groups/history_split.py): tracing, velocity
modes and the division of contour and history against hand-computed values, and end to
end on a scripted scene of two parties in one cluster walking at different speeds."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from laserpeople.tracking.groups import GroupTrackerParams
from laserpeople.tracking.groups.history_split import (
    HistorySplitSettings,
    divide_contour,
    divide_history,
    mode_velocities,
    trace_velocities,
    velocity_modes,
)
from test_track_groups import _run
from test_track_groups_coherence import _pts


def _history(stamps: list[float]) -> list[tuple[float, np.ndarray]]:
    """Point a at (t, 0) (1 m/s along x), point b standing at (5, 1)."""
    return [(t, _pts(t, 0.0, 5.0, 1.0)) for t in stamps]


def test_trace_follows_each_point_back_and_gives_its_mean_velocity() -> None:
    # now (t = 1.0): a at (1, 0), b at (5, 1); snapshots at 0.2 .. 0.8 s
    history = _history([0.2, 0.4, 0.6, 0.8])
    got = trace_velocities(_pts(1.0, 0.0, 5.0, 1.0), history, 1.0, np.zeros(2), min_age=0.3)
    assert got is not None
    u, age, path = got
    assert age == pytest.approx(0.8)
    # a: (1 - 0.2) / 0.8 = 1 m/s; b: 0
    np.testing.assert_allclose(u, [[1.0, 0.0], [0.0, 0.0]], atol=1e-12)
    assert [t for t, _ in path] == [0.2, 0.4, 0.6, 0.8]
    np.testing.assert_allclose(path[0][1], [[0.2, 0.0], [5.0, 1.0]])
    # the window keeps the snapshots at most 0.5 s old: 0.6 and 0.8 s, a trace of 0.4 s
    got = trace_velocities(_pts(1.0, 0.0), history, 1.0, np.zeros(2), 0.3, window=0.5)
    assert got is not None and got[1] == pytest.approx(0.4)
    np.testing.assert_allclose(got[0], [[1.0, 0.0]], atol=1e-12)
    # no snapshot min_age old: no trace
    assert trace_velocities(_pts(1.0, 0.0), history[-1:], 1.0, np.zeros(2), 0.3) is None
    assert trace_velocities(np.empty((0, 2)), history, 1.0, np.zeros(2), 0.3) is None


def test_trace_moves_back_by_the_velocity_before_matching() -> None:
    """Two points 0.3 m apart on x, both walking at 1 m/s: moved back by the track's
    velocity each point finds itself in the snapshot 0.2 s before (nearest to the raw
    position it would find the other's old position half of the time)."""
    history = [(0.8, _pts(0.8, 0.0, 1.1, 0.0))]
    u, _, _ = trace_velocities(_pts(1.0, 0.0, 1.3, 0.0), history, 1.0, np.array([1.0, 0.0]), 0.1)  # type: ignore[misc]
    np.testing.assert_allclose(u, [[1.0, 0.0], [1.0, 0.0]], atol=1e-12)


SETTINGS = HistorySplitSettings(min_dv=0.5, separation=2.0, min_points=2)


def test_velocity_modes_by_hand() -> None:
    # three blobs: two at 1 m/s (+-0.1 on y), one standing; blob sizes 2, 2, 3
    u = _pts(1.0, 0.1, 1.0, 0.1, 1.0, -0.1, 1.0, -0.1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    blobs = np.array([7, 7, 9, 9, 3, 3, 3])
    modes = velocity_modes(u, blobs, SETTINGS)
    assert modes is not None
    # mode means (1, 0) and (0, 0): dv = 1; spread sqrt(4 * 0.01 / 7) = 0.0756
    assert modes[0] == modes[1] == modes[2] == modes[3] != modes[4] == modes[5] == modes[6]
    np.testing.assert_allclose(mode_velocities(u, modes)[modes[0]], [1.0, 0.0], atol=1e-12)
    # dv 0.4 < min_dv 0.5
    assert velocity_modes(u * 0.4, blobs, SETTINGS) is None
    # separation: blob velocities (1, +-0.45) and (0, 0): dv = 1 against a spread of
    # sqrt(4 * 0.45^2 / 7) = 0.3402, a ratio of 2.94
    wide = u.copy()
    wide[:4, 1] *= 4.5
    assert velocity_modes(wide, blobs, replace(SETTINGS, separation=2.9)) is not None
    assert velocity_modes(wide, blobs, replace(SETTINGS, separation=3.0)) is None
    # a mode of fewer than min_points points
    assert velocity_modes(u, blobs, replace(SETTINGS, min_points=4)) is None
    # one blob, or one velocity: no modes
    assert velocity_modes(u, np.zeros(7, dtype=np.int64), SETTINGS) is None
    assert velocity_modes(np.zeros((7, 2)), blobs, SETTINGS) is None


def test_velocity_modes_keep_a_blob_whole() -> None:
    """A blob's points take the mode of the blob's mean velocity, whatever their own."""
    u = _pts(1.0, 0.0, 1.0, 0.0, 0.4, 0.0, 0.0, 0.0, 0.0, 0.0)
    blobs = np.array([0, 0, 1, 1, 1])  # blob 1: mean 0.133 m/s
    modes = velocity_modes(u, blobs, SETTINGS)
    assert modes is not None
    assert modes[0] == modes[1] != modes[2] == modes[3] == modes[4]


def test_contour_and_history_divided_by_the_nearest_mode() -> None:
    points = _pts(0.0, 0.0, 1.0, 0.0, 3.0, 0.0)
    modes = np.array([0, 0, 1])
    contour = _pts(0.4, 0.0, 1.9, 0.0, 2.1, 0.0, 5.0, 0.0)
    np.testing.assert_array_equal(divide_contour(contour, points, modes), [0, 0, 1, 1])
    assert divide_contour(np.empty((0, 2)), points, modes).size == 0
    history = [(0.0, _pts(9.0, 9.0)), (0.2, _pts(0.1, 0.0, 2.9, 0.0, 2.5, 0.0))]
    path = [(0.2, _pts(0.1, 0.0, 0.1, 0.0, 2.9, 0.0))]  # the 0.0 s snapshot not traced
    half0 = divide_history(history, path, modes, 0)
    half1 = divide_history(history, path, modes, 1)
    assert [t for t, _ in half0] == [0.2] == [t for t, _ in half1]
    np.testing.assert_allclose(half0[0][1], [[0.1, 0.0]])
    np.testing.assert_allclose(half1[0][1], [[2.9, 0.0], [2.5, 0.0]])


def _parties(k: int) -> list[tuple[float, float, int]]:
    """A pair walking at 1.2 m/s beside a pair walking at 0.2 m/s, 0.6 m between their
    nearest members: one cluster at d_P = 1.3 m until they are 1.15 m apart along x
    (scan 12); truth groups 0 and 1."""
    xa, xb = 0.12 * k, 0.02 * k
    return [(xa, 0.0, 0), (xa, 0.6, 0), (xb, 1.2, 1), (xb, 1.8, 1)]


def test_history_split_separates_parties_walking_at_different_speeds_in_one_cluster() -> None:
    """000's splits need two observations: the pairs are one track until scan 12 or
    later. The history split (preset) finds the two velocity modes of the track's one
    observation and splits it while they are one cluster (labels 0-0, 0-1), at about
    half the memory-less clustering error; without it (the coherence term alone, or
    000's setting) the error stays near memory-less clustering's."""
    tracker, history, result, memoryless = _run(
        _parties, 40, params=GroupTrackerParams.history_splitting()
    )
    assert memoryless.under_segmented >= 12
    first_two = next(k for k, out in enumerate(history) if len(out.of_kind("group")) == 2)
    assert first_two < 12
    assert sorted(t.labels for t in history[-1].of_kind("group")) == ["0-0", "0-1"]
    assert "merge" not in [e.kind for e in tracker.events]
    assert result.error <= 0.6 * memoryless.error
    for params in (
        GroupTrackerParams.history_splitting(history_split=False),
        GroupTrackerParams(),
    ):
        _, _, plain, _ = _run(_parties, 40, params=params)
        assert plain.error > 0.8 * memoryless.error


def test_an_event_reported_again_by_another_hypothesis_is_one_event() -> None:
    """Hypotheses that split (merge) the same groups at different scans may take turns as
    the best: the event is recorded once (within N-scan-back scans), a split's two halves
    once."""
    from laserpeople.tracking.groups.tracker import GroupEvent, GroupMHTTracker

    tracker = GroupMHTTracker()
    tracker._record(GroupEvent(1.0, "split", ("0-1-0",)), 10)
    tracker._record(GroupEvent(1.0, "split", ("0-1-1",)), 10)  # the other half
    tracker._record(GroupEvent(1.2, "split", ("0-1-1",)), 12)  # another hypothesis
    tracker._record(GroupEvent(1.1, "split", ("0-0",)), 11)
    assert [e.labels for e in tracker.events] == [("0-1-0",), ("0-0",)]
    tracker._record(GroupEvent(3.0, "split", ("0-1-0",)), 30)  # much later: a new split
    assert len(tracker.events) == 3
    tracker._record(GroupEvent(3.1, "merge", ("0", "1")), 31)
    tracker._record(GroupEvent(3.3, "merge", ("0", "1")), 33)  # another hypothesis' merge
    tracker._record(GroupEvent(3.3, "merge", ("0", "2")), 33)
    assert [e.kind for e in tracker.events] == ["split", "split", "split", "merge", "merge"]


def test_default_is_000s_setting_and_the_history_split_is_a_preset() -> None:
    """The default is 000's setting (the likelihood of eqs. 19-24 alone, splits on two
    observations), also spelled out as paper_likelihood(); the history split with the
    motion coherence over 1 s is the preset history_splitting(); the history split needs
    the snapshots of the coherence term and is off without them."""
    default = GroupTrackerParams()
    assert default == GroupTrackerParams.paper_likelihood()
    assert not default.history_split and default.coherence_lag == 0.0
    assert default.interaction_settings().history_split is None
    preset = GroupTrackerParams.history_splitting()
    assert preset.history_split and preset.coherence_lag == 1.0
    assert preset.interaction_settings().history_split is not None
    lagless = replace(preset, coherence_lag=0.0)
    assert lagless.interaction_settings().history_split is None
    assert GroupTrackerParams.people_only().interaction_settings().history_split is None


def test_history_split_model_makes_halves_of_the_two_motions() -> None:
    """A track (velocity 0.5 m/s, the mean of its parties) whose one observation is a
    party walking at 1 m/s beside one standing, 1.25 m apart: the branch generator offers
    the history split; its halves carry the labels X-0 and X-1, the modes' velocities,
    positions at the means of the contour parts nearest each mode, n/2, must match, and
    the pieces are the two parties' points."""
    from laserpeople.tracking.groups.coherence import CoherentGroupModel
    from laserpeople.tracking.groups.interaction import GroupBranches
    from laserpeople.tracking.groups.model import GroupPayload
    from laserpeople.tracking.groups.observations import GroupObservations
    from laserpeople.tracking.mht.tracktree import TrackNode, TrackTree

    params = GroupTrackerParams.history_splitting()
    ring = 0.08 * np.column_stack(
        [np.cos(np.arange(8) * np.pi / 4), np.sin(np.arange(8) * np.pi / 4)]
    )

    def scene(t: float) -> np.ndarray:
        return np.concatenate([ring + np.array([t, 0.0]), ring + np.array([0.0, 0.6])])

    history = tuple((0.2 * i, scene(0.2 * i)) for i in range(6))  # 0.0 .. 1.0 s
    last = scene(1.0)
    mean = np.array([*last.mean(axis=0), 0.5, 0.0, 2.0])
    node = TrackNode(0, 0, -1, mean, np.eye(5) * 0.01, 1.0, "detected",
                     payload=GroupPayload(last - mean[:2], ("0",), history=history))  # fmt: skip
    model = CoherentGroupModel(params.model_settings(), params.coherence_settings())
    tree = TrackTree()
    tree.new_family()
    branches = GroupBranches(model, tree, params.interaction_settings(), lambda n: ("0",))
    now = scene(1.1)
    obs = GroupObservations.from_points(now, np.arange(16), 1.3, 0.3)
    assert len(obs) == 1
    model.predict([node], 1.1)
    model.scan = obs
    branches.begin_scan(obs, 1.1)
    assert model.coherence_term(node, obs, 0) < 0.0
    split = branches._history_split(node, 0)
    assert split is not None
    walker = next(i for i, h in enumerate(split.halves) if h.mean[2] > 0.5)
    for i, half in enumerate(split.halves):
        payload = half.payload
        assert isinstance(payload, GroupPayload)
        assert payload.labels == (("0-0",), ("0-1",))[i]
        assert payload.must_match and payload.event == "split"
        assert half.mean[4] == pytest.approx(1.0)  # n/2
        # the predicted contour: the last observation moved by 0.05 m (0.5 m/s, 0.1 s)
        part = (last[:8] if i == walker else last[8:]) + (0.05, 0.0)
        np.testing.assert_allclose(half.mean[:2], part.mean(axis=0), atol=1e-9)
        np.testing.assert_allclose(payload.contour + half.mean[:2], part, atol=1e-9)
        speed = 1.0 if i == walker else 0.0
        np.testing.assert_allclose(half.mean[2:4], (speed, 0.0), atol=0.1)
        assert len(payload.history) >= 5  # the snapshots its points were traced through
        pts, _, _, share, _ = split.pieces[i]
        assert share == pytest.approx(0.5)
        np.testing.assert_allclose(
            np.sort(pts, axis=0), np.sort(now[:8] if i == walker else now[8:], axis=0)
        )
    # the model offers it as an event with p_S / p_C
    events = branches._history_events((node,), [1], np.array([0]))
    assert [e.kind for e in events] == ["history"]
    assert events[0].log_ratio == pytest.approx(np.log(params.p_s / params.p_c))
