from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from laserpeople.errors import RecordingError
from laserpeople.io.tracks_csv import HEADER, TracksCsvWriter, convert_tracks, iter_tracks_csv
from laserpeople.scan import Pose2D
from laserpeople.tracks import Track, Tracks


def _tracks(k: int, pose: Pose2D | None = None) -> Tracks:
    leg = Track(3, "leg", [1.0 + k, 2.0], [0.5, 0.0], np.diag([0.01, 0.02]))
    grp = Track(1, "group", [0.0, k], [0.0, 0.0], np.eye(2), size=3, labels="1-0|2")
    return Tracks(0.1 * k, k, (leg, grp), "world", pose)


def test_round_trip_and_flush(tmp_path: Path) -> None:
    path = tmp_path / "t.csv"
    with TracksCsvWriter(path) as out:
        out.write(_tracks(0))
        # rows of the first scan are on disk before the writer is closed
        assert path.read_text().count("\n") == 3
        out.write(Tracks(0.1, 1))
        out.write(_tracks(2))
    assert path.read_text().splitlines()[0] == ",".join(HEADER)
    back = list(iter_tracks_csv(path))
    assert [t.scan_index for t in back] == [0, 2]
    g = back[1].of_kind("group")[0]
    assert (g.size, g.labels, g.track_id) == (3, "1-0|2", 1)
    np.testing.assert_allclose(back[1].of_kind("leg")[0].position, [3.0, 2.0])
    assert [len(t) for t in iter_tracks_csv(path, kinds=("leg",))] == [1, 1]


def test_frame_conversion_round_trips() -> None:
    pose = Pose2D(2.0, -1.0, math.pi / 3)
    world = _tracks(1, pose)
    sensor = convert_tracks(world, "sensor")
    back = convert_tracks(sensor, "world")
    for a, b in zip(world, back, strict=True):
        np.testing.assert_allclose(a.position, b.position, atol=1e-12)
        np.testing.assert_allclose(a.covariance, b.covariance, atol=1e-12)
    np.testing.assert_allclose(
        sensor.tracks[0].position, pose.inverse_transform_points(world.tracks[0].position[None])[0]
    )


def test_sensor_pose_round_trips_and_bad_cells_are_refused(tmp_path: Path) -> None:
    pose = Pose2D(2.5, -1.25, -2.75)
    path = tmp_path / "t.csv"
    with TracksCsvWriter(path, frame="sensor", topic="/scan") as out:
        out.write(_tracks(0, pose))  # world-frame tracks written in the sensor frame
        leg = _tracks(1).tracks[0]
        out.write(Tracks(0.1, 1, (leg,), "sensor"))  # no pose: empty cells
    lines = path.read_text().splitlines()
    assert lines[0].endswith(",topic,frame,sensor_x,sensor_y,sensor_yaw")
    assert lines[1].endswith(",/scan,sensor,2.500000,-1.250000,-2.750000000")
    back = list(iter_tracks_csv(path, frame="world"))
    assert back[0].sensor_pose == pose and back[0].frame == "sensor"
    assert back[1].sensor_pose is None
    world = convert_tracks(back[0], "world")  # the pose read back moves them home
    np.testing.assert_allclose(world.tracks[0].position, [1.0, 2.0], atol=2e-4)
    for cells, problem in (
        (",/scan,sensor,1.0,,2.0", "not three numbers"),
        (",/scan,sensor,1.0,nan,2.0", "not finite"),
    ):
        bad = tmp_path / "bad.csv"
        bad.write_text(lines[0] + "\n" + lines[1].rsplit(",/scan", 1)[0] + cells + "\n")
        with pytest.raises(RecordingError, match=f"line 2: the sensor pose .* {problem}"):
            list(iter_tracks_csv(bad))


def test_bad_csv_is_a_clear_error(tmp_path: Path) -> None:
    bad = tmp_path / "bad.csv"
    bad.write_text("a,b\n1,2\n")
    with pytest.raises(RecordingError, match="missing column"):
        list(iter_tracks_csv(bad))
    bad.write_text(",".join(HEADER) + "\n0,0.0,1,robot,0,0,0,0,1,0,1,1,\n")
    with pytest.raises(RecordingError, match="line 2"):
        list(iter_tracks_csv(bad))


def test_file_problems_are_one_line_errors(tmp_path: Path) -> None:
    with pytest.raises(RecordingError, match="is a directory"):
        list(iter_tracks_csv(tmp_path))
    binary = tmp_path / "b.csv"
    binary.write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(RecordingError, match="not a text CSV"):
        list(iter_tracks_csv(binary))
    short = tmp_path / "short.csv"
    short.write_text(",".join(HEADER) + "\n0,0.0,1,leg,0,0\n")
    with pytest.raises(RecordingError, match="line 2: fewer fields"):
        list(iter_tracks_csv(short))
    with pytest.raises(RecordingError, match="cannot write"):
        TracksCsvWriter(binary / "sub.csv")


def test_scans_must_not_go_backwards(tmp_path: Path) -> None:
    path = tmp_path / "t.csv"
    with TracksCsvWriter(path) as out:
        out.write(_tracks(2))
        out.write(_tracks(1))
    with pytest.raises(RecordingError, match="scan 1 come after scan 2"):
        list(iter_tracks_csv(path))
