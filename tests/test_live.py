"""`laserpeople live`: keys, CDR, bounded queues, time jumps, and real runs on loopback Zenoh
(a bag played as CDR LaserScan + tf into one session, live in another, the people received
in a third) compared with what `track` computes for the same recording."""

from __future__ import annotations

import asyncio
import json
import struct
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("zenoh", reason="needs the live extra (eclipse-zenoh)")
sys.path.insert(0, str(Path(__file__).parent))

from laserpeople.live.keys import (
    BridgeKeys,
    RmwKeys,
    dds_type_name,
    parse_rmw_attachment,
    rmw_attachment,
)
from laserpeople.live.messages import RosDecoder, RosEncoder, ros2_typestore
from laserpeople.live.source import LiveScans, TimeJump
from laserpeople.scan import Pose2D, Scan
from live_harness import Collect, compare, live_rows, track_rows

DEMO = "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag"
MIR = "mir/rosbags/mir_data/legs-test-split-2022-11-21-15-51-02-topic-split.bag"


def _scan(stamp: float, sensor: str = "/scan") -> Scan:
    return Scan.from_angles(
        stamp, -1.0, 1.0, 0.5, np.array([1.0, 2.0, 3.0, 4.0, 5.0]), sensor=sensor
    )


def test_rmw_keys_and_tokens_as_rmw_zenoh_forms_them() -> None:
    store = ros2_typestore()
    keys = RmwKeys(7, store)
    assert dds_type_name("sensor_msgs/msg/LaserScan") == "sensor_msgs::msg::dds_::LaserScan_"
    # REP 2011 hash of std_msgs/msg/String as ROS 2 Jazzy publishes it
    assert keys.type_hash("std_msgs/msg/String") == (
        "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"
    )
    key = keys.key("/robot/scan/", "sensor_msgs/msg/LaserScan")
    assert key.startswith("7/robot/scan/sensor_msgs::msg::dds_::LaserScan_/RIHS01_")
    assert keys.subscription("/scan", "sensor_msgs/msg/LaserScan").endswith("LaserScan_/*")
    token = keys.endpoint_token("abc", 3, "MP", "/laserpeople/people", "people_msgs/msg/People")
    parts = token.split("/")
    assert parts[:9] == ["@ros2_lv", "7", "abc", "0", "3", "MP", "%", "%", "laserpeople"]
    assert parts[9] == "%laserpeople%people" and parts[10] == "people_msgs::msg::dds_::People_"
    assert parts[12] == "::,:,:,:,,"
    assert (
        RmwKeys(0, store, "none")
        .key("/scan", "sensor_msgs/msg/LaserScan")
        .endswith("/TypeHashNotSupported")
    )
    assert BridgeKeys().key("/scan", "x/msg/Y") == "scan"
    assert BridgeKeys("bot1").key("/scan", "x/msg/Y") == "bot1/scan"


def test_rmw_attachment_is_zenoh_ext_serialisation() -> None:
    from zenoh.ext import Int64, z_serialize

    gid = bytes(range(16))
    ours = rmw_attachment(5, 1_700_000_000_000_000_000, gid)
    theirs = z_serialize((Int64(5), Int64(1_700_000_000_000_000_000), gid)).to_bytes()
    assert ours == theirs
    assert parse_rmw_attachment(ours) == (5, 1_700_000_000_000_000_000, gid)
    assert struct.unpack_from("<q", ours)[0] == 5


def test_laserscan_and_tf_round_trip_through_cdr() -> None:
    store = ros2_typestore()
    enc, dec = RosEncoder(store), RosDecoder(store)
    scan = _scan(12.25)
    back, frame_id = dec.scan(enc.scan(scan, "/scan", "laser"), "/scan", 3)
    assert frame_id == "laser" and back.stamp == pytest.approx(12.25, abs=1e-9)
    np.testing.assert_allclose(back.ranges, scan.ranges, atol=1e-6)
    assert back.angle_increment == pytest.approx(0.5, abs=1e-7)
    (tf,) = dec.transforms(enc.transform(3.5, "odom", "base", Pose2D(1.0, -2.0, 0.5)), "/tf")
    assert (tf.parent, tf.child) == ("odom", "base")
    assert (tf.pose.x, tf.pose.y) == pytest.approx((1.0, -2.0)) and tf.pose.theta == pytest.approx(
        0.5
    )
    with pytest.raises(Exception, match="cannot decode"):
        dec.scan(b"\x00\x01\x00\x00garbage", "/scan", 0)


def test_queue_keeps_the_newest_per_laser_and_counts_drops() -> None:
    scans = LiveScans(["/a", "/b"], depth=1)
    for t in (1.0, 1.1, 1.2):
        scans.put(_scan(t, "/a"), "la")
    scans.put(_scan(1.15, "/b"), "lb")
    assert scans.counts.dropped["/a"] == 2 and scans.counts.dropped["/b"] == 0
    first, second = scans.take(0.1), scans.take(0.1)
    assert first is not None and second is not None
    assert (first.scan.sensor, first.scan.stamp) == ("/b", 1.15)  # oldest stamp first
    assert (second.scan.stamp, second.scan.index) == (1.2, 2)  # the newest, its arrival count
    assert scans.take(0.05) is None


def test_time_jump_resets_and_the_scan_is_not_lost() -> None:
    scans = LiveScans(["/scan"], depth=10)
    for t in (100.0, 100.1, 3.0):
        scans.put(_scan(t), "laser")
    it = scans.scans()
    assert [next(it).stamp, next(it).stamp] == [100.0, 100.1]
    with pytest.raises(TimeJump, match=r"jumped -97\.100 s"):
        next(it)
    scans.finish()
    assert [s.stamp for s in scans.scans()] == [3.0]
    assert scans.counts.resets == 1


@pytest.mark.slow
def test_live_run_resets_tracking_on_a_time_jump() -> None:
    """A bag played twice in a loop: the second pass starts new tracks, with a warning."""
    from laserpeople.live.runner import LiveRun, tracker_pipelines
    from laserpeople.sim.scenarios import run_scenario

    rec = run_scenario("demo", seconds=2.0, seed=3)
    scans = LiveScans([rec.scans[0].sensor], depth=10_000)
    for s in [*rec.scans, *rec.scans]:
        scans.put(s, "laser")
    scans.finish()
    resets: list[str] = []
    sink = Collect()
    run = LiveRun(
        scans, tracker_pipelines("leg-mht"), [sink], frame="sensor", on_reset=resets.append
    )
    stats = run.run()
    assert len(resets) == 1 and "tracking reset" in resets[0]
    assert stats.frames == 2 * len(rec.scans)


@pytest.fixture(scope="module")
def sim_bag(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from laserpeople.sim.scenarios import run_scenario

    path = tmp_path_factory.mktemp("live") / "walk.bag"
    run_scenario("demo", seconds=4.0, seed=3).write(path)
    return path


@pytest.mark.slow
def test_live_equals_track_on_a_simulated_recording(sim_bag: Path) -> None:
    from laserpeople.io import open_recording

    with open_recording(sim_bag) as rec:
        topic = rec.topics()[0].name
        n = rec.topics()[0].count
    offline = track_rows(sim_bag, [topic], frame="sensor")
    result = live_rows(sim_bag, [topic], max_scans=n, speed=2.0, frame="sensor")
    assert sum(result.session.scans.counts.dropped.values()) == 0
    assert result.received == n
    assert sum(len(v) for v in offline.values()) > 20  # people and legs were tracked
    assert compare(result.rows, offline) == []


@pytest.mark.slow
@pytest.mark.shared
def test_live_equals_track_on_the_real_demo_bag(shared_data: Path) -> None:
    bag = shared_data / DEMO
    offline = track_rows(bag, ["/scan"], max_frames=200)
    result = live_rows(bag, ["/scan"], max_scans=200, speed=4.0)
    assert sum(result.session.scans.counts.dropped.values()) == 0
    assert any(kind == "person" for rows in offline.values() for kind, *_ in rows)
    assert compare(result.rows, offline) == []
    assert result.stats.published == 200 and len(result.stats.arrival_ms) == 200


@pytest.mark.slow
@pytest.mark.shared
def test_live_auto_on_the_real_demo_bag_tracks_in_the_sensor_frame_from_the_first_scan(
    shared_data: Path,
) -> None:
    """leg_tracker's demo bag has no tf: the default `--frame auto` holds no frame, waits for
    transforms once, then stops looking them up, and publishes what `track` computes."""
    bag = shared_data / DEMO
    offline = track_rows(bag, ["/scan"], max_frames=200)
    result = live_rows(bag, ["/scan"], max_scans=200, speed=4.0, frame="auto", tf_wait=0.1)
    counts = result.session.scans.counts
    decision = result.session.run.decision
    assert sum(counts.dropped.values()) == 0
    assert decision.frame == "sensor" and 1 < decision.looked_at < 200
    assert counts.waited_for_tf == 0  # no scan waited for a transform
    assert sum(counts.without_pose.values()) == decision.looked_at  # no lookup once decided
    assert result.stats.published == 200
    assert compare(result.rows, offline) == []


@pytest.mark.slow
@pytest.mark.shared
def test_live_equals_track_on_the_mir_bag_through_rmw_zenoh_keys(shared_data: Path) -> None:
    """Two lasers fused in the world frame (tf + --mount mir100), rmw_zenoh keys, tokens."""
    bag = shared_data / MIR
    topics = ["front_laser_link", "back_laser_link"]
    offline = track_rows(bag, topics, ["mir100"], max_frames=100)
    result = live_rows(
        bag, topics, transport="rmw", mounts=["mir100"], frame="world", max_scans=200, speed=4.0
    )
    counts = result.session.scans.counts
    assert sum(counts.dropped.values()) == 0 and sum(counts.without_pose.values()) == 0
    assert counts.tf_timeouts == 0
    assert compare(result.rows, offline) == []
    assert all(k.startswith("0/laserpeople/") for k in result.people_keys)
    kinds = {t.split("/")[5] for t in result.tokens}
    assert {"NN", "MP", "MS"} <= kinds  # node, publishers and subscriptions announced
    assert any(
        "%laserpeople%people/people_msgs::msg::dds_::People_/RIHS01_" in t for t in result.tokens
    )


@pytest.mark.slow
def test_foxglove_client_receives_scans_and_people(sim_bag: Path) -> None:
    pytest.importorskip("foxglove", reason="needs the live extra (foxglove-sdk)")
    websockets = pytest.importorskip("websockets", reason="needs the live extra (websockets)")
    from laserpeople.io import open_recording
    from laserpeople.live.foxglove import FoxgloveSink

    with open_recording(sim_bag) as rec:
        n = rec.topics()[0].count
        topic = rec.topics()[0].name
    scan_topic = topic if topic.startswith("/") else "/" + topic
    viewer = FoxgloveSink(0, lasers=[topic])
    url = f"ws://127.0.0.1:{viewer.port}"
    got: dict[str, int] = {}
    ready = threading.Event()
    done = threading.Event()

    async def client() -> None:
        async with websockets.connect(url, subprotocols=["foxglove.sdk.v1"]) as ws:
            channels: dict[int, str] = {}
            subscribed: set[int] = set()
            ready.set()
            deadline = time.monotonic() + 60
            while time.monotonic() < deadline and not done.is_set():
                try:
                    raw = await asyncio.wait_for(ws.recv(), 0.5)
                except TimeoutError:
                    continue
                if isinstance(raw, str):
                    msg = json.loads(raw)
                    if msg.get("op") == "advertise":
                        new = []
                        for ch in msg["channels"]:
                            channels[ch["id"]] = ch["topic"]
                            if ch["id"] not in subscribed:
                                subscribed.add(ch["id"])
                                new.append({"id": ch["id"], "channelId": ch["id"]})
                        if new:
                            await ws.send(json.dumps({"op": "subscribe", "subscriptions": new}))
                elif raw[0] == 1:  # message data: opcode, subscription id (u32), time, payload
                    sub_id = struct.unpack_from("<I", raw, 1)[0]
                    topic = channels[sub_id]
                    got[topic] = got.get(topic, 0) + 1
                    wanted = ("/laserpeople/people", "/laserpeople/legs", scan_topic)
                    if all(got.get(t, 0) > 5 for t in wanted):
                        return

    thread = threading.Thread(target=lambda: asyncio.run(client()), daemon=True)
    thread.start()
    assert ready.wait(10)
    try:
        # the channels are advertised on first use; keep the run going until the client has data
        result = live_rows(sim_bag, [topic], max_scans=n, speed=2.0, extra_sinks=[viewer])
        done.set()
        thread.join(10)
    finally:
        done.set()
    assert result.stats.frames > 0
    assert got.get(scan_topic, 0) > 0, got
    assert got.get("/laserpeople/people", 0) > 0 and got.get("/laserpeople/legs", 0) > 0, got


def test_live_without_the_extra_says_what_to_install(monkeypatch: pytest.MonkeyPatch) -> None:
    from typer.testing import CliRunner

    from laserpeople.cli import app

    monkeypatch.setitem(sys.modules, "zenoh", None)  # `import zenoh` raises ImportError
    result = CliRunner().invoke(app, ["live", "--max-scans", "1"])
    assert result.exit_code != 0
    assert "pip install 'laserpeople[live]'" in str(result.exception)


def test_the_oldest_scan_leaves_without_waiting_for_the_other_lasers() -> None:
    clock = [0.0]
    scans = LiveScans(["/front", "/back"], depth=10, clock=lambda: clock[0])
    scans.put(_scan(10.00, "/front"), "f")
    scans.put(_scan(10.08, "/front"), "f")
    item = scans.take(0.0)  # /back has sent nothing yet: the grouping waits, not the queue
    assert item is not None and item.scan.stamp == 10.00
    scans.put(_scan(10.04, "/back"), "b")  # arrives late but is older than the second front
    order = [scans.take(0.0), scans.take(0.0)]
    assert [(i.scan.sensor, i.scan.stamp) for i in order if i is not None] == [
        ("/back", 10.04),
        ("/front", 10.08),
    ]
    assert scans.take(0.0) is None


@pytest.mark.slow
def test_live_command_records_what_track_replays(sim_bag: Path, tmp_path: Path) -> None:
    """`laserpeople live --record`: the recording, tracked by `track`, gives the tracks live
    published; the summary names the latency."""
    from typer.testing import CliRunner

    from laserpeople.cli import app
    from laserpeople.io import open_recording
    from laserpeople.io.tracks_bag import iter_tracks_bag
    from live_harness import free_port, play_when_subscribed

    with open_recording(sim_bag) as rec:
        topic, n = rec.topics()[0].name, rec.topics()[0].count
    port = free_port()
    out = tmp_path / "live.mcap"

    player = play_when_subscribed(sim_bag, topic, port)
    args = ["live", "--topic", topic, "--listen", f"tcp/127.0.0.1:{port}", "--frame", "sensor"]
    args += ["--queue", "100000", "--max-scans", str(n), "--record", str(out), "--duration", "120"]
    result = CliRunner().invoke(app, args)
    player.join(30)
    assert result.exit_code == 0, result.output
    assert f"{topic}: {n} scans received, 0 dropped" in result.output
    assert "latency from arrival to publication: median" in result.output
    live_tracks = {t.scan_index: t for t in iter_tracks_bag(out, ("person", "leg"))}
    replayed = track_rows(out, [topic])
    assert len(live_tracks) > 10
    recorded = {
        i: sorted((tr.kind, tr.track_id, float(tr.position[0]), float(tr.position[1])) for tr in t)
        for i, t in live_tracks.items()
    }
    assert compare(recorded, replayed) == []


def test_live_transforms_interpolate_like_track_and_wait_for_the_robot() -> None:
    from laserpeople.io.poses import parse_mounts
    from laserpeople.live.messages import TransformSample
    from laserpeople.live.poses import LiveTransforms

    tf = LiveTransforms(mounts=parse_mounts(["laser=base_link:0.5,0,0"]))
    # the mount alone names no world frame: wait for the robot's transforms
    pose, reason, settled = tf.lookup("laser", 1.0)
    assert pose is None and not settled and "no transforms" in reason
    tf.add([TransformSample("odom", "base_link", 0.98, Pose2D(1.0, 0.0, 0.0), 0.0)], static=False,
           source="/tf")  # fmt: skip
    pose, _, settled = tf.lookup("laser", 1.0)
    assert not settled  # no sample at or after 1.0 s yet: held (within 0.05 s)
    assert pose is not None and (pose.x, pose.y) == pytest.approx((1.5, 0.0))
    tf.add([TransformSample("odom", "base_link", 1.02, Pose2D(2.0, 0.0, np.pi / 2), 0.0)],
           static=False, source="/tf")  # fmt: skip
    pose, _, settled = tf.lookup("laser", 1.0)
    assert settled and tf.world_frame == "odom"
    # halfway: base at (1.5, 0) heading pi/4; the laser 0.5 m ahead of it
    assert pose is not None
    assert (pose.x, pose.y, pose.theta) == pytest.approx(
        (1.5 + 0.5 * np.cos(np.pi / 4), 0.5 * np.sin(np.pi / 4), np.pi / 4)
    )
    tf.reset()
    assert tf.lookup("laser", 1.0)[0] is None  # time-varying transforms forgotten
