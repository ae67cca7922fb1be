"""Regressions from the acceptance pass of `laserpeople view`: world frame when only the
first scans lack a pose (skipped and counted), and --mount for bags."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import LaserPeopleError
from laserpeople.io import write_recording
from laserpeople.scan import Pose2D
from laserpeople.truth import TruthFrame
from laserpeople.viz import Scene
from test_viz_support import make_scans

runner = CliRunner()


def test_auto_frame_is_world_when_only_first_scans_lack_pose() -> None:
    scans = make_scans(6)
    scans[0] = replace(scans[0], pose=None)
    scans[1] = replace(scans[1], pose=None)
    scene = Scene(scans)
    assert scene.frame == "world"
    frames = list(scene.frames())
    assert [f.scan.index for f in frames] == [2, 3, 4, 5]
    assert scene.skipped_without_pose == 2


def test_view_mount_only_for_bags(tmp_path: Path) -> None:
    rec = tmp_path / "r.npz"
    write_recording(rec, make_scans(3), [], {})
    res = runner.invoke(app, ["view", str(rec), "--mount", "mir100", "-o", str(tmp_path / "x.png")])
    assert res.exit_code != 0
    assert isinstance(res.exception, LaserPeopleError)
    assert "apply to ROS bags only" in str(res.exception)


def test_view_mount_gives_bag_world_frame(tmp_path: Path) -> None:
    from laserpeople.io.rosbag_writer import write_laserscan_bag

    bag = tmp_path / "r.bag"
    write_laserscan_bag(bag, [replace(s, pose=None) for s in make_scans(3)])
    out = tmp_path / "x.png"
    args = ["view", str(bag), "-o", str(out), "--size", "160x120"]
    res = runner.invoke(app, args)
    assert res.exit_code == 0, res.output
    assert "sensor frame" in res.output
    res = runner.invoke(app, [*args, "--mount", "front=base:1,0,0", "--world-frame", "base"])
    assert res.exit_code == 0, res.output
    assert "world frame" in res.output


def test_view_unwritable_output_and_directory_tracks(tmp_path: Path) -> None:
    rec = tmp_path / "r.npz"
    write_recording(rec, make_scans(3), [], {})
    blocker = tmp_path / "file"
    blocker.write_text("x")
    for name in ("x.png", "x.gif"):
        res = runner.invoke(app, ["view", str(rec), "-o", str(blocker / name), "--size", "64x48"])
        assert res.exit_code != 0
        assert isinstance(res.exception, LaserPeopleError)
        assert f"{name}: cannot write the output" in str(res.exception)
    res = runner.invoke(
        app, ["view", str(rec), "--tracks", str(tmp_path), "-o", str(tmp_path / "y.png")]
    )
    assert isinstance(res.exception, LaserPeopleError)
    assert "is a directory, not a tracks CSV" in str(res.exception)


def test_truth_in_the_laser_frame_is_drawn_where_the_person_is() -> None:
    """Labels in each scan's laser frame (the leg_tracker benchmark's) are moved into the
    world for a world-frame picture and left as they are in the sensor frame; labels in the
    world frame the other way round. Sensor at (1, -2), turned 90 degrees: a label 2 m ahead
    of the laser is at (1, 0) in the world."""
    pose = Pose2D(1.0, -2.0, math.pi / 2)
    scans = make_scans(2, pose=pose)
    ahead = [TruthFrame.from_positions(s.stamp, s.index, np.array([7]), np.array([[2.0, 0.0]]))
             for s in scans]  # fmt: skip
    world = [replace(f, positions=np.array([[1.0, 0.0]])) for f in ahead]

    def drawn(truth: list[TruthFrame], frame: str, truth_frame: str) -> np.ndarray:
        scene = Scene(scans, None, truth, frame=frame, truth_frame=truth_frame)  # type: ignore[arg-type]
        got = [f.truth for f in scene.frames()]
        assert all(t is not None for t in got)
        return np.concatenate([t.positions for t in got if t is not None])

    tol = 1e-9  # one rotation and translation of exact inputs
    np.testing.assert_allclose(drawn(ahead, "world", "sensor"), [[1.0, 0.0]] * 2, atol=tol)
    np.testing.assert_allclose(drawn(ahead, "sensor", "sensor"), [[2.0, 0.0]] * 2, atol=tol)
    np.testing.assert_allclose(drawn(world, "sensor", "world"), [[2.0, 0.0]] * 2, atol=tol)
    np.testing.assert_allclose(drawn(world, "world", "world"), [[1.0, 0.0]] * 2, atol=tol)
    # without --truth-frame the truth is taken in the tracks' frame
    assert Scene(scans, None, ahead, tracks_frame="sensor").truth_frame == "sensor"
    assert Scene(scans, None, ahead).truth_frame == "world"


def test_truth_velocities_and_legs_turn_with_the_positions() -> None:
    """The velocity is rotated (not translated) the same way round as the positions: sensor
    at (1, -2) turned 90 degrees; a person 2 m ahead of the laser walking away from it at
    1 m/s along the laser's x axis walks along +y in the world, legs 0.1 m either side of
    the laser's x axis are 0.1 m either side along the world's x axis."""
    pose = Pose2D(1.0, -2.0, math.pi / 2)
    scans = make_scans(2, pose=pose)
    ahead = [
        replace(
            TruthFrame.from_positions(s.stamp, s.index, np.array([7]), np.array([[2.0, 0.0]])),
            velocities=np.array([[1.0, 0.0]]),
            leg_positions=np.array([[[2.0, 0.1], [2.0, -0.1]]]),
        )
        for s in scans
    ]
    # world = (1, -2) + R(90 deg) p: R (x, y) = (-y, x); velocity R v only
    world = [
        replace(
            f,
            positions=np.array([[1.0, 0.0]]),
            velocities=np.array([[0.0, 1.0]]),
            leg_positions=np.array([[[0.9, 0.0], [1.1, 0.0]]]),
        )
        for f in ahead
    ]

    def drawn(truth: list[TruthFrame], frame: str, truth_frame: str) -> list[TruthFrame]:
        scene = Scene(scans, None, truth, frame=frame, truth_frame=truth_frame)  # type: ignore[arg-type]
        got = [f.truth for f in scene.frames()]
        assert len(got) == 2
        return [t for t in got if t is not None]

    tol = 1e-9  # one rotation and translation of exact inputs
    both = ((drawn(ahead, "world", "sensor"), world), (drawn(world, "sensor", "world"), ahead))
    for got, want in both:
        assert len(got) == 2
        for g, w in zip(got, want, strict=True):
            np.testing.assert_allclose(g.positions, w.positions, atol=tol)
            np.testing.assert_allclose(g.velocities, w.velocities, atol=tol)
            np.testing.assert_allclose(g.leg_positions, w.leg_positions, atol=tol)
