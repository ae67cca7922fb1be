"""The settings of issue 33: one preset for the papers' behaviour, colour
re-identification settable from --config and shown by --print-config, and the mounts
file of `align` read by `track --mounts` and by every --mount."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
from typer.testing import CliRunner

from laserpeople.alignment import Mount, write_mounts
from laserpeople.cli import app
from laserpeople.config import load_config
from laserpeople.errors import ConfigError
from laserpeople.identity.reid import ReidParams
from laserpeople.io.poses import parse_mounts
from laserpeople.scan import Pose2D
from laserpeople.tracking.csa import CSAParams
from laserpeople.tracking.groups import GroupTrackerParams
from laserpeople.tracking.particle.feet import FeetParams
from laserpeople.tracking.particle.upper_body import UpperBodyParams


def _printed(args: list[str]) -> dict:
    result = CliRunner().invoke(app, ["track", "--print-config", *args])
    assert result.exit_code == 0, result.output
    return tomllib.loads(result.output)


def test_paper_preset_gives_each_tracker_its_papers_values() -> None:
    g = load_config(GroupTrackerParams, None, "paper")
    assert (g.eps_n, g.size_count, g.model_prior, g.merge_likelihood) == (
        0.1,
        "blobs",
        "literal",
        "density",
    )
    assert (g.observation_area, g.share_parts, g.static_groups, g.confirm_scans) == (
        0.0,
        False,
        True,
        1,
    )
    c = load_config(CSAParams, None, "paper")
    assert not c.adopt_escaped and not c.fragment_rule
    assert not c.person_scores and not c.adopt_orphans and not c.group_rows
    assert not c.person_mixture and not c.background_people
    from laserpeople.identity.reid import ReidParams

    assert not load_config(ReidParams, None, "paper").early
    f = load_config(FeetParams, None, "paper")
    assert (f.h_width, f.voronoi, f.long_weight, f.rescue_legs, f.blob_body) == (
        0.0,
        False,
        1.0,
        False,
        False,
    )
    assert (f.overlap_max, f.still_time, f.cell_refresh, f.claim_distance) == (0.0,) * 4
    d = FeetParams()
    assert d.overlap_max > 0.0 and d.still_time > 0.0 and d.cell_refresh > 0.0
    assert d.claim_distance > 0.0
    assert f.split_distance == 0.0 and d.split_distance > 0.0
    assert f.report_offset == 0.0 and d.report_offset > 0.0
    u = load_config(UpperBodyParams, None, "paper")
    assert (u.surface_offset, u.carry_depth, u.object_memory, u.max_eigenvalue) == (0, 0, 0, 0)
    assert g.mht.n_scan == 8 and g.model_prior == "literal"
    assert GroupTrackerParams().eps_n == 1.0  # the defaults are not changed
    assert GroupTrackerParams().model_prior == "normalised"
    with pytest.raises(ConfigError, match="unknown preset"):
        load_config(CSAParams, None, "000")


def test_paper_preset_on_the_command_line_under_the_config(tmp_path: Path) -> None:
    shown = _printed(["--tracker", "group-mht", "--preset", "paper"])
    assert shown["group_tracker"]["eps_n"] == 0.1
    cfg = tmp_path / "c.toml"
    cfg.write_text("[group_tracker]\neps_n = 0.5\n")
    shown = _printed(["--tracker", "group-mht", "--preset", "paper", "--config", str(cfg)])
    assert shown["group_tracker"]["eps_n"] == 0.5  # the file wins
    assert shown["group_tracker"]["size_count"] == "blobs"
    # the group tracker's nested [group_tracker.mht]: 000's depth of eight under the preset,
    # kept when the file sets another key of the table; the default's own depth is 3
    assert load_config(GroupTrackerParams, None, "paper").mht.n_scan == 8
    cfg.write_text("[group_tracker.mht]\nk_best = 5\n")
    g = load_config(GroupTrackerParams, cfg, "paper")
    assert (g.mht.n_scan, g.mht.k_best, g.eps_n) == (8, 5, 0.1)
    shown = _printed(["--tracker", "group-mht", "--preset", "paper", "--config", str(cfg)])
    assert shown["group_tracker"]["mht"]["n_scan"] == 8
    assert load_config(GroupTrackerParams, cfg).mht.n_scan is None
    from laserpeople.tracking.groups import GroupMHTTracker

    assert GroupMHTTracker(load_config(GroupTrackerParams, cfg)).mht.params.depth == 3
    paper = GroupMHTTracker(load_config(GroupTrackerParams, cfg, "paper"))
    assert paper.mht.params.depth == 8
    bad = CliRunner().invoke(app, ["track", "--print-config", "--preset", "000"])
    assert bad.exit_code != 0 and "unknown preset" in str(bad.exception)


def test_reid_and_appearance_from_the_config(tmp_path: Path) -> None:
    cfg = tmp_path / "c.toml"
    cfg.write_text("[reid]\nmin_observations = 7\n[reid.appearance]\nbins = 12\n")
    params = load_config(ReidParams, cfg)
    assert (params.min_observations, params.appearance.bins) == (7, 12)
    shown = _printed(["--tracker", "csa", "--config", str(cfg)])
    assert shown["reid"]["min_observations"] == 7
    assert shown["reid"]["appearance"]["bins"] == 12


def test_mounts_file_of_align_is_a_mount(tmp_path: Path) -> None:
    path = write_mounts(
        tmp_path / "mounts.toml",
        [Mount("/back_laser", "base_footprint", Pose2D(-0.3, 0.1, 3.1), None)],
    )
    got = parse_mounts([str(path)])
    assert got["back_laser"][0] == "base_footprint"
    assert got["back_laser"][1].as_array() == pytest.approx([-0.3, 0.1, 3.1])
    empty = tmp_path / "empty.toml"
    empty.write_text("# nothing\n")
    with pytest.raises(ConfigError, match=r"no \[mounts\.LASER\] table"):
        parse_mounts([str(empty)])
    missing = CliRunner().invoke(
        app, ["track", "x.bag", "-o", str(tmp_path / "t.csv"), "--mounts", "nope.toml"]
    )
    assert missing.exit_code != 0 and "no such mounts file" in str(missing.exception)
