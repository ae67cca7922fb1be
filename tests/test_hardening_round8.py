"""What a demanding user meets, eighth round: the Python API given the wrong types or an
output that is its input, a tracks CSV rewritten by a run that fails at once, duplicate
rows of one track, foreign manifest lines, an unreachable scheduler."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from laserpeople.errors import ConfigError, RecordingError, ScanFormatError
from laserpeople.scan import Pose2D, Scan


@pytest.fixture(scope="module")
def walk(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A short simulated recording with ground truth (.npz)."""
    from laserpeople.sim.scenarios import run_scenario

    path = tmp_path_factory.mktemp("walk") / "walk.npz"
    run_scenario("figure-eight", seconds=1.0, seed=3).write(path)
    return path


@pytest.fixture(scope="module")
def tracks_csv(walk: Path) -> Path:
    """The tracks CSV of ``walk``."""
    from laserpeople.pipeline import build

    out = walk.with_name("tracks.csv")
    build(walk, outputs=[out]).run()
    return out


def test_build_refuses_an_output_that_is_the_recording(walk: Path, tmp_path: Path) -> None:
    """``build("run.mcap", outputs=["run.mcap"])`` replaced the recording with the tracks
    bag written from it."""
    from laserpeople.pipeline import build

    bag = tmp_path / "run.mcap"
    build(walk, outputs=[bag]).run()
    before = bag.read_bytes()
    with pytest.raises(ConfigError, match=r"outputs\[1\] .*run\.mcap would write over the input"):
        build(bag, outputs=[tmp_path / "other.csv", str(bag)])
    assert bag.read_bytes() == before


@pytest.mark.parametrize(
    ("call", "says"),
    [
        ("open_recording", r"open_recording\(\): path must be a file path .*got int 5"),
        ("iter_tracks_csv", r"iter_tracks_csv\(\): path must be a file path .*got int 5"),
        ("read_tracks_file", r"read_tracks_file\(\): path must be a file path .*got int 5"),
        ("read_truth_csv", r"read_truth_csv\(\): path must be a file path .*got int 5"),
        ("build", r"build\(\): recording must be a file path .*got int 5"),
    ],
)
def test_a_path_of_the_wrong_type_is_named(call: str, says: str) -> None:
    from laserpeople.io import open_recording
    from laserpeople.io.tracks_csv import iter_tracks_csv
    from laserpeople.io.tracks_files import read_tracks_file
    from laserpeople.io.truth_csv import read_truth_csv
    from laserpeople.pipeline import build

    function = {
        "open_recording": open_recording,
        "iter_tracks_csv": iter_tracks_csv,
        "read_tracks_file": read_tracks_file,
        "read_truth_csv": read_truth_csv,
        "build": build,
    }[call]
    with pytest.raises(TypeError, match=says):
        function(5)  # type: ignore[operator]


def test_tracks_readers_name_a_wrong_frame_or_kinds_at_the_call(tracks_csv: Path) -> None:
    """``kinds="person"`` was taken letter by letter (``"leg" in "person"``), a frame
    ``"map"`` as world: both silently."""
    from laserpeople.io.tracks_csv import iter_tracks_csv
    from laserpeople.io.tracks_files import read_tracks_file

    with pytest.raises(TypeError, match=r"kinds must be a tuple of kinds .*got str 'person'"):
        read_tracks_file(tracks_csv, kinds="person")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"unknown kind\(s\) 'people'"):
        iter_tracks_csv(tracks_csv, kinds=("people",))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"frame must be 'world' or 'sensor', got 'map'"):
        iter_tracks_csv(tracks_csv, frame="map")  # type: ignore[arg-type]
    assert list(read_tracks_file(tracks_csv, kinds=("person",)))


def test_evaluate_names_paths_swapped_arguments_and_dict_params(
    walk: Path, tracks_csv: Path
) -> None:
    from laserpeople.evaluation.report import evaluate
    from laserpeople.io import open_recording
    from laserpeople.io.tracks_files import read_tracks_file

    with open_recording(walk) as recording:  # type: ignore[attr-defined]
        truth = list(recording.truth())
    tracks = list(read_tracks_file(tracks_csv))
    with pytest.raises(TypeError, match=r"truth_frames must be .*got the path .*read_truth_csv"):
        evaluate(str(walk), tracks)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"tracks must be .*got the path .*read_tracks_file"):
        evaluate(truth, tracks_csv)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"got an item of type \w+ \(are .* swapped\?\)"):
        evaluate(tracks, truth)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"params must be an EvaluationParams or None, got dict"):
        evaluate(truth, tracks, {"max_distance": 1.0})  # type: ignore[arg-type]
    assert evaluate(truth, tracks).result().clear_mot.num_frames == len(truth)


RANGES = np.linspace(1.0, 2.0, 5)


@pytest.mark.parametrize(
    ("fields", "error", "says"),
    [
        ({"ranges": None}, TypeError, r"ranges must be an array of real numbers.*NoneType"),
        ({"ranges": ["a", "b"]}, TypeError, r"ranges must be an array .*<U1"),
        ({"ranges": RANGES + 1j}, TypeError, r"ranges must be an array .*complex128"),
        ({"ranges": np.ones((2, 3))}, ScanFormatError, r"ranges must be one-dimensional"),
        ({"intensities": ["x"] * 5}, TypeError, r"intensities must be an array"),
        ({"angle_min": "-1"}, TypeError, r"angle_min must be a real number, got str '-1'"),
        ({"angle_min": np.zeros(2)}, TypeError, r"angle_min must be a real number, got ndarray"),
        ({"stamp": None}, TypeError, r"stamp must be a real number, got NoneType"),
        ({"range_max": None}, TypeError, r"range_max must be a real number, got NoneType"),
        ({"range_min": "0"}, TypeError, r"range_min must be a real number, got str"),
        ({"pose": (1.0, 2.0, 0.0)}, TypeError, r"pose must be a Pose2D or None, got tuple"),
    ],
)
def test_a_scan_field_of_the_wrong_type_is_named(
    fields: dict[str, object], error: type[Exception], says: str
) -> None:
    """Complex ranges lost their imaginary part with a warning; the others raised numpy's
    or math's words without the field."""
    given: dict[str, object] = {
        "stamp": 1.0,
        "angle_min": -1.0,
        "angle_increment": 0.01,
        "ranges": RANGES,
        **fields,
    }
    with pytest.raises(error, match=says):
        Scan(**given)  # type: ignore[arg-type]


def test_scan_fields_of_other_numeric_types_are_still_taken() -> None:
    scan = Scan(
        np.float32(1.0),  # type: ignore[arg-type]
        -1,
        np.float64(0.01),  # type: ignore[arg-type]
        [1, 2, 3],  # type: ignore[arg-type]
        intensities=np.arange(3, dtype=np.int32),  # type: ignore[arg-type]
        pose=Pose2D(1.0, 0.0, 0.0),
    )
    assert scan.ranges.dtype == np.float64 and scan.intensities is not None
    assert scan.intensities.dtype == np.float64
    np.testing.assert_allclose(scan.points("world")[0], [1.0 + np.cos(-1.0), np.sin(-1.0)])


OLD_TRACKS = "scan,stamp,track_id,kind,x,y\n0,0.000000,1,person,1.0,2.0\n"
BAD_FIRST_SCAN = "FLASER 3 1.0 nan\nFLASER 3 1.0 2.0 3.0 0 0 0 0 0 0 1.0 host 1.0\n"
"""A CARMEN log whose first scan is damaged: the run stops before any scan."""


@pytest.mark.parametrize(("command", "what"), [("track", "tracks"), ("detect", "detections")])
def test_a_run_failing_before_any_scan_leaves_the_old_csv_and_says_so(
    command: str, what: str, tmp_path: Path
) -> None:
    """The old CSV was emptied (to a header) when the writer opened it, before the
    recording's first scan failed to read."""
    from typer.testing import CliRunner

    from laserpeople.cli import app

    log = tmp_path / "bad.log"
    log.write_text(BAD_FIRST_SCAN)
    old = tmp_path / "old.csv"
    old.write_text(OLD_TRACKS)
    run = CliRunner().invoke(app, [command, str(log), "-o", str(old)])
    assert run.exit_code == 1 and isinstance(run.exception, RecordingError), run.output
    text = str(run.exception)
    assert "line 1: FLASER" in text
    assert f"the {what} CSV {old} was left as it was (no scan was written)" in text, text
    assert old.read_text() == OLD_TRACKS
    new = tmp_path / "new.csv"
    run = CliRunner().invoke(app, [command, str(log), "-o", str(new)])
    assert f"no {what} CSV was written (no scan was)" in str(run.exception)
    assert not new.exists()


def test_the_tracks_writer_empties_an_old_file_at_the_first_scan_or_a_good_close(
    tmp_path: Path,
) -> None:
    from laserpeople.io.tracks_csv import TracksCsvWriter, iter_tracks_csv
    from laserpeople.tracks import Tracks

    old = tmp_path / "old.csv"
    old.write_text(OLD_TRACKS)
    with pytest.raises(RuntimeError), TracksCsvWriter(old):
        assert old.read_text() == OLD_TRACKS  # opened, not yet emptied
        raise RuntimeError("the run failed")
    assert old.read_text() == OLD_TRACKS
    TracksCsvWriter(old).close()  # a run of no scan that ended well: its own, empty CSV
    assert old.read_text().splitlines() == [old.read_text().splitlines()[0]]
    assert list(iter_tracks_csv(old)) == []
    old.write_text(OLD_TRACKS)
    with pytest.raises(RuntimeError), TracksCsvWriter(old) as out:
        out.write(Tracks(0.5, 4, (), "world"))
        raise RuntimeError("the run failed after a scan")
    assert "person" not in old.read_text() and old.read_text().startswith("scan,stamp")


def test_two_rows_of_one_track_in_one_scan_are_an_error_naming_the_lines(
    tmp_path: Path,
) -> None:
    """The second row of person 3 in scan 1 made a second person 3 that evaluate scored
    as a false positive (or matched in the first's place)."""
    from laserpeople.errors import RecordingError
    from laserpeople.io.tracks_csv import iter_tracks_csv

    path = tmp_path / "dup.csv"
    path.write_text(
        "scan,stamp,track_id,kind,x,y\n"
        "0,0.0,3,person,1.0,2.0\n"
        "1,0.1,3,person,1.0,2.0\n"
        "1,0.1,3,leg,1.1,2.0\n"
        "1,0.1,4,person,3.0,2.0\n"
        "1,0.1,3,person,1.2,2.1\n"
    )
    with pytest.raises(
        RecordingError, match=r"scan 1: lines 3 and 6: person track 3 has two rows in scan 1"
    ):
        list(iter_tracks_csv(path, kinds=("leg",)))
    path.write_text("scan,stamp,track_id,kind,x,y\n0,0.0,3,person,1,2\n1,0.1,3,person,1,2\n")
    assert [len(t.tracks) for t in iter_tracks_csv(path)] == [1, 1]


def _entry(name: str) -> str:
    import json

    row = {"name": name}
    return json.dumps(
        {"version": 1, "name": name, "input_hash": "h", "config_hash": "c", "rows": [row]}
    )


def test_foreign_manifest_lines_are_named_kept_and_a_cut_off_line_is_ended(
    tmp_path: Path,
) -> None:
    """A note, a line of another tool or a JSON object without our keys in the middle of
    manifest.jsonl was taken as a torn line (or as the recording "None") without a word,
    and the rewrite at the end of the run dropped it."""
    from laserpeople.batch.manifest import Manifest
    from laserpeople.errors import LaserPeopleWarning

    path = tmp_path / "manifest.jsonl"
    path.write_text(
        f'{_entry("a")}\n# rerun after the disk was changed\n{{"job": 7}}\n{_entry("b")}\n'
        '{"version": 1, "name": "c", "inp'  # cut off by a kill: no warning
    )
    with pytest.warns(LaserPeopleWarning, match=r"manifest.jsonl: lines 2, 3 are no entry"):
        manifest = Manifest(tmp_path)
    assert set(manifest.entries) == {"a", "b"} and manifest.torn == 1
    manifest.record("d", "h", "c", [])
    manifest.record("e", "h", "c", [])
    with pytest.warns(LaserPeopleWarning, match=r"lines 2, 3 are no entry"):
        again = Manifest(tmp_path)  # the cut-off line stays one: "d" was not glued to it
    assert set(again.entries) == {"a", "b", "d", "e"} and again.torn == 1
    again.compact()
    lines = path.read_text().splitlines()
    assert lines[-2:] == ["# rerun after the disk was changed", '{"job": 7}'], lines
    assert len(lines) == 6


def test_an_unreachable_scheduler_is_a_clear_error(tmp_path: Path) -> None:
    """Dask's traceback (an OSError after 20 s, or a ValueError for an address without
    a port) came out of ``batch --scheduler``."""
    pytest.importorskip("dask.distributed")
    from typer.testing import CliRunner

    from laserpeople.batch.run import ClusterSpec, open_client
    from laserpeople.cli import app

    with (
        pytest.raises(ConfigError, match=r"cannot reach the Dask scheduler 'tcp://127.0.0.1:9'"),
        open_client(ClusterSpec(scheduler="tcp://127.0.0.1:9", connect_timeout=0.5)),
    ):
        pass
    recording = tmp_path / "r.npz"
    recording.write_bytes(b"")
    run = CliRunner().invoke(
        app, ["batch", str(recording), "--out", str(tmp_path / "o"), "--scheduler", "nowhere"]
    )
    assert isinstance(run.exception, ConfigError), run.output
    assert "cannot reach the Dask scheduler 'nowhere': missing port" in str(run.exception)
    assert "drop --scheduler" in str(run.exception)


def _json_mcap(path: Path, profile: str = "") -> None:
    """An MCAP of JSON messages (as Foxglove's own tools write), no ROS schema."""
    import json
    import struct

    def text(value: str) -> bytes:
        return struct.pack("<I", len(value)) + value.encode()

    def record(op: int, body: bytes) -> bytes:
        return struct.pack("<BQ", op, len(body)) + body

    magic = b"\x89MCAP0\r\n"
    data = magic + record(1, text(profile) + text("test"))
    data += record(3, struct.pack("<H", 1) + text("Point") + text("jsonschema") + text("{}"))
    data += record(4, struct.pack("<HH", 1, 1) + text("/points") + text("json") + bytes(4))
    for i in range(3):
        stamp = i * 10**8
        body = struct.pack("<HIQQ", 1, i, stamp, stamp) + json.dumps({"x": i}).encode()
        data += record(5, body)
    data += record(0x0F, bytes(4)) + record(2, bytes(20)) + magic
    path.write_bytes(data)


@pytest.mark.parametrize("command", ["info", "track", "evaluate-truth", "evaluate-tracks"])
def test_an_mcap_of_no_ros_messages_is_said_so(command: str, tmp_path: Path) -> None:
    """rosbags' "Profile is not ros2." came out as a corrupt or truncated bag."""
    from typer.testing import CliRunner

    from laserpeople.cli import app

    mcap = tmp_path / "points.mcap"
    _json_mcap(mcap)
    args = {
        "info": ["info", str(mcap)],
        "track": ["track", str(mcap), "-o", str(tmp_path / "t.csv")],
        "evaluate-truth": ["evaluate", str(tmp_path / "t.csv"), "--truth", str(mcap)],
        "evaluate-tracks": ["evaluate", str(mcap), "--truth", str(tmp_path / "x.npz")],
    }[command]
    (tmp_path / "t.csv").write_text(OLD_TRACKS)
    from laserpeople.sim.scenarios import run_scenario

    run_scenario("figure-eight", seconds=0.5, seed=3).write(tmp_path / "x.npz")
    run = CliRunner().invoke(app, args)
    assert isinstance(run.exception, RecordingError), run.output
    text = str(run.exception)
    assert f"{mcap}: an MCAP of no ROS messages (profile ''; schemas in jsonschema)" in text
    assert "corrupt" not in text and "ros2 bag record" in text


def test_evaluate_and_view_given_a_foxglove_export_are_told_what_to_give(
    walk: Path, tracks_csv: Path, tmp_path: Path
) -> None:
    """The export of ``view -o x.mcap`` draws tracks as MarkerArrays: read as tracks it
    failed with "'...MarkerArray' object has no attribute 'header'", as truth with a list
    of its topics."""
    from typer.testing import CliRunner

    from laserpeople.cli import app

    export = tmp_path / "drawn.mcap"
    run = CliRunner().invoke(
        app, ["view", str(walk), "--tracks", str(tracks_csv), "-o", str(export)]
    )
    assert run.exit_code == 0, run.output
    run = CliRunner().invoke(app, ["evaluate", str(export), "--truth", str(walk)])
    text = str(run.exception)
    assert "carries visualization_msgs/msg/MarkerArray, not people_msgs/msg/People" in text
    assert "a Foxglove export of `laserpeople view -o FILE.mcap`" in text
    assert "give the tracks CSV it was drawn from" in text
    run = CliRunner().invoke(
        app, ["view", str(walk), "--tracks", str(export), "-o", str(tmp_path / "v.png")]
    )
    assert "give the tracks CSV it was drawn from" in str(run.exception)
    run = CliRunner().invoke(app, ["evaluate", str(tracks_csv), "--truth", str(export)])
    text = str(run.exception)
    assert "it is a Foxglove export of `laserpeople view -o FILE.mcap`" in text, text
    assert "give the recording or the truth CSV it was drawn from" in text
    run = CliRunner().invoke(app, ["info", str(export)])
    assert "tracks drawn for Foxglove (laserpeople view): /laserpeople/legs" in run.output
    assert "tracks of laserpeople track --bag" not in run.output


MIR_BAG = "mir/rosbags/mir_data/legs-test-split-2022-11-21-15-51-02-topic-split.bag"


@pytest.mark.parametrize(
    "args",
    [
        ["track", "-o", "{out}.csv", "--output-frame", "world"],
        ["track", "-o", "{out}.csv", "--topics", "all"],
        ["view", "-o", "{out}.png", "--frame", "world"],
    ],
)
def test_missing_laser_mounts_are_named_with_what_to_do(
    args: list[str], shared_data: Path, tmp_path: Path
) -> None:
    """The MiR bag's /tf has odom -> base_footprint only: the error said "the scan has no
    sensor pose" without which frames were not linked or that ``--mount mir100`` links
    them (``info`` said it; the commands that need the poses did not)."""
    from typer.testing import CliRunner

    from laserpeople.cli import app

    bag = shared_data / MIR_BAG
    given = [a.format(out=tmp_path / "out") for a in args]
    run = CliRunner().invoke(app, [given[0], str(bag), *given[1:]])
    assert isinstance(run.exception, RecordingError | ConfigError), run.output
    text = str(run.exception)
    assert "/tf links no laser frame " in text and "'front_laser_link'" in text, text
    assert "to 'odom' (transforms in the recording: odom -> base_footprint)" in text
    assert "try --mount mir100" in text


def test_train_refuses_to_write_over_a_file_of_its_neko_folder(
    shared_data: Path, tmp_path: Path
) -> None:
    """``-o NEKO/leg_segment_labels.json`` replaced the labels it trained on (the folder
    was an input, its files were not)."""
    import shutil

    from typer.testing import CliRunner

    from laserpeople.cli import app

    neko = tmp_path / "neko"
    shutil.copytree(shared_data / "neko7055", neko)
    labels = (neko / "leg_segment_labels.json").read_bytes()
    out = neko / "leg_segment_labels.json"
    run = CliRunner().invoke(
        app, ["train", "--neko", str(neko), "--neko-frames", "0-9", "-o", str(out)]
    )
    assert isinstance(run.exception, ConfigError), run.output
    assert f"-o {out} would write over the input {out}" in str(run.exception)
    assert out.read_bytes() == labels


def test_evaluate_refuses_a_laser_topic_nothing_reads(
    walk: Path, tracks_csv: Path, tmp_path: Path
) -> None:
    """``--laser-topic`` pairs a bag's truth topic with a laser; given with a recording's
    own truth (or for several tracks files) it was ignored without a word."""
    from typer.testing import CliRunner

    from laserpeople.cli import app

    run = CliRunner().invoke(
        app, ["evaluate", str(tracks_csv), "--truth", str(walk), "--laser-topic", "/scan"]
    )
    assert isinstance(run.exception, ConfigError), run.output
    assert "--laser-topic applies to ground truth from a bag (--truth BAG[:TOPIC])" in str(
        run.exception
    )
    other = tmp_path / "other.csv"
    other.write_bytes(tracks_csv.read_bytes())
    run = CliRunner().invoke(
        app,
        ["evaluate", str(tracks_csv), str(other), "--truth", str(walk), "--truth", str(walk),
         "--laser-topic", "/scan"],
    )  # fmt: skip
    assert isinstance(run.exception, ConfigError), run.output
    assert "--laser-topic applies to one TRACKS file" in str(run.exception)
    run = CliRunner().invoke(app, ["evaluate", str(tracks_csv), "--truth", str(walk)])
    assert run.exit_code == 0, run.output


def test_a_ros2_bag_folder_without_its_storage_file_is_said_so(tmp_path: Path) -> None:
    """rosbags' "Some database files are missing" came out as a corrupt or truncated bag
    (with a hint for ROS 1 bags)."""
    rosbag2 = pytest.importorskip("rosbags.rosbag2")
    from rosbags.typesys import Stores, get_typestore

    from laserpeople.io import open_recording

    store = get_typestore(Stores.LATEST)
    folder = tmp_path / "run"
    text = store.types["std_msgs/msg/String"]
    with rosbag2.Writer(folder, version=8) as writer:
        conn = writer.add_connection("/chatter", text.__msgtype__, typestore=store)
        writer.write(conn, 1, store.serialize_cdr(text(data="x"), text.__msgtype__))
    (folder / "run.db3").unlink()
    with pytest.raises(
        RecordingError,
        match=r"run: metadata.yaml names the storage file run.db3, not in the folder "
        r"\(it holds no .db3 or .mcap file\) \(copy the whole bag folder",
    ):
        open_recording(folder)
    (folder / "renamed.db3").write_bytes(b"")
    with pytest.raises(RecordingError, match=r"\(it holds renamed.db3\).*or give .*renamed.db3"):
        open_recording(folder)


def test_a_misspelt_name_in_another_trackers_section_is_named(walk: Path, tmp_path: Path) -> None:
    """One ``--config`` serves every tracker; ``[csa] subcluster_distanse`` was only said
    to be "read by another tracker" by ``track --tracker leg-mht``, and the typo went
    unnoticed until the csa run."""
    from typer.testing import CliRunner

    from laserpeople.cli import app

    config = tmp_path / "shared.toml"
    config.write_text("[leg_tracker]\nlambda_new = 0.002\n\n[csa]\nsubcluster_distanse = 0.5\n")
    args = ["track", str(walk), "-o", str(tmp_path / "t.csv"), "--config", str(config)]
    run = CliRunner().invoke(app, args)
    assert isinstance(run.exception, ConfigError), run.output
    text = str(run.exception)
    assert f"{config}: line 5: unknown parameter(s) subcluster_distanse in [csa]" in text, text
    assert "did you mean 'subcluster_distance'?" in text
    assert "a section another command or tracker reads" in text
    config.write_text("[leg_tracker]\nlambda_new = 0.002\n\n[csa]\nsubcluster_distance = 0.5\n")
    run = CliRunner().invoke(app, args)
    assert run.exit_code == 0, run.output
    assert "[csa] is read by another command or tracker" in run.output


@pytest.mark.parametrize("pattern", ["leg_tracker.lambda_*", "[leg_tracker] lambda_new"])
def test_fit_learn_takes_the_keys_with_the_trackers_section(pattern: str) -> None:
    """The TOML fit writes names the keys under [leg_tracker]; ``--learn
    leg_tracker.lambda_new`` matched no key."""
    from laserpeople.fitting.estimates import Estimate
    from laserpeople.fitting.flow import _select
    from laserpeople.tracking.legs import LegTrackerParams

    learned = [Estimate("lambda_new", 0.01, "5 new", 9), Estimate("p_det_free", 0.8, "x", 9)]
    chosen, left, params = _select([pattern], learned, [], LegTrackerParams())
    assert [e.key for e in chosen] == ["lambda_new"]
    assert left == (("p_det_free", "not chosen by --learn"),)
    assert params.lambda_new == pytest.approx(0.01, rel=1e-12)


def test_fit_learn_with_another_section_is_named() -> None:
    from laserpeople.errors import LaserPeopleError
    from laserpeople.fitting.estimates import Estimate
    from laserpeople.fitting.flow import _select
    from laserpeople.tracking.legs import LegTrackerParams

    learned = [Estimate("lambda_new", 0.01, "5 new", 9)]
    with pytest.raises(
        LaserPeopleError, match=r"names the section \[csa\], not the tracker's \[leg_tracker\]"
    ):
        _select(["[csa] lambda_new"], learned, [], LegTrackerParams())


def _one_scan(stamp: float = 0.0, index: int = 0) -> Scan:
    return Scan(stamp, -1.0, 0.01, np.ones(5), index=index)


@pytest.mark.parametrize(
    ("call", "says"),
    [
        ("laser_frames(scan)", r"laser_frames\(\): scans must be an iterable of Scan, got one "),
        ("laser_frames('run.bag')", r"laser_frames\(\): .*the path 'run\.bag': read its scans"),
        ("laser_frames(5)", r"laser_frames\(\): scans must be an iterable of Scan, got int 5"),
        ("list(laser_frames([scan, 3]))", r"got an item of type int \(item 1\)"),
        ("list(laser_frames([frame]))", r"type Frame \(item 0\): it takes scans, not frames"),
        ("LaserGrouper(['a', 'b'])(scan)", r"LaserGrouper\(\): scans must be an iterable"),
        ("list(FrameChooser()([scan]))", r"FrameChooser\(\): frames .*make frames of the scans"),
        ("FrameChooser()(frame)", r"FrameChooser\(\): .*got one Frame: give a list of it"),
    ],
)
def test_sources_given_one_scan_or_the_wrong_items_name_what_they_take(
    call: str, says: str
) -> None:
    """``laser_frames(scan)`` raised ``'Scan' object is not iterable`` only when the
    pipeline pulled its first frame; ``FrameChooser()(scans)`` that a Scan has no
    attribute ``scans``."""
    from laserpeople.pipeline import FrameChooser, LaserGrouper, laser_frames

    scan = _one_scan()
    frame = next(iter(laser_frames([scan])))
    names = {"laser_frames": laser_frames, "LaserGrouper": LaserGrouper}
    names |= {"FrameChooser": FrameChooser, "scan": scan, "frame": frame}
    with pytest.raises(TypeError, match=says):
        eval(call, names)
    frames = list(FrameChooser()(laser_frames(iter([scan, _one_scan(0.1, 1)]))))
    assert [f.index for f in frames] == [0, 1]


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (["simulate", "crossing"], "did you mean 'crossing-3', "),
        (["simulate", "entr"], "did you mean 'entrance-hall' or 'entrance-hall-moving'?"),
        (["simulate", "figure"], "did you mean 'figure-eight'?"),
        (["track", "{walk}", "--tracker", "upper"], "did you mean 'upper-body-pf'?"),
        (["track", "{walk}", "--preset", "pap"], "did you mean 'paper'?"),
        (["track", "{walk}", "--topic", "/las"], "no topic '/las'; did you mean 'laser'?"),
    ],
)
def test_the_start_of_a_known_name_is_suggested(
    args: list[str], says: str, walk: Path, tmp_path: Path
) -> None:
    """``simulate crossing`` offered feet-crossing, crossing-3-swap and crossing-3-twice
    (the first three of the list that start or end with it), not crossing-3; ``pap`` (a
    start not ending at a ``-``) and a topic's start offered nothing."""
    from typer.testing import CliRunner

    from laserpeople.cli import app

    given = [a.format(walk=walk) for a in args] + ["-o", str(tmp_path / "out.npz")]
    if given[0] == "track":
        given[-1] = str(tmp_path / "out.csv")
    run = CliRunner().invoke(app, given)
    assert run.exit_code != 0
    assert says in " ".join(f"{run.output} {run.exception}".split()), run.output


def test_names_a_start_suggests_shortest_first_and_short_starts_suggest_nothing() -> None:
    from laserpeople.spelling import closest

    known = ["feet-crossing", "crossing-3-swap", "crossing-3-twice", "crossing-3"]
    assert closest("crossing", known) == ["crossing-3", "feet-crossing", "crossing-3-swap"]
    assert closest("Entr", ["office", "entrance-hall"]) == ["entrance-hall"]
    assert closest("of", ["office"]) == []  # two letters start too many names
    assert closest("/sca", ["/scan_front", "odom"], key=lambda n: n.lstrip("/")) == ["/scan_front"]


def _ctrl_c_at_once(items: object, total: object = None, description: str = "") -> object:
    """A stand-in for the commands' ``progress``: Ctrl-C before the first scan."""
    raise KeyboardInterrupt
    yield  # (a generator, as progress is)


@pytest.mark.parametrize(
    ("command", "what", "extra"),
    [
        ("track", "tracks", []),
        ("detect", "detections", []),
        ("detect", "detections", ["--all-segments"]),
    ],
)
def test_ctrl_c_before_the_first_scan_leaves_the_old_csv_and_says_so(
    command: str,
    what: str,
    extra: list[str],
    walk: Path,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The old CSV was emptied to a header, and the command said it "holds the tracks of
    those scans" after 0 scans."""
    from typer.testing import CliRunner

    from laserpeople.cli import app, detect, track

    monkeypatch.setattr(track if command == "track" else detect, "progress", _ctrl_c_at_once)
    old = tmp_path / "old.csv"
    old.write_text(OLD_TRACKS)
    run = CliRunner().invoke(app, [command, str(walk), "-o", str(old), *extra])
    said = " ".join(run.output.split())
    assert run.exit_code == 130, run.output
    assert "interrupted (Ctrl-C) before the first scan" in said, said
    assert f"the {what} CSV {old} was left as it was (no scan was written)" in said, said
    assert "holds" not in said
    assert old.read_text() == OLD_TRACKS
    new = tmp_path / "new.csv"
    run = CliRunner().invoke(app, [command, str(walk), "-o", str(new), *extra])
    assert run.exit_code == 130 and not new.exists()
    assert f"no {what} CSV was written (no scan was)" in " ".join(run.output.split())


@pytest.mark.parametrize(
    ("index", "says"),
    [
        (3.0, r"got float 3\.0 \(a scan of run\.bag\): give int\(3\.0\)"),
        (3.5, r"index must be an integer, .*got float 3\.5 \(a scan of run\.bag\)$"),
        (True, r"index must be an integer, .*got bool True"),
        ("3", r"index must be an integer, .*got str '3'"),
        (None, r"index must be an integer, .*got NoneType None"),
    ],
)
def test_a_scan_index_that_is_no_integer_is_refused(index: object, says: str) -> None:
    """``Scan(..., index=3.5)`` was taken: the tracks CSV's scan column then read 3.5 and
    evaluate paired nothing with it."""
    with pytest.raises(TypeError, match=says):
        Scan(0.0, -1.0, 0.01, RANGES, index=index, source="run.bag")  # type: ignore[arg-type]


def test_a_scan_index_of_numpys_integers_is_taken_as_an_int() -> None:
    scan = Scan(0.0, -1.0, 0.01, RANGES, index=np.int64(7))  # type: ignore[arg-type]
    assert type(scan.index) is int and scan.index == 7


DEMO_BAG = "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag"


def test_a_misspelt_world_frame_is_named_not_the_mounts(shared_data: Path, tmp_path: Path) -> None:
    """``--world-frame odomm`` was answered with "the laser mounts are missing from /tf:
    try --mount mir100"; on a bag without /tf at all with "give them with --mount"."""
    from typer.testing import CliRunner

    from laserpeople.cli import app

    misspelt = "no transform of the recording names the world frame 'odomm': did you mean 'odom'?"
    run = CliRunner().invoke(app, ["info", str(shared_data / MIR_BAG), "--world-frame", "odomm"])
    said = " ".join(run.output.split())
    assert run.exit_code == 0 and misspelt in said and "--mount" not in said, said
    out = tmp_path / "t.csv"
    args = ["--world-frame", "odomm", "--output-frame", "world", "-o", str(out)]
    run = CliRunner().invoke(app, ["track", str(shared_data / MIR_BAG), *args])
    assert isinstance(run.exception, RecordingError) and misspelt in str(run.exception)
    run = CliRunner().invoke(app, ["info", str(shared_data / DEMO_BAG), "--world-frame", "map"])
    said = " ".join(run.output.split())
    assert "/scan: 1265 scans: no pose data (no /tf, /tf_static or odometry)" in said, said
    assert "mounts are missing" not in said


def test_a_world_frame_no_transform_names_is_said_misspelt(tmp_path: Path) -> None:
    """The same on a bag of /tf map -> odom -> base_link -> front_laser (no shared data)."""
    from laserpeople.io.rosbag import RosbagRecording
    from test_io_rosbag_tf import GAPS, _write

    bag = tmp_path / "tf.bag"
    _write(bag)
    with RosbagRecording(bag, world_frame="odomm", pose_params=GAPS) as rec:
        assert all(s.pose is None for s in rec.scans())
        summary, problem = rec.pose_summary(), rec.pose_problem()
    said = "no transform of the recording names the world frame 'odomm': did you mean 'odom'?"
    assert said in summary and problem is not None and said in problem
    assert "(its frames: base_link, front_laser, map, odom; check --world-frame)" in summary
    assert "mounts are missing" not in summary + problem


def test_demo_takes_its_folder_with_o_as_the_other_commands(tmp_path: Path) -> None:
    """``laserpeople demo -o out`` (every other command writes with -o) was "No such
    option: -o"."""
    from typer.testing import CliRunner

    from laserpeople.cli import app

    out = tmp_path / "out"
    run = CliRunner().invoke(app, ["demo", "-o", str(out), "--seconds", "0.3", "--no-gif"])
    assert run.exit_code == 0, run.output
    assert (out / "demo.npz").is_file() and (out / "demo-tracks.csv").is_file()


def test_view_with_stop_before_start_names_the_options(walk: Path, tmp_path: Path) -> None:
    """It said "empty scan window: start 10 >= stop 5", without the options or what to
    do."""
    from typer.testing import CliRunner

    from laserpeople.cli import app

    out = tmp_path / "v.png"
    args = ["view", str(walk), "-o", str(out), "--start", "10", "--stop", "5"]
    run = CliRunner().invoke(app, args)
    said = " ".join(f"{run.output} {run.exception}".split())
    assert "--start 10 --stop 5 draw no scan" in said and "give a --stop after" in said, said
    assert not out.exists()


@pytest.mark.parametrize("command", ["track", "detect"])
def test_a_recording_given_as_config_is_named(command: str, walk: Path, tmp_path: Path) -> None:
    """``--config run.bag`` said "not UTF-8 text (byte 70 is not UTF-8)"."""
    from typer.testing import CliRunner

    from laserpeople.cli import app

    bag = tmp_path / "run.bag"
    bag.write_bytes(b"#ROSBAG V2.0\n\xe9\xff" + bytes(64))
    run = CliRunner().invoke(
        app, [command, str(walk), "-o", str(tmp_path / "t.csv"), "--config", str(bag)]
    )
    assert isinstance(run.exception, ConfigError), run.output
    assert "run.bag: a .bag file, not a TOML config file" in str(run.exception)
    assert "--print-config" in str(run.exception)


@pytest.mark.parametrize("stop", ["ctrl-c", "damaged first scan"])
def test_a_run_stopped_before_the_first_scan_leaves_an_old_tracks_bag(
    stop: str, walk: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``track --bag out.mcap`` stopped before its first scan replaced an older bag with
    an empty one (712 bytes), silently."""
    from typer.testing import CliRunner

    from laserpeople.cli import app, track

    bag = tmp_path / "out.mcap"
    run = CliRunner().invoke(
        app, ["track", str(walk), "-o", str(tmp_path / "a.csv"), "--bag", str(bag)]
    )
    assert run.exit_code == 0, run.output
    before = bag.read_bytes()
    recording = walk
    if stop == "ctrl-c":
        monkeypatch.setattr(track, "progress", _ctrl_c_at_once)
    else:
        recording = tmp_path / "bad.log"
        recording.write_text(BAD_FIRST_SCAN)
    run = CliRunner().invoke(
        app, ["track", str(recording), "-o", str(tmp_path / "a.csv"), "--bag", str(bag)]
    )
    said = " ".join(f"{run.output} {run.exception}".split())
    assert f"the tracks bag {bag} was left as it was (no scan was written)" in said, said
    assert bag.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []
    new = tmp_path / "new.mcap"
    run = CliRunner().invoke(
        app, ["track", str(recording), "-o", str(tmp_path / "b.csv"), "--bag", str(new)]
    )
    assert "no tracks bag was written (no scan was)" in " ".join(
        f"{run.output} {run.exception}".split()
    )
    assert not new.exists()


def test_evaluate_given_the_recording_as_tracks_says_so(
    walk: Path, tracks_csv: Path, tmp_path: Path
) -> None:
    """``evaluate run.npz --truth tracks.csv`` said "not a text CSV: line 1 (byte 17) is
    not UTF-8"."""
    from typer.testing import CliRunner

    from laserpeople.cli import app
    from laserpeople.errors import EvaluationError

    run = CliRunner().invoke(app, ["evaluate", str(walk), "--truth", str(tracks_csv)])
    assert isinstance(run.exception, EvaluationError), run.output
    text = str(run.exception)
    assert "is a recording (.npz), not tracks: are TRACKS and --truth swapped?" in text, text
    assert f"laserpeople evaluate tracks.csv --truth {walk.name}" in text


@pytest.mark.parametrize("name", ["tracks.csv", "tracks.txt"])
def test_a_tracks_table_given_as_a_recording_says_what_it_is(
    name: str, tracks_csv: Path, tmp_path: Path
) -> None:
    """``info tracks.txt`` asked "is this a CARMEN log?"; ``info tracks.csv`` listed the
    recording formats without saying what a .csv is for."""
    from typer.testing import CliRunner

    from laserpeople.cli import app

    table = tmp_path / name
    table.write_bytes(tracks_csv.read_bytes())
    run = CliRunner().invoke(app, ["info", str(table)])
    assert isinstance(run.exception, RecordingError), run.output
    text = str(run.exception)
    assert "table" in text and "goes to `view --tracks` or `evaluate`" in text, text
    assert "CARMEN log?" not in text


def test_a_misspelt_mount_child_gets_the_laser_frame_meant() -> None:
    from laserpeople.io.poses import stray_mount_notes

    mounts = {"laserr": ("base_link", Pose2D()), "front_laser_link": ("base", Pose2D())}
    notes = stray_mount_notes(mounts, {"/scan": "laser"})
    assert len(notes) == 2
    assert "mount of 'laserr' not used: no laser's scans have that frame id and no " in notes[0]
    assert "transform names it (did you mean 'laser'?) (CHILD is" in notes[0]
    assert "did you mean" not in notes[1]


def test_one_topic_given_as_a_string_is_named(walk: Path) -> None:
    """``rec.scans("/scan")`` was read letter by letter: "no topic '/'"."""
    from laserpeople.io import open_recording

    with open_recording(walk) as rec, pytest.raises(TypeError, match=r"give \['laser'\]$"):
        next(rec.scans("laser"))  # type: ignore[arg-type]
    log = walk.with_name("one.log")
    log.write_text("FLASER 3 1.0 2.0 3.0 0 0 0 0 0 0 1.0 host 1.0\n")
    with open_recording(log) as rec:
        with pytest.raises(TypeError, match=r"topics must be a list of laser names .*'FLASER'"):
            next(rec.scans("FLASER"))  # type: ignore[arg-type]
        assert len(list(rec.scans(["FLASER"]))) == 1


@pytest.mark.parametrize("given", ["scans", "path", "scan"])
def test_a_pipeline_of_scans_is_told_to_make_frames(given: str, walk: Path) -> None:
    """``Pipeline(rec.scans())`` ran, each Scan taken for a frame, with no stage to notice."""
    from laserpeople.io import open_recording
    from laserpeople.pipeline import Pipeline

    with open_recording(walk) as rec:
        source = {"scans": rec.scans(), "path": str(walk), "scan": next(rec.scans())}[given]
        with pytest.raises(TypeError, match=r"Pipeline\(\): source must be an iterable of Fr"):
            list(Pipeline(source))  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (["simulate", "demo", "-s", "1", "-o", "{tmp}/d.nzp"], "'.nzp'; did you mean '.npz'?"),
        (["view", "{walk}", "-o", "{tmp}/v.pgn"], "'.pgn'; did you mean '.png'?"),
        (
            ["track", "{walk}", "-o", "{tmp}/t.csv", "--bag", "{tmp}/t.mcpa"],
            "'t.mcpa'; did you mean '.mcap'?",
        ),
    ],
)
def test_two_swapped_letters_are_suggested(
    args: list[str], says: str, walk: Path, tmp_path: Path
) -> None:
    """``-o v.pgn`` listed the kinds without the one meant: difflib rates a swap of two
    letters of a three-letter name 0.67, below the cutoff."""
    from typer.testing import CliRunner

    from laserpeople.cli import app
    from laserpeople.spelling import closest

    run = CliRunner().invoke(app, [a.format(walk=walk, tmp=tmp_path) for a in args])
    assert run.exit_code != 0
    said = " ".join(f"{run.output} {run.exception}".split())
    assert says in said, said
    assert closest("odmo", ["odom", "map"]) == ["odom"]
    assert closest("abc", ["cab", "bca"]) == []  # not two neighbours swapped
