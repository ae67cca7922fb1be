"""Ratio pruning of the group tracker (docs/groups.md "Settings", ratio pruning): hypotheses below
``GROUP_MIN_RATIO`` times their cluster's best are dropped unless ``mht.min_ratio`` is
set, and an explicit value is kept."""

from __future__ import annotations

import math

from laserpeople.evaluation.groups import frames_from_scans
from laserpeople.sim.scenarios import run_scenario
from laserpeople.tracking.groups import GroupMHTTracker, GroupTrackerParams
from laserpeople.tracking.groups.tracker import GROUP_MIN_RATIO
from laserpeople.tracking.mht.core import MHTParams


def test_group_tracker_resolves_an_unset_min_ratio_to_its_own_default() -> None:
    assert GROUP_MIN_RATIO == 3e-3
    for params in (
        GroupTrackerParams(),
        GroupTrackerParams.people_only(),
    ):
        assert GroupMHTTracker(params).mht.params.ratio == GROUP_MIN_RATIO
    pinned = GroupTrackerParams(mht=MHTParams(min_ratio=1e-3))
    assert GroupMHTTracker(pinned).mht.params.ratio == 1e-3
    assert GroupMHTTracker(pinned).mht.params.k == MHTParams().k == 20


def _ratios(params: GroupTrackerParams) -> list[float]:
    """Every hypothesis' probability relative to its cluster's best, after every frame of
    a short simulated hall run."""
    scans = run_scenario("entrance-hall", seconds=8.0, seed=0).scans
    tracker = GroupMHTTracker(params)
    out: list[float] = []
    for lf in frames_from_scans(scans):
        tracker.update(lf.frame)
        for c in tracker.mht.clusters:
            best = max(h.log_weight for h in c.hypotheses)
            out += [math.exp(h.log_weight - best) for h in c.hypotheses]
    return out


def test_no_group_hypothesis_below_the_ratio_is_kept() -> None:
    kept = _ratios(GroupTrackerParams())
    assert min(kept) >= GROUP_MIN_RATIO * (1.0 - 1e-9)
    # with the old threshold the same run keeps hypotheses the new one drops
    old = _ratios(GroupTrackerParams(mht=MHTParams(min_ratio=1e-3)))
    assert min(old) >= 1e-3 * (1.0 - 1e-9)
    assert any(r < GROUP_MIN_RATIO for r in old)
    assert len(kept) < len(old)
