"""What a demanding user meets, eighth round: the Python API given the wrong types or an
output that is its input, a tracks CSV rewritten by a run that fails at once, duplicate
rows of one track, foreign manifest lines, an unreachable scheduler."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from laserpeople.errors import ConfigError, ScanFormatError
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
