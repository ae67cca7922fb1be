"""How ROS 2 topics are named on Zenoh: ``zenoh-bridge-ros2dds`` and ``rmw_zenoh``.

- **Bridge** (``zenoh-bridge-ros2dds`` on the robot, ROS 2 over DDS there): a topic is the
  key of its name without the leading ``/`` (``/scan`` -> ``scan``); the payload is the
  message's CDR bytes. An optional ``prefix`` is put in front (for a bridge configured to
  route under a prefix).
- **rmw_zenoh** (the robot runs ``RMW_IMPLEMENTATION=rmw_zenoh_cpp``): a topic is
  ``<domain>/<name without leading and trailing />/<DDS type name>/<type hash>``, e.g.
  ``0/scan/sensor_msgs::msg::dds_::LaserScan_/RIHS01_64c1...``; the type hash is the REP 2011
  ``RIHS01_`` hash of the type description (``TypeHashNotSupported`` on Humble). Every
  publication carries an attachment (sequence number, source time [ns], 16-byte publisher
  gid), and every node, publisher and subscription announces itself with a Zenoh liveliness
  token ``@ros2_lv/<domain>/<zid>/<node id>/<entity id>/<NN|MP|MS>/<enclave>/<namespace>/
  <node>[/<topic>/<type>/<hash>/<qos>]`` with ``/`` inside a part written ``%``, which is
  how ``ros2 topic list`` and matching find them (as ``rmw_zenoh_cpp``'s
  ``liveliness_utils.cpp`` forms them). Subscriptions here match any type hash
  (``<domain>/<name>/<type>/*``), so a robot on another ROS 2 release is still heard.
"""

from __future__ import annotations

import hashlib
import struct
from dataclasses import dataclass, field
from typing import Any, Literal, Protocol

Transport = Literal["bridge", "rmw"]
HASH_NOT_SUPPORTED = "TypeHashNotSupported"
DEFAULT_QOS = "::,:,:,:,,"
"""rmw_zenoh's QoS part of a liveliness token for the default profile (reliable, volatile,
keep last 10): every field equal to the default is left empty."""


def strip_topic(topic: str) -> str:
    """A topic name without leading and trailing ``/``.

    Raises:
        ValueError: Nothing is left.
    """
    name = topic.strip().strip("/")
    if not name:
        raise ValueError(f"topic {topic!r} has no name")
    return name


def dds_type_name(msgtype: str) -> str:
    """The DDS type name of a ROS 2 type: ``pkg/msg/Name`` -> ``pkg::msg::dds_::Name_``."""
    pkg, kind, name = msgtype.split("/")
    return f"{pkg}::{kind}::dds_::{name}_"


def mangle(name: str) -> str:
    """A name as one part of a liveliness token (``/`` written ``%``)."""
    return name.replace("/", "%")


class KeyStyle(Protocol):
    """Key expressions of one way of putting ROS 2 on Zenoh."""

    @property
    def name(self) -> Transport:
        """``bridge`` or ``rmw``."""
        ...

    def key(self, topic: str, msgtype: str) -> str:
        """The key a message of ``msgtype`` on ``topic`` is published on."""
        ...

    def subscription(self, topic: str, msgtype: str) -> str:
        """The key expression that receives ``topic``."""
        ...


@dataclass(frozen=True)
class BridgeKeys:
    """Keys of ``zenoh-bridge-ros2dds``: the topic name (see the module notes)."""

    prefix: str = ""
    name: Transport = "bridge"

    def key(self, topic: str, msgtype: str) -> str:
        """``[prefix/]topic``."""
        head = self.prefix.strip("/")
        return f"{head}/{strip_topic(topic)}" if head else strip_topic(topic)

    def subscription(self, topic: str, msgtype: str) -> str:
        """The same key as :meth:`key`."""
        return self.key(topic, msgtype)


@dataclass(frozen=True)
class RmwKeys:
    """Keys, attachments and liveliness tokens of ``rmw_zenoh`` (see the module notes).

    Args:
        domain: ROS domain id.
        typestore: rosbags typestore that computes the type hashes.
        hashes: ``rihs01`` (Iron and later) or ``none`` (Humble: ``TypeHashNotSupported``).
        node: Node name in the liveliness tokens.
    """

    domain: int = 0
    typestore: Any = None
    hashes: Literal["rihs01", "none"] = "rihs01"
    node: str = "laserpeople"
    name: Transport = "rmw"
    _hash_cache: dict[str, str] = field(default_factory=dict, compare=False, repr=False)

    def type_hash(self, msgtype: str) -> str:
        """The REP 2011 hash of ``msgtype`` (``RIHS01_<64 hex>``), or
        ``TypeHashNotSupported``."""
        if self.hashes == "none" or self.typestore is None:
            return HASH_NOT_SUPPORTED
        if msgtype not in self._hash_cache:
            self._hash_cache[msgtype] = str(self.typestore.hash_rihs01(msgtype))
        return self._hash_cache[msgtype]

    def key(self, topic: str, msgtype: str) -> str:
        """``<domain>/<topic>/<DDS type>/<hash>``."""
        return (
            f"{self.domain}/{strip_topic(topic)}/{dds_type_name(msgtype)}/{self.type_hash(msgtype)}"
        )

    def subscription(self, topic: str, msgtype: str) -> str:
        """``<domain>/<topic>/<DDS type>/*``: any type hash."""
        return f"{self.domain}/{strip_topic(topic)}/{dds_type_name(msgtype)}/*"

    def node_token(self, zid: str, node_id: int = 0) -> str:
        """Liveliness token of the node."""
        return f"@ros2_lv/{self.domain}/{zid}/{node_id}/{node_id}/NN/%/%/{mangle(self.node)}"

    def endpoint_token(
        self, zid: str, entity_id: int, kind: Literal["MP", "MS"], topic: str, msgtype: str
    ) -> str:
        """Liveliness token of a publisher (``MP``) or subscription (``MS``) on ``topic``."""
        name = "/" + strip_topic(topic)
        return (
            f"@ros2_lv/{self.domain}/{zid}/0/{entity_id}/{kind}/%/%/{mangle(self.node)}/"
            f"{mangle(name)}/{dds_type_name(msgtype)}/{self.type_hash(msgtype)}/{DEFAULT_QOS}"
        )


def publisher_gid(token: str) -> bytes:
    """A 16-byte publisher gid derived from its liveliness token (rmw_zenoh hashes the token
    too; the gid only has to be unique and stable)."""
    return hashlib.sha256(token.encode()).digest()[:16]


def rmw_attachment(sequence: int, source_ns: int, gid: bytes) -> bytes:
    """An rmw_zenoh publication attachment: sequence number and source time [ns] as int64
    little-endian, then the gid as a byte sequence (length 16 as LEB128, the bytes), as
    zenoh-ext's serialiser writes them."""
    if len(gid) != 16:
        raise ValueError("an rmw_zenoh gid has 16 bytes")
    return struct.pack("<qqB", sequence, source_ns, 16) + gid


def parse_rmw_attachment(data: bytes) -> tuple[int, int, bytes]:
    """Sequence number, source time [ns] and gid of an rmw_zenoh attachment.

    Raises:
        ValueError: Not an attachment of that form.
    """
    if len(data) != 33 or data[16] != 16:
        raise ValueError(f"not an rmw_zenoh attachment ({len(data)} bytes)")
    sequence, source_ns = struct.unpack_from("<qq", data)
    return int(sequence), int(source_ns), bytes(data[17:])


__all__ = [
    "DEFAULT_QOS",
    "HASH_NOT_SUPPORTED",
    "BridgeKeys",
    "KeyStyle",
    "RmwKeys",
    "Transport",
    "dds_type_name",
    "mangle",
    "parse_rmw_attachment",
    "publisher_gid",
    "rmw_attachment",
    "strip_topic",
]
