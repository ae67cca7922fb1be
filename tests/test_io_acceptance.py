"""Regressions from the acceptance pass of the readers: directories, binary CSVs, bad
cells, and the zero-stamp count of simulated bags."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from laserpeople.errors import RecordingError
from laserpeople.io.carmen import CarmenRecording
from laserpeople.io.rosbag import RosbagRecording
from laserpeople.io.rosbag_writer import write_laserscan_bag
from laserpeople.io.truth_csv import read_truth_csv
from laserpeople.scan import Scan


def test_bag_reader_says_directory(tmp_path: Path) -> None:
    folder = tmp_path / "x.bag"
    folder.mkdir()
    with pytest.raises(RecordingError, match="is a directory, not a bag"):
        RosbagRecording(folder)


def test_carmen_reader_says_directory(tmp_path: Path) -> None:
    folder = tmp_path / "x.log"
    folder.mkdir()
    with pytest.raises(RecordingError, match="is a directory, not a CARMEN log"):
        CarmenRecording(folder)


def test_truth_csv_directory_and_binary(tmp_path: Path) -> None:
    folder = tmp_path / "d.csv"
    folder.mkdir()
    with pytest.raises(RecordingError, match="is a directory"):
        read_truth_csv(folder)
    binary = tmp_path / "b.csv"
    binary.write_bytes(b"scan,stamp\n\xd5\xff\x00\x01")
    with pytest.raises(RecordingError, match=r"b\.csv: not a text CSV"):
        read_truth_csv(binary)


@pytest.mark.parametrize(
    ("row", "message"),
    [
        ("5,0.25,3.0,1,2", "line 2: column person_id is '3.0', a number but not an integer"),
        ("5,0.25,1,2", "line 2: column y is empty, not a number"),
        ("5,0.25,1,2,3,4,9", "line 2: 1 more field"),
    ],
)
def test_truth_csv_bad_cell_names_column(tmp_path: Path, row: str, message: str) -> None:
    path = tmp_path / "t.csv"
    path.write_text(f"scan,stamp,person_id,x,y,group_id\n{row}\n")
    with pytest.raises(RecordingError, match=message):
        read_truth_csv(path)


def test_truth_csv_trailing_empty_field_is_fine(tmp_path: Path) -> None:
    path = tmp_path / "t.csv"
    path.write_text("scan,stamp,person_id,x,y\n0,0.5,1,2.0,3.0,\n")
    (frame,) = read_truth_csv(path)
    np.testing.assert_allclose(frame.positions, [[2.0, 3.0]])


def test_scan_stamped_zero_is_not_counted_as_log_time(tmp_path: Path) -> None:
    """A simulated bag starts at t = 0; its header stamp 0 equals the log time, so nothing
    was substituted and `info` must not report it."""
    scans = [
        Scan(0.1 * k, -1.0, 0.5, np.full(5, 2.0), range_max=10.0, sensor="laser", index=k)
        for k in range(3)
    ]
    path = tmp_path / "s.bag"
    write_laserscan_bag(path, scans)
    with RosbagRecording(path) as rec:
        stamps = [s.stamp for s in rec.scans()]
        assert rec.scans_with_log_time == 0
    np.testing.assert_allclose(stamps, [0.0, 0.1, 0.2])


@pytest.mark.parametrize(
    ("base", "hint"), [("base_footprint", "--mount mir100"), ("chassis", "--mount CHILD=")]
)
def test_pose_summary_suggests_mount(tmp_path: Path, base: str, hint: str) -> None:
    from laserpeople.io.rosbag_writer import open_bag
    from laserpeople.scan import Pose2D

    path = tmp_path / "m.bag"
    with open_bag(path) as sink:
        for k in range(2):
            scan = Scan(1.0 + k, -1.0, 0.5, np.full(5, 2.0), range_max=10.0, sensor="front")
            sink.pose(scan.stamp, "odom", base, Pose2D(0.1 * k, 0.0, 0.0), "/tf")
            sink.scan(scan, "/front", "front_laser_link")
    with RosbagRecording(path) as rec:
        scans = list(rec.scans())
        assert all(s.pose is None for s in scans)
        assert hint in rec.pose_summary()
