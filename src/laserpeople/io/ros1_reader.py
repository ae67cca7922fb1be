"""One ROS 1 bag read as ``rosbags.highlevel.AnyReader`` reads it, without importing the
ROS 2 readers.

``AnyReader`` imports the readers of every format when it is imported: the ROS 2 SQLite
and MCAP storages, their YAML metadata and their decompressors, about 0.15-0.2 s of CPU
per process that a ROS 1 bag never uses. :class:`Ros1Reader` offers the part of
``AnyReader``'s interface this package uses (``connections``, ``typestore``,
``messages``, ``deserialize``, ``open``/``close``, ``stack``, ``is2``) over
``rosbags.rosbag1.Reader``, with the message types the bag itself defines, checked
against their MD5 sums as ``AnyReader`` checks them. The typestore of a set of definitions
is built once per process (:data:`TYPESTORES`): ``track`` opens a bag once to list it and
once per laser topic it reads, and building the types again took 6-17 ms per open on the
project's bags. A bag of standard types only (``LaserScan``, ``TFMessage``, ``Odometry``,
by type and MD5 sum: :func:`standard_types`), whose messages the package decodes from their
bytes, has its typestore built and checked when it is first asked for
(:attr:`Ros1Reader.typestore`), usually never: that parsing of the definitions took 3.6 ms
of CPU on the demo bag and 15 ms on the corridor bag.
"""

from __future__ import annotations

from collections.abc import Collection, Iterator
from contextlib import ExitStack, suppress
from pathlib import Path
from typing import Any

TYPESTORES: dict[tuple[tuple[str, str, str], ...], Any] = {}
"""Typestores by the connections' ``(type, definition, MD5 sum)``, each built and checked
once (a few bags' worth: emptied when :data:`TYPESTORES_KEPT` is reached)."""

TYPESTORES_KEPT = 16
"""How many sets of definitions :data:`TYPESTORES` holds before it starts afresh."""


def standard_types() -> frozenset[tuple[str, str]]:
    """``(type, MD5 sum)`` of the ROS 1 standard types the package decodes from their bytes
    (``io/laserscan_ros1.py``, ``io/pose_msgs_ros1.py``, imported here at first use, as they
    import numpy): a bag of these alone builds its typestore at first use."""
    from laserpeople.io.laserscan_ros1 import LASERSCAN_MD5
    from laserpeople.io.pose_msgs_ros1 import ODOMETRY_MD5, TF_MD5

    return frozenset(
        {
            ("sensor_msgs/msg/LaserScan", LASERSCAN_MD5),
            ("tf2_msgs/msg/TFMessage", TF_MD5),
            ("tf/msg/tfMessage", TF_MD5),
            ("nav_msgs/msg/Odometry", ODOMETRY_MD5),
        }
    )


class Ros1ReaderError(Exception):
    """The bag's message definitions are missing or disagree with their MD5 sums, or a
    message does not decode."""


class Ros1Reader:
    """Read one ROS 1 bag (``.bag``); the interface of ``AnyReader`` for one bag.

    Args:
        path: The bag.

    Attributes:
        connections: The bag's connections (empty until :meth:`open`).
        stack: Not None while the reader is open.
    """

    is2 = False
    """Never a ROS 2 bag (``AnyReader.is2``)."""

    def __init__(self, path: str | Path) -> None:
        from rosbags.rosbag1 import Reader
        from rosbags.serde import SerdeError
        from rosbags.typesys import Stores, get_typestore

        self._serde_error = SerdeError
        self.paths = [Path(path)]
        self._reader = Reader(self.paths[0])
        self.stack: ExitStack | None = None
        self.connections: list[Any] = []
        self._typestore: Any = get_typestore(Stores.EMPTY)
        self._pending: tuple[tuple[tuple[str, str, str], ...], list[Any]] | None = None

    @property
    def typestore(self) -> Any:
        """The message types the bag defines (empty until :meth:`open`), built and checked
        against their MD5 sums at the first use for a bag of :func:`standard_types` alone.

        Raises:
            Ros1ReaderError: A type's definition does not give its MD5 sum.
        """
        if self._pending is not None:
            key, connections = self._pending
            self._typestore = _cached_typestore(key, connections)
            self._pending = None
        return self._typestore

    def is_standard(self, msgtype: str) -> bool:
        """Whether every connection of ``msgtype`` carries one of :func:`standard_types`
        (False when it has none): such a type is known without the typestore."""
        standard = standard_types()
        digests = [c.digest for c in self.connections if c.msgtype == msgtype]
        return bool(digests) and all((msgtype, d) in standard for d in digests)

    def open(self) -> None:
        """Open the bag and build the typestore of its message definitions."""
        from rosbags.interfaces import MessageDefinitionFormat

        if self.stack is not None:
            raise Ros1ReaderError("the reader is already open")
        self.stack = ExitStack()
        try:
            self.stack.enter_context(self._reader)
            connections = list(self._reader.connections)
            for conn in connections:
                if conn.msgdef.format != MessageDefinitionFormat.MSG:
                    raise Ros1ReaderError(
                        f"topic {conn.topic}: the bag holds no message definition of {conn.msgtype}"
                    )
            key = tuple((c.msgtype, c.msgdef.data, c.digest or "") for c in connections)
            self._pending = None
            standard = standard_types()
            if key not in TYPESTORES and all(
                (c.msgtype, c.digest) in standard for c in connections
            ):
                self._pending = (key, connections)  # (built when asked for)
            else:
                self._typestore = _cached_typestore(key, connections)
            self.connections = connections
        except BaseException:
            with suppress(Exception):
                self.close()
            raise

    def close(self) -> None:
        """Close the bag."""
        stack, self.stack = self.stack, None
        if stack is None:
            raise Ros1ReaderError("the reader is not open")
        self.connections = []
        stack.close()

    def __enter__(self) -> Ros1Reader:
        self.open()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def messages(
        self,
        connections: Collection[Any] = (),
        start: int | None = None,
        stop: int | None = None,
    ) -> Iterator[tuple[Any, int, bytes]]:
        """``(connection, log time [ns], raw message)`` of ``connections`` (all when empty)
        in log-time order, from ``start`` up to before ``stop`` [ns] when given."""
        if self.stack is None:
            raise Ros1ReaderError("the reader is not open")
        return self._reader.messages(connections=list(connections), start=start, stop=stop)

    def deserialize(self, rawdata: bytes, typ: str) -> object:
        """The message ``rawdata`` of type ``typ`` decoded."""
        try:
            return self.typestore.deserialize_ros1(rawdata, typ)
        except self._serde_error as err:
            raise Ros1ReaderError(*err.args) from None


def _cached_typestore(key: tuple[tuple[str, str, str], ...], connections: list[Any]) -> Any:
    """:func:`_checked_typestore` of ``connections`` (whose ``(type, definition, MD5
    sum)`` are ``key``), from :data:`TYPESTORES` when built before."""
    typestore = TYPESTORES.get(key)
    if typestore is None:
        typestore = _checked_typestore(connections)
        if len(TYPESTORES) >= TYPESTORES_KEPT:
            TYPESTORES.clear()
        TYPESTORES[key] = typestore
    return typestore


def _checked_typestore(connections: list[Any]) -> Any:
    """A typestore of the message definitions of ``connections`` (ROS 1 ``.msg`` text),
    each type checked against its connection's MD5 sum.

    Raises:
        Ros1ReaderError: A type's definition does not give its MD5 sum.
    """
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    types: dict[str, Any] = {}
    digests: dict[str, str] = {}
    for conn in connections:
        types.update(get_types_from_msg(conn.msgdef.data, conn.msgtype))
        if conn.digest:
            digests[conn.msgtype] = conn.digest
    typestore = get_typestore(Stores.EMPTY)
    typestore.register(types)
    for msgtype, digest in digests.items():
        have = typestore.generate_msgdef(msgtype)[1]
        if have != digest:
            raise Ros1ReaderError(f"message type {msgtype!r} hash mismatch {have} != {digest}")
    return typestore


__all__ = ["TYPESTORES", "Ros1Reader", "Ros1ReaderError", "standard_types"]
