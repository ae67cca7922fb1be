"""Ratio pruning, k and N-scan depth of the leg MHT by people policy: ``arras`` keeps 1e-3,
k 20 and N 8 (the values 000's reproduction and the golden tests use), ``tracks`` (the
default) gets 1e-2, k 5 and N 4; an explicit ``mht.min_ratio``, ``k_best`` or ``n_scan``
wins under either policy."""

from __future__ import annotations

import tomllib
from dataclasses import replace

import numpy as np
import pytest

from laserpeople.config import ConfigError, from_mapping, load_config, to_toml
from laserpeople.tracking.groups.params import GroupTrackerParams
from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams
from laserpeople.tracking.mht.core import MIN_RATIO, MHTParams
from laserpeople.tracks import Detections


def test_policy_resolves_min_ratio() -> None:
    assert MIN_RATIO == 1e-3
    assert LegTrackerParams().mht.min_ratio is None  # unset: the policy decides
    assert LegTrackerParams().mht_params().min_ratio == 1e-2
    assert LegTrackerParams(people_policy="tracks").mht_params().min_ratio == 1e-2
    arras = LegTrackerParams(people_policy="arras")
    assert arras.mht_params().min_ratio == 1e-3
    assert arras.mht_params().ratio == 1e-3
    # resolved at use: switching the policy of a tracks parameter set switches the ratio
    assert replace(LegTrackerParams(), people_policy="arras").mht_params().min_ratio == 1e-3
    assert replace(arras, people_policy="tracks").mht_params().min_ratio == 1e-2
    # the other MHT parameters pass through unchanged
    p = arras.mht_params()
    assert p.existence_ratio == 1e-3 and p.max_cluster_size == MHTParams().max_cluster_size


def test_policy_resolves_k_and_depth() -> None:
    assert LegTrackerParams().mht.k_best is None and LegTrackerParams().mht.n_scan is None
    arras = LegTrackerParams(people_policy="arras").mht_params()
    assert (arras.k_best, arras.n_scan, arras.k, arras.depth) == (20, 8, 20, 8)
    tracks = LegTrackerParams().mht_params()
    assert (tracks.k_best, tracks.n_scan, tracks.k, tracks.depth) == (5, 4, 5, 4)
    switched = replace(LegTrackerParams(), people_policy="arras").mht_params()
    assert (switched.k, switched.depth) == (20, 8)
    for policy in ("arras", "tracks"):
        mine = LegTrackerParams(people_policy=policy, mht=MHTParams(k_best=7, n_scan=0))
        assert (mine.mht_params().k, mine.mht_params().depth) == (7, 0)  # 0 is not "unset"
    assert (MHTParams().k, MHTParams().depth) == (20, 8)  # a bare core: 000's depth


def test_tracker_mht_branches_at_most_the_policy_k() -> None:
    rng = np.random.default_rng(3)
    for policy, k in (("arras", 20), ("tracks", 5)):
        tracker = LegMHTTracker(LegTrackerParams(people_policy=policy))
        assert tracker.mht.params.k == k
        most = 0
        for i in range(15):  # six legs close together: many ways to assign them
            xy = np.array([[0.2 * j + 0.05 * i, 1.0] for j in range(6)])
            xy += rng.normal(0.0, 0.03, xy.shape)
            tracker.update(
                Detections(0.1 * i, i, xy, np.tile(np.eye(2) * 0.01, (6, 1, 1)), np.ones(6))
            )
            stats = tracker.last_stats
            assert stats is not None
            most = max(most, stats.max_cluster_hypotheses)
        assert most == k  # the listing fills k children and stops there


def test_explicit_min_ratio_wins() -> None:
    for policy in ("arras", "tracks"):
        p = LegTrackerParams(people_policy=policy, mht=MHTParams(min_ratio=0.05))
        assert p.mht_params().min_ratio == 0.05
        zero = LegTrackerParams(people_policy=policy, mht=MHTParams(min_ratio=0.0))
        assert zero.mht_params().ratio == 0.0  # 0: no ratio pruning, not "unset"


def test_tracker_mht_uses_the_policy_ratio() -> None:
    for policy, ratio in (("arras", 1e-3), ("tracks", 1e-2)):
        tracker = LegMHTTracker(LegTrackerParams(people_policy=policy))
        assert tracker.mht.params.min_ratio == ratio
        tracker.update(Detections.empty(0.0, 0))


def test_group_tracker_and_bare_core_keep_min_ratio() -> None:
    assert GroupTrackerParams().mht.ratio == MIN_RATIO
    assert MHTParams().ratio == MIN_RATIO
    assert MHTParams(min_ratio=0.2).ratio == 0.2


def test_min_ratio_validation() -> None:
    for bad in (1.0, -0.1, True):
        with pytest.raises(ValueError, match="min_ratio"):
            MHTParams(min_ratio=bad)
    with pytest.raises(ValueError, match="k_best"):
        MHTParams(k_best=0)
    with pytest.raises(ValueError, match="n_scan"):
        MHTParams(n_scan=-1)
    with pytest.raises(ConfigError, match="min_ratio"):
        from_mapping(LegTrackerParams, {"mht": {"min_ratio": "a lot"}})


def test_toml_unset_and_set(tmp_path) -> None:  # type: ignore[no-untyped-def]
    text = to_toml(LegTrackerParams())
    assert "# mht.min_ratio unset" in text
    tomllib.loads(text)  # valid TOML: the unset value is a comment
    path = tmp_path / "p.toml"
    path.write_text(text)
    back = load_config(LegTrackerParams, path)
    assert back == LegTrackerParams() and back.mht.min_ratio is None
    path.write_text('[leg_tracker]\npeople_policy = "arras"\nmht.min_ratio = 0.01\n')
    q = load_config(LegTrackerParams, path)
    assert q.mht_params().min_ratio == 0.01
    text = to_toml(q)
    assert "mht.min_ratio = 0.01" in text
