"""A live viewer: the scans and tracks served over the Foxglove WebSocket protocol.

Uses the ``foxglove-sdk`` package's server. The channels and messages are those that
``laserpeople view -o out.mcap`` writes (:mod:`laserpeople.viz.mcap_export`): each laser's
``sensor_msgs/msg/LaserScan`` on its topic, ``/tf`` (world -> laser) in the world frame,
and one ``visualization_msgs/msg/MarkerArray`` per kind on ``/laserpeople/legs``,
``/laserpeople/people`` and ``/laserpeople/groups``, all CDR with their ``ros2msg``
definitions, so Foxglove draws them without ROS. Open Foxglove, "Open connection",
``ws://HOST:PORT``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from laserpeople.errors import ConfigError
from laserpeople.frame import Frame
from laserpeople.io.rosbag_writer import SCAN_TYPE, TF_TYPE, sensor_frame_id, sensor_topic
from laserpeople.live.messages import MemorySink, ros2_typestore
from laserpeople.live.zenoh_link import INSTALL_HINT
from laserpeople.tracks import Tracks
from laserpeople.viz.mcap_export import (
    MARKER_TOPICS,
    MARKERS_TYPE,
    TF_TOPIC,
    WORLD_FRAME_ID,
    _Markers,
)


def import_foxglove() -> Any:
    """The ``foxglove`` module, or a :class:`ConfigError` that says what to install."""
    try:
        import foxglove
    except ImportError:
        raise ConfigError(
            "--foxglove needs the Foxglove SDK (foxglove-sdk), which is not installed",
            hint=INSTALL_HINT,
        ) from None
    return foxglove


class FoxgloveSink:
    """Serves each frame's scans and tracks to Foxglove clients (see the module notes).

    Args:
        port: TCP port of the WebSocket server (0: any free port, see :attr:`port`).
        host: Address to listen on (``0.0.0.0`` for other machines).
        name: Server name shown by Foxglove.
        lasers: Laser topics whose channels are advertised from the start (with ``/tf``
            and the markers), so that a client that connects gets every channel at once.
    """

    def __init__(
        self,
        port: int = 8765,
        host: str = "127.0.0.1",
        name: str = "laserpeople",
        lasers: Sequence[str] = (),
    ) -> None:
        foxglove = import_foxglove()
        self._foxglove = foxglove
        self.typestore = ros2_typestore()
        self.sink = MemorySink(self.typestore)
        self.markers = _Markers(self.typestore)
        try:
            self.server = foxglove.start_server(name=name, host=host, port=port)
        except Exception as exc:  # the SDK's own error for a port in use
            raise ConfigError(
                f"cannot serve Foxglove on {host}:{port}: {exc}",
                hint="choose another port with --foxglove PORT, or with --foxglove-host an "
                "address of this machine (127.0.0.1, 0.0.0.0 for every interface)",
            ) from exc
        self.port = int(self.server.port)
        self.host = host
        self._channels: dict[str, Any] = {}
        self.frames = 0
        for laser in lasers:
            self._channel(sensor_topic(laser), SCAN_TYPE)
        self._channel(TF_TOPIC, TF_TYPE)
        for topic in MARKER_TOPICS.values():
            self._channel(topic, MARKERS_TYPE)

    def _channel(self, topic: str, msgtype: str) -> Any:
        channel = self._channels.get(topic)
        if channel is None:
            text, _ = self.typestore.generate_msgdef(msgtype, ros_version=2)
            schema = self._foxglove.Schema(name=msgtype, encoding="ros2msg", data=text.encode())
            channel = self._foxglove.Channel(topic, schema=schema, message_encoding="cdr")
            self._channels[topic] = channel
        return channel

    def _log(self, topic: str, msgtype: str, msg: Any, stamp: float) -> None:
        data = bytes(self.typestore.serialize_cdr(msg, msgtype))
        self._channel(topic, msgtype).log(data, log_time=round(stamp * 1e9))

    def write(self, frame: Frame, tracks: Tracks | None) -> None:
        """Send the frame's scans, their poses (world frame) and the tracks' markers."""
        world = frame.frame == "world"
        for scan in frame.scans:
            sid = sensor_frame_id(scan.sensor)
            self.sink.scan(scan, sensor_topic(scan.sensor), sid)
            if world and scan.pose is not None:
                self.sink.pose(scan.stamp, WORLD_FRAME_ID, sid, scan.pose, TF_TOPIC)
        for m in self.sink.take():
            self._channel(m.topic, m.msgtype).log(m.data, log_time=round(m.stamp * 1e9))
        first = sensor_frame_id(frame.scans[0].sensor) if frame.scans else "laser"
        header = self.sink.header(frame.stamp, WORLD_FRAME_ID if world else first)
        for kind, topic in MARKER_TOPICS.items():
            kept = list(tracks.of_kind(kind)) if tracks is not None else []
            arr = self.markers.track_markers(header, kind, kept)
            self._log(topic, MARKERS_TYPE, arr, frame.stamp)
        self.frames += 1

    def close(self) -> None:
        """Stop the server."""
        for channel in self._channels.values():
            channel.close()
        self.server.stop()


__all__ = ["FoxgloveSink", "import_foxglove"]
