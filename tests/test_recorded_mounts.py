"""`--mount` on a recording that already holds the lasers' world poses (`live --record`,
`track --bag`): the mount is left out and said, so `track` tracks in the recording's world
frame and reproduces what was recorded, instead of tracking in the robot's frame."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from laserpeople.io.poses import (
    MIR100_LASER_MOUNTS,
    TransformTree,
    mounts_to_use,
    parse_mounts,
)
from laserpeople.io.rosbag import RosbagRecording
from laserpeople.io.rosbag_writer import open_bag, write_laserscan_bag
from laserpeople.io.tracks_bag import WORLD_FRAME_ID
from laserpeople.scan import Pose2D, Scan

LASERS = ("front_laser_link", "back_laser_link")


def _robot(t: float) -> Pose2D:
    """The robot (base_footprint) in odom at time t [s]: drives and turns."""
    return Pose2D(0.3 * t, 0.1 * t, 0.2 * t)


def _scan(stamp: float, laser: str, pose: Pose2D | None) -> Scan:
    ranges = np.linspace(1.0, 3.0, 9)
    scan = Scan.from_angles(stamp, -1.0, 1.0, 0.25, ranges, sensor=laser)
    return scan.with_pose(pose)


def _recorded(path: Path) -> dict[tuple[str, float], Pose2D]:
    """A two-laser recording as `live --record` writes it: per scan, the laser's pose in the
    world frame on /tf (robot pose composed with the MiR100 mount). Returns the poses."""
    poses: dict[tuple[str, float], Pose2D] = {}
    scans = []
    for i in range(20):
        for k, laser in enumerate(LASERS):
            t = 10.0 + 0.08 * i + 0.03 * k
            pose = _robot(t).compose(MIR100_LASER_MOUNTS[laser][1])
            poses[(laser, round(t, 6))] = pose
            scans.append(_scan(t, laser, pose))
    write_laserscan_bag(path, scans, world_frame=WORLD_FRAME_ID)
    return poses


def test_mount_is_left_out_when_the_recording_holds_the_world_poses(tmp_path: Path) -> None:
    path = tmp_path / "live.mcap"
    written = _recorded(path)
    with RosbagRecording(path, mounts=parse_mounts(["mir100"])) as rec:
        got = {(s.sensor.lstrip("/"), round(s.stamp, 6)): s.pose for s in rec.scans()}
        assert rec.pose_frame() == WORLD_FRAME_ID  # not base_footprint, the robot's frame
        notes = rec.mount_notes
    assert got.keys() == written.keys()
    for key, pose in written.items():
        p = got[key]
        assert p is not None
        # the recorded pose itself (the mount alone would be off by the robot's motion: m)
        assert abs(p.x - pose.x) < 1e-9 and abs(p.y - pose.y) < 1e-9, key
        assert abs(math.remainder(p.theta - pose.theta, 2 * math.pi)) < 1e-9, key
    assert len(notes) == 2
    assert all("not used" in n and "base_footprint" in n and "'world'" in n for n in notes)
    assert any("'front_laser_link'" in n for n in notes)
    assert any("'back_laser_link'" in n for n in notes)


def test_track_with_mount_on_the_recording_gives_the_tracks_without_it(tmp_path: Path) -> None:
    """The pipeline `track` runs: same frames, same poses with and without `--mount mir100`,
    and its summary says the mounts were left out."""
    from laserpeople.pipeline import build

    path = tmp_path / "live.mcap"
    _recorded(path)

    class Poses:
        def __init__(self) -> None:
            self.rows: list[tuple[float, str, float, float, float]] = []

        def write(self, frame, tracks) -> None:  # type: ignore[no-untyped-def]
            for s in frame.scans:
                assert s.pose is not None
                self.rows.append((frame.stamp, s.sensor, s.pose.x, s.pose.y, s.pose.theta))

        def close(self) -> None:
            return None

    runs = {}
    for mounts in ([], ["mir100"]):
        sink = Poses()
        pipe = build(path, topics=list(LASERS), mounts=mounts, outputs=[sink], frame="world")
        pipe.run()
        runs[bool(mounts)] = (sink.rows, pipe.source.summary())
    plain, mounted = runs[False][0], runs[True][0]
    assert len(plain) == 40 and len(mounted) == 40
    got, want = np.array([r[2:] for r in mounted]), np.array([r[2:] for r in plain])
    assert np.allclose(got, want, rtol=0.0, atol=1e-9)  # the mount alone: off by metres
    assert [r[:2] for r in plain] == [r[:2] for r in mounted]
    assert not any("not used" in line for line in runs[False][1])
    assert sum("not used" in line for line in runs[True][1]) == 2


def test_mount_still_wins_where_its_parent_is_in_the_recording(tmp_path: Path) -> None:
    """Correcting a recording's wrong laser mount (odom -> base_link on /tf, base_link ->
    laser on /tf_static) with --mount keeps working: the mount is used, no note."""
    path = tmp_path / "robot.mcap"
    with open_bag(path) as sink:
        sink.pose(0.0, "base_link", "laser", Pose2D(9.0, 9.0, 1.0), "/tf_static")
        for i in range(5):
            t = 1.0 + 0.1 * i
            sink.pose(t, "odom", "base_link", _robot(t), "/tf")
            sink.scan(_scan(t, "laser", None), "/laser", "laser")
    with RosbagRecording(path, mounts=parse_mounts(["laser=base_link:0.5,0,0"])) as rec:
        poses = [(s.stamp, s.pose) for s in rec.scans()]
        assert rec.mount_notes == [] and rec.pose_frame() == "odom"
    for t, pose in poses:
        want = _robot(t).compose(Pose2D(0.5, 0.0, 0.0))
        assert pose is not None
        assert abs(pose.x - want.x) < 1e-9 and abs(pose.y - want.y) < 1e-9


def test_mounts_to_use_leaves_out_only_mounts_whose_parent_the_recording_lacks() -> None:
    own = TransformTree()
    own.add_track("odom", "base_link", np.array([0.0, 1.0]), np.zeros((2, 3)), source="/tf")
    own.add_static("base_link", "a", Pose2D(1.0, 0.0, 0.0), source="/tf_static")
    own.add_track("world", "b", np.array([0.0, 1.0]), np.zeros((2, 3)), source="/tf")
    mounts = {
        "a": ("base_link", Pose2D(2.0, 0.0, 0.0)),  # same parent: a correction, used
        "b": ("base_footprint", Pose2D(0.0, 0.0, 0.0)),  # parent unknown, b placed: left out
        "c": ("base_footprint", Pose2D(0.0, 1.0, 0.0)),  # laser not in the recording: used
        "d": ("base_link", Pose2D(0.0, 0.0, 0.0)),  # new laser on a known frame: used
    }
    use, notes = mounts_to_use(mounts, own.edges())
    assert sorted(use) == ["a", "c", "d"]
    assert len(notes) == 1 and notes[0].startswith("mount of 'b' on 'base_footprint' not used")
    assert "/tf already places 'b' in 'world'" in notes[0]


def test_live_leaves_out_the_same_mounts_when_a_recording_is_replayed_into_it() -> None:
    """`live --mount mir100` fed a recording's /tf (world -> laser): poses in 'world' as the
    recording holds them, as `track` gives them, not the mount alone in base_footprint."""
    from laserpeople.live.messages import TransformSample
    from laserpeople.live.poses import LiveTransforms

    tf = LiveTransforms(mounts=parse_mounts(["mir100"]))
    mount = MIR100_LASER_MOUNTS["front_laser_link"][1]
    for t in (1.0, 1.1):
        pose = _robot(t).compose(mount)
        tf.add(
            [TransformSample(WORLD_FRAME_ID, "front_laser_link", t, pose, 0.0)],
            static=False,
            source="/tf",
        )
    pose, reason, settled = tf.lookup("front_laser_link", 1.1)
    want = _robot(1.1).compose(mount)
    assert pose is not None and settled, reason
    assert tf.world_frame == WORLD_FRAME_ID
    assert abs(pose.x - want.x) < 1e-9 and abs(pose.y - want.y) < 1e-9
    assert abs(math.remainder(pose.theta - want.theta, 2 * math.pi)) < 1e-9
    assert (
        len(tf.mount_notes) == 1 and "'front_laser_link' on 'base_footprint'" in (tf.mount_notes[0])
    )


def test_stray_mount_notes_name_only_children_nothing_else_names() -> None:
    """A misspelt laser frame and a topic given as CHILD are stray; a laser frame, a frame
    of the recording's transforms and a link of a chain of given mounts are not."""
    from laserpeople.io.poses import stray_mount_notes

    mounts = parse_mounts(
        [
            "laser=base_link:0.2,0,0",  # the laser's frame id
            "base_link=base_footprint:0,0,0",  # a chain: base_link is laser's parent
            "imu=odom:0,0,0",  # a frame the transforms name
            "front_laser=base_link:0.4,0,0",  # misspelt
            "/scan=base_link:0.1,0,0",  # the topic, not the frame id
        ]
    )
    notes = stray_mount_notes(mounts, {"/scan": "laser"}, ["odom", "imu"])
    assert len(notes) == 2
    assert notes[0].startswith("mount of 'front_laser' not used")
    assert notes[1].startswith("mount of 'scan' not used")
    assert all("/scan 'laser'" in n for n in notes)


def _robot_bag(path: Path, lasers: list[tuple[str, str]]) -> Path:
    """A bag of 5 scans at 10 Hz of each (topic, frame id) of ``lasers`` (the k-th 0.02 k s
    after the first), with the robot's odometry on ``/tf``."""
    with open_bag(path) as sink:
        for i in range(5):
            t = 1.0 + 0.1 * i
            sink.pose(t, "odom", "base_link", _robot(t), "/tf")
            for k, (topic, frame) in enumerate(lasers):
                sink.scan(_scan(t + 0.02 * k, frame, None), topic, frame)
    return path


def test_bag_notes_a_mount_its_lasers_do_not_have(tmp_path: Path) -> None:
    path = _robot_bag(tmp_path / "robot.mcap", [("/front_scan", "laser")])
    specs = ["laser=base_link:0.5,0,0", "front_scan=base_link:0.5,0,0"]
    with RosbagRecording(path, mounts=parse_mounts(specs)) as rec:
        assert all(s.pose is not None for s in rec.scans())
        assert len(rec.mount_notes) == 1
        assert "'front_scan' not used" in rec.mount_notes[0]
        assert "/front_scan 'laser'" in rec.mount_notes[0]


def test_track_says_which_mount_was_not_used_before_it_stops(tmp_path: Path) -> None:
    """Two lasers without poses cannot be fused: the error comes with the note that the
    given mounts name no laser (their topics were given, not their frame ids)."""
    from typer.testing import CliRunner

    from laserpeople.cli import app

    lasers = [("/front_scan", "laser_a"), ("/back_scan", "laser_b")]
    path = _robot_bag(tmp_path / "two.mcap", lasers)
    args = ["track", str(path), "--topics", "all", "-o", str(tmp_path / "t.csv")]
    mounts = ["--mount", "front_scan=base_link:0.4,0,0", "--mount", "back_scan=base_link:-0.4,0,3"]
    result = CliRunner().invoke(app, [*args, *mounts])
    assert result.exit_code != 0
    out = " ".join(result.output.split())
    assert "several lasers can only be fused" in str(result.exception)
    assert "mount of 'front_scan' not used" in out and "mount of 'back_scan' not used" in out


def test_info_prints_the_note_of_a_stray_mount(tmp_path: Path) -> None:
    from typer.testing import CliRunner

    from laserpeople.cli import app

    path = tmp_path / "one.mcap"
    with open_bag(path) as sink:
        for i in range(3):
            sink.scan(_scan(1.0 + 0.1 * i, "laser", None), "/scan", "laser")
    result = CliRunner().invoke(app, ["info", str(path), "--mount", "front_laser=base_link:1,0,0"])
    assert result.exit_code == 0, result.output
    out = " ".join(result.output.split())
    assert "mount of 'front_laser' not used" in out and "/scan 'laser'" in out
