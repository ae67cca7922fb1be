"""Run `live` on a bag played into Zenoh on loopback, and the same bag through `track`'s
pipeline, for tests and benchmarks."""

from __future__ import annotations

import socket
import threading
import time
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from laserpeople.frame import Frame
from laserpeople.tracks import Tracks

KINDS = ("person", "leg")
Rows = dict[int, list[tuple[str, int, float, float]]]
"""scan index -> (kind, id, x, y) sorted."""


def free_port() -> int:
    """A TCP port free on loopback now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def play_when_subscribed(bag: Path, topic: str, port: int) -> threading.Thread:
    """A thread that connects to a `live` command listening on loopback ``port``, waits
    (up to 60 s) until it has subscribed to ``topic``, then plays ``bag`` into it at twice
    its speed over the bridge's keys (started)."""

    def play() -> None:
        from laserpeople.live.replay import replay_bag
        from laserpeople.live.runner import key_style
        from laserpeople.live.zenoh_link import Publishers, ZenohSettings, open_session

        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:  # until the command listens and has subscribed
            tx = open_session(ZenohSettings(connect=(f"tcp/127.0.0.1:{port}",)))
            pubs = Publishers(tx, key_style("bridge"), block=True)
            if pubs.matched(topic, "sensor_msgs/msg/LaserScan", timeout=2.0):
                time.sleep(0.5)
                replay_bag(bag, pubs.publish, speed=2.0)
                tx.close()
                return
            tx.close()

    player = threading.Thread(target=play, daemon=True)
    player.start()
    return player


class Collect:
    """A pipeline sink keeping (kind, id, x, y) per frame index."""

    def __init__(self) -> None:
        self.rows: Rows = {}

    def write(self, frame: Frame, tracks: Tracks | None) -> None:
        if tracks is not None:
            self.rows[frame.index] = sorted(
                (t.kind, int(t.track_id), float(t.position[0]), float(t.position[1]))
                for t in tracks
                if t.kind in KINDS
            )

    def close(self) -> None:
        """Nothing to flush: the rows are kept in memory."""


def track_rows(
    bag: Path,
    topics: Sequence[str],
    mounts: Sequence[str] = (),
    max_frames: int | None = None,
    frame: str = "auto",
) -> Rows:
    """What `track` computes for ``bag`` (default leg-mht), per frame."""
    from laserpeople.pipeline import build

    sink = Collect()
    build(
        bag,
        topics=list(topics),
        mounts=list(mounts),
        outputs=[sink],
        max_frames=max_frames,
        frame=frame,  # type: ignore[arg-type]
    ).run()
    return sink.rows


@dataclass
class LiveResult:
    rows: Rows
    session: Any
    stats: Any
    received: int
    people_keys: set[str] = field(default_factory=set)
    tokens: list[str] = field(default_factory=list)


def live_rows(
    bag: Path,
    topics: Sequence[str],
    *,
    transport: str = "bridge",
    mounts: Sequence[str] = (),
    frame: str = "sensor",
    max_scans: int,
    speed: float = 4.0,
    depth: int = 100_000,
    extra_sinks: Sequence[Any] = (),
    make_pipeline: Any = None,
    tf_wait: float = 2.0,
) -> LiveResult:
    """Play ``bag`` into a Zenoh session on loopback, run live on it, and receive the
    published people and legs in a third session."""
    from laserpeople.io.poses import parse_mounts
    from laserpeople.live.messages import ros2_typestore
    from laserpeople.live.replay import replay_bag
    from laserpeople.live.runner import LiveSession, LiveTopics, tracker_pipelines
    from laserpeople.live.zenoh_link import Publishers, Subscriptions, ZenohSettings, open_session

    endpoint = f"tcp/127.0.0.1:{free_port()}"
    session = LiveSession(
        LiveTopics(lasers=tuple(topics)),
        ZenohSettings(listen=(endpoint,)),
        transport,  # type: ignore[arg-type]
        make_pipeline or tracker_pipelines("leg-mht"),
        mounts=parse_mounts(list(mounts)),
        use_poses=frame != "sensor",
        frame=frame,  # type: ignore[arg-type]
        depth=depth,
        tf_wait=tf_wait,
        order_wait=tf_wait,
        extra_sinks=extra_sinks,
    )
    session.scans.limit = max_scans
    store = ros2_typestore()
    rx = open_session(ZenohSettings(connect=(endpoint,)))
    tx = open_session(ZenohSettings(connect=(endpoint,)))
    rows: Rows = defaultdict(list)
    keys: set[str] = set()
    lock = threading.Lock()

    def on_people(data: bytes) -> None:
        msg = store.deserialize_cdr(data, "people_msgs/msg/People")
        with lock:
            for p in msg.people:
                tags = dict(zip(p.tagnames, p.tags, strict=True))
                rows[int(tags["scan"])].append(
                    (tags["kind"], int(p.name), float(p.position.x), float(p.position.y))
                )

    subs = Subscriptions(rx, session.keys)
    for kind in ("people", "legs"):
        keys.add(subs.add(f"/laserpeople/{kind}", "people_msgs/msg/People", on_people))
    pubs = Publishers(tx, session.keys, block=True)
    tokens: list[str] = []
    try:
        time.sleep(0.8)  # let the sessions route the subscriptions
        player = threading.Thread(
            target=replay_bag,
            args=(bag, pubs.publish),
            kwargs={"speed": speed, "topics": list(topics), "max_scans": max_scans},
            daemon=True,
        )
        player.start()
        stats = session.run.run()
        player.join(timeout=30)
        if transport == "rmw":
            tokens = [str(r.ok.key_expr) for r in rx.liveliness().get("@ros2_lv/**")]
        time.sleep(0.5)
    finally:
        subs.close()
        pubs.close()
        rx.close()
        tx.close()
        session.close()
    out = {k: sorted(v) for k, v in rows.items()}
    return LiveResult(
        out, session, stats, sum(session.scans.counts.received.values()), keys, tokens
    )


def compare(live: Rows, offline: Rows, tol: float = 1e-6) -> list[str]:
    """Differences between two runs' rows (empty: equal within ``tol`` metres)."""
    problems = []
    for scan in sorted(set(live) | set(offline)):
        a, b = live.get(scan, []), offline.get(scan, [])
        if [r[:2] for r in a] != [r[:2] for r in b]:
            problems.append(f"scan {scan}: ids {[r[:2] for r in a]} vs {[r[:2] for r in b]}")
            continue
        for ra, rb in zip(a, b, strict=True):
            if abs(ra[2] - rb[2]) > tol or abs(ra[3] - rb[3]) > tol:
                problems.append(f"scan {scan}: {ra} vs {rb}")
    return problems
