"""Regression tests of hostile input found by ``benchmarks/fuzz_readers.py``.

Each test builds the damaged bytes from a small file the project writes and checks that the
reader ends in a result or a ``LaserPeopleError`` naming the file, never another exception,
a hang or a large allocation.
"""

from __future__ import annotations

import io
import json
import math
import sqlite3
import struct
import time
import tracemalloc
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from laserpeople.config import check_sections, from_mapping, load_config, param
from laserpeople.detection.detector import LegDetectorParams, default_model
from laserpeople.detection.model_file import load_model
from laserpeople.errors import ConfigError, LaserPeopleError, ModelFileError, RecordingError
from laserpeople.io import open_recording, write_recording
from laserpeople.io.carmen import write_carmen_log
from laserpeople.io.rosbag_writer import write_laserscan_bag
from laserpeople.scan import Pose2D, Scan
from laserpeople.tracking.legs import LegTrackerParams
from laserpeople.truth import TruthFrame

# -- small files the project writes --------------------------------------------------------


def _scans(n: int = 12, sensor: str = "scan") -> list[Scan]:
    rng = np.random.default_rng(1)
    return [
        Scan(
            stamp=10.0 + 0.1 * k,
            angle_min=-1.0,
            angle_increment=0.05,
            ranges=1.0 + rng.random(41),
            range_min=0.05,
            range_max=8.0,
            sensor=sensor,
            pose=Pose2D(0.1 * k, 0.0, 0.01 * k),
            index=k,
        )
        for k in range(n)
    ]


def _truth(n: int = 12) -> list[TruthFrame]:
    return [
        TruthFrame(
            stamp=10.0 + 0.1 * k,
            scan_index=k,
            person_ids=np.array([1, 2]),
            positions=np.ones((2, 2)),
            velocities=np.zeros((2, 2)),
            group_ids=np.array([-1, -1]),
            leg_positions=np.zeros((2, 2, 2)),
            hues=np.zeros(2),
        )
        for k in range(n)
    ]


def _read_all(path: Path, **options: Any) -> tuple[int, Any]:
    """Open, list topics and read every scan; returns (scans read, recording)."""
    rec = open_recording(path, **options)
    try:
        rec.topics()
        n = sum(1 for _ in rec.scans())
        list(rec.truth())
    finally:
        rec.close()
    return n, rec


def _only_our_errors(fn: Callable[[], object]) -> None:
    """``fn`` returns or raises a LaserPeopleError (never anything else), quickly and in
    little memory."""
    tracemalloc.start()
    t0 = time.monotonic()
    try:
        fn()
    except LaserPeopleError:
        pass
    finally:
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
    assert time.monotonic() - t0 < 20.0
    assert peak < 64 * 2**20, f"peak {peak / 2**20:.0f} MiB"


# -- ROS 1 --------------------------------------------------------------------------------


def _ros1_records(data: bytes) -> Iterator[tuple[int, int, dict[str, tuple[int, bytes]]]]:
    """(header length offset, data length offset, fields) of each top-level ROS 1 record
    and of the records inside uncompressed chunks."""
    stack = [(13, len(data))]
    while stack:
        pos, end = stack.pop()
        while pos + 8 <= end:
            (hlen,) = struct.unpack_from("<I", data, pos)
            fields, q = {}, pos + 4
            while q < pos + 4 + hlen:
                (flen,) = struct.unpack_from("<I", data, q)
                name, _, value = data[q + 4 : q + 4 + flen].partition(b"=")
                fields[name.decode()] = (q + 4 + len(name) + 1, value)
                q += 4 + flen
            dpos = pos + 4 + hlen
            (dlen,) = struct.unpack_from("<I", data, dpos)
            yield pos, dpos, fields
            if fields["op"][1] == b"\x05" and fields["compression"][1] == b"none":
                stack.append((dpos + 4, dpos + 4 + dlen))
            pos = dpos + 4 + dlen


@pytest.fixture
def ros1_bag(tmp_path: Path) -> Path:
    path = tmp_path / "small.bag"
    write_laserscan_bag(path, _scans())
    return path


def test_ros1_huge_chunk_length_is_refused_before_allocating(ros1_bag: Path) -> None:
    data = bytearray(ros1_bag.read_bytes())
    chunk = next(d for _, d, f in _ros1_records(bytes(data)) if f["op"][1] == b"\x05")
    struct.pack_into("<I", data, chunk, 0xFFFFFFFF)
    ros1_bag.write_bytes(bytes(data))
    _only_our_errors(lambda: _read_all(ros1_bag))
    with pytest.raises(RecordingError, match=r"small\.bag"):
        _read_all(ros1_bag)


def test_ros1_huge_index_record_is_refused_before_allocating(ros1_bag: Path) -> None:
    data = bytearray(ros1_bag.read_bytes())
    index = next(d for _, d, f in _ros1_records(bytes(data)) if f["op"][1] == b"\x04")
    struct.pack_into("<I", data, index, 0xFFFFFFF0)
    ros1_bag.write_bytes(bytes(data))
    _only_our_errors(lambda: _read_all(ros1_bag))


def test_ros1_record_under_the_tf_connection_is_a_damaged_scan(ros1_bag: Path) -> None:
    data = bytearray(ros1_bag.read_bytes())
    records = list(_ros1_records(bytes(data)))
    conns = {f["topic"][1]: f["conn"][1] for _, _, f in records if f["op"][1] == b"\x07"}
    scan_conn, tf_conn = conns[b"scan"], conns[b"/tf"]
    messages = [f for _, _, f in records if f["op"][1] == b"\x02" and f["conn"][1] == scan_conn]
    off, _ = messages[5]["conn"]
    data[off : off + 4] = tf_conn
    ros1_bag.write_bytes(bytes(data))
    with pytest.raises(RecordingError, match=r"scan 5 is damaged.*5 scans .* read before") as e:
        _read_all(ros1_bag)
    assert e.value.scan == 5 and "--on-error skip" in str(e.value)
    n, rec = _read_all(ros1_bag, on_error="skip")
    assert n == 11 and rec.damaged.count == 1
    assert "skipped 1 damaged scan" in rec.damaged.summary()


def test_ros1_corrupt_lz4_chunk(tmp_path: Path) -> None:
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    from laserpeople.io.rosbag_writer import BagSink

    path = tmp_path / "lz4.bag"
    writer = Writer(path)
    writer.set_compression(Writer.CompressionFormat.LZ4)
    writer.chunk_threshold = 2048
    writer.open()
    sink = BagSink(writer, get_typestore(Stores.ROS1_NOETIC), True)
    for scan in _scans(30):
        sink.scan(scan, "/scan", "laser")
    writer.close()
    data = bytearray(path.read_bytes())
    chunks = [d for _, d, f in _ros1_records(bytes(data)) if f["op"][1] == b"\x05"]
    assert len(chunks) > 3
    data[chunks[2] + 30 : chunks[2] + 60] = b"\xa5" * 30
    path.write_bytes(bytes(data))
    with pytest.raises(RecordingError, match=r"lz4\.bag"):
        _read_all(path)
    n, rec = _read_all(path, on_error="skip")
    assert 0 < n < 30 and "ends early" in rec.damaged.summary()


# -- MCAP, db3, ROS 2 folders ----------------------------------------------------------------


def _mcap_records(data: bytes) -> list[int]:
    out, pos = [], 8
    while pos + 9 <= len(data) - 8:
        out.append(pos)
        pos += 9 + struct.unpack_from("<Q", data, pos + 1)[0]
    return out


@pytest.mark.parametrize("length", [2**64 - 1, 2**63 - 1, 2**32 - 1])
def test_mcap_huge_record_length(tmp_path: Path, length: int) -> None:
    path = tmp_path / "small.mcap"
    write_laserscan_bag(path, _scans())
    data = bytearray(path.read_bytes())
    for pos in _mcap_records(bytes(data))[:6]:
        bad = bytearray(data)
        struct.pack_into("<Q", bad, pos + 1, length)
        path.write_bytes(bytes(bad))
        _only_our_errors(lambda: _read_all(path))


def test_mcap_one_inserted_byte(tmp_path: Path) -> None:
    path = tmp_path / "small.mcap"
    write_laserscan_bag(path, _scans())
    data = path.read_bytes()
    for pos in range(8, len(data), max(len(data) // 40, 1)):
        path.write_bytes(data[:pos] + b"\x07" + data[pos:])
        _only_our_errors(lambda: _read_all(path))


@pytest.mark.parametrize(
    "sql",
    [
        "UPDATE messages SET data = CAST(data AS TEXT)",
        "UPDATE messages SET data = 12345 WHERE id = 2",
        "UPDATE topics SET name = ''",
        "UPDATE topics SET name = 42",
        "UPDATE messages SET timestamp = 'abc' WHERE id = 3",
        "UPDATE messages SET timestamp = 1.5 WHERE id = 3",
        "UPDATE messages SET topic_id = (SELECT max(id) FROM topics) WHERE id % 2 = 0",
        "DROP TABLE messages",
    ],
)
def test_db3_wrong_column_types(tmp_path: Path, sql: str) -> None:
    path = tmp_path / "small.db3"
    write_laserscan_bag(path, _scans())
    with sqlite3.connect(path) as con:
        con.execute(sql)
    _only_our_errors(lambda: _read_all(path))
    _only_our_errors(lambda: _read_all(path, on_error="skip"))


def test_db3_truncated(tmp_path: Path) -> None:
    path = tmp_path / "small.db3"
    write_laserscan_bag(path, _scans())
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(RecordingError, match=r"small\.db3"):
        _read_all(path)


@pytest.fixture
def ros2_folder(tmp_path: Path) -> Path:
    from rosbags.rosbag2 import StoragePlugin
    from rosbags.rosbag2 import Writer as Writer2
    from rosbags.typesys import Stores, get_typestore

    from laserpeople.io.rosbag_writer import BagSink

    folder = tmp_path / "bag"
    writer = Writer2(folder, version=9, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    sink = BagSink(writer, get_typestore(Stores.LATEST), False)
    for scan in _scans():
        sink.scan(scan, "/scan", "laser")
    writer.close()
    return folder


@pytest.mark.parametrize(
    ("key", "value"),
    [
        ("compression_format", "lz4"),
        ("compression_mode", "message"),
        ("message_count", "file"),
        ("name", "{nanoseconds: 'x'}"),
        ("nanoseconds", "'abc'"),
        ("offered_qos_profiles", "7"),
    ],
)
def test_ros2_metadata_wrong_values(ros2_folder: Path, key: str, value: str) -> None:
    meta = ros2_folder / "metadata.yaml"
    lines = meta.read_text().splitlines()
    lines = [
        (line.split(":")[0] + f": {value}") if line.strip().startswith(f"{key}:") else line
        for line in lines
    ]
    meta.write_text("\n".join(lines) + "\n")
    _only_our_errors(lambda: _read_all(ros2_folder))


@pytest.mark.parametrize("depth", [1000, 50000])
def test_ros2_metadata_deep_nesting(ros2_folder: Path, depth: int) -> None:
    meta = ros2_folder / "metadata.yaml"
    meta.write_text(meta.read_text() + "extra: " + "[" * depth + "]" * depth + "\n")
    with pytest.raises(RecordingError, match="nests"):
        _read_all(ros2_folder)


# -- npz ----------------------------------------------------------------------------------


@pytest.fixture
def npz_arrays(tmp_path: Path) -> dict[str, np.ndarray]:
    path = tmp_path / "base.npz"
    write_recording(path, _scans(), _truth())
    with np.load(path) as z:
        return {k: z[k] for k in z.files}


def _npz(tmp_path: Path, arrays: dict[str, np.ndarray]) -> Path:
    path = tmp_path / "edited.npz"
    buf = io.BytesIO()
    np.savez(buf, **arrays)  # type: ignore[arg-type]
    path.write_bytes(buf.getvalue())
    return path


@pytest.mark.parametrize(
    "edit",
    [
        lambda a: a.update(version=np.empty(0, dtype=np.int64)),
        lambda a: a.update(version=np.array("1")),
        lambda a: a.update(sensor_names=np.empty(0, dtype=str)),
        lambda a: a.update(scan_offset=a["scan_offset"].astype(float) * np.nan),
        lambda a: a.update(scan_pose=a["scan_pose"].ravel()),
        lambda a: a.update(truth_group=np.empty(0, dtype=np.int64)),
        lambda a: a.update(scan_index=a["scan_index"][::-1].copy()),
        lambda a: a.update(scan_sensor=a["scan_sensor"] + 5),
        lambda a: a.update(scan_offset=a["scan_offset"][::-1].copy()),
        lambda a: a.update(truth_stamp=a["truth_stamp"] * np.inf),
        lambda a: a.update(meta_json=np.array("[" * 100000)),
        lambda a: a.update(ranges=a["ranges"].astype(str)),
    ],
)
def test_npz_edited_arrays(
    tmp_path: Path, npz_arrays: dict[str, np.ndarray], edit: Callable[[dict], None]
) -> None:
    edit(npz_arrays)
    path = _npz(tmp_path, npz_arrays)
    with pytest.raises(RecordingError, match=r"edited\.npz"):
        _read_all(path)


def test_npz_damaged_scan_in_the_middle(tmp_path: Path, npz_arrays: dict[str, np.ndarray]) -> None:
    npz_arrays["scan_stamp"][7] = np.nan
    path = _npz(tmp_path, npz_arrays)
    with pytest.raises(RecordingError, match=r"scan 7 is damaged.*7 scans") as e:
        _read_all(path)
    assert e.value.scan == 7
    n, rec = _read_all(path, on_error="skip")
    assert n == 11 and rec.damaged.count == 1


def test_on_error_must_be_stop_or_skip(tmp_path: Path) -> None:
    path = tmp_path / "r.npz"
    write_recording(path, _scans(2))
    with pytest.raises(ConfigError, match="stop, skip"):
        open_recording(path, on_error="ignore")


# -- CARMEN ---------------------------------------------------------------------------------


def test_carmen_nan_pose_gives_no_pose(tmp_path: Path) -> None:
    path = tmp_path / "a.log"
    write_carmen_log(path, _scans(5))
    text = path.read_text().replace("ODOM 0.2 ", "ODOM nan ", 1)
    path.write_text(text)
    with pytest.raises(RecordingError, match="not finite"):
        _read_all(path)
    rec = open_recording(path, on_error="skip")
    scans = list(rec.scans())
    assert len(scans) == 5 and rec.damaged.count == 1
    assert all(s.pose is None or np.all(np.isfinite(s.pose.as_array())) for s in scans)


def test_carmen_bad_scan_header_skipped(tmp_path: Path) -> None:
    path = tmp_path / "a.log"
    write_carmen_log(path, _scans(5))
    lines = path.read_text().splitlines(keepends=True)
    k = next(i for i, line in enumerate(lines) if line.startswith("RAWLASER") and i > 4)
    parts = lines[k].split(" ")
    parts[4] = "0"  # angular resolution 0
    lines[k] = " ".join(parts)
    path.write_text("".join(lines))
    with pytest.raises(RecordingError):
        _read_all(path)
    n, rec = _read_all(path, on_error="skip")
    assert n == 4 and rec.damaged.count == 1


# -- model JSON -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "edit",
    [
        lambda t: t.replace('"alpha": ', '"alpha": ' + "9" * 5000 + ', "x": ', 1),
        lambda t: t[:-2] + ', "deep": ' + "[" * 100000 + "]" * 100000 + "}",
        lambda t: t.replace('"threshold": ', '"threshold": 1e999, "t": ', 1),
        lambda t: t.replace('"alpha": ', '"alpha": 1e300, "a": ', 1),
        lambda t: t.replace('"polarity": ', '"polarity": ' + "1" * 400 + ', "p": ', 1),
        lambda t: t.replace('"feature": ', '"feature": true, "f": ', 1),
        lambda t: t.replace('"threshold": ', '"threshold": NaN, "t": ', 1),
    ],
)
def test_model_json_hostile_values(tmp_path: Path, edit: Callable[[str], str]) -> None:
    path = tmp_path / "model.json"
    default_model().save(path)
    path.write_text(edit(path.read_text()))
    with pytest.raises(ModelFileError, match=r"model\.json"):
        load_model(path)


# -- config TOML ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "text",
    [
        "leg_tracker = 3\n",
        "leg_tracker = true\n",
        "leg_tracker = [1, 2]\n",
        "deep = " + "{a = " * 500 + "1" + "}" * 500 + "\n",
        "x = " + "[" * 5000 + "]" * 5000 + "\n",
        "a." * 20000 + "b = 1\n",
        "[leg_tracker]\np_occ_approved = nan\n",
        "[leg_tracker]\np_occ_approved = inf\n",
        "[leg_tracker]\np_occ_approved = " + "9" * 30 + "\n",
    ],
)
def test_config_hostile_toml(tmp_path: Path, text: str) -> None:
    path = tmp_path / "c.toml"
    path.write_text(text)
    t0 = time.monotonic()
    with pytest.raises(ConfigError, match=r"c\.toml"):
        check_sections(path, [LegTrackerParams])
        load_config(LegTrackerParams, path)
    assert time.monotonic() - t0 < 5.0


def test_config_nan_names_the_key(tmp_path: Path) -> None:
    path = tmp_path / "c.toml"
    path.write_text("[leg_detector]\ncentre_offset = nan\n")
    with pytest.raises(ConfigError, match=r"\[leg_detector\] centre_offset is NaN"):
        load_config(LegDetectorParams, path)


def test_config_inf_only_where_the_default_is_inf() -> None:
    @dataclass(frozen=True)
    class P:
        limit: float = param(math.inf, "test", "no limit by default")
        gain: float = param(1.0, "test", "a gain")
        count: int = param(3, "test", "a count")

    assert from_mapping(P, {"limit": math.inf}).limit == math.inf
    with pytest.raises(ConfigError, match="gain is infinite"):
        from_mapping(P, {"gain": math.inf})
    with pytest.raises(ConfigError, match="limit is NaN"):
        from_mapping(P, {"limit": math.nan})
    with pytest.raises(ConfigError, match="count is larger"):
        from_mapping(P, {"count": 10**30})


@dataclass(frozen=True)
class _Inner:
    gate: float = param(1.0, "test", "gate")


@dataclass(frozen=True)
class _Outer:
    inner: _Inner = param(_Inner(), "test", "nested")  # noqa: RUF009


def test_config_nested_section_given_as_number() -> None:
    with pytest.raises(ConfigError, match="must be a table"):
        from_mapping(_Outer, {"inner": 3})


def test_default_model_still_loads(tmp_path: Path) -> None:
    path = tmp_path / "m.json"
    default_model().save(path)
    doc = json.loads(path.read_text())
    assert load_model(path).features == tuple(doc["features"])
