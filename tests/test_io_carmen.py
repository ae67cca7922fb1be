"""CARMEN logs: field layouts, poses, bad lines, gzip, and writer round trips."""

from __future__ import annotations

import gzip
import math
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from laserpeople.errors import (
    RecordingError,
    ScanFormatError,
    TopicNotFoundError,
    UnsortedStampsError,
)
from laserpeople.io import open_recording
from laserpeople.io.carmen import CarmenRecording, write_carmen_log
from laserpeople.io.poses import PoseParams
from laserpeople.io.rosbag import RosbagRecording
from laserpeople.scan import Pose2D, Scan


def _nums(values: np.ndarray) -> str:
    return " ".join(f"{v:g}" for v in values)


def _flaser(n: int, stamp: float, pose: tuple[float, float, float]) -> str:
    r = np.linspace(1.0, 3.0, n)
    r[0] = 81.9  # CARMEN's "no return"
    return f"FLASER {n} {_nums(r)} {pose[0]} {pose[1]} {pose[2]} 9 9 9 {stamp} host {stamp + 0.5}"


def _rawlaser(k: int, stamp: float, n: int = 5, remissions: bool = True) -> str:
    r = np.array([1.0, 2.0, 50.0, 0.0, 2.5])[:n] if n <= 5 else np.full(n, 2.0)
    rem = f"{n} {_nums(np.arange(n) * 10.0)}" if remissions else "0"
    # start -0.5 rad, fov 0.1 rad per beam, max range 50 m
    fov = 0.1 * (n - 1)
    return f"RAWLASER{k} 0 -0.5 {fov:g} 0.1 50 0.01 0 {n} {_nums(r)} {rem} {stamp} host {stamp}"


def _robotlaser(stamp: float) -> str:
    return (
        f"ROBOTLASER1 0 -1.5708 3.14159 0.785398 80 0.01 0 5 1 2 3 4 5 0 "
        f"1.5 2.5 0.5 1.0 2.0 0.4 0.3 0.1 0.5 0.2 0.0 {stamp} host {stamp}"
    )


def _write(path: Path, lines: list[str]) -> Path:
    path.write_text("\n".join(lines) + "\n")
    return path


def test_flaser_layout_angles_and_no_return(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "f.log",
        ["# comment", "PARAM robot_width 0.5 host 0", _flaser(181, 10.0, (1.0, 2.0, 0.3))],
    )
    rec = open_recording(path)
    assert isinstance(rec, CarmenRecording)
    (scan,) = list(rec.scans())
    assert scan.sensor == "FLASER" and scan.index == 0 and scan.stamp == 10.0
    assert scan.n_beams == 181
    assert scan.angles[0] == pytest.approx(-math.pi / 2)
    assert scan.angles[90] == pytest.approx(0.0, abs=1e-12)
    assert scan.angles[-1] == pytest.approx(math.pi / 2)
    assert not scan.valid[0] and scan.valid[1:].all()  # 81.9 m is CARMEN's max reading
    assert scan.ranges[-1] == pytest.approx(3.0)
    assert scan.pose == Pose2D(1.0, 2.0, 0.3)
    assert rec.other_lines == {"#": 1, "PARAM": 1}


def test_flaser_with_180_readings_spans_minus_90_to_89_degrees(tmp_path: Path) -> None:
    path = _write(tmp_path / "f.log", [_flaser(180, 1.0, (0, 0, 0))])
    (scan,) = list(CarmenRecording(path).scans())
    assert np.degrees(scan.angle_increment) == pytest.approx(1.0)
    assert np.degrees(scan.angles[-1]) == pytest.approx(89.0)


def test_rawlaser_layout_remissions_and_odom_interpolation(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "r.clf",
        [
            "ODOM 0 0 3.0 0 0 0 1.0 host 1.0",
            _rawlaser(1, 1.25),
            "ODOM 2 4 -3.0 0 0 0 2.0 host 2.0",
            _rawlaser(1, 3.0),
        ],
    )
    rec = CarmenRecording(path, pose_params=PoseParams(max_gap=1.0))
    assert [(t.name, t.count) for t in rec.topics()] == [("RAWLASER1", 2)]
    first, second = list(rec.scans())
    assert first.angle_min == pytest.approx(-0.5) and first.angle_increment == pytest.approx(0.1)
    np.testing.assert_allclose(first.angles, [-0.5, -0.4, -0.3, -0.2, -0.1])
    np.testing.assert_array_equal(first.valid, [True, True, False, False, True])  # 50 = max
    assert first.intensities is not None
    np.testing.assert_allclose(first.intensities, [0, 10, 20, 30, 40])
    assert first.pose is not None
    assert (first.pose.x, first.pose.y) == pytest.approx((0.5, 1.0))
    # a quarter of the short way from 3.0 to -3.0 across pi
    assert first.pose.theta == pytest.approx(3.0 + 0.25 * (2 * math.pi - 6.0))
    assert second.pose is None  # 1 s after the last ODOM: not extrapolated
    assert rec.scans_without_pose == 1
    assert "stamp not covered by ODOM" in rec.pose_summary()


def test_laser_offset_composes_with_odometry(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "r.log",
        ["ODOM 1 1 1.5707963267948966 0 0 0 1.0 host 1.0", _rawlaser(2, 1.0)],
    )
    rec = CarmenRecording(path, laser_offsets={"RAWLASER2": Pose2D(0.5, 0.0, 0.0)})
    (scan,) = list(rec.scans(["/rawlaser2"]))
    assert scan.pose is not None
    assert (scan.pose.x, scan.pose.y) == pytest.approx((1.0, 1.5))


def test_robotlaser_uses_the_laser_pose(tmp_path: Path) -> None:
    path = _write(tmp_path / "r.log", [_robotlaser(5.0)])
    (scan,) = list(CarmenRecording(path).scans())
    assert scan.sensor == "ROBOTLASER1" and scan.n_beams == 5
    assert scan.intensities is None
    assert scan.pose == Pose2D(1.5, 2.5, 0.5)
    assert scan.stamp == 5.0
    assert scan.range_max == 80.0


def test_lasers_are_merged_in_stamp_order(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "m.log",
        [_rawlaser(1, 1.0), _rawlaser(1, 1.2), _robotlaser(1.1), _rawlaser(2, 0.9)],
    )
    rec = CarmenRecording(path)
    got = [(s.sensor, s.index, s.stamp) for s in rec.scans()]
    assert got == [
        ("RAWLASER2", 0, 0.9),
        ("RAWLASER1", 0, 1.0),
        ("ROBOTLASER1", 0, 1.1),
        ("RAWLASER1", 1, 1.2),
    ]
    assert "no ODOM lines" in rec.pose_summary()


def test_bad_line_names_file_and_line_or_is_skipped_and_counted(tmp_path: Path) -> None:
    lines = [_rawlaser(1, 1.0), "RAWLASER1 0 -0.5 0.4 0.1 50 0.01 0 5 1 2 x", _rawlaser(1, 2.0)]
    path = _write(tmp_path / "bad.log", lines)
    with pytest.raises(RecordingError, match="line 2") as err:
        list(CarmenRecording(path).scans())
    assert str(path) in str(err.value) and "skip_bad_lines" in str(err.value)
    rec = CarmenRecording(path, skip_bad_lines=True)
    assert [s.index for s in rec.scans()] == [0, 1]
    assert rec.bad_lines == 1 and "line 2" in rec.bad_line_examples[0]
    assert "malformed" not in rec.pose_summary()  # (info says it once, on its own line)
    # a truncated final line (logger killed) is the common case
    cut = _write(tmp_path / "cut.log", [_rawlaser(1, 1.0), _rawlaser(1, 2.0)[:30]])
    with pytest.raises(RecordingError, match="line 2"):
        list(CarmenRecording(cut).scans())
    bad_odom = _write(tmp_path / "odom.log", ["ODOM 1 2", _rawlaser(1, 1.0)])
    with pytest.raises(RecordingError, match="line 1: ODOM"):
        CarmenRecording(bad_odom)


def test_beam_count_disagreeing_with_fov_names_the_line(tmp_path: Path) -> None:
    line = "RAWLASER1 0 -0.5 2.0 0.1 50 0.01 0 5 1 1 1 1 1 0 1.0 host 1.0"  # fov implies 21
    path = _write(tmp_path / "b.log", ["ODOM 0 0 0 0 0 0 1.0 h 1.0", line])
    with pytest.raises(ScanFormatError, match="line 2") as err:
        list(CarmenRecording(path).scans())
    assert err.value.scan == 0 and str(path) in str(err.value)


def test_unsorted_stamps_and_missing_things(tmp_path: Path) -> None:
    path = _write(tmp_path / "u.log", [_rawlaser(1, 2.0), _rawlaser(1, 1.0)])
    with pytest.raises(UnsortedStampsError, match="line 2"):
        list(CarmenRecording(path).scans())
    with pytest.raises(TopicNotFoundError, match="RAWLASER1"):
        list(CarmenRecording(path).scans(["FLASER"]))
    with pytest.raises(RecordingError, match="file not found"):
        CarmenRecording(tmp_path / "none.log")
    empty = _write(tmp_path / "e.log", ["PARAM a b"])
    with pytest.raises(RecordingError, match="no laser lines"):
        CarmenRecording(empty)


def test_gzipped_log_and_truncated_gzip(tmp_path: Path) -> None:
    lines = [_rawlaser(1, 1.0 + 0.1 * k, n=40, remissions=False) for k in range(300)]
    path = tmp_path / "g.log.gz"
    with gzip.open(path, "wt") as fh:
        fh.write("\n".join(lines) + "\n")
    rec = open_recording(path)
    assert isinstance(rec, CarmenRecording)
    assert sum(1 for _ in rec.scans()) == 300
    cut = tmp_path / "cut.log.gz"
    data = path.read_bytes()
    cut.write_bytes(data[: len(data) // 2])
    with pytest.raises(RecordingError, match="corrupt or truncated") as err:
        list(CarmenRecording(cut).scans())
    assert str(cut) in str(err.value)


def _scans() -> list[Scan]:
    rng = np.random.default_rng(5)
    out = []
    for k in range(10):
        for s, name in enumerate(("front", "rear")):
            r = rng.uniform(0.5, 9.0, 13)
            r[4] = np.nan
            r[7] = 12.0  # beyond range_max: invalid
            out.append(
                Scan(
                    50.0 + 0.1 * k + 0.02 * s,
                    2.356 if s else -1.2,
                    -0.2 if s else 0.2,
                    r,
                    range_min=0.0,
                    range_max=10.0,
                    intensities=rng.uniform(0, 1, 13) if s else None,
                    sensor=name,
                    index=k,
                    pose=Pose2D(0.3 * k, 0.1, 3.0 + 0.05 * k),
                )
            )
    return out


@pytest.mark.parametrize("name", ["rt.log", "rt.log.gz"])
def test_writer_round_trip(tmp_path: Path, name: str) -> None:
    original = _scans()
    path = tmp_path / name
    result = write_carmen_log(path, original)
    assert (result.scans, result.odom_lines, result.poses_not_written) == (20, 10, 10)
    rec = open_recording(path)
    assert [t.name for t in rec.topics()] == ["RAWLASER1", "RAWLASER2"]
    back = list(rec.scans())
    assert len(back) == 20
    sensor_of = {"front": "RAWLASER1", "rear": "RAWLASER2"}
    for a, b in zip(original, back, strict=True):
        assert b.sensor == sensor_of[a.sensor] and b.index == a.index
        assert b.stamp == pytest.approx(a.stamp, abs=1e-6)
        np.testing.assert_allclose(b.angles, a.angles, atol=1e-8)
        np.testing.assert_array_equal(b.valid, a.valid)
        np.testing.assert_allclose(b.ranges[a.valid], a.ranges[a.valid], rtol=1e-8)
        if a.intensities is not None:
            assert b.intensities is not None
            np.testing.assert_allclose(b.intensities, a.intensities, rtol=1e-8)
        if a.sensor == "front":  # the ODOM lines carry this laser's poses exactly
            assert b.pose is not None and a.pose is not None
            assert (b.pose.x, b.pose.y, b.pose.theta) == pytest.approx(
                (a.pose.x, a.pose.y, math.remainder(a.pose.theta, 2 * math.pi)), abs=1e-8
            )


def test_writer_keeps_lines_written_before_a_failure(tmp_path: Path) -> None:
    def broken() -> Iterator[Scan]:
        yield from _scans()[:4]
        raise RuntimeError("simulated failure")

    path = tmp_path / "partial.log"
    with pytest.raises(RuntimeError):
        write_carmen_log(path, broken())
    assert sum(1 for _ in CarmenRecording(path).scans()) == 4
    assert sorted(p.name for p in tmp_path.iterdir()) == ["partial.log"]


def test_real_corridor_scans_survive_a_carmen_round_trip(shared_data: Path, tmp_path: Path) -> None:
    """The corridor bags came from a CARMEN log; writing their scans back to CARMEN and
    reading them again gives the same beams and the same odometry poses."""
    src = next(shared_data.rglob("corridor2.bag"))
    with RosbagRecording(src) as rec:
        originals = []
        for scan in rec.scans(["/RAWLASER1"]):
            if scan.pose is not None:
                originals.append(scan)
            if len(originals) == 60:
                break
    out = tmp_path / "corridor.log"
    write_carmen_log(out, originals)
    back = list(CarmenRecording(out).scans())
    assert len(back) == 60
    for a, b in zip(originals, back, strict=True):
        assert b.n_beams == a.n_beams == 361
        np.testing.assert_array_equal(b.valid, a.valid)
        np.testing.assert_allclose(b.ranges[a.valid], a.ranges[a.valid], rtol=1e-7)
        assert b.pose is not None and a.pose is not None
        assert (b.pose.x, b.pose.y) == pytest.approx((a.pose.x, a.pose.y), abs=1e-6)
