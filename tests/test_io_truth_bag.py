"""People ground truth from bag topics (leg_tracker/Person, SPENCER TrackedPersons,
people_msgs/People), written here with rosbags' own writer, and the real dev recording
checked against its CSV."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from laserpeople.errors import MessageTypeError, TopicNotFoundError
from laserpeople.io.rosbag_writer import open_bag
from laserpeople.io.truth_bag import (
    LEG_TRACKER_PERSON,
    PEOPLE_MSGS_PEOPLE,
    SPENCER_TRACKED_PERSONS,
    read_truth_bag,
    register_people_types,
    split_truth_spec,
)
from laserpeople.io.truth_csv import read_truth_csv
from laserpeople.scan import Scan


def _scan(k: int, stamp: float) -> Scan:
    inc = math.radians(1.0)
    return Scan.from_angles(
        stamp, -0.5, -0.5 + 9 * inc, inc, np.full(10, 2.0), sensor="/scan", index=k
    )


def _point(types, x: float, y: float):
    return types["geometry_msgs/msg/Point"](x=x, y=y, z=0.0)


def _person(types, pid: int, x: float, y: float):
    pose = types["geometry_msgs/msg/Pose"](
        position=_point(types, x, y),
        orientation=types["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
    )
    return types[LEG_TRACKER_PERSON](pose=pose, id=pid)


def test_leg_tracker_person_labels_pair_with_the_scan_before_them(tmp_path: Path) -> None:
    """Scans at 10 Hz whose header stamps run 100 s ahead of the log time (as in the dev
    recording); two people labelled after scan 0, one after scan 2, none after scan 1."""
    path = tmp_path / "person.bag"
    with open_bag(path) as sink:
        register_people_types(sink.typestore)
        types = sink.typestore.types
        for k in range(4):
            t = 10.0 + 0.1 * k
            scan = _scan(k, t + 100.0)
            # the header stamp is the scan's; the log time is t
            msg = types["sensor_msgs/msg/LaserScan"](
                header=sink.header(scan.stamp, "laser"),
                angle_min=scan.angle_min,
                angle_max=scan.angle_max,
                angle_increment=scan.angle_increment,
                time_increment=0.0,
                scan_time=0.0,
                range_min=0.0,
                range_max=5.0,
                ranges=np.asarray(scan.ranges, dtype=np.float32),
                intensities=np.empty(0, dtype=np.float32),
            )
            sink.write("/scan", "sensor_msgs/msg/LaserScan", msg, t)
            if k == 0:
                sink.write("/gt", LEG_TRACKER_PERSON, _person(types, 5, 1.0, 2.0), t + 0.05)
                sink.write("/gt", LEG_TRACKER_PERSON, _person(types, 7, 3.0, 4.0), t + 0.06)
            if k == 2:
                sink.write("/gt", LEG_TRACKER_PERSON, _person(types, 5, 1.5, 2.5), t + 0.05)
    truth = read_truth_bag(path)
    assert (truth.topic, truth.msgtype, truth.laser_topic) == ("/gt", LEG_TRACKER_PERSON, "/scan")
    assert truth.labels == 3 and truth.messages == 3 and truth.unpaired == 0
    assert [f.scan_index for f in truth.frames] == [0, 2]
    assert truth.frames[0].person_ids.tolist() == [5, 7]
    np.testing.assert_allclose(truth.frames[0].positions, [[1.0, 2.0], [3.0, 4.0]])
    np.testing.assert_allclose(truth.frames[1].positions, [[1.5, 2.5]])
    # the frame carries the scan's header stamp, which the tracks CSV also carries
    assert truth.frames[1].stamp == pytest.approx(110.2)
    assert "3 labels of 2 people on 2 scans of /scan" in truth.summary()
    # Person has no header: its labels are in the laser frame, and say so
    assert truth.frame == "sensor" and [f.frame for f in truth.frames] == ["sensor"] * 2


def _stamped_bag(path: Path, msgtype: str, frame_id: str = "base_laser") -> None:
    """Scans at 0.0, 0.1, ... 0.4 s; truth messages stamped 0.1 (two people), 0.31 and 9.0
    (no scan near: unpaired), written out of step with the scans."""
    with open_bag(path) as sink:
        register_people_types(sink.typestore)
        types = sink.typestore.types
        for k in range(5):
            sink.scan(_scan(k, 1.0 + 0.1 * k), "/scan", "laser")
        for stamp, people in (
            (1.1, [("alice", 1.0, 0.5), ("bob", 2.0, -0.5)]),
            (1.31, [("alice", 1.1, 0.6)]),
            (9.0, [("bob", 0.0, 0.0)]),
        ):
            header = sink.header(stamp, frame_id)
            if msgtype == PEOPLE_MSGS_PEOPLE:
                people_msgs = [
                    types["people_msgs/msg/Person"](
                        name=name,
                        position=_point(types, x, y),
                        velocity=_point(types, 0.0, 0.0),
                        reliability=1.0,
                        tagnames=[],
                        tags=[],
                    )
                    for name, x, y in people
                ]
                msg = types[msgtype](header=header, people=people_msgs)
            else:
                tracks = []
                for name, x, y in people:
                    pose = types["geometry_msgs/msg/PoseWithCovariance"](
                        pose=_person(types, 0, x, y).pose, covariance=np.zeros(36)
                    )
                    twist = types["geometry_msgs/msg/TwistWithCovariance"](
                        twist=types["geometry_msgs/msg/Twist"](
                            linear=types["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
                            angular=types["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
                        ),
                        covariance=np.zeros(36),
                    )
                    tracks.append(
                        types["spencer_tracking_msgs/msg/TrackedPerson"](
                            track_id={"alice": 11, "bob": 12}[name],
                            is_occluded=False,
                            is_matched=True,
                            detection_id=0,
                            age=types["builtin_interfaces/msg/Duration"](sec=0, nanosec=0),
                            pose=pose,
                            twist=twist,
                        )
                    )
                msg = types[msgtype](header=header, tracks=tracks)
            sink.write("/people", msgtype, msg, 2.0)


@pytest.mark.parametrize("suffix", [".bag", ".mcap"])
@pytest.mark.parametrize("msgtype", [SPENCER_TRACKED_PERSONS, PEOPLE_MSGS_PEOPLE])
def test_stamped_people_pair_by_header_stamp(tmp_path: Path, msgtype: str, suffix: str) -> None:
    path = tmp_path / f"people{suffix}"
    _stamped_bag(path, msgtype)
    truth = read_truth_bag(path, "people")  # the leading slash is optional
    assert truth.msgtype == msgtype and truth.frame_id == "base_laser"
    assert [f.scan_index for f in truth.frames] == [1, 3]
    assert truth.labels == 4 and truth.unpaired == 1
    ids = {"alice": 11, "bob": 12}
    if msgtype == PEOPLE_MSGS_PEOPLE:  # names become 0, 1, ... in order of appearance
        ids = {"alice": 0, "bob": 1}
        assert truth.names == {0: "alice", 1: "bob"}
    assert truth.frames[0].person_ids.tolist() == [ids["alice"], ids["bob"]]
    np.testing.assert_allclose(truth.frames[0].positions, [[1.0, 0.5], [2.0, -0.5]])
    np.testing.assert_allclose(truth.frames[1].positions, [[1.1, 0.6]])
    assert truth.frames[0].stamp == pytest.approx(1.1)
    # another frame than the laser's ("laser"): may be the world frame or not, so not stated
    assert truth.laser_frame_id == "laser" and truth.frame is None
    assert [f.frame for f in truth.frames] == [None, None]


def test_stamped_people_in_the_laser_frame_say_so(tmp_path: Path) -> None:
    path = tmp_path / "people.bag"
    _stamped_bag(path, PEOPLE_MSGS_PEOPLE, frame_id="laser")
    truth = read_truth_bag(path)
    assert truth.frame == "sensor" and [f.frame for f in truth.frames] == ["sensor"] * 2


def test_topic_errors_name_the_topics(tmp_path: Path) -> None:
    path = tmp_path / "people.bag"
    _stamped_bag(path, PEOPLE_MSGS_PEOPLE)
    with pytest.raises(TopicNotFoundError, match=r"no topic '/nope'.*people_msgs/People"):
        read_truth_bag(path, "/nope")
    with pytest.raises(MessageTypeError, match="LaserScan, not people ground-truth"):
        read_truth_bag(path, "/scan")
    plain = tmp_path / "plain.bag"
    with open_bag(plain) as sink:
        sink.scan(_scan(0, 1.0), "/scan", "laser")
    with pytest.raises(TopicNotFoundError, match="no people ground-truth topic"):
        read_truth_bag(plain)


def test_split_truth_spec(tmp_path: Path) -> None:
    assert split_truth_spec("a.bag:/gt") == (Path("a.bag"), "/gt")
    assert split_truth_spec("a.bag") == (Path("a.bag"), None)
    odd = tmp_path / "x:y.csv"
    odd.write_text("")
    assert split_truth_spec(str(odd)) == (odd, None)


def test_dev_recording_truth_equals_its_csv(shared_data: Path) -> None:
    bag = shared_data / "leg_tracker_benchmarks" / "person_following_outdoor_1_first.bag"
    truth = read_truth_bag(bag, "/ground_truth_people_tracks")
    csv = read_truth_csv(bag.with_suffix(".people.csv"))
    assert truth.laser_topic == "/scan_base2"
    assert truth.labels == len(csv) == 2709  # data README
    assert [f.scan_index for f in truth.frames] == [f.scan_index for f in csv]
    for a, b in zip(truth.frames, csv, strict=True):
        assert a.person_ids.tolist() == b.person_ids.tolist() == [2]
        np.testing.assert_allclose(a.positions, b.positions, atol=1e-9)
