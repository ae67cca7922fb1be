"""Live grouping of several lasers: frames close as soon as every laser delivered, the wait is
bounded by the lasers' measured period, late scans join the next frame; all counted.

The clocks are fakes: the tests count frames and scans, they time nothing.
"""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np
import pytest

from laserpeople.frame import Frame
from laserpeople.live.choice import FrameDecision
from laserpeople.live.grouping import FIRST_WAIT, MAX_RECENT, LiveGrouper
from laserpeople.live.source import LiveFrames, LiveScans, TimeJump
from laserpeople.pipeline.sources import LaserGrouper
from laserpeople.scan import Pose2D, Scan

FRONT, BACK = "/front", "/back"
PERIOD = 0.079  # the MiR lasers: 12.7 Hz each, the back one 30-43 ms after the front one


def _scan(stamp: float, sensor: str, index: int = 0) -> Scan:
    return Scan.from_angles(
        stamp, -1.0, 1.0, 0.5, np.array([1.0, 2.0, 3.0, 4.0, 5.0]), sensor=sensor, index=index
    )


def _ids(frames: list[Frame]) -> list[tuple[tuple[str, int], ...]]:
    return [tuple((s.sensor, s.index) for s in f.scans) for f in frames]


def test_a_frame_closes_when_the_other_laser_delivered_not_at_the_next_scan() -> None:
    grouper = LiveGrouper([FRONT, BACK])
    assert grouper.push(_scan(10.000, FRONT, 0), arrival=0.000) == []
    # the first frame waits for the reference period (its tolerance) ...
    assert grouper.push(_scan(10.035, BACK, 0), arrival=0.035) == []
    first = grouper.push(_scan(10.079, FRONT, 1), arrival=0.079)
    assert _ids(first) == [((FRONT, 0), (BACK, 0))]
    # ... the next ones close at their back scan, not at the next front scan 79 ms later
    frames = grouper.push(_scan(10.114, BACK, 1), arrival=0.114)
    assert _ids(frames) == [((FRONT, 1), (BACK, 1))]
    assert grouper.stats.complete == 2 and grouper.stats.closed_by_wait == 0
    assert grouper.deadline() is None  # nothing left open


def test_synchronised_lasers_close_a_frame_at_the_partner_scan_of_the_same_stamp() -> None:
    # two lasers triggered together: the partner's scan carries the reference's own stamp,
    # which is as new as the frame needs (no wait for a newer one)
    grouper = LiveGrouper([FRONT, BACK])
    frames: list[Frame] = []
    for i in range(3):
        t = 10 + i * PERIOD
        frames += grouper.push(_scan(t, FRONT, i), arrival=i * PERIOD)
        frames += grouper.push(_scan(t, BACK, i), arrival=i * PERIOD + 0.001)
    # the first frame closes once the reference period (its tolerance) is known; each later
    # one at its own partner scan, never by the wait
    assert _ids(frames) == [((FRONT, i), (BACK, i)) for i in range(3)]
    assert grouper.stats.closed_by_wait == 0 and grouper.deadline() is None


def test_a_frame_waits_one_measured_period_of_the_other_laser_and_a_late_scan_is_counted() -> None:
    grouper = LiveGrouper([FRONT, BACK])
    frames: list[Frame] = []
    for i in range(4):  # periods measured: the back laser's is 80 ms, the front's 79 ms
        arrival = 10.03 + i * 0.08
        frames += grouper.push(_scan(10 + i * PERIOD, FRONT, i), arrival - 0.03)
        frames += grouper.push(_scan(10.03 + i * 0.08, BACK, i), arrival)
    assert len(frames) == 4 and grouper.stats.complete == 4
    assert grouper.wait() == pytest.approx(0.08)  # the slowest other laser's period
    t4 = 10 + 4 * PERIOD
    assert grouper.push(_scan(t4, FRONT, 4), arrival=1.0) == []
    assert grouper.deadline() == pytest.approx(1.08)
    assert grouper.expire(1.079) == []
    closed = grouper.expire(1.081)  # the wait ran out: the frame leaves without /back
    assert _ids(closed) == [((FRONT, 4),)]
    assert closed[0].missing == (BACK,)
    assert grouper.stats.closed_by_wait == 1
    # /back's scan of that instant comes late: counted, in no frame (track on the recording,
    # which does not hold it, groups the next frames as live does)
    assert grouper.push(_scan(t4 + 0.040, BACK, 4), arrival=1.12) == []
    assert grouper.stats.late[BACK] == 1
    assert grouper.push(_scan(t4 + PERIOD, FRONT, 5), arrival=1.16) == []
    nxt = grouper.push(_scan(t4 + PERIOD + 0.045, BACK, 5), arrival=1.21)
    assert _ids(nxt) == [((FRONT, 5), (BACK, 5))]
    assert grouper.stats.frames == 6 and grouper.stats.complete == 5
    summary = grouper.stats.summary()
    assert "5 with every laser, 1 without some" in summary
    assert "1 closed by the wait (80.0 ms)" in summary
    assert "1 late (came after their frame left; in no frame)" in summary


def test_the_wait_before_the_periods_are_measured_and_a_fixed_one() -> None:
    assert LiveGrouper([FRONT, BACK]).wait() == FIRST_WAIT
    assert LiveGrouper([FRONT, BACK], wait=0.02).wait() == 0.02


def test_live_frames_are_the_frames_a_recording_of_the_same_scans_gives() -> None:
    """Scans arriving with jittered delays, each laser in order, the lasers interleaved in
    any order: when no wait runs out, the frames are LaserGrouper's on the recording (so
    `track` on live's recording groups as live did)."""
    rng = np.random.default_rng(3)
    events = []  # (arrival, scan)
    for i in range(200):
        t = 100 + i * PERIOD + rng.uniform(-0.002, 0.002)
        if i != 50:  # the front laser misses a scan: /back's of that instant is unmatched
            events.append((t + rng.uniform(0.0, 0.03), _scan(t, FRONT, i)))
        if i not in (70, 71):  # the back laser misses two: two frames without it
            tb = t + rng.uniform(0.030, 0.043)
            events.append((tb + rng.uniform(0.0, 0.03), _scan(tb, BACK, i)))
    events.sort(key=lambda e: e[0])
    live = LiveGrouper([FRONT, BACK], wait=1.0)
    frames: list[Frame] = []
    for arrival, scan in events:
        frames += live.push(scan, arrival)
    frames += live.flush()
    recorded = list(
        LaserGrouper([FRONT, BACK])(sorted((s for _, s in events), key=lambda s: s.stamp))
    )
    assert _ids(frames) == _ids(recorded)
    assert len(frames) == 199 and live.stats.complete == 197
    assert live.stats.missing[BACK] == 2 and live.stats.unmatched[BACK] == 1
    assert (
        live.stats.closed_by_wait == 0 and live.stats.late[BACK] == 0
    )  # the next back scan closed them


def test_live_frames_give_a_frame_before_the_next_scan_is_taken() -> None:
    """Through LiveScans and LiveFrames: the MiR pattern gives each frame out when its back
    scan is taken, without waiting for the next front scan (the clock advances 1 ms per look,
    so nothing blocks)."""
    ticks = itertools.count()
    scans = LiveScans([FRONT, BACK], depth=10, clock=lambda: next(ticks) * 1e-3)
    for stamp, sensor in ((10.0, FRONT), (10.035, BACK), (10.079, FRONT), (10.114, BACK),
                          (10.158, FRONT)):  # fmt: skip
        scans.put(replace(_scan(stamp, sensor), pose=Pose2D(0.0, 0.0, 0.0)), sensor)
    frames = iter(LiveFrames(scans, FrameDecision("world")))
    assert [s.stamp for s in next(frames).scans] == [10.0, 10.035]
    assert [s.stamp for s in next(frames).scans] == [10.079, 10.114]
    assert scans.counts.taken[FRONT] == 2  # the third front scan was not needed
    assert scans.counts.taken[BACK] == 2


def test_frames_open_at_a_time_jump_are_given_out_before_the_reset() -> None:
    ticks = itertools.count()
    scans = LiveScans([FRONT, BACK], depth=10, clock=lambda: next(ticks) * 1e-3)
    for stamp, sensor in ((10.0, FRONT), (10.035, BACK), (10.079, FRONT), (5.0, FRONT)):
        scans.put(replace(_scan(stamp, sensor), pose=Pose2D(0.0, 0.0, 0.0)), sensor)
    frames = iter(LiveFrames(scans, FrameDecision("world")))
    assert [s.stamp for s in next(frames).scans] == [10.0, 10.035]
    second = next(frames)  # open when the jump came: given out without /back, not lost
    assert [s.stamp for s in second.scans] == [10.079] and second.missing == (BACK,)
    with pytest.raises(TimeJump):
        next(frames)


def test_a_silent_reference_laser_does_not_grow_the_kept_scans() -> None:
    grouper = LiveGrouper([FRONT, BACK])
    for i in range(MAX_RECENT + 10):
        assert grouper.push(_scan(10 + i * PERIOD, BACK, i), i * PERIOD) == []
    assert grouper.stats.unmatched[BACK] == 10  # the oldest, counted: no frame took them
    assert len(grouper.flush()) == 0 and grouper.stats.unmatched[BACK] == MAX_RECENT + 10


def test_a_slow_tracker_does_not_close_frames_whose_scans_wait_in_the_queue() -> None:
    """The tracker takes the scans long after their wait ran out (it was busy): the frames
    still get the scans that had arrived, none is closed by the wait."""
    clock = [0.0]
    scans = LiveScans([FRONT, BACK], depth=10, clock=lambda: clock[0])
    for stamp, sensor in ((10.0, FRONT), (10.035, BACK), (10.079, FRONT), (10.114, BACK),
                          (10.158, FRONT)):  # fmt: skip
        clock[0] = stamp - 10.0  # arrival
        scans.put(replace(_scan(stamp, sensor), pose=Pose2D(0.0, 0.0, 0.0)), sensor)
    clock[0] = 5.0  # the tracker comes back 5 s later
    frames = LiveFrames(scans, FrameDecision("world"))
    it = iter(frames)
    assert [s.stamp for s in next(it).scans] == [10.0, 10.035]
    assert [s.stamp for s in next(it).scans] == [10.079, 10.114]
    assert frames.grouper is not None and frames.grouper.stats.closed_by_wait == 0


def test_with_late_scans_track_on_what_live_tracked_groups_as_live_did() -> None:
    """The MiR pattern: each back scan is within the tolerance of two front scans (42 ms
    after one, 37 ms before the next). Some back scans come after their frame's wait ran
    out. The frames live gives out are those LaserGrouper makes from the scans they hold
    (what `--record` writes), so `track` on the recording gives the same frames."""
    rng = np.random.default_rng(5)
    events = []  # (arrival, scan)
    back_arrival = 0.0
    for i in range(300):
        t = 100 + i * PERIOD
        events.append((t + 0.002, _scan(t, FRONT, i)))
        delay = 0.2 if i % 37 == 5 else rng.uniform(0.0, 0.01)  # some come 200 ms late ...
        back_arrival = max(back_arrival, t + 0.042 + delay)  # ... and hold up the next ones
        events.append((back_arrival, _scan(t + 0.042, BACK, i)))
    events.sort(key=lambda e: e[0])
    live = LiveGrouper([FRONT, BACK])
    frames: list[Frame] = []
    for arrival, scan in events:
        frames += live.push(scan, arrival)
        frames += live.expire(arrival)
    frames += live.flush()
    assert live.stats.late[BACK] == 24 and live.stats.closed_by_wait == 24  # 8 delays x 3
    held = sorted((s for f in frames for s in f.scans), key=lambda s: s.stamp)
    assert _ids(frames) == _ids(list(LaserGrouper([FRONT, BACK])(held)))


def test_with_several_lasers_a_pass_delayed_by_one_period_drops_nothing() -> None:
    """Each laser delivers two scans while the tracker is busy: kept with several lasers
    (queue of 2 each), the older one dropped and counted with one laser (queue of 1)."""
    several = LiveScans([FRONT, BACK], clock=lambda: 0.0)
    one = LiveScans([FRONT], clock=lambda: 0.0)
    for stamp in (10.0, 10.079):
        several.put(_scan(stamp, FRONT), "f")
        several.put(_scan(stamp + 0.042, BACK), "b")
        one.put(_scan(stamp, FRONT), "f")
    assert sum(several.counts.dropped.values()) == 0 and several.waiting() == 4
    assert one.counts.dropped[FRONT] == 1 and one.waiting() == 1
