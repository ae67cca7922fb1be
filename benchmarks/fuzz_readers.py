"""Fuzz every reader with mutated copies of real files and of files the project writes.

Seeded and reproducible: case ``i`` of a run with ``--seed S`` always builds the same bytes.
Each case writes one mutated file, then runs the library's read path on it (open, list the
topics, iterate at most ``--max-scans`` scans and truth frames, or load the model / config
/ CSV) in a forked worker process that has an address-space cap (``RLIMIT_AS``) and a
per-case time limit. The outcome of each case is one of:

``ok``             the read path returned a result
``error``          it raised a :class:`~laserpeople.errors.LaserPeopleError` (what we want
                   for damaged input)
``bad-exception``  any other exception (a traceback for the user)
``bad-timeout``    the case ran past the time limit (CPU seconds of the worker)
``bad-memory``     ``MemoryError`` or the worker died (address-space cap)
``bad-empty``      a silent empty: the read path returned nothing from an input that
                   holds something (a recording whose topics list scans but none came, a
                   tracking run over no scan) without an error

Besides the recordings, CSVs, models and TOML files, it covers tracks bags (what
``evaluate TRACKS.bag|.mcap|.db3`` reads), ROS maps (``map.yaml`` and its PGM, as
``track --map`` loads them), neko7055 directories (xy data and labels JSON, as ``train
--neko`` reads them), whole tracking runs under a mutated ``--config`` of each tracker, and
option values: every command run in-process with a hostile value for one of its options.

Usage::

    python benchmarks/fuzz_readers.py --cases 10000 --seed 0
    python benchmarks/fuzz_readers.py --cases 200 --only ros1 --show 5   # show bad cases
    python benchmarks/fuzz_readers.py --replay 1234                      # rerun one case

Cases are spread over the formats by fixed weights; the case list is the same for every
``--cases`` prefix, so ``--replay`` with the same ``--seed`` rebuilds a reported case.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import gzip
import io
import json
import math
import os
import random
import resource
import shutil
import signal
import sqlite3
import struct
import sys
import tempfile
import time
import traceback
from collections import Counter, defaultdict
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

DATA = Path(os.environ.get("LASERPEOPLE_SHARED_DATA", Path(__file__).parents[2] / "shared/data"))
OUTCOMES = ("ok", "error", "bad-exception", "bad-timeout", "bad-memory", "bad-empty")

# -- seed files ---------------------------------------------------------------------------


@dataclass(frozen=True)
class Seed:
    """One unmutated input: its format, a name, and where it lives."""

    fmt: str
    name: str
    path: Path


def _sim_scans(n: int = 40, sensors: tuple[str, ...] = ("scan",), pose: bool = True) -> list[Any]:
    from laserpeople.scan import Pose2D, Scan

    rng = np.random.default_rng(7)
    out = []
    for k in range(n):
        for s, name in enumerate(sensors):
            ranges = 2.0 + rng.random(90) * 3.0
            ranges[rng.random(90) < 0.05] = np.inf
            out.append(
                Scan(
                    stamp=100.0 + 0.1 * k + 0.01 * s,
                    angle_min=-math.pi / 2,
                    angle_increment=math.pi / 89,
                    ranges=ranges,
                    range_min=0.05,
                    range_max=10.0,
                    intensities=rng.random(90) * 100 if s == 0 else None,
                    sensor=name,
                    pose=Pose2D(0.01 * k, -0.02 * k, 0.003 * k) if pose else None,
                    index=k,
                )
            )
    return out


def _truth_frames(n: int = 40) -> list[Any]:
    from laserpeople.truth import TruthFrame

    frames = []
    for k in range(n):
        m = k % 3
        frames.append(
            TruthFrame(
                stamp=100.0 + 0.1 * k,
                scan_index=k,
                person_ids=np.arange(m, dtype=np.int64),
                positions=np.full((m, 2), 1.5) + 0.01 * k,
                velocities=np.zeros((m, 2)),
                group_ids=np.full(m, -1, dtype=np.int64),
                leg_positions=np.zeros((m, 2, 2)),
                hues=np.full(m, 30.0),
            )
        )
    return frames


def _tracks_csv(path: Path) -> None:
    from laserpeople.io.tracks_csv import TracksCsvWriter
    from laserpeople.tracks import Track, Tracks

    with TracksCsvWriter(path, frame="world") as out:
        for k in range(30):
            tracks = tuple(
                Track(
                    track_id=j + 1,
                    kind="person" if j % 2 else "leg",
                    position=np.array([1.0 + 0.1 * k, float(j)]),
                    velocity=np.array([0.5, 0.0]),
                    covariance=np.eye(2) * 0.01,
                    labels="1-0|2" if j == 2 else "",
                )
                for j in range(k % 4)
            )
            out.write(Tracks(100.0 + 0.1 * k, k, tracks, "world"))


def _detections_csv(path: Path) -> None:
    from laserpeople.io.detections_csv import DetectionsCsvWriter
    from laserpeople.tracks import Detections

    with DetectionsCsvWriter(path) as out:
        for k in range(30):
            m = k % 4
            out.write(
                Detections(
                    100.0 + 0.1 * k,
                    k,
                    np.arange(2 * m, dtype=float).reshape(m, 2),
                    np.tile(np.eye(2) * 0.01, (m, 1, 1)),
                    np.linspace(-1, 1, m),
                )
            )


def _toml_text() -> str:
    from laserpeople.config import to_toml
    from laserpeople.detection.detector import LegDetectorParams
    from laserpeople.tracking.legs import LegTrackerParams

    return to_toml(LegDetectorParams()) + "\n" + to_toml(LegTrackerParams())


def _ros2_folder(target: Path, suffix: str) -> None:
    """A ROS 2 bag folder (metadata.yaml + storage file) with a few scans."""
    from rosbags.rosbag2 import StoragePlugin
    from rosbags.rosbag2 import Writer as Writer2
    from rosbags.typesys import Stores, get_typestore

    from laserpeople.io.rosbag_writer import BagSink

    plugin = StoragePlugin.MCAP if suffix == ".mcap" else StoragePlugin.SQLITE3
    writer = Writer2(target, version=9, storage_plugin=plugin)
    writer.open()
    sink = BagSink(writer, get_typestore(Stores.LATEST), False)
    for scan in _sim_scans(15):
        sink.scan(scan, "/scan", "laser")
        sink.pose(scan.stamp, "odom", "laser", scan.pose, "/tf")
    writer.close()


def _ros1_lz4(path: Path) -> None:
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.typesys import Stores, get_typestore

    from laserpeople.io.rosbag_writer import BagSink

    writer = Writer1(path)
    writer.set_compression(Writer1.CompressionFormat.LZ4)
    writer.chunk_threshold = 4096
    writer.open()
    sink = BagSink(writer, get_typestore(Stores.ROS1_NOETIC), True)
    for scan in _sim_scans(30):
        sink.scan(scan, "/scan", "laser")
        sink.pose(scan.stamp, "odom", "laser", scan.pose, "/tf")
    writer.close()


def _tracks_bag(path: Path) -> None:
    """A tracks bag as `laserpeople track --bag` writes it (scans, /tf, people, markers)."""
    from laserpeople.io.rosbag_writer import open_bag
    from laserpeople.io.tracks_bag import TracksBagWriter
    from laserpeople.tracks import Track, Tracks

    with open_bag(path) as sink:
        writer = TracksBagWriter(sink)
        for k, scan in enumerate(_sim_scans(25)):
            tracks = tuple(
                Track(
                    track_id=j + 1,
                    kind=("leg", "person", "group")[j % 3],
                    position=np.array([1.0 + 0.1 * k, float(j)]),
                    velocity=np.array([0.5, 0.0]),
                    covariance=np.eye(2) * 0.01,
                    members=(1, 2) if j % 3 == 1 else (),
                )
                for j in range(k % 4)
            )
            writer.write([scan], Tracks(scan.stamp, k, tracks, "world", scan.pose))


def _map_dir(target: Path) -> None:
    """A map_server map: map.yaml and a 120 x 80 PGM with a wall."""
    target.mkdir(parents=True, exist_ok=True)
    pixels = np.full((80, 120), 254, dtype=np.uint8)
    pixels[10, :] = 0
    pixels[:, 100] = 0
    (target / "map.pgm").write_bytes(b"P5\n120 80\n255\n" + pixels.tobytes())
    (target / "map.yaml").write_text(
        "image: map.pgm\nresolution: 0.05\norigin: [-2.0, -1.0, 0.0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n",
        encoding="utf-8",
    )


def _neko_dir(target: Path, scans: list[Any]) -> None:
    """A neko7055 directory (xy_data.txt + leg_segment_labels.json) of full-circle scans."""
    target.mkdir(parents=True, exist_ok=True)
    beams = 90
    rows = [f"{beams} 2 {len(scans)}"]
    labels: dict[str, list[int]] = {}
    for k, scan in enumerate(scans):
        r = np.resize(np.nan_to_num(np.asarray(scan.ranges), posinf=0.0), beams)
        a = -math.pi + 2 * math.pi * np.arange(beams) / beams
        rows.extend(f"{x:.4f} {y:.4f}" for x, y in zip(r * np.cos(a), r * np.sin(a), strict=True))
        labels[str(k)] = [0, 2] if k % 2 else [1]
    (target / "xy_data.txt").write_text("\n".join(rows) + "\n", encoding="utf-8")
    (target / "leg_segment_labels.json").write_text(
        json.dumps({"description": "jump 0.1 m, wrap around", "labels": labels}), encoding="utf-8"
    )


TOML_TRACKERS = ("leg-mht", "nn", "csa", "group-mht", "feet-pf")
"""Trackers whose ``--print-config`` is a TOML seed for whole tracking runs."""


def _print_config(tracker: str, recording: Path) -> str:
    from typer.testing import CliRunner

    from laserpeople.cli import app

    out = recording.with_suffix(".printed.csv")
    run = CliRunner().invoke(
        app, ["track", str(recording), "-o", str(out), "--tracker", tracker, "--print-config"]
    )
    if run.exit_code != 0:
        raise SystemExit(f"--print-config for {tracker} failed: {run.output[-500:]}")
    return run.stdout


def _options_dir(target: Path, recording: Path) -> None:
    """The inputs of the option-value cases: a recording, tracks and truth CSVs."""
    from laserpeople.io.truth_csv import write_truth_csv

    target.mkdir(parents=True, exist_ok=True)
    shutil.copy(recording, target / "rec.npz")
    _tracks_csv(target / "tracks.csv")
    write_truth_csv(target / "truth.csv", _truth_frames(30))
    (target / "commands.json").write_text(json.dumps(OPTION_CASES), encoding="utf-8")


def build_seeds(work: Path) -> dict[str, list[Seed]]:
    """Write the project's own files into ``work`` and collect the real ones."""
    from laserpeople.detection.detector import default_model
    from laserpeople.io.carmen import write_carmen_log
    from laserpeople.io.npz import write_recording
    from laserpeople.io.rosbag_writer import write_laserscan_bag
    from laserpeople.io.truth_csv import write_truth_csv

    seeds: dict[str, list[Seed]] = defaultdict(list)

    def add(fmt: str, name: str, path: Path) -> None:
        seeds[fmt].append(Seed(fmt, name, path))

    work.mkdir(parents=True, exist_ok=True)
    scans = _sim_scans(40, ("scan", "rear"))
    for suffix, fmt in ((".bag", "ros1"), (".mcap", "mcap"), (".db3", "db3")):
        p = work / f"sim{suffix}"
        write_laserscan_bag(p, scans)
        add(fmt, f"sim{suffix}", p)
    p = work / "sim_lz4.bag"
    _ros1_lz4(p)
    add("ros1", "sim_lz4.bag", p)
    for suffix in (".mcap", ".db3"):
        d = work / f"folder{suffix.replace('.', '_')}"
        _ros2_folder(d, suffix)
        add("ros2dir", d.name, d)
    p = work / "sim.npz"
    write_recording(p, scans, _truth_frames(40), {"scenario": "fuzz"})
    add("npz", "sim.npz", p)
    p = work / "nopose.npz"
    write_recording(p, _sim_scans(10, pose=False))
    add("npz", "nopose.npz", p)
    p = work / "sim.log"
    write_carmen_log(p, scans)
    add("carmen", "sim.log", p)
    p = work / "sim.log.gz"
    write_carmen_log(p, _sim_scans(10))
    add("carmen", "sim.log.gz", p)
    p = work / "model.json"
    default_model().save(p)
    add("model", "default model", p)
    p = work / "config.toml"
    p.write_text(_toml_text(), encoding="utf-8")
    add("toml", "config.toml", p)
    p = work / "tracks.csv"
    _tracks_csv(p)
    add("tracks_csv", "tracks.csv", p)
    p = work / "detections.csv"
    _detections_csv(p)
    add("detections_csv", "detections.csv", p)
    p = work / "truth.csv"
    write_truth_csv(p, _truth_frames(30))
    add("truth_csv", "truth.csv", p)

    for suffix, fmt in ((".bag", "tracks_ros1"), (".mcap", "tracks_mcap"), (".db3", "tracks_db3")):
        p = work / f"tracks{suffix}"
        _tracks_bag(p)
        add(fmt, f"tracks{suffix}", p)
    d = work / "map"
    _map_dir(d)
    add("map", "map.yaml + map.pgm", d)
    d = work / "neko_sim"
    _neko_dir(d, _sim_scans(4, pose=False))
    add("neko", "simulated neko dir", d)
    small = work / "small.npz"
    write_recording(small, _sim_scans(20), _truth_frames(20), {"scenario": "fuzz"})
    for tracker in TOML_TRACKERS:
        p = work / f"track_{tracker}.toml"
        p.write_text(f"# tracker: {tracker}\n" + _print_config(tracker, small), encoding="utf-8")
        add("toml_track", f"{tracker} --print-config", p)
    d = work / "options"
    _options_dir(d, small)
    add("options", "command lines", d)

    real_bags = [
        "leg_tracker/rosbags/training_scans_res=0.33/positive_2_extracted.bag",
        "leg_tracker/rosbags/training_scans_res=0.33/positive_not_extracted/positive_2.bag",
        "mir/rosbags/mir_data/legs-test-split-2022-11-21-15-51-02-topic-split.bag",
    ]
    for rel in real_bags:
        if (DATA / rel).is_file():
            add("ros1", Path(rel).name, DATA / rel)
    people = DATA / "leg_tracker_benchmarks/person_following_outdoor_1_first.people.csv"
    if people.is_file():
        p = work / "people_head.csv"
        lines = people.read_text(encoding="utf-8").splitlines(keepends=True)
        p.write_text("".join(lines[:300]), encoding="utf-8")
        add("truth_csv", "people.csv (first 300 rows)", p)
    neko = DATA / "neko7055/xy_data.txt"
    if neko.is_file():
        from laserpeople.io.neko import read_neko_scans

        real = read_neko_scans(neko)[:20]
        p = work / "neko_as_carmen.log"
        write_carmen_log(p, real)
        add("carmen", "neko7055 as CARMEN", p)
        d = work / "neko_real"
        _neko_dir(d, real[:3])
        add("neko", "neko7055 (3 frames)", d)
    return dict(seeds)


# -- mutations ------------------------------------------------------------------------------

HOSTILE_INTS = (0, 1, 2, 7, 255, 0x7FFFFFFF, 0x80000000, 0xFFFFFFFF, 0xFFFFFFFE)
HOSTILE_NUMBERS = (
    "nan",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e999",
    "0",
    "-1",
    "4294967295",
    "123456789012",
    "9" * 25,
    "1" * 5000,
    "-0",
    "abc",
    "",
    "0x10",
    "1_000",
    "NaN",
)


def _byte_mutation(data: bytes, rng: random.Random) -> tuple[bytes, str]:
    n = len(data)
    kind = rng.choice(("truncate", "insert", "delete", "overwrite", "flip", "zero", "dup"))
    pos = rng.randrange(max(n, 1))
    if kind == "truncate":
        return data[:pos], f"truncate at {pos}"
    if kind == "insert":
        k = rng.choice((1, 1, 2, 4, 8, 64))
        return data[:pos] + rng.randbytes(k) + data[pos:], f"insert {k} at {pos}"
    if kind == "delete":
        k = rng.choice((1, 1, 2, 4, 8, 64))
        return data[:pos] + data[pos + k :], f"delete {k} at {pos}"
    if kind == "overwrite":
        k = rng.choice((1, 2, 4, 8, 16))
        return data[:pos] + rng.randbytes(k) + data[pos + k :], f"overwrite {k} at {pos}"
    if kind == "flip":
        if not n:
            return data, "flip (empty)"
        b = bytearray(data)
        b[pos] ^= 1 << rng.randrange(8)
        return bytes(b), f"flip bit at {pos}"
    if kind == "zero":
        k = rng.choice((4, 16, 256))
        return data[:pos] + b"\0" * k + data[pos + k :], f"zero {k} at {pos}"
    k = rng.choice((16, 256, 4096))
    return data[:pos] + data[pos : pos + k] * 2 + data[pos + k :], f"duplicate {k} at {pos}"


def _ros1_fields(data: bytes) -> Iterator[tuple[int, int, dict[str, tuple[int, bytes]]]]:
    """(header_len offset, data_len offset, {field: (value offset, value)}) of every
    ROS 1 record, descending into uncompressed chunks."""
    stack = [(13, len(data))]
    while stack:
        pos, end = stack.pop()
        while pos + 8 <= end:
            (hlen,) = struct.unpack_from("<I", data, pos)
            hstart = pos + 4
            if hstart + hlen + 4 > end:
                break
            fields: dict[str, tuple[int, bytes]] = {}
            q = hstart
            while q + 4 <= hstart + hlen:
                (flen,) = struct.unpack_from("<I", data, q)
                body = data[q + 4 : q + 4 + flen]
                if b"=" in body:
                    name, value = body.split(b"=", 1)
                    fields[name.decode("latin-1")] = (q + 4 + len(name) + 1, value)
                q += 4 + flen
            dpos = hstart + hlen
            (dlen,) = struct.unpack_from("<I", data, dpos)
            yield pos, dpos, fields
            if (
                fields.get("op", (0, b""))[1] == b"\x05"
                and fields.get("compression", (0, b""))[1] == b"none"
            ):
                stack.append((dpos + 4, min(dpos + 4 + dlen, end)))
            pos = dpos + 4 + dlen


def _ros1_mutation(data: bytes, rng: random.Random) -> tuple[bytes, str]:
    records = list(_ros1_fields(data))
    if not records or rng.random() < 0.35:
        return _byte_mutation(data, rng)
    b = bytearray(data)
    hpos, dpos, fields = rng.choice(records)
    kind = rng.choice(("hlen", "dlen", "conn", "conn", "field", "time", "count"))
    if kind in ("hlen", "dlen"):
        pos = hpos if kind == "hlen" else dpos
        (old,) = struct.unpack_from("<I", b, pos)
        value = rng.choice((*HOSTILE_INTS, old + 1, max(old - 1, 0), old * 2))
        struct.pack_into("<I", b, pos, value & 0xFFFFFFFF)
        return bytes(b), f"{kind} at {pos}: {old} -> {value}"
    conns = sorted(
        {
            struct.unpack_from("<I", f["conn"][1])[0]
            for _, _, f in records
            if "conn" in f and len(f["conn"][1]) == 4
        }
    )
    with_conn = [(h, d, f) for h, d, f in records if "conn" in f and len(f["conn"][1]) == 4]
    if kind == "conn" and with_conn:
        hpos, dpos, fields = rng.choice(with_conn)
        off, value = fields["conn"]
        old = struct.unpack_from("<I", value)[0]
        new = rng.choice([c for c in conns if c != old] or [old + 1, old + 7, 0xFFFFFFFF])
        struct.pack_into("<I", b, off, new)
        return bytes(b), f"conn at {off}: {old} -> {new}"
    if kind == "time":
        timed = [(h, d, f) for h, d, f in records if "time" in f and len(f["time"][1]) == 8]
        if timed:
            _, _, fields = rng.choice(timed)
            off, _ = fields["time"]
            sec = rng.choice((0, 0xFFFFFFFF, 1, 0x7FFFFFFF))
            struct.pack_into("<II", b, off, sec, rng.choice((0, 999_999_999, 0xFFFFFFFF)))
            return bytes(b), f"time at {off} -> {sec}"
    if kind == "count":
        counted = [
            (f, k)
            for _, _, f in records
            for k in ("count", "chunk_count", "conn_count", "size", "ver")
            if k in f and len(f[k][1]) == 4
        ]
        if counted:
            f, k = rng.choice(counted)
            off, _ = f[k]
            value = rng.choice(HOSTILE_INTS)
            struct.pack_into("<I", b, off, value)
            return bytes(b), f"{k} at {off} -> {value}"
    if fields:
        name = rng.choice(sorted(fields))
        off, value = fields[name]
        new = rng.randbytes(len(value)) if value else b""
        b[off : off + len(value)] = new
        return bytes(b), f"field {name} at {off} randomised"
    return _byte_mutation(data, rng)


def _mcap_mutation(data: bytes, rng: random.Random) -> tuple[bytes, str]:
    if rng.random() < 0.4:
        return _byte_mutation(data, rng)
    positions = []
    pos = 8
    while pos + 9 <= len(data):
        (length,) = struct.unpack_from("<Q", data, pos + 1)
        positions.append(pos)
        if length > len(data):
            break
        pos += 9 + length
    if not positions:
        return _byte_mutation(data, rng)
    b = bytearray(data)
    pos = rng.choice(positions)
    kind = rng.choice(("length", "opcode", "inner"))
    if kind == "length":
        (old,) = struct.unpack_from("<Q", b, pos + 1)
        new = rng.choice((0, 1, old + 1, max(old - 1, 0), 2**32 - 1, 2**63 - 1, 2**64 - 1, old * 3))
        struct.pack_into("<Q", b, pos + 1, new)
        return bytes(b), f"record length at {pos}: {old} -> {new}"
    if kind == "opcode":
        old = b[pos]
        b[pos] = rng.choice(
            (0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 0x0A, 0x0B, 0x0C, 0x0D, 0x0E, 0x0F, 0xFF)
        )
        return bytes(b), f"opcode at {pos}: {old} -> {b[pos]}"
    (length,) = struct.unpack_from("<Q", b, pos + 1)
    if length >= 4:
        off = pos + 9 + rng.randrange(max(length - 3, 1))
        value = rng.choice((0xFFFFFFFF, 0x7FFFFFFF, 0, 12345678))
        if off + 4 <= len(b):
            struct.pack_into("<I", b, off, value)
            return bytes(b), f"inner u32 at {off} -> {value}"
    return _byte_mutation(data, rng)


SQL_EDITS = (
    "UPDATE messages SET data = CAST(data AS TEXT)",
    "UPDATE messages SET data = 'hello' WHERE id % 3 = 0",
    "UPDATE messages SET data = NULL WHERE id = 5",
    "UPDATE messages SET data = 12345 WHERE id = 2",
    "UPDATE messages SET data = x'' WHERE id = 3",
    "UPDATE messages SET data = substr(data, 1, 20) WHERE id = 4",
    "UPDATE messages SET timestamp = 'abc' WHERE id = 3",
    "UPDATE messages SET timestamp = 1.5 WHERE id = 3",
    "UPDATE messages SET timestamp = NULL WHERE id = 3",
    "UPDATE messages SET timestamp = -5 WHERE id = 3",
    "UPDATE messages SET timestamp = 9223372036854775807 WHERE id = 6",
    "UPDATE messages SET topic_id = 99 WHERE id = 3",
    "UPDATE messages SET topic_id = 'x' WHERE id = 3",
    "UPDATE messages SET topic_id = (SELECT max(id) FROM topics) WHERE id % 2 = 0",
    "UPDATE topics SET name = ''",
    "UPDATE topics SET name = NULL",
    "UPDATE topics SET name = 42",
    "UPDATE topics SET type = 'sensor_msgs/msg/Nothing'",
    "UPDATE topics SET type = ''",
    "UPDATE topics SET type = 7",
    "UPDATE topics SET serialization_format = 'ros1'",
    "UPDATE topics SET offered_qos_profiles = x'ff00ff'",
    "UPDATE topics SET offered_qos_profiles = '- {a: [[[[[[[[[[[[[[[[[[[[[[[[[[[[[[['",
    "UPDATE topics SET offered_qos_profiles = 12",
    "DELETE FROM topics WHERE id = 1",
    "DELETE FROM topics",
    "DROP TABLE messages",
    "DROP TABLE topics",
    "DROP TABLE IF EXISTS schema",
    "DROP TABLE IF EXISTS metadata",
    "UPDATE metadata SET metadata = 'rosbag2_bagfile_information: {version: x}'",
    "UPDATE metadata SET metadata = 7",
    "UPDATE metadata SET metadata = '" + "[" * 3000 + "'",
    "UPDATE schema SET schema_version = 'x'",
    "UPDATE schema SET schema_version = 99",
    "UPDATE messages SET id = id + 1000 WHERE id % 2 = 1",
    "INSERT INTO messages (topic_id, timestamp, data) VALUES (1, 0, x'00')",
    "UPDATE message_definitions SET encoded_message_definition = 'int32 x\n==='",
    "UPDATE message_definitions SET encoding = 'ros1msg'",
)


def _db3_mutation(path: Path, data: bytes, rng: random.Random, out: Path) -> str:
    if rng.random() < 0.35:
        mutated, what = _byte_mutation(data, rng)
        out.write_bytes(mutated)
        return what
    out.write_bytes(data)
    edits = rng.sample(SQL_EDITS, rng.choice((1, 1, 2)))
    con = sqlite3.connect(out)
    done = []
    for sql in edits:
        try:
            con.execute(sql)
            done.append(sql)
        except sqlite3.Error:
            continue
    con.commit()
    con.close()
    return "; ".join(done) or "no SQL edit applied"


YAML_VALUES = (
    "'abc'",
    "-1",
    "1.5",
    "null",
    "[]",
    "{}",
    "[[[[[[[[[[]]]]]]]]]]",
    "9" * 40,
    ".nan",
    ".inf",
    "zstd",
    "lz4",
    "file",
    "message",
    "'" + "x" * 10000 + "'",
    "true",
    "- a\n- b",
    "{nanoseconds: 'x'}",
    "*alias",
    "&a [*a]",
)


def _yaml_mutation(text: str, rng: random.Random) -> tuple[str, str]:
    lines = text.splitlines()
    kind = rng.choice(("value", "value", "value", "delete", "nest", "bytes", "compression"))
    if kind == "nest":
        depth = rng.choice((100, 1000, 5000, 50000))
        return text + "\nextra: " + "[" * depth + "]" * depth + "\n", f"nesting {depth}"
    if kind == "compression":
        mode = rng.choice(("file", "message", "", "FILE", "chunk", "7"))
        fmt = rng.choice(("zstd", "lz4", "bz2", "", "gzip", "[]"))
        out = []
        for line in lines:
            stripped = line.strip()
            if stripped.startswith("compression_mode:"):
                line = line.split(":")[0] + f": {mode or chr(39) * 2}"
            elif stripped.startswith("compression_format:"):
                line = line.split(":")[0] + f": {fmt or chr(39) * 2}"
            out.append(line)
        return "\n".join(out) + "\n", f"compression {mode!r}/{fmt!r}"
    if kind == "bytes":
        mutated, what = _byte_mutation(text.encode(), rng)
        return mutated.decode("latin-1"), what
    candidates = [i for i, line in enumerate(lines) if ":" in line]
    if not candidates:
        return text, "no key"
    i = rng.choice(candidates)
    if kind == "delete":
        del lines[i]
        return "\n".join(lines) + "\n", f"delete line {i}"
    key = lines[i].split(":", 1)[0]
    value = rng.choice(YAML_VALUES)
    lines[i] = f"{key}: {value}"
    return "\n".join(lines) + "\n", f"line {i} {key.strip()} = {value[:30]}"


def _npz_mutation(data: bytes, rng: random.Random) -> tuple[bytes, str]:
    if rng.random() < 0.3:
        return _byte_mutation(data, rng)
    with np.load(io.BytesIO(data), allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    key = rng.choice(sorted(arrays))
    a = arrays[key]
    kind = rng.choice(
        (
            "empty",
            "nan",
            "inf",
            "flatten",
            "reshape",
            "dtype-str",
            "dtype-float",
            "huge",
            "negative",
            "shuffle",
            "drop",
            "scalar",
            "2d",
            "bool",
            "reverse",
        )
    )
    what = f"{key}: {kind}"
    if kind == "empty":
        arrays[key] = np.empty((0,), dtype=a.dtype)
    elif kind in ("nan", "inf", "huge", "negative"):
        b = np.array(a, dtype=np.float64 if a.dtype.kind in "fiub" else a.dtype, copy=True)
        if b.size and b.dtype.kind == "f":
            idx = rng.randrange(b.size)
            value = {"nan": np.nan, "inf": np.inf, "huge": 1e300, "negative": -5.0}[kind]
            b.flat[idx] = value
            what += f" at {idx}"
            if a.dtype.kind in "iu" and kind in ("huge", "negative"):
                b = b.astype(np.int64) if kind == "negative" else np.full_like(a, 2**62)
        arrays[key] = b
    elif kind == "flatten":
        arrays[key] = a.ravel()
    elif kind == "reshape":
        arrays[key] = a.reshape(-1, 1) if a.size else a.reshape(0, 1)
    elif kind == "dtype-str":
        arrays[key] = a.astype(str)
    elif kind == "dtype-float":
        arrays[key] = a.astype(np.float64) + 0.5 if a.dtype.kind in "fiub" else a
    elif kind == "shuffle":
        b = np.array(a, copy=True)
        if b.ndim:
            np.random.default_rng(rng.randrange(2**32)).shuffle(b)
        arrays[key] = b
    elif kind == "drop":
        del arrays[key]
    elif kind == "scalar":
        arrays[key] = np.array(a.flat[0] if a.size else 0)
    elif kind == "2d":
        arrays[key] = np.stack([a, a]) if a.ndim else a
    elif kind == "bool":
        arrays[key] = np.ones(a.shape, dtype=bool)
    elif kind == "reverse":
        arrays[key] = a[::-1].copy() if a.ndim else a
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue(), what


def _text_token_mutation(text: str, rng: random.Random, sep: str) -> tuple[str, str]:
    lines = text.splitlines(keepends=True)
    if not lines:
        return text, "empty"
    kind = rng.choice(("token", "token", "token", "drop-line", "dup-line", "swap", "tokens", "big"))
    i = rng.randrange(len(lines))
    if kind == "drop-line":
        del lines[i]
        return "".join(lines), f"drop line {i}"
    if kind == "dup-line":
        lines.insert(i, lines[i])
        return "".join(lines), f"duplicate line {i}"
    if kind == "swap":
        j = rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
        return "".join(lines), f"swap lines {i},{j}"
    if kind == "big":
        return text + lines[-1].rstrip("\n") * 2000 + "\n", "one huge line"
    tokens = lines[i].rstrip("\n").split(sep)
    if kind == "tokens":
        cut = rng.randrange(len(tokens) + 1)
        tokens = tokens[:cut] if rng.random() < 0.5 else tokens + ["1"] * rng.randrange(1, 5)
        lines[i] = sep.join(tokens) + "\n"
        return "".join(lines), f"line {i} has {len(tokens)} fields"
    j = rng.randrange(len(tokens))
    value = rng.choice(HOSTILE_NUMBERS)
    tokens[j] = value
    lines[i] = sep.join(tokens) + "\n"
    return "".join(lines), f"line {i} field {j} = {value[:20]!r}"


def _csv_mutation(data: bytes, rng: random.Random) -> tuple[bytes, str]:
    if rng.random() < 0.25:
        return _byte_mutation(data, rng)
    text, what = _text_token_mutation(data.decode("utf-8"), rng, ",")
    return text.encode("utf-8", "surrogateescape"), what


def _carmen_mutation(data: bytes, rng: random.Random, gz: bool) -> tuple[bytes, str]:
    raw = gzip.decompress(data) if gz else data
    if rng.random() < 0.3:
        mutated, what = _byte_mutation(raw, rng)
    else:
        text, what = _text_token_mutation(raw.decode("ascii"), rng, " ")
        mutated = text.encode("latin-1", "replace")
    if gz:
        if rng.random() < 0.2:
            compressed, w2 = _byte_mutation(gzip.compress(mutated, mtime=0), rng)
            return compressed, f"{what}; gz {w2}"
        return gzip.compress(mutated, mtime=0), what
    return mutated, what


def _json_hostile(rng: random.Random) -> Any:
    return rng.choice(
        (
            float("inf"),
            float("-inf"),
            float("nan"),
            1e308,
            -1e308,
            10**5000,
            2**64,
            -(2**63),
            "1",
            None,
            True,
            [],
            {},
            [1, 2],
            0,
            -1,
            15,
            0.5,
        )
    )


def _json_mutation(data: bytes, rng: random.Random) -> tuple[bytes, str]:
    if rng.random() < 0.25:
        return _byte_mutation(data, rng)
    doc = json.loads(data)
    kind = rng.choice(("leaf", "leaf", "leaf", "delete", "nest", "bignum", "type"))
    if kind == "nest":
        depth = rng.choice((100, 1000, 100000))
        text = json.dumps(doc)[:-1] + ', "deep": ' + "[" * depth + "]" * depth + "}"
        return text.encode(), f"nesting {depth}"
    if kind == "bignum":
        text = json.dumps(doc).replace('"alpha": ', '"alpha": ' + "9" * 5000 + "", 1)
        text = text.replace('"alpha": ' + "9" * 5000 + "", '"alpha": ' + "9" * 5000 + ', "x": ', 1)
        return text.encode(), "5000-digit alpha"
    # collect paths to leaves
    paths: list[tuple[Any, Any]] = []

    def walk(node: Any) -> None:
        if isinstance(node, dict):
            for k in list(node):
                paths.append((node, k))
                walk(node[k])
        elif isinstance(node, list):
            for i in range(len(node)):
                paths.append((node, i))
                walk(node[i])

    walk(doc)
    parent, key = rng.choice(paths)
    if kind == "delete":
        del parent[key]
        what = f"delete {key!r}"
    elif kind == "type":
        parent[key] = rng.choice(("x", [parent[key]], {"v": parent[key]}, None))
        what = f"{key!r} wrapped"
    else:
        value = _json_hostile(rng)
        parent[key] = value
        what = f"{key!r} = {str(value)[:20]}"
    try:
        text = json.dumps(doc)
    except ValueError:
        text = json.dumps(doc, allow_nan=True)
    return text.encode(), what


def _toml_mutation(data: bytes, rng: random.Random) -> tuple[bytes, str]:
    text = data.decode("utf-8")
    kind = rng.choice(("value", "value", "value", "section", "nest", "bytes", "unknown", "hang"))
    lines = text.splitlines()
    if kind == "bytes":
        return _byte_mutation(data, rng)
    if kind == "section":
        name = rng.choice(("leg_tracker", "leg_detector"))
        value = rng.choice(("3", "true", "[1, 2]", '"x"', "1e999", "{a = 1}", "nan"))
        body = [line for line in lines if not line.startswith(f"[{name}]")]
        return (f"{name} = {value}\n" + "\n".join(body)).encode(), f"[{name}] = {value}"
    if kind == "nest":
        depth = rng.choice((50, 500, 5000, 100000))
        value = "{a = " * depth + "1" + "}" * depth
        return (f"deep = {value}\n" + text).encode(), f"inline table depth {depth}"
    if kind == "hang":
        n = rng.choice((1000, 100000, 1000000))
        value = rng.choice(("[" * n, '"' + "\\" * n, "a." * n + "b = 1", "{" * n))
        return (text + "\nx = " + value + "\n").encode(), f"pathological {n}"
    if kind == "unknown":
        return (text + "\nnot_a_param = 1\n").encode(), "unknown key"
    candidates = [i for i, line in enumerate(lines) if "=" in line]
    i = rng.choice(candidates)
    key = lines[i].split("=", 1)[0].strip()
    value = rng.choice(
        (
            "nan",
            "inf",
            "-inf",
            "+nan",
            "1e308",
            "-1e308",
            "9" * 30,
            "0",
            "-1",
            '"abc"',
            "true",
            "[]",
            "[nan, inf]",
            "{}",
            "1979-05-27",
            "-0.0",
        )
    )
    lines[i] = f"{key} = {value}"
    return ("\n".join(lines) + "\n").encode(), f"{key} = {value}"


# -- read paths ---------------------------------------------------------------------------


def read_recording(path: Path, max_scans: int, on_error: str) -> None:
    """Open, list topics, iterate scans and truth (bounded), as the commands do."""
    from laserpeople.io import open_recording

    options: dict[str, Any] = {} if on_error == "stop" else {"on_error": on_error}
    rec = open_recording(path, **options)
    try:
        listed = sum(max(int(t.count), 0) for t in rec.topics())
        n = 0
        for i, scan in enumerate(rec.scans()):
            scan.points()
            n += 1
            if i + 1 >= max_scans:
                break
        if n == 0 and listed > 0:
            raise SilentEmptyError(f"topics list {listed} scans, none read and no error")
        for i, _frame in enumerate(rec.truth()):
            if i + 1 >= max_scans:
                break
    finally:
        rec.close()


def read_model(path: Path, max_scans: int, on_error: str) -> None:
    """Load a model file and classify one feature row."""
    from laserpeople.detection.model_file import load_model

    model = load_model(path)
    model.classifier.decision_function(np.ones((1, len(model.features))))


def read_toml(path: Path, max_scans: int, on_error: str) -> None:
    """Load the detector and tracker sections, as `laserpeople track --config` does."""
    from laserpeople.config import check_sections, load_config
    from laserpeople.detection.detector import LegDetectorParams
    from laserpeople.tracking.legs import LegTrackerParams

    check_sections(path, [LegDetectorParams, LegTrackerParams])
    load_config(LegDetectorParams, path)
    load_config(LegTrackerParams, path)


def read_tracks_csv(path: Path, max_scans: int, on_error: str) -> None:
    """Read a tracks CSV as `evaluate` and `view --tracks` do."""
    from laserpeople.io.tracks_csv import iter_tracks_csv

    for i, _ in enumerate(iter_tracks_csv(path)):
        if i + 1 >= max_scans:
            break


def read_detections_csv(path: Path, max_scans: int, on_error: str) -> None:
    """Read a detections CSV."""
    from laserpeople.io.detections_csv import iter_detections_csv

    for i, _ in enumerate(iter_detections_csv(path)):
        if i + 1 >= 10 * max_scans:
            break


def read_truth(path: Path, max_scans: int, on_error: str) -> None:
    """Read a ground-truth CSV."""
    from laserpeople.io.truth_csv import read_truth_csv

    read_truth_csv(path)


def read_neko(path: Path, max_scans: int, on_error: str) -> None:
    """Read a neko7055 directory as `train --neko` does (scans, labels, segment features)."""
    from laserpeople.detection.training import neko_segments

    neko_segments(path)


class SilentEmptyError(Exception):
    """A read path returned nothing from an input that holds something, without an error."""


def read_tracks_bag(path: Path, max_scans: int, on_error: str) -> None:
    """Read a tracks bag as `evaluate TRACKS.bag` does."""
    from laserpeople.io.tracks_bag import iter_tracks_bag

    for i, _ in enumerate(iter_tracks_bag(path)):
        if i + 1 >= max_scans:
            break


def read_map(path: Path, max_scans: int, on_error: str) -> None:
    """Load a ROS map as `track --map` does and ask the seeded grid about a few points."""
    from laserpeople.background.occupancy import OccupancyGrid, load_ros_map

    grid = OccupancyGrid(prior=load_ros_map(path / "map.yaml"))
    grid.static_time(np.array([[0.0, 0.0], [1.0, -0.5], [3.0, 2.0]]))


def read_toml_track(path: Path, max_scans: int, on_error: str) -> None:
    """A whole `track --config` run of the tracker named in the file's first line."""
    from laserpeople.cli.track import run_tracking
    from laserpeople.tracking import registry

    head = path.read_bytes()[:80].decode("utf-8", "replace").splitlines()[:1]
    tracker = head[0].split(":", 1)[1].strip() if head and head[0].startswith("# tracker:") else ""
    if tracker not in registry.TRACKERS:
        tracker = "leg-mht"
    small = path.parent.parent / "seeds" / "small.npz"
    out = path.with_suffix(".tracks.csv")
    try:
        stats = run_tracking(small, out, tracker_name=tracker, config=path)
    finally:
        with contextlib.suppress(OSError):
            out.unlink()
    if not stats.get("scans"):
        raise SilentEmptyError(f"{tracker}: tracking ran over no scan")


MESSAGE_LIMIT = 1500
"""Longest error message an option value may produce (long values are cut)."""


def run_options(path: Path, max_scans: int, on_error: str) -> None:
    """Run one command line with a hostile option value in-process (as a user would)."""
    from typer.testing import CliRunner

    from laserpeople.cli import app
    from laserpeople.cli.common import STATE
    from laserpeople.errors import LaserPeopleError

    argv = json.loads(path.read_text(encoding="utf-8"))["argv"]
    STATE.quiet = True
    try:
        run = CliRunner().invoke(app, argv)
    finally:
        for out in path.parent.glob(path.stem + "_out*"):
            with contextlib.suppress(OSError):
                shutil.rmtree(out) if out.is_dir() else out.unlink()
    exc = run.exception
    if exc is None or (isinstance(exc, SystemExit) and exc.code == 0):
        return
    if isinstance(exc, SystemExit):
        text = run.output
        if len(text) > MESSAGE_LIMIT:
            raise ValueError(f"usage error message of {len(text)} characters")
        raise LaserPeopleError(f"exit {exc.code}: {text.strip()[-300:]}")
    if isinstance(exc, LaserPeopleError):
        if len(str(exc)) > MESSAGE_LIMIT:
            raise ValueError(f"error message of {len(str(exc))} characters: {str(exc)[:200]}")
        raise exc
    raise exc


READ_PATHS: dict[str, Callable[[Path, int, str], None]] = {
    "ros1": read_recording,
    "mcap": read_recording,
    "db3": read_recording,
    "ros2dir": read_recording,
    "npz": read_recording,
    "carmen": read_recording,
    "neko": read_neko,
    "tracks_ros1": read_tracks_bag,
    "tracks_mcap": read_tracks_bag,
    "tracks_db3": read_tracks_bag,
    "map": read_map,
    "toml_track": read_toml_track,
    "options": run_options,
    "model": read_model,
    "toml": read_toml,
    "tracks_csv": read_tracks_csv,
    "detections_csv": read_detections_csv,
    "truth_csv": read_truth,
}

WEIGHTS = {
    "ros1": 20,
    "mcap": 12,
    "db3": 10,
    "ros2dir": 5,
    "npz": 12,
    "carmen": 8,
    "neko": 4,
    "tracks_ros1": 6,
    "tracks_mcap": 6,
    "tracks_db3": 5,
    "map": 6,
    "toml_track": 5,
    "options": 8,
    "model": 8,
    "toml": 8,
    "tracks_csv": 6,
    "detections_csv": 4,
    "truth_csv": 5,
}


# -- cases ----------------------------------------------------------------------------------


@dataclass(frozen=True)
class Case:
    """One fuzz case: the seed file it mutates and the random seed of its mutation."""

    index: int
    fmt: str
    seed: Seed
    rng_seed: int
    on_error: str


def plan(seeds: dict[str, list[Seed]], n: int, master: int, only: set[str] | None) -> list[Case]:
    """The first ``n`` cases of the run with seed ``master``."""
    rng = random.Random(master)
    fmts = [f for f in WEIGHTS if f in seeds and (not only or f in only)]
    if not fmts:
        raise SystemExit(f"no seed files for the formats {sorted(only or WEIGHTS)}")
    weights = [WEIGHTS[f] for f in fmts]
    cases = []
    for i in range(n):
        fmt = rng.choices(fmts, weights)[0]
        seed = rng.choice(seeds[fmt])
        on_error = "skip" if rng.random() < 0.3 else "stop"
        cases.append(Case(i, fmt, seed, rng.randrange(2**63), on_error))
    return cases


def materialise(case: Case, work: Path) -> tuple[Path, str]:
    """Write the mutated file of ``case`` under ``work``; return its path and what changed."""
    rng = random.Random(case.rng_seed)
    src = case.seed.path
    fmt = case.fmt
    if fmt == "ros2dir":
        out = work / f"case{case.index}"
        if out.exists():
            shutil.rmtree(out)
        shutil.copytree(src, out)
        meta = out / "metadata.yaml"
        if rng.random() < 0.6:
            text, what = _yaml_mutation(meta.read_text(encoding="utf-8"), rng)
            meta.write_bytes(text.encode("latin-1", "replace"))
            return out, "metadata.yaml " + what
        storage = next(p for p in out.iterdir() if p.suffix in (".mcap", ".db3"))
        data = storage.read_bytes()
        if storage.suffix == ".db3":
            tmp = work / f"tmp{case.index}.db3"
            what = _db3_mutation(storage, data, rng, tmp)
            os.replace(tmp, storage)
        else:
            mutated, what = _mcap_mutation(data, rng)
            storage.write_bytes(mutated)
        return out, f"{storage.name} {what}"
    if fmt in ("map", "neko"):
        out = work / f"case{case.index}"
        if out.exists():
            shutil.rmtree(out)
        shutil.copytree(src, out)
        what = (_map_mutation if fmt == "map" else _neko_mutation)(out, rng)
        return out, what
    if fmt == "options":
        out = work / f"case{case.index}.json"
        argv, what = _option_case(src, out, rng)
        out.write_text(json.dumps({"argv": argv}), encoding="utf-8")
        return out, what
    data = src.read_bytes()
    out = (
        work
        / f"case{case.index}{''.join(src.suffixes[-2:]) if src.suffix == '.gz' else src.suffix}"
    )
    if fmt in ("db3", "tracks_db3"):
        what = _db3_mutation(src, data, rng, out)
        return out, what
    mutate: dict[str, Callable[[bytes, random.Random], tuple[bytes, str]]] = {
        "ros1": _ros1_mutation,
        "mcap": _mcap_mutation,
        "tracks_ros1": _ros1_mutation,
        "tracks_mcap": _mcap_mutation,
        "toml_track": _toml_mutation,
        "npz": _npz_mutation,
        "carmen": lambda d, r: _carmen_mutation(d, r, src.suffix == ".gz"),
        "model": _json_mutation,
        "toml": _toml_mutation,
        "tracks_csv": _csv_mutation,
        "detections_csv": _csv_mutation,
        "truth_csv": _csv_mutation,
    }
    mutated, what = _apply(mutate[fmt], data, rng)
    if rng.random() < 0.15 and fmt not in ("model", "toml", "toml_track"):
        mutated, w2 = _apply(mutate[fmt], mutated, rng)
        what = f"{what}; {w2}"
    out.write_bytes(mutated)
    return out, what


def _apply(
    mutate: Callable[[bytes, random.Random], tuple[bytes, str]], data: bytes, rng: random.Random
) -> tuple[bytes, str]:
    """A structured mutation, or a byte mutation when the input no longer parses."""
    try:
        return mutate(data, rng)
    except Exception:
        return _byte_mutation(data, rng)


def _neko_mutation(folder: Path, rng: random.Random) -> str:
    """Mutate the xy data (tokens, bytes, huge coordinates) or the labels JSON of a neko
    directory in place."""
    xy, labels = folder / "xy_data.txt", folder / "leg_segment_labels.json"
    kind = rng.choice(("xy", "xy", "labels", "labels", "special"))
    if kind == "xy":
        data = xy.read_bytes()
        if rng.random() < 0.3:
            mutated, what = _byte_mutation(data, rng)
        else:
            text, what = _text_token_mutation(data.decode("utf-8"), rng, " ")
            mutated = text.encode("utf-8")
        xy.write_bytes(mutated)
        return f"xy_data {what}"
    if kind == "labels":
        mutated, what = _apply(_json_mutation, labels.read_bytes(), rng)
        labels.write_bytes(mutated)
        return f"labels {what}"
    value = rng.choice(("Infinity", "-Infinity", "NaN", "1e300", "-1", "4294967296", '"x"'))
    labels.write_text(
        '{"description": "x", "labels": {"0": [' + value + '], "1": [0]}}', encoding="utf-8"
    )
    if rng.random() < 0.5:
        lines = xy.read_text(encoding="utf-8").splitlines()
        lines[1 + rng.randrange(len(lines) - 1)] = rng.choice(("1e308 0", "-1e308 1e308", "1e30 0"))
        xy.write_text("\n".join(lines) + "\n", encoding="utf-8")
        return f"label index {value}; a huge xy point"
    return f"label index {value}"


MAP_VALUES = (
    "1e-300",
    "1e300",
    "0",
    "-0.05",
    "nan",
    "inf",
    "[1e300, 0, 0]",
    "[nan, 0, 0]",
    "[0, 0]",
    "abc",
    "missing.pgm",
    "/dev/zero",
    "map.yaml",
    "2",
    "-1",
    "",
)


def _map_mutation(folder: Path, rng: random.Random) -> str:
    """Mutate a map folder in place: a yaml value, the PGM header's size, or PGM bytes."""
    yaml, pgm = folder / "map.yaml", folder / "map.pgm"
    kind = rng.choice(("yaml", "yaml", "header", "header", "bytes"))
    if kind == "yaml":
        lines = yaml.read_text(encoding="utf-8").splitlines()
        i = rng.randrange(len(lines))
        key = lines[i].split(":", 1)[0]
        value = rng.choice(MAP_VALUES)
        lines[i] = f"{key}: {value}"
        yaml.write_text("\n".join(lines) + "\n", encoding="utf-8")
        return f"map.yaml {key} = {value}"
    data = pgm.read_bytes()
    if kind == "header":
        w, h = rng.choice(
            ((100000, 100000), (65535, 65535), (0, 0), (1, 10**9), (4294967295, 1), (12000, 12000))
        )
        body = data.split(b"255\n", 1)[1]
        pgm.write_bytes(f"P5\n{w} {h}\n255\n".encode() + body)
        return f"PGM header {w} x {h}"
    mutated, what = _byte_mutation(data, rng)
    pgm.write_bytes(mutated)
    return f"map.pgm {what}"


OPTION_CASES: list[tuple[list[str], str]] = [
    (["info", "{rec}"], "--topic"),
    (["simulate", "demo", "-o", "{out}.npz", "-s", "2"], "--rate"),
    (["simulate", "demo", "-o", "{out}.npz"], "--seconds"),
    (["simulate", "demo", "-o", "{out}.npz", "-s", "2"], "--seed"),
    (["detect", "{rec}", "-o", "{out}.csv"], "--topic"),
    (["detect", "{rec}", "-o", "{out}.csv"], "--detector"),
    (["train", "{rec}", "-o", "{out}.json"], "--rounds"),
    (["train", "{rec}", "-o", "{out}.json"], "--jump-distance"),
    (["train", "{rec}", "-o", "{out}.json"], "--features"),
    (["track", "{rec}", "-o", "{out}.csv"], "--restamp"),
    (["track", "{rec}", "-o", "{out}.csv"], "--topic"),
    (["track", "{rec}", "-o", "{out}.csv"], "--output-frame"),
    (["track", "{rec}", "-o", "{out}.csv"], "--tracker"),
    (["track", "{rec}", "-o", "{out}.csv"], "--people-policy"),
    (["track", "{rec}", "-o", "{out}.csv", "--tracker", "csa"], "--background"),
    (["track", "{rec}", "-o", "{out}.csv"], "--mount"),
    (["track", "{rec}", "-o", "{out}.csv"], "--on-error"),
    (["evaluate", "{tracks}", "--truth", "{truth}"], "--gate"),
    (["evaluate", "{tracks}", "--truth", "{truth}"], "--kind"),
    (["evaluate", "{tracks}", "--truth", "{truth}"], "--followed-person"),
    (["view", "{rec}", "-o", "{out}.gif", "--stop", "5"], "--fps"),
    (["view", "{rec}", "-o", "{out}.png"], "--size"),
    (["view", "{rec}", "-o", "{out}.png"], "--extent"),
    (["view", "{rec}", "-o", "{out}.png"], "--scan"),
    (["view", "{rec}", "-o", "{out}.gif", "--stop", "5"], "--every"),
    (["view", "{rec}", "-o", "{out}.gif", "--stop", "5"], "--trail"),
    (["view", "{rec}", "-o", "{out}.png"], "--start"),
    (["fit", "{rec}", "--truth", "{truth}", "-o", "{out}.toml"], "--validation"),
    (["fit", "{rec}", "--truth", "{truth}", "-o", "{out}.toml"], "--min-events"),
    (["bench", "{rec}", "--tracker", "nn"], "--repeat"),
    (["bench", "{rec}", "--tracker", "nn"], "--max-scans"),
    (["align", "{rec}", "-o", "{out}.toml"], "--reference"),
]
"""Command lines (``{rec}`` a small recording, ``{tracks}``/``{truth}`` CSVs, ``{out}`` an
output stem) and the option that gets a hostile value."""

OPTION_VALUES = (
    *HOSTILE_NUMBERS,
    "1e-300",
    "1e-9",
    "99999999999",
    "-5",
    "x" * 5000,
    "all",
    "world",
    "sensor",
    "mir100",
    "a=b:1e308,0,0",
    "a=b:1,2",
    "10x10",
    "0x0",
    "99999x99999",
    "-1,1,-1,1",
    "0,0,0,0",
    "1,2,3",
)


def _option_case(folder: Path, out: Path, rng: random.Random) -> tuple[list[str], str]:
    spec = json.loads((folder / "commands.json").read_text(encoding="utf-8"))
    argv, option = rng.choice(spec)
    value = rng.choice(OPTION_VALUES)
    names = {
        "rec": str(folder / "rec.npz"),
        "tracks": str(folder / "tracks.csv"),
        "truth": str(folder / "truth.csv"),
        "out": str(out.with_name(out.stem + "_out")),
    }
    full = [a.format(**names) for a in argv] + [option, value]
    return full, f"{' '.join(argv[:1])} {option} {value[:30]!r}"


# -- running ---------------------------------------------------------------------------------


class _Timeout(BaseException):
    pass


def _on_alarm(signum: int, frame: Any) -> None:
    raise _Timeout


def run_case(case: Case, work: Path, max_scans: int, time_limit: float) -> tuple[str, str]:
    """Build and run one case in this process; returns (outcome, detail)."""
    from laserpeople.errors import LaserPeopleError

    path, what = materialise(case, work)
    # the limit is CPU time (user + system) of the worker: on a loaded machine the wall
    # clock says nothing about a hang; the parent's wall-clock deadline is the backstop
    signal.signal(signal.SIGPROF, _on_alarm)
    signal.setitimer(signal.ITIMER_PROF, time_limit)
    try:
        READ_PATHS[case.fmt](path, max_scans, case.on_error)
        outcome, detail = "ok", what
    except LaserPeopleError as exc:
        outcome, detail = "error", f"{what} -> {exc}"
    except _Timeout:
        outcome, detail = "bad-timeout", what
    except MemoryError:
        outcome, detail = "bad-memory", what
    except SilentEmptyError as exc:
        outcome, detail = "bad-empty", f"{what} -> {exc}"
    except RecursionError as exc:
        outcome, detail = "bad-exception", f"{what} -> RecursionError {str(exc)[:80]}"
    except Exception as exc:
        tb = traceback.extract_tb(exc.__traceback__)
        where = "; ".join(f"{Path(f.filename).name}:{f.lineno}" for f in tb[-3:])
        outcome, detail = (
            "bad-exception",
            f"{what} -> {type(exc).__name__}: {str(exc)[:200]} [{where}]",
        )
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
    if path.is_dir():
        shutil.rmtree(path, ignore_errors=True)
    else:
        with contextlib.suppress(OSError):
            path.unlink()
    return outcome, detail


def _worker(
    cases: list[Case], work: Path, max_scans: int, time_limit: float, mem_mb: int, wfd: int
) -> None:
    limit = resource.getrusage(resource.RUSAGE_SELF)  # touch
    del limit
    vm = _vm_bytes()
    cap = vm + mem_mb * 2**20
    resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
    quiet = os.open(os.devnull, os.O_WRONLY)  # the commands' status lines and warnings
    os.dup2(quiet, 1)
    os.dup2(quiet, 2)
    with os.fdopen(wfd, "w", buffering=1) as out:
        for case in cases:
            out.write(json.dumps({"start": case.index}) + "\n")
            outcome, detail = run_case(case, work, max_scans, time_limit)
            out.write(
                json.dumps({"index": case.index, "outcome": outcome, "detail": detail}) + "\n"
            )


def _vm_bytes() -> int:
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")


WALL_FACTOR = 20
"""A worker silent for this many times the per-case CPU limit (plus 30 s) of wall time is
killed as hung (generous: the machine may be loaded)."""


def run_batch(
    cases: list[Case], work: Path, max_scans: int, time_limit: float, mem_mb: int
) -> list[dict[str, Any]]:
    """Run ``cases`` in forked workers; a worker that dies or hangs fails its current case
    and a new worker continues with the next one."""
    results: list[dict[str, Any]] = []
    pending = list(cases)
    while pending:
        rfd, wfd = os.pipe()
        pid = os.fork()
        if pid == 0:
            os.close(rfd)
            code = 0
            try:
                _worker(pending, work, max_scans, time_limit, mem_mb, wfd)
            except BaseException:
                code = 3
            os._exit(code)
        os.close(wfd)
        current: int | None = None
        done: set[int] = set()
        buf = b""
        deadline = time.monotonic() + WALL_FACTOR * time_limit + 30
        killed = False
        with os.fdopen(rfd, "rb", buffering=0) as fh:
            os.set_blocking(fh.fileno(), False)
            while True:
                try:
                    chunk = fh.read(65536)
                except BlockingIOError:
                    chunk = None
                if chunk == b"":
                    break
                if chunk:
                    buf += chunk
                    *lines, buf = buf.split(b"\n")
                    for line in lines:
                        msg = json.loads(line)
                        if "start" in msg:
                            current = msg["start"]
                            deadline = time.monotonic() + WALL_FACTOR * time_limit + 30
                        else:
                            results.append(msg)
                            done.add(msg["index"])
                            current = None
                    continue
                if time.monotonic() > deadline:
                    os.kill(pid, signal.SIGKILL)
                    killed = True
                    break
                time.sleep(0.005)
        _, status = os.waitpid(pid, 0)
        if current is not None:
            results.append(
                {
                    "index": current,
                    "outcome": "bad-timeout" if killed else "bad-memory",
                    "detail": f"worker {'killed after hang' if killed else 'died'} "
                    f"(status {status})",
                }
            )
            done.add(current)
        pending = [c for c in pending if c.index not in done]
    return results


def main(argv: list[str] | None = None) -> int:
    """Command line: run the fuzz cases and print counts per format and outcome."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", type=int, default=10000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--max-scans", type=int, default=60)
    ap.add_argument("--time-limit", type=float, default=10.0, help="seconds per case")
    ap.add_argument("--mem-mb", type=int, default=768, help="address space per worker [MiB]")
    ap.add_argument("--batch", type=int, default=250)
    ap.add_argument("--jobs", type=int, default=1, help="batches run at the same time")
    ap.add_argument(
        "--only",
        action="append",
        choices=sorted(WEIGHTS),
        help="formats to fuzz (repeatable)",
    )
    ap.add_argument("--show", type=int, default=3, help="bad cases to print per format")
    ap.add_argument("--replay", type=int, action="append", help="run one case in-process")
    ap.add_argument("--json", type=Path, help="write every result to this file")
    ap.add_argument(
        "--log",
        type=Path,
        help="append each result to this JSON-lines file as it comes (a long run can be "
        "read while it goes)",
    )
    ap.add_argument("--stop-only", action="store_true", help="run every case with on_error='stop'")
    args = ap.parse_args(argv)

    root = Path(tempfile.mkdtemp(prefix="lp-fuzz-"))
    try:
        seeds = build_seeds(root / "seeds")
        n = max(args.cases, max(args.replay or [0]) + 1)
        cases = plan(seeds, n, args.seed, set(args.only) if args.only else None)
        if args.stop_only:
            cases = [dataclasses.replace(c, on_error="stop") for c in cases]
        work = root / "work"
        work.mkdir()
        if args.replay:
            for i in args.replay:
                case = cases[i]
                path, what = materialise(case, work)
                print(f"case {i}: {case.fmt} {case.seed.name} on_error={case.on_error}: {what}")
                try:
                    READ_PATHS[case.fmt](path, args.max_scans, case.on_error)
                    print("  ok")
                except Exception:
                    traceback.print_exc()
            return 0
        t0 = time.monotonic()
        results: list[dict[str, Any]] = []
        batches = [cases[i : i + args.batch] for i in range(0, len(cases), args.batch)]
        pool = ThreadPoolExecutor(max_workers=max(args.jobs, 1))
        runs = [
            pool.submit(run_batch, batch, work, args.max_scans, args.time_limit, args.mem_mb)
            for batch in batches
        ]
        for future in as_completed(runs):
            done = future.result()
            results.extend(done)
            if args.log:
                with args.log.open("a", encoding="utf-8") as log:
                    for r in done:
                        fmt = cases[r["index"]].fmt
                        log.write(json.dumps({**r, "fmt": fmt, "seed": args.seed}) + "\n")
            print(
                f"\r{len(results)}/{len(cases)} cases, {time.monotonic() - t0:.0f} s",
                end="",
                file=sys.stderr,
                flush=True,
            )
        pool.shutdown()
        print(file=sys.stderr)
    finally:
        shutil.rmtree(root, ignore_errors=True)
    by_index = {c.index: c for c in cases}
    table: dict[str, Counter[str]] = defaultdict(Counter)
    bad: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for r in results:
        fmt = by_index[r["index"]].fmt
        table[fmt][r["outcome"]] += 1
        if r["outcome"].startswith("bad"):
            bad[fmt].append(r)
    print(f"seed {args.seed}, {len(results)} cases, {time.monotonic() - t0:.0f} s")
    print(f"| format | cases | {' | '.join(OUTCOMES)} |")
    print("|---|---:|" + "---:|" * len(OUTCOMES))
    total: Counter[str] = Counter()
    for fmt in WEIGHTS:
        if fmt not in table:
            continue
        row = table[fmt]
        total.update(row)
        cells = " | ".join(str(row[o]) for o in OUTCOMES)
        print(f"| {fmt} | {sum(row.values())} | {cells} |")
    cells = " | ".join(str(total[o]) for o in OUTCOMES)
    print(f"| all | {sum(total.values())} | {cells} |")
    for fmt, items in bad.items():
        for r in items[: args.show]:
            c = by_index[r["index"]]
            print(
                f"  BAD {fmt} case {r['index']} ({c.seed.name}, {c.on_error}): "
                f"{r['outcome']}: {r['detail'][:400]}"
            )
    if args.json:
        args.json.write_text(json.dumps(results, indent=0), encoding="utf-8")
    return 1 if any(o.startswith("bad") for o in total if total[o]) else 0


if __name__ == "__main__":
    sys.exit(main())
