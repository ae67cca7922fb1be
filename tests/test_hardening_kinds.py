"""What a demanding user meets: the kinds of beams left out, truth with text ids, the
evaluation's public views, options and config values that cannot be, outputs that cannot
be written."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app

if TYPE_CHECKING:
    from laserpeople.scan import Scan


def _scan(ranges: list[float], range_min: float = 0.1, range_max: float = 8.0) -> Scan:
    from laserpeople.scan import Scan

    return Scan(
        stamp=10.0,
        angle_min=-1.0,
        angle_increment=2.0 / max(len(ranges) - 1, 1),
        ranges=np.array(ranges),
        range_min=range_min,
        range_max=range_max,
        sensor="/front",
        index=0,
    )


def test_each_kind_of_beam_left_out_is_counted_apart() -> None:
    """NaN is no negative, +inf no 'over range_max', zero no 'under range_min'; the limits
    themselves are returns; the kinds add up to the scan's invalid beams."""
    from laserpeople.pipeline.empty_scans import BEAM_KINDS, beam_kinds

    nan, inf = float("nan"), float("inf")
    ranges = [nan, nan, nan, inf, inf, -inf, -1.0, -0.5, -2.0, -3.0, 0.0, 0.0]
    ranges += [0.05, 0.09, 0.02, 0.01, 0.07, 8.5, 9.0, 1e6, 20.0, 30.0, 40.0, 50.0]
    ranges += [0.1, 8.0, 4.0]  # range_min and range_max count as returns
    scan = _scan(ranges)
    counts = beam_kinds(scan)
    assert dict(zip(BEAM_KINDS, counts.tolist(), strict=True)) == {
        "NaN": 3,
        "+inf": 2,
        "-inf": 1,
        "negative": 4,
        "zero": 2,
        "under range_min": 5,
        "over range_max": 7,
    }
    assert int(counts.sum()) == scan.n_invalid
    # range_min 0: a zero range is still 'zero', never 'under range_min'
    zero_min = beam_kinds(_scan([0.0, 0.0, 1.0], range_min=0.0))
    assert zero_min.tolist() == [0, 0, 0, 0, 2, 0, 0]
    assert beam_kinds(_scan([1.0, 2.0])).tolist() == [0] * 7


def test_check_sums_kinds_over_scans_and_says_each() -> None:
    from laserpeople.pipeline.empty_scans import EmptyScanCheck

    nan = float("nan")
    check = EmptyScanCheck()
    list(check(iter([_scan([nan, 1.0, -1.0]), _scan([nan, 9.0, 0.0, 2.0])])))
    assert (check.beams, check.left_out) == (7, 5)
    assert check.beam_summary().startswith(
        "5 of 7 beams had no valid return and were left out "
        "(NaN 2, negative 1, zero 1, over range_max 1;"
    )
    clean = EmptyScanCheck()
    list(clean(iter([_scan([1.0, 2.0])])))
    assert clean.beam_summary() == ""


def test_track_says_each_kind_of_beam_left_out(tmp_path: Path) -> None:
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "bad ranges.npz"
    run_scenario("figure-eight", seconds=2.0, seed=5).write(rec)
    with np.load(rec) as z:
        arrays = {k: z[k] for k in z.files}
    ranges = arrays["ranges"]
    start = int(arrays["scan_offset"][3])
    bad = [np.nan] * 3 + [-np.inf] + [-1.0] * 4 + [0.0] * 2 + [1e6] * 5
    ranges[start : start + len(bad)] = bad
    after = int(np.count_nonzero(np.isposinf(ranges)))
    limit = np.repeat(arrays["scan_range_max"], np.diff(arrays["scan_offset"]))
    over = int(np.count_nonzero(np.isfinite(ranges) & (ranges > limit)))
    np.savez(rec, **arrays)
    run = CliRunner().invoke(app, ["track", str(rec), "-o", str(tmp_path / "t.csv")])
    assert run.exit_code == 0, run.output
    text = " ".join(run.output.split())
    assert f"NaN 3, +inf {after:,}, -inf 1, negative 4, zero 2, over range_max {over};" in text
    assert over >= 5  # the counts are the file's, after the edit


def test_truth_names_are_numbered_after_the_integer_ids_and_said(tmp_path: Path) -> None:
    """A name keeps one number across scans; integer ids stay themselves; names are
    numbered after the largest integer id in the order first seen, and the reader says so."""
    from laserpeople.errors import LaserPeopleWarning
    from laserpeople.io.truth_csv import read_truth_csv

    path = tmp_path / "named.csv"
    path.write_text(
        "scan,stamp,person_id,x,y\n"
        "0,0.0,p3,1,2\n0,0.0,alice,3,4\n0,0.0,4,5,6\n"
        "1,0.1,alice,3.1,4\n1,0.1,p3,1.1,2\n1,0.1,9,7,7\n"
    )
    with pytest.warns(LaserPeopleWarning, match=r"p3 = 10, alice = 11 \(") as caught:
        frames = read_truth_csv(path)
    assert str(path) in str(caught[0].message)
    assert [f.person_ids.tolist() for f in frames] == [[10, 11, 4], [11, 10, 9]]
    np.testing.assert_allclose(frames[1].positions[0], [3.1, 4.0], atol=1e-12)
    only_names = tmp_path / "names.csv"
    only_names.write_text("scan,stamp,person_id,x,y\n0,0.0,bob,1,2\n1,0.1,bob,1,2\n")
    with pytest.warns(LaserPeopleWarning, match=r"for 1 people, numbered in the order first "):
        assert [f.person_ids.tolist() for f in read_truth_csv(only_names)] == [[0], [0]]


@pytest.mark.parametrize(
    ("cell", "message"),
    [("3.0", "'3.0', a number but not an integer"), ("-2", "negative"), ("1e400", "not an")],
)
def test_truth_ids_that_are_numbers_but_no_ids_are_refused_with_the_line(
    tmp_path: Path, cell: str, message: str
) -> None:
    from laserpeople.errors import RecordingError
    from laserpeople.io.truth_csv import read_truth_csv

    path = tmp_path / "t.csv"
    path.write_text(f"scan,stamp,person_id,x,y\n0,0.0,1,1,2\n1,0.1,{cell},1,2\n")
    with pytest.raises(RecordingError, match=message) as info:
        read_truth_csv(path)
    assert str(info.value).startswith(f"{path}: line 3: ")


def test_evaluate_scores_named_truth_as_numbered_truth(tmp_path: Path) -> None:
    import json

    from laserpeople.io.truth_csv import write_truth_csv
    from laserpeople.sim.scenarios import run_scenario

    result = run_scenario("figure-eight", seconds=4.0, seed=3)
    rec = tmp_path / "rec.npz"
    result.write(rec)
    tracks = tmp_path / "tracks.csv"
    assert CliRunner().invoke(app, ["track", str(rec), "-o", str(tracks)]).exit_code == 0
    numbered = tmp_path / "numbered.csv"
    write_truth_csv(numbered, result.truth)
    ids = {int(i) for f in result.truth for i in f.person_ids}
    named = tmp_path / "named.csv"
    lines = numbered.read_text().splitlines()
    renamed = [lines[0]]
    for line in lines[1:]:
        cells = line.split(",")
        cells[2] = f"walker {cells[2]}" if cells[2] else ""
        renamed.append(",".join(cells))
    named.write_text("\n".join(renamed) + "\n")
    scores = []
    for truth in (numbered, named):
        run = CliRunner().invoke(app, ["evaluate", str(tracks), "--truth", str(truth), "--json"])
        assert run.exit_code == 0, run.output
        scores.append(run.output)
    assert "person_id is a name" not in scores[0]
    assert f"person_id is a name for {len(ids)} people" in " ".join(scores[1].split())
    assert ids and len(lines) > 10
    first = json.loads(scores[0][scores[0].index("{") :])
    second = json.loads(scores[1][scores[1].index("{") :])
    assert first == second and first["mota"] > 0.5


def test_view_reads_a_named_truth_once_and_says_the_numbers_once(tmp_path: Path) -> None:
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "rec.npz"
    run_scenario("figure-eight", seconds=1.0, seed=3).write(rec)
    truth = tmp_path / "named.csv"
    truth.write_text("scan,stamp,person_id,x,y\n0,0.0,alice,1,2\n1,0.1,alice,1.1,2\n")
    run = CliRunner().invoke(
        app, ["view", str(rec), "--truth", str(truth), "-o", str(tmp_path / "v.png")]
    )
    assert run.exit_code == 0, run.output
    assert " ".join(run.output.split()).count("alice = 0") == 1


def test_clear_mot_last_pairs_are_the_last_frame_s_only_and_read_only() -> None:
    """The pairs of the frame accumulated last: not a person's last match in any frame
    (person 2 missed in frame 1 is not in them), the new track after a switch."""
    from laserpeople.evaluation import ClearMot
    from laserpeople.evaluation.synthetic import synthetic_sequence

    nan = [np.nan, np.nan]
    people = {1: np.array([[0.0, 0.0]] * 3), 2: np.array([[5.0, 0.0]] * 3)}
    tracks = {
        7: np.array([[0.0, 0.1], [0.0, 0.1], nan]),
        8: np.array([[5.0, 0.1], [9.0, 0.0], [5.0, 0.0]]),  # person 2 missed in frame 1
        9: np.array([nan, nan, [0.1, 0.0]]),  # person 1's track from frame 2
    }
    metric = ClearMot()
    assert dict(metric.last_pairs) == {}
    seen = []
    for truth, frame_tracks in zip(*synthetic_sequence(people, tracks), strict=True):
        metric.accumulate(truth, frame_tracks)
        seen.append(dict(metric.last_pairs))
    assert seen == [{1: 7, 2: 8}, {1: 7}, {1: 9, 2: 8}]
    assert metric.result().id_switches == 1
    with pytest.raises(TypeError):
        metric.last_pairs[1] = 3  # type: ignore[index]


def test_groups_oracle_gap_reads_no_private_attribute_of_the_evaluation() -> None:
    import ast

    bench = Path(__file__).resolve().parents[1] / "benchmarks" / "groups_oracle_gap.py"
    tree = ast.parse(bench.read_text())
    private = {
        node.attr
        for node in ast.walk(tree)
        if isinstance(node, ast.Attribute)
        and isinstance(node.value, ast.Name)
        and node.value.id == "mot"
        and node.attr.startswith("_")
    }
    assert private == set()


def test_no_scan_note_names_what_to_check_after_its_wait() -> None:
    from laserpeople.live.waiting import NO_SCAN_WAIT, no_scan_note

    lasers, endpoint = ("/scan",), ("tcp/10.0.0.9:7447",)
    assert no_scan_note(NO_SCAN_WAIT - 0.1, lasers, endpoint, 0) == ""
    unanswered = no_scan_note(NO_SCAN_WAIT, lasers, endpoint, 0)
    assert unanswered.startswith(
        "no scan on /scan after 10 s: nothing answers at tcp/10.0.0.9:7447"
    )
    assert "still waiting (Ctrl-C stops" in unanswered
    alone = no_scan_note(12.0, lasers, (), 0)
    assert "no Zenoh peer or router found: give --connect" in alone
    reached = no_scan_note(12.0, ("/front", "/back"), endpoint, 2)
    assert reached.startswith("no scan on /front, /back after 12 s: connected to 2 Zenoh")
    assert "check the topic names" in reached and "nothing answers" not in reached
    unknown = no_scan_note(12.0, lasers, endpoint, None)
    assert "nothing answers" not in unknown and "connected to" not in unknown


def test_live_says_while_waiting_that_nothing_answers_at_its_endpoint(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    pytest.importorskip("zenoh")
    import laserpeople.live.waiting as waiting
    from laserpeople.errors import LaserPeopleError
    from live_harness import free_port

    monkeypatch.setattr(waiting, "NO_SCAN_WAIT", 0.5)
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    run = CliRunner().invoke(app, ["live", "--connect", endpoint, "--duration", "2.5"])
    assert isinstance(run.exception, LaserPeopleError), run.output
    text = " ".join(run.output.split())
    import re

    assert re.search(rf"warning: no scan on /scan after \d+ s: nothing answers at {endpoint}", text)
    assert text.count("warning: no scan on /scan") == 1
    assert f"nothing answers at {endpoint}" in str(run.exception)


@pytest.fixture(scope="module")
def small_recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from laserpeople.sim.scenarios import run_scenario

    path = tmp_path_factory.mktemp("small") / "small run.npz"
    run_scenario("figure-eight", seconds=1.0, seed=2).write(path)
    return path


@pytest.mark.parametrize(
    ("option", "name", "extra"),
    [
        ("--bag", "b.bag", []),
        ("--plot", "p.png", []),
        ("--animate", "a.gif", []),
        ("-o", "t.csv", None),
    ],
)
def test_track_refuses_a_folder_for_a_file_output_before_tracking(
    tmp_path: Path, small_recording: Path, option: str, name: str, extra: list[str] | None
) -> None:
    """Found after the whole run before ("Is a directory", with "free disk space" for a
    bag): now before any work, the CSV not begun."""
    from laserpeople.errors import ConfigError

    folder = tmp_path / name
    folder.mkdir()
    csv = tmp_path / "tracks.csv"
    args = ["track", str(small_recording), "-o", str(folder if extra is None else csv)]
    if extra is not None:
        args += [option, str(folder)]
    run = CliRunner().invoke(app, args)
    assert isinstance(run.exception, ConfigError), run.output
    assert str(run.exception).startswith(f"{option} {folder} is a folder: {option} writes a file")
    assert not csv.exists()


def test_simulate_view_and_detect_refuse_a_folder_for_their_file(
    tmp_path: Path, small_recording: Path
) -> None:
    from laserpeople.errors import ConfigError

    folder = tmp_path / "out.npz"
    folder.mkdir()
    for args in (
        ["simulate", "figure-eight", "--seconds", "1", "-o", str(folder)],
        ["view", str(small_recording), "-o", str(folder)],
        ["detect", str(small_recording), "-o", str(folder)],
    ):
        run = CliRunner().invoke(app, args)
        assert isinstance(run.exception, ConfigError), (args, run.output)
        assert f"-o {folder} is a folder" in str(run.exception)
    assert list(folder.iterdir()) == []


def test_batch_out_is_a_folder_and_stays_allowed(tmp_path: Path) -> None:
    from laserpeople.io.paths import check_outputs

    out = tmp_path / "runs"
    out.mkdir()
    check_outputs({"--out": out}, [], folders={"--out"})
    with pytest.raises(Exception, match="is a folder"):
        check_outputs({"--out": out}, [])


CONFIG = """# my settings
[group_tracker]
static_groups = true
p_c = 0.5

[leg_tracker]
p_det_free = 0.3
people.static_legs = "yes"
kalman = { accel_psd = "x" }

[leg_tracker.people]
gate_probability = 0.9
"""


@pytest.mark.parametrize(
    ("keys", "line"),
    [
        (["group_tracker", "static_groups"], 3),
        (["leg_tracker", "p_det_free"], 7),
        (["leg_tracker", "people", "static_legs"], 8),  # a dotted key under its table
        (["leg_tracker", "kalman", "accel_psd"], 9),  # inside an inline table
        (["leg_tracker", "people", "gate_probability"], 12),  # under [leg_tracker.people]
        (["leg_tracker", "people"], 11),  # a table: its header
        (["leg_tracker", "p_c"], None),  # p_c is set under another table only
        (["reid", "p_det_free"], None),
    ],
)
def test_key_line_finds_the_line_of_a_dotted_key_under_its_table(
    tmp_path: Path, keys: list[str], line: int | None
) -> None:
    from laserpeople.config import key_line

    path = tmp_path / "c.toml"
    path.write_text(CONFIG)
    assert key_line(path, keys) == line


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            '[leg_tracker]\n\n# speed\nlambda_new = "fast"\n',
            'line 4: [leg_tracker] lambda_new = "fast" has the wrong type (text): expected a '
            "number like the default 0.001",
        ),
        (
            "[leg_tracker]\np_det_free = 0.3\n[leg_tracker.people]\nstatic_legs = 1\n",
            "line 4: [leg_tracker] people.static_legs = 1 has the wrong type (an integer): "
            "expected true or false like the default false",
        ),
        (
            "[leg_tracker]\npeople_policy = true\n",
            "line 2: [leg_tracker] people_policy = true has the wrong type (true or false): "
            'expected text in quotes like the default "tracks"',
        ),
        ("leg_tracker = 3\n", "line 1: [leg_tracker] must be a table"),
        ("[leg_tracker]\n\nmax_sped = 1.0\n", "line 3: unknown parameter(s) max_sped"),
        ("# a\n\n[leg_trackr]\n", "line 3: unknown section(s) [leg_trackr]"),
        ("[leg_tracker]\n\np_det_free = 1.5\n", "line 3: [leg_tracker] p_det_free = 1.5 is a"),
    ],
)
def test_track_names_the_file_line_key_and_type_wanted_of_a_config_value(
    tmp_path: Path, small_recording: Path, text: str, message: str
) -> None:
    from laserpeople.errors import ConfigError

    config = tmp_path / "my settings.toml"
    config.write_text(text)
    run = CliRunner().invoke(
        app, ["track", str(small_recording), "-o", str(tmp_path / "t.csv"), "--config", str(config)]
    )
    assert isinstance(run.exception, ConfigError), run.output
    assert str(run.exception).startswith(f"{config}: {message}")


def test_a_misspelt_laserpeople_variable_is_said_and_the_known_ones_are_not() -> None:
    from laserpeople.cli.environment import unknown_variables

    env = {
        "LASERPEOPLE_PURE_PYHTON": "1",
        "laserpeople_shared_data": "/data",
        "LASERPEOPLE_PURE_PYTHON": "1",
        "LASERPEOPLE_SHARED_DATA": "/data",
        "PATH": "/bin",
        "MY_LASERPEOPLE_X": "1",
    }
    lines = unknown_variables(env)
    assert lines == [
        "the environment variable LASERPEOPLE_PURE_PYHTON is not read by laserpeople (did you "
        "mean 'LASERPEOPLE_PURE_PYTHON'?); it reads LASERPEOPLE_PURE_PYTHON and "
        "LASERPEOPLE_SHARED_DATA",
        "the environment variable laserpeople_shared_data is not read by laserpeople (did you "
        "mean 'LASERPEOPLE_SHARED_DATA'?); it reads LASERPEOPLE_PURE_PYTHON and "
        "LASERPEOPLE_SHARED_DATA",
    ]


def test_commands_warn_of_an_unread_variable(small_recording: Path, tmp_path: Path) -> None:
    run = CliRunner().invoke(
        app,
        ["track", str(small_recording), "-o", str(tmp_path / "t.csv")],
        env={"LASERPEOPLE_PURE_PYHTON": "1"},
    )
    assert run.exit_code == 0, run.output
    text = " ".join(run.output.split())
    assert "warning: the environment variable LASERPEOPLE_PURE_PYHTON is not read" in text


def test_a_warning_of_the_same_text_is_said_once_per_command(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """LASERPEOPLE_PURE_PYTHON=maybe was said by each of the two C extensions loaded."""
    import warnings

    import laserpeople.cli.common as common
    from laserpeople.errors import LaserPeopleWarning

    said: list[str] = []
    monkeypatch.setattr(common, "warn", said.append)
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        common.warnings_as_lines()
        for text in ("a note", "a note", "another note", "a note"):
            warnings.warn(text, LaserPeopleWarning, stacklevel=1)
        common.warnings_as_lines()  # the next command says it again
        warnings.warn("a note", LaserPeopleWarning, stacklevel=1)
    assert said == ["a note", "another note", "a note"]


def test_titles_draw_what_the_font_has_and_a_question_mark_for_the_rest() -> None:
    pytest.importorskip("matplotlib")
    from laserpeople.viz.figure import drawable

    assert drawable("run ü é 🙂.npz /scan") == "run ü é ?.npz /scan"
    assert drawable("plain\nascii") == "plain\nascii"


@pytest.mark.parametrize("suffix", [".png", ".gif"])
def test_view_of_a_recording_named_with_an_emoji_prints_no_font_warning(
    tmp_path: Path, suffix: str
) -> None:
    pytest.importorskip("matplotlib")
    import shutil
    import warnings

    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "my run ü 🙂.npz"
    run_scenario("figure-eight", seconds=1.0, seed=2).write(rec)
    out = tmp_path / "out ü" / f"v 🙂{suffix}"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run = CliRunner().invoke(app, ["view", str(rec), "-o", str(out)])
    assert run.exit_code == 0, run.output
    assert [str(w.message) for w in caught if "Glyph" in str(w.message)] == []
    assert out.stat().st_size > 1000
    shutil.rmtree(out.parent)


def test_train_neko_names_a_file_a_missing_folder_and_a_folder_without_the_data(
    tmp_path: Path, small_recording: Path
) -> None:
    from laserpeople.errors import RecordingError

    empty = tmp_path / "empty"
    empty.mkdir()
    (tmp_path / "half").mkdir()
    (tmp_path / "half" / "xy_data.txt").write_text("720 2 0\n")
    cases = [
        (small_recording, "is a file, not a neko7055 folder"),
        (tmp_path / "missing", "neko7055 folder not found"),
        (empty, "no xy_data.txt and no leg_segment_labels.json in this folder"),
        (tmp_path / "half", "no leg_segment_labels.json in this folder: not a neko7055"),
    ]
    for folder, message in cases:
        run = CliRunner().invoke(
            app, ["train", "-o", str(tmp_path / "m.json"), "--neko", str(folder)]
        )
        assert isinstance(run.exception, RecordingError), run.output
        assert str(run.exception).startswith(f"{folder}: {message}")
        assert "holding xy_data.txt and leg_segment_labels.json" in str(run.exception)


def test_a_folder_given_as_a_bag_is_named_so_not_called_corrupt(tmp_path: Path) -> None:
    from laserpeople.errors import RecordingError

    folder = tmp_path / "positives"
    folder.mkdir()
    run = CliRunner().invoke(
        app, ["train", "-o", str(tmp_path / "m.json"), "--positives", str(folder)]
    )
    assert isinstance(run.exception, RecordingError), run.output
    text = str(run.exception)
    assert text.startswith(f"{folder}: is a folder without metadata.yaml, not a bag")
    assert "reindex" not in text and "corrupt" not in text


@pytest.mark.parametrize("command", ["info", "track", "view", "detect"])
def test_an_empty_world_frame_is_refused_not_taken_for_the_default(
    small_recording: Path, tmp_path: Path, command: str
) -> None:
    args = [command, str(small_recording), "--world-frame", ""]
    if command != "info":
        args += ["-o", str(tmp_path / ("v.png" if command == "view" else "t.csv"))]
    run = CliRunner().invoke(app, args)
    assert run.exit_code == 2, run.output
    assert "Invalid value for '--world-frame': is empty" in " ".join(run.output.split())


@pytest.mark.parametrize("option", [["--world-frame", "odom"], ["--mount", "laser=base:1,0,0"]])
def test_info_refuses_bag_options_on_a_recording_without_tf_as_the_others_do(
    small_recording: Path, option: list[str]
) -> None:
    from laserpeople.errors import ConfigError

    run = CliRunner().invoke(app, ["info", str(small_recording), *option])
    assert isinstance(run.exception, ConfigError), run.output
    assert "--world-frame and --mount apply to ROS bags only" in str(run.exception)


def test_bench_of_a_recording_says_the_scenario_options_are_not_used(
    small_recording: Path,
) -> None:
    args = ["bench", str(small_recording), "--tracker", "nn", "--repeat", "1", "--max-scans", "5"]
    run = CliRunner().invoke(app, [*args, "--seconds", "-1", "--seed", "3"])
    assert run.exit_code == 0, run.output
    text = " ".join(run.output.split())
    assert "warning: --seconds, --seed set the simulated scenario, which is not run" in text
    plain = CliRunner().invoke(app, args)
    assert plain.exit_code == 0 and "simulated scenario" not in plain.output


def test_align_refuses_an_empty_reference(small_recording: Path, tmp_path: Path) -> None:
    run = CliRunner().invoke(
        app, ["align", str(small_recording), "-o", str(tmp_path / "m.toml"), "--reference", ""]
    )
    assert run.exit_code == 2, run.output
    assert "Invalid value for '--reference': is empty" in " ".join(run.output.split())


def _dead_pid() -> int:
    import subprocess

    done = subprocess.run(["true"], check=True)
    assert done.returncode == 0
    proc = subprocess.Popen(["true"])
    proc.wait()
    return proc.pid


def test_track_bag_says_a_folder_left_by_a_killed_run_and_not_a_running_one(
    small_recording: Path, tmp_path: Path
) -> None:
    import os

    bag = tmp_path / "out.bag"
    dead = tmp_path / f".out.bag.{_dead_pid()}-abcd1234"
    running = tmp_path / f".out.bag.{os.getpid()}-efgh5678"
    other = tmp_path / f".other.bag.{_dead_pid()}-abcd1234"
    for folder in (dead, running, other):
        folder.mkdir()
    run = CliRunner().invoke(
        app, ["track", str(small_recording), "-o", str(tmp_path / "t.csv"), "--bag", str(bag)]
    )
    assert run.exit_code == 0, run.output
    text = " ".join(run.output.split())
    assert f"warning: {bag}: {dead.name} beside it was left by an earlier run" in text
    assert running.name not in text and other.name not in text
    assert bag.is_file() and dead.is_dir()  # said, not removed
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".out.bag.")) == sorted(
        [dead.name, running.name]
    )  # the run's own folder is gone


def test_live_record_says_where_the_frames_of_a_killed_recording_are(tmp_path: Path) -> None:
    import warnings

    from laserpeople.errors import LaserPeopleWarning
    from laserpeople.io.mcap_record import McapRecorder

    target = tmp_path / "run.mcap"
    dead = tmp_path / f".run.mcap.{_dead_pid()}-zz"
    dead.mkdir()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        recorder = McapRecorder(target)
        recorder.close()
    said = [str(w.message) for w in caught if issubclass(w.category, LaserPeopleWarning)]
    assert said == [
        f"{target}: {dead.name} beside it holds the frames of an earlier recording into it "
        f"that was killed: `laserpeople track {dead / 'out' / 'out.mcap'} --on-error skip` "
        "reads them; move or remove the folder"
    ]
    assert target.is_file()


def test_detect_says_each_kind_of_beam_it_skipped(tmp_path: Path) -> None:
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "bad ranges.npz"
    run_scenario("figure-eight", seconds=1.0, seed=5).write(rec)
    with np.load(rec) as z:
        arrays = {k: z[k] for k in z.files}
    ranges = arrays["ranges"]
    ranges[np.isposinf(ranges)] = 30.0  # no return written as a long range
    start = int(arrays["scan_offset"][2])
    ranges[start : start + 6] = [np.nan, np.nan, -1.0, 0.0, 0.0, 0.0]
    np.savez(rec, **arrays)  # type: ignore[arg-type]
    limit = np.repeat(arrays["scan_range_max"], np.diff(arrays["scan_offset"]))
    over = int(np.count_nonzero(np.isfinite(ranges) & (ranges > limit)))
    run = CliRunner().invoke(app, ["detect", str(rec), "-o", str(tmp_path / "d.csv")])
    assert run.exit_code == 0, run.output
    text = " ".join(run.output.split())
    assert f"{over + 6:,} invalid beams skipped (NaN 2, negative 1, zero 3, over range_max " in text
    assert f"over range_max {over:,}); wrote" in text and over > 0


def test_a_sweep_over_a_section_with_nested_tables_keeps_the_config_s_nested_values(
    tmp_path: Path,
) -> None:
    """[grid.leg_tracker] failed on every setting ('kalman = KalmanParams(...) must be a
    table'): the leg tracker's parameters hold nested tables."""
    from laserpeople.batch.options import TrackOptions, resolve

    config = tmp_path / "base.toml"
    config.write_text("[leg_tracker]\npeople.static_legs = true\nkalman.accel_psd = 20.0\n")
    options = TrackOptions(config=config)
    plain = resolve(options)
    swept = resolve(options, {"leg_tracker": {"lambda_new": 0.0005}})
    assert swept.tracker_params.lambda_new == pytest.approx(0.0005, abs=1e-15)
    assert swept.tracker_params.people.static_legs is True
    assert swept.tracker_params.kalman.accel_psd == pytest.approx(20.0, abs=1e-12)
    assert swept.tracker_params.kalman == plain.tracker_params.kalman
    assert swept.digest != plain.digest
    same = resolve(options, {"leg_tracker": {"lambda_new": plain.tracker_params.lambda_new}})
    assert same.digest == plain.digest


def test_a_grid_value_the_parameters_refuse_names_the_sweep_file(
    small_recording: Path, tmp_path: Path
) -> None:
    from laserpeople.errors import ConfigError

    sweep = tmp_path / "grid.toml"
    sweep.write_text("[grid.leg_tracker]\nlambda_neww = [0.1]\n")
    run = CliRunner().invoke(
        app,
        ["batch", str(small_recording), "--out", str(tmp_path / "out"), "--sweep", str(sweep)],
    )
    assert isinstance(run.exception, ConfigError), run.output
    assert str(run.exception).startswith(f"{sweep}: unknown parameter(s) lambda_neww in")


def test_evaluate_of_a_folder_that_is_no_batch_folder_says_so(tmp_path: Path) -> None:
    from laserpeople.errors import EvaluationError

    plain = tmp_path / "runs"
    plain.mkdir()
    sweep = tmp_path / "sweep"
    (sweep / "settings-000" / "tune").mkdir(parents=True)
    (sweep / "sweep.csv").write_text("rank\n")
    for folder, hint in ((plain, "give a tracks file and its --truth"), (sweep, "a sweep's")):
        run = CliRunner().invoke(app, ["evaluate", str(folder)])
        assert isinstance(run.exception, EvaluationError), run.output
        text = str(run.exception)
        assert text.startswith(f"{folder}: is a folder but not the --out folder of")
        assert hint in text


def test_simulate_refuses_an_output_it_cannot_write_before_simulating(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """`simulate -o scene.csv` says which extensions it writes before any simulation runs
    (a long scenario was simulated in full and then refused)."""
    from laserpeople import sim
    from laserpeople.errors import LaserPeopleError

    ran: list[str] = []
    monkeypatch.setattr(sim, "run_scenario", lambda name, **_: ran.append(name))
    out = tmp_path / "scene.csv"
    run = CliRunner().invoke(app, ["simulate", "demo", "--seconds", "600", "-o", str(out)])
    assert isinstance(run.exception, LaserPeopleError), run.output
    assert "cannot write simulated recordings as '.csv'" in str(run.exception)
    assert ran == [] and not out.exists()


def test_fit_truth_that_is_a_folder_or_missing_is_named_so(tmp_path: Path) -> None:
    """`fit --truth` given a folder, a missing file or another file says which it is."""
    from laserpeople.fitting.data import read_truth
    from laserpeople.fitting.estimates import FitError

    (tmp_path / "runs").mkdir()
    (tmp_path / "notes.txt").write_text("scan,stamp\n")
    for name, what in (
        ("runs", "is a folder, not a truth file"),
        ("nosuch.txt", "does not exist"),
        ("notes.txt", "is neither a truth CSV nor a bag"),
    ):
        with pytest.raises(FitError, match=what):
            read_truth(str(tmp_path / name), None)
