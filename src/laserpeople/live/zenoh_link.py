"""The Zenoh side: a session, the subscriptions that feed :class:`LiveScans` and the
publishers of the tracks (package ``eclipse-zenoh``; see :mod:`laserpeople.live.keys` for
the key expressions of ``zenoh-bridge-ros2dds`` and ``rmw_zenoh``).
"""

from __future__ import annotations

import json
import re
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Literal

from laserpeople.errors import ConfigError, LaserPeopleError
from laserpeople.live.keys import KeyStyle, RmwKeys, publisher_gid, rmw_attachment
from laserpeople.live.messages import Message

INSTALL_HINT = "pip install 'laserpeople[live]' (eclipse-zenoh, foxglove-sdk, websockets)"


def import_zenoh() -> Any:
    """The ``zenoh`` module, or a :class:`ConfigError` that says what to install."""
    try:
        import zenoh
    except ImportError:
        raise ConfigError(
            "live needs the Zenoh package (eclipse-zenoh), which is not installed",
            hint=INSTALL_HINT,
        ) from None
    return zenoh


ENDPOINT = re.compile(r"[a-z][a-z0-9+.-]*/\S+")
"""A Zenoh endpoint: ``<protocol>/<address>[?<metadata>][#<config>]`` (no spaces)."""


@dataclass(frozen=True)
class ZenohSettings:
    """How the Zenoh session is opened.

    Attributes:
        mode: ``peer`` or ``client`` (a client talks only to the router or bridge it
            connects to).
        connect: Endpoints to connect to (``tcp/192.168.1.5:7447``).
        listen: Endpoints to listen on.
        scouting: Multicast scouting (find peers on the LAN without ``connect``).
    """

    mode: Literal["peer", "client"] = "peer"
    connect: tuple[str, ...] = ()
    listen: tuple[str, ...] = ()
    scouting: bool = False

    def __post_init__(self) -> None:
        if self.mode not in ("peer", "client"):
            raise ConfigError(f"zenoh mode {self.mode!r} is not peer or client")
        if self.mode == "client" and not self.connect:
            raise ConfigError(
                "a zenoh client needs an endpoint", hint="give --connect tcp/HOST:7447"
            )
        for option, endpoints in (("--connect", self.connect), ("--listen", self.listen)):
            for endpoint in endpoints:
                if not ENDPOINT.fullmatch(endpoint):
                    raise ConfigError(
                        f"{option} {endpoint!r} is not a Zenoh endpoint PROTOCOL/ADDRESS",
                        hint="e.g. tcp/192.168.1.5:7447, udp/10.0.0.2:7447 or tcp/[::1]:7447",
                    )

    def config(self) -> Any:
        """A ``zenoh.Config``."""
        zenoh = import_zenoh()
        cfg = zenoh.Config()
        cfg.insert_json5("mode", json.dumps(self.mode))
        cfg.insert_json5("connect/endpoints", json.dumps(list(self.connect)))
        cfg.insert_json5("listen/endpoints", json.dumps(list(self.listen)))
        cfg.insert_json5("scouting/multicast/enabled", json.dumps(self.scouting))
        return cfg


def open_session(settings: ZenohSettings) -> Any:
    """Open a Zenoh session.

    Raises:
        LaserPeopleError: The session cannot be opened (bad endpoint, port in use).
    """
    zenoh = import_zenoh()
    try:
        return zenoh.open(settings.config())
    except Exception as exc:  # zenoh raises its own ZError
        raise LaserPeopleError(
            f"cannot open a Zenoh session ({settings.mode}, connect "
            f"{', '.join(settings.connect) or 'none'}): {exc}",
            hint="check --connect (tcp/HOST:PORT) and that the router or bridge runs",
        ) from exc


class Subscriptions:
    """Zenoh subscribers of ROS topics; each sample's payload goes to a callback.

    Args:
        session: An open Zenoh session.
        keys: The key style (bridge or rmw_zenoh).
    """

    def __init__(self, session: Any, keys: KeyStyle) -> None:
        self.session = session
        self.keys = keys
        self._subs: list[Any] = []
        self._tokens: list[Any] = []

    def add(self, topic: str, msgtype: str, callback: Callable[[bytes], None]) -> str:
        """Subscribe to ``topic``; returns the key expression."""
        key = self.keys.subscription(topic, msgtype)

        def on_sample(sample: Any) -> None:
            callback(sample.payload.to_bytes())

        self._subs.append(self.session.declare_subscriber(key, on_sample))
        if isinstance(self.keys, RmwKeys):
            token = self.keys.endpoint_token(
                str(self.session.zid()), 100 + len(self._subs), "MS", topic, msgtype
            )
            self._tokens.append(self.session.liveliness().declare_token(token))
        return key

    def close(self) -> None:
        """Undeclare everything."""
        for item in (*self._tokens, *self._subs):
            item.undeclare()
        self._tokens.clear()
        self._subs.clear()


class Publishers:
    """Zenoh publishers of ROS topics, declared on first use; with ``rmw_zenoh`` keys each
    also has its liveliness token and every message its attachment.

    Args:
        session: An open Zenoh session.
        keys: The key style.
        block: Block when the network is congested (default: drop, as ROS sensor data).
    """

    def __init__(self, session: Any, keys: KeyStyle, *, block: bool = False) -> None:
        self.session = session
        self.keys = keys
        self.block = block
        self._pubs: dict[str, tuple[Any, bytes]] = {}
        self._tokens: list[Any] = []
        self._sequence = 0
        self._lock = threading.Lock()
        self.sent = 0
        self._node: Any = None
        if isinstance(keys, RmwKeys):
            self._node = session.liveliness().declare_token(keys.node_token(str(session.zid())))

    def _publisher(self, topic: str, msgtype: str) -> tuple[Any, bytes]:
        entry = self._pubs.get(topic)
        if entry is None:
            zenoh = import_zenoh()
            congestion = zenoh.CongestionControl.BLOCK if self.block else None
            pub = self.session.declare_publisher(
                self.keys.key(topic, msgtype), congestion_control=congestion
            )
            gid = b""
            if isinstance(self.keys, RmwKeys):
                token = self.keys.endpoint_token(
                    str(self.session.zid()), 1 + len(self._pubs), "MP", topic, msgtype
                )
                self._tokens.append(self.session.liveliness().declare_token(token))
                gid = publisher_gid(token)
            entry = (pub, gid)
            self._pubs[topic] = entry
        return entry

    def declare(self, topics: dict[str, str]) -> None:
        """Declare the publishers of ``topics`` (topic -> type) now, so that subscribers
        and ``ros2 topic list`` see them before the first message."""
        for topic, msgtype in topics.items():
            self._publisher(topic, msgtype)

    def matched(self, topic: str, msgtype: str, timeout: float = 0.0) -> bool:
        """Whether a subscriber of ``topic`` is reachable, waiting up to ``timeout`` [s]."""
        pub, _ = self._publisher(topic, msgtype)
        deadline = time.monotonic() + timeout
        while not pub.matching_status.matching:
            if time.monotonic() >= deadline:
                return False
            time.sleep(0.05)
        return True

    def publish(self, messages: Sequence[Message]) -> None:
        """Put each message on its topic's key."""
        with self._lock:
            for m in messages:
                pub, gid = self._publisher(m.topic, m.msgtype)
                if gid:
                    self._sequence += 1
                    pub.put(m.data, attachment=rmw_attachment(self._sequence, time.time_ns(), gid))
                else:
                    pub.put(m.data)
                self.sent += 1

    def close(self) -> None:
        """Undeclare everything."""
        with self._lock:
            for pub, _ in self._pubs.values():
                pub.undeclare()
            for token in self._tokens:
                token.undeclare()
            if self._node is not None:
                self._node.undeclare()
                self._node = None
            self._pubs.clear()
            self._tokens.clear()


__all__ = [
    "INSTALL_HINT",
    "Publishers",
    "Subscriptions",
    "ZenohSettings",
    "import_zenoh",
    "open_session",
]
