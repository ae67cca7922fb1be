"""Which Foxglove clients `live --foxglove` accepts: the WebSocket subprotocol each offers.

The foxglove-sdk server speaks ``foxglove.sdk.v1`` only (as foxglove_bridge 3 does). The
current Foxglove app offers it; Lichtblick offers it beside the older
``foxglove.websocket.v1`` since its December 2025 releases; an older app or client that
offers only ``foxglove.websocket.v1`` is refused in the handshake (HTTP 400), as
docs/live.md says.
"""

from __future__ import annotations

import asyncio

import pytest

pytest.importorskip("foxglove", reason="needs the live extra (foxglove-sdk)")
websockets = pytest.importorskip("websockets", reason="needs the live extra (websockets)")

SDK = "foxglove.sdk.v1"
OLD = "foxglove.websocket.v1"


async def _handshake(port: int, offered: list[str]) -> str | int:
    """The subprotocol the server chose for a client offering ``offered``, or the HTTP
    status it refused the connection with."""
    from websockets.exceptions import InvalidStatus

    try:
        async with websockets.connect(
            f"ws://127.0.0.1:{port}", subprotocols=offered, open_timeout=10
        ) as ws:
            return str(ws.subprotocol)
    except InvalidStatus as exc:
        return int(exc.response.status_code)


@pytest.mark.parametrize(
    ("client", "offered", "answer"),
    [
        ("the current Foxglove app", [SDK], SDK),
        ("Lichtblick with foxglove.sdk.v1", [OLD, SDK], SDK),
        ("an older Foxglove Studio or Lichtblick", [OLD], 400),
    ],
)
def test_the_handshake_of_each_client(client: str, offered: list[str], answer: str | int) -> None:
    from laserpeople.live.foxglove import FoxgloveSink

    viewer = FoxgloveSink(0)
    try:
        got = asyncio.run(_handshake(viewer.port, offered))
    finally:
        viewer.close()
    assert got == answer, client
