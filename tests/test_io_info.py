"""`laserpeople info` on real bags, CARMEN logs and npz recordings."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.cli.info import summarise
from laserpeople.errors import TopicNotFoundError
from laserpeople.io import open_recording, write_recording
from laserpeople.io.carmen import write_carmen_log
from laserpeople.io.npz import TopicInfo
from laserpeople.scan import Pose2D, Scan
from laserpeople.truth import TruthFrame


def _info(*args: str) -> dict:
    result = CliRunner().invoke(app, ["info", *args, "--json"])
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout)


def test_info_lists_both_mir_lasers(shared_data: Path) -> None:
    path = next(shared_data.rglob("legs-test-split-*.bag"))
    report = _info(str(path))
    topics = {t["topic"]: t for t in report["topics"]}
    assert set(topics) == {"front_laser_link", "back_laser_link"}
    for t in topics.values():
        assert t["scans"] == 737 and t["beams"] == [541]
        assert t["fov_deg"] == [pytest.approx(270.0)]
        assert t["angular_resolution_deg"] == [pytest.approx(-0.5)]
        assert t["rate_hz"] == pytest.approx(12.7, abs=0.1)
        assert t["range_min_m"] == pytest.approx(0.05) and t["range_max_m"] == pytest.approx(29.0)
        assert 0.0 < t["invalid_share"] < 0.5
        assert t["scans_with_pose"] == 0 and t["scans_without_pose"] == 737
    assert report["ground_truth"] is False
    assert report["other_topics"] == [
        {"topic": "/tf", "msgtype": "tf2_msgs/msg/TFMessage", "messages": 2399}
    ]
    table = CliRunner().invoke(app, ["info", str(path)])
    assert table.exit_code == 0
    assert "front_laser_link" in table.stdout and "back_laser_link" in table.stdout


def test_info_mounts_give_the_mir_lasers_poses(shared_data: Path) -> None:
    path = next(shared_data.rglob("legs-test-split-*.bag"))
    report = _info(
        str(path),
        "--topic",
        "front_laser_link",
        "--mount",
        "front_laser_link=base_footprint:0.4,0.2,0.785",
    )
    (t,) = report["topics"]
    assert t["topic"] == "front_laser_link"
    assert t["scans_with_pose"] > 700  # all but those outside the /tf samples
    assert report["world_frame"] == "odom"
    both = _info(str(path), "--mount", "mir100")
    assert [t["scans_with_pose"] > 700 for t in both["topics"]] == [True, True]


def test_info_rate_and_poses_of_a_corridor_bag(shared_data: Path) -> None:
    path = next(shared_data.rglob("corridor.bag"))
    report = _info(str(path), "-t", "/RAWLASER1")
    (t,) = report["topics"]
    assert t["scans"] == 1563 and t["beams"] == [361]
    assert t["rate_hz"] == pytest.approx(45.4, abs=0.5)
    assert t["scans_without_pose"] == 2


class _TwoLasers:
    """A recording whose second laser's scan comes first in time."""

    path = Path("two.bag")
    has_truth = False

    def topics(self) -> list[TopicInfo]:
        return [TopicInfo("/first", "sensor_msgs/msg/LaserScan", 1), TopicInfo("/second", "x", 2)]

    def scans(self, topics: list[str] | None = None) -> Iterator[Scan]:
        for stamp, sensor in ((0.0, "/second"), (0.05, "/first"), (0.1, "/second")):
            yield Scan(stamp, -1.0, 1.0, np.array([1.0, 2.0, 3.0]), 0.0, 8.0, sensor=sensor)


def test_info_lists_lasers_in_the_recording_order_not_by_first_scan() -> None:
    report = summarise(_TwoLasers(), None)  # type: ignore[arg-type]
    assert [t["topic"] for t in report["topics"]] == ["/first", "/second"]
    assert [t["scans"] for t in report["topics"]] == [1, 2]


def test_info_lists_first_the_corridor_laser_track_takes(shared_data: Path) -> None:
    path = next(shared_data.rglob("corridor.bag"))
    report = _info(str(path), "--no-poses")
    assert [t["topic"] for t in report["topics"]] == ["/RAWLASER1", "/ROBOTLASER1"]
    with open_recording(path) as rec:
        assert rec.resolve_topics(None)[0] == "/RAWLASER1"  # the laser `track` takes


def test_info_on_npz_with_truth_and_on_carmen(tmp_path: Path) -> None:
    scans = [
        Scan(0.1 * k, -1.0, 0.5, np.array([1.0, np.nan, 2.0, 9.0, 3.0]), 0.0, 8.0, sensor="s")
        for k in range(3)
    ]
    truth = [
        TruthFrame(
            0.0,
            0,
            np.array([1]),
            np.zeros((1, 2)),
            np.zeros((1, 2)),
            np.array([-1]),
            np.zeros((1, 2, 2)),
            np.zeros(1),
        )
    ]
    npz = write_recording(tmp_path / "r.npz", scans, truth)
    report = _info(str(npz))
    (t,) = report["topics"]
    assert report["ground_truth"] is True
    assert t["scans"] == 3 and t["rate_hz"] == pytest.approx(10.0)
    assert t["invalid_share"] == pytest.approx(2 / 5)
    assert t["fov_deg"] == [pytest.approx(math.degrees(2.0))]
    log = tmp_path / "r.log"
    write_carmen_log(log, [s.with_pose(Pose2D(1, 2, 0)) for s in scans])
    report = _info(str(log))
    assert report["topics"][0]["topic"] == "RAWLASER1"
    assert report["topics"][0]["scans_with_pose"] == 3
    report = _info(str(log), "--no-poses")
    assert report["topics"][0]["scans_with_pose"] == 0


def test_info_missing_topic_fails_with_one_line(shared_data: Path) -> None:
    path = next(shared_data.rglob("demo_stationary_simple_environment.bag"))
    result = CliRunner().invoke(app, ["info", str(path), "-t", "/nope"])
    assert isinstance(result.exception, TopicNotFoundError)
    proc = subprocess.run(
        [
            sys.executable,
            "-c",
            "from laserpeople.cli import main; main()",
            "info",
            str(path),
            "-t",
            "/nope",
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 1
    assert "no topic '/nope'" in proc.stderr and "/scan" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_info_says_the_malformed_lines_of_a_carmen_log_once(tmp_path: Path) -> None:
    scans = [
        Scan(0.1 * k, -1.0, 0.5, np.array([1.0, 2.0, 2.0, 9.0, 3.0]), 0.0, 8.0, sensor="s")
        for k in range(3)
    ]
    log = tmp_path / "r.log"
    write_carmen_log(log, [s.with_pose(Pose2D(1, 2, 0)) for s in scans])
    lines = log.read_text().splitlines()
    log.write_text("\n".join([*lines[:2], "RAWLASER1 garbage", *lines[2:]]) + "\n")
    result = CliRunner().invoke(app, ["info", str(log), "--on-error", "skip"])
    assert result.exit_code == 0, result.output
    assert result.output.count("malformed lines skipped") == 1
    assert "malformed lines skipped: 1" in result.output
