"""What to tell a user whose live run has received nothing yet.

A Zenoh peer told to ``--connect`` to an endpoint nobody answers on does not fail: it keeps
trying in the background, and the run waits for scans that never come. After
:data:`NO_SCAN_WAIT` seconds without a scan :func:`no_scan_note` says so once, naming what
to check (whether anything answered at the endpoints given, or the topic names), while the
run goes on waiting (Ctrl-C, or ``--duration``, ends it with the summary).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

NO_SCAN_WAIT = 10.0
"""Seconds without any scan after which a live run says what to check [s]."""


def connected_count(session: Any) -> int | None:
    """Zenoh peers and routers ``session`` (a ``zenoh.Session``) is connected to; None when
    the session cannot tell."""
    try:
        info = session.info
        return len(list(info.peers_zid())) + len(list(info.routers_zid()))
    except Exception:  # a closed session or another binding: say nothing of connections
        return None


def no_scan_note(
    waited: float, lasers: Sequence[str], connect: Sequence[str], connected: int | None
) -> str:
    """The line to print after ``waited`` [s] without a scan on ``lasers``; empty before
    :data:`NO_SCAN_WAIT`. ``connect`` are the endpoints given, ``connected`` the Zenoh
    peers and routers reached (None: unknown)."""
    if waited < NO_SCAN_WAIT:
        return ""
    return (
        f"no scan on {', '.join(lasers)} after {waited:.0f} s: {why_no_scan(connect, connected)}; "
        "still waiting (Ctrl-C stops; --duration S gives up after S s)"
    )


def why_no_scan(connect: Sequence[str], connected: int | None) -> str:
    """What to check when no scan arrives: the endpoints ``connect`` when none of them
    answered (``connected`` 0), how to find a peer when none was given or found, else the
    topics and keys."""
    if connected == 0 and connect:
        return (
            f"nothing answers at {', '.join(connect)} (no Zenoh peer or router connected): "
            "check the address and port, and that zenoh-bridge-ros2dds or the router runs there"
        )
    if connected == 0:
        return (
            "no Zenoh peer or router found: give --connect tcp/ROBOT:7447 (the bridge's or "
            "router's endpoint), or --scouting on the robot's network"
        )
    reached = "" if connected is None else f"connected to {connected} Zenoh peer(s) or router(s), "
    return (
        f"{reached}check the topic names (ros2 topic list on the robot), --transport, "
        "--domain and --key-prefix"
    )


__all__ = ["NO_SCAN_WAIT", "connected_count", "no_scan_note", "why_no_scan"]
