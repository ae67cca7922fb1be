"""`live --record`: each frame's tracks are encoded once, published and recorded from the
same bytes, and the recording reads back as a `track --bag` output (frame tag, topics)."""

from __future__ import annotations

import dataclasses
from collections import Counter
from pathlib import Path
from typing import Any

import pytest

from laserpeople.errors import ConfigError
from laserpeople.io.tracks_bag import MARKERS_TYPE, PEOPLE_TYPE, iter_tracks_bag
from laserpeople.live.messages import Message, TrackEncoder, ros2_typestore
from laserpeople.live.runner import tracker_pipelines
from laserpeople.live.sinks import LiveStats, PublishSink, RecordSink
from laserpeople.live.source import LiveScans
from laserpeople.pipeline.sources import laser_frames
from laserpeople.scan import Pose2D, Scan

FRAMES = 40
POSE = Pose2D(2.0, -1.0, 0.5)
"""Pose of the laser in the world frame [m, m, rad] in the world-frame runs."""


def _scans(world: bool) -> list[Scan]:
    """The first ``FRAMES`` scans of the simulated ``demo`` scene (people walking past one
    laser, 10 Hz), posed at ``POSE`` in the world-frame runs."""
    from laserpeople.sim import run_scenario

    result = run_scenario("demo", seconds=FRAMES / 10 + 1, seed=0, rate=10.0)
    first = result.scans[0].sensor
    scans = [s for s in result.scans if s.sensor == first][:FRAMES]
    assert len(scans) == FRAMES
    return [dataclasses.replace(s, sensor="/scan", pose=POSE if world else None) for s in scans]


class Counting:
    """Wraps a typestore's ``serialize_cdr`` to count the messages serialised per type."""

    def __init__(self, typestore: Any) -> None:
        self.counts: Counter[str] = Counter()
        original = typestore.serialize_cdr

        def serialize_cdr(msg: Any, msgtype: str, *args: Any, **kwargs: Any) -> Any:
            self.counts[msgtype] += 1
            return original(msg, msgtype, *args, **kwargs)

        typestore.serialize_cdr = serialize_cdr


def _run(out: Path, world: bool, prefix: str = "/laserpeople") -> tuple[list[Message], Any]:
    """Track the scans with leg-mht, publishing (into a list) and recording into ``out``;
    the published messages and the serialisations counted on both typestores."""
    store = ros2_typestore()
    counting = Counting(store)
    encoder = TrackEncoder(store, prefix)
    encoder.sink.frame_ids.update({"world": "odom", "scan": "base_laser"})
    published: list[Message] = []
    publish = PublishSink(published.extend, encoder, LiveScans(["/scan"], None), LiveStats())
    record = RecordSink(out, encoder)
    counting_bag = Counting(record._writer.sink.typestore)
    frames = (
        f.with_fields(frame="world" if world else "sensor") for f in laser_frames(_scans(world))
    )
    tracker_pipelines("leg-mht")(frames, [publish, record]).run()
    counting.counts.update(counting_bag.counts)
    return published, (counting, encoder, publish)


@pytest.mark.parametrize("world", [False, True])
def test_each_frame_is_encoded_once_when_publishing_and_recording(
    tmp_path: Path, world: bool
) -> None:
    published, (counting, encoder, publish) = _run(tmp_path / "run.mcap", world)
    frames = publish.stats.published
    assert frames == FRAMES
    assert encoder.encoded == frames  # not 2 per frame
    # 3 People (people, legs, groups) and 1 MarkerArray per frame, over both typestores
    assert counting.counts[PEOPLE_TYPE] == 3 * frames
    assert counting.counts[MARKERS_TYPE] == frames
    # the recording serialises only what is not published: the scans (and their poses)
    assert counting.counts["sensor_msgs/msg/LaserScan"] == frames
    assert counting.counts["tf2_msgs/msg/TFMessage"] == (frames if world else 0)
    assert len(published) == 4 * frames


def _recorded(path: Path) -> dict[str, list[bytes]]:
    """Topic -> the raw bytes of its messages in the recording, in order."""
    from laserpeople.io.bag_guard import open_reader
    from laserpeople.io.tracks_bag import register_people_types

    out: dict[str, list[bytes]] = {}
    reader = open_reader(path, register=register_people_types, hint="")
    try:
        for conn, _, raw in reader.messages():
            out.setdefault(conn.topic, []).append(bytes(raw))
    finally:
        reader.close()
    return out


@pytest.mark.parametrize("prefix", ["/laserpeople", "/robot/people_out"])
def test_recorded_tracks_are_the_published_bytes_on_the_track_bag_topics(
    tmp_path: Path, prefix: str
) -> None:
    out = tmp_path / "run.mcap"
    published, _ = _run(out, world=True, prefix=prefix)
    recorded = _recorded(out)
    by_topic: dict[str, list[bytes]] = {}
    for m in published:
        by_topic.setdefault(m.topic, []).append(m.data)
    names = {"people": "/laserpeople/people", "legs": "/laserpeople/legs"}
    names |= {"groups": "/laserpeople/groups", "markers": "/laserpeople/markers"}
    for leaf, topic in names.items():
        sent = by_topic[f"{prefix}/{leaf}"]
        assert len(sent) == FRAMES
        assert recorded[topic] == sent
    assert len(recorded["/scan"]) == FRAMES and len(recorded["/tf"]) == FRAMES


@pytest.mark.parametrize("world", [False, True])
def test_the_recording_reads_back_in_the_frame_tracked_whatever_the_header_names(
    tmp_path: Path, world: bool
) -> None:
    """Headers carry the robot's frame ids (``odom``, ``base_laser``); the ``frame`` tag
    still tells world from sensor positions, and the tracks are those published."""
    out = tmp_path / "run.mcap"
    published, _ = _run(out, world=world)
    store = ros2_typestore()
    sent = [
        store.deserialize_cdr(m.data, PEOPLE_TYPE) for m in published if m.msgtype == PEOPLE_TYPE
    ]
    assert {m.header.frame_id for m in sent} == {"odom" if world else "base_laser"}
    back = list(iter_tracks_bag(out))
    assert back and {t.frame for t in back} == {"world" if world else "sensor"}
    sent_rows = sorted(
        (p.name, round(p.position.x, 6), round(p.position.y, 6)) for m in sent for p in m.people
    )
    back_rows = sorted(
        (str(t.track_id), round(float(t.position[0]), 6), round(float(t.position[1]), 6))
        for tracks in back
        for t in tracks
    )
    assert len(back_rows) > FRAMES and back_rows == sent_rows  # to 1 µm


def test_record_refuses_a_ros1_bag(tmp_path: Path) -> None:
    encoder = TrackEncoder(ros2_typestore())
    with pytest.raises(ConfigError, match="ROS 1"):
        RecordSink(tmp_path / "run.bag", encoder)
    assert not (tmp_path / "run.bag").exists()


def test_planned_defaults_give_each_message_its_own_lists_and_arrays() -> None:
    """Defaults come from a plan made once per type: lists and fixed-size arrays are new per
    message (also inside left-out nested messages), given fields are kept, left-out nested
    messages are zero."""
    from laserpeople.io.tracks_bag import build_message

    store = ros2_typestore()
    a = build_message(store, "visualization_msgs/msg/Marker", id=7, text="P7")
    b = build_message(store, "visualization_msgs/msg/Marker")
    a.points.append(build_message(store, "geometry_msgs/msg/Point", x=1.0))
    assert b.points == [] and len(a.points) == 1 and a.points[0].x == 1.0
    assert (a.id, a.text, b.id, b.text) == (7, "P7", 0, "")
    assert a.lifetime.sec == 0 and a.texture.data.size == 0 and a.texture.header.frame_id == ""
    odom = build_message(store, "nav_msgs/msg/Odometry")
    other = build_message(store, "nav_msgs/msg/Odometry")
    odom.pose.covariance[0] = 2.0
    assert odom.pose.covariance.shape == (36,) and other.pose.covariance[0] == 0.0
    assert other.pose is not odom.pose
