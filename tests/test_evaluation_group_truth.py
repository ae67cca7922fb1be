"""Group tracks are scored against the truth's groups (each at its members' mean, a person
alone as a group of one), not against its people: ``evaluate`` with kind "group"."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.evaluation import EvaluationParams, evaluate
from laserpeople.evaluation.group_truth import ALONE_ID, group_truth
from laserpeople.tracks import Track, Tracks
from laserpeople.truth import TruthFrame


def _truth(scan: int) -> TruthFrame:
    """Persons 0 and 1 of group 3, 0.8 m apart; person 2 alone 5 m away; world frame."""
    frame = TruthFrame.from_positions(
        0.1 * scan, scan, np.array([0, 1, 2]), np.array([[0.0, 0.0], [0.8, 0.0], [5.0, 1.0]]),
        frame="world",
    )  # fmt: skip
    frame.group_ids[:] = [3, 3, -1]
    return frame


def _groups(scan: int) -> Tracks:
    def group(tid: int, x: float, y: float, size: int) -> Track:
        return Track(tid, "group", np.array([x, y]), np.zeros(2), 0.01 * np.eye(2), size=size)

    return Tracks(0.1 * scan, scan, (group(7, 0.4, 0.0, 2), group(8, 5.0, 1.0, 1)), "world")


def test_group_truth_is_the_groups_at_their_members_mean_in_the_truths_frame() -> None:
    got = group_truth(_truth(4))
    order = np.argsort(got.person_ids)
    assert got.person_ids[order].tolist() == [3, ALONE_ID + 2]
    np.testing.assert_allclose(got.positions[order], [[0.4, 0.0], [5.0, 1.0]], atol=1e-12)
    assert (got.frame, got.scan_index, got.stamp) == ("world", 4, pytest.approx(0.4))


def test_group_tracks_are_scored_against_the_groups_not_the_people() -> None:
    # a group track at the pair's centre is 0.4 m from each member: within a 0.3 m gate
    # only of the group; scored against the people it would miss both and leave a track
    # unmatched (3 truth objects, MOTA 1 - (2 + 1) / 3 = 0)
    params = EvaluationParams(gate=0.3, kind="group")
    got = evaluate([_truth(k) for k in range(5)], [_groups(k) for k in range(5)], params)
    mot = got.result().clear_mot
    assert mot.num_truth == 10 and mot.matches == 10
    assert mot.mota == pytest.approx(1.0, abs=1e-12)
    people = evaluate(
        [_truth(k) for k in range(5)],
        [_groups(k) for k in range(5)],
        EvaluationParams(gate=0.3, kind="person"),
    )
    assert people.result().clear_mot.num_truth == 15  # the people (no person tracks here)


def test_a_truth_without_groups_gives_each_person_as_a_group_of_one() -> None:
    frame = TruthFrame.from_positions(0.0, 0, np.array([4, 9]), np.array([[1.0, 2.0], [3.0, 4.0]]))
    got = group_truth(frame)
    assert sorted(got.person_ids.tolist()) == [ALONE_ID + 4, ALONE_ID + 9]
    assert got.frame is None
