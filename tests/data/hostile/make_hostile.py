"""Write the small hostile files of ``tests/data/hostile/`` (issue 36: hardening, round two).

Each file reproduces one cause of a bad ending found by the mutation campaign; the tests in
``tests/test_hardening_hostile.py`` read them. Run from the repository root to rebuild them
(the output is deterministic)::

    PYTHONPATH=src python tests/data/hostile/make_hostile.py

One file is not kept: a CSV field over the 131,072-character limit needs a 128 KiB file, so
:func:`long_field_csv` writes it where a test asks for it.
"""

from __future__ import annotations

import math
import sqlite3
import struct
import sys
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent


def small_scans(n: int = 8, sensor: str = "scan", pose: bool = True) -> list[Any]:
    """``n`` scans of 41 beams at 10 Hz, with a slowly moving pose."""
    from laserpeople.scan import Pose2D, Scan

    rng = np.random.default_rng(36)
    return [
        Scan(
            stamp=10.0 + 0.1 * k,
            angle_min=-1.0,
            angle_increment=0.05,
            ranges=1.0 + rng.random(41),
            range_min=0.05,
            range_max=8.0,
            sensor=sensor,
            pose=Pose2D(0.1 * k, 0.0, 0.01 * k) if pose else None,
            index=k,
        )
        for k in range(n)
    ]


def _tracks(k: int) -> Any:
    """Two person tracks of frame ``k`` (a :class:`~laserpeople.tracks.Tracks`)."""
    from laserpeople.tracks import Track, Tracks

    tracks = tuple(
        Track(
            track_id=j + 1,
            kind="person",
            position=np.array([1.0 + 0.1 * k, float(j)]),
            velocity=np.array([0.5, 0.0]),
            covariance=np.eye(2) * 0.01,
        )
        for j in range(2)
    )
    return Tracks(10.0 + 0.1 * k, k, tracks, "world")


def tracks_bag(path: Path, frames: int = 4) -> None:
    """A tracks bag as ``track --bag`` writes it, cut down to its person topic (no scans,
    no markers: a small file)."""
    from laserpeople.io.rosbag_writer import open_bag
    from laserpeople.io.tracks_bag import (
        PEOPLE_TYPE,
        TRACK_TOPICS,
        TracksBagWriter,
        build_message,
    )

    with open_bag(path) as sink:
        writer = TracksBagWriter(sink, scans=False)
        for k in range(frames):
            tracks = _tracks(k)
            people = [writer._person(t, k) for t in tracks.tracks]
            header = sink.header(tracks.stamp, "world")
            msg = build_message(sink.typestore, PEOPLE_TYPE, header=header, people=people)
            sink.write(TRACK_TOPICS["person"], PEOPLE_TYPE, msg, tracks.stamp)


def ros1_records(data: bytes) -> list[tuple[int, int, dict[str, bytes]]]:
    """(record start, data length offset, header fields) of the top-level ROS 1 records."""
    out = []
    pos = 13
    while pos + 8 <= len(data):
        (hlen,) = struct.unpack_from("<I", data, pos)
        fields, q = {}, pos + 4
        while q < pos + 4 + hlen:
            (flen,) = struct.unpack_from("<I", data, q)
            name, _, value = data[q + 4 : q + 4 + flen].partition(b"=")
            fields[name.decode()] = value
            q += 4 + flen
        dpos = pos + 4 + hlen
        (dlen,) = struct.unpack_from("<I", data, dpos)
        out.append((pos, dpos, fields))
        pos = dpos + 4 + dlen
    return out


def _corrupt_first_chunk_length(path: Path) -> None:
    raw = bytearray(path.read_bytes())
    chunk = next(d for _, d, f in ros1_records(bytes(raw)) if f.get("op") == b"\x05")
    struct.pack_into("<I", raw, chunk, 0xFFFFFFF0)
    path.write_bytes(bytes(raw))


def make_tracks_bags(out: Path) -> None:
    """Cause 1: tracks bags that are cut short, malformed or carry a corrupt length."""
    full = out / "_full.mcap"
    tracks_bag(full)
    data = full.read_bytes()
    (out / "tracks_truncated.mcap").write_bytes(data[: len(data) * 3 // 5])
    full.unlink()

    db3 = out / "tracks_malformed.db3"
    tracks_bag(db3)
    con = sqlite3.connect(db3)  # small pages: a small file
    con.execute("PRAGMA page_size = 512")
    con.execute("VACUUM")
    con.close()
    raw = bytearray(db3.read_bytes())
    page = 512
    raw[3 * page : 4 * page] = b"\xa5" * page  # "database disk image is malformed"
    db3.write_bytes(bytes(raw))

    bag = out / "tracks_chunk_length.bag"
    tracks_bag(bag)
    _corrupt_first_chunk_length(bag)


def make_poses(out: Path) -> None:
    """Cause 3: a tf translation of 1e300 m; CARMEN odometry at x = 2**32 m; a map
    resolution of 1e-300 m."""
    from laserpeople.io.carmen import write_carmen_log
    from laserpeople.io.rosbag_writer import open_bag
    from laserpeople.scan import Pose2D

    with open_bag(out / "tf_1e300.mcap") as sink:
        for scan in small_scans(4, pose=False):
            sink.scan(scan, "/scan", "laser")
            sink.pose(scan.stamp, "odom", "laser", Pose2D(1e300, 0.0, 0.0), "/tf")
    log = out / "odom_2e32.log"
    write_carmen_log(log, small_scans(4))
    lines = []
    for line in log.read_text(encoding="ascii").splitlines():
        tokens = line.split()
        if tokens and tokens[0] == "ODOM":
            tokens[1] = "4294967296"
        lines.append(" ".join(tokens))
    log.write_text("\n".join(lines) + "\n", encoding="ascii")
    _map(out / "map_resolution", "resolution: 1e-300", 20, 10)


def _map(folder: Path, resolution_line: str, width: int, height: int, pixels: int = -1) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    n = width * height if pixels < 0 else pixels
    (folder / "map.pgm").write_bytes(f"P5\n{width} {height}\n255\n".encode() + b"\xfe" * n)
    (folder / "map.yaml").write_text(
        f"image: map.pgm\n{resolution_line}\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n",
        encoding="utf-8",
    )


def make_map_bomb(out: Path) -> None:
    """Cause 4: a PGM whose header claims 100000 x 100000 pixels (the file holds 64)."""
    _map(out / "map_bomb", "resolution: 0.05", 100000, 100000, pixels=64)


def make_neko(out: Path) -> None:
    """Cause 5: neko7055 labels with an index ``Infinity``; xy data with +-1e308."""
    beams, frames = 8, 2
    good = "\n".join(f"{1.0 + 0.1 * i:.2f} {0.5:.2f}" for i in range(beams * frames))
    for name, xy, labels in (
        ("neko_infinity", good, '{"description": "x", "labels": {"0": [Infinity], "1": [0]}}'),
        (
            "neko_huge_xy",
            good.replace("1.30 0.50", "1e308 -1e308", 1),
            '{"description": "x", "labels": {"0": [0], "1": [1]}}',
        ),
    ):
        folder = out / name
        folder.mkdir(parents=True, exist_ok=True)
        (folder / "xy_data.txt").write_text(f"{beams} 2 {frames}\n{xy}\n", encoding="utf-8")
        (folder / "leg_segment_labels.json").write_text(labels, encoding="utf-8")


def make_range_limits(out: Path) -> None:
    """Cause 9: scans whose range limits leave no usable beam (range_max NaN in a bag,
    range_min > range_max in a recording, range_max 0 in a CARMEN log)."""
    from laserpeople.io import write_recording
    from laserpeople.io.carmen import write_carmen_log
    from laserpeople.io.rosbag_writer import write_laserscan_bag

    scans = small_scans(4)
    for scan in scans:  # past the checks of Scan, as a broken driver writes them
        object.__setattr__(scan, "range_max", math.nan)
    write_laserscan_bag(out / "range_max_nan.mcap", scans)
    write_recording(out / "range_limits_crossed.npz", small_scans(4))
    with np.load(out / "range_limits_crossed.npz") as z:
        arrays = {k: z[k] for k in z.files}
    arrays["scan_range_min"][:] = 5.0
    arrays["scan_range_max"][:] = 1.0
    np.savez_compressed(out / "range_limits_crossed.npz", **arrays)  # type: ignore[arg-type]
    scans = small_scans(4)
    for scan in scans:
        object.__setattr__(scan, "range_max", 0.0)
    write_carmen_log(out / "range_max_zero.log", scans)


def make_misc(out: Path) -> None:
    """Causes 6, 7, 8, 10 and the extras: a TOML with a huge free range, a small recording
    for the option values, a tracks CSV whose rows of one scan disagree on the stamp, a
    recording whose first chunk is damaged before its first scan."""
    from laserpeople.io import write_recording
    from laserpeople.io.rosbag_writer import write_laserscan_bag
    from laserpeople.io.tracks_csv import TracksCsvWriter

    (out / "free_range.toml").write_text("[occupancy]\nfree_range = 1e308\n", encoding="utf-8")
    write_recording(out / "small.npz", small_scans(20))
    csv = out / "tracks_stamps_differ.csv"
    with TracksCsvWriter(csv) as writer:
        for k in range(3):
            writer.write(_tracks(k))
    lines = csv.read_text(encoding="utf-8").splitlines()
    lines[2] = lines[2].replace("10.000000", "10.500000", 1)  # scan 0's second row
    csv.write_text("\n".join(lines) + "\n", encoding="utf-8")
    bag = out / "first_chunk.mcap"
    write_laserscan_bag(bag, small_scans(3, pose=False))
    raw = bytearray(bag.read_bytes())
    pos = 8  # after the magic: records of opcode (1 byte) and length (8 bytes)
    while raw[pos] != 0x06:  # the first chunk
        pos += 9 + struct.unpack_from("<Q", raw, pos + 1)[0]
    start = pos + 9 + 8 + 8 + 8 + 4  # its compression string
    start += 4 + struct.unpack_from("<I", raw, start)[0] + 8  # its records
    raw[start : start + 9] = b"\xff" * 9  # the first record's opcode and length
    bag.write_bytes(bytes(raw))


def long_field_csv(path: Path, header: str, row_head: str) -> Path:
    """Cause 2: a CSV whose row has a field of 140,000 characters (written on demand)."""
    path.write_text(f"{header}\n{row_head}{'9' * 140_000}\n", encoding="utf-8")
    return path


def main() -> None:
    """Write every kept file into this folder."""
    for make in (
        make_tracks_bags,
        make_poses,
        make_map_bomb,
        make_neko,
        make_range_limits,
        make_misc,
    ):
        make(HERE)
    for path in sorted(HERE.rglob("*")):
        if path.is_file() and path.suffix != ".py":
            print(f"{path.stat().st_size:>8}  {path.relative_to(HERE)}", file=sys.stderr)


if __name__ == "__main__":
    main()
