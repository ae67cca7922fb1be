"""What a demanding new user tries: a recording given as a symbolic link whose target is
gone, `view` of a tracks file that holds no track, misspelt names in configs and options."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import ConfigError, RecordingError


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from laserpeople.sim.scenarios import run_scenario

    path = tmp_path_factory.mktemp("rec") / "walk.npz"
    run_scenario("figure-eight", seconds=1.0, seed=3).write(path)
    return path


@pytest.mark.parametrize("suffix", [".bag", ".npz", ".log", ".mcap"])
def test_a_link_to_a_missing_recording_says_where_it_points(tmp_path: Path, suffix: str) -> None:
    from laserpeople.io import open_recording

    (tmp_path / "runs").mkdir()
    link = tmp_path / "runs" / f"again{suffix}"
    link.symlink_to(f"runs/gone{suffix}")  # relative: read from runs/, not from here
    with pytest.raises(RecordingError) as err:
        open_recording(link)
    assert f"a symbolic link to 'runs/gone{suffix}', which does not exist (a relative link" in str(
        err.value
    )
    with pytest.raises(RecordingError, match=r"nothere\.bag: file not found"):
        open_recording(tmp_path / "nothere.bag")


def test_batch_names_a_link_to_a_missing_recording(tmp_path: Path) -> None:
    from laserpeople.batch.hashing import content_hash

    link = tmp_path / "a.bag"
    link.symlink_to(tmp_path / "b.bag")
    with pytest.raises(RecordingError, match=f"a symbolic link to '{tmp_path / 'b.bag'}', which"):
        content_hash(link)
    (tmp_path / "b.bag").write_bytes(b"x")
    assert content_hash(link) == content_hash(tmp_path / "b.bag")
    os.unlink(tmp_path / "b.bag")


def test_view_of_a_tracks_file_without_a_track_says_so(tmp_path: Path, recording: Path) -> None:
    from laserpeople.io.tracks_csv import HEADER

    empty = tmp_path / "tracks.csv"
    empty.write_text(",".join(HEADER) + "\n")
    run = CliRunner().invoke(
        app, ["view", str(recording), "--tracks", str(empty), "-o", str(tmp_path / "v.png")]
    )
    assert run.exit_code == 0, run.output
    assert f"{empty} holds no track: the drawing shows none" in " ".join(run.output.split())
    tracks = tmp_path / "t.csv"
    assert (
        CliRunner().invoke(app, ["-q", "track", str(recording), "-o", str(tracks)]).exit_code == 0
    )
    run = CliRunner().invoke(
        app, ["view", str(recording), "--tracks", str(tracks), "-o", str(tmp_path / "w.png")]
    )
    assert run.exit_code == 0 and "holds no track" not in run.output


TRACKERS = ["csa", "feet-pf", "group-mht", "leg-mht", "nn", "upper-body-pf"]


@pytest.mark.parametrize(
    ("typed", "meant"),
    [
        ("leg_mht", ["leg-mht"]),  # _ for -
        ("LEG-MHT", ["leg-mht"]),  # case
        ("legmht", ["leg-mht"]),  # 0.92
        ("group-mth", ["group-mht"]),  # 0.89
        ("csa2", ["csa"]),  # 0.86
        ("n", []),  # 'nn' 0.67: too far
        ("particle", []),
    ],
)
def test_misspelt_names_get_the_close_ones(typed: str, meant: list[str]) -> None:
    from laserpeople.spelling import closest

    assert closest(typed, TRACKERS) == meant


def test_suggestions_by_leaf_start_and_end() -> None:
    from laserpeople.spelling import closest, did_you_mean

    nested = ["kalman.gate_probability", "people.gate_probability", "people", "p_det_free"]
    assert closest("gate_probabilty", nested) == nested[:2]
    assert closest("p_det", ["p_t", "p_det_free", "p_det_approved"]) == [
        "p_det_free",
        "p_det_approved",
    ]  # p_t is 0.75 alike: not offered
    assert closest("threshold", ["score_threshold", "centre_offset"]) == ["score_threshold"]
    assert closest("a", ["b", "c", "d", "e"]) == []
    assert did_you_mean("x", ["x_a", "x_b", "x_c", "x_d"]) == "did you mean 'x_a', 'x_b' or 'x_c'?"


@pytest.mark.parametrize(
    ("text", "said"),
    [
        (
            "[leg_tracker]\ngate_probabilty = 0.9\n",
            "unknown parameter(s) gate_probabilty in [leg_tracker]; gate_probabilty: did you "
            "mean 'kalman.gate_probability' or 'people.gate_probability'?",
        ),
        (
            "[leg_trackr]\np_det_free = 0.9\n",
            "unknown section(s) [leg_trackr]; [leg_trackr]: did you mean 'leg_tracker'?",
        ),
        (
            "p_det = 0.9\n",
            "p_det outside any [section]; p_det: did you mean 'leg_tracker.p_det_free' or "
            "'leg_tracker.p_det_approved'?",
        ),
        ("[leg_detector]\nzzz = 1\n", "unknown parameter(s) zzz in [leg_detector] ("),
    ],
)
def test_config_typos_are_answered_with_the_parameter_meant(
    tmp_path: Path, recording: Path, text: str, said: str
) -> None:
    config = tmp_path / "c.toml"
    config.write_text(text)
    run = CliRunner().invoke(
        app, ["track", str(recording), "-o", str(tmp_path / "t.csv"), "--config", str(config)]
    )
    assert isinstance(run.exception, ConfigError)
    assert said in str(run.exception)
    assert not (tmp_path / "t.csv").exists()


def test_a_dotted_key_as_suggested_reads() -> None:
    """The suggestion for a parameter outside a section (``leg_tracker.p_det_free``) is a
    TOML dotted key: written so, above every section, it is read."""
    import tomllib

    from laserpeople.config import from_mapping
    from laserpeople.tracking.registry import get

    cls = get("leg-mht").params_cls
    params = from_mapping(cls, tomllib.loads("leg_tracker.lambda_new = 0.25\n")["leg_tracker"])
    assert params.lambda_new == 0.25


@pytest.mark.parametrize(
    ("args", "said"),
    [
        (["simulate", "demoo", "-o", "x.npz"], "unknown scenario 'demoo': did you mean 'demo'?"),
        (["track", "REC", "-o", "t.csv", "--detector", "adaboot"], "did you mean 'adaboost'?"),
        (["track", "REC", "-o", "t.csv", "--preset", "papers"], "did you mean 'paper'?"),
        (["track", "REC", "-o", "t.csv", "--tracker", "group-mth"], "did you mean 'group-mht'?"),
    ],
)
def test_misspelt_option_values_get_a_suggestion(
    tmp_path: Path, recording: Path, args: list[str], said: str
) -> None:
    args = [
        str(recording) if a == "REC" else str(tmp_path / a) if a.endswith(("npz", "csv")) else a
        for a in args
    ]
    run = CliRunner().invoke(app, args)
    assert run.exception is not None and said in str(run.exception)


def test_view_of_several_lasers_names_the_one_drawn(tmp_path: Path, recording: Path) -> None:
    import dataclasses

    from laserpeople.io import open_recording, write_recording

    with open_recording(recording) as rec:
        scans = list(rec.scans())
    both = [dataclasses.replace(s, sensor=name) for s in scans for name in ("/front", "/rear")]
    two = tmp_path / "two.npz"
    write_recording(two, both)
    run = CliRunner().invoke(app, ["view", str(two), "-o", str(tmp_path / "a.png")])
    assert run.exit_code == 0, run.output
    line = "drew topic /front (the recording has /front, /rear; use --topic, or --topics all"
    assert line in " ".join(run.output.split())
    for more in (["--topics", "all"], ["--topic", "/rear"]):
        run = CliRunner().invoke(app, ["view", str(two), "-o", str(tmp_path / "b.png"), *more])
        assert run.exit_code == 0 and "drew topic" not in run.output, run.output
    run = CliRunner().invoke(app, ["view", str(recording), "-o", str(tmp_path / "c.png")])
    assert run.exit_code == 0 and "drew topic" not in run.output


@pytest.mark.parametrize("suffix", [".npz", ".log", ".bag", ".mcap"])
def test_an_empty_recording_of_any_format_is_said_empty(tmp_path: Path, suffix: str) -> None:
    """An .npz said 'File is not a zip file' and a CARMEN log 'no laser lines'."""
    from laserpeople.io import open_recording

    empty = tmp_path / f"run{suffix}"
    empty.write_bytes(b"")
    with pytest.raises(RecordingError, match=r"the file is empty \(0 bytes\), not a recording"):
        open_recording(empty)
    run = CliRunner().invoke(app, ["info", str(empty)])
    assert "empty (0 bytes)" in str(run.exception)


def test_batch_of_a_folder_takes_the_recordings_in_it_once(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    from laserpeople.cli.batch import expand

    runs = tmp_path / "runs"
    (runs / "ros2bag").mkdir(parents=True)
    (runs / "ros2bag" / "metadata.yaml").write_text("")
    (runs / "deeper").mkdir()
    (runs / "deeper" / "x.bag").write_bytes(b"")
    for name in ("a.npz", "c.MCAP", "run.log", "notes.txt", "a.people.csv"):
        (runs / name).write_bytes(b"")
    (runs / "b.npz").symlink_to("a.npz")  # the same recording by another name
    monkeypatch.chdir(tmp_path)
    got = expand(["runs"], Path("runs/out"))
    assert got == [Path(f"runs/{n}") for n in ("a.npz", "c.MCAP", "ros2bag", "run.log")]
    said = " ".join(capsys.readouterr().err.split())
    assert (
        "runs: a folder: its 5 recordings; left out 2 other entries (deeper, notes.txt); "
        "subfolders are not searched" in said
    )
    assert "tracked once: runs/a.npz (also as runs/b.npz)" in said
    # the output folder inside it is left out and said; a ROS 2 bag folder is one recording
    (runs / "out").mkdir()
    assert expand(["runs"], runs / "out") == got
    assert "3 other entries (deeper, notes.txt, out (the output folder))" in capsys.readouterr().err
    assert expand(["runs/ros2bag"]) == [Path("runs/ros2bag")]
    (tmp_path / "empty").mkdir()
    with pytest.raises(ConfigError, match=r"the folder empty holds no recording"):
        expand(["empty"])
