"""Confirmed groups: a group of the MHT's best hypothesis is reported once it has been there
for ``group_tracker.confirm_scans`` scans (``confirm_event_scans`` for a split or merge of a
reported group); ``confirm_scans = 1`` is 000 (every group, every scan)."""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.tracking.groups import GroupMHTTracker, GroupTrackerParams
from laserpeople.tracking.groups.confirm import Candidate, Confirmation, ConfirmSettings
from laserpeople.tracks import Tracks
from test_track_groups_static import OBJECT, PlaceModel, _blob, _frame, _near_object

PAPER = GroupTrackerParams(confirm_scans=1, confirm_event_scans=1, coast_time=0.0)
"""Every group of the best hypothesis reported from its first scan, and only those (no
vanished group reported at its prediction, ``coast_time``): the reports confirmation
chooses from."""


def _run(
    centres_at: Callable[[int], list[np.ndarray]], steps: int, params: GroupTrackerParams
) -> tuple[GroupMHTTracker, list[Tracks]]:
    tracker = GroupMHTTracker(params)
    out = []
    for k in range(steps):
        centres = centres_at(k)
        pts = np.concatenate([_blob(c) for c in centres]) if centres else np.empty((0, 2))
        out.append(tracker.update(_frame(pts, k)))
    return tracker, out


def _walker(k: int) -> np.ndarray:
    return np.array([0.1 * k, 0.0])


FLICKER = np.array([4.0, 6.0])


def _walker_and_flicker(k: int) -> list[np.ndarray]:
    """A walker throughout; something at FLICKER (6 m away) in scans 10-11 and 20."""
    return [_walker(k), FLICKER] if k in (10, 11, 20) else [_walker(k)]


def _reported(out: list[Tracks]) -> int:
    return sum(len(t.of_kind("group")) for t in out)


def _near(tracks: Tracks, place: np.ndarray) -> list[int]:
    return [
        t.track_id
        for t in tracks.of_kind("group")
        if float(np.linalg.norm(t.position - place)) < 0.6
    ]


def test_paper_setting_reports_every_group_from_its_first_scan() -> None:
    tracker, out = _run(_walker_and_flicker, 40, PAPER)
    # the MHT puts a group into its best hypothesis from the second scan of its points on
    assert [len(_near(t, _walker(k))) for k, t in enumerate(out)] == [0] + [1] * 39
    assert any(_near(t, FLICKER) for t in out)  # 000 reports the flicker
    assert tracker.unconfirmed_groups_withheld == 0


@pytest.mark.parametrize("n", [2, 3, 5])
def test_a_walker_is_reported_from_its_nth_scan_with_one_id(n: int) -> None:
    params = GroupTrackerParams(confirm_scans=n, confirm_event_scans=1, coast_time=0.0)
    tracker, out = _run(_walker_and_flicker, 40, params)
    shown = [_near(t, _walker(k)) for k, t in enumerate(out)]
    # in the best hypothesis from scan 1 on: its n-th scan there is scan n
    assert [len(s) for s in shown] == [0] * n + [1] * (40 - n)
    assert len({i for s in shown for i in s}) == 1
    _, paper = _run(_walker_and_flicker, 40, PAPER)
    walker_ids = {i for k, t in enumerate(paper) for i in _near(t, _walker(k))}
    assert {i for s in shown for i in s} == walker_ids  # the same track id as 000 reports
    # withheld: the walker's first n - 1 scans in the best hypothesis and the flicker's scans
    assert tracker.unconfirmed_groups_withheld == _reported(paper) - _reported(out)
    assert tracker.confirmation.withheld_born == tracker.unconfirmed_groups_withheld


@pytest.mark.parametrize("n", [3, 4])
def test_a_flicker_of_one_or_two_scans_is_never_reported(n: int) -> None:
    tracker, out = _run(
        _walker_and_flicker, 40, GroupTrackerParams(confirm_scans=n, coast_time=0.0)
    )
    assert not any(_near(t, FLICKER) for t in out)
    _, paper = _run(_walker_and_flicker, 40, PAPER)
    flicker_scans = sum(len(_near(t, FLICKER)) for t in paper)
    assert flicker_scans >= 1
    assert tracker.unconfirmed_groups_withheld == (n - 1) + flicker_scans


def _pair_parting(k: int) -> list[np.ndarray]:
    """Two people walking side by side 0.8 m apart (one group at d_P 1.3 m), parting from
    scan 15 on at 0.2 m per scan sideways each."""
    apart = 0.4 + 0.2 * max(0, k - 15)
    return [np.array([0.1 * k, apart]), np.array([0.1 * k, -apart])]


def test_a_split_of_a_reported_group_is_reported_at_once_with_event_scans_one() -> None:
    params = GroupTrackerParams(confirm_scans=3, confirm_event_scans=1, coast_time=0.0)
    tracker, out = _run(_pair_parting, 40, params)
    _, paper = _run(_pair_parting, 40, PAPER)
    counts = [len(t.of_kind("group")) for t in out]
    assert counts[3:] == [len(t.of_kind("group")) for t in paper[3:]]  # no gap after the split
    assert counts[-1] == 2
    assert [e.kind for e in tracker.events] == ["split"]
    assert tracker.confirmation.withheld_event == 0
    # a wait for split halves leaves the people unreported for that wait
    waits = GroupTrackerParams(confirm_scans=3, confirm_event_scans=3, coast_time=0.0)
    waited, late = _run(_pair_parting, 40, waits)
    gap = [k for k, t in enumerate(late) if k >= 3 and not t.of_kind("group")]
    assert len(gap) == 2
    assert waited.confirmation.withheld_event == 4  # two halves, two scans each
    assert [e.kind for e in waited.events] == ["split"]


def test_a_group_hidden_on_a_static_place_is_not_counted_as_unconfirmed() -> None:
    """An object on a static place and a walker, with the default (confirm_scans 3): the
    object is counted by the static rule only, the walker's first two scans as
    unconfirmed."""
    tracker = GroupMHTTracker(GroupTrackerParams())
    model = PlaceModel(_near_object)
    tracker.use_static_model(model)  # type: ignore[arg-type]
    out = []
    for k in range(30):
        model.now = 0.1 * k
        pts = np.concatenate([_blob(OBJECT), _blob(np.array([0.1 * k, 3.0]))])
        out.append(tracker.update(_frame(pts, k)))
    assert [len(t.of_kind("group")) for t in out] == [0, 0, 0] + [1] * 27
    assert not any(_near(t, OBJECT) for t in out)
    assert tracker.static_groups_hidden == 29
    assert tracker.unconfirmed_groups_withheld == 2


def test_confirmation_counts_n_of_the_last_m_scans() -> None:
    conf = Confirmation(ConfirmSettings(scans=3, window=4, event_scans=1))
    c = Candidate(7, "", ("7",))
    answers = {k: conf.select(k, [c])[0] for k in (1, 2, 4)}  # absent in scan 3
    assert answers == {1: False, 2: False, 4: True}  # 3 of scans 1-4
    assert conf.select(9, [c]) == [True]  # confirmed for good
    late = Confirmation(ConfirmSettings(scans=3, window=4, event_scans=1))
    d = Candidate(8, "", ("8",))
    # scans 3-6 hold two: not yet; 4-7 three
    assert [late.select(k, [d])[0] for k in (1, 2, 5, 6, 7)] == [False] * 4 + [True]
    assert late.withheld == late.withheld_born == 4


def test_confirmation_waits_event_scans_only_for_groups_of_reported_people() -> None:
    conf = Confirmation(ConfirmSettings(scans=3, window=3, event_scans=1))
    born = Candidate(2, "", ("2",))
    for k in (1, 2, 3):
        conf.select(k, [born])
    half = Candidate(9, "split", ("2-0",))  # a half of the reported group 2
    stranger = Candidate(10, "merge", ("5", "6"))  # a merge of groups never reported
    hidden = Candidate(11, "split", ("2-1",), visible=False)  # hidden, e.g. on a static place
    assert conf.select(4, [half, stranger, hidden]) == [True, False, False]
    assert (conf.withheld_born, conf.withheld_event) == (2, 1)
    assert conf.select(5, [stranger, hidden]) == [False, False]
    assert conf.select(6, [stranger]) == [True]


def test_confirm_parameters_are_checked() -> None:
    with pytest.raises(ValueError, match="at least 1"):
        GroupTrackerParams(confirm_scans=0)
    with pytest.raises(ValueError, match="confirm_window must be at least"):
        GroupTrackerParams(confirm_scans=3, confirm_window=2)
    with pytest.raises(ValueError, match="must not be negative"):
        GroupTrackerParams(confirm_window=-1)
    assert GroupTrackerParams(confirm_scans=4, confirm_window=0).confirm_settings().window == 4


def test_track_says_how_many_group_scans_were_not_confirmed(tmp_path: Path) -> None:
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "hall.npz"
    run_scenario("entrance-hall", seconds=8.0, seed=0).write(rec)  # 2 s learning
    out = tmp_path / "g.csv"
    line = r"(\d+) group-scans of groups not yet confirmed were not reported"
    config = tmp_path / "confirm.toml"
    config.write_text("[group_tracker]\nconfirm_scans = 3\n")
    args = ["track", str(rec), "-o", str(out), "--tracker", "group-mht"]
    result = CliRunner().invoke(app, [*args, "--config", str(config)])
    assert result.exit_code == 0, result.output
    found = re.search(line, result.output)
    assert found and int(found.group(1)) > 0
    config.write_text("[group_tracker]\nconfirm_scans = 1\nconfirm_event_scans = 1\n")
    result = CliRunner().invoke(app, [*args, "--config", str(config)])
    assert result.exit_code == 0, result.output
    assert not re.search(line, result.output)
