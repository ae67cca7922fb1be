"""Text a user gave (file names, topics, track ids, notes) is printed as written: rich takes
``[a]`` for markup and drops it, and draws ``:fire:`` as an emoji, unless told not to."""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

from laserpeople.cli import app

NAME = "run[a]:fire:"
"""A file name rich would print as ``run🔥`` (markup tag dropped, emoji code drawn)."""


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from laserpeople.sim.scenarios import run_scenario

    path = tmp_path_factory.mktemp("text") / f"{NAME}.npz"
    run_scenario("figure-eight", seconds=4.0, seed=3).write(path)
    return path


@pytest.fixture(scope="module")
def tracks(recording: Path) -> Path:
    """Tracks of ``recording`` whose ids are text with brackets (``[b]0``)."""
    plain = recording.with_name("plain.csv")
    run = CliRunner().invoke(app, ["--quiet", "track", str(recording), "-o", str(plain)])
    assert run.exit_code == 0, run.output
    with plain.open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    out = recording.with_name(f"{NAME}.csv")
    with out.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        for row in rows:
            writer.writerow({**row, "track_id": f"[b]{row['track_id']}"})
    return out


def test_info_prints_the_file_name_as_written(recording: Path) -> None:
    run = CliRunner().invoke(app, ["info", str(recording)])
    assert run.exit_code == 0, run.output
    assert f"{NAME}.npz" in run.output


def test_bench_prints_the_file_name_as_written(recording: Path) -> None:
    run = CliRunner().invoke(
        app, ["--quiet", "bench", str(recording), "--tracker", "nn", "--repeat", "1"]
    )
    assert run.exit_code == 0, run.output
    assert f"{NAME}.npz: " in run.output


def test_evaluate_of_many_prints_each_name_as_written(recording: Path, tracks: Path) -> None:
    other = tracks.with_name("[c]other.csv")
    other.write_bytes(tracks.read_bytes())
    run = CliRunner().invoke(
        app,
        ["evaluate", str(tracks), str(other), "--truth", str(recording), "--truth", str(recording)],
    )
    assert run.exit_code == 0, run.output
    table = run.stdout
    assert f"│ {NAME} " in table and "│ [c]other " in table


def test_evaluate_followed_person_prints_text_track_ids_as_written(
    recording: Path, tracks: Path
) -> None:
    run = CliRunner().invoke(
        app, ["evaluate", str(tracks), "--truth", str(recording), "--followed-person", "auto"]
    )
    assert run.exit_code == 0, run.output
    assert "frames per id: [b]" in run.stdout


def test_fit_prints_recordings_and_notes_as_written(capsys: pytest.CaptureFixture[str]) -> None:
    from laserpeople.cli.fit import _print
    from laserpeople.fitting.estimates import Estimate
    from laserpeople.fitting.flow import FitResult
    from laserpeople.fitting.validate import ValidationRow

    result = FitResult(
        tracker="leg-mht",
        params=None,
        estimates=(Estimate("p_det_free", 0.5, "12 of 24 scans of [leg] tracks", 24),),
        kept=(),
        counts="",
        training=(NAME,),
        validation=(NAME,),
        rows=(ValidationRow(NAME, "default", {"MOTA": 0.5}),),
    )
    _print(result)
    out = capsys.readouterr().out
    assert "12 of 24 scans of [leg] tracks" in out and f"│ {NAME} " in out


def test_an_error_names_the_file_as_written(tmp_path: Path) -> None:
    """The error line (a pipe or a terminal alike) keeps ``[a]`` and ``:fire:``."""
    import os
    import subprocess
    import sys

    src = Path(__file__).resolve().parents[1] / "src"
    missing = tmp_path / f"{NAME}.bag"
    done = subprocess.run(
        [sys.executable, "-m", "laserpeople.cli", "info", str(missing)],
        env=dict(os.environ, PYTHONPATH=str(src)),
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 1
    assert done.stderr.startswith(f"error: {missing}: file not found"), done.stderr


def test_status_lines_on_a_terminal_keep_the_text(monkeypatch: pytest.MonkeyPatch) -> None:
    """On a terminal status lines go through rich: still no markup and no emoji."""
    import io

    from rich.console import Console

    from laserpeople.cli import common

    buf = io.StringIO()
    monkeypatch.setattr(common, "_isatty", lambda stream: True)
    monkeypatch.setattr(common.STATE, "quiet", False)
    monkeypatch.setattr(common.err_console, "_console", Console(file=buf, width=200))
    common.say(f"wrote {NAME}.csv")
    common.warn("bad value of [leg_tracker] people.gate")
    assert buf.getvalue() == (
        f"wrote {NAME}.csv\nwarning: bad value of [leg_tracker] people.gate\n"
    )


BAG_HEAD = b"#ROSBAG V2.0\nrest of a bag"
MCAP_HEAD = b"\x89MCAP0\r\nrest of an mcap"
NPZ_HEAD = b"PK\x03\x04rest of a zip"


@pytest.mark.parametrize(
    ("name", "head", "says"),
    [
        ("run.mcap", BAG_HEAD, "is a ROS 1 bag by its first bytes, but named '.mcap'"),
        ("run.txt", BAG_HEAD, "is a ROS 1 bag by its first bytes, but named '.txt'"),
        ("run.npz", BAG_HEAD, "is a ROS 1 bag by its first bytes, but named '.npz'"),
        ("run", BAG_HEAD, "is a ROS 1 bag by its first bytes, but has no extension"),
        ("run.bag", MCAP_HEAD, "is an MCAP file by its first bytes, but named '.bag'"),
        ("run.bag", NPZ_HEAD, "is a zip archive (an .npz recording) by its first bytes"),
    ],
)
def test_a_recording_of_another_format_than_its_extension_is_named_so(
    tmp_path: Path, name: str, head: bytes, says: str
) -> None:
    """Not "corrupt, try rosbag reindex" nor "no laser lines" for a whole file renamed:
    the error names what it is and the extension to give it."""
    from laserpeople.errors import RecordingError
    from laserpeople.io import open_recording

    path = tmp_path / name
    path.write_bytes(head)
    with pytest.raises(RecordingError) as err:
        open_recording(path)
    message = str(err.value)
    assert says in message and "reindex" not in message, message
    suffix = {NPZ_HEAD: ".npz", MCAP_HEAD: ".mcap"}.get(head, ".bag")
    assert f"rename it to run{suffix}:" in message


@pytest.mark.parametrize(("name", "head"), [("truth.mcap", BAG_HEAD), ("truth.bag", NPZ_HEAD)])
def test_a_truth_bag_of_another_format_is_named_so(tmp_path: Path, name: str, head: bytes) -> None:
    from laserpeople.errors import RecordingError
    from laserpeople.io.bag_guard import check_bag_file

    path = tmp_path / name
    path.write_bytes(head)
    with pytest.raises(RecordingError, match="by its first bytes, but named"):
        check_bag_file(path)


def test_files_of_their_own_format_open_as_before(tmp_path: Path, recording: Path) -> None:
    from laserpeople.io import open_recording
    from laserpeople.io.sniff import check_extension

    check_extension(recording)  # an .npz named .npz
    log = tmp_path / "run.log"
    log.write_text("# a CARMEN log\nODOM 0 0 0 0 0 0 1.0 host 1.0\n")
    check_extension(log)  # text: the CARMEN reader says what it lacks
    with open_recording(recording) as rec:
        assert rec.topics()


@pytest.mark.parametrize("command", ["track", "detect", "view"])
def test_a_bag_without_a_laser_topic_names_the_topics_it_has(tmp_path: Path, command: str) -> None:
    """Every command says which topics the bag has, not only that none is a laser's."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    from laserpeople.errors import TopicNotFoundError

    store = get_typestore(Stores.ROS1_NOETIC)
    text = store.types["std_msgs/msg/String"]
    bag = tmp_path / "chatter.bag"
    with Writer(bag) as writer:
        conn = writer.add_connection("/chatter", "std_msgs/msg/String", typestore=store)
        for k in range(3):
            data = store.serialize_ros1(text(data=f"hello {k}"), "std_msgs/msg/String")
            writer.write(conn, (1000 + k) * 10**9, data)
    out = tmp_path / ("out.png" if command == "view" else "out.csv")
    run = CliRunner().invoke(app, [command, str(bag), "-o", str(out)])
    assert isinstance(run.exception, TopicNotFoundError), run.output
    assert "topics here: /chatter (std_msgs/msg/String)" in str(run.exception)
    assert not out.exists()


TRUTH = "scan,stamp,person_id,x,y\n0,10.0,1,1.0,2.0\n1,10.1,1,1.1,2.0\n"


def test_a_truth_csv_with_a_byte_order_mark_reads(tmp_path: Path) -> None:
    """A spreadsheet's "CSV UTF-8" export starts with a byte order mark: the header's first
    name is still ``scan``."""
    from laserpeople.io.truth_csv import read_truth_csv

    path = tmp_path / "excel.csv"
    path.write_bytes(b"\xef\xbb\xbf" + TRUTH.encode())
    frames = read_truth_csv(path)
    assert [f.scan_index for f in frames] == [0, 1]
    assert frames[1].positions.tolist() == [[1.1, 2.0]]


def test_a_tracks_csv_with_a_byte_order_mark_reads(tmp_path: Path, tracks: Path) -> None:
    from laserpeople.io.tracks_csv import iter_tracks_csv

    bom = tmp_path / "bom.csv"
    bom.write_bytes(b"\xef\xbb\xbf" + tracks.read_bytes())
    got = [len(t) for t in iter_tracks_csv(bom, frame="sensor")]
    want = [len(t) for t in iter_tracks_csv(tracks, frame="sensor")]
    assert got == want and sum(got) > 0


@pytest.mark.parametrize(("sep", "says"), [(";", "separated by ';'"), ("\t", "separated by tabs")])
def test_a_csv_of_another_separator_says_so(tmp_path: Path, sep: str, says: str) -> None:
    from laserpeople.errors import RecordingError
    from laserpeople.io.truth_csv import read_truth_csv

    path = tmp_path / "semi.csv"
    path.write_text(TRUTH.replace(",", sep))
    with pytest.raises(RecordingError, match=f"{says}: save the CSV with commas"):
        read_truth_csv(path)
    path.write_text("")
    with pytest.raises(RecordingError, match="the ground-truth CSV is empty: no header line"):
        read_truth_csv(path)
    path.write_text(TRUTH.replace("person_id", "person"))  # commas, a column misnamed
    with pytest.raises(RecordingError, match="missing column") as err:
        read_truth_csv(path)
    assert "separated" not in str(err.value)


def test_truth_columns_not_read_are_said(tmp_path: Path) -> None:
    """A column the reader does not know (``group`` for ``group_id``) is not dropped
    silently: a warning names it; ``group_id`` and ``frame`` are read without one."""
    import warnings

    from laserpeople.errors import LaserPeopleWarning
    from laserpeople.io.truth_csv import read_truth_csv

    path = tmp_path / "extra.csv"
    path.write_text("scan,stamp,person_id,x,y,group,note\n0,10.0,1,1.0,2.0,3,a\n")
    with pytest.warns(LaserPeopleWarning, match=r"column\(s\) group, note not read"):
        frames = read_truth_csv(path)
    assert frames[0].group_ids.tolist() == [-1]
    path.write_text("scan,stamp,person_id,x,y,group_id,frame\n0,10.0,1,1.0,2.0,3,sensor\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error", LaserPeopleWarning)
        assert read_truth_csv(path)[0].group_ids.tolist() == [3]


def test_the_command_line_prints_warnings_as_warning_lines(tmp_path: Path, tracks: Path) -> None:
    """A torn tracks CSV and an unread truth column end in ``warning: ...`` lines, not in
    Python's ``file.py:123: TornScanWarning:`` with the source line after it."""
    import os
    import subprocess
    import sys

    torn = tmp_path / "torn.csv"
    data = tracks.read_bytes()
    torn.write_bytes(data[: len(data) // 2])
    truth = tmp_path / "truth.csv"  # (scans within the tracks': truth of no shared scan is refused)
    truth.write_text("scan,stamp,person_id,x,y,note\n40,10.0,1,1.0,2.0,a\n41,10.1,1,1.1,2.0,a\n")
    src = Path(__file__).resolve().parents[1] / "src"
    done = subprocess.run(
        [sys.executable, "-m", "laserpeople.cli", "evaluate", str(torn), "--truth", str(truth)],
        env=dict(os.environ, PYTHONPATH=str(src)),
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    lines = done.stderr.splitlines()
    assert any(line.startswith(f"warning: {torn}: scan ") and "cut off" in line for line in lines)
    assert any(line.startswith(f"warning: {truth}: column(s) note not read") for line in lines)
    assert "Warning:" not in done.stderr and ".py:" not in done.stderr, done.stderr


def test_a_config_saved_with_a_byte_order_mark_reads(tmp_path: Path) -> None:
    """An editor's "UTF-8 with BOM": not 'Invalid statement (at line 1, column 1)'."""
    from laserpeople.config import load_config
    from laserpeople.tracking.legs import LegTrackerParams

    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf[leg_tracker]\nlambda_new = 0.002\n")
    assert load_config(LegTrackerParams, path).lambda_new == 0.002


@pytest.mark.parametrize(
    ("text", "says"),
    [
        (b'[mounts.front]\nparent = "base\xe9"\nx = 0\ny = 0\ntheta = 0\n', "byte 29 is not UTF-8"),
        (b"[mounts.front]\nx = " + b"[" * 5000 + b"]" * 5000 + b"\n", "nest 5000 deep"),
        (
            b'[mounts.front]\nparent = "base"\nx = 1e300\ny = 0\ntheta = 0\n',
            "mount 'front' is off its robot",
        ),
        (b'[mounts.front]\nparent = "base"\nx = 0\ny = 0\ntheta = nan\n', "a finite angle"),
    ],
)
def test_a_hostile_mounts_file_is_an_error_naming_it(
    tmp_path: Path, text: bytes, says: str
) -> None:
    """Not a traceback (UnicodeDecodeError, RecursionError), and not a pose of 1e300 m that
    the reader then blames on the recording ("scan 0 is damaged")."""
    from laserpeople.alignment import read_mounts
    from laserpeople.errors import ConfigError

    path = tmp_path / "mounts.toml"
    path.write_bytes(text)
    with pytest.raises(ConfigError, match=says) as err:
        read_mounts(path)
    assert str(err.value).startswith(f"{path}: ")


def test_label_probabilities_not_summing_to_one_name_the_keys(tmp_path: Path) -> None:
    """The error names the keys the file writes (``p_det_free``) and the paper by its
    authors, not the code ``000`` of the source."""
    from laserpeople.config import load_config
    from laserpeople.errors import ConfigError
    from laserpeople.tracking.legs import LegTrackerParams

    path = tmp_path / "sum.toml"
    path.write_text("[leg_tracker]\np_det_approved = 0.25\n")
    with pytest.raises(ConfigError) as err:
        load_config(LegTrackerParams, path)
    message = str(err.value)
    assert "approved tracks (p_det_approved, p_occ_approved, p_del_approved)" in message
    assert "must be 1 (Arras et al. 2008 eq. 8), got 1.05" in message and "000" not in message


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        (["track", "{rec}", "-o", "{tmp}/other.bag"], "-o writes a tracks CSV, not a .bag file"),
        (["track", "{rec}", "-o", "{tmp}/t.parquet"], "not a .parquet file"),
        (["detect", "{rec}", "-o", "{tmp}/d.npz"], "-o writes a detections CSV, not a .npz"),
        (["train", "{rec}", "-o", "{tmp}/m.csv"], "-o writes a model JSON, not a .csv file"),
        (["fit", "{rec}", "-o", "{tmp}/p.json"], "-o writes the learned parameters as TOML"),
        (["align", "{rec}", "-o", "{tmp}/m.bag"], "-o writes the mounts as TOML, not a .bag"),
        (
            ["evaluate", "{tmp}/t.csv", "--truth", "{rec}", "--per-frame", "{tmp}/f.png"],
            "--per-frame writes the per-frame table as CSV, not a .png file",
        ),
    ],
)
def test_an_output_named_as_another_format_is_refused_before_writing(
    tmp_path: Path, recording: Path, argv: list[str], says: str
) -> None:
    """A CSV written to ``other.bag`` would replace a recording, and to ``t.parquet`` is no
    Parquet file: the option's format is said, and nothing is written."""
    from laserpeople.errors import ConfigError

    (tmp_path / "t.csv").write_text("scan,stamp,track_id,kind,x,y\n")
    (tmp_path / "other.bag").write_bytes(b"#ROSBAG V2.0\nsomebody's recording")
    args = [a.format(rec=recording, tmp=tmp_path) for a in argv]
    run = CliRunner().invoke(app, args)
    assert isinstance(run.exception, ConfigError), run.output
    assert says in str(run.exception)
    assert (tmp_path / "other.bag").read_bytes().endswith(b"somebody's recording")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["other.bag", "t.csv"]


def test_other_extensions_are_written_as_asked(tmp_path: Path, recording: Path) -> None:
    out = tmp_path / "tracks.txt"
    run = CliRunner().invoke(app, ["--quiet", "track", str(recording), "-o", str(out)])
    assert run.exit_code == 0, run.output
    assert out.read_text().startswith("scan,stamp,track_id")


def test_a_neko_directory_given_as_a_recording_points_to_train_neko(tmp_path: Path) -> None:
    from laserpeople.errors import RecordingError
    from laserpeople.io import open_recording

    (tmp_path / "xy_data.txt").write_text("720 2 120\n")
    with pytest.raises(RecordingError, match="read by `laserpeople train --neko DIR`"):
        open_recording(tmp_path)


def _ctrl_c_after(n: int) -> Any:
    """A stand-in for ``cli.common.progress`` that passes ``n`` items, then is Ctrl-C."""

    def progress(items: Any, total: Any = None, description: str = "") -> Any:
        for k, item in enumerate(items):
            if k == n:
                raise KeyboardInterrupt
            yield item

    return progress


def test_detect_interrupted_says_so_and_leaves_a_complete_csv(
    tmp_path: Path, recording: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from laserpeople.cli import detect
    from laserpeople.io.detections_csv import iter_detections_csv

    monkeypatch.setattr(detect, "progress", _ctrl_c_after(5))  # frame 5 is written, not passed on
    out = tmp_path / "legs.csv"
    run = CliRunner().invoke(app, ["detect", str(recording), "-o", str(out)])
    assert run.exit_code == 130
    assert f"interrupted (Ctrl-C) after 6 scans: {out} holds the legs" in run.output
    assert sorted({int(r["scan"]) for r in iter_detections_csv(out)}) == [0, 1, 2, 3, 4, 5]


def test_any_command_interrupted_says_so(recording: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """typer ends a Ctrl-C with status 130 and not a word; the program says it stopped."""
    from laserpeople.cli import info

    monkeypatch.setattr(info, "progress", _ctrl_c_after(3))
    run = CliRunner().invoke(app, ["info", str(recording)])
    assert run.exit_code == 130
    assert run.output.strip().endswith("interrupted (Ctrl-C)")


def test_a_progress_bar_on_a_terminal_ends_cleanly(recording: Path) -> None:
    """On a terminal the progress bar's live display enters the stderr console as a context
    manager; the console made on first use stood in for it without one, and every command
    with a bar ended in 'lost sys.stderr' (exit status 1) after its output."""
    import os
    import pty
    import subprocess
    import sys

    src = Path(__file__).resolve().parents[1] / "src"
    leader, follower = pty.openpty()
    proc = subprocess.Popen(
        [sys.executable, "-m", "laserpeople.cli", "info", str(recording)],
        env=dict(os.environ, PYTHONPATH=str(src), COLUMNS="60", TERM="xterm"),
        stdin=follower,
        stdout=follower,
        stderr=follower,
    )
    os.close(follower)
    chunks = []
    while True:
        try:
            data = os.read(leader, 65536)
        except OSError:  # the terminal closed with the process
            break
        if not data:
            break
        chunks.append(data)
    os.close(leader)
    status = proc.wait(timeout=120)
    text = b"".join(chunks).decode(errors="replace")
    assert status == 0, text
    assert "lost sys.stderr" not in text and "TypeError" not in text, text
    assert "reading" in text and "ground truth:" in text


def test_track_errors_mid_run_name_the_recording(tmp_path: Path) -> None:
    """``--output-frame world`` of a recording without poses fails at its first scan,
    where the CSV writer does not know the recording: the error names it."""
    from dataclasses import replace

    from laserpeople.errors import LaserPeopleError
    from laserpeople.sim import SimResult
    from laserpeople.sim.scenarios import run_scenario

    result = run_scenario("figure-eight", seconds=2.0, seed=4)
    rec = tmp_path / "no poses.npz"
    SimResult([replace(s, pose=None) for s in result.scans], result.truth, result.meta).write(rec)
    out = tmp_path / "t.csv"
    run = CliRunner().invoke(app, ["track", str(rec), "-o", str(out), "--output-frame", "world"])
    assert isinstance(run.exception, LaserPeopleError), run.output
    assert str(run.exception).startswith(f"{rec}: scan 0: cannot express tracks in the world")
    # no scan was written: no CSV is left (an older one would be left as it was)
    assert "no tracks CSV was written (no scan was)" in str(run.exception)
    assert not out.exists()


def _ranges_scan(index: int, ranges: list[float]) -> Any:
    import numpy as np

    from laserpeople.scan import Scan

    return Scan(
        stamp=10.0 + 0.1 * index,
        angle_min=-0.5,
        angle_increment=0.25,
        ranges=np.array(ranges),
        range_min=0.1,
        range_max=8.0,
        sensor="/front",
        index=index,
    )


def test_scans_without_a_valid_beam_are_counted() -> None:
    """NaN, infinite, zero, negative, under range_min or over range_max: no valid beam.
    One beam within the limits (range_max itself included) makes a scan not empty."""
    from laserpeople.pipeline.empty_scans import EmptyScanCheck

    nan, inf = float("nan"), float("inf")
    rows = [
        [1.0, 2.0, 3.0, 4.0, 5.0],  # 0: seen
        [nan, inf, -inf, -1.0, 0.0],  # 1: empty
        [0.05, 8.5, nan, nan, nan],  # 2: empty (under range_min, over range_max)
        [nan, nan, 8.0, nan, nan],  # 3: range_max counts as a return
        [nan, nan, nan, nan, 0.1],  # 4: range_min counts too
        [-2.0, -2.0, -2.0, -2.0, -2.0],  # 5: empty
    ]
    check = EmptyScanCheck()
    passed = list(check(_ranges_scan(k, r) for k, r in enumerate(rows)))
    assert [s.index for s in passed] == [0, 1, 2, 3, 4, 5]
    assert (check.scans, check.empty, check.first) == (6, 3, ("/front", 1))
    assert check.summary().startswith("3 of 6 scans had no valid beam")
    assert "the first: scan 1 of /front" in check.summary()
    none = EmptyScanCheck()
    list(none(_ranges_scan(0, r) for r in rows[:1]))
    assert none.summary() == ""


def test_track_says_how_many_scans_had_no_valid_beam(tmp_path: Path) -> None:
    import numpy as np

    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "dark.npz"
    run_scenario("figure-eight", seconds=3.0, seed=5).write(rec)
    with np.load(rec) as z:
        arrays = {k: z[k] for k in z.files}
    start, stop = arrays["scan_offset"][[10, 15]]
    arrays["ranges"][start:stop] = np.nan  # scans 10-14 of a driver writing NaN
    np.savez(rec, **arrays)  # type: ignore[arg-type]
    run = CliRunner().invoke(app, ["track", str(rec), "-o", str(tmp_path / "t.csv")])
    assert run.exit_code == 0, run.output
    n = len(arrays["scan_index"])
    assert f"5 of {n} scans had no valid beam" in run.output
    assert "the first: scan 10 of " in run.output


def test_batch_says_a_recording_named_twice_is_tracked_once(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from laserpeople.cli.batch import expand

    a, b = tmp_path / "a.bag", tmp_path / "b.bag"
    a.write_bytes(b"")
    b.write_bytes(b"")
    assert expand([str(a), str(tmp_path / "*.bag")]) == [a, b]
    err = capsys.readouterr().err
    assert f"named more than once by the paths and globs given, tracked once: {a}\n" in err
    assert expand([str(b)]) == [b] and capsys.readouterr().err == ""


def test_view_warns_of_a_truth_csv_of_another_recording(tmp_path: Path, recording: Path) -> None:
    """As it does for tracks: labels of scans the recording does not have."""
    truth = tmp_path / "other.people.csv"
    truth.write_text("scan,stamp,person_id,x,y\n0,10.0,1,1.0,2.0\n3599,370.0,1,1.0,2.0\n")
    run = CliRunner().invoke(
        app, ["view", str(recording), "-o", str(tmp_path / "v.png"), "--truth", str(truth)]
    )
    assert run.exit_code == 0, run.output
    assert f"warning: {truth} may not belong to {recording.name}: the truth labels scans" in (
        run.output
    )
    assert "up to 3599 but" in run.output
    fits = tmp_path / "fits.csv"
    fits.write_text("scan,stamp,person_id,x,y\n0,10.0,1,1.0,2.0\n")
    run = CliRunner().invoke(
        app, ["view", str(recording), "-o", str(tmp_path / "w.png"), "--truth", str(fits)]
    )
    assert run.exit_code == 0 and "may not belong" not in run.output, run.output


@pytest.mark.parametrize("name", ["a.png", "a.mcap", "a.csv"])
def test_track_animate_writes_gif_or_mp4_only(tmp_path: Path, recording: Path, name: str) -> None:
    """``--animate a.png`` drew one frame of the run in silence ("wrote a.png (1 frames)")."""
    from laserpeople.errors import ConfigError

    out = tmp_path / "t.csv"
    run = CliRunner().invoke(
        app, ["track", str(recording), "-o", str(out), "--animate", str(tmp_path / name)]
    )
    assert isinstance(run.exception, ConfigError), run.output
    assert f"--animate writes a .gif or an .mp4, not {name!r}" in str(run.exception)
    assert not out.exists() and not (tmp_path / name).exists()


def test_not_utf8_names_the_line_and_the_byte_in_the_file(tmp_path: Path) -> None:
    """Python's error of a file read in chunks gives the byte within a chunk (a truth CSV
    bad at byte 126,198 said "byte 3318"): the line and the byte in the file are given,
    and a character split across two 1 MiB chunks is not taken for an error."""
    from laserpeople.errors import RecordingError
    from laserpeople.io.csv_read import not_utf8
    from laserpeople.io.truth_csv import read_truth_csv

    rows = [b"scan,stamp,person_id,x,y\n"] + [b"%d,10.0,1,1.0,2.0\n" % k for k in range(50_000)]
    body = b"".join(rows)
    lines = len(rows)
    pad = (1 << 20) - 1 - len(body)  # the 2-byte character starts at the chunk's last byte
    assert pad > 0
    body += b"#" * pad + "é".encode() + b"\n"  # (a comment line: line `lines + 1`)
    bad_at = len(body) + 10  # the \xff after "9999999,10"
    text = body + b"9999999,10\xff.0,1,1.0,2.0\n"
    path = tmp_path / "big.csv"
    path.write_bytes(text)
    where = f"line {lines + 2:,} (byte {bad_at:,}) is not UTF-8"
    assert not_utf8(path) == where
    with pytest.raises(RecordingError, match=rf"not a text CSV: line {lines + 2:,} \(byte"):
        read_truth_csv(path)
    good = tmp_path / "good.csv"
    good.write_bytes(body)
    assert not_utf8(good) == "it is not UTF-8 text"


def test_detect_report_without_beam_truth_is_refused_before_the_run(
    tmp_path: Path, recording: Path
) -> None:
    """Not after detecting every scan and writing the CSV."""
    from laserpeople.errors import ConfigError
    from laserpeople.io import open_recording

    bag = tmp_path / "no truth.mcap"
    CliRunner().invoke(
        app, ["--quiet", "simulate", "figure-eight", "--seconds", "1", "-o", str(bag)]
    )
    with open_recording(bag) as rec:
        assert not rec.has_truth
    out = tmp_path / "legs.csv"
    run = CliRunner().invoke(app, ["detect", str(bag), "-o", str(out), "--report"])
    assert isinstance(run.exception, ConfigError), run.output
    assert "--report needs per-beam ground truth" in str(run.exception)
    assert not out.exists()


def test_view_refuses_no_truth_with_a_truth(tmp_path: Path, recording: Path) -> None:
    from laserpeople.errors import LaserPeopleError

    truth = tmp_path / "t.csv"
    truth.write_text(TRUTH)
    out = tmp_path / "v.png"
    run = CliRunner().invoke(
        app, ["view", str(recording), "-o", str(out), "--no-truth", "--truth", str(truth)]
    )
    assert isinstance(run.exception, LaserPeopleError), run.output
    assert "--no-truth and --truth" in str(run.exception) and not out.exists()


def test_why_unwritable_names_a_file_on_the_way() -> None:
    from laserpeople.io.paths import why_unwritable

    here = Path(__file__)
    assert why_unwritable(FileExistsError(17, "File exists"), here / "x.csv") == (
        f"{here} is a file, not a folder"
    )
    assert why_unwritable(NotADirectoryError(20, "Not a directory"), here / "a" / "b.csv") == (
        f"{here} is a file, not a folder"
    )
    assert why_unwritable(PermissionError(13, "Permission denied"), here / "x.csv") == (
        "Permission denied"
    )


@pytest.mark.parametrize(
    "argv",
    [
        ["track", "{rec}", "-o", "{file}/t.csv"],
        ["detect", "{rec}", "-o", "{file}/sub/d.csv"],
        ["view", "{rec}", "-o", "{file}/v.png"],
        ["simulate", "figure-eight", "--seconds", "1", "-o", "{file}/s.npz"],
        ["train", "{rec}", "-T", "2", "-o", "{file}/m.json"],
        # an output folder that is a file (these ended in a FileExistsError traceback)
        ["demo", "--out-dir", "{file}", "--seconds", "1"],
        ["batch", "{rec}", "--out", "{file}"],
    ],
)
def test_an_output_under_a_file_says_the_file_is_not_a_folder(
    tmp_path: Path, recording: Path, argv: list[str]
) -> None:
    """Not the system's bare "File exists" (of the folder it tried to make), and the file
    is left as it was."""
    from laserpeople.errors import LaserPeopleError

    file = tmp_path / "runs.bag"
    file.write_bytes(b"#ROSBAG V2.0\n")
    run = CliRunner().invoke(app, [a.format(rec=recording, file=file) for a in argv])
    assert isinstance(run.exception, LaserPeopleError), run.output
    assert f"{file} is a file, not a folder" in str(run.exception)
    assert file.read_bytes() == b"#ROSBAG V2.0\n"


def test_batch_takes_an_existing_file_with_glob_characters_as_named(tmp_path: Path) -> None:
    """``run[1].bag`` is a file, not a glob matching ``run1.bag``: it was 'matches no file'."""
    from laserpeople.cli.batch import expand

    named = tmp_path / "run[1].bag"
    named.write_bytes(b"")
    assert expand([str(named)]) == [named]
    (tmp_path / "run1.bag").write_bytes(b"")
    assert expand([str(tmp_path / "run[12].bag")]) == [tmp_path / "run1.bag"]  # a glob


@pytest.mark.parametrize("endpoint", ["not an endpoint", "192.168.1.5:7447", "tcp:1.2.3.4"])
def test_live_refuses_an_endpoint_that_is_not_protocol_slash_address(endpoint: str) -> None:
    """Before Zenoh's own error (its Rust source paths and a JSON5 location)."""
    from laserpeople.errors import ConfigError
    from laserpeople.live.zenoh_link import ZenohSettings

    with pytest.raises(ConfigError, match=r"is not a Zenoh endpoint PROTOCOL/ADDRESS"):
        ZenohSettings("client", connect=(endpoint,))
    with pytest.raises(ConfigError, match=r"--listen .* is not a Zenoh endpoint"):
        ZenohSettings("peer", listen=(endpoint,))
    for good in ("tcp/192.168.1.5:7447", "tcp/[::1]:7447", "unixsock-stream//tmp/zenoh.sock"):
        ZenohSettings("client", connect=(good,), listen=(good,))


def test_neko_frames_outside_the_data_or_backwards_are_refused(tmp_path: Path) -> None:
    """``--neko-frames 200-300`` of 120 frames trained on nothing and said only "training
    needs legs and non-legs, got 0 segments"; ``50-10`` likewise."""
    from laserpeople.cli.train import parse_frames
    from laserpeople.detection.training import neko_frames
    from laserpeople.errors import ConfigError

    assert neko_frames(tmp_path, 120, None) == set(range(120))
    assert neko_frames(tmp_path, 120, [0, 119]) == {0, 119}
    with pytest.raises(ConfigError, match=r"frame\(s\) 120 not in the data: it has frames 0-119"):
        neko_frames(tmp_path, 120, [119, 120])
    with pytest.raises(ConfigError, match=r"frame\(s\) -1, 200, 201 \.\.\. not in the data"):
        neko_frames(tmp_path, 120, [-1, 5, 200, 201, 202])
    with pytest.raises(ValueError, match="50-10 goes backwards"):
        parse_frames("0-3,50-10")
    assert parse_frames("0-2,7") == [0, 1, 2, 7]
