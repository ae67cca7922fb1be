"""Laser alignment by point-to-line ICP (004 Sec. 2 preprocessing) and `laserpeople align`."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.alignment import (
    Alignment,
    AlignmentError,
    Mount,
    align_lasers,
    align_recording,
    line_normals,
    read_mounts,
    write_mounts,
)
from laserpeople.cli import app
from laserpeople.io.poses import MIR100_LASER_MOUNTS
from laserpeople.scan import Pose2D
from laserpeople.sim.scenarios.schenk import (
    schenk_sensors,
    schenk_sensors_one_side,
    schenk_world,
)
from laserpeople.sim.simulator import Scene, SimResult, simulate


def _empty_room(sensors: list) -> SimResult:
    return simulate(Scene(schenk_world(), [], sensors[:2]), 1.0, seed=1, rate=10.0)


def _error(est: Pose2D, truth: Pose2D) -> tuple[float, float]:
    dth = math.remainder(est.theta - truth.theta, 2 * math.pi)
    return math.hypot(est.x - truth.x, est.y - truth.y), abs(math.degrees(dth))


def test_recovers_a_known_offset_from_a_rough_guess() -> None:
    """Opposite sides of the 004 room (4 m apart, facing each other); the guess is off by
    0.3 m, 0.2 m and 8 degrees."""
    sensors = schenk_sensors()
    rec = _empty_room(sensors)
    truth = sensors[0].mount.inverse().compose(sensors[1].mount)
    guess = Pose2D(truth.x + 0.3, truth.y - 0.2, truth.theta + math.radians(8.0))
    fit = align_lasers(rec.scans, "feet_a", static=True, initial={"feet_b": guess})["feet_b"]
    dist, deg = _error(fit.pose, truth)
    assert dist < 0.02 and deg < 0.5
    assert fit.residual < 0.03


def test_recovers_a_known_offset_without_a_guess() -> None:
    """Both lasers on one side (setup (h)), 2 m apart: the coarse search finds the pose."""
    sensors = schenk_sensors_one_side()
    rec = _empty_room(sensors)
    truth = sensors[0].mount.inverse().compose(sensors[1].mount)
    fit = align_lasers(rec.scans, "feet_a", static=True)["feet_b"]
    dist, deg = _error(fit.pose, truth)
    assert dist < 0.02 and deg < 0.5
    assert fit.explained > 0.8


def test_line_normals_of_a_wall() -> None:
    x = np.linspace(0, 2, 30)
    pts = np.column_stack([x, 0.5 * x + 1.0])
    n = line_normals(pts, 6)
    expect = np.array([-0.5, 1.0]) / math.hypot(0.5, 1.0)
    assert np.abs(n @ expect) == pytest.approx(np.ones(30))


def test_mounts_round_trip_and_errors(tmp_path: Path) -> None:
    fit = Alignment("b", "a", Pose2D(1.0, -2.0, 0.5), 0.01, 0.9, 100, 1)
    mounts = [Mount("a", "base", Pose2D(0.1, 0.2, 0.3), None), Mount("b", "base", fit.pose, fit)]
    path = write_mounts(tmp_path / "m.toml", mounts)
    back = read_mounts(path)
    assert back["a"] == ("base", Pose2D(0.1, 0.2, 0.3))
    assert back["b"][1].as_array() == pytest.approx([1.0, -2.0, 0.5])
    (tmp_path / "bad.toml").write_text('[mounts.x]\nparent = "p"\nx = 1\n')
    from laserpeople.errors import ConfigError

    with pytest.raises(ConfigError, match="needs parent, x, y and theta"):
        read_mounts(tmp_path / "bad.toml")


def test_one_laser_cannot_be_aligned() -> None:
    rec = _empty_room(schenk_sensors())
    with pytest.raises(AlignmentError, match="need two lasers"):
        align_lasers([s for s in rec.scans if s.sensor == "feet_a"], static=True)


def test_cli_align_writes_mounts(tmp_path: Path) -> None:
    sensors = schenk_sensors_one_side()
    rec_path = _empty_room(sensors).write(tmp_path / "room.npz")
    out = tmp_path / "mounts.toml"
    result = CliRunner().invoke(
        app, ["align", str(rec_path), "-o", str(out), "--static", "--reference", "feet_a"]
    )
    assert result.exit_code == 0, result.output
    # the table's units are printed (rich took "[m]" and "[deg]" for markup and dropped them)
    header = " ".join(result.stdout.split())
    for unit in ("[m]", "[deg]"):
        assert unit in header
    mounts = read_mounts(out)
    parent, pose = mounts["feet_b"]
    assert parent == "feet_a"
    assert _error(pose, sensors[0].mount.inverse().compose(sensors[1].mount))[0] < 0.02


def test_mir_front_back_lasers_agree_with_the_mir100_mounts(shared_data: Path) -> None:
    """The real MiR bag: the back laser's pose estimated from the data (no initial guess)
    lies within 3 cm and 1 degree of the MiR100 URDF mounts, with a small residual."""
    path = next(shared_data.rglob("legs-test-split-*.bag"))
    front = {"front_laser_link": MIR100_LASER_MOUNTS["front_laser_link"]}
    mounts = {m.laser: m for m in align_recording(path, mounts=front)}
    est = mounts["back_laser_link"]
    assert est.parent == "base_footprint" and est.fit is not None
    dist, deg = _error(est.pose, MIR100_LASER_MOUNTS["back_laser_link"][1])
    assert dist < 0.03 and deg < 1.0
    assert est.fit.residual < 0.03


def _bag_with_frame_ids(tmp_path: Path, sensors: list) -> Path:
    """The empty room's feet lasers in a bag whose topics (/scan_a, /scan_b) differ from
    their scans' frame ids (feet_a_link, feet_b_link), as on most robots."""
    from laserpeople.io.rosbag_writer import open_bag

    path = tmp_path / "room.mcap"
    with open_bag(path) as sink:
        for scan in _empty_room(sensors).scans:
            topic = "/scan_" + scan.sensor[-1]
            sink.scan(scan.with_pose(None), topic, f"{scan.sensor}_link")
    return path


def test_align_names_bag_lasers_by_frame_id_as_track_mount_reads_them(tmp_path: Path) -> None:
    """The mounts file names each laser by its scans' frame id (what `track --mount`
    matches), and a given mount of the first laser's frame id puts the other on the robot."""
    sensors = schenk_sensors_one_side()
    path = _bag_with_frame_ids(tmp_path, sensors)
    notes: list[str] = []
    given = {"feet_a_link": ("base_link", sensors[0].mount)}
    mounts = {m.laser: m for m in align_recording(path, static=True, mounts=given, notes=notes)}
    assert set(mounts) == {"feet_a_link", "feet_b_link"} and notes == []
    est = mounts["feet_b_link"]
    assert est.parent == "base_link" and est.fit is not None
    dist, deg = _error(est.pose, sensors[1].mount)  # on the robot, not relative to feet_a
    assert dist < 0.02 and deg < 0.5
    # the reference may be named by its topic; the estimate is then relative to its frame
    back = align_recording(path, static=True, reference="/scan_b")
    assert [(m.laser, m.parent) for m in back] == [("feet_a_link", "feet_b_link")]


def test_align_says_when_a_given_mount_names_no_laser(tmp_path: Path) -> None:
    sensors = schenk_sensors_one_side()
    path = _bag_with_frame_ids(tmp_path, sensors)
    notes: list[str] = []
    given = {"feet_a": ("base_link", sensors[0].mount)}  # the sensor's name, not its frame id
    mounts = align_recording(path, static=True, mounts=given, notes=notes)
    assert [(m.laser, m.parent) for m in mounts] == [("feet_b_link", "feet_a_link")]
    assert len(notes) == 1 and "mount of 'feet_a' not used" in notes[0]
    assert "/scan_a 'feet_a_link'" in notes[0]
