"""The ten causes of bad endings of issue 36, each read from a small hostile file kept in
``tests/data/hostile/`` (``make_hostile.py`` there writes them).

Before the fixes each of these ended in a traceback (``OverflowError``, ``struct.error``,
``MemoryError``, ``DecompressionBombError``, ``_csv.Error`` ...), ran for ever, replaced an
input, or exited 0 with nothing. Now each ends in a :class:`LaserPeopleError` that names the
file (or the option) and the bound, or is counted as damage.
"""

from __future__ import annotations

import math
import shutil
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import (
    ConfigError,
    LaserPeopleError,
    RecordingError,
    ScanFormatError,
)
from laserpeople.io import open_recording

HOSTILE = Path(__file__).parent / "data" / "hostile"
sys.path.insert(0, str(HOSTILE))
import make_hostile  # type: ignore[import-not-found]  # noqa: E402  (writes the files)


def _read_all(path: Path, **options: Any) -> int:
    rec = open_recording(path, **options)
    try:
        return sum(1 for _ in rec.scans())
    finally:
        rec.close()


def _cli(*argv: str | Path) -> Any:
    return CliRunner().invoke(app, [str(a) for a in argv])


def _refused(run: Any, *words: str) -> str:
    """The run ended in one of our errors (no traceback) whose message holds ``words``."""
    assert run.exit_code != 0, run.output
    assert isinstance(run.exception, LaserPeopleError), repr(run.exception)
    message = str(run.exception)
    for word in words:
        assert word in message, message
    return message


@pytest.fixture
def truth(tmp_path: Path) -> Path:
    from laserpeople.io.truth_csv import write_truth_csv
    from laserpeople.truth import TruthFrame

    path = tmp_path / "truth.csv"
    frames = [
        TruthFrame.from_positions(10.0 + 0.1 * k, k, np.array([1]), np.array([[1.0, 0.0]]))
        for k in range(4)
    ]
    write_truth_csv(path, frames)
    return path


# -- 1. tracks bags ---------------------------------------------------------------------------


def test_a_whole_tracks_bag_reads(tmp_path: Path) -> None:
    from laserpeople.io.tracks_bag import iter_tracks_bag

    for suffix in (".mcap", ".db3", ".bag"):
        path = tmp_path / f"tracks{suffix}"
        make_hostile.tracks_bag(path)
        frames = list(iter_tracks_bag(path))
        assert [f.scan_index for f in frames] == [0, 1, 2, 3]
        assert all(len(f) == 2 for f in frames)


@pytest.mark.parametrize(
    ("name", "says"),
    [
        ("tracks_truncated.mcap", "File end magic is invalid"),
        ("tracks_malformed.db3", "malformed"),
        ("tracks_chunk_length.bag", "struct.error"),
    ],
)
def test_cause_1_damaged_tracks_bags(name: str, says: str, truth: Path) -> None:
    from laserpeople.io.tracks_bag import iter_tracks_bag

    with pytest.raises(RecordingError, match=name.replace(".", r"\.")) as err:
        list(iter_tracks_bag(HOSTILE / name))
    assert says in str(err.value) and "laserpeople track --bag" in str(err.value)
    _refused(_cli("evaluate", HOSTILE / name, "--truth", truth), name, says)


def test_cause_1_a_person_with_a_huge_scan_tag(tmp_path: Path) -> None:
    from laserpeople.io.rosbag_writer import open_bag
    from laserpeople.io.tracks_bag import (
        PEOPLE_TYPE,
        TRACK_TOPICS,
        build_message,
        iter_tracks_bag,
        register_people_types,
    )

    path = tmp_path / "tags.mcap"
    with open_bag(path) as sink:
        register_people_types(sink.typestore)
        person = build_message(
            sink.typestore,
            "people_msgs/msg/Person",
            name="1",
            tagnames=["kind", "scan"],
            tags=["person", "9" * 30],
        )
        msg = build_message(
            sink.typestore, PEOPLE_TYPE, header=sink.header(1.0, "world"), people=[person]
        )
        sink.write(TRACK_TOPICS["person"], PEOPLE_TYPE, msg, 1.0)
    with pytest.raises(RecordingError, match=r"scan tag .* too large"):
        list(iter_tracks_bag(path))


# -- 2. CSV fields over the field limit -------------------------------------------------------


@pytest.mark.parametrize(
    ("reader", "header", "row"),
    [
        ("tracks", "scan,stamp,track_id,kind,x,y", "0,1.0,1,person,1.0,"),
        ("truth", "scan,stamp,person_id,x,y", "0,1.0,1,1.0,"),
        ("detections", "scan,stamp,x,y,score", "0,1.0,1.0,1.0,"),
    ],
)
def test_cause_2_a_field_over_the_limit(reader: str, header: str, row: str, tmp_path: Path) -> None:
    from laserpeople.io.detections_csv import iter_detections_csv
    from laserpeople.io.tracks_csv import iter_tracks_csv
    from laserpeople.io.truth_csv import read_truth_csv

    path = make_hostile.long_field_csv(tmp_path / f"{reader}.csv", header, row)
    read = {
        "tracks": lambda p: list(iter_tracks_csv(p)),
        "truth": read_truth_csv,
        "detections": lambda p: list(iter_detections_csv(p)),
    }[reader]
    with pytest.raises(RecordingError, match=r"line 2: .*longer than 131,072 characters") as err:
        read(path)
    assert str(path) in str(err.value)


def test_cause_2_every_command_reading_csv(tmp_path: Path, truth: Path) -> None:
    csv = make_hostile.long_field_csv(
        tmp_path / "t.csv", "scan,stamp,track_id,kind,x,y", "0,1.0,1,person,1.0,"
    )
    _refused(_cli("evaluate", csv, "--truth", truth), "131,072")
    long_truth = make_hostile.long_field_csv(
        tmp_path / "truth_long.csv", "scan,stamp,person_id,x,y", "0,1.0,1,1.0,"
    )
    tracks = tmp_path / "tracks.csv"  # the hostile file, mended
    text = (HOSTILE / "tracks_stamps_differ.csv").read_text(encoding="utf-8")
    tracks.write_text(text.replace("10.500000", "10.000000"), encoding="utf-8")
    _refused(_cli("evaluate", tracks, "--truth", long_truth), "truth_long.csv", "131,072")
    out = tmp_path / "v.png"
    _refused(_cli("view", HOSTILE / "small.npz", "-o", out, "--tracks", csv), "131,072")
    _refused(_cli("view", HOSTILE / "small.npz", "-o", out, "--truth", long_truth), "131,072")


# -- 3. huge finite poses, map resolution -------------------------------------------------------


@pytest.mark.parametrize("name", ["tf_1e300.mcap", "odom_2e32.log"])
def test_cause_3_pose_beyond_the_bound_is_a_damaged_scan(name: str, tmp_path: Path) -> None:
    with pytest.raises(ScanFormatError, match=r"sensor pose .* beyond 1e\+07 m"):
        _read_all(HOSTILE / name)
    with pytest.raises(RecordingError, match="every scan is damaged"):
        _read_all(HOSTILE / name, on_error="skip")
    _refused(_cli("track", HOSTILE / name, "-o", tmp_path / "t.csv"), name, "1e+07 m")


def test_cause_3_pose_within_the_bound_reads(tmp_path: Path) -> None:
    from laserpeople.scan import POSE_LIMIT, Pose2D, Scan

    far = [
        Scan(0.1 * k, -1.0, 0.05, np.ones(41), pose=Pose2D(0.999 * POSE_LIMIT, -POSE_LIMIT, 0.0))
        for k in range(3)
    ]
    assert all(s.pose is not None for s in far)
    with pytest.raises(ScanFormatError, match="beyond"):
        Scan(0.0, -1.0, 0.05, np.ones(41), pose=Pose2D(1.001 * POSE_LIMIT, 0.0, 0.0))
    with pytest.raises(ScanFormatError, match="not finite"):
        Scan(0.0, -1.0, 0.05, np.ones(41), pose=Pose2D(0.0, 0.0, math.inf))


def test_cause_3_poses_far_apart_stop_the_grid(tmp_path: Path) -> None:
    from laserpeople.background.occupancy import GRID_CELL_LIMIT
    from laserpeople.io import write_recording
    from laserpeople.scan import Pose2D

    scans = make_hostile.small_scans(20)
    scans = [
        s if s.index < 10 else type(s)(**{**vars(s), "pose": Pose2D(5e6, 5e6, 0.0)}) for s in scans
    ]
    path = tmp_path / "jump.npz"
    write_recording(path, scans)
    run = _cli("track", path, "-o", tmp_path / "t.csv", "--tracker", "csa")
    _refused(run, "occupancy grid would span", f"{GRID_CELL_LIMIT:,}")


def test_cause_3_map_resolution(tmp_path: Path) -> None:
    from laserpeople.background.occupancy import MapFileError, load_ros_map

    with pytest.raises(MapFileError, match=r"resolution 1e-300 m is outside 0\.01-100 m"):
        load_ros_map(HOSTILE / "map_resolution" / "map.yaml")
    run = _cli(
        "track", HOSTILE / "small.npz", "-o", tmp_path / "t.csv", "--map",
        HOSTILE / "map_resolution" / "map.yaml",
    )  # fmt: skip
    _refused(run, "map.yaml", "resolution 1e-300")


# -- 4. map image headers -----------------------------------------------------------------------


def test_cause_4_map_image_claiming_too_many_pixels(tmp_path: Path) -> None:
    from laserpeople.background.occupancy import MAP_PIXEL_LIMIT, MapFileError, load_ros_map

    with pytest.raises(MapFileError, match=f"more than the {MAP_PIXEL_LIMIT:,} pixels"):
        load_ros_map(HOSTILE / "map_bomb" / "map.yaml")
    # below Pillow's own bomb check, above ours: refused from the header, before the pixels
    shutil.copytree(HOSTILE / "map_bomb", tmp_path / "m")
    pgm = tmp_path / "m" / "map.pgm"
    pgm.write_bytes(b"P5\n8000 8000\n255\n" + b"\xfe" * 64)
    with pytest.raises(MapFileError, match="claims 8000 x 8000 pixels"):
        load_ros_map(tmp_path / "m" / "map.yaml")
    pgm.write_bytes(b"P5\n20 10\n255\n" + b"\xfe" * 200)  # the same folder, a sound image
    assert load_ros_map(tmp_path / "m" / "map.yaml").occupied.shape == (10, 20)


# -- 5. neko7055 files --------------------------------------------------------------------------


def test_cause_5_neko_label_index_infinity(tmp_path: Path) -> None:
    from laserpeople.io.neko import read_neko_labels

    with pytest.raises(RecordingError, match="segment index inf is not an integer"):
        read_neko_labels(HOSTILE / "neko_infinity" / "leg_segment_labels.json")
    run = _cli("train", "--neko", HOSTILE / "neko_infinity", "-o", tmp_path / "m.json")
    _refused(run, "leg_segment_labels.json", "segment index inf")


def test_cause_5_neko_huge_xy(tmp_path: Path) -> None:
    from laserpeople.io.neko import read_neko_scans

    with pytest.raises(RecordingError, match=r"line 5: point \(1e\+308, -1e\+308\) is more than"):
        read_neko_scans(HOSTILE / "neko_huge_xy" / "xy_data.txt")
    run = _cli("train", "--neko", HOSTILE / "neko_huge_xy", "-o", tmp_path / "m.json")
    _refused(run, "xy_data.txt", "1000 m")


# -- 6. [occupancy] free_range --------------------------------------------------------------------


def test_cause_6_free_range(tmp_path: Path) -> None:
    from laserpeople.background.occupancy import OccupancyParams

    run = _cli(
        "track", HOSTILE / "small.npz", "-o", tmp_path / "t.csv", "--tracker", "csa",
        "--config", HOSTILE / "free_range.toml",
    )  # fmt: skip
    assert isinstance(run.exception, ConfigError), run.output
    _refused(run, "free_range.toml", "free_range must be at most 1000 m")
    assert OccupancyParams(free_range=1000.0).free_range == 1000.0
    with pytest.raises(ValueError, match="samples per beam"):
        OccupancyParams(free_range=1000.0, resolution=0.001)


# -- 7. GIF frame delay -------------------------------------------------------------------------


def test_cause_7_gif_frame_delay(tmp_path: Path) -> None:
    out = tmp_path / "v.gif"
    rec = HOSTILE / "small.npz"
    _refused(_cli("view", rec, "-o", out, "--fps", "1e-9"), "--fps 1e-09", "[0.01, 1000]")
    assert not out.exists()
    run = _cli("view", rec, "-o", out, "--fps", "0.01", "--stop", "2")  # 100 s a frame
    assert run.exit_code == 0, run.output
    data = out.read_bytes()
    delay = data.index(b"\x21\xf9\x04") + 4  # graphic control extension: delay in 1/100 s
    assert int.from_bytes(data[delay : delay + 2], "little") == 10000


# -- 8. align over its input -----------------------------------------------------------------------


def test_cause_8_align_does_not_replace_its_input(tmp_path: Path) -> None:
    rec = tmp_path / "rec.npz"
    shutil.copy(HOSTILE / "small.npz", rec)
    before = rec.read_bytes()
    for target in (rec, tmp_path / "." / "rec.npz"):
        run = _cli("align", rec, "-o", target)
        _refused(run, "would write over the input")
    link = tmp_path / "link.npz"
    link.hardlink_to(rec)
    _refused(_cli("align", rec, "-o", link), "would write over the input")
    assert rec.read_bytes() == before


# -- 9. range limits that leave no usable beam ---------------------------------------------------


@pytest.mark.parametrize(
    ("name", "says"),
    [
        ("range_max_nan.mcap", "range_max=nan m leave no usable beam"),
        ("range_limits_crossed.npz", "range_min=5 m, range_max=1 m leave no usable beam"),
        ("range_max_zero.log", "maximum range 0.0 is not a positive number"),
    ],
)
def test_cause_9_no_usable_beam(name: str, says: str, tmp_path: Path) -> None:
    with pytest.raises(RecordingError, match=says.replace("(", r"\(")):
        _read_all(HOSTILE / name)
    with pytest.raises(RecordingError, match="every scan is damaged, none could be used"):
        _read_all(HOSTILE / name, on_error="skip")
    out = tmp_path / "t.csv"
    commands: list[list[str | Path]] = [["track", "-o", out], ["detect", "-o", out], ["info"]]
    for command in commands:
        run = _cli(command[0], HOSTILE / name, *command[1:], "--on-error", "skip")
        message = _refused(run, "every scan is damaged")
        assert "-inf" not in message


def test_cause_9_info_prints_sound_range_limits() -> None:
    run = _cli("info", HOSTILE / "small.npz")
    assert run.exit_code == 0, run.output
    assert "0.05–8.0" in run.output and "-inf" not in run.output


# -- 10. option values that make no sense ---------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        (["track", "--restamp", "1e308"], "--restamp must be a scan rate in [0.1, 1000] Hz"),
        (["track", "--restamp", "1e-300"], "--restamp must be a scan rate in [0.1, 1000] Hz"),
        (["train", "-T", "99999999999"], "--rounds must be 1-1,000"),
        (["train", "--jump-distance", "nan"], "--jump-distance must be a distance in (0, 10] m"),
    ],
)
def test_cause_10_option_values(argv: list[str], says: str, tmp_path: Path) -> None:
    out = tmp_path / ("m.json" if argv[0] == "train" else "t.csv")
    run = _cli(argv[0], HOSTILE / "small.npz", "-o", out, *argv[1:])
    assert isinstance(run.exception, ConfigError), run.output
    _refused(run, says)
    assert not out.exists() or out.stat().st_size < 200


# -- the rest of the issue ------------------------------------------------------------------------


def test_long_option_values_are_cut_in_errors(tmp_path: Path) -> None:
    value = "a" * 5000
    message = _refused(
        _cli("align", HOSTILE / "small.npz", "-o", tmp_path / "m.toml", "--mount", value)
    )
    assert "a" * 70 + "…" in message and "a" * 81 not in message
    assert len(message) < 400


def test_tracks_csv_refuses_differing_stamps_in_one_scan() -> None:
    from laserpeople.io.tracks_csv import iter_tracks_csv

    with pytest.raises(RecordingError, match=r"line 3: stamp 10\.5 differs from 10\.0") as err:
        list(iter_tracks_csv(HOSTILE / "tracks_stamps_differ.csv"))
    assert err.value.scan == 0


def test_damage_before_the_first_scan_is_worded_so() -> None:
    with pytest.raises(RecordingError) as err:
        _read_all(HOSTILE / "first_chunk.mcap", poses=False)
    message = str(err.value)
    assert "cannot read its first scan" in message and "scan -1" not in message
    with pytest.raises(RecordingError, match="every scan is damaged"):
        _read_all(HOSTILE / "first_chunk.mcap", poses=False, on_error="skip")


def test_view_closes_the_tracks_csv_on_an_error_path(tmp_path: Path) -> None:
    import gc
    import os

    tracks = tmp_path / "tracks.csv"  # sound tracks of scans 0-2
    text = (HOSTILE / "tracks_stamps_differ.csv").read_text(encoding="utf-8")
    tracks.write_text(text.replace("10.500000", "10.000000"), encoding="utf-8")
    rec = tmp_path / "rec.npz"  # scan 5 is damaged: drawing stops there, the CSV half read
    with np.load(HOSTILE / "small.npz") as z:
        arrays = {k: z[k] for k in z.files}
    arrays["scan_stamp"][5] = np.nan
    np.savez(rec, **arrays)
    gc.disable()  # only the command's own closing counts
    try:
        run = _cli("view", rec, "-o", tmp_path / "v.gif", "--tracks", tracks)
        _refused(run, "scan 5")
        fds = Path(f"/proc/{os.getpid()}/fd")
        open_files = {os.path.realpath(p) for p in fds.iterdir() if p.is_symlink()}
    finally:
        gc.enable()
    assert str(tracks.resolve()) not in open_files


# -- found by benchmarks/fuzz_readers.py while this round ran ----------------------------------


def test_neko_labels_nested_too_deep(tmp_path: Path) -> None:
    from laserpeople.io.neko import read_neko_labels

    path = tmp_path / "leg_segment_labels.json"
    path.write_text('{"labels": {"0": ' + "[" * 100_000 + "]" * 100_000 + "}}", encoding="utf-8")
    with pytest.raises(RecordingError, match="not a neko7055 label file"):
        read_neko_labels(path)


@pytest.mark.parametrize(
    "argv",
    [
        ["view", "{rec}", "-o", "{out}.gif", "--trail", "99999999999"],
        ["bench", "{rec}", "--tracker", "nn", "--repeat", "99999999999"],
        ["bench", "{rec}", "--tracker", "nn", "--max-scans", "9" * 25],
    ],
)
def test_counts_that_ran_for_ever_are_bounded(argv: list[str], tmp_path: Path) -> None:
    names = {"rec": str(HOSTILE / "small.npz"), "out": str(tmp_path / "out")}
    run = _cli(*(a.format(**names) for a in argv))
    assert run.exit_code == 2, run.output  # a usage error naming the bound
    assert "less than or equal to" in run.output
