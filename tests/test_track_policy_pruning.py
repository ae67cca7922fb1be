"""Ratio pruning of the leg MHT by people policy: ``arras`` keeps 1e-3 (the value 000's
reproduction and the golden tests use), ``tracks`` (the default) gets 1e-2; an explicit
``mht.min_ratio`` wins under either policy."""

from __future__ import annotations

import tomllib
from dataclasses import replace

import pytest

from laserpeople.config import ConfigError, from_mapping, load_config, to_toml
from laserpeople.tracking.groups.tracker import GroupTrackerParams
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
    assert (p.k_best, p.n_scan, p.existence_ratio) == (20, 8, 1e-3)


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
