"""``feet-pf`` on a laser at upper-body height warns (naming the laser, its height and what
to use instead), as ``upper-body-pf`` on a leg-height laser does."""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.pipeline.laser_height import feet_warning, mount_warning


def test_feet_warning_names_the_high_laser_and_the_tracker_to_use() -> None:
    text = feet_warning("feet-pf", ["/a", "/b"], {"/a": 0.2, "/b": 1.1})
    assert "feet-pf models a laser at feet height" in text
    assert "/b at 1.10 m (upper-body height)" in text
    assert "/a" not in text
    assert text.endswith("use upper-body-pf")
    # at the bound (0.7 m) it is upper-body height; below, and unknown, no warning
    assert feet_warning("feet-pf", ["/a"], {"/a": 0.7}) != ""
    assert feet_warning("feet-pf", ["/a"], {"/a": 0.69}) == ""
    assert feet_warning("feet-pf", ["/a"], {}) == ""
    assert feet_warning("upper-body-pf", ["/a"], {"/a": 1.1}) == ""


def test_mount_warning_picks_the_trackers_own() -> None:
    assert "upper-body-pf models" in mount_warning("upper-body-pf", ["/a"], {"/a": 0.2})
    assert "feet-pf models" in mount_warning("feet-pf", ["/a"], {"/a": 1.2})
    assert mount_warning("feet-pf", ["/a"], {"/a": 0.2}) == ""
    assert mount_warning("leg-mht", ["/a"], {"/a": 1.2}) == ""


def test_track_feet_pf_on_a_torso_height_laser_warns(tmp_path: Path) -> None:
    """random-groups seed 2 draws its laser at 1.20 m (torso height)."""
    rec = tmp_path / "torso.npz"
    res = CliRunner().invoke(
        app, ["simulate", "random-groups", "--seed", "2", "-s", "1", "-o", str(rec)]
    )
    assert res.exit_code == 0, res.output
    out = tmp_path / "t.csv"
    res = CliRunner().invoke(app, ["track", str(rec), "--tracker", "feet-pf", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "feet-pf models a laser at feet height" in res.stderr
    assert "laser at 1.20 m (upper-body height)" in res.stderr
