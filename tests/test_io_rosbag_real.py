"""Every known bag in ../shared/data read through RosbagRecording, checked against the raw
messages decoded with rosbags directly and against the counts stated in the data README.

Each bag is decoded once by the reader (module fixture); the raw check decodes only the
sampled messages. The tests check the recordings listed in EXPECTED; a bag that appears under
../shared/data later is reported (a warning naming it) and otherwise left alone, so new data
never turns these tests red. A listed bag that is missing still fails.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from rosbags.highlevel import AnyReader

from laserpeople.io import open_recording
from laserpeople.io.poses import MIR100_LASER_MOUNTS
from laserpeople.io.rosbag import RosbagRecording
from laserpeople.scan import Pose2D, Scan

INC_033 = 0.006135923322290182  # 0.3516 deg
INC_MIR = -0.008726646192371845  # -0.5 deg
INC_CORRIDOR = 0.008727000094950199

# file name -> {topic: (scans, beams, angle_increment)}; from the data README, checked
# against the bags' own indices in test_expected_table_matches_bag_indices.
EXPECTED: dict[str, dict[str, tuple[int, int, float]]] = {
    "demo_stationary_simple_environment.bag": {"/scan": (1265, 512, INC_033)},
    "negative_2.bag": {
        "/left_scan": (435, 768, INC_033),
        "/rear_scan": (435, 768, INC_033),
        "/right_scan": (434, 768, INC_033),
    },
    **{
        f"positive_{k}_extracted.bag": {"/training_scan": (n, 768, INC_033)}
        for k, n in ((1, 197), (2, 83), (3, 175), (4, 295), (6, 187), (7, 267))
    },
    **{
        f"positive_{k}.bag": {topic: (n, 768, INC_033)}
        for k, topic, n in (
            (1, "right_scan", 400),
            (2, "right_scan", 243),
            (3, "right_scan", 345),
            (4, "right_scan", 307),
            (5, "right_scan", 296),
            (6, "/rear_scan", 355),
            (7, "/rear_scan", 510),
        )
    },
    "corridor.bag": {
        "/RAWLASER1": (1563, 361, INC_CORRIDOR),
        "/ROBOTLASER1": (370, 361, INC_CORRIDOR),
    },
    "corridor1.bag": {
        "right_scan": (1563, 361, INC_CORRIDOR),
        "/ROBOTLASER1": (370, 361, INC_CORRIDOR),
    },
    "corridor2.bag": {
        "/RAWLASER1": (1563, 361, INC_CORRIDOR),
        "/ROBOTLASER1": (370, 361, INC_CORRIDOR),
    },
    "legs-test-split-2022-11-21-15-51-02-topic-split.bag": {
        "front_laser_link": (737, 541, INC_MIR),
        "back_laser_link": (737, 541, INC_MIR),
    },
    # leg_tracker_benchmarks/: 3,600 scans, 245 beams over 86 deg (0.352 deg), 10 Hz
    "person_following_outdoor_1_first.bag": {"/scan_base2": (3600, 245, INC_033)},
    # leg_tracker_benchmarks/: 290 scans, 768 beams over 270 deg, 7.5 Hz, a moving robot
    "general_tracking_moving_1_first.bag": {"/scan": (290, 768, INC_033)},
}


def known_bags(shared_data: Path) -> list[Path]:
    """The bags under ``shared_data`` that EXPECTED describes; every other bag is named in a
    warning (new data is reported, not failed on). A bag EXPECTED lists but the directory
    lacks fails: data the tests rely on was removed."""
    found = sorted(shared_data.rglob("*.bag"))
    unknown = [p for p in found if p.name not in EXPECTED]
    if unknown:
        names = ", ".join(str(p.relative_to(shared_data)) for p in unknown)
        warnings.warn(
            f"bags under {shared_data} that the real-data tests do not know (not checked; "
            f"add them to EXPECTED in {Path(__file__).name}): {names}",
            stacklevel=2,
        )
    missing = set(EXPECTED) - {p.name for p in found}
    assert not missing, f"bags listed in EXPECTED are missing under {shared_data}: {missing}"
    return [p for p in found if p.name in EXPECTED]


@dataclass
class ReadResult:
    path: Path
    stamps: dict[str, list[float]] = field(default_factory=dict)
    indices: dict[str, list[int]] = field(default_factory=dict)
    beams: dict[str, set[int]] = field(default_factory=dict)
    order: list[float] = field(default_factory=list)
    samples: dict[tuple[str, int], Scan] = field(default_factory=dict)
    poses: dict[str, list[tuple[float, float, float, float]]] = field(default_factory=dict)
    without_pose: int = 0
    world: str | None = None
    summary: str = ""


def _sample_indices(n: int) -> set[int]:
    return {0, 1, n // 2, n - 1}


def _read(path: Path) -> ReadResult:
    out = ReadResult(path)
    with RosbagRecording(path) as rec:
        counts = {t.name: t.count for t in rec.topics()}
        for scan in rec.scans():
            t = scan.sensor
            out.order.append(scan.stamp)
            out.stamps.setdefault(t, []).append(scan.stamp)
            out.indices.setdefault(t, []).append(scan.index)
            out.beams.setdefault(t, set()).add(scan.n_beams)
            if scan.index in _sample_indices(counts[t]):
                out.samples[(t, scan.index)] = scan
            if scan.pose is not None:
                p = scan.pose
                out.poses.setdefault(t, []).append((scan.stamp, p.x, p.y, p.theta))
        out.without_pose = rec.scans_without_pose
        out.world = rec.world_frame
        out.summary = rec.pose_summary()
    return out


@pytest.fixture(scope="module")
def bags(shared_data: Path) -> dict[str, ReadResult]:
    return {p.name: _read(p) for p in known_bags(shared_data)}


def _stamp(msg: Any) -> float:
    return msg.header.stamp.sec + 1e-9 * msg.header.stamp.nanosec


def test_every_known_bag_is_read(bags: dict[str, ReadResult]) -> None:
    assert set(bags) == set(EXPECTED)
    for name, result in bags.items():
        for topic, (n, beams, _) in EXPECTED[name].items():
            assert len(result.stamps[topic]) == n, (name, topic)
            assert result.indices[topic] == list(range(n)), (name, topic)
            assert result.beams[topic] == {beams}, (name, topic)
        assert set(result.stamps) == set(EXPECTED[name]), name


def test_readme_totals(bags: dict[str, ReadResult]) -> None:
    extracted = sum(len(r.stamps["/training_scan"]) for n, r in bags.items() if "extracted" in n)
    raw = sum(
        len(s)
        for n, r in bags.items()
        if n.startswith("positive_") and "extracted" not in n
        for s in r.stamps.values()
    )
    assert extracted == 1204
    assert raw == 2456


def test_expected_table_matches_bag_indices(shared_data: Path) -> None:
    for path in known_bags(shared_data):
        with AnyReader([path]) as reader:
            lasers = {
                c.topic: c.msgcount
                for c in reader.connections
                if c.msgtype == "sensor_msgs/msg/LaserScan"
            }
        assert lasers == {t: v[0] for t, v in EXPECTED[path.name].items()}, path.name


def test_scans_are_time_ordered_across_topics(bags: dict[str, ReadResult]) -> None:
    for name, result in bags.items():
        assert np.all(np.diff(result.order) >= 0), name
    # the three lasers of negative_2 really interleave
    neg = bags["negative_2.bag"]
    assert min(neg.stamps["/rear_scan"]) < max(neg.stamps["/left_scan"])


def test_sampled_scans_equal_raw_messages(bags: dict[str, ReadResult]) -> None:
    """Stamps, angles, limits, ranges and invalid masks against rosbags' own decoding."""
    checked = 0
    for result in bags.values():
        with AnyReader([result.path]) as reader:
            for conn in reader.connections:
                if conn.msgtype != "sensor_msgs/msg/LaserScan":
                    continue
                wanted = _sample_indices(conn.msgcount)
                for k, (c, _, raw) in enumerate(reader.messages(connections=[conn])):
                    if k not in wanted:
                        continue
                    msg: Any = reader.deserialize(raw, c.msgtype)
                    scan = result.samples[(conn.topic, k)]
                    r = np.asarray(msg.ranges, dtype=np.float64)
                    assert scan.stamp == pytest.approx(_stamp(msg), abs=1e-9)
                    assert scan.angle_min == pytest.approx(msg.angle_min)
                    assert scan.angle_increment == pytest.approx(msg.angle_increment)
                    # the header's angle_max agrees with the beam count to within the 1.5 beams
                    # Scan.from_angles tolerates: /ROBOTLASER1 of corridor{,1}.bag has
                    # angle_min/max pulled in by half a beam each (a converter quirk)
                    off = abs(scan.angle_max - msg.angle_max) / abs(msg.angle_increment)
                    assert off < (1.5 if conn.topic == "/ROBOTLASER1" else 0.5), off
                    np.testing.assert_allclose(
                        scan.angles[-1],
                        msg.angle_min + (len(r) - 1) * msg.angle_increment,
                        atol=1e-9,
                    )
                    assert scan.range_min == pytest.approx(msg.range_min)
                    assert scan.range_max == pytest.approx(msg.range_max)
                    np.testing.assert_array_equal(scan.ranges, r)
                    with np.errstate(invalid="ignore"):
                        valid = (
                            np.isfinite(r) & (r > 0) & (r >= msg.range_min) & (r <= msg.range_max)
                        )
                    np.testing.assert_array_equal(scan.valid, valid)
                    assert scan.source == str(result.path)
                    checked += 1
    assert checked >= 4 * 22


def test_mir_negative_increment_angles_and_points(bags: dict[str, ReadResult]) -> None:
    result = bags["legs-test-split-2022-11-21-15-51-02-topic-split.bag"]
    for topic in ("front_laser_link", "back_laser_link"):
        scan = result.samples[(topic, 0)]
        assert scan.angle_increment < 0
        assert scan.angles[0] == pytest.approx(math.radians(135.0), abs=1e-6)
        assert scan.angles[270] == pytest.approx(0.0, abs=1e-6)
        assert scan.angles[-1] == pytest.approx(math.radians(-135.0), abs=1e-6)
        assert np.all(np.diff(scan.angles) < 0)
        pts = scan.points()
        valid = scan.valid
        # beams 0..269 lie left of the laser (y > 0), beams 271.. right of it
        assert np.all(pts[:270][valid[:270], 1] > 0)
        assert np.all(pts[271:][valid[271:], 1] < 0)
        r = scan.ranges
        k = int(np.flatnonzero(valid)[0])
        a = math.radians(135.0) - k * math.radians(0.5)
        assert pts[k] == pytest.approx((r[k] * math.cos(a), r[k] * math.sin(a)), abs=1e-6)


def test_mir_bag_lacks_laser_mounts_and_says_so(bags: dict[str, ReadResult]) -> None:
    result = bags["legs-test-split-2022-11-21-15-51-02-topic-split.bag"]
    # /tf holds only odom -> base_footprint: no chain reaches the laser frames
    assert result.world == "odom"
    assert result.without_pose == 2 * 737
    assert "no transform chain from 'odom' to 'front_laser_link'" in result.summary
    assert "odom -> base_footprint" in result.summary


def _mir_scans(path: Path, mounts: dict, n: int) -> list[Scan]:
    with RosbagRecording(path, mounts=mounts) as rec:
        out = []
        for scan in rec.scans():
            out.append(scan)
            if len(out) == n:
                break
    return out


def test_mir_lasers_share_the_world_frame_with_given_mounts(shared_data: Path) -> None:
    """Poses = /tf (odom -> base_footprint) interpolated here with np.interp, composed with
    the MiR100 mounts by hand."""
    path = next(shared_data.rglob("legs-test-split-*.bag"))
    scans = _mir_scans(path, MIR100_LASER_MOUNTS, 40)
    with AnyReader([path]) as reader:
        conn = next(c for c in reader.connections if c.topic == "/tf")
        tf = []
        for c, _, raw in reader.messages(connections=[conn]):
            msg: Any = reader.deserialize(raw, c.msgtype)
            for tr in msg.transforms:
                q = tr.transform.rotation
                yaw = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y**2 + q.z**2))
                tv = tr.transform.translation
                tf.append((_stamp(tr), tv.x, tv.y, yaw))
    tf_arr = np.array(sorted(tf))
    with_pose = [s for s in scans if s.pose is not None]
    assert {s.sensor for s in with_pose} == {"front_laser_link", "back_laser_link"}
    assert len(with_pose) >= 38
    for s in with_pose:
        base = [np.interp(s.stamp, tf_arr[:, 0], tf_arr[:, i]) for i in (1, 2)]
        yaw = np.interp(s.stamp, tf_arr[:, 0], np.unwrap(tf_arr[:, 3]))
        mount = MIR100_LASER_MOUNTS[s.sensor][1]
        cy, sy = math.cos(yaw), math.sin(yaw)
        expect = (base[0] + cy * mount.x - sy * mount.y, base[1] + sy * mount.x + cy * mount.y)
        assert s.pose is not None
        assert (s.pose.x, s.pose.y) == pytest.approx(expect, abs=1e-6)
        dtheta = (s.pose.theta - (yaw + mount.theta) + math.pi) % (2 * math.pi) - math.pi
        assert abs(dtheta) < 1e-6


def _overlap(scans: list[Scan]) -> float:
    """Median share of back-laser world points within 5 cm of the front laser's last scan."""
    from scipy.spatial import cKDTree

    last: dict[str, Scan] = {}
    shares = []
    for s in scans:
        if s.pose is None:
            continue
        last[s.sensor] = s
        if len(last) == 2 and s.sensor == "back_laser_link" and s.index % 20 == 0:
            front, _ = last["front_laser_link"].valid_points("world")
            back, _ = s.valid_points("world")
            dist, _ = cKDTree(front).query(back)
            shares.append(float(np.mean(dist < 0.05)))
    assert len(shares) >= 10
    return float(np.median(shares))


def test_mir100_mounts_make_both_lasers_see_the_same_walls(shared_data: Path) -> None:
    """An independent check of the mounts and of the negative increment: with the MiR100
    mounts the lasers agree where their views overlap; with the yaws mirrored they do not."""
    path = next(shared_data.rglob("legs-test-split-*.bag"))
    good = _overlap(_mir_scans(path, MIR100_LASER_MOUNTS, 500))
    mirrored = {
        k: (parent, Pose2D(p.x, p.y, -p.theta)) for k, (parent, p) in MIR100_LASER_MOUNTS.items()
    }
    bad = _overlap(_mir_scans(path, mirrored, 500))
    assert good > 0.3
    assert bad < 0.1


def test_corridor_poses_equal_odometry_interpolated_independently(
    bags: dict[str, ReadResult],
) -> None:
    """The reader takes poses from /tf; here they are recomputed from /ODOM with np.interp."""
    for name in ("corridor.bag", "corridor1.bag", "corridor2.bag"):
        result = bags[name]
        with AnyReader([result.path]) as reader:
            conn = next(c for c in reader.connections if c.topic == "/ODOM")
            rows = []
            for c, _, raw in reader.messages(connections=[conn]):
                msg: Any = reader.deserialize(raw, c.msgtype)
                q = msg.pose.pose.orientation
                yaw = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y**2 + q.z**2))
                rows.append((_stamp(msg), msg.pose.pose.position.x, msg.pose.pose.position.y, yaw))
        odom = np.array(rows)
        assert result.world == "odom"
        tol = 0.05
        expected_missing = 0
        for topic, stamps in result.stamps.items():
            s = np.array(stamps)
            outside = (s < odom[0, 0] - tol) | (s > odom[-1, 0] + tol)
            expected_missing += int(outside.sum())
            posed = np.array(result.poses[topic])
            assert len(posed) == int((~outside).sum())
            inside = (posed[:, 0] >= odom[0, 0]) & (posed[:, 0] <= odom[-1, 0])
            p = posed[inside]
            x = np.interp(p[:, 0], odom[:, 0], odom[:, 1])
            y = np.interp(p[:, 0], odom[:, 0], odom[:, 2])
            yaw = np.interp(p[:, 0], odom[:, 0], np.unwrap(odom[:, 3]))
            np.testing.assert_allclose(p[:, 1], x, atol=1e-6)
            np.testing.assert_allclose(p[:, 2], y, atol=1e-6)
            dyaw = (p[:, 3] - yaw + np.pi) % (2 * np.pi) - np.pi
            np.testing.assert_allclose(dyaw, 0.0, atol=1e-6)
            # the robot stands still in this log, at the pose the ODOM lines give
            assert p[:, 1] == pytest.approx(3.64207) and p[:, 2] == pytest.approx(-21.093501)
        assert result.without_pose == expected_missing
        assert 0 < expected_missing < 5


def test_static_bags_have_no_pose_data_and_say_so(bags: dict[str, ReadResult]) -> None:
    result = bags["demo_stationary_simple_environment.bag"]
    assert result.without_pose == 1265
    assert "no pose data" in result.summary


def test_open_recording_dispatches_bags(shared_data: Path) -> None:
    path = next(shared_data.rglob("demo_stationary_simple_environment.bag"))
    rec = open_recording(path)
    try:
        assert isinstance(rec, RosbagRecording)
        assert [t.name for t in rec.topics()] == ["/scan"]
        assert not rec.has_truth and list(rec.truth()) == []
        first = next(iter(rec.scans(["scan"])))  # the leading slash is optional
        assert first.sensor == "/scan" and first.index == 0
    finally:
        rec.close()


def test_an_unknown_bag_is_reported_not_failed(tmp_path: Path) -> None:
    """A bag the table does not know, beside the known ones, gives a warning naming it."""
    for name in EXPECTED:
        (tmp_path / name).write_bytes(b"")
    (tmp_path / "new").mkdir()
    (tmp_path / "new" / "brand_new.bag").write_bytes(b"")
    with pytest.warns(UserWarning, match=r"new/brand_new\.bag"):
        paths = known_bags(tmp_path)
    assert sorted(p.name for p in paths) == sorted(EXPECTED)
    (tmp_path / "negative_2.bag").unlink()
    with pytest.raises(AssertionError, match=r"negative_2\.bag"), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        known_bags(tmp_path)
