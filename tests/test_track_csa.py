"""The Cluster Sorting Algorithm (002 Sec. 2)."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Any

import numpy as np
import pytest

from laserpeople.frame import Frame
from laserpeople.scan import PointSet, Pose2D, Scan
from laserpeople.tracking.csa import (
    ClusterSortingTracker,
    CSAEvent,
    CSAParams,
    coast_people,
    leader_clusters,
    on_a_wall,
    per_person_scores,
    person_first,
    person_groups,
    split_ready,
    viterbi_step,
)

LOG_2PI = math.log(2 * math.pi)


def test_viterbi_step_by_hand() -> None:
    """Two old estimates at x = 0 and x = 1 (position variance 0.01, R = 0.01, so
    S = 0.02 I and the Kalman gain on position is 1/2), path scores 0 and -1.

    - z0 = (0.1, 0) is only in the gate of estimate 0: d2 = 0.5 -> position 0.05.
    - z1 = (0.9, 0) is only in the gate of estimate 1: d2 = 0.5 -> position 0.95,
      score -1 - 0.25 = -1.25.
    - z2 = (0.55, 0) is in both gates (d2 = 15.125 and 10.125 < 16). Path scores:
      0 - 7.5625 = -7.5625 via estimate 0, -1 - 5.0625 = -6.0625 via estimate 1, so the
      Viterbi step continues estimate 1 although its old score is worse; position
      1 + (0.55 - 1) / 2 = 0.775.
    - z3 = (5, 5) is in no gate.
    Scores are shifted so that z0's (-0.25 + const) is 0: [0, -1, -5.8125]. Position
    variance after the update: (1/2)^2 0.01 + (1/2)^2 0.01 = 0.005.
    """
    means = np.array([[0.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]])
    covs = np.array([np.diag([0.01, 0.01, 1.0, 1.0])] * 2)
    z = np.array([[0.1, 0.0], [0.9, 0.0], [0.55, 0.0], [5.0, 5.0]])
    step = viterbi_step(means, covs, np.array([0.0, -1.0]), z, 0.01, 16.0, 10.0)
    assert step.selected.tolist() == [True, True, True, False]
    assert step.predecessor.tolist() == [0, 1, 1]
    assert step.means[:, 0] == pytest.approx([0.05, 0.95, 0.775])
    assert step.means[:, 1:] == pytest.approx(np.zeros((3, 3)))
    assert step.scores == pytest.approx([0.0, -1.0, -5.8125])
    assert step.covs[:, 0, 0] == pytest.approx([0.005] * 3)


def test_viterbi_euclidean_cap_closes_the_gate() -> None:
    means = np.zeros((1, 4))
    covs = np.diag([10.0, 10.0, 1.0, 1.0])[None]
    z = np.array([[0.5, 0.0], [1.5, 0.0]])
    step = viterbi_step(means, covs, np.zeros(1), z, 0.01, 9.21, 1.0)
    assert step.selected.tolist() == [True, False]


def test_leader_clusters_follow_002() -> None:
    # the first estimate opens a sub-cluster; 1.4 m from it joins, 1.6 m does not, and the
    # third point (2.9 m) is within 1.5 m of the second *unassigned* one, not of the first
    pts = np.array([[0.0, 0.0], [1.4, 0.0], [1.6, 0.0], [2.9, 0.0], [10.0, 0.0]])
    assert leader_clusters(pts, 1.5).tolist() == [0, 0, 1, 1, 2]


def test_split_conditions() -> None:
    p = CSAParams()
    three = np.array([[0.0, 0.0], [0.3, 0.0], [3.5, 0.0], [3.6, 0.2], [0.0, 3.5], [0.2, 3.4]])
    ok, labels = split_ready(three, 3, p)
    assert ok and labels.max() == 2
    # condition 1: number of sub-clusters must equal the number of people
    assert not split_ready(three, 2, p)[0]
    # condition 2: every pair more than 3.0 m apart
    close = three.copy()
    close[4:] = [[0.0, 2.5], [0.2, 2.4]]
    assert not split_ready(close, 3, p)[0]


def _blob(centre: tuple[float, float], k: int) -> np.ndarray:
    """Ten points on two legs of a person at ``centre`` (legs 0.2 m apart)."""
    ang = np.linspace(0, np.pi, 5) + 0.1 * k
    out = []
    for dx in (-0.1, 0.1):
        out.append(np.c_[centre[0] + dx + 0.05 * np.cos(ang), centre[1] - 0.05 * np.sin(ang)])
    return np.concatenate(out)


def _frames(
    paths: Sequence[Sequence[tuple[float, float, float]]],
    seconds: float,
    hidden: dict[int, tuple[float, float]] | None = None,
) -> list[Frame]:
    """Frames at 10 Hz of people moving along piecewise-linear (t, x, y) paths; person i is
    not seen during ``hidden[i] = (t0, t1)``."""
    frames = []
    for k in range(int(seconds * 10) + 1):
        t = k / 10
        pts = []
        for i, path in enumerate(paths):
            if hidden and i in hidden and hidden[i][0] <= t < hidden[i][1]:
                continue
            ts = [q[0] for q in path]
            x = np.interp(t, ts, [q[1] for q in path])
            y = np.interp(t, ts, [q[2] for q in path])
            pts.append(_blob((float(x), float(y)), k))
        xy = np.concatenate(pts)
        ps = PointSet(t, xy, np.zeros(len(xy), dtype=np.int64), np.arange(len(xy)))
        frames.append(Frame(k, t, (), "synthetic", "world", None, ps, np.ones(len(xy), dtype=bool)))
    return frames


def _run(frames: list[Frame]) -> tuple[ClusterSortingTracker, list]:
    csa = ClusterSortingTracker()
    return csa, [csa.update(f) for f in frames]


def test_person_person_merge_and_split() -> None:
    a = [(0, -2.5, 3.0), (2, -0.25, 3.0), (4, -0.25, 3.0), (6, -2.5, 3.0)]
    b = [(0, 2.5, 3.0), (2, 0.25, 3.0), (4, 0.25, 3.0), (6, 2.5, 3.0)]
    csa, out = _run(_frames([a, b], 7.0))
    kinds = [e.kind for e in csa.events]
    assert kinds == ["merge person+person", "split"]
    assert csa.events[0].members == (0, 1)
    mid = out[35]  # t = 3.5 s: one cluster, still reported as its two people
    assert not mid.of_kind("group")  # group rows only when asked
    at = {t.track_id: t.position for t in mid.of_kind("person")}
    assert sorted(at) == [0, 1]
    assert np.linalg.norm(at[0] - [-0.25, 3.0]) < 0.15  # each at its own legs
    assert np.linalg.norm(at[1] - [0.25, 3.0]) < 0.15
    asked = ClusterSortingTracker(CSAParams(group_rows=True))
    groups = [asked.update(f) for f in _frames([a, b], 3.5)][-1].of_kind("group")
    assert len(groups) == 1 and groups[0].members == (0, 1)
    end = out[-1].of_kind("person")
    assert sorted(t.track_id for t in end) == [0, 1] and not out[-1].of_kind("group")
    # the split happens only once the two are more than 3.0 m apart
    split_t = csa.events[1].stamp
    assert 2 * (0.25 + (split_t - 4.0) / 2 * 2.25) > 3.0 - 0.4


def test_person_cluster_and_cluster_cluster_merges() -> None:
    # a and b meet at (0, 3); c joins them (person + cluster)
    a = [(0, -2.5, 3.0), (2, -0.25, 3.0), (6, -0.25, 3.0)]
    b = [(0, 2.5, 3.0), (2, 0.25, 3.0), (6, 0.25, 3.0)]
    c = [(0, 0.0, 0.0), (2, 0.0, 0.0), (4, 0.0, 2.6), (6, 0.0, 2.6)]
    csa, _ = _run(_frames([a, b, c], 6.0))
    kinds = [e.kind for e in csa.events]
    assert kinds == ["merge person+person", "merge person+cluster"]
    assert csa.events[-1].members == (0, 1, 2)
    assert list(csa.clusters.values()) == [(0, 1, 2)]
    # two pairs, each merged, then the pairs meet (cluster + cluster)
    p1 = [(0, -4.0, 3.0), (2, -4.0, 2.7), (4, -0.5, 2.7), (6, -0.5, 2.7)]
    p2 = [(0, -4.0, 0.0), (2, -4.0, 2.3), (4, -0.5, 2.3), (6, -0.5, 2.3)]
    q1 = [(0, 4.0, 3.0), (2, 4.0, 2.7), (4, 0.5, 2.7), (6, 0.5, 2.7)]
    q2 = [(0, 4.0, 0.0), (2, 4.0, 2.3), (4, 0.5, 2.3), (6, 0.5, 2.3)]
    csa, _ = _run(_frames([p1, p2, q1, q2], 6.0))
    kinds = [e.kind for e in csa.events]
    assert kinds.count("merge person+person") == 2
    assert kinds[-1] == "merge cluster+cluster"
    assert csa.events[-1].members == (0, 1, 2, 3)


def test_crossing3_end_to_end_with_colour() -> None:
    """002 Sec. 3 on the simulator: the CSA loses nobody on crossing-3, and with the colour
    stage all three people keep their identity after the crossing (permutations where
    002's VBA alone swapped them)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from crossing_common import laser_runs, reidentify, score

    for variant in ("crossing-3-p1", "crossing-3-p3"):
        case = laser_runs(variant, 0, ("csa",), CSAParams(group_rows=True))
        tracks = case.tracks["csa"]
        # no track lost: 3 people at the end, and the cluster held all three
        assert len(tracks[-1].of_kind("person")) == 3
        assert max(len(g.members) for t in tracks for g in t.of_kind("group")) == 3
        on = score(case, reidentify(case, "csa"))
        assert on.correct == (3,), variant


def test_a_person_lost_in_the_cluster_is_adopted_at_the_split() -> None:
    """002 Sec. 4: a person who walks away unseen (in the others' shadow) is lost by the VBA
    and found again as a new target. The cluster, short of one sub-cluster, splits with that
    target once all are 3 m apart, and the target takes the cluster's third person.
    Without coast_people: with it, person 2's paths coast 1 s, its orphan then claims a leg
    of person 1 that leader clustering cut apart, person 0 leaves first (split_apart) and
    the split of the other two gives 1 and 2 each other's places (docs/csa.md, "What it
    cannot do")."""
    a = [(0, -2.5, 3.0), (2, -0.3, 3.0), (5, -0.3, 3.0), (7, -2.2, 3.0), (9, -2.2, 3.0)]
    b = [(0, 2.5, 3.0), (2, 0.3, 3.0), (5, 0.3, 3.0), (7, 2.2, 3.0), (9, 2.2, 3.0)]
    c = [(0, 0.0, 0.5), (2, 0.0, 2.5), (4, 0.0, 2.5), (6, 0.0, -0.5), (9, 0.0, -0.5)]
    frames = _frames([a, b, c], 9.0, hidden={2: (4.0, 5.5)})
    csa = ClusterSortingTracker(CSAParams(coast_people=False))
    out = [csa.update(f) for f in frames]
    assert [e.kind for e in csa.events][-1] == "split"
    assert csa.events[-1].members == (0, 1, 2)
    assert sorted(t.track_id for t in out[-1].of_kind("person")) == [0, 1, 2]
    # without the extension the cluster never splits
    plain = ClusterSortingTracker(
        CSAParams(adopt_escaped=False, adopt_orphans=False, group_rows=True, coast_people=False)
    )
    last = [plain.update(f) for f in frames][-1]
    assert last.of_kind("group") and "split" not in [e.kind for e in plain.events]


def test_two_people_crossing_in_one_cluster_keep_rows_and_ids() -> None:
    """Two people walk past each other 0.5 m apart (a along y = 3.0 to the right, b along
    y = 3.5 to the left): their gates share points, they merge into one cluster and split
    again 3 m apart on the other's side. 002 keeps each person's identity through the
    cluster: in every scan from the second (a new target is reported once confirmed,
    confirm_scans = 2) both person rows are reported, each within 0.3 m of its own
    person, with the ids they started with. A tracker that reports the cluster as one group
    (no person rows while merged) or hands out ids at the split by where people were last
    seen apart (swapped here) fails."""
    a = [(0, -3.0, 3.0), (8, 3.0, 3.0)]
    b = [(0, 3.0, 3.5), (8, -3.0, 3.5)]
    csa, out = _run(_frames([a, b], 8.0))
    assert [e.kind for e in csa.events] == ["merge person+person", "split"]
    merged = 0
    for k, tracks in enumerate(out):
        t = k / 10
        truth = {
            0: (np.interp(t, [0, 8], [-3.0, 3.0]), 3.0),
            1: (np.interp(t, [0, 8], [3.0, -3.0]), 3.5),
        }
        rows = {x.track_id: x.position for x in tracks.of_kind("person")}
        assert sorted(rows) == ([] if k == 0 else [0, 1]), t
        for pid, xy in truth.items() if k else ():
            assert np.linalg.norm(rows[pid] - xy) < 0.3, (t, pid)
        merged += int(bool(csa.events) and csa.events[0].stamp <= t < csa.events[-1].stamp)
    assert merged >= 20  # the cluster held both for at least 2 s


def test_per_person_scores_by_hand() -> None:
    """Paths of person 7 scored [-3, -1] and of person 9 [-10, -12] become [-2, 0] and
    [0, -2]: each person's best path scores 0."""
    s = per_person_scores(np.array([-3.0, -10.0, -1.0, -12.0]), np.array([7, 9, 7, 9]))
    assert s == pytest.approx([-2.0, 0.0, 0.0, -2.0])


def _many_and_one() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Person 1 with three paths 0.1, 0.45 and 0.45 m from the point z = (0, 0); person 2
    with one path 0.15 m from it and two 5 and 6 m away (outside the gate). Position
    variance 0.04 and R = 0.01, so S = 0.05 I and d2 = d^2 / 0.05."""
    means = np.zeros((6, 4))
    means[:, 0] = [0.1, 0.45, -0.45, 0.15, 5.0, 6.0]
    covs = np.array([np.diag([0.04, 0.04, 1.0, 1.0])] * 6)
    return means, covs, np.array([1, 1, 1, 2, 2, 2])


def test_person_mixture_gives_a_point_to_the_person_whose_paths_explain_it() -> None:
    """By hand, exp(-d2 / 2) of each gating path: person 1 exp(-0.1) = 0.905 and
    exp(-2.025) = 0.132 twice, sum 1.169, over sqrt(3): 0.675; person 2 exp(-0.225) =
    0.799 (its far paths do not gate the point). Person 2 takes the point, through its
    path 3; the Kalman gain is 0.04 / 0.05 = 0.8, so x = 0.15 - 0.8 * 0.15 = 0.03. Near
    misses pick person 1: the best single path (002, origin None: path 0, x = 0.1 - 0.08
    = 0.02), the plain sum (1.169 > 0.799), the mean over all of a person's paths gated
    or not (0.390 > 0.266)."""
    means, covs, origin = _many_and_one()
    z = np.zeros((1, 2))
    step = viterbi_step(means, covs, np.zeros(6), z, 0.01, 9.21, 1.0, origin)
    assert step.predecessor.tolist() == [3]
    assert step.means[0, 0] == pytest.approx(0.03, abs=1e-9)
    plain = viterbi_step(means, covs, np.zeros(6), z, 0.01, 9.21, 1.0)
    assert plain.predecessor.tolist() == [0]
    assert plain.means[0, 0] == pytest.approx(0.02, abs=1e-9)


def test_person_first_keeps_only_the_chosen_persons_paths() -> None:
    """Totals -0.1, -0.1 (person 1, both legs gate the point) and -0.05 (person 2):
    person 1 2 exp(-0.1) / sqrt(2) = 1.280 > exp(-0.05) = 0.951 keeps both paths (near
    misses: the best single path and the mean, 0.905, pick person 2). With person 1's
    second path outside the gate, 0.905 < 0.951: person 2 keeps its path."""
    inf = -np.inf
    origin = np.array([1, 1, 2])
    out = person_first(np.array([[-0.1], [-0.1], [-0.05]]), origin)
    assert out[:, 0].tolist() == [-0.1, -0.1, inf]
    out = person_first(np.array([[-0.1], [inf], [-0.05]]), origin)
    assert out[:, 0].tolist() == [inf, inf, -0.05]


def test_crossing3_identities_through_the_crossing_with_colour() -> None:
    """crossing-3 123 -> 213 (seed 7; both lasers, the simulator's foreground): the CSA's
    person rows for everyone inside the cluster plus colour re-identification keep IDF1
    at or above 0.95 over the whole run (group rows instead of people, or ids guessed at
    the split, gave 0.77)."""
    import sys
    from pathlib import Path

    from laserpeople.evaluation import evaluate

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from crossing_common import laser_runs, reidentify

    case = laser_runs("crossing-3-p2", 7, ("csa",))
    summary = evaluate(case.result.truth, reidentify(case, "csa")).result().summary()
    assert summary["idf1"] >= 0.95


def test_targets_started_together_that_merge_at_once_are_one_person() -> None:
    """Four blobs 0.7 m apart appear in one scan (a burst of foreground, e.g. a moving
    laser whose static world model is dropped): four targets start, their gates share
    points and they merge in the next scan. Younger than fragment_age (1 s), they are
    fragments of the oldest: one person. With fragment_age = 0 they are four people. In
    the first scan none is reported yet (confirm_scans = 2). Without count_people the
    cluster stays one person; with it (the default), the three person-sized groups
    nobody holds, seen for count_seconds (1 s), are counted as its people from then on."""
    paths = [[(0, 0.7 * i, 3.0), (10, 0.7 * i, 3.0)] for i in range(4)]
    frames = _frames(paths, 2.0)
    alone = ClusterSortingTracker(CSAParams(count_people=False))
    counts = [len(alone.update(f).of_kind("person")) for f in frames]
    assert counts[0] == 0 and counts[1:] == [1] * (len(frames) - 1)
    assert list(alone.clusters.values()) == [(0,)]
    every = ClusterSortingTracker(CSAParams(fragment_age=0.0, count_people=False))
    assert [len(every.update(f).of_kind("person")) for f in frames] == [0] + [4] * (len(frames) - 1)
    assert list(every.clusters.values()) == [(0, 1, 2, 3)]
    counted = ClusterSortingTracker()
    counts = [len(counted.update(f).of_kind("person")) for f in frames]
    # merged in scan 1, the free groups first seen there, counted 1 s later (scan 11)
    assert counts == [0] + [1] * 10 + [4] * 10
    assert [len(m) for m in counted.clusters.values()] == [4]


def _standing(
    people: Sequence[Callable[[int], tuple[float, float] | None]], scans: int
) -> list[Frame]:
    """Frames at 10 Hz of people, each at ``person(k)`` in scan k (None: not seen)."""
    frames = []
    for k in range(scans):
        pts = [_blob(xy, k) for xy in (person(k) for person in people) if xy is not None]
        xy = np.concatenate(pts)
        ps = PointSet(k / 10, xy, np.zeros(len(xy), dtype=np.int64), np.arange(len(xy)))
        frames.append(
            Frame(k, k / 10, (), "synthetic", "world", None, ps, np.ones(len(xy), dtype=bool))
        )
    return frames


def test_a_new_target_is_reported_once_seen_in_confirm_scans_in_a_row() -> None:
    """A person seen in every scan is reported from its second scan (confirm_scans = 2,
    from the third with 3); a blob seen every other scan (clutter that flickers) is tracked
    but never reported: each miss before confirmation starts the count again. With
    confirm_scans = 1 (002) both are reported at once."""
    frames = _standing([lambda k: (0.0, 3.0), lambda k: None if k % 2 else (3.0, 3.0)], 20)

    def ids(params: CSAParams) -> list[list[int]]:
        csa = ClusterSortingTracker(params)
        return [sorted(t.track_id for t in csa.update(f).of_kind("person")) for f in frames]

    assert ids(CSAParams()) == [[]] + [[0]] * 19
    assert ids(CSAParams(confirm_scans=3)) == [[], []] + [[0]] * 18
    assert ids(CSAParams(confirm_scans=1)) == [[0, 1]] * 20


def test_a_confirmed_target_missed_for_a_scan_stays_reported() -> None:
    """Confirmation is earned once: a person confirmed in scans 0-1 and not seen in scan 5
    (within ``max_unseen``) is reported in scan 5 at its prediction and after it, with
    the id it had (a tracker that restarts the count on every miss hides it for scans
    5-6). A person seen throughout is reported from scan 1 on."""
    frames = _standing([lambda k: (0.0, 3.0), lambda k: None if k == 5 else (3.0, 3.0)], 12)
    assert CSAParams().max_unseen >= 0.1
    csa = ClusterSortingTracker(CSAParams(confirm_scans=2))
    ids = [sorted(t.track_id for t in csa.update(f).of_kind("person")) for f in frames]
    assert ids == [[]] + [[0, 1]] * 11


def test_a_target_unseen_for_max_unseen_is_kept_unreported_for_lost_keep() -> None:
    """lost_keep (0.5 s): a person (target 1) beside one seen throughout (target 0) is not
    seen in scans 5-17 (last seen at 0.4 s, back at 1.8 s, 1.4 s later). It is reported
    while unseen for at most max_unseen (1 s: scans 5-13; scan 14 sits on the limit),
    not in scans 15-17, and from scan 18 on again as target 1, at once. With
    lost_keep = 0 (deleted at 1 s) it comes back as a new target 2, reported from scan 19
    (confirm_scans 2); unseen for 2.1 s (longer than max_unseen + lost_keep) it is a new
    target 2 with the default too."""

    def frames(back: int) -> list[Frame]:
        return _standing(
            [lambda k: (0.0, 3.0), lambda k: None if 5 <= k < back else (3.0, 3.0)], 40
        )

    assert CSAParams().max_unseen + CSAParams().lost_keep == pytest.approx(1.5)
    kept = _reported(frames(18), CSAParams())
    assert kept[1:14] == [[0, 1]] * 13
    assert kept[15:18] == [[0]] * 3
    assert kept[18:] == [[0, 1]] * 22
    deleted = _reported(frames(18), CSAParams(lost_keep=0.0))
    assert deleted[15:19] == [[0]] * 4
    assert deleted[19:] == [[0, 2]] * 21
    too_long = _reported(frames(25), CSAParams())
    assert too_long[15:26] == [[0]] * 11
    assert too_long[26:] == [[0, 2]] * 14
    assert CSAParams.paper_preset["lost_keep"] == 0.0
    with pytest.raises(ValueError, match="lost_keep"):
        CSAParams(lost_keep=-0.1)


def _jump_then_back(gap: int, back: int, points: int = 10, missed: int = -1) -> list[Frame]:
    """Target 0 stands at (0, 3); person 1 stands at (3, 3), seen from scan 0 (not in scan
    ``missed``), unseen in scans ``gap`` to ``back`` - 1; in scan ``gap`` + 2 only, a blob
    (someone else) shows 0.7 m aside, at (3.7, 3). From scan ``back`` on person 1's blob is
    there again, with only its first ``points`` points in scan ``back``. 10 Hz."""
    frames = _standing(
        [
            lambda k: (0.0, 3.0),
            lambda k: None if gap <= k < back or k == missed else (3.0, 3.0),
            lambda k: (3.7, 3.0) if k == gap + 2 else None,
        ],
        back + 8,
    )
    f = frames[back]
    assert f.points is not None
    xy = np.r_[_blob((0.0, 3.0), back), _blob((3.0, 3.0), back)[:points]]
    ps = PointSet(f.stamp, xy, np.zeros(len(xy), dtype=np.int64), np.arange(len(xy)))
    frames[back] = replace(f, points=ps, foreground=np.ones(len(xy), dtype=bool))
    return frames


def _person_1(frames: list[Frame], params: CSAParams) -> list[tuple[int, float] | None]:
    """Per scan: the id and x [m] of the person track nearest (3, 3) other than target 0."""
    csa = ClusterSortingTracker(params)
    out: list[tuple[int, float] | None] = []
    for f in frames:
        rows = [t for t in csa.update(f).of_kind("person") if t.track_id != 0]
        near = min(rows, key=lambda t: abs(t.position[0] - 3.0), default=None)
        out.append(None if near is None else (near.track_id, float(near.position[0])))
    return out


def test_jump_back_a_steady_target_that_jumped_onto_a_blob_gets_its_person_back() -> None:
    """jump_back: target 1, seen in every scan from 0.0 to 0.7 s (jump_back_seen 0.5 s),
    unseen for 0.2 s, takes the blob of scan 10 (0.7 m aside, more than init_distance
    0.6 m from its prediction: a jump) and runs off (x > 4.0 m in scan 12). Its person's
    points, back in scan 13 inside the gate of its state before the jump and selected by
    nobody, continue it: id 1 at x 3.0 +- 0.05 m from scan 13 on. Without the setting (002,
    the paper preset) they start target 2, reported from scan 14. Not for fewer than
    min_points (3) points in scan 13 (they could not start a target either: id 1 runs on),
    nor once the state before the jump was last seen more than max_unseen (1 s) ago (back
    in scan 19, 1.2 s later: a new target 2)."""
    p = CSAParams()
    assert p.min_points == 3 and p.max_unseen == pytest.approx(1.0)
    assert p.jump_back_seen == pytest.approx(0.5)
    jumped = _person_1(_jump_then_back(8, 13), p)
    assert jumped[12] is not None and jumped[12][0] == 1 and jumped[12][1] > 4.0
    assert all(r is not None and r[0] == 1 for r in jumped[13:])
    assert all(r is not None and abs(r[1] - 3.0) < 0.05 for r in jumped[13:])
    plain = _person_1(_jump_then_back(8, 13), CSAParams(jump_back=False))
    assert plain[13] is not None and plain[13][0] == 1 and plain[13][1] > 4.2
    assert plain[14] == (2, pytest.approx(3.0, abs=0.05))
    assert CSAParams.paper_preset["jump_back"] is False
    two = _person_1(_jump_then_back(8, 13, points=2), p)
    assert two[13] is not None and two[13][0] == 1 and two[13][1] > 4.2
    late = _person_1(_jump_then_back(8, 19), p)
    assert late[20] == (2, pytest.approx(3.0, abs=0.05))


def test_jump_back_not_for_a_target_seen_for_less_than_jump_back_seen() -> None:
    """jump_back_seen: target 1 had points in every scan for 0.4 s only (scans 0-4) before
    its gap, as a target on clutter that flickers: its jump onto the blob of scan 7 is not
    undone, the points back in scan 10 start target 2 (reported from scan 11), as without
    jump_back. With jump_back_seen 0.3 s (below 0.4 s) the target goes back. Seen from
    scan 0 to 7 but not in scan 3, it had points in every scan for 0.3 s (scans 4-7) before
    its gap at scan 8: no jump back either (the time counts from the last missed scan)."""
    short = _person_1(_jump_then_back(5, 10), CSAParams())
    assert short[10] is not None and short[10][0] == 1 and short[10][1] > 4.2
    assert short[11] == (2, pytest.approx(3.0, abs=0.05))
    assert short == _person_1(_jump_then_back(5, 10), CSAParams(jump_back=False))
    lower = _person_1(_jump_then_back(5, 10), CSAParams(jump_back_seen=0.3))
    assert all(r is not None and r[0] == 1 and abs(r[1] - 3.0) < 0.05 for r in lower[10:])
    broken = _person_1(_jump_then_back(8, 13, missed=3), CSAParams())
    assert broken[13] is not None and broken[13][0] == 1 and broken[13][1] > 4.2
    assert broken[14] == (2, pytest.approx(3.0, abs=0.05))
    with pytest.raises(ValueError, match="jump_back_seen"):
        CSAParams(jump_back_seen=-0.1)


def test_a_cluster_unseen_for_max_unseen_is_kept_unreported_for_lost_keep() -> None:
    """lost_keep for a cluster: two people merged at 2 s (targets 1 and 2; target 0 stands
    far off) are not seen from 2.5 to 3.8 s (last seen at 2.4 s). The cluster's people are
    reported for 1 s after they were last seen (scans 25-34), not in scans 35-37, and
    from scan 38 on again as 1 and 2 (002's merge and split, nothing else). Deleted at
    1 s (lost_keep = 0) they come back as new targets."""
    a = [(0, -2.5, 3.0), (2, -0.25, 3.0), (5.5, -0.25, 3.0), (7.5, -2.5, 3.0)]
    b = [(0, 2.5, 3.0), (2, 0.25, 3.0), (5.5, 0.25, 3.0), (7.5, 2.5, 3.0)]
    c = [(0, 0.0, 8.0), (9, 0.0, 8.0)]
    frames = _frames([c, a, b], 9.0, hidden={1: (2.5, 3.8), 2: (2.5, 3.8)})
    csa = ClusterSortingTracker()
    ids = [sorted(t.track_id for t in csa.update(f).of_kind("person")) for f in frames]
    assert [e.kind for e in csa.events] == ["merge person+person", "split"]
    assert ids[25:35] == [[0, 1, 2]] * 10
    assert ids[35:38] == [[0]] * 3
    assert ids[38:] == [[0, 1, 2]] * (len(frames) - 38)
    deleted = _reported(frames, CSAParams(lost_keep=0.0))
    assert all(1 not in r and 2 not in r for r in deleted[35:])
    assert any(len(r) > 1 for r in deleted[38:])


def _on_a_robot(
    robot_speed: float, frame: str = "world", unseen: range = range(0), stands: int = 0
) -> list[Frame]:
    """Frames at 10 Hz of a laser driving along x at ``robot_speed`` [m/s] after standing
    for the first ``stands`` scans; from scan 2 on it sees furniture (a blob that stays at
    (0, 3)) and a person who walks from (3, 3) along x at 1 m/s, except in the scans
    ``unseen`` (world frame points; ``frame`` "sensor" marks a run without poses)."""
    frames = []
    for k in range(22 + stands):
        xy = np.empty((0, 2))
        if k >= 2:
            walker = [] if k in unseen else [_blob((3.0 + (k - 2) / 10, 3.0), k)]
            xy = np.concatenate([_blob((0.0, 3.0), k), *walker])
        ps = PointSet(k / 10, xy, np.zeros(len(xy), dtype=np.int64), np.arange(len(xy)))
        pose = Pose2D(robot_speed * max(k - stands, 0) / 10, 0.0, 0.0)
        fg = np.ones(len(xy), dtype=bool)
        frames.append(Frame(k, k / 10, (), "synthetic", frame, pose, ps, fg))  # type: ignore[arg-type]
    return frames


def _reported(frames: list[Frame], params: CSAParams) -> list[list[int]]:
    csa = ClusterSortingTracker(params)
    return [sorted(t.track_id for t in csa.update(f).of_kind("person")) for f in frames]


def test_on_a_moving_laser_a_target_is_reported_once_it_walked() -> None:
    """moving_travel (0.5 m): once the laser has moved (world frame), a new target is
    reported only after the mean of its points lay 0.5 m from where it started. The
    furniture (target 0) is never reported; the person (target 1, 1 m/s) from the scan
    in which it has walked 0.5 m (scan 5 of 0.1 s; not before scan 4). On a still laser,
    in a run without poses (sensor frame) and with moving_travel = 0 (002, --preset
    paper) both are reported from their second scan (confirm_scans = 2)."""
    moving = _reported(_on_a_robot(0.5), CSAParams())[2:]
    assert all(0 not in ids for ids in moving)
    assert moving[:4] == [[]] * 4
    assert moving[6:] == [[1]] * 14
    both = [[], [], []] + [[0, 1]] * 19
    assert _reported(_on_a_robot(0.0), CSAParams()) == both
    assert _reported(_on_a_robot(0.5, "sensor"), CSAParams()) == both
    assert _reported(_on_a_robot(0.5), CSAParams(moving_travel=0.0)) == both
    assert CSAParams.paper_preset["moving_travel"] == 0.0


def test_furniture_seen_before_the_laser_moved_is_not_reported_once_it_moves() -> None:
    """moving_travel also holds for targets started while the laser still stood (the
    robot's first seconds: the occupancy grid has learned nothing yet). The laser stands
    for 10 scans, then drives at 0.5 m/s (moved more than 0.05 m from scan 12 on). The furniture
    (target 0) is reported from its second scan (3) while the laser stands and not once
    it moved; the person (target 1), who walked 0.5 m by then, is reported throughout.
    Counted only from the scan the laser moved (the rule before), the furniture stays
    reported; with moving_travel = 0 (002) both are reported throughout."""
    frames = _on_a_robot(0.5, stands=10)
    ids = _reported(frames, CSAParams())
    assert ids[3:12] == [[0, 1]] * 9
    assert ids[12:] == [[1]] * 20
    assert _reported(frames, CSAParams(moving_travel=0.0))[3:] == [[0, 1]] * 29


def test_furniture_that_merged_with_a_walker_is_not_reported_after_the_split() -> None:
    """moving_travel holds for a person whatever it merged into or split from: on a laser
    driving at 0.5 m/s, furniture (a blob at (0, 3), target 0) is passed 0.4 m away by a
    walker (1 m/s along y = 3.4, target 1); the two merge into one cluster, which splits
    once they are 3 m apart. The furniture, which never walked, is not reported once the
    laser moved (scan 2): neither as a person of the cluster nor as the single target it
    becomes after the split (the rule once held only for a target started from
    unselected points). The walker is reported from its sixth scan on. With
    moving_travel = 0 (002) the furniture is reported throughout."""
    frames = []
    for k in range(90):
        t = k / 10
        xy = np.concatenate([_blob((0.0, 3.0), k), _blob((-4.0 + t, 3.4), k)])
        ps = PointSet(t, xy, np.zeros(len(xy), dtype=np.int64), np.arange(len(xy)))
        pose = Pose2D(0.5 * t, 0.0, 0.0)
        frames.append(Frame(k, t, (), "synthetic", "world", pose, ps, np.ones(len(xy), bool)))
    csa = ClusterSortingTracker(CSAParams())
    ids = [sorted(t.track_id for t in csa.update(f).of_kind("person")) for f in frames]
    kinds = [e.kind for e in csa.events]
    assert "merge person+person" in kinds and "split" in kinds
    assert all(0 not in row for row in ids[2:])  # the laser moved from scan 2 on
    assert all(1 in row for row in ids[6:])
    plain = _reported(frames, CSAParams(moving_travel=0.0))
    assert all(0 in row for row in plain[1:])


def test_people_who_walk_away_together_from_a_cluster_are_reported() -> None:
    """moving_travel counts a cluster's people as they walk too: on a laser driving at
    0.5 m/s, two people stand 0.9 m apart (targets 0 and 1, not yet walked), one steps
    0.45 m to the other at t = 1-1.5 s (less than moving_travel; the two merge into one
    cluster), and from t = 2 s both walk along x at 1 m/s. Standing, neither is reported;
    from t = 3 s (1 m walked as people of the cluster) both are. Without counting the
    travel of a cluster's people, neither would ever be."""

    def step_y(t: float) -> float:
        return 3.9 - 0.45 * min(max(t - 1.0, 0.0) / 0.5, 1.0)

    frames = []
    for k in range(50):
        t = k / 10
        x = 2.0 + max(t - 2.0, 0.0)
        xy = np.concatenate([_blob((x, 3.0), k), _blob((x, step_y(t)), k)])
        ps = PointSet(t, xy, np.zeros(len(xy), dtype=np.int64), np.arange(len(xy)))
        pose = Pose2D(0.5 * t, 0.0, 0.0)
        frames.append(Frame(k, t, (), "synthetic", "world", pose, ps, np.ones(len(xy), bool)))
    csa = ClusterSortingTracker(CSAParams())
    ids = [sorted(t.track_id for t in csa.update(f).of_kind("person")) for f in frames]
    assert "merge person+person" in [e.kind for e in csa.events]
    assert ids[3:20] == [[]] * 17
    assert ids[30:] == [[0, 1]] * 20


def test_a_person_who_walks_out_of_a_clusters_gates_becomes_a_target() -> None:
    """cut_free: two people stand together (one cluster of people 0 and 1); a third person
    (one leg seen, 5 points) is first seen at t = 3 s right beside them, inside the
    cluster's gates, so the cluster takes its points and no target starts; it then walks
    away to (0, 5.5) and stands. Its points form a sub-cluster that holds no person's main
    paths: it is cut off as a new target, reported there at the end, and the cluster
    keeps its two people at their own legs. Without the rule (002, --preset paper; and
    without count_people, which counts the third person into the cluster instead) the
    cluster holds the third person's points for ever and nobody is reported there."""
    a = [(0, -2.5, 3.0), (2, -0.25, 3.0), (8, -0.25, 3.0)]
    b = [(0, 2.5, 3.0), (2, 0.25, 3.0), (8, 0.25, 3.0)]
    frames = _frames([a, b], 8.0)
    out = []
    for f in frames:
        pts = f.points.points
        if f.stamp >= 3.0:
            y = float(np.interp(f.stamp, [3.0, 5.0], [3.7, 5.5]))
            pts = np.concatenate([pts, _blob((0.0, y), f.index)[:5]])
        ps = PointSet(f.stamp, pts, np.zeros(len(pts), dtype=np.int64), np.arange(len(pts)))
        out.append(replace(f, points=ps, foreground=np.ones(len(pts), dtype=bool)))

    def end(params: CSAParams) -> tuple[ClusterSortingTracker, dict[int, np.ndarray]]:
        csa = ClusterSortingTracker(params)
        last = [csa.update(f) for f in out][-1]
        return csa, {t.track_id: t.position for t in last.of_kind("person")}

    csa, rows = end(CSAParams())
    near_c = [k for k, xy in rows.items() if np.linalg.norm(xy - [0.0, 5.5]) < 0.3]
    assert len(near_c) == 1 and near_c[0] not in (0, 1)
    assert np.linalg.norm(rows[0] - [-0.25, 3.0]) < 0.2
    assert np.linalg.norm(rows[1] - [0.25, 3.0]) < 0.2
    assert (0, 1) in csa.clusters.values()
    _, plain = end(CSAParams(cut_free=False, count_people=False))
    assert all(np.linalg.norm(xy - [0.0, 5.5]) > 0.5 for xy in plain.values())
    assert CSAParams.paper_preset["cut_free"] is False


def _escaped_onto_furniture(robot_speed: float, furniture: float = 5.0) -> list[Frame]:
    """Frames at 10 Hz, 8 s: two people walk towards each other along y = 3 and meet at
    t = 2 s (one cluster); from then on the first stands there and the second is not
    seen (lost in the shadow, 002 Sec. 4); from t = 3 s furniture (a blob at
    (``furniture``, 3)) is seen. The laser drives along x at ``robot_speed``."""
    frames = []
    for k in range(81):
        t = k / 10
        a = (-3.0 + 1.375 * min(t, 2.0), 3.0)
        blobs = [_blob(a, k)]
        if t < 2.0:
            blobs.append(_blob((3.0 - 1.375 * t, 3.0), k))
        if t >= 3.0:
            blobs.append(_blob((furniture, 3.0), k))
        xy = np.concatenate(blobs)
        ps = PointSet(t, xy, np.zeros(len(xy), dtype=np.int64), np.arange(len(xy)))
        pose = Pose2D(robot_speed * t, 0.0, 0.0)
        frames.append(Frame(k, t, (), "synthetic", "world", pose, ps, np.ones(len(xy), bool)))
    return frames


def _person_1_at(
    frames: list[Frame], params: CSAParams, place: tuple[float, float], event: str
) -> list[bool]:
    """Per frame, whether the CSA reports person 1 within 0.3 m of ``place`` [m]; the run
    must hold an ``event`` (the way person 1's identity went to the furniture)."""
    csa = ClusterSortingTracker(params)
    rows = []
    for f in frames:
        out = {t.track_id: t.position for t in csa.update(f).of_kind("person")}
        rows.append(1 in out and bool(np.linalg.norm(out[1] - np.asarray(place)) < 0.3))
    assert event in [e.kind for e in csa.events]
    return rows


def test_on_a_moving_laser_furniture_that_takes_a_lost_persons_id_is_not_reported() -> None:
    """moving_travel holds for the target that continues a person (adopt_escaped,
    adopt_orphans): person 1, lost inside the cluster of people 0 and 1, is taken to be
    the target started on the furniture, 5 m away (the cluster splits). On a laser
    driving at 0.5 m/s that target never walked, so person 1 is not reported there (it
    was, at once, before: its identity had walked). On a still laser and with
    moving_travel = 0 (002) person 1 is reported at the furniture after the split."""

    def at_furniture(frames: list[Frame], params: CSAParams) -> list[bool]:
        return _person_1_at(frames, params, (5.0, 3.0), "split")

    assert not any(at_furniture(_escaped_onto_furniture(0.5), CSAParams()))
    assert all(at_furniture(_escaped_onto_furniture(0.0), CSAParams())[40:])
    plain = CSAParams(moving_travel=0.0)
    assert all(at_furniture(_escaped_onto_furniture(0.5), plain)[40:])


def test_on_a_moving_laser_furniture_that_adopts_an_orphan_is_not_reported() -> None:
    """As above with adopt_orphans: the furniture, 1.2 m from the cluster, is started
    beside it and 0.95 m from where person 1 was last estimated, so person 1 (whose paths
    all died) takes it. On a laser driving at 0.5 m/s person 1 is not reported there
    (person 1 walks past that place before the meeting, scans 11-15); on a still laser
    and with moving_travel = 0 it is, once adopted."""

    def at_furniture(frames: list[Frame], params: CSAParams) -> list[bool]:
        return _person_1_at(frames, params, (1.2, 3.0), "adopt orphan")[30:]

    assert not any(at_furniture(_escaped_onto_furniture(0.5, 1.2), CSAParams()))
    assert all(at_furniture(_escaped_onto_furniture(0.0, 1.2), CSAParams())[10:])
    plain = CSAParams(moving_travel=0.0)
    assert all(at_furniture(_escaped_onto_furniture(0.5, 1.2), plain)[10:])


def _wall(x0: float, x1: float, y: float = 5.0) -> np.ndarray:
    """Returns every 0.05 m along a straight wall y = ``y`` from ``x0`` to ``x1`` [m]."""
    xs = np.arange(x0, x1 + 1e-9, 0.05)
    return np.c_[xs, np.full(len(xs), y)]


def test_on_a_wall_by_hand() -> None:
    """A target on a 4 m wall is on it; on a 0.9 m one not for a length of 1 m (for
    0.8 m it is); a person's two legs alone are not (their points span 0.3 m), nor legs
    0.3 m in front of the wall (their own points, legs and wall, lie on no line)."""
    wall = _wall(-2.0, 2.0)
    assert on_a_wall(np.array([0.0, 5.0]), wall, 1.0)
    short = _wall(-0.45, 0.45)
    assert not on_a_wall(np.array([0.0, 5.0]), short, 1.0)
    assert on_a_wall(np.array([0.0, 5.0]), short, 0.8)
    legs = _blob((0.0, 5.0), 0)
    assert not on_a_wall(np.array([0.0, 4.97]), legs, 1.0)
    front = np.concatenate([_blob((0.0, 4.7), 0), wall])
    assert not on_a_wall(np.array([0.0, 4.68]), front, 1.0)


def test_on_a_moving_laser_a_target_sliding_along_a_wall_is_not_reported() -> None:
    """moving_wall (1 m): on a laser driving along x at 0.5 m/s, the foreground holds a
    0.3 m piece of a 12 m wall (y = 5) that moves with the view at 0.5 m/s (the leg
    detector's hits on a wall), and a person walking at 1 m/s along y = 4. The piece's
    target walks 0.5 m in a second but sits on the wall, so it is not reported once the
    laser moved (scan 2); the person is, from scan 6 on. With moving_wall = 0 the piece
    is reported once it slid 0.5 m."""
    frames = []
    for k in range(40):
        t = k / 10
        wall = _wall(-4.0, 8.0)
        piece = np.abs(wall[:, 0] - 0.5 * t) <= 0.15
        person = _blob((-2.0 + t, 4.0), k)
        xy = np.concatenate([wall, person])
        fg = np.r_[piece, np.ones(len(person), dtype=bool)]
        ps = PointSet(t, xy, np.zeros(len(xy), dtype=np.int64), np.arange(len(xy)))
        pose = Pose2D(0.5 * t, 0.0, 0.0)
        frames.append(Frame(k, t, (), "synthetic", "world", pose, ps, fg))

    def rows(params: CSAParams) -> list[dict[int, np.ndarray]]:
        csa = ClusterSortingTracker(params)
        return [{t.track_id: t.position for t in csa.update(f).of_kind("person")} for f in frames]

    def on_wall(row: dict[int, np.ndarray]) -> bool:
        return any(abs(xy[1] - 5.0) < 0.2 for xy in row.values())

    def on_person(row: dict[int, np.ndarray], k: int) -> bool:
        return any(np.linalg.norm(xy - [-2.0 + k / 10, 4.0]) < 0.2 for xy in row.values())

    kept = rows(CSAParams())
    assert not any(on_wall(r) for r in kept[2:])  # the laser moved from scan 2 on
    assert all(on_person(r, k) for k, r in enumerate(kept) if k >= 6)
    plain = rows(CSAParams(moving_wall=0.0))
    assert all(on_wall(r) for r in plain[12:])
    assert CSAParams.paper_preset["moving_wall"] == 0.0


def test_on_a_moving_laser_a_target_unseen_for_moving_unseen_is_not_reported() -> None:
    """moving_unseen (0.3 s): on a moving laser with poses, the walker (target 1, reported
    from scan 8 once it walked) is not seen in scans 12-17: it is reported while unseen
    for at most 0.3 s (scans 12-14, last seen in scan 11), not in scans 15-17, and again,
    with the same id, once seen in scan 18 (it is tracked on until max_unseen, 1 s). On a
    still laser, without poses and with moving_unseen = 0 (002) it is reported throughout."""
    hidden = range(12, 18)
    moving = _reported(_on_a_robot(0.5, unseen=hidden), CSAParams())
    assert [1 in ids for ids in moving[8:]] == [True] * 7 + [False] * 3 + [True] * 4
    for frames, params in (
        (_on_a_robot(0.0, unseen=hidden), CSAParams()),
        (_on_a_robot(0.5, "sensor", unseen=hidden), CSAParams()),
        (_on_a_robot(0.5, unseen=hidden), CSAParams(moving_unseen=0.0, moving_travel=0.0)),
    ):
        assert all(1 in ids for ids in _reported(frames, params)[3:])
    assert CSAParams.paper_preset["moving_unseen"] == 0.0


def _cli_run(tmp_path, params: CSAParams, frames: int | None = None, static=None):  # type: ignore[no-untyped-def]
    """crossing-3-p1, seed 7, as ``laserpeople track --tracker csa --appearance on`` runs
    it (the front laser, ``--background auto``; ``static``: the static world models'
    parameters, None: defaults): the truth and the pipeline's steps."""
    from itertools import islice

    from laserpeople.io import open_recording
    from laserpeople.pipeline import build
    from laserpeople.sim.scenarios import run_scenario

    path = run_scenario("crossing-3-p1", seed=7).write(tmp_path / "p1.npz")
    pipe = build(path, tracker="csa", params=params, reidentify=True, static_world=static)
    steps = list(islice(pipe, frames))
    return list(open_recording(path).truth()), steps, pipe


def test_people_standing_while_the_background_learns_are_tracked_from_the_start(
    tmp_path,  # type: ignore[no-untyped-def]
) -> None:
    """The three people of crossing-3 stand through the first 1.5 s, while the per-beam
    histogram learns. With ``background_people`` their legs are not learned as static: at
    scan 10 (1.0 s) every person has foreground points within 0.4 m and a person row
    within 0.5 m, and the static world model says how many beams it left out; with 002's
    setting (false, the paper preset, which learns only the first seconds:
    ``[auto_background] prelearn`` false) none has a point. With ``prelearn`` the walls the
    whole recording shows behind them make them foreground without ``background_people``
    too."""
    from laserpeople.pipeline.background import (
        AutoBackgroundParams,
        StaticWorldParams,
        background_of,
        describe_background,
    )

    online = StaticWorldParams(auto_background=AutoBackgroundParams(prelearn=False))
    for on in (True, False):
        params = CSAParams(background_people=on)
        truth, steps, pipe = _cli_run(tmp_path, params, frames=25, static=online)
        said = describe_background(background_of(pipe.stages))
        assert ("beams on the leg MHT's people while it learned" in said) is on, said
        frame, tracks = steps[10].frame, steps[10].tracks
        assert frame.points is not None and frame.foreground is not None
        assert tracks is not None
        fg = frame.points.points[frame.foreground]
        rows = np.array([t.position for t in tracks.of_kind("person")]).reshape(-1, 2)
        for xy in truth[10].positions:
            near = int((np.linalg.norm(fg - xy, axis=1) < 0.4).sum())
            assert (near >= 3) if on else (near == 0)
            if on:
                assert np.linalg.norm(rows - xy, axis=1).min() < 0.5
    truth, steps, _ = _cli_run(tmp_path, CSAParams(background_people=False), frames=25)
    frame = steps[10].frame
    assert frame.points is not None and frame.foreground is not None
    fg = frame.points.points[frame.foreground]
    for xy in truth[10].positions:
        assert int((np.linalg.norm(fg - xy, axis=1) < 0.4).sum()) >= 3


def test_crossing3_as_the_cli_runs_it_with_colour(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """crossing-3 123 -> 132 (seed 7) as ``laserpeople track --tracker csa --appearance
    on`` runs it with ``[csa] background_people``: person IDF1 over the whole run at or
    above 0.95 (0.85 without, the people standing while the background learns learned as
    static)."""
    from dataclasses import replace

    from laserpeople.evaluation import evaluate

    truth, steps, _ = _cli_run(tmp_path, CSAParams(background_people=True))
    tracks = [replace(s.tracks, tracks=s.tracks.of_kind("person")) for s in steps if s.tracks]
    assert evaluate(truth, tracks).result().summary()["idf1"] >= 0.95


def test_only_the_csa_asks_for_the_people_of_the_learning_period() -> None:
    """``[csa] background_people`` reaches the pipeline (``learns_behind_people``); it is
    on by default, off under ``--preset paper`` (002 learns no background, 004 every
    frequent range), and for trackers that do not ask for it."""
    from laserpeople.config import load_config
    from laserpeople.pipeline.background import AutoBackground, background_stage
    from laserpeople.pipeline.leg_foreground import learns_behind_people
    from laserpeople.tracking.nearest import NearestNeighbourTracker

    assert learns_behind_people(ClusterSortingTracker())
    assert not learns_behind_people(ClusterSortingTracker(CSAParams(background_people=False)))
    assert not learns_behind_people(ClusterSortingTracker(load_config(CSAParams, None, "paper")))
    assert not learns_behind_people(NearestNeighbourTracker())
    stage = background_stage("auto", behind_people=True)
    assert isinstance(stage, AutoBackground) and stage.learn_people
    plain = background_stage("auto")
    assert isinstance(plain, AutoBackground) and not plain.learn_people


def test_cut_free_starts_a_target_from_min_points_estimates_and_drops_fewer() -> None:
    """cut_free by hand on a cluster of people 0 and 1 (estimates at their legs, 4 each)
    with two far sub-clusters that hold no person's main paths: 3 estimates of person 0's
    paths around (0, 3) (min_points = 3: a new target at their mean, (0, 3.033), started
    next to the cluster) and 2 of person 1's around (3, 0) (fewer: dropped). The cluster keeps
    its 8 leg estimates and nothing else."""
    from laserpeople.tracking.csa.tracker import _Cluster

    legs0 = [(-0.3, 0.0), (-0.1, 0.0), (-0.3, 0.05), (-0.1, 0.05)]
    legs1 = [(0.1, 0.0), (0.3, 0.0), (0.1, 0.05), (0.3, 0.05)]
    far0 = [(-0.1, 3.0), (0.1, 3.0), (0.0, 3.1)]
    far1 = [(3.0, -0.05), (3.0, 0.05)]
    xy = np.array(legs0 + legs1 + far0 + far1)
    origin = np.array([0] * 4 + [1] * 4 + [0] * 3 + [1] * 2)
    means = np.c_[xy, np.zeros((len(xy), 2))]
    cl = _Cluster(
        9, (0, 1), means, np.tile(np.eye(4) * 0.01, (len(xy), 1, 1)), np.zeros(len(xy)), origin, 0.0
    )
    cl.labels = leader_clusters(means[:, :2], 1.5)
    assert int(cl.labels.max()) + 1 == 3  # the legs, (0, 3) and (3, 0)
    csa = ClusterSortingTracker(CSAParams())
    csa._s.next_pid = 5
    out: dict = {}
    csa._cut_free(cl, 2.0, out)
    assert list(out) == [5]
    new = out[5]
    assert np.allclose(new.mean, [0.0, (3.0 + 3.0 + 3.1) / 3, 0.0, 0.0], atol=1e-12)
    assert (new.spawned_by, new.born, new.hits) == (9, 2.0, 1)
    assert np.allclose(cl.means[:, :2], np.array(legs0 + legs1), atol=1e-12)
    assert cl.origin.tolist() == [0] * 4 + [1] * 4
    assert cl.labels.tolist() == [0] * 8


def test_person_groups_by_complete_linkage_by_hand() -> None:
    """Complete linkage at 0.6 m: two legs 0.3 m apart are one group; a chain 0, 0.35,
    0.7 m is two groups (0.35 joins 0 first, then 0.7 is 0.7 m from 0), where single
    linkage would give one; labels in the order of each group's first position."""
    legs = [(0.0, 0.0), (0.3, 0.0)]
    other = [(1.2, 0.0), (1.4, 0.1)]
    assert person_groups(np.array(legs + other + [(0.1, 0.05)]), 0.6).tolist() == [0, 0, 1, 1, 0]
    chain = np.array([(0.0, 0.0), (0.35, 0.0), (0.7, 0.0)])
    assert person_groups(chain, 0.6).tolist() == [0, 0, 1]
    assert person_groups(chain, 0.7).tolist() == [0, 0, 0]
    assert person_groups(chain[::-1], 0.6).tolist() == [0, 0, 1]  # 0.7 and 0.35 first
    assert person_groups(np.zeros((0, 2)), 0.6).tolist() == []


def _with_points(frames: list[Frame], extra: Callable[[Frame], np.ndarray]) -> list[Frame]:
    out = []
    for f in frames:
        pts = np.concatenate([f.points.points, extra(f)])  # type: ignore[union-attr]
        ps = PointSet(f.stamp, pts, np.zeros(len(pts), dtype=np.int64), np.arange(len(pts)))
        out.append(replace(f, points=ps, foreground=np.ones(len(pts), dtype=bool)))
    return out


def test_a_person_who_walks_into_a_groups_gates_is_counted() -> None:
    """count_people: people 0 and 1 stand together (one cluster); a third person walks up
    from (0, 4.6) and stands at (0, 3.8), 0.85 m from each,
    the target started for it merges as a fragment of the cluster's people and their
    paths take its legs (one person's paths end up on two people). One of the three
    person-sized groups then holds nobody's main paths, farther than leg_gap from its
    owner's main group (so not the owner's other leg): once seen for count_seconds it is
    a new person of the cluster, and to the end each of the three has a row of its own
    within 0.2 m. Without the rule (002, --preset paper) two rows stand for three people."""
    a = [(0, -2.5, 3.0), (2, -0.3, 3.0), (8, -0.3, 3.0)]
    b = [(0, 2.5, 3.0), (2, 0.3, 3.0), (8, 0.3, 3.0)]

    def third(f: Frame) -> np.ndarray:
        if f.stamp < 3.0:
            return np.empty((0, 2))
        return _blob((0.0, float(np.interp(f.stamp, [3.0, 4.0], [4.6, 3.8]))), f.index)

    frames = _with_points(_frames([a, b], 8.0), third)

    def rows(params: CSAParams) -> tuple[ClusterSortingTracker, list[dict[int, np.ndarray]]]:
        csa = ClusterSortingTracker(params)
        out = [{t.track_id: t.position for t in csa.update(f).of_kind("person")} for f in frames]
        return csa, out

    places = np.array([(-0.3, 3.0), (0.3, 3.0), (0.0, 3.8)])

    def covered(last: dict[int, np.ndarray]) -> int:
        """How many of the three people have a row of their own within 0.2 m."""
        xy = np.array(list(last.values())).reshape(-1, 2)
        d = np.linalg.norm(xy[:, None] - places[None], axis=-1)
        return int(((d < 0.2).sum(axis=0) == 1).sum())

    csa, seen = rows(CSAParams())
    counted = [e for e in csa.events if e.kind == "count people"]
    assert len(counted) == 1 and counted[0].stamp <= 6.0
    assert all(len(last) == 3 and covered(last) == 3 for last in seen[-15:])
    _, plain = rows(CSAParams(count_people=False))
    assert all(len(last) == 2 and covered(last) < 3 for last in plain[-15:])
    assert CSAParams.paper_preset["count_people"] is False


def test_a_persons_own_legs_and_a_short_glimpse_are_not_counted() -> None:
    """count_people respects legs: people 0 and 1 stand together, person 1 with its legs
    0.45 m apart; at person_width 0.5 each leg is a person-sized group of its own, and the
    leg that holds none of person 1's main paths lies within leg_gap (0.5 m) of them, so
    it may be person 1's other leg: never counted (with leg_gap 0.4 it is). A blob seen
    0.9 m beside them (inside their gates) for 0.5 s (shorter than count_seconds, 1 s)
    is not counted either;
    with count_seconds 0.3 it is."""
    a = [(0, -2.5, 3.0), (2, -0.4, 3.0), (6, -0.4, 3.0)]
    b = [(0, 2.5, 3.0), (2, 0.4, 3.0), (6, 0.4, 3.0)]

    def wide_legs(f: Frame) -> np.ndarray:
        """Person 1 standing at (0.425, 3.0), legs at x = 0.2 and 0.65 (0.45 m apart)."""
        legs = _blob((0.3, 3.0), f.index)
        return np.concatenate([legs[:5], legs[5:] + np.array([0.25, 0.0])])

    def glimpse(f: Frame) -> np.ndarray:
        return _blob((0.0, 3.8), f.index) if 4.0 <= f.stamp < 4.5 else np.empty((0, 2))

    legs = _with_points(_frames([a], 6.0), wide_legs)

    def counted(frames: list[Frame], params: CSAParams) -> list[CSAEvent]:
        csa = ClusterSortingTracker(params)
        for f in frames:
            csa.update(f)
        return [e for e in csa.events if e.kind == "count people"]

    assert counted(legs, CSAParams(person_width=0.5)) == []
    assert len(counted(legs, CSAParams(person_width=0.5, leg_gap=0.4))) == 1
    seen = _with_points(_frames([a, b], 6.0), glimpse)
    assert counted(seen, CSAParams()) == []
    assert len(counted(seen, CSAParams(count_seconds=0.3))) == 1


def test_at_torso_height_a_group_is_counted_after_torso_count_seconds() -> None:
    """torso_count_seconds (0.3 s): at torso height (the pipeline sets at_torso_height) the
    blob seen 0.9 m beside a standing pair for 0.5 s (scans at 4.0-4.4 s) is counted as a
    person of their cluster; with torso_count_seconds 0.45 it is not (0.4 s seen), nor at
    feet height (count_seconds, 1 s)."""
    a = [(0, -2.5, 3.0), (2, -0.4, 3.0), (6, -0.4, 3.0)]
    b = [(0, 2.5, 3.0), (2, 0.4, 3.0), (6, 0.4, 3.0)]

    def glimpse(f: Frame) -> np.ndarray:
        return _blob((0.0, 3.8), f.index) if 4.0 <= f.stamp < 4.5 else np.empty((0, 2))

    seen = _with_points(_frames([a, b], 6.0), glimpse)

    def counted(params: CSAParams, torso: bool) -> list[CSAEvent]:
        csa = ClusterSortingTracker(params)
        csa.at_torso_height = torso
        for f in seen:
            csa.update(f)
        return [e for e in csa.events if e.kind == "count people"]

    assert CSAParams().torso_count_seconds == 0.3
    events = counted(CSAParams(), True)
    assert len(events) == 1 and 4.3 <= events[0].stamp <= 4.4 + 1e-9
    assert counted(CSAParams(torso_count_seconds=0.45), True) == []
    assert counted(CSAParams(), False) == []
    with pytest.raises(ValueError, match="torso_count_seconds"):
        CSAParams(torso_count_seconds=-0.1)


def _drifting(drift: float, seconds: float = 8.0) -> list[Frame]:
    """Frames at 10 Hz of a laser driving along x at 0.5 m/s that sees, from scan 2 on, a
    blob starting at (0, 3) and moving along x at ``drift`` [m/s] (a piece of furniture
    whose centre drifts with the view and the odometry, or a slow walker)."""
    frames = []
    for k in range(int(seconds * 10) + 1):
        xy = np.empty((0, 2))
        if k >= 2:
            xy = _blob((drift * (k - 2) / 10, 3.0), k)
        ps = PointSet(k / 10, xy, np.zeros(len(xy), dtype=np.int64), np.arange(len(xy)))
        fg = np.ones(len(xy), dtype=bool)
        frames.append(Frame(k, k / 10, (), "synthetic", "world", Pose2D(0.05 * k, 0, 0), ps, fg))
    return frames


def test_on_a_moving_laser_travel_must_be_covered_within_moving_window() -> None:
    """moving_window (3 s): a target drifting at 0.1 m/s covers moving_travel (0.5 m) only
    after 5 s, never within 3 s, and is not reported; with moving_window = 0 (from where it
    started, however long ago) it is reported once it lay 0.5 m from its start (5 s after
    it was first seen, scan 52). A walker at 0.3 m/s (0.9 m in 3 s) is reported with the
    window, once it walked 0.5 m (within about 1.7 s of its first scan)."""
    slow = _drifting(0.1)
    assert all(ids == [] for ids in _reported(slow, CSAParams()))
    without = _reported(slow, CSAParams(moving_window=0.0))
    first = next(k for k, ids in enumerate(without) if ids)
    assert 50 <= first <= 54, first
    assert without[first:] == [[0]] * (len(slow) - first)
    walker = _reported(_drifting(0.3), CSAParams())
    first = next(k for k, ids in enumerate(walker) if ids)
    assert 17 <= first <= 21, first
    assert walker[first:] == [[0]] * (len(walker) - first)
    assert CSAParams.paper_preset["moving_travel"] == 0.0  # the window has nothing to act on


@pytest.mark.slow
def test_on_a_moving_torso_height_laser_torso_runs_give_the_people(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """random-groups tuning seed 11 (a robot driving with a laser at 1.12 m among parties
    of people, 30 s) as ``laserpeople track --tracker csa`` runs it: the recording states
    the laser's height, so the foreground keeps torso-shaped runs besides the points near
    leg detections (the "foreground" line says so) and person MOTA reaches 0.35 (0.41;
    0.26 with ``[leg_foreground] torso_blobs = false``, where the leg detector fires on a
    person in under a third of the scans)."""
    from laserpeople.evaluation import evaluate
    from laserpeople.io import open_recording
    from laserpeople.pipeline import build
    from laserpeople.pipeline.background import background_of, describe_foreground
    from laserpeople.sim.scenarios import run_scenario

    path = run_scenario("random-groups", seed=11, seconds=30.0).write(tmp_path / "rg11.npz")
    pipe = build(path, tracker="csa")
    steps = list(pipe)
    said = describe_foreground(background_of(pipe.stages))
    assert "points of torso-shaped runs (the laser sits at torso height, 1.12 m)" in said, said
    tracks = [replace(s.tracks, tracks=s.tracks.of_kind("person")) for s in steps if s.tracks]
    truth = list(open_recording(path).truth())
    assert evaluate(truth, tracks).result().summary()["mota"] >= 0.35


def test_a_walked_person_found_again_next_to_where_it_was_lost_keeps_having_walked() -> None:
    """moving_adopt_near (0.5 m): a person who walked (not held by moving_travel) that is
    continued by a target that has not walked keeps having walked when the target was
    started within 0.5 m of where the person was last estimated (0.3 m: it is the person
    found again), and waits to walk from the target's start when it was started farther
    (1.0 m: furniture near a lost person, as in the orphan test above). A person that had
    not walked either takes the target's start; with 0 every person does."""
    start = (np.array([1.0, 3.0]), 2.0)

    def held(params: CSAParams, last: tuple[float, float], walked: bool = True) -> bool:
        csa = ClusterSortingTracker(params)
        csa._unwalked = {5: start}
        if not walked:
            csa._unwalked[7] = (np.array([-4.0, 3.0]), 0.0)
        csa._adopted(5, 7, np.array(last))
        assert 5 not in csa._unwalked
        if 7 in csa._unwalked:
            assert np.allclose(csa._unwalked[7][0], start[0]) and csa._unwalked[7][1] == 2.0
        return 7 in csa._unwalked

    assert CSAParams().moving_adopt_near == 0.5
    assert not held(CSAParams(), (1.3, 3.0))
    assert not held(CSAParams(), (1.0, 3.5))
    assert held(CSAParams(), (1.0, 3.51))
    assert held(CSAParams(), (2.0, 3.0))
    assert held(CSAParams(), (1.3, 3.0), walked=False)
    assert held(CSAParams(moving_adopt_near=0.0), (1.3, 3.0))


def _legs_seen(
    frames: list[Frame], centres: Callable[[int], list[tuple[float, float]]]
) -> list[Frame]:
    """``frames`` with leg detections (world frame, the frame's pose) at the two legs of each
    person centred at ``centres(k)`` in scan k (legs 0.2 m apart, as ``_blob``)."""
    from laserpeople.tracks import Detections

    out = []
    for k, f in enumerate(frames):
        legs = np.array([(x + dx, y) for x, y in centres(k) for dx in (-0.1, 0.1)]).reshape(-1, 2)
        cov = np.tile(np.eye(2) * 0.01**2, (len(legs), 1, 1))
        dets = Detections(f.stamp, f.index, legs, cov, np.ones(len(legs)), "world", f.sensor_pose)
        out.append(f.with_fields(legs=dets))
    return out


def test_missed_legs_and_unheld_people_by_hand() -> None:
    """missed_legs: a leg with a point exactly 0.2 m away is held, one 0.21 m away is
    missed; unheld_people: a person 0.75 m from an object is held, 0.76 m is not, and of
    two unheld people 0.5 m apart only the first starts a target."""
    from laserpeople.tracking.csa.leg_people import missed_legs, unheld_people

    legs = np.array([[0.0, 0.0], [1.0, 0.0], [5.0, 5.0]])
    pts = np.array([[0.2, 0.0], [1.21, 0.0]])
    np.testing.assert_allclose(missed_legs(pts, legs), [[1.0, 0.0], [5.0, 5.0]], atol=1e-12)
    np.testing.assert_allclose(missed_legs(np.empty((0, 2)), legs), legs, atol=1e-12)
    people = np.array([[0.75, 0.0], [0.0, 0.76], [3.0, 0.0], [3.5, 0.0]])
    got = unheld_people(people, np.array([[0.0, 0.0]]))
    np.testing.assert_allclose(got, [[0.0, 0.76], [3.0, 0.0]], atol=1e-12)


def test_on_a_moving_laser_the_leg_mhts_people_start_targets_and_keep_their_legs() -> None:
    """moving_people: on a laser driving at 0.5 m/s from its first scan, a person who
    comes into view at scan 10 and stands at (3, 3) with both legs detected never walks,
    so moving_travel alone never reports them; the leg MHT confirms them as a person and
    the CSA reports them from a few scans on, for good, with one id. Furniture at (0, 6)
    whose points carry no leg detection starts no target at all. The walker of
    _on_a_robot, whose legs are detected, hidden in scans 12-17 (no points, no
    detections): the leg MHT still holds their legs, which become the CSA's points, so
    the walker stays reported (without the setting it is not while unseen longer than
    moving_unseen)."""
    people = [lambda k: (3.0, 3.0) if k >= 10 else None, lambda k: (0.0, 6.0)]
    stand = _legs_seen(_standing(people, 40), lambda k: [(3.0, 3.0)] if k >= 10 else [])
    stand = [replace(f, sensor_pose=Pose2D(0.05 * k, 0.0, 0.0)) for k, f in enumerate(stand)]
    with_people = _reported(stand, CSAParams())
    assert all(ids == [] for ids in _reported(stand, CSAParams(moving_people=False))[5:])
    assert len(with_people[-1]) == 1
    assert all(ids == with_people[-1] for ids in with_people[20:])
    csa = ClusterSortingTracker()
    for f in stand:
        csa.update(f)
    far = [t for t in csa._s.singles.values() if float(np.hypot(*(t.mean[:2] - (0, 6)))) < 1]
    assert [t.pid for t in far] == [0]  # only the target started before the laser moved
    hidden = range(12, 18)
    walker = _legs_seen(
        _on_a_robot(0.5, unseen=hidden),
        lambda k: [] if k < 2 or k in hidden else [(3.0 + (k - 2) / 10, 3.0)],
    )
    seen = _reported(walker, CSAParams())
    walking = [i for i in seen[8] if i in seen[-1]]
    assert len(walking) == 1
    assert all(walking[0] in ids for ids in seen[8:])
    off = _reported(walker, CSAParams(moving_people=False))
    assert [1 in ids for ids in off[8:]] == [True] * 7 + [False] * 3 + [True] * 4
    assert CSAParams.paper_preset["moving_people"] is False


def test_the_pipeline_hands_the_csas_leg_mht_the_peoples_static_model() -> None:
    """With moving_people the CSA consumes legs and the pipeline hands its leg MHT's
    people layer the static world model of the filter of person tracks on static places
    (one model, fed once per frame; also with that filter off); without the setting the
    CSA reads no legs and runs no leg MHT."""
    from laserpeople.pipeline.background import StaticWorldParams
    from laserpeople.pipeline.recording import tracker_stages
    from laserpeople.pipeline.static_people import PeopleStaticModel
    from laserpeople.pipeline.static_tracks import StaticTrackParams

    csa = ClusterSortingTracker()
    assert "legs" in csa.consumes
    pre, _, hide = tracker_stages(csa)
    models = [s for s in pre if isinstance(s, PeopleStaticModel)]
    assert len(models) == 1 and hide is not None
    assert csa._people is not None
    assert csa._people._tracker.tracker.person_tracks.static_model is models[0]
    off = StaticWorldParams(static_tracks=StaticTrackParams(hide=False))
    csa = ClusterSortingTracker()
    pre, _, hide = tracker_stages(csa, static_world=off)
    models = [s for s in pre if isinstance(s, PeopleStaticModel)]
    assert hide is None and len(models) == 1
    assert csa._people is not None
    assert csa._people._tracker.tracker.person_tracks.static_model is models[0]
    plain = ClusterSortingTracker(CSAParams(moving_people=False))
    assert "legs" not in plain.consumes and plain._people is None


def _still_then_moving(stands: int, step: float = 0.1) -> list[Frame]:
    """Frames at 10 Hz of a laser that stands for ``stands`` scans and then drives along x
    at ``step`` [m] per scan, seeing a person standing at (3, 3) with both legs detected
    from scan 5 on, whose points the foreground lacks, and a blob of furniture at (0, 6)
    without legs (world frame, with a scan so that the leg MHT's people layer watches the
    poses)."""
    frames = _legs_seen(
        _standing([lambda k: (0.0, 6.0)], stands + 15), lambda k: [(3.0, 3.0)] if k >= 5 else []
    )
    out = []
    for k, f in enumerate(frames):
        pose = Pose2D(step * max(k - stands + 1, 0), 0.0, 0.0)
        scan = Scan(f.stamp, 0.0, 0.01, np.full(10, 5.0), pose=pose, index=k)
        out.append(replace(f, scans=(scan,), sensor_pose=pose))
    return out


def test_the_leg_mht_runs_over_the_held_frames_when_the_laser_first_moves() -> None:
    """While the laser stands, LegPeople only holds the frames of the last 2 s (the leg
    MHT is not run: nothing of it is used); when the laser first moves, it tracks the 21
    held frames (0.0-2.0 s before, both ends kept) and then the current one, so its people
    are those of a leg MHT run on every frame from 2 s before, and the person standing
    since scan 5 is confirmed at that moment (one frame alone confirms nobody)."""
    from laserpeople.tracking.csa.leg_people import HOLD_SECONDS, LegPeople

    assert HOLD_SECONDS == 2.0
    frames = _still_then_moving(40)
    held, every, alone = LegPeople(), LegPeople(), LegPeople()
    calls: list[int] = []
    track = held._tracker.update

    def counted(frame: Frame) -> Any:
        calls.append(frame.index)
        return track(frame)

    held._tracker.update = counted  # type: ignore[method-assign]
    for f in frames[:40]:
        held.hold(f)
    assert calls == [] and held.people.shape == (0, 2)
    for f in frames[20:40]:
        every.update(f)
    for f in frames[40:]:
        held.update(f)
        every.update(f)
        np.testing.assert_allclose(held.people, every.people, atol=1e-12)
        np.testing.assert_allclose(held.legs, every.legs, atol=1e-12)
    assert calls[:22] == list(range(19, 41))
    np.testing.assert_allclose(held.people, [[3.0, 3.0]], atol=0.05)
    alone.update(frames[40])
    assert alone.people.shape == (0, 2)


def test_the_leg_mhts_people_layer_measures_motion_from_the_first_frame_held() -> None:
    """The people layer of the held leg MHT is told the robot moved when the laser is
    0.05 m (MotionParams.moved_distance) from the run's first pose, not from the first of
    the frames it tracks: the laser creeps 0.004 m per scan for 15 scans (0.06 m), and
    with 0.5 s held, the first frame tracked is only 0.02 m behind."""
    from laserpeople.tracking.csa.leg_people import LegPeople

    frames = _still_then_moving(1, step=0.004)
    people = LegPeople(hold_seconds=0.5)
    for f in frames[:14]:
        people.hold(f)
    people.update(frames[14])
    assert people._tracker.tracker.person_tracks.moving


def test_the_csa_reports_the_same_with_the_held_frames_as_with_the_leg_mht_on_every_frame() -> None:
    """moving_people: the CSA's tracks on a laser that stands for 4 s and then drives are
    the same whether its leg MHT holds the frames until the laser moves or runs on every
    frame: the person standing since scan 5, whose legs alone are seen, is reported from
    the first moving frame on (the leg MHT confirmed them over the held frames, and their
    legs are the CSA's points), not before; the furniture only while the laser stands (a
    still laser's targets are all reported; once it moves they must walk)."""
    frames = _still_then_moving(40)

    def run(hold: bool) -> list[list[tuple[int, float, float]]]:
        csa = ClusterSortingTracker()
        assert csa._people is not None
        if not hold:
            csa._people.hold = csa._people.update  # type: ignore[method-assign]
        out = []
        for f in frames:
            rows = csa.update(f).of_kind("person")
            out.append([(t.track_id, *np.round(t.position, 9)) for t in rows])
        return out

    held = run(True)
    assert held == run(False)
    assert all([r[0] for r in rows] == [0] for rows in held[1:40])
    for rows in held[40:]:
        assert len(rows) == 1 and math.hypot(rows[0][1] - 3.0, rows[0][2] - 3.0) < 0.1


def _one_walks_off(hide: tuple[float, float] = (7.0, 7.3)) -> list[Frame]:
    """Frames at 10 Hz, 9 s: people 0, 1 and 2 meet at (0, 3) by t = 2 s (one cluster);
    1 and 2 stay there, 0.4 m apart, while 0 walks off along y = 3 at 1 m/s from t = 4 s
    (x = -0.25 - (t - 4)) and is not seen during ``hide``."""
    a = [(0, -3.0, 3.0), (2, -0.25, 3.0), (4, -0.25, 3.0), (9, -5.25, 3.0)]
    b = [(0, 3.0, 3.0), (2, 0.25, 3.0), (9, 0.25, 3.0)]
    c = [(0, 0.0, 6.0), (2, 0.0, 3.4), (9, 0.0, 3.4)]
    return _frames([a, b, c], 9.0, hidden={0: hide})


def test_a_person_apart_from_the_rest_of_its_cluster_leaves_it_with_its_id() -> None:
    """split_apart: of a cluster of three, people 1 and 2 stay together (002's split, which
    needs all three pairwise 3 m apart, never comes) while person 0 walks off. Once its
    sub-cluster's centroid lies more than separation_distance (3 m) from the other's, at
    x about -3.0 + 0.12 (t about 6.6 s: the other sub-cluster's centroid is at x 0.12), it
    leaves the cluster as a single target with id 0, which coasts through the scans
    without points and keeps its id to the end. Without the rule (002) its Viterbi paths
    die while it is unseen and it comes back as a new id; a rule that lets a person leave
    at subcluster_distance (1.5 m) leaves before t = 5.5 s. (With coast_people alone its
    paths coast through the 0.3 s unseen and it keeps id 0 too.)"""
    frames = _one_walks_off()
    csa = ClusterSortingTracker()
    out = [csa.update(f) for f in frames]
    apart = [e for e in csa.events if e.kind == "split apart"]
    assert len(apart) == 1 and apart[0].members == (0,)
    assert 6.5 <= apart[0].stamp <= 6.9  # 3 m apart at t = 6.63 s
    assert list(csa.clusters.values()) == [(1, 2)]
    rows = {t.track_id: t.position for t in out[-1].of_kind("person")}
    assert np.linalg.norm(rows[0] - [-5.25, 3.0]) < 0.3
    assert np.linalg.norm(rows[1] - [0.25, 3.0]) < 0.3
    assert np.linalg.norm(rows[2] - [0.0, 3.4]) < 0.3
    plain = ClusterSortingTracker(CSAParams(split_apart=False, coast_people=False))
    last = [plain.update(f) for f in frames][-1]
    far = [t.track_id for t in last.of_kind("person") if t.position[0] < -4.0]
    assert far and 0 not in far
    assert CSAParams.paper_preset["split_apart"] is False


def test_coast_people_appends_the_predicted_paths_of_people_not_continued() -> None:
    """coast_people at t = 10 s, max_unseen 1 s: the step continued person 1's paths only.
    Person 2 (paths last continued 0.9 s ago) keeps its two predicted estimates, appended
    after the step's in their order; person 3 (1.1 s ago) and person 4 (not in
    ``continued``: counted from the cluster's last scan with measurements, 1.5 s ago) do
    not; the predicted estimate of person 1 is not appended again. ``continued`` of person
    1 becomes 10 s, the others' stay."""
    new = (
        np.array([[0.0, 0.0, 0.1, 0.0]]),
        np.eye(4)[None] * 0.01,
        np.array([0.0]),
        np.array([1]),
    )
    pm = np.arange(20.0).reshape(5, 4)
    predicted = (
        pm,
        np.eye(4)[None].repeat(5, 0) * 0.5,
        np.array([-1.0, -2.0, -3.0, -4.0, -5.0]),
        np.array([1, 2, 3, 2, 4]),
    )
    continued = {1: 9.5, 2: 9.1, 3: 8.9}
    means, covs, scores, origin = coast_people(new, predicted, continued, (10.0, 8.5), 1.0)
    assert origin.tolist() == [1, 2, 2]
    assert means.tolist() == [[0.0, 0.0, 0.1, 0.0], pm[1].tolist(), pm[3].tolist()]
    assert scores.tolist() == [0.0, -2.0, -4.0]
    assert covs[1:, 0, 0] == pytest.approx([0.5, 0.5], abs=1e-12)
    assert continued == {1: 10.0, 2: 9.1, 3: 8.9, 4: 8.5}
    late = {1: 9.5, 2: 9.1, 3: 8.9}  # person 4 counted from 9.2 s: 0.8 s ago
    assert coast_people(new, predicted, late, (10.0, 9.2), 1.0)[3].tolist() == [1, 2, 2, 4]
    # and from then on: 1.1 s later it is not coasted, although the cluster was seen since
    later = coast_people(new, predicted, late, (10.3, 10.2), 1.0)[3].tolist()
    assert later == [1]  # person 2 too: 1.2 s


def test_a_person_of_a_cluster_missed_for_a_moment_keeps_its_id() -> None:
    """coast_people: people 0 and 1 stand 0.6 m apart in one cluster; person 1's points
    are missed for 0.3 s (t = 3.0-3.3 s). Its paths, not continued, are kept predicted, and
    its points, back, continue them: ids 0 and 1 at their places to the end, nobody
    counted. Without the rule (002) its paths end, person 0's paths take its points when
    they come back, and a new person (id 2) is counted there a second later."""
    a = [(0, -2.5, 3.0), (2, -0.3, 3.0), (6, -0.3, 3.0)]
    b = [(0, 2.5, 3.0), (2, 0.3, 3.0), (6, 0.3, 3.0)]
    frames = _frames([a, b], 6.0, hidden={1: (3.0, 3.3)})
    csa = ClusterSortingTracker()
    out = [csa.update(f) for f in frames]
    assert [e.kind for e in csa.events] == ["merge person+person"]
    for k, rows in enumerate(out[30:], 30):
        at = {t.track_id: t.position for t in rows.of_kind("person")}
        assert sorted(at) == [0, 1]
        if k >= 36:  # from 0.3 s after the points are back: each at its own legs
            assert np.linalg.norm(at[0] - [-0.3, 3.0]) < 0.1
            assert np.linalg.norm(at[1] - [0.3, 3.0]) < 0.1
    plain = ClusterSortingTracker(CSAParams(coast_people=False))
    last = [plain.update(f) for f in frames][-1]
    assert sorted(t.track_id for t in last.of_kind("person")) == [0, 2]
    assert CSAParams.paper_preset["coast_people"] is False
