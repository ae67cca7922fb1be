"""`--preset paper` for the leg MHT and the leg detector: 000 Secs. 2-3 as written.

Each departure of the leg and people tracker from 000 and the leg detector's centre
offset are set back to 000's value by the preset; the values below are written out from
the paper (not read from the preset), so a field the preset drops, or sets wrongly, fails.
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any, get_type_hints

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.config import load_config
from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.errors import ConfigError
from laserpeople.scan import Scan
from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams
from laserpeople.tracking.people import LegState, PersonFuser, PersonParams

INF = math.inf

PAPER_000_LEGS: dict[str, Any] = {
    "people_policy": "arras",  # Sec. 3.3: a person exists while a validated leg pair does
    "max_report_unseen": INF,  # every track of the best hypothesis is reported
    "kalman.coast_velocity_time": INF,  # Sec. 3.1: constant velocity, also while occluded
    "person.validate_still": False,  # Sec. 3.3: validation by orientation agreement only
    "person.relink_time": 0.0,  # Sec. 3.3: a newly validated pair is a new person
    "person.max_leg_separation": INF,  # Sec. 3.3: deleted after L steps apart, never hidden
    "person.max_spread": INF,  # Sec. 3.3: every pair closer than theta_d is a candidate
    "person.dissolve_wide": False,  # Sec. 3.3: no dissolving of wide persons
}
"""000's values of the leg tracker's departures (docs/papers.md)."""

PAPER_000_DETECTOR: dict[str, Any] = {
    "centre_offset": 0.0,  # Sec. 2: a leg at its segment's centre
    "sparse.enabled": False,  # Sec. 2.2: features of segments of three points or more
}


def _get(obj: Any, dotted: str) -> Any:
    for part in dotted.split("."):
        obj = getattr(obj, part)
    return obj


def _source(cls: type, dotted: str) -> str:
    """The metadata source of the parameter ``dotted`` of ``cls`` (nested tables dotted)."""
    *outer, last = dotted.split(".")
    for part in outer:
        cls = get_type_hints(cls)[part]
    return str(next(f for f in dataclasses.fields(cls) if f.name == last).metadata["source"])


def _flat(preset: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in preset.items():
        if isinstance(value, Mapping):
            out.update(_flat(value, f"{prefix}{key}."))
        else:
            out[f"{prefix}{key}"] = value
    return out


@pytest.mark.parametrize("name", sorted(PAPER_000_LEGS))
def test_each_leg_tracker_departure_is_set_to_000_by_the_preset(name: str) -> None:
    paper = load_config(LegTrackerParams, None, "paper")
    assert _get(paper, name) == PAPER_000_LEGS[name]
    assert _get(LegTrackerParams(), name) != PAPER_000_LEGS[name]  # a departure by default
    source = _source(LegTrackerParams, name)
    assert source.startswith("departure from 000 Sec. 3") and "--preset paper" in source


@pytest.mark.parametrize("name", sorted(PAPER_000_DETECTOR))
def test_the_leg_detector_preset_gives_000s_leg_position(name: str) -> None:
    paper = load_config(LegDetectorParams, None, "paper")
    assert _get(paper, name) == PAPER_000_DETECTOR[name]
    assert _get(LegDetectorParams(), name) != PAPER_000_DETECTOR[name]


def test_the_presets_set_exactly_the_listed_departures() -> None:
    assert _flat(LegTrackerParams.paper_preset) == PAPER_000_LEGS
    assert _flat(LegDetectorParams.paper_preset) == PAPER_000_DETECTOR
    assert "--preset paper" in _source(LegDetectorParams, "centre_offset")


def test_the_paper_tracker_is_000s_mht_and_people_from_leg_pairs() -> None:
    paper = load_config(LegTrackerParams, None, "paper")
    mht = paper.mht_params()
    assert (mht.k_best, mht.n_scan) == (20, 8)  # 000 Sec. 3.4.3's depth of eight
    assert mht.min_ratio == pytest.approx(1e-3, rel=1e-12)
    tracker = LegMHTTracker(paper)
    assert tracker.person_tracks is None and tracker.people.params.relink_time == 0.0
    assert LegMHTTracker(LegTrackerParams()).person_tracks is not None


def _standing_pair(params: PersonParams, seconds: float) -> int:
    """Persons reported after two legs 0.2 m apart stood still for ``seconds`` at 10 Hz."""
    fuser = PersonFuser(params)
    cov = np.diag([0.01, 0.01, 0.1, 0.1])
    legs = {
        1: LegState(1, np.array([2.0, 0.1, 0.0, 0.0]), cov),
        2: LegState(2, np.array([2.0, -0.1, 0.0, 0.0]), cov),
    }
    out = []
    for k in range(round(10 * seconds) + 1):
        out = fuser.update(legs, 0.1 * k)
    return len(out)


def test_standing_legs_make_a_person_only_with_the_default() -> None:
    assert _standing_pair(LegTrackerParams().person, 3.0) == 1
    assert _standing_pair(load_config(LegTrackerParams, None, "paper").person, 3.0) == 0


def _one_leg_scan(centre: tuple[float, float], radius: float) -> tuple[Scan, np.ndarray]:
    """A 180 deg, 0.25 deg scan of one cylinder before a wall at 4 m, and the points (N, 2)
    [m] the scanner sees of the cylinder."""
    angles = np.deg2rad(np.arange(-90.0, 90.0 + 1e-9, 0.25))
    d = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    c = np.asarray(centre)
    b = d @ c
    disc = b**2 - (c @ c - radius**2)
    hit = disc >= 0
    wall = 4.0 / np.maximum(np.cos(angles), 1e-3)
    ranges = np.where(hit, b - np.sqrt(np.clip(disc, 0, None)), np.minimum(wall, 15.0))
    scan = Scan(0.0, float(angles[0]), float(np.deg2rad(0.25)), ranges, 0.05, 20.0)
    return scan, ranges[hit, None] * d[hit]


def test_the_paper_detector_puts_a_leg_at_its_points_centroid() -> None:
    scan, points = _one_leg_scan((2.0, 0.3), 0.07)
    det = AdaBoostLegDetector.default(load_config(LegDetectorParams, None, "paper")).detect(scan)
    assert len(det) == 1
    np.testing.assert_allclose(det.positions[0], points.mean(axis=0), atol=1e-9)
    moved = AdaBoostLegDetector.default().detect(scan)  # 0.045 m farther from the sensor
    assert np.hypot(*moved.positions[0]) - np.hypot(*det.positions[0]) == pytest.approx(
        0.045, abs=1e-9
    )


def _printed(args: list[str]) -> str:
    result = CliRunner().invoke(app, ["track", "--print-config", *args])
    assert result.exit_code == 0, result.output
    return result.output


def test_the_printed_paper_setting_reads_back_and_names_the_preset(tmp_path: Path) -> None:
    text = _printed(["--tracker", "leg-mht", "--preset", "paper"])
    shown = tomllib.loads(text)
    assert shown["leg_tracker"]["people_policy"] == "arras"
    assert shown["leg_tracker"]["person"]["max_leg_separation"] == INF
    assert shown["leg_detector"]["centre_offset"] == 0.0
    assert "relink_time = 0.0  # from --preset paper (default 1.0)" in text
    cfg = tmp_path / "paper.toml"
    cfg.write_text(text)  # inf written out is read back where the meaning says what it does
    assert load_config(LegTrackerParams, cfg) == load_config(LegTrackerParams, None, "paper")
    assert load_config(LegDetectorParams, cfg).centre_offset == 0.0
    # the file over the preset: one extension switched back on, the others stay 000's
    cfg.write_text("[leg_tracker.person]\nrelink_time = 1.0\n")
    mixed = load_config(LegTrackerParams, cfg, "paper")
    assert mixed.person.relink_time == 1.0 and not mixed.person.validate_still
    assert mixed.people_policy == "arras"


def test_infinity_only_where_the_meaning_says_what_it_does(tmp_path: Path) -> None:
    cfg = tmp_path / "c.toml"
    cfg.write_text("[leg_tracker.kalman]\ncoast_velocity_time = inf\n")
    assert load_config(LegTrackerParams, cfg).kalman.coast_velocity_time == INF
    for text in (
        "[leg_tracker.kalman]\nmax_dt = inf\n",
        "[leg_tracker.person]\nmax_leg_separation = -inf\n",
    ):
        cfg.write_text(text)
        with pytest.raises(ConfigError, match="is infinite"):
            load_config(LegTrackerParams, cfg)


def test_people_policy_on_the_command_line_goes_over_the_preset() -> None:
    from laserpeople.tracking import registry

    paper = load_config(LegTrackerParams, None, "paper")
    tracks = registry.with_people_policy(paper, "tracks", "leg-mht")
    assert tracks.people_policy == "tracks" and tracks.person.relink_time == 0.0


def test_the_leg_foreground_stage_keeps_its_leg_mht_under_the_preset(tmp_path: Path) -> None:
    """The MHT the leg foreground stage runs for trackers of points is no paper's tracker:
    ``--preset paper`` leaves it as ``[leg_tracker]`` without the preset gives it, and
    --print-config of such a tracker shows that."""
    from laserpeople.pipeline.background import load_static_world

    assert load_static_world(None, "paper").leg_tracker == LegTrackerParams()
    cfg = tmp_path / "c.toml"
    cfg.write_text("[leg_tracker.person]\nrelink_time = 2.0\n")
    assert load_static_world(cfg, "paper").leg_tracker.person.relink_time == 2.0
    assert load_static_world(cfg, "paper").leg_tracker.people_policy == "tracks"
    shown = tomllib.loads(_printed(["--tracker", "feet-pf", "--preset", "paper"]))
    assert shown["leg_tracker"]["people_policy"] == "tracks"
    assert shown["leg_tracker"]["person"]["relink_time"] == 1.0
    assert shown["leg_detector"]["centre_offset"] == 0.0  # the detector is 000's for all
    assert shown["feet_pf"]["leg_reid"] is False  # the tracker's own section is its paper's
