"""`laserpeople view` and `laserpeople demo` from the command line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.viz import Scene
from test_viz_support import make_scans, make_tracks, write_scene

pytest.importorskip("matplotlib")
from PIL import Image

runner = CliRunner()


def test_view_writes_png_gif_and_mcap(tmp_path: Path) -> None:
    rec, csv = write_scene(tmp_path, n=6)
    for name, extra in (
        ("one.png", ["--scan", "3"]),
        ("all.png", []),
        ("all.gif", ["--every", "2"]),
        ("all.mcap", []),
    ):
        out = tmp_path / name
        res = runner.invoke(
            app,
            ["view", str(rec), "--tracks", str(csv), "-o", str(out), "--size", "320x240", *extra],
        )
        assert res.exit_code == 0, res.output
        assert out.exists() and out.stat().st_size > 0
    with Image.open(tmp_path / "all.gif") as gif:
        assert gif.n_frames == 3
        assert gif.size == (320, 240)


def test_view_says_how_many_scans_an_overview_holds(tmp_path: Path) -> None:
    """A trajectory overview is one image of many scans: `view` names the scans drawn
    (--start 1 --stop 5: 4 of the 6), not "1 frame"; one scan's PNG is 1 frame and a GIF
    of every other scan of 6 is 3 frames."""
    rec, csv = write_scene(tmp_path, n=6)
    said = {}
    for name, extra in (
        ("all.png", ["--start", "1", "--stop", "5"]),
        ("one.png", ["--scan", "3"]),
        ("all.gif", ["--every", "2"]),
    ):
        out = tmp_path / name
        res = runner.invoke(app, ["view", str(rec), "--tracks", str(csv), "-o", str(out), *extra])
        assert res.exit_code == 0, res.output
        said[name] = res.output
    assert f"wrote {tmp_path / 'all.png'} (overview of 4 scans, " in said["all.png"]
    assert f"wrote {tmp_path / 'one.png'} (1 frame, " in said["one.png"]
    assert f"wrote {tmp_path / 'all.gif'} (3 frames, " in said["all.gif"]


def test_view_reports_bad_options_as_errors(tmp_path: Path) -> None:
    rec, _csv = write_scene(tmp_path, n=3)
    res = runner.invoke(app, ["view", str(rec), "-o", str(tmp_path / "x.png"), "--size", "big"])
    assert res.exit_code != 0
    assert "WIDTHxHEIGHT" in str(res.exception)
    res = runner.invoke(app, ["view", str(rec), "-o", str(tmp_path / "x.png"), "--frame", "map"])
    assert res.exit_code != 0


def test_world_frame_without_poses_is_a_clear_error(tmp_path: Path) -> None:
    scans = make_scans(2, pose=None)
    from laserpeople.errors import PoseUnavailableError

    with pytest.raises(PoseUnavailableError, match="--frame sensor"):
        Scene(scans, frame="world")
    assert Scene(scans).frame == "sensor"


def test_extent_ignores_a_diverging_track_far_away(tmp_path: Path) -> None:
    from dataclasses import replace

    from laserpeople.tracks import Track

    tracks = make_tracks(4)
    wild = Track(99, "leg", [500.0, -300.0], [0.0, 0.0], np.eye(2))
    tracks[2] = replace(tracks[2], tracks=(*tracks[2].tracks, wild))
    x0, x1, y0, y1 = Scene(make_scans(4), tracks).extent()
    assert -10 < x0 < x1 < 15 and -10 < y0 < y1 < 15


@pytest.mark.slow
def test_demo_runs_end_to_end(tmp_path: Path) -> None:
    res = runner.invoke(app, ["demo", "--seconds", "4", "--out-dir", str(tmp_path)])
    assert res.exit_code == 0, res.output
    assert "leg-mht" in res.output and "MOTA" in res.output
    assert (tmp_path / "demo-tracks.csv").read_text().startswith("scan,stamp,track_id")
    with Image.open(tmp_path / "demo.gif") as gif:
        assert gif.n_frames >= 10


def test_demo_runs_every_leg_fed_tracker_leg_mht_first() -> None:
    from laserpeople.demo import MAIN_TRACKER, tracker_factories
    from laserpeople.tracking import registry

    names = [name for name, _make in tracker_factories()]
    assert names[0] == MAIN_TRACKER
    leg_fed = [n for n, e in registry.TRACKERS.items() if e.consumes == frozenset({"legs"})]
    assert sorted(names) == sorted(leg_fed) and "group-mht" not in names
