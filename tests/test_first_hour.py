"""What a new user meets in the first hour (issue 30): Ctrl-C during `track`, a group CSV
scored as people, `info` on a bag with a truth topic, a truth CSV on another clock, a
text or empty file named .bag, the value names in --help, upper-body-pf on a leg-height
laser and the sections --print-config prints."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import EvaluationError, RecordingError
from laserpeople.evaluation.pairing import PairingCounts
from laserpeople.io.bag_guard import check_bag_file

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def demo(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from laserpeople.sim import run_scenario

    path = tmp_path_factory.mktemp("demo") / "demo.npz"
    run_scenario("demo", seconds=3.0, seed=0).write(path)
    return path


def test_ctrl_c_during_track_reports_and_leaves_a_whole_csv(tmp_path: Path) -> None:
    from laserpeople.sim import run_scenario

    rec = tmp_path / "hall.npz"
    run_scenario("entrance-hall", seconds=60.0, seed=0).write(rec)
    out = tmp_path / "t.csv"
    env = dict(os.environ, PYTHONPATH=str(REPO / "src"))
    proc = subprocess.Popen(
        [sys.executable, "-m", "laserpeople.cli", "track", str(rec), "-o", str(out)],
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    deadline = time.monotonic() + 120.0
    while time.monotonic() < deadline and (not out.exists() or out.stat().st_size < 20000):
        time.sleep(0.2)  # until tracking has written some rows
    proc.send_signal(signal.SIGINT)
    err = proc.communicate(timeout=120)[1]
    assert proc.returncode == 130, err
    assert "interrupted (Ctrl-C) after" in err and "scans tracked" in err, err
    lines = out.read_text().splitlines()
    assert lines[0].startswith("scan,stamp,track_id,kind")
    assert all(len(ln.split(",")) == len(lines[0].split(",")) for ln in lines[1:])
    assert len(lines) > 10


def test_group_csv_scored_as_people_is_refused_with_the_kind_to_use(
    demo: Path, tmp_path: Path
) -> None:
    out = tmp_path / "g.csv"
    res = CliRunner().invoke(
        app, ["--quiet", "track", str(demo), "--tracker", "group-mht", "-o", str(out)]
    )
    assert res.exit_code == 0, res.output
    res = CliRunner().invoke(app, ["evaluate", str(out), "--truth", str(demo)])
    assert isinstance(res.exception, EvaluationError)  # main() prints it as one line
    message = str(res.exception)
    assert "holds no person tracks, only" in message and "--kind group" in message


def test_leg_rows_alone_are_scored_as_nobody_confirmed(demo: Path, tmp_path: Path) -> None:
    """A leg tracker that confirmed nobody wrote leg rows only: scored (every label a miss),
    not refused as another tracker's output."""
    full = tmp_path / "t.csv"
    res = CliRunner().invoke(app, ["--quiet", "track", str(demo), "-o", str(full)])
    assert res.exit_code == 0, res.output
    lines = full.read_text().splitlines()
    kind = lines[0].split(",").index("kind")
    legs = [ln for ln in lines[1:] if ln.split(",")[kind] == "leg"]
    assert legs and len(legs) < len(lines) - 1
    out = tmp_path / "legs.csv"
    out.write_text("\n".join([lines[0], *legs]) + "\n")
    res = CliRunner().invoke(app, ["evaluate", str(out), "--truth", str(demo), "--json"])
    assert res.exit_code == 0, res.output
    assert "confirmed nobody" in res.output
    scores = json.loads(res.stdout[res.stdout.index("{") :])
    assert scores["recall"] == pytest.approx(0.0, abs=1e-9)
    assert scores["mota"] == pytest.approx(0.0, abs=1e-9)


def _truth_bag(path: Path) -> None:
    """Ten scans of /scan and a leg_tracker Person after each."""
    import math

    from laserpeople.io.rosbag_writer import open_bag
    from laserpeople.io.truth_bag import LEG_TRACKER_PERSON, register_people_types

    with open_bag(path) as sink:
        register_people_types(sink.typestore)
        types = sink.typestore.types
        for k in range(10):
            t = 10.0 + 0.1 * k
            msg = types["sensor_msgs/msg/LaserScan"](
                header=sink.header(t, "laser"),
                angle_min=-0.5,
                angle_max=-0.5 + 9 * math.radians(1.0),
                angle_increment=math.radians(1.0),
                time_increment=0.0,
                scan_time=0.0,
                range_min=0.0,
                range_max=5.0,
                ranges=np.full(10, 2.0, dtype=np.float32),
                intensities=np.empty(0, dtype=np.float32),
            )
            sink.write("/scan", "sensor_msgs/msg/LaserScan", msg, t)
            point = types["geometry_msgs/msg/Point"](x=1.0, y=0.1 * k, z=0.0)
            quat = types["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0)
            pose = types["geometry_msgs/msg/Pose"](position=point, orientation=quat)
            person = types[LEG_TRACKER_PERSON](pose=pose, id=3)
            sink.write("/people_truth", LEG_TRACKER_PERSON, person, t + 0.05)


def test_info_says_ground_truth_yes_for_a_truth_topic(tmp_path: Path) -> None:
    bag = tmp_path / "truth.bag"
    _truth_bag(bag)
    res = CliRunner().invoke(app, ["info", str(bag)])
    assert res.exit_code == 0, res.output
    assert "ground truth: yes, topic /people_truth (use --truth BAG:/people_truth)" in res.stdout
    res = CliRunner().invoke(app, ["info", str(bag), "--json"])
    assert '"ground_truth": true' in res.stdout


def test_truth_on_another_clock_is_a_note_and_varying_stamps_a_warning() -> None:
    def counts(diffs: list[float]) -> PairingCounts:
        c = PairingCounts()
        c.max_stamp_offset = max(abs(d) for d in diffs)
        c.min_stamp_difference, c.max_stamp_difference = min(diffs), max(diffs)
        return c

    assert counts([0.0, 0.01]).stamp_check() == ("", False)
    text, is_warning = counts([-130.30, -130.28, -130.27]).stamp_check()
    assert not is_warning and "-130.285 s" in text and "paired by scan index" in text
    text, is_warning = counts([-130.3, 0.0]).stamp_check()
    assert is_warning and "up to 130.300 s" in text


def test_text_and_empty_files_named_bag_are_refused_plainly(tmp_path: Path) -> None:
    text, empty = tmp_path / "notes.bag", tmp_path / "empty.bag"
    text.write_text("hello world\n")
    empty.write_bytes(b"")
    with pytest.raises(RecordingError, match="not a bag: it starts with text"):
        check_bag_file(text)
    with pytest.raises(RecordingError, match=r"empty \(0 bytes\)"):
        check_bag_file(empty)
    res = CliRunner().invoke(app, ["info", str(text)])
    assert isinstance(res.exception, RecordingError)
    message = str(res.exception)
    assert "not a bag" in message and "reindex" not in message and "Error" not in message


@pytest.mark.parametrize(
    "command", ["track", "view", "evaluate", "info", "detect", "train", "fit", "bench", "align"]
)
def test_help_names_values_plainly(command: str) -> None:
    res = CliRunner().invoke(app, [command, "--help"], env={"COLUMNS": "100"})
    assert res.exit_code == 0
    for name in ("<str>", "<list[", "<path>", "<int>", "<float", "<Path>"):
        assert name not in res.stdout, res.stdout
    if command == "track":
        help_text = res.stdout.split("--background", 1)[1].split("\n  --", 1)[0]
        assert len(help_text.splitlines()) <= 4, help_text


def test_command_summaries_are_not_cut_mid_sentence() -> None:
    res = CliRunner().invoke(app, ["--help"], env={"COLUMNS": "100"})
    assert "et al." not in res.stdout.split("Commands:")[1]
    assert "Train the AdaBoost leg detector from labelled scans." in res.stdout


def test_upper_body_pf_on_a_leg_height_laser_warns(demo: Path, tmp_path: Path) -> None:
    from laserpeople.pipeline.laser_height import upper_body_warning

    out = tmp_path / "u.csv"
    args = ["track", str(demo), "--tracker", "upper-body-pf", "-o", str(out)]
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 0, res.output
    assert "upper-body-pf models a laser at upper-body height" in res.stderr
    assert "laser at 0.20 m (leg height)" in res.stderr
    assert "is not recorded" in upper_body_warning("upper-body-pf", ["/scan"], {})
    assert upper_body_warning("upper-body-pf", ["/scan"], {"/scan": 1.1}) == ""
    assert upper_body_warning("feet-pf", ["/scan"], {"/scan": 0.2}) == ""


@pytest.mark.parametrize(
    ("tracker", "has_leg_tracker"),
    [("leg-mht", True), ("nn", False), ("group-mht", True), ("csa", True)],
)
def test_print_config_prints_only_the_sections_the_tracker_reads(
    tracker: str, has_leg_tracker: bool
) -> None:
    res = CliRunner().invoke(app, ["track", "--tracker", tracker, "--print-config"])
    assert res.exit_code == 0, res.output
    sections = [ln for ln in res.stdout.splitlines() if ln.startswith("[") and "." not in ln]
    assert ("[leg_tracker]" in sections) is has_leg_tracker
    assert ("[leg_foreground]" in sections) is (tracker in ("group-mht", "csa"))


def test_view_reads_truth_from_a_bag_topic_as_evaluate_does(tmp_path: Path) -> None:
    bag = tmp_path / "truth.bag"
    _truth_bag(bag)
    out = tmp_path / "v.png"
    res = CliRunner().invoke(
        app, ["view", str(bag), "--truth", f"{bag}:/people_truth", "--scan", "3", "-o", str(out)]
    )
    assert res.exit_code == 0, res.output
    assert out.stat().st_size > 0
    assert "labels of 1 person on" in res.stderr and "truth: 1 person" not in res.stderr
    res = CliRunner().invoke(app, ["view", "--help"], env={"COLUMNS": "200"})
    assert "BAG:/topic" in res.stdout and "(world frame)" not in res.stdout


def test_sources_are_one_short_line() -> None:
    from laserpeople.config import SOURCE_LENGTH, short_source

    assert short_source("000 Table 10") == "000 Table 10"
    long_paper = "000 eqs. 8-10 (the deletion mass N-scan-back pruning cuts off); " + "x" * 80
    assert short_source(long_paper) == "000 eqs. 8-10"
    measured = "measured (issue 10, session 14, docs/people-benchmarks.md): " + "y" * 500
    assert short_source(measured) == "measured: docs/people-benchmarks.md"
    assumed = "assumption (000 gives no value): a swinging leg gains ~1.5 m/s in ~0.1 s; " * 3
    assert short_source(assumed) == "assumption"
    assert short_source("as PersonParams.max_spread (extension of 000): " + "z" * 90) == (
        "as PersonParams.max_spread"
    )
    res = CliRunner().invoke(app, ["track", "--tracker", "leg-mht", "--print-config"])
    assert res.exit_code == 0
    for line in res.stdout.splitlines():
        assert "session" not in line and "issue " not in line, line
    docs = (REPO / "docs" / "parameters.md").read_text()
    assert "session" not in docs
    assert all(len(short_source(s)) <= SOURCE_LENGTH + 10 for s in (measured, assumed))


def test_view_draws_a_sensor_frame_csv_where_the_world_frame_one_is(
    demo: Path, tmp_path: Path
) -> None:
    from PIL import Image

    from laserpeople.io.tracks_csv import read_tracks_frame

    pictures = []
    for frame in ("sensor", "world"):
        csv_path = tmp_path / f"{frame}.csv"
        args = ["--quiet", "track", str(demo), "-o", str(csv_path), "--output-frame", frame]
        assert CliRunner().invoke(app, args).exit_code == 0
        assert read_tracks_frame(csv_path) == frame
        png = tmp_path / f"{frame}.png"
        res = CliRunner().invoke(
            app, ["view", str(demo), "--tracks", str(csv_path), "--scan", "40", "-o", str(png)]
        )
        assert res.exit_code == 0, res.output
        assert f"tracks in the {frame} frame" in res.stderr
        pictures.append(np.asarray(Image.open(png).convert("RGB")).astype(float))
    # the same picture (up to anti-aliasing of the 4-decimal positions)
    assert np.abs(pictures[0] - pictures[1]).mean() < 0.01


def test_view_draws_every_laser_of_a_fused_run(tmp_path: Path) -> None:
    from laserpeople.io import open_recording
    from laserpeople.sim import run_scenario
    from laserpeople.viz import Scene

    rec = tmp_path / "four.npz"
    run_scenario("speed-normal", seconds=1.0, seed=0).write(rec)  # four lasers (004)
    source = open_recording(rec)
    names = [t.name for t in source.topics()]
    source.close()
    assert len(names) >= 2
    one = list(Scene(rec, topic=names[0], frame="world").frames())
    every = list(Scene(rec, topic=names[0], other_topics=tuple(names[1:]), frame="world").frames())
    assert len(one) == len(every)
    assert len(every[5].points) > len(one[5].points)  # the other lasers' points drawn too
    res = CliRunner().invoke(
        app, ["view", str(rec), "--topics", "all", "--scan", "5", "-o", str(tmp_path / "v.png")]
    )
    assert res.exit_code == 0, res.output
    assert f"topics {', '.join(names)}" in res.stderr


def test_view_of_world_frame_tracks_without_poses_asks_for_the_mounts(tmp_path: Path) -> None:
    from laserpeople.io import write_recording
    from laserpeople.scan import Scan

    rec = tmp_path / "no_poses.npz"
    ranges = np.full(181, 3.0)
    scans = [Scan(0.1 * k, -1.5, 3.0 / 180, ranges, 0.0, 8.0, index=k) for k in range(3)]
    write_recording(rec, scans)
    csv_path = tmp_path / "world.csv"
    csv_path.write_text(
        "scan,stamp,track_id,kind,x,y,vx,vy,cov_xx,cov_xy,cov_yy,size,labels,topic,frame\n"
        "1,0.1,0,person,1.0,2.0,0,0,0.01,0,0.01,1,,laser,world\n"
    )
    res = CliRunner().invoke(
        app,
        ["view", str(rec), "--tracks", str(csv_path), "--scan", "1", "-o", str(tmp_path / "v.png")],
    )
    assert res.exception is not None
    message = str(res.exception)
    assert "scan 1: the tracks are in the world frame" in message
    assert "--mount" in message and "--output-frame" not in message


def test_info_does_not_take_the_tracks_of_track_bag_for_ground_truth(tmp_path: Path) -> None:
    """A bag written by `track --bag` holds people_msgs/People tracks, the type of a truth
    topic: info names them as tracks, and says the bag has no ground truth."""
    from laserpeople.sim import run_scenario

    rec = tmp_path / "walk.npz"
    run_scenario("demo", seconds=1.0, seed=0).write(rec)
    bag = tmp_path / "tracks.mcap"
    ran = CliRunner().invoke(
        app, ["track", str(rec), "-o", str(tmp_path / "t.csv"), "--bag", str(bag)]
    )
    assert ran.exit_code == 0, ran.output
    res = CliRunner().invoke(app, ["info", str(bag)])
    assert res.exit_code == 0, res.output
    out = " ".join(res.stdout.split())
    assert "ground truth: no" in out
    assert "tracks of laserpeople track --bag: /laserpeople/people, /laserpeople/legs" in out
    res = CliRunner().invoke(app, ["info", str(bag), "--json"])
    assert '"ground_truth": false' in res.stdout
