"""`live --frame auto`: the frame is chosen as the frames come, no frame is held for the
choice, transforms are waited for once while undecided, and a late world choice switches
once. Run on a fake clock, without Zenoh: counts, not wall-clock times."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.frame import Frame
from laserpeople.io.poses import parse_mounts
from laserpeople.live.messages import TransformSample
from laserpeople.live.poses import LiveTransforms
from laserpeople.live.runner import LiveRun, tracker_pipelines
from laserpeople.live.source import LiveScans
from laserpeople.scan import Pose2D, Scan
from laserpeople.tracks import Tracks

PERIOD = 0.1
"""Scan period of the fake laser [s] (10 Hz, as leg_tracker's demo bag)."""


def _scan(i: int) -> Scan:
    """A wall at 3 m with two leg-sized bumps at 1.5 m, stamped ``i * PERIOD``."""
    angles = np.linspace(-np.pi / 2, np.pi / 2, 181)
    ranges = np.full(angles.size, 3.0)
    for centre in (-0.1 + 0.002 * i, 0.1 + 0.002 * i):
        ranges[np.abs(angles - centre) < 0.04] = 1.5
    step = float(angles[1] - angles[0])
    return Scan.from_angles(
        100.0 + i * PERIOD, float(angles[0]), float(angles[-1]), step, ranges, sensor="/scan"
    )


class Clock:
    """A settable clock [s]."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def _arrived(n: int, transforms: LiveTransforms | None, clock: Clock) -> LiveScans:
    """``n`` scans arrived at ``PERIOD`` intervals (queue deep enough to drop none), the
    clock then far past every wait."""
    scans = LiveScans(["/scan"], transforms, depth=1000, tf_wait=0.1, clock=clock)
    for i in range(n):
        clock.now = i * PERIOD
        scans.put(_scan(i), "laser")
    clock.now = 1000.0
    scans.finish()
    return scans


class Seen:
    """A sink noting, per frame, its coordinate frame and how many scans had been taken
    from the receive queue when it was published; ``then`` runs after each frame."""

    def __init__(self, scans: LiveScans, then: object = None) -> None:
        self.scans = scans
        self.then = then
        self.frames: list[tuple[int, str, int]] = []

    def write(self, frame: Frame, tracks: Tracks | None) -> None:
        self.frames.append((frame.index, frame.frame, self.scans.counts.taken["/scan"]))
        if callable(self.then):
            self.then(frame)

    def close(self) -> None:
        """Nothing to flush."""


def test_auto_without_poses_holds_no_frame_and_stops_looking_after_one_second() -> None:
    clock = Clock()
    scans = _arrived(30, LiveTransforms(), clock)
    said: list[str] = []
    seen = Seen(scans)
    run = LiveRun(scans, tracker_pipelines("leg-mht"), [seen], frame="auto", on_choice=said.append)
    stats = run.run()
    assert stats.frames == 30 and [f[0] for f in seen.frames] == list(range(30))
    # every frame is published before the next scan is taken: none waits for the choice
    assert [taken - (index + 1) for index, _, taken in seen.frames] == [0] * 30
    assert {kind for _, kind, _ in seen.frames} == {"sensor"}
    # decided at the first frame that arrived 1 s after the first one (frame 10, 11 looked at)
    assert run.decision.frame == "sensor" and run.decision.index == 10
    assert (
        len(said) == 1 and "sensor frame" in said[0] and "11 frames looked at in 1.00 s" in said[0]
    )
    assert "no transforms received yet" in said[0]
    # poses are looked up only while undecided
    assert scans.counts.without_pose["/scan"] == 11
    assert run.frames is not None and run.frames.summary() == [said[0]]


def test_a_run_ending_before_the_choice_says_what_was_done() -> None:
    clock = Clock()
    scans = _arrived(4, LiveTransforms(), clock)  # 0.3 s of scans: no choice yet
    run = LiveRun(scans, tracker_pipelines("leg-mht"), [], frame="auto")
    assert run.run().frames == 4 and run.decision.undecided
    assert run.frames is not None and run.frames.summary() == [
        "no frame chosen: the run ended after 4 frames without a sensor pose (4 tracked in "
        "the sensor frame, 0 skipped)"
    ]


def _odometry(transforms: LiveTransforms, stamps: np.ndarray) -> None:
    transforms.add(
        [TransformSample("odom", "base_link", float(t), Pose2D(0.01 * k, 0.0, 0.0), 0.0)
         for k, t in enumerate(stamps)],
        static=False,
        source="/odom",
    )  # fmt: skip


def _stream(transforms: LiveTransforms, n: int) -> LiveScans:
    """``n`` scans, each taken as it arrives (a tracker that keeps up), on a clock that moves
    20 ms a call (so that a wait for transforms ends after a few calls)."""
    ticks = [0.0]

    def clock() -> float:
        ticks[0] += 0.02
        return ticks[0]

    scans = LiveScans(["/scan"], transforms, depth=10, tf_wait=0.1, clock=clock)
    scans.undecided = True
    it = scans.scans()
    for i in range(n):
        scans.put(_scan(i), "laser")
        assert next(it).pose is None
    return scans


def test_while_undecided_a_scan_waits_for_transforms_only_once_and_only_when_some_came() -> None:
    assert _stream(LiveTransforms(), 8).counts.waited_for_tf == 0  # a robot without tf
    # a robot whose odometry stopped 1 s before the first scan: the first scan waits for a
    # newer sample, the later ones no more (tf_wait after the first scan is over)
    transforms = LiveTransforms(mounts=parse_mounts(["laser=base_link:0.2,0,0"]))
    _odometry(transforms, np.array([99.0]))
    scans = _stream(transforms, 8)
    assert scans.counts.waited_for_tf == 1
    scans.undecided = False  # (world chosen: each scan waits up to tf_wait again)
    scans.put(_scan(8), "laser")
    next(scans.scans())
    assert scans.counts.waited_for_tf == 2


def test_auto_with_poses_from_the_start_works_in_the_world_frame_at_once() -> None:
    clock = Clock()
    transforms = LiveTransforms(mounts=parse_mounts(["laser=base_link:0.2,0,0"]))
    _odometry(transforms, 100.0 + PERIOD * np.arange(-1, 32))
    scans = _arrived(30, transforms, clock)
    said: list[str] = []
    seen = Seen(scans)
    run = LiveRun(scans, tracker_pipelines("leg-mht"), [seen], frame="auto", on_choice=said.append)
    run.run()
    assert [taken - (index + 1) for index, _, taken in seen.frames] == [0] * 30
    assert {kind for _, kind, _ in seen.frames} == {"world"}
    assert len(said) == 1
    assert said[0] == (
        "working in the world frame 'odom': frame 0 has a sensor pose (1 frame looked at, 0.00 s "
        "after the first scan)"
    )
    assert sum(scans.counts.without_pose.values()) == 0


def test_auto_switches_once_to_the_world_frame_when_poses_come_late() -> None:
    clock = Clock()
    transforms = LiveTransforms(mounts=parse_mounts(["laser=base_link:0.2,0,0"]))
    scans = _arrived(30, transforms, clock)

    def robot_starts(frame: Frame) -> None:  # the robot's odometry comes after frame 2
        if frame.index == 2:
            _odometry(transforms, 100.0 + PERIOD * np.arange(-1, 32))

    said: list[str] = []
    seen = Seen(scans, robot_starts)
    pipelines = tracker_pipelines("leg-mht")
    made: list[object] = []

    def counted(frames: object, sinks: object) -> object:
        made.append(frames)
        return pipelines(frames, sinks)  # type: ignore[arg-type]

    run = LiveRun(scans, counted, [seen], frame="auto", on_choice=said.append)  # type: ignore[arg-type]
    stats = run.run()
    # every frame once, in order; the first three in the sensor frame, then the world frame
    assert [f[0] for f in seen.frames] == list(range(30)) and stats.frames == 30
    assert [kind for _, kind, _ in seen.frames] == ["sensor"] * 3 + ["world"] * 27
    assert [taken - (index + 1) for index, _, taken in seen.frames] == [0] * 30
    assert len(made) == 2  # one new pipeline (a new tracker) for the switch
    assert len(said) == 1 and said[0].startswith(
        "working in the world frame 'odom': frame 3 has a sensor pose (4 frames looked at, 0.30 s "
        "after the first scan)"
    )
    assert "the 3 frames before it were tracked in the sensor frame" in said[0]
    assert run.decision.sensor_frames == 3 and run.decision.index == 3


def test_auto_with_several_lasers_skips_and_counts_frames_until_a_pose() -> None:
    from laserpeople.live.choice import FrameDecision

    decision = FrameDecision("auto", within=1.0)
    posed = _scan(3)
    from dataclasses import replace

    def frame(i: int, scan: Scan) -> Frame:
        return Frame(index=i, stamp=scan.stamp, scans=(scan, scan), topic="fused")

    assert not decision.look(frame(0, _scan(0)), 0.0, reason="no world frame")
    assert not decision.look(frame(1, _scan(1)), 0.5, reason="no world frame")
    assert decision.undecided
    decision.skipped += 2
    assert decision.look(frame(3, replace(posed, pose=Pose2D(1.0, 2.0, 0.0))), 0.7, reason="")
    assert decision.frame == "world" and decision.looked_at == 3
    assert decision.message.endswith("the 2 frames before it had none and were skipped")
    late = FrameDecision("auto", within=1.0)
    late.look(frame(0, _scan(0)), 5.0, reason="r")
    assert late.look(frame(9, _scan(9)), 6.0, reason="no world frame: laser frame not connected")
    assert (
        late.frame == "sensor" and "(2 frames looked at in 1.00 s, up to frame 9;" in late.message
    )
    assert FrameDecision("world").frame == "world"


@pytest.mark.parametrize("requested", ["world", "sensor"])
def test_a_requested_frame_is_not_decided(requested: str) -> None:
    from laserpeople.live.choice import FrameDecision

    decision = FrameDecision(requested)  # type: ignore[arg-type]
    assert not decision.undecided and decision.message.endswith("(as requested)")


def test_warm_up_encodes_tracks_so_the_first_frame_does_not_make_the_serialisers() -> None:
    from laserpeople.live.runner import warm_up

    encoded: list[int] = []

    class Spy:
        def encode(self, scans: tuple[Scan, ...], tracks: Tracks) -> list[object]:
            encoded.append(len(scans))
            return []

    warm_up(tracker_pipelines("leg-mht"), Spy())  # type: ignore[arg-type]
    assert encoded == [1] * 5  # every synthetic frame, one scan each


def test_a_pose_exactly_within_seconds_after_the_first_scan_decides_world() -> None:
    """``within`` is inclusive both ways: a frame arriving exactly ``within`` (1 s) after the
    first scan decides world when it has a pose, sensor when it has none."""
    from dataclasses import replace

    from laserpeople.live.choice import FrameDecision

    def frame(i: int, pose: Pose2D | None) -> Frame:
        return Frame(index=i, stamp=100.0 + i, scans=(replace(_scan(i), pose=pose),), topic="/scan")

    for pose, chosen in ((Pose2D(1.0, 2.0, 0.0), "world"), (None, "sensor")):
        decision = FrameDecision("auto", within=1.0)
        assert not decision.look(frame(0, None), 5.0, reason="no world frame")
        assert not decision.look(frame(1, None), 5.5, reason="no world frame")
        assert decision.look(frame(2, pose), 6.0, reason="no world frame")
        assert decision.frame == chosen and decision.index == 2 and decision.looked_at == 3
        assert abs(decision.seconds - 1.0) < 1e-12
