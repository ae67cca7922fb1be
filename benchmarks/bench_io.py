"""Reading speed and memory of the recording readers.

Run: ``.venv/bin/python benchmarks/bench_io.py [--runs 7]``

* scans/s reading the 768-beam ROS 1 bags ``positive_not_extracted/positive_*.bag``
  (2456 scans) through :class:`~laserpeople.io.rosbag.RosbagRecording`: median of the runs;
* peak Python heap while streaming them (tracemalloc, a separate run) and the process's
  peak resident set size;
* for comparison, scans/s of rosbags' own decoding alone, of the CARMEN reader on the
  same scans written as a CARMEN log, and of writing them to ``.mcap``.
"""

from __future__ import annotations

import argparse
import resource
import statistics
import sys
import tempfile
import time
import tracemalloc
from collections.abc import Callable
from pathlib import Path

from laserpeople.io.carmen import CarmenRecording, write_carmen_log
from laserpeople.io.rosbag import RosbagRecording
from laserpeople.io.rosbag_writer import write_laserscan_bag

REPO = Path(__file__).resolve().parents[1]
DATA = REPO.parent / "shared" / "data"
BAGS = sorted(DATA.glob("leg_tracker/rosbags/training_scans_res=0.33/positive_not_extracted/*.bag"))


def read_bags() -> int:
    n = 0
    for path in BAGS:
        with RosbagRecording(path) as rec:
            for scan in rec.scans():
                n += scan.n_beams > 0
    return n


def decode_only() -> int:
    from rosbags.highlevel import AnyReader

    n = 0
    for path in BAGS:
        with AnyReader([path]) as reader:
            for conn, _, raw in reader.messages():
                reader.deserialize(raw, conn.msgtype)
                n += 1
    return n


def timed(fn: Callable[[], int], runs: int) -> tuple[float, int]:
    rates = []
    count = 0
    for _ in range(runs):
        t0 = time.perf_counter()
        count = fn()
        rates.append(count / (time.perf_counter() - t0))
    return statistics.median(rates), count


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--runs", type=int, default=7)
    args = parser.parse_args()
    if not BAGS:
        sys.exit(f"no bags found under {DATA}")

    rate, count = timed(read_bags, args.runs)
    print(
        f"RosbagRecording, 768-beam ROS 1 bags: {count} scans, median {rate:,.0f} scans/s "
        f"over {args.runs} runs"
    )
    rate, _ = timed(decode_only, args.runs)
    print(f"  rosbags decoding alone:              median {rate:,.0f} scans/s")

    tracemalloc.start()
    read_bags()
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    print(f"  peak Python heap while streaming:    {peak / 2**20:.1f} MiB (tracemalloc)")

    with tempfile.TemporaryDirectory() as tmp:
        with RosbagRecording(BAGS[0]) as rec:
            scans = list(rec.scans())
        log = Path(tmp) / "bench.log"
        write_carmen_log(log, scans)

        def read_carmen() -> int:
            return sum(1 for _ in CarmenRecording(log).scans())

        rate, count = timed(read_carmen, args.runs)
        print(
            f"CarmenRecording, same scans as RAWLASER1: {count} scans, median {rate:,.0f} scans/s"
        )

        def write_mcap() -> int:
            out = Path(tmp) / "bench.mcap"
            out.unlink(missing_ok=True)
            return write_laserscan_bag(out, scans)

        rate, count = timed(write_mcap, args.runs)
        print(f"write_laserscan_bag .mcap: {count} scans, median {rate:,.0f} scans/s")

    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"peak resident set size of this process: {rss:.0f} MiB")


if __name__ == "__main__":
    main()
