"""`laserpeople track`: recording in, tracks CSV out; config printing; registry."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.cli import track as track_cli
from laserpeople.cli.common import open_with_poses
from laserpeople.errors import ConfigError
from laserpeople.io.tracks_csv import iter_tracks_csv
from laserpeople.scan import Scan
from laserpeople.tracking import registry
from laserpeople.tracks import Detections


class LabelDetector:
    """A stand-in detector: the mean point of the beams of each labelled leg."""

    def detect(self, scan: Scan) -> Detections:
        assert scan.labels is not None
        pts = scan.points("sensor")
        keys = scan.labels.person * 2 + scan.labels.leg
        found = []
        for key in np.unique(keys[scan.labels.is_leg]):
            sel = (keys == key) & scan.labels.is_leg
            if np.count_nonzero(sel) >= 2:
                found.append(pts[sel].mean(axis=0))
        pos = np.array(found).reshape(-1, 2)
        m = len(pos)
        return Detections(
            scan.stamp, scan.index, pos, np.tile(np.eye(2) * 0.01, (m, 1, 1)), np.ones(m),
            "sensor", scan.pose,
        )  # fmt: skip


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from laserpeople.sim.scenarios import run_scenario

    path = tmp_path_factory.mktemp("rec") / "walk.npz"
    run_scenario("figure-eight", seconds=6.0, seed=1).write(path)
    return path


def test_run_tracking_writes_legs_and_people(recording: Path, tmp_path: Path) -> None:
    out = tmp_path / "tracks.csv"
    stats = track_cli.run_tracking(recording, out, detector=LabelDetector())
    assert stats["scans"] > 100 and stats["leg_tracks"] >= 2
    frames = list(iter_tracks_csv(out, frame="world"))
    kinds = {t.kind for f in frames for t in f}
    assert kinds == {"leg", "person"}
    assert stats["person_tracks"] >= 1


def test_command_with_injected_detector(
    recording: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(track_cli, "make_detector", lambda *a, **k: LabelDetector())
    out = tmp_path / "t.csv"
    cfg = tmp_path / "c.toml"
    sections = {
        "leg-mht": "[leg_tracker]\nlambda_fal = 0.003\n",
        "nn": "[nn_tracker]\nmin_hits = 3\n",
    }
    for tracker, section in sections.items():
        cfg.write_text(section + "[leg_detector]\n")
        result = CliRunner().invoke(
            app,
            ["--quiet", "track", str(recording), "--tracker", tracker, "--config", str(cfg),
             "--output-frame", "sensor", "-o", str(out)],
        )  # fmt: skip
        assert result.exit_code == 0, result.output
        rows = out.read_text().splitlines()
        assert rows[0].startswith("scan,stamp,track_id,kind") and len(rows) > 100


def test_misspelt_config_section_is_an_error(recording: Path, tmp_path: Path) -> None:
    cfg = tmp_path / "c.toml"
    cfg.write_text("[leg_trackr]\np_occ_free = 0.5\n")
    for args in (["--print-config"], [str(recording), "-o", str(tmp_path / "t.csv")]):
        result = CliRunner().invoke(app, ["track", *args, "--config", str(cfg)])
        assert isinstance(result.exception, ConfigError), result.output
        assert "[leg_trackr]" in str(result.exception) and "[leg_tracker]" in str(result.exception)
    assert not (tmp_path / "t.csv").exists()
    # a section of another tracker may share the file: said to be ignored, not an error
    cfg.write_text("[nn_tracker]\nmin_hits = 3\n")
    result = CliRunner().invoke(app, ["track", "--print-config", "--config", str(cfg)])
    assert result.exit_code == 0, result.output
    assert "[nn_tracker] is read by another command or tracker" in result.stderr


def test_bag_options_on_other_recordings_are_an_error(recording: Path, tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="ROS bags only"):
        open_with_poses(recording, "odom", [])
    carmen = tmp_path / "run.log"
    carmen.write_text("")
    with pytest.raises(ConfigError, match="ROS bags only"):
        open_with_poses(carmen, None, ["mir100"])


def test_print_config_shows_sources() -> None:
    result = CliRunner().invoke(app, ["track", "--print-config"])
    assert result.exit_code == 0, result.output
    assert (
        "p_occ_approved = 0.79" in result.output and "Arras et al. 2008 Table 10" in result.output
    )
    assert "# P(" in result.output and " 000 " not in result.output and "004" not in result.output
    assert "[leg_detector]" in result.output


def test_unknown_tracker_and_missing_output(recording: Path) -> None:
    with pytest.raises(ConfigError):
        registry.get("nope")
    result = CliRunner().invoke(app, ["track", str(recording)])
    assert result.exit_code != 0


def test_registry_lists_builtin_trackers() -> None:
    assert {"leg-mht", "nn"} <= set(registry.TRACKERS)
    with pytest.raises(ValueError):
        registry.register(registry.TRACKERS["nn"])


def test_real_bag_end_to_end(shared_data: Path) -> None:
    bag = shared_data / "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag"
    if not bag.exists():
        pytest.skip(f"{bag} not present")
    from laserpeople.io import open_recording

    # the first 150 scans keep the test short
    rec = open_recording(bag)
    scans = []
    for scan in rec.scans():
        scans.append(scan)
        if len(scans) == 150:
            break
    rec.close()
    det = track_cli.make_detector("adaboost", None, None)
    from laserpeople.tracking.legs import LegMHTTracker

    tracker = LegMHTTracker()
    outs = [tracker.update(det.detect(s)) for s in scans]
    assert len(outs) == 150
    assert any(len(o.of_kind("leg")) > 0 for o in outs)


@pytest.fixture(scope="module")
def short_recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from laserpeople.sim.scenarios import run_scenario

    path = tmp_path_factory.mktemp("short") / "short.npz"
    run_scenario("figure-eight", seconds=1.0, seed=2).write(path)
    return path


def test_plot_and_animate_options(
    short_recording: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from PIL import Image

    from laserpeople.io import open_recording

    monkeypatch.setattr(track_cli, "make_detector", lambda *a, **k: LabelDetector())
    out, png, gif = tmp_path / "t.csv", tmp_path / "t.png", tmp_path / "t.gif"
    result = CliRunner().invoke(
        app,
        ["--quiet", "track", str(short_recording), "-o", str(out), "--plot", str(png),
         "--animate", str(gif)],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    rec = open_recording(short_recording)
    n_scans = sum(1 for _ in rec.scans())
    rec.close()
    with Image.open(png) as im:
        assert (
            im.format == "PNG"
            and im.size[0] > 100
            and np.unique(np.asarray(im.convert("L"))).size > 2
        )
    with Image.open(gif) as im:
        assert im.format == "GIF" and getattr(im, "n_frames", 1) == n_scans
    bad = CliRunner().invoke(
        app, ["track", str(short_recording), "-o", str(out), "--plot", "x.gif"]
    )
    assert bad.exit_code != 0


def test_plot_of_a_moving_robot_uses_the_mounts_given_to_track(
    shared_data: Path, tmp_path: Path
) -> None:
    """`track --mount mir100 --plot`: the tracks are in the world frame, and the drawing must
    read the bag with the same mounts (it used to reopen it without, find no sensor pose,
    and fail after the tracks were written)."""
    bag = shared_data / "mir/rosbags/mir_data/legs-test-split-2022-11-21-15-51-02-topic-split.bag"
    if not bag.exists():
        pytest.skip(f"{bag} not present")
    out, png = tmp_path / "t.csv", tmp_path / "t.png"
    result = CliRunner().invoke(
        app,
        ["--quiet", "track", str(bag), "--mount", "mir100", "-o", str(out), "--plot", str(png)],
    )
    assert result.exit_code == 0, result.output
    assert png.stat().st_size > 10_000
    assert any(t.kind == "person" for tr in iter_tracks_csv(out, frame="world") for t in tr)


@pytest.mark.parametrize(
    ("done", "seconds", "text"),
    [
        (500, 10.0, "50 per s"),
        (3, 3.0, "1 per s"),  # one a second: still a rate
        (3, 78.0, "26 s each"),  # bench's stages: not '0 per s'
        (1, 1.5, "2 s each"),
    ],
)
def test_progress_rate_of_slow_items_is_seconds_each(done: int, seconds: float, text: str):
    from laserpeople.cli.common import rate_text

    assert rate_text(done, seconds) == text
