"""Options a command takes but a run would not use are said, and live names are checked
before a session opens (third hardening round)."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import ConfigError


@pytest.fixture(scope="module")
def still(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A short recording of a still laser (simulated, with poses)."""
    from laserpeople.sim.scenarios import run_scenario

    path = tmp_path_factory.mktemp("still") / "demo.npz"
    run_scenario("demo", seconds=2.0, seed=3).write(path)
    return path


@pytest.fixture(scope="module")
def model(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A copy of the shipped leg model, as a user's --model file."""
    import shutil

    import laserpeople.detection as detection

    path = tmp_path_factory.mktemp("model") / "mine.json"
    shutil.copy(Path(detection.__file__).parent / "models" / "default.json", path)
    return path


def _track(still: Path, out: Path, *args: str) -> str:
    run = CliRunner().invoke(app, ["track", str(still), "-o", str(out), *args])
    assert run.exit_code == 0, run.output
    return run.output


def test_a_leg_model_a_tracker_of_points_never_used_is_said(
    still: Path, model: Path, tmp_path: Path
) -> None:
    out = tmp_path / "t.csv"
    said = _track(still, out, "--tracker", "feet-pf", "--model", str(model))
    assert f"--model {model} had no effect: feet-pf tracks foreground points" in said
    said = _track(still, out, "--tracker", "group-mht", "--detector", "heuristic")
    assert "--detector heuristic had no effect: group-mht" in said
    config = tmp_path / "legs.toml"
    config.write_text("[leg_detector]\nscore_threshold = 0.5\n")
    said = _track(still, out, "--tracker", "feet-pf", "--config", str(config))
    assert f"[leg_detector] of {config} had no effect" in said
    # a --print-config dump holds the defaults: fed back, it asks nothing of the detector
    dump = CliRunner().invoke(app, ["track", "--tracker", "feet-pf", "--print-config"])
    config.write_text(dump.output)
    assert "[leg_detector]" in dump.output
    said = _track(still, out, "--tracker", "feet-pf", "--config", str(config))
    assert "had no effect" not in said
    # used: a tracker of legs; points narrowed to legs on a still laser too
    assert "had no effect" not in _track(still, out, "--model", str(model))
    config.write_text('[leg_foreground]\nuse = "always"\n')
    said = _track(
        still, out, "--tracker", "feet-pf", "--model", str(model), "--config", str(config)
    )
    assert "had no effect" not in said
    # nothing given: nothing said
    assert "had no effect" not in _track(still, out, "--tracker", "feet-pf")


def test_a_static_world_model_nobody_asks_is_said(still: Path, tmp_path: Path) -> None:
    out = tmp_path / "t.csv"
    said = _track(still, out, "--people-policy", "arras", "--background", "histogram")
    assert "--background histogram had no effect: leg-mht with the arras people policy" in said
    off = tmp_path / "off.toml"
    off.write_text("[static_tracks]\nhide = false\n")
    said = _track(still, out, "--tracker", "nn", "--config", str(off), "--background", "occupancy")
    assert "--background occupancy had no effect: nn asks no static world model" in said
    # asked: nn hides person tracks on static places by default
    assert "had no effect" not in _track(still, out, "--tracker", "nn", "--background", "histogram")
    assert "had no effect" not in _track(still, out, "--people-policy", "arras")


def _map(tmp_path: Path) -> Path:
    image = tmp_path / "free.pgm"
    image.write_bytes(b"P5\n40 40\n255\n" + bytes([254]) * 1600)
    yaml = tmp_path / "free.yaml"
    yaml.write_text(
        "image: free.pgm\nresolution: 0.5\norigin: [-10.0, -10.0, 0.0]\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\nnegate: 0\n"
    )
    return yaml


def test_a_map_seeds_the_model_that_hides_static_person_tracks(still: Path, tmp_path: Path) -> None:
    out = tmp_path / "t.csv"
    grid = _map(tmp_path)
    # nn asks the people's model (static_tracks.hide): the map seeds it (it was refused)
    said = _track(still, out, "--tracker", "nn", "--map", str(grid))
    assert f"seeded by the map {grid}" in said
    off = tmp_path / "off.toml"
    off.write_text("[static_tracks]\nhide = false\n")
    for args, why in (
        (["--tracker", "nn", "--config", str(off)], "with static_tracks.hide = false"),
        (["--people-policy", "arras"], "arras people policy has no static world model"),
    ):
        run = CliRunner().invoke(
            app, ["track", str(still), "-o", str(out), "--map", str(grid), *args]
        )
        assert isinstance(run.exception, ConfigError), run.output
        assert "--map seeds the static world model, but this run uses none" in str(run.exception)
        assert why in str(run.exception)


def test_a_preset_that_sets_nothing_of_the_tracker_is_said(still: Path, tmp_path: Path) -> None:
    from laserpeople.pipeline.unused_options import preset_note
    from laserpeople.tracking import registry

    out = tmp_path / "t.csv"
    said = _track(still, out, "--preset", "paper")  # the leg MHT has 000's values
    assert "sets nothing of" not in said
    said = _track(still, out, "--tracker", "nn", "--preset", "paper")
    assert "--preset paper sets nothing of [nn_tracker]: nn follows no paper" in said
    for name in ("leg-mht", "group-mht", "csa", "feet-pf", "upper-body-pf"):
        assert preset_note(name, registry.get(name).params_cls, "paper") is None
    assert preset_note("nn", registry.get("nn").params_cls, None) is None
    # batch and live say it too (before anything runs)
    pytest.importorskip("dask")
    batch = CliRunner().invoke(
        app,
        [
            "batch",
            str(tmp_path / "none*.bag"),
            "-o",
            str(tmp_path / "b"),
            "--tracker",
            "nn",
            "--preset",
            "paper",
        ],
    )
    assert "--preset paper sets nothing of [nn_tracker]" in batch.output
    pytest.importorskip("zenoh")
    live = CliRunner().invoke(
        app, ["live", "--tracker", "nn", "--preset", "paper", "--duration", "0.3"]
    )
    assert "--preset paper sets nothing of [nn_tracker]" in live.output


@pytest.mark.parametrize(
    ("name", "problem"),
    [
        ("/my people", "holds ' '"),
        ("/a*b", "holds '*'"),
        ("/x//y", "empty part"),
        ("/1st/people", "'1st' starts with a digit"),
        ("/robot/2d", "'2d' starts with a digit"),
        ("/a__b", "holds '__'"),
        ("/odöm", "holds 'ö'"),
        ("~/scan", "holds '~'"),
        ("/{ns}/scan", "holds '{'"),
        ("", "empty"),
        ("/", "empty"),
    ],
)
def test_topic_names_that_ros_2_refuses(name: str, problem: str) -> None:
    from laserpeople.live.names import topic_problem

    found = topic_problem(name)
    assert found is not None and problem in found


@pytest.mark.parametrize("name", ["/scan", "scan", "/scan/", "/robot1/base_scan", "/_x", "/a_b/c9"])
def test_topic_names_that_ros_2_takes(name: str) -> None:
    from laserpeople.live.names import topic_problem

    assert topic_problem(name) is None


def test_live_names_are_checked_before_a_session_opens() -> None:
    from laserpeople.cli.live import check_live_names
    from laserpeople.live.names import check_key_prefix

    def refused(**over: object) -> str:
        args: dict[str, object] = {
            "lasers": ["/scan"],
            "tf_topic": "/tf",
            "tf_static_topic": "/tf_static",
            "odom_topic": "/odom",
            "output_prefix": "/laserpeople",
            "key_prefix": "",
        }
        args.update(over)
        with pytest.raises(ConfigError) as caught:
            check_live_names(**args)  # type: ignore[arg-type]
        return str(caught.value)

    assert "--output-prefix '/my people' is not a ROS 2 topic name" in refused(
        output_prefix="/my people"
    )
    assert "--topic '/sc an'" in refused(lasers=["/sc an"])
    assert "--odom-topic '/od om'" in refused(odom_topic="/od om")
    assert "--topic /scan is given twice" in refused(lasers=["/scan", "scan/"])
    assert "--topic '/laserpeople/people' is a topic this run publishes" in refused(
        lasers=["/laserpeople/people"]
    )
    assert "--tf-topic '/out/markers' is a topic this run publishes" in refused(
        tf_topic="/out/markers", output_prefix="/out"
    )
    assert "--key-prefix 'robot/$' cannot start a Zenoh key" in refused(key_prefix="robot/$")
    assert "empty part" in refused(key_prefix="a//b")
    # taken: no prefix at all, topics switched off, a prefix with slashes round it
    check_live_names(["/scan"], "none", "", "none", "/", "/robot1/")
    check_live_names(["/front", "/back"], "/tf", "/tf_static", "/odom", "people_out", "")
    for fine in ("", "/", "robot1", "fleet/robot 1"):
        check_key_prefix(fine)


def test_live_refuses_a_bad_name_on_the_command_line() -> None:
    pytest.importorskip("zenoh")
    run = CliRunner().invoke(app, ["live", "--output-prefix", "/my people", "--duration", "0.3"])
    assert isinstance(run.exception, ConfigError), run.output
    assert "--output-prefix '/my people' is not a ROS 2 topic name" in str(run.exception)
    port = CliRunner().invoke(app, ["live", "--foxglove", "70000", "--duration", "0.3"])
    assert port.exit_code == 2 and "Invalid value for '--foxglove'" in port.output
    queue = CliRunner().invoke(app, ["live", "--queue", "0", "--duration", "0.3"])
    assert queue.exit_code == 2 and "Invalid value for '--queue'" in queue.output


@pytest.mark.parametrize(
    ("value", "forced", "warned"),
    [
        ("", False, False),
        ("0", False, False),
        ("false", False, False),
        (" No ", False, False),
        ("OFF", False, False),
        ("1", True, False),
        ("true", True, False),
        ("yes", True, False),
        ("junk", True, True),
        ("2", True, True),
    ],
)
def test_the_pure_python_switch_reads_words_and_warns_of_junk(
    monkeypatch: pytest.MonkeyPatch, value: str, forced: bool, warned: bool
) -> None:
    import warnings

    from laserpeople.errors import LaserPeopleWarning
    from laserpeople.tracking.mht import compiled

    monkeypatch.setenv(compiled.PURE_PYTHON, value)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert compiled.forced_pure_python() is forced
    said = [w for w in caught if issubclass(w.category, LaserPeopleWarning)]
    assert bool(said) is warned
    if warned:
        assert f"LASERPEOPLE_PURE_PYTHON={value!r} is neither 1 nor 0" in str(said[0].message)


def test_a_laser_frame_changing_mid_recording_and_zero_stamps_are_said(tmp_path: Path) -> None:
    from dataclasses import replace

    from laserpeople.io.rosbag_writer import open_bag
    from laserpeople.sim.scenarios import run_scenario

    scans = list(run_scenario("demo", seconds=1.0, seed=1).scans)
    bag = tmp_path / "changed.bag"
    with open_bag(bag) as sink:
        for k, scan in enumerate(scans):
            frame = "laser" if k < 8 else ("laser_b" if k < 15 else "laser_c")
            if k in (3, 4):  # a driver that wrote no stamp: the bag's log time is used
                sink.scan(replace(scan, stamp=0.0), "/scan", frame, log_stamp=scan.stamp)
            else:
                sink.scan(scan, "/scan", frame)
    n = len(scans)
    run = CliRunner().invoke(app, ["track", str(bag), "-o", str(tmp_path / "t.csv")])
    assert run.exit_code == 0, run.output
    others = sorted([(7, "laser_b"), (n - 15, "laser_c")], key=lambda c: (-c[0], c[1]))
    counted = ", ".join(f"{count} in {frame!r}" for count, frame in others)
    assert f"/scan: header.frame_id changed from 'laser' at scan 8 ({counted})" in run.output
    assert "2 scans with a zero header stamp were stamped with the time the bag logged" in (
        run.output
    )
    info = CliRunner().invoke(app, ["info", str(bag)])
    assert "header.frame_id changed from 'laser' at scan 8" in info.output


def test_a_scanner_sweeping_the_other_way_gives_the_same_features_and_legs() -> None:
    """A scanner with negative angle_increment (mounted upside down, the MiR's) gives each
    segment the features of the same beams swept by increasing angle: features 4 and 5
    (jump to the segment at smaller / larger angles) were swapped: on 4 s of this scene the
    mirrored copy gave 249 legs against 221."""
    from dataclasses import replace

    import numpy as np

    from laserpeople.detection.detector import AdaBoostLegDetector
    from laserpeople.detection.features import compute_features
    from laserpeople.segmentation import JumpDistanceSegmenter
    from laserpeople.sim.scenarios import run_scenario

    scans = list(run_scenario("demo", seconds=1.0, seed=0).scans)
    step = 2.0**-10  # binary angles: the reversed layout has exactly the same beam angles
    up, down = [], []
    for scan in scans:
        half = (scan.n_beams - 1) * step / 2.0
        up.append(replace(scan, angle_min=-half, angle_increment=step, pose=None, labels=None))
        down.append(
            replace(
                scan,
                ranges=scan.ranges[::-1].copy(),
                angle_min=half,
                angle_increment=-step,
                pose=None,
                labels=None,
            )
        )
    segmenter = JumpDistanceSegmenter()
    for k in (5, 15):
        a = compute_features(segmenter(up[k]), up[k], up[k - 1]).values
        b = compute_features(segmenter(down[k]), down[k], down[k - 1]).values[::-1]
        assert a.shape == b.shape and np.max(np.abs(a[:, 3:5] - b[:, 3:5])) < 1e-9
        assert np.max(np.abs(a - b)) < 1e-6  # (sums in the other order)
    ups, downs = AdaBoostLegDetector.default(), AdaBoostLegDetector.default()
    found_up = sum(len(ups.detect(s).positions) for s in up)
    found_down = sum(len(downs.detect(s).positions) for s in down)
    assert found_up == found_down


def test_batch_takes_a_recording_once_by_any_spelling_and_not_its_own_output(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    from laserpeople.cli.batch import expand

    runs = tmp_path / "runs"
    runs.mkdir()
    a, b = runs / "a.bag", runs / "b.bag"
    a.write_bytes(b"")
    b.write_bytes(b"")
    monkeypatch.chdir(tmp_path)
    # one file, three spellings: tracked once (it was tracked three times into one file)
    got = expand(["runs/a.bag", str(a), "runs/../runs/a.bag", "runs/b.bag"])
    assert got == [Path("runs/a.bag"), Path("runs/b.bag")]
    assert "tracked once: runs/a.bag" in capsys.readouterr().err
    # the output folder inside the input folder: a rerun's glob leaves it out, and says so
    out = runs / "out"
    (out / "tracks").mkdir(parents=True)
    (out / "summary.csv").write_text("")
    assert expand(["runs/*"], Path("runs/out")) == [Path("runs/a.bag"), Path("runs/b.bag")]
    assert "left out 1 glob matches in the output folder runs/out" in capsys.readouterr().err
    assert expand(["runs/**"], out) == [Path("runs"), Path("runs/a.bag"), Path("runs/b.bag")]
    assert "left out 3 glob matches" in capsys.readouterr().err
    with pytest.raises(ConfigError, match="matches only the output folder"):
        expand(["runs/out/*"], out)
    assert expand(["runs/*"]) == [Path("runs/a.bag"), Path("runs/b.bag"), Path("runs/out")]


def test_evaluate_says_when_one_truth_scores_several_tracks_files(
    still: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import shutil

    monkeypatch.chdir(tmp_path)
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    _track(still, tmp_path / "a" / "tracks.csv")
    _track(still, tmp_path / "b" / "tracks.csv", "--tracker", "nn")
    shutil.copy(still, tmp_path / "other.npz")
    run = CliRunner().invoke(
        app,
        ["evaluate", "a/tracks.csv", "b/tracks.csv", "--truth", str(still), "--truth", str(still)],
    )
    assert run.exit_code == 0, run.output
    assert (
        "one truth scores 2 TRACKS files (a/tracks.csv, b/tracks.csv): the pooled row counts "
        "its people 2 times" in run.output
    )
    # another recording (even a copy) for each file: nothing said; rows named by path (the
    # stems are the same)
    other = CliRunner().invoke(
        app,
        ["evaluate", "a/tracks.csv", "b/tracks.csv", "--truth", str(still), "--truth", "other.npz"],
    )
    assert other.exit_code == 0, other.output
    assert "one truth scores" not in other.output
    assert "a/tracks.csv" in other.output and "b/tracks.csv" in other.output


def test_a_csv_of_another_of_our_formats_is_named_so(tmp_path: Path) -> None:
    from laserpeople.errors import RecordingError
    from laserpeople.io.tracks_csv import iter_tracks_csv
    from laserpeople.io.truth_csv import read_truth_csv

    tracks = tmp_path / "tracks.csv"
    tracks.write_text("scan,stamp,track_id,kind,x,y\n0,0.0,1,person,1.0,2.0\n")
    truth = tmp_path / "run.people.csv"
    truth.write_text("scan,stamp,person_id,x,y\n0,0.0,1,1.0,2.0\n")
    legs = tmp_path / "legs.csv"
    legs.write_text("scan,stamp,x,y,score,topic\n0,0.0,1.0,2.0,0.5,laser\n")
    with pytest.raises(RecordingError) as as_truth:
        read_truth_csv(tracks)
    assert "this header is that of a tracks CSV (`laserpeople track -o`): give it as TRACKS" in (
        str(as_truth.value)
    )
    for wrong, said in (
        (truth, "a ground-truth CSV: give it with --truth"),
        (legs, "a detections CSV"),
    ):
        with pytest.raises(RecordingError) as as_tracks:
            list(iter_tracks_csv(wrong))
        assert f"this header is that of {said}" in str(as_tracks.value)
    with pytest.raises(RecordingError) as neither:
        read_truth_csv(legs)
    assert "detections CSV" in str(neither.value)
    odd = tmp_path / "odd.csv"
    odd.write_text("frame,id,x,y\n1,1,0.5,0.5\n")
    with pytest.raises(RecordingError) as unknown:
        read_truth_csv(odd)
    assert "this header is that of" not in str(unknown.value)


def test_live_options_the_transport_or_frame_would_not_use_are_refused() -> None:
    from laserpeople.cli.live import check_live_options

    def refused(**over: object) -> str:
        args: dict[str, object] = {
            "transport": "bridge",
            "key_prefix": "",
            "domain": 0,
            "type_hashes": "rihs01",
            "frame": "auto",
            "world_frame": None,
            "mount": None,
            "map_path": None,
        }
        args.update(over)
        with pytest.raises(ConfigError) as caught:
            check_live_options(**args)  # type: ignore[arg-type]
        return str(caught.value)

    assert "--key-prefix 'robot1' applies to the bridge transport" in refused(
        transport="rmw", key_prefix="robot1"
    )
    assert "--domain 5 applies to the rmw transport" in refused(domain=5)
    assert "--domain 5 and --type-hashes none apply to the rmw transport" in refused(
        domain=5, type_hashes="none"
    )
    assert "--type-hashes 'junk': choose rihs01 or none" in refused(
        transport="rmw", type_hashes="junk"
    )
    assert "--world-frame needs the world frame" in refused(frame="sensor", world_frame="map")
    assert "--mount and --map need the world frame" in refused(
        frame="sensor", mount=["mir100"], map_path=Path("map.yaml")
    )
    # what each transport and frame uses is taken
    check_live_options("rmw", "", 5, "none", "world", "map", ["mir100"], Path("map.yaml"))
    check_live_options("bridge", "/robot1/", 0, "rihs01", "sensor", None, [], None)


@pytest.mark.slow
def test_live_says_a_leg_model_a_tracker_of_points_never_used(model: Path, tmp_path: Path) -> None:
    pytest.importorskip("zenoh")
    from laserpeople.io import open_recording
    from laserpeople.sim.scenarios import run_scenario
    from live_harness import free_port, play_when_subscribed

    bag = tmp_path / "walk.bag"
    run_scenario("demo", seconds=2.0, seed=3).write(bag)
    with open_recording(bag) as rec:
        topic, n = rec.topics()[0].name, rec.topics()[0].count
    port = free_port()

    player = play_when_subscribed(bag, topic, port)
    args = ["live", "--topic", topic, "--listen", f"tcp/127.0.0.1:{port}", "--frame", "sensor"]
    args += ["--tracker", "feet-pf", "--model", str(model)]
    args += ["--queue", "100000", "--max-scans", str(n), "--duration", "120"]
    result = CliRunner().invoke(app, args)
    player.join(30)
    assert result.exit_code == 0, result.output
    assert f"--model {model} had no effect: feet-pf tracks foreground points" in result.output


def test_a_topic_given_twice_is_said_and_read_once(
    capsys: pytest.CaptureFixture[str],
) -> None:
    from laserpeople.cli.track import topics_from

    assert topics_from(["/a", "/b", "/a"], None) == ["/a", "/b"]
    assert "--topic /a given more than once: read once" in capsys.readouterr().err
    assert topics_from(["/a", "/b"], None) == ["/a", "/b"]
    assert capsys.readouterr().err == ""
    assert topics_from(None, None) is None


def test_view_of_a_scan_outside_the_window_names_the_scans_it_holds(
    still: Path, tmp_path: Path
) -> None:
    from laserpeople.errors import LaserPeopleError

    out = str(tmp_path / "v.png")
    for args, held in (
        (["--scan", "500"], "it holds scans 0-40"),
        (["--scan", "30", "--stop", "20"], "it holds scans 0-19"),
        (["--scan", "5", "--start", "20"], "it holds scans 20-40"),
    ):
        run = CliRunner().invoke(app, ["view", str(still), "-o", out, *args])
        assert isinstance(run.exception, LaserPeopleError), run.output
        assert f"is not in the recording window ({held})" in str(run.exception)


def test_live_says_a_background_its_run_never_used(
    still: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from types import SimpleNamespace

    from laserpeople.cli.live import _unused_options
    from laserpeople.pipeline.recording import build

    def session(background: str) -> SimpleNamespace:
        pipe = build(still, tracker="leg-mht", background=background)
        for _ in pipe:
            pass
        return SimpleNamespace(
            run=SimpleNamespace(pipeline=pipe),
            scans=SimpleNamespace(counts=SimpleNamespace(resets=0)),
        )

    _unused_options(session("none"), "leg-mht", [], "histogram")
    said = capsys.readouterr().err
    assert "--background histogram had no effect: leg-mht with the arras people policy" in said
    _unused_options(session("histogram"), "leg-mht", [], "histogram")
    assert "had no effect" not in capsys.readouterr().err


def test_evaluate_says_when_a_batch_scored_a_recording_laser_by_laser(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A batch folder's rows of one recording tracked per laser are each scored against
    every labelled person: said once per recording, with its lasers; one laser, fused
    rows (topic None) and two recordings with one laser each are not."""
    from laserpeople.cli.evaluate import shared_truth_note

    truth = tmp_path / "scene.npz"
    truth.write_bytes(b"")
    other = tmp_path / "other.npz"
    other.write_bytes(b"")
    csv = tmp_path / "t.csv"
    shared_truth_note(
        [
            ("scene /front", csv, str(truth), "/front"),
            ("scene /rear", csv, str(truth), "/rear"),
            ("other /front", csv, str(other), "/front"),
            ("fused", csv, str(other), None),
        ]
    )
    err = capsys.readouterr().err
    assert err.count("laser by laser") == 1
    assert "scene was tracked laser by laser (/front, /rear)" in err
    assert "track it fused (`batch --topics all`)" in err
    shared_truth_note([("scene /front", csv, str(truth), "/front")])
    assert "laser by laser" not in capsys.readouterr().err
