"""Latency of `laserpeople live`: from publishing a scan to receiving its people, over Zenoh.

A simulated scene is played at a fixed scan rate as CDR ``sensor_msgs/LaserScan`` into a
Zenoh session on loopback; ``laserpeople live`` runs as its own process (as on a robot),
tracks with the leg MHT and publishes ``people_msgs/People``; this script receives them
and measures, per scan, the time from its publication to the arrival of its people message
(matched by the header stamp). Printed per run: scans sent, frames published, dropped
scans (from live's summary), latency median and p99 [ms], and live's CPU time per scan
[ms] (user + system time of the process over the scans it tracked, start-up excluded).

Runs: the ``demo`` scene (4 people) and the ``entrance-hall`` scene (up to 20 people) at
40 Hz with the default queue (1 scan: keep the newest); then the entrance hall at 4x the
rate live sustained on it (1000 / CPU ms per scan): the queue stays bounded, drops are
counted and the latency stays bounded instead of growing.

    PYTHONPATH=src .venv/bin/python benchmarks/bench_live.py            # about 2 minutes
    PYTHONPATH=src .venv/bin/python benchmarks/bench_live.py --seconds 20 --json live.json
"""

from __future__ import annotations

import argparse
import json
import os
import re
import socket
import subprocess
import sys
import threading
import time
from dataclasses import asdict, dataclass, replace
from pathlib import Path

from laserpeople.live.keys import BridgeKeys
from laserpeople.live.messages import Message, RosEncoder, ros2_typestore
from laserpeople.live.zenoh_link import Publishers, Subscriptions, ZenohSettings, open_session
from laserpeople.samples import quantile
from laserpeople.scan import Scan
from laserpeople.sim import run_scenario

TOPIC = "/laser"
VERBOSE = False


@dataclass
class Result:
    scene: str
    rate_hz: float
    people_in_view: float
    sent: int
    received: int
    dropped: int
    median_ms: float
    p99_ms: float
    max_ms: float
    cpu_ms_per_scan: float


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def cpu_seconds(pid: int) -> float:
    """User + system CPU time of a process [s] (Linux /proc)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def scene(
    name: str, seconds: float, rate: float, last: int | None = None
) -> tuple[list[Scan], float]:
    """Scans of a simulated scene at ``rate`` [Hz] (the ``last`` ones only, when given) and
    the mean number of people in view in them."""
    result = run_scenario(name, seconds=seconds, seed=0, rate=rate)
    first = result.scans[0].sensor
    scans = [s for s in result.scans if s.sensor == first]
    if last is not None:
        scans = scans[-last:]
    wanted = {s.index for s in scans}
    counts = [len(t.positions) for t in result.truth if t.scan_index in wanted]
    return scans, (sum(counts) / len(counts) if counts else 0.0)


def run(name: str, scans: list[Scan], people: float, rate: float, queue: int) -> Result:
    """Play ``scans`` at ``rate`` into a live process and time the people coming back."""
    port = free_port()
    endpoint = f"tcp/127.0.0.1:{port}"
    cmd = [sys.executable, "-m", "laserpeople.cli", "live", "--topic", TOPIC, "--frame", "sensor"]
    cmd += ["--connect", endpoint, "--queue", str(queue), "--max-scans", str(len(scans))]
    cmd += ["--duration", str(len(scans) / rate + 30)]
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1] / "src")}
    session = open_session(ZenohSettings(listen=(endpoint,)))
    keys = BridgeKeys()
    store = ros2_typestore()
    encoder = RosEncoder(store)
    sent_at: dict[int, float] = {}
    latencies: list[float] = []
    lock = threading.Lock()

    def on_people(data: bytes) -> None:
        now = time.monotonic()
        msg = store.deserialize_cdr(data, "people_msgs/msg/People")
        key = round((msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec) / 1e3)
        with lock:
            t = sent_at.get(key)
            if t is not None:
                latencies.append(1e3 * (now - t))

    subs = Subscriptions(session, keys)
    subs.add("/laserpeople/people", "people_msgs/msg/People", on_people)
    pubs = Publishers(session, keys, block=True)
    payloads = []
    for s in scans:
        data = encoder.scan(s, TOPIC, "laser")
        back = store.deserialize_cdr(data, "sensor_msgs/msg/LaserScan").header.stamp
        payloads.append((round((back.sec * 1_000_000_000 + back.nanosec) / 1e3), data))
    proc = subprocess.Popen(
        cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
    )
    try:
        if not pubs.matched(TOPIC, "sensor_msgs/msg/LaserScan", timeout=60):
            raise SystemExit("live did not subscribe within 60 s")
        time.sleep(1.0)
        cpu0 = cpu_seconds(proc.pid)
        start = time.monotonic()
        for i, (key, data) in enumerate(payloads):
            due = start + i / rate
            wait = due - time.monotonic()
            if wait > 0:
                time.sleep(wait)
            with lock:
                sent_at[key] = time.monotonic()
            pubs.publish([Message(TOPIC, "sensor_msgs/msg/LaserScan", data, 0.0)])
        cpu1 = cpu_seconds(proc.pid)
        output, _ = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
        subs.close()
        pubs.close()
        session.close()
    if VERBOSE:
        print(output, file=sys.stderr)
    dropped = re.search(r"(\d+) dropped \(queue full\)", output)
    frames = re.search(r"(\d+) frames tracked", output)
    if dropped is None or frames is None:
        raise SystemExit(f"unexpected output of live:\n{output}")
    tracked = max(1, int(frames.group(1)))
    return Result(
        name,
        rate,
        round(people, 1),
        len(scans),
        len(latencies),
        int(dropped.group(1)),
        round(quantile(latencies, 0.5), 2),
        round(quantile(latencies, 0.99), 2),
        round(max(latencies, default=0.0), 2),
        round(1e3 * (cpu1 - cpu0) / tracked, 2),
    )


def restamped(scans: list[Scan], rate: float) -> list[Scan]:
    """The scans with stamps at ``rate`` [Hz] from the first one's."""
    t0 = scans[0].stamp
    return [replace(s, stamp=t0 + i / rate) for i, s in enumerate(scans)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=10.0, help="scene length [s]")
    parser.add_argument("--rate", type=float, default=40.0, help="scan rate [Hz]")
    parser.add_argument("--json", type=Path, help="also write the rows as JSON")
    parser.add_argument("--verbose", action="store_true", help="print live's own summary")
    args = parser.parse_args()
    global VERBOSE
    VERBOSE = args.verbose
    rows = []
    header = (
        f"{'scene':<14} {'Hz':>6} {'people':>6} {'sent':>5} {'recv':>5} {'dropped':>7} "
        f"{'median ms':>9} {'p99 ms':>8} {'max ms':>8} {'CPU ms/scan':>11}"
    )
    print(header)

    def show(r: Result) -> None:
        rows.append(r)
        print(
            f"{r.scene:<14} {r.rate_hz:>6.1f} {r.people_in_view:>6.1f} {r.sent:>5} "
            f"{r.received:>5} {r.dropped:>7} {r.median_ms:>9.1f} {r.p99_ms:>8.1f} "
            f"{r.max_ms:>8.1f} {r.cpu_ms_per_scan:>11.2f}",
            flush=True,
        )

    demo, demo_people = scene("demo", args.seconds, args.rate)
    show(run("demo", demo, demo_people, args.rate, queue=1))
    # the crowded end of the scene (people come in over its first half)
    hall, hall_people = scene(
        "entrance-hall", max(2 * args.seconds, 30.0), args.rate, int(args.seconds * args.rate)
    )
    last = run("entrance-hall", hall, hall_people, args.rate, queue=1)
    show(last)
    sustainable = 1e3 / max(last.cpu_ms_per_scan, 1e-3)
    fast = 4.0 * sustainable
    # as long a run in wall time as at 40 Hz: 4x as many scans of the same scene
    more = int(args.seconds * fast)
    long_hall, long_people = scene(
        "entrance-hall", more / args.rate + args.seconds, args.rate, more
    )
    show(run("hall 4x", restamped(long_hall, fast), long_people, fast, queue=1))
    if args.json:
        args.json.write_text(json.dumps([asdict(r) for r in rows], indent=2))


if __name__ == "__main__":
    main()
