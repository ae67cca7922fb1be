"""What a demanding user meets, seventh round: empty paths, the coasting's public view,
SIGTERM, recordings still being written, CSVs and units of other tools, a laser topic with
two message types or none, full disks in batch, tracks outside the picture, scans dropped
live, truth of no shared scan."""

from __future__ import annotations

from pathlib import Path

import pytest
import typer
from typer.testing import CliRunner

from laserpeople.cli import TEXT_PATH_PARAMETERS, app, is_path_parameter


def _path_options() -> list[tuple[str, str, bool]]:
    """(command, what the command line calls the parameter, whether it is an argument) of
    every parameter that names files."""
    group = typer.main.get_command(app)
    found = []
    for name, command in group.commands.items():  # type: ignore[attr-defined]
        for param in command.params:
            if is_path_parameter(name, param):
                is_argument = param.param_type_name == "argument"
                shown = param.metavar if is_argument else param.opts[0]
                found.append((name, shown, is_argument))
    return sorted(found)


def test_every_text_path_parameter_exists_and_paths_are_found() -> None:
    group = typer.main.get_command(app)
    names = {
        (name, p.name)
        for name, command in group.commands.items()  # type: ignore[attr-defined]
        for p in command.params
    }
    assert names >= TEXT_PATH_PARAMETERS
    found = {(c, o) for c, o, _ in _path_options()}
    assert ("track", "--config") in found and ("evaluate", "--truth") in found
    assert ("batch", "RECORDINGS") in found and ("demo", "--out-dir") in found
    assert len(found) >= 40


@pytest.mark.parametrize(("command", "option", "is_argument"), _path_options())
def test_an_empty_path_is_refused_naming_the_option(
    command: str, option: str, is_argument: bool
) -> None:
    """``--config ""`` (an unset shell variable) is no ``.``: refused before any file is
    read or written, naming the option."""
    args = [command, ""] if is_argument else [command, option, ""]
    run = CliRunner().invoke(app, args)
    text = " ".join(run.output.split())
    assert run.exit_code == 2, run.output
    assert f"Invalid value for '{option}'" in text and "': is empty: give a file" in text, text


def test_groups_oracle_gap_reads_no_private_attribute_but_its_own() -> None:
    """The benchmark asks the tracker's coasting through its public ``in``, not ``_last``."""
    import ast
    from pathlib import Path

    bench = Path(__file__).resolve().parents[1] / "benchmarks" / "groups_oracle_gap.py"
    tree = ast.parse(bench.read_text(encoding="utf-8"))
    private = {
        ast.unparse(node)
        for node in ast.walk(tree)
        if isinstance(node, ast.Attribute)
        and node.attr.startswith("_")
        and not node.attr.startswith("__")
        and not (isinstance(node.value, ast.Name) and node.value.id == "self")
    }
    assert private == set()
    assert "self.tracker.coasting" in bench.read_text(encoding="utf-8")


SIGTERM_AFTER = """
import os, signal, sys
from laserpeople.cli import {module} as command

def progress(items, total=None, description=""):
    for k, item in enumerate(items):
        if k == 6:
            os.kill(os.getpid(), signal.SIGTERM)
        yield item

command.progress = progress
sys.argv = ["laserpeople", *sys.argv[1:]]
from laserpeople.cli import run
run()
"""
"""A program that sends itself SIGTERM when the command's 7th scan is asked for."""


@pytest.mark.parametrize(("module", "what"), [("track", "tracks"), ("detect", "legs")])
def test_sigterm_stops_as_ctrl_c_naming_it_with_a_complete_csv(
    module: str, what: str, tmp_path: Path
) -> None:
    """``kill PID`` (SIGTERM) ended the process at once without a word; now it stops as on
    Ctrl-C: status 143, the message names SIGTERM and the scans the CSV holds, whole."""
    import csv
    import os
    import subprocess
    import sys

    from laserpeople.sim.scenarios import run_scenario

    recording = tmp_path / "walk.npz"
    run_scenario("figure-eight", seconds=3.0, seed=3).write(recording)
    out = tmp_path / "out.csv"
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1] / "src")}
    program = [sys.executable, "-c", SIGTERM_AFTER.format(module=module)]
    done = subprocess.run(
        [*program, module, str(recording), "-o", str(out)],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
        check=False,
    )
    text = " ".join(done.stderr.split())
    assert done.returncode == 143, done.stderr
    assert f"interrupted (SIGTERM) after 7 scans: {out} holds the {what}" in text, text
    with open(out, newline="", encoding="utf-8") as fh:
        scans = {int(row["scan"]) for row in csv.DictReader(fh)}
    assert scans and max(scans) <= 6, scans


def test_sigterm_is_named_and_gets_its_own_exit_status() -> None:
    import signal

    from laserpeople.cli.stopping import Terminated, stop_name, stop_on_sigterm, stop_status

    assert (stop_status(Terminated()), stop_status(KeyboardInterrupt())) == (143, 130)
    assert (stop_name(143), stop_name(130)) == ("SIGTERM", "Ctrl-C")
    before = signal.getsignal(signal.SIGTERM)
    try:
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        assert not stop_on_sigterm()  # ignored by the parent: kept ignored
        assert signal.getsignal(signal.SIGTERM) is signal.SIG_IGN
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        assert stop_on_sigterm()
        with pytest.raises(Terminated):
            signal.raise_signal(signal.SIGTERM)
    finally:
        signal.signal(signal.SIGTERM, before)


def test_a_file_of_another_format_is_given_the_name_its_reader_wants() -> None:
    from laserpeople.io.sniff import renamed

    assert renamed(Path("d/run.txt"), ".bag") == "run.bag"
    assert renamed(Path("run.bag.active"), ".bag") == "run.bag"  # not run.bag.bag
    assert renamed(Path("run.mcap.active"), ".bag") == "run.mcap.bag"
    assert renamed(Path("run"), ".npz") == "run.npz"


def _ros1_bag(path: Path) -> Path:
    path.write_bytes(b"#ROSBAG V2.0\n" + bytes(64))
    return path


def _ros2_folder_being_recorded(folder: Path, files: int = 1) -> Path:
    folder.mkdir()
    for k in range(files):
        (folder / f"{folder.name}_{k}.mcap").write_bytes(b"\x89MCAP0\r\n" + bytes(64))
    return folder


def test_recordings_still_being_written_are_named_so(tmp_path: Path) -> None:
    """``rosbag record``'s ``x.bag.active`` and a ROS 2 bag folder whose metadata.yaml is not
    written yet: said to be still recording (or stopped hard), with the file that reads."""
    from laserpeople.errors import RecordingError
    from laserpeople.io import open_recording

    active = _ros1_bag(tmp_path / "run.bag.active")
    with pytest.raises(RecordingError) as caught:
        open_recording(active)
    message = str(caught.value)
    assert "`rosbag record` writes a bag under this name while it records" in message
    assert "renamed to run.bag" in message and "run.bag.bag" not in message
    folder = _ros2_folder_being_recorded(tmp_path / "live", files=2)
    with pytest.raises(RecordingError) as caught:
        open_recording(folder)
    message = " ".join(str(caught.value).split())
    assert "a ROS 2 bag folder without metadata.yaml" in message
    assert f"give {folder / 'live_0.mcap'} itself (2 storage files: one at a time)" in message
    assert f"`ros2 bag reindex {folder}`" in message
    (tmp_path / "plain").mkdir()
    with pytest.raises(RecordingError, match="is a directory, not a recording"):
        open_recording(tmp_path / "plain")


def test_batch_of_a_folder_names_each_recording_still_being_written(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from laserpeople.cli.batch import folder_recordings

    for name in ("a.txt", "b.txt", "c.png", "d.png"):
        (tmp_path / name).write_text("x")
    _ros1_bag(tmp_path / "z.bag.active")
    _ros2_folder_being_recorded(tmp_path / "y_live")
    (tmp_path / "whole.npz").write_bytes(b"PK\x03\x04")
    assert folder_recordings(tmp_path, None) == [tmp_path / "whole.npz"]
    text = " ".join(capsys.readouterr().err.split())
    assert "left out 6 other entries (y_live (a ROS 2 bag folder without metadata.yaml" in text
    assert "z.bag.active (named as a bag `rosbag record` is still writing" in text
    assert "a.txt, b.txt, c.png, ...)" in text


def test_columns_of_another_tool_are_named_with_the_names_wanted() -> None:
    """Another case or an alias (``Timestamp``, ``ID``) is named for the missing column;
    a column stands for one missing column at most; a missing ``scan`` or ``kind`` none
    stands for is explained."""
    from laserpeople.io.csv_read import columns_to_rename

    hint = columns_to_rename(["scan", "stamp", "track_id", "x"], ["Timestamp", "ID", " X ", "k"])
    assert hint == (
        "; scan is the 0-based index of each scan on its laser topic, by which tracks and truth"
        " are paired; rename the column(s) Timestamp to stamp, ID to track_id,  X  to x (stamps"
        " in seconds, positions in metres, as this program writes them)"
    )
    assert "ID to track_id (" in columns_to_rename(["track_id", "person_id"], ["ID"])
    assert "to track_id" not in columns_to_rename(["person_id", "track_id"], ["ID"])
    assert columns_to_rename(["stamp"], ["when"]) == ""
    assert columns_to_rename(["kind"], ["KIND"]).startswith("; rename the column(s) KIND to kind")
    assert columns_to_rename(["kind"], []).startswith("; kind is leg, person or group")


def test_a_tracks_csv_of_another_tool_is_read_with_its_extra_columns_said(
    tmp_path: Path,
) -> None:
    from laserpeople.errors import LaserPeopleWarning, RecordingError
    from laserpeople.io.tracks_csv import iter_tracks_csv

    path = tmp_path / "other.csv"
    path.write_text("y,x,kind,track_id,stamp,scan,confidence,note\n2,1,person,a,0.1,3,0.9,\n")
    with pytest.warns(LaserPeopleWarning, match=r"column\(s\) confidence, note not read"):
        (scan,) = list(iter_tracks_csv(path))
    assert (scan.scan_index, scan.tracks[0].position.tolist()) == (3, [1.0, 2.0])
    path.write_text("Scan,Timestamp,ID,kind,X,Y\n3,0.1,a,person,1,2\n")
    with pytest.raises(RecordingError, match=r"rename the column\(s\) Scan to scan, Timestamp to"):
        list(iter_tracks_csv(path))


def test_a_tracks_csv_of_this_program_reads_without_a_warning(tmp_path: Path) -> None:
    import warnings

    from laserpeople.errors import LaserPeopleWarning
    from laserpeople.io.tracks_csv import KNOWN_COLUMNS, iter_tracks_csv

    path = tmp_path / "ours.csv"
    row = "3,0.1,7,group,1,2,0,0,0.1,0,0.1,2,,/scan,world,0,0,0,1 2;3 4"
    path.write_text(",".join(KNOWN_COLUMNS) + "\n" + row + "\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error", LaserPeopleWarning)
        (scan,) = list(iter_tracks_csv(path))
    assert scan.tracks[0].contour.tolist() == [[1.0, 2.0], [3.0, 4.0]]


def _paired(truth_stamps: list[float], tracks_stamps: list[float]) -> object:
    """The counts of pairing one person (5 m from the origin) and one track 0.1 m from
    them per scan, with these stamps."""
    import numpy as np

    from laserpeople.evaluation.pairing import PairingCounts, pair_by_scan
    from laserpeople.tracks import Track, Tracks
    from laserpeople.truth import TruthFrame

    def truth(k: int, stamp: float) -> TruthFrame:
        return TruthFrame(
            stamp=stamp,
            scan_index=k,
            person_ids=np.array([1]),
            positions=np.array([[3.0, 4.0]]),
            velocities=np.zeros((1, 2)),
            group_ids=np.array([-1]),
            leg_positions=np.zeros((1, 2, 2)),
            hues=np.zeros(1),
        )

    def tracks(k: int, stamp: float) -> Tracks:
        track = Track(
            track_id=1,
            kind="person",
            position=np.array([3.0, 4.1]),
            velocity=np.zeros(2),
            covariance=np.eye(2),
        )
        return Tracks(stamp, k, (track,), "world")

    counts = PairingCounts()
    frames = [truth(k, s) for k, s in enumerate(truth_stamps)]
    list(pair_by_scan(frames, [tracks(k, s) for k, s in enumerate(tracks_stamps)], counts))
    return counts


@pytest.mark.parametrize(
    ("factor", "unit", "said"),
    [
        (1000.0, "milliseconds", True),
        (1e6, "microseconds", True),
        (1e9, "nanoseconds", True),
        (1009.0, "milliseconds", True),  # within 1 %
        (1011.0, "", False),  # beyond it
        (100.0, "", False),
        (1.0, "", False),
        (1e-3, "milliseconds", True),  # the truth's in ms
    ],
)
def test_stamps_in_another_unit_are_named_by_the_ratio_of_their_spans(
    factor: float, unit: str, said: bool
) -> None:
    """Spans are compared, not stamps: tracks stamped from 0 in ms against truth stamped
    from 50 s in s still show the factor of 1000."""
    truth = [50.0 + 0.1 * k for k in range(20)]
    tracks = [0.1 * k * factor for k in range(20)]
    text = _paired(truth, tracks).stamp_unit()  # type: ignore[attr-defined]
    assert bool(text) == said, text
    if said:
        whose = "truth's" if factor < 1 else "tracks'"
        assert f"the {whose} stamps advance" in text and f"in {unit}?" in text


def test_a_stamp_unit_is_said_in_the_stamp_warning_and_not_with_one_pair() -> None:
    counts = _paired([0.1 * k for k in range(10)], [100.0 * k for k in range(10)])
    text, is_warning = counts.stamp_check()  # type: ignore[attr-defined]
    assert is_warning and "advance 1,000 times as far as the truth's" in text
    assert "check that they come from the same recording" not in text
    one = _paired([5.0], [5000.0])
    assert one.stamp_unit() == ""  # type: ignore[attr-defined]
    other = _paired([0.1 * k for k in range(10)], [3.0 * k for k in range(10)])
    assert "check that they come from the same recording" in other.stamp_check()[0]  # type: ignore[attr-defined]


def test_positions_in_another_unit_are_named_by_their_mean_distance() -> None:
    """One person 5 m out, one track 5.1 m out: the ratio is 1.02 (metres); the track in
    mm is 1020 times as far; 3x around the factor is the band (2,900 still mm, 3,100 not)."""
    from laserpeople.evaluation.pairing import PairingCounts

    def said(truth: float, tracks: float) -> str:
        counts = PairingCounts(truth_distances=(truth, 1), tracks_distances=(tracks, 1))
        return counts.position_unit()

    assert said(5.0, 5.1) == ""
    assert "the tracks are 1,020 times as far" in said(5.0, 5100.0)
    assert "in millimetres?" in said(1.0, 2900.0) and said(1.0, 3100.0) == ""
    assert "in millimetres?" in said(1.0, 340.0) and said(1.0, 320.0) == ""
    assert "the people are 1,000 times as far" in said(1000.0, 1.0)
    assert "in micrometres?" in said(1.0, 1e6)
    assert said(0.0, 5.0) == "" and PairingCounts().position_unit() == ""
    counts = _paired([0.1 * k for k in range(3)], [0.1 * k for k in range(3)])
    assert counts.truth_distances == pytest.approx((15.0, 3), abs=1e-12)  # type: ignore[attr-defined]
    assert counts.tracks_distances[0] == pytest.approx(3 * 5.08035, abs=1e-4)  # type: ignore[attr-defined]


def test_evaluate_names_millimetres_and_milliseconds_of_another_tool(tmp_path: Path) -> None:
    from laserpeople.cli import app

    truth = tmp_path / "truth.csv"
    truth.write_text(
        "scan,stamp,person_id,x,y\n" + "".join(f"{k},{0.1 * k:.1f},1,3,4\n" for k in range(10))
    )
    mm = tmp_path / "mm.csv"
    mm.write_text(
        "scan,stamp,track_id,kind,x,y\n"
        + "".join(f"{k},{0.1 * k:.1f},1,person,3000,4100\n" for k in range(10))
    )
    run = CliRunner().invoke(app, ["evaluate", str(mm), "--truth", str(truth)])
    text = " ".join(run.output.split())
    assert (
        "as far from the origin as the people on average: are their positions in millimetres?"
        in text
    )
    assert "if not, are the truth and the tracks in the same frame?" in text
    ms = tmp_path / "ms.csv"
    ms.write_text(
        "scan,stamp,track_id,kind,x,y\n"
        + "".join(f"{k},{100 * k},1,person,3,4.1\n" for k in range(10))
    )
    run = CliRunner().invoke(app, ["evaluate", str(ms), "--truth", str(truth)])
    text = " ".join(run.output.split())
    assert run.exit_code == 0, text
    assert (
        "the tracks' stamps advance 1,000 times as far as the truth's: are they in milliseconds?"
        in text
    )


def _bag_with_two_types_on_scan(path: Path) -> None:
    """A ROS 2 MCAP bag whose /scan carries 6 LaserScans and, first, 2 std_msgs Strings."""
    import math

    import numpy as np
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    types = store.types
    with Writer(path, version=8, storage_plugin=StoragePlugin.MCAP) as writer:
        text = writer.add_connection("/scan", "std_msgs/msg/String", typestore=store)
        laser = writer.add_connection("/scan", "sensor_msgs/msg/LaserScan", typestore=store)
        for k in range(6):
            t = 10 * 10**9 + k * 10**8
            header = types["std_msgs/msg/Header"](
                stamp=types["builtin_interfaces/msg/Time"](sec=10, nanosec=k * 10**8),
                frame_id="laser",
            )
            msg = types["sensor_msgs/msg/LaserScan"](
                header=header,
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
            writer.write(laser, t, store.serialize_cdr(msg, "sensor_msgs/msg/LaserScan"))
            if k % 3 == 0:
                note = types["std_msgs/msg/String"](data="hello")
                writer.write(text, t + 1, store.serialize_cdr(note, "std_msgs/msg/String"))


def test_a_laser_topic_carrying_another_type_too_is_read_and_the_rest_said(
    tmp_path: Path,
) -> None:
    """Not 'scan 1 is damaged': the other type's messages are left out and counted; the
    topic is a laser topic even when the other type's connection comes first."""
    from laserpeople.cli import app
    from laserpeople.io import open_recording

    bag = tmp_path / "two"
    _bag_with_two_types_on_scan(bag)
    rec = open_recording(bag)
    assert [(t.name, t.count) for t in rec.topics()] == [("/scan", 6)]
    assert [s.index for s in rec.scans()] == [0, 1, 2, 3, 4, 5]
    assert rec.read_notes() == [  # type: ignore[attr-defined]
        "/scan also carries messages of another type: 2 std_msgs/msg/String messages left "
        "out (only its laser scans are read)"
    ]
    rec.close()
    run = CliRunner().invoke(app, ["info", str(bag)])
    assert run.exit_code == 0, run.output
    assert "/scan also carries other messages, left out: 2 std_msgs/msg/String" in run.output


def test_a_batch_tracks_file_not_written_names_the_output_and_keeps_nothing(
    tmp_path: Path,
) -> None:
    """The writer's error named the hidden staging file and said what it holds, but the
    staging file is removed: the row names the tracks file and says nothing is kept."""
    from laserpeople.batch.task import unwritten
    from laserpeople.errors import RecordingError

    temp, final = tmp_path / ".run.csv.1-abc.tmp", tmp_path / "run.csv"
    full = RecordingError(
        "cannot write the tracks CSV at scan 145 of /scan: No space left on device; it holds "
        "the rows of the 141 scans handled before (120 with rows, up to scan 144 of /scan), "
        "whole: scan 145 of /scan and the scans after it are missing",
        path=temp,
        hint="free disk space or choose another path with -o",
    )
    said = unwritten(full, temp, final)
    assert str(said) == (
        f"{final}: cannot write the tracks CSV at scan 145 of /scan: No space left on device; "
        "nothing of it is kept (a tracks file is moved into place whole) (free disk space, "
        "then run the same command again: it tracks what is not done)"
    )
    other = RecordingError("scan 3 is damaged", path=tmp_path / "run.bag")
    assert unwritten(other, temp, final) is other


def _scene_with_tracks(positions: list[tuple[float, float]]) -> object:
    """A scene of 3 sensor-frame scans (points 2 m out over +-0.5 rad), one track at each
    of ``positions`` in every scan."""
    import numpy as np

    from laserpeople.scan import Scan
    from laserpeople.tracks import Track, Tracks
    from laserpeople.viz.scene import Scene

    scans = [
        Scan(
            stamp=0.1 * k,
            angle_min=-0.5,
            angle_increment=0.1,
            ranges=np.full(11, 2.0),
            range_min=0.1,
            range_max=8.0,
            sensor="laser",
            index=k,
        )
        for k in range(3)
    ]
    tracks = [
        Tracks(
            0.1 * k,
            k,
            tuple(
                Track(
                    track_id=i,
                    kind="person",
                    position=np.array(p),
                    velocity=np.zeros(2),
                    covariance=np.eye(2),
                )
                for i, p in enumerate(positions)
            ),
            "sensor",
        )
        for k in range(3)
    ]
    return Scene(scans, tracks, frame="sensor", tracks_frame="sensor")


def test_track_positions_outside_the_drawn_area_are_counted_with_the_farthest() -> None:
    """A track inside the area is not counted; one 5 km out (mm) and one 2.5 m beyond the
    box of the points (beyond the 2 m slack: not fitted) are, with the farthest distance
    beyond the area's edge; the warning asks about millimetres only past 100 m."""
    inside = _scene_with_tracks([(1.9, 0.0)])
    xmin, xmax, ymin, ymax = inside.extent()  # type: ignore[attr-defined]
    assert inside.tracks_outside.count == 0 and inside.tracks_outside.warning() == ""  # type: ignore[attr-defined]
    box_hi = xmax - 0.5  # (the area is the box with a 0.5 m margin)
    scene = _scene_with_tracks([(1.9, 0.0), (box_hi + 2.5, 0.0), (5000.0, 4000.0)])
    assert scene.extent() == pytest.approx((xmin, xmax, ymin, ymax), abs=1e-12)  # type: ignore[attr-defined]
    outside = scene.tracks_outside  # type: ignore[attr-defined]
    assert (outside.count, outside.of) == (6, 9)
    assert outside.farthest == pytest.approx(5000.0 - xmax, abs=1e-9)
    assert "6 of 9 track positions lie outside" in outside.warning()
    assert "positions in millimetres" in outside.warning()
    near = _scene_with_tracks([(1.9, 0.0), (box_hi + 2.5, 0.0)])
    near.extent()  # type: ignore[attr-defined]
    assert near.tracks_outside.farthest == pytest.approx(2.0, abs=1e-9)  # type: ignore[attr-defined]
    assert "tracks beyond the bulk of the scan points" in near.tracks_outside.warning()  # type: ignore[attr-defined]


def test_track_plot_and_animate_say_the_tracks_outside_the_picture_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A drawing's result carries the scene's count (render), and `track --plot --animate`
    says it once, as `view` does; nothing is said when every track is inside."""
    from laserpeople import viz
    from laserpeople.cli.track import draw_tracks
    from laserpeople.viz.render import render

    scene = _scene_with_tracks([(1.9, 0.0), (5000.0, 4000.0)])
    drawn = render(scene, tmp_path / "p.png")  # type: ignore[arg-type]
    assert (drawn.tracks_outside.count, drawn.tracks_outside.of) == (3, 6)

    def fake(scene: object) -> object:
        return lambda *args, **kwargs: render(scene, args[2])  # type: ignore[arg-type]

    monkeypatch.setattr(viz, "plot_tracks", fake(scene))
    monkeypatch.setattr(viz, "animate_tracks", fake(scene))
    draw_tracks(None, tmp_path / "t.csv", None, "sensor", tmp_path / "a.png", tmp_path / "b.gif")  # type: ignore[arg-type]
    assert capsys.readouterr().err.count("3 of 6 track positions lie outside") == 1
    inside = _scene_with_tracks([(1.9, 0.0)])
    monkeypatch.setattr(viz, "plot_tracks", fake(inside))
    draw_tracks(None, tmp_path / "t.csv", None, "sensor", tmp_path / "c.png", None)  # type: ignore[arg-type]
    assert "lie outside" not in capsys.readouterr().err


def test_live_warns_when_the_tracking_drops_more_than_one_scan_in_a_hundred() -> None:
    """1 of 100 dropped is no news; 2 of 100 is, with the share, the laser's mean period
    (from the arrivals: 99 periods over 0.99 s = 10.0 ms) and the tracking time."""
    from laserpeople.live.source import LiveCounts

    counts = LiveCounts()
    counts.received["/scan"] = 100
    counts.first_arrival["/scan"], counts.last_arrival["/scan"] = 5.0, 5.99
    counts.dropped["/scan"] = 1
    assert counts.dropped_warning("/scan", 12.0) == ""
    counts.dropped["/scan"] = 2
    assert counts.dropped_warning("/scan", 12.0) == (
        "/scan: 2 of 100 scans (2%) were dropped, not tracked: the tracking did not keep up "
        "(median 12.00 ms a frame against a scan every 10.0 ms), so the tracks skip them; a "
        "lighter tracker, fewer lasers or a less loaded computer keeps up"
    )
    assert LiveCounts().dropped_warning("/scan", 1.0) == ""


def _bag_with_an_empty_laser_topic(path: Path) -> None:
    """A ROS 2 MCAP bag with a /scan connection and no scan on it (and one String)."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    with Writer(path, version=8, storage_plugin=StoragePlugin.MCAP) as writer:
        writer.add_connection("/scan", "sensor_msgs/msg/LaserScan", typestore=store)
        chat = writer.add_connection("/chatter", "std_msgs/msg/String", typestore=store)
        text = store.types["std_msgs/msg/String"](data="x")
        writer.write(chat, 10**9, store.serialize_cdr(text, "std_msgs/msg/String"))


@pytest.mark.parametrize("command", ["track", "detect"])
def test_a_laser_topic_without_a_scan_is_an_error_not_an_empty_success(
    command: str, tmp_path: Path
) -> None:
    from laserpeople.cli import app
    from laserpeople.errors import RecordingError

    bag = tmp_path / "empty_topic"
    _bag_with_an_empty_laser_topic(bag)
    out = tmp_path / "out.csv"
    run = CliRunner().invoke(app, [command, str(bag), "-o", str(out)])
    assert run.exit_code == 1 and isinstance(run.exception, RecordingError), run.output
    assert str(run.exception).startswith(
        f"{bag}: no scan was read, so {out} holds the CSV header alone (`laserpeople info`"
    )
    assert out.read_text().startswith("scan,stamp,") and len(out.read_text().splitlines()) == 1


def test_info_lists_a_laser_topic_without_a_scan_and_no_pose_line(tmp_path: Path) -> None:
    from laserpeople.cli import app

    bag = tmp_path / "empty_topic"
    _bag_with_an_empty_laser_topic(bag)
    run = CliRunner().invoke(app, ["info", str(bag)])
    assert run.exit_code == 0, run.output
    row = next(line for line in run.output.splitlines() if "/scan" in line)
    assert row.split() == ["/scan", "0", "-", "-", "-", "-", "-", "-", "0/0"]
    assert "poses:" not in run.output  # (was 'every scan has a pose in frame None')


def test_a_truth_spec_without_a_bag_before_its_topic_is_refused() -> None:
    """``--truth :/people`` (``--truth "$BAG:/people"`` with BAG unset) named the current
    folder ('.: a topic can only be given for a bag')."""
    from laserpeople.errors import ConfigError
    from laserpeople.io.truth_bag import split_truth_spec

    with pytest.raises(ConfigError, match=r"truth ':/people' names no bag before ':/people'"):
        split_truth_spec(":/people")
    assert split_truth_spec("run.bag:/people") == (Path("run.bag"), "/people")
    assert split_truth_spec("run.bag:") == (Path("run.bag"), None)
    assert split_truth_spec("truth.csv") == (Path("truth.csv"), None)


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_a_tracks_parquet_on_a_full_disk_is_a_clear_error() -> None:
    """pyarrow's own words were 'OSError: [Errno 28] Error writing bytes to file ... (at
    error.pxi:92)'; the error names the file, the scans buffered and the reason."""
    import numpy as np

    from laserpeople.batch.parquet import TracksParquetSink
    from laserpeople.errors import RecordingError
    from laserpeople.frame import Frame
    from laserpeople.tracks import Track, Tracks

    sink = TracksParquetSink("/dev/full")
    track = Track(
        track_id=1,
        kind="person",
        position=np.array([1.0, 2.0]),
        velocity=np.zeros(2),
        covariance=np.eye(2),
    )
    for k in range(3):
        sink.write(
            Frame(index=k, stamp=0.1 * k, scans=(), topic="/scan"), Tracks(0.1 * k, k, (track,))
        )
    with pytest.raises(RecordingError) as caught:
        sink.close()
    assert str(caught.value) == (
        "/dev/full: cannot write the tracks Parquet with the rows up to scan 2: No space left "
        "on device (free disk space or choose another output folder)"
    )


def _apart(
    truth: tuple[int, int],
    truth_stamps: tuple[float, float],
    tracks: tuple[int, int],
    tracks_stamps: tuple[float, float],
) -> object:
    from laserpeople.evaluation.pairing import PairingCounts

    return PairingCounts(
        frames_scored=30,
        frames_without_tracks=30,
        truth_scans=truth,
        truth_stamps=truth_stamps,
        tracks_scans=tracks,
        tracks_stamps=tracks_stamps,
    )


def test_truth_of_the_tracks_own_clock_is_told_from_another_recording() -> None:
    """The truth's scans 1000-1029 at 0.1 s put the tracks' scan 0 at 100.0 s; 0.5 s plus
    2 % of the 100 s between is the tolerance (2.5 s): 102.49 is one clock, 102.51 not."""
    truth, stamps = (1000, 1029), (200.0, 202.9)
    assert _apart(truth, stamps, (0, 49), (100.0, 104.9)).one_clock()  # type: ignore[attr-defined]
    assert _apart(truth, stamps, (0, 49), (102.49, 107.39)).one_clock()  # type: ignore[attr-defined]
    assert not _apart(truth, stamps, (0, 49), (102.51, 107.41)).one_clock()  # type: ignore[attr-defined]
    assert not _apart(truth, stamps, (0, 49), (97.49, 102.39)).one_clock()  # type: ignore[attr-defined]
    # a truth of one scan: the tracks' period (0.1 s) puts scan 0 at 200 - 100 = 100 s
    assert _apart((1000, 1000), (200.0, 200.0), (0, 49), (100.0, 104.9)).one_clock()  # type: ignore[attr-defined]
    assert not _apart((1000, 1000), (200.0, 200.0), (0, 0), (100.0, 100.0)).one_clock()  # type: ignore[attr-defined]


def test_only_truth_and_tracks_apart_in_scans_and_clock_are_refused() -> None:
    other = _apart((1000, 1029), (600.0, 602.9), (0, 49), (100.0, 104.9))
    error = other.disjoint()  # type: ignore[attr-defined]
    assert error is not None and str(error).startswith(
        "truth and tracks share no scan: the truth covers scans 1000-1029 (stamps "
        "600.000-602.900 s), the tracks scans 0-49 (stamps 100.000-104.900 s)"
    )
    assert _apart((1000, 1029), (200.0, 202.9), (0, 49), (100.0, 104.9)).disjoint() is None  # type: ignore[attr-defined]
    overlapping = _apart((40, 69), (600.0, 602.9), (0, 49), (100.0, 104.9))
    assert overlapping.disjoint() is None  # type: ignore[attr-defined]
    touching = _apart((50, 79), (600.0, 602.9), (0, 49), (100.0, 104.9))
    assert touching.disjoint() is not None  # type: ignore[attr-defined]
    from laserpeople.evaluation.pairing import PairingCounts

    some_matched = PairingCounts(
        frames_scored=30,
        frames_without_tracks=29,
        truth_scans=(1000, 1029),
        truth_stamps=(600.0, 602.9),
        tracks_scans=(0, 49),
        tracks_stamps=(100.0, 104.9),
    )
    assert some_matched.disjoint() is None


def test_evaluate_of_several_files_makes_truth_of_no_shared_scan_a_row_error(
    tmp_path: Path,
) -> None:
    from laserpeople.cli import app

    def write(path: Path, header: str, row: str, scans: range, stamp0: float) -> Path:
        path.write_text(
            header + "".join(row.format(k=k, t=stamp0 + 0.1 * k, x=0.1 * k) for k in scans)
        )
        return path

    tracks_header = "scan,stamp,track_id,kind,x,y\n"
    good = write(tmp_path / "good.csv", tracks_header, "{k},{t:.3f},1,person,{x:.2f},1\n",
                 range(0, 30), 100.0)  # fmt: skip
    other = write(tmp_path / "other.csv", tracks_header, "{k},{t:.3f},1,person,{x:.2f},1\n",
                  range(500, 530), 900.0)  # fmt: skip
    truth = write(tmp_path / "truth.csv", "scan,stamp,person_id,x,y\n", "{k},{t:.3f},7,{x:.2f},1\n",
                  range(0, 30), 100.0)  # fmt: skip
    run = CliRunner().invoke(
        app, ["evaluate", str(good), str(other), "--truth", str(truth), "--truth", str(truth)]
    )
    text = " ".join(run.output.split())
    assert "other: truth and tracks share no scan: the truth covers scans 0-29" in text, text
    row = next(line for line in run.output.splitlines() if "│ other" in line)
    assert "error" in row
    assert "pooled (1)" in run.output


def test_a_manifest_that_cannot_be_written_is_an_error_naming_it(tmp_path: Path) -> None:
    """A full disk while `batch` appends a manifest line ended in a traceback
    (``OSError: [Errno 28]`` from manifest.py); the error names the manifest and the line,
    and keeps the lines before."""
    import os

    from laserpeople.batch.manifest import Manifest
    from laserpeople.batch.task import TopicRow
    from laserpeople.errors import RecordingError

    manifest = Manifest(tmp_path)
    row = TopicRow(recording="a.bag", name="a", topic="/scan", status="done")
    manifest.record("a", "h", "d", [row])
    kept = (tmp_path / "manifest.jsonl").read_text()
    (tmp_path / "manifest.jsonl").unlink()
    (tmp_path / "manifest.jsonl").mkdir()  # (a write that fails as a full disk's does)
    with pytest.raises(RecordingError) as caught:
        manifest.record("b", "h", "d", [row])
    message = str(caught.value)
    assert message.startswith(
        f"{tmp_path / 'manifest.jsonl'}: cannot write the line of b into the manifest: "
    )
    assert "the lines written before are kept" in message and "free disk space" in message
    (tmp_path / "manifest.jsonl").rmdir()
    (tmp_path / "manifest.jsonl").write_text(kept)
    (tmp_path / f".manifest.jsonl.{os.getpid()}.tmp").mkdir()
    with pytest.raises(RecordingError, match="cannot write its lines in one per recording"):
        manifest.compact()
    assert (tmp_path / "manifest.jsonl").read_text() == kept


@pytest.mark.parametrize("name", ["summary.parquet", "summary.csv"])
def test_a_batch_summary_that_cannot_be_written_is_an_error_naming_it(
    name: str, tmp_path: Path
) -> None:
    """(pyarrow's 'OSError: ... error.pxi' or a traceback before.)"""
    import os

    from laserpeople.batch.summary import write_summary
    from laserpeople.batch.task import TopicRow
    from laserpeople.errors import RecordingError

    blocker = tmp_path / f".{name}.{os.getpid()}.tmp"
    blocker.mkdir()  # (a write that fails as a full disk's does)
    (blocker / "x").write_text("x")  # (not removed: a folder, not the staging file)
    row = TopicRow(recording="a.bag", name="a", topic="/scan", status="done")
    with pytest.raises(RecordingError) as caught:
        write_summary([row], tmp_path)
    assert str(caught.value).startswith(f"{tmp_path / name}: cannot write the batch summary: ")
    assert "the tracks and the manifest are kept" in str(caught.value)
    assert not (tmp_path / name).exists()
