"""Export a scene to ``.mcap`` for Foxglove Studio (and ROS 2 tools).

Written with rosbags' ROS 2 MCAP writer, CDR-encoded, with the message definitions
embedded, so Foxglove decodes everything without a ROS installation. Channels, one
message per drawn scan on each:

==========================  ====================================  =========================
topic                       type                                  content
==========================  ====================================  =========================
``/<sensor>``               ``sensor_msgs/msg/LaserScan``         the scan, sensor frame
``/tf``                     ``tf2_msgs/msg/TFMessage``            world -> sensor (only when
                                                                  drawing in the world frame)
``/laserpeople/legs``       ``visualization_msgs/msg/MarkerArray`` leg tracks
``/laserpeople/people``     ``visualization_msgs/msg/MarkerArray`` person tracks
``/laserpeople/groups``     ``visualization_msgs/msg/MarkerArray`` group tracks
``/laserpeople/truth``      ``visualization_msgs/msg/MarkerArray`` ground truth (when given)
==========================  ====================================  =========================

Every MarkerArray starts with a DELETEALL marker so that tracks that ended disappear.
A track is a cylinder (person), sphere (leg) or its contour (group, a closed LINE_STRIP;
a circle of the covariance when the contour is unknown), a text label with its id (and a
group's size), a LINE_STRIP 95 % covariance ellipse, and an ARROW for 1 s of velocity.
Colours are the same as in the pictures.
"""

from __future__ import annotations

import math
import shutil
import tempfile
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

import numpy as np

from laserpeople.errors import LaserPeopleError
from laserpeople.scan import Pose2D, Scan
from laserpeople.tracks import Track, TrackKind
from laserpeople.truth import TruthFrame
from laserpeople.viz.colors import TRUTH, to_unit, track_color
from laserpeople.viz.geometry import covariance_ellipses
from laserpeople.viz.scene import Scene, SceneFrame

WORLD_FRAME_ID = "world"
MARKER_TOPICS: dict[TrackKind, str] = {
    "leg": "/laserpeople/legs",
    "person": "/laserpeople/people",
    "group": "/laserpeople/groups",
}
TRUTH_TOPIC = "/laserpeople/truth"
TF_TOPIC = "/tf"
SCAN_TYPE = "sensor_msgs/msg/LaserScan"
MARKERS_TYPE = "visualization_msgs/msg/MarkerArray"
TF_TYPE = "tf2_msgs/msg/TFMessage"

# visualization_msgs/Marker constants
ARROW, SPHERE, CYLINDER, LINE_STRIP, TEXT = 0, 2, 3, 4, 9
ADD, DELETEALL = 0, 3


def sensor_topic(sensor: str) -> str:
    """The topic of a sensor's scans: its name with one leading slash."""
    return "/" + (sensor.strip("/") or "scan")


def sensor_frame_id(sensor: str) -> str:
    """The TF frame id of a sensor: its name without slashes."""
    return sensor.strip("/").replace("/", "_") or "laser"


class _Messages:
    """Builders of the ROS 2 messages, from rosbags' built-in typestore."""

    def __init__(self) -> None:
        from rosbags.typesys import Stores, get_typestore

        self.store = get_typestore(Stores.ROS2_HUMBLE)
        t = self.store.types
        self.Time = t["builtin_interfaces/msg/Time"]
        self.Duration = t["builtin_interfaces/msg/Duration"]
        self.Header = t["std_msgs/msg/Header"]
        self.ColorRGBA = t["std_msgs/msg/ColorRGBA"]
        self.Point = t["geometry_msgs/msg/Point"]
        self.Vector3 = t["geometry_msgs/msg/Vector3"]
        self.Quaternion = t["geometry_msgs/msg/Quaternion"]
        self.Pose = t["geometry_msgs/msg/Pose"]
        self.Transform = t["geometry_msgs/msg/Transform"]
        self.TransformStamped = t["geometry_msgs/msg/TransformStamped"]
        self.TFMessage = t[TF_TYPE]
        self.LaserScan = t[SCAN_TYPE]
        self.Marker = t["visualization_msgs/msg/Marker"]
        self.MarkerArray = t[MARKERS_TYPE]
        self.CompressedImage = t["sensor_msgs/msg/CompressedImage"]
        self.MeshFile = t["visualization_msgs/msg/MeshFile"]

    def serialize(self, msg: Any, msgtype: str) -> bytes:
        return bytes(self.store.serialize_cdr(msg, msgtype))

    def header(self, stamp: float, frame_id: str) -> Any:
        sec = math.floor(stamp)
        nsec = min(round((stamp - sec) * 1e9), 999_999_999)
        return self.Header(stamp=self.Time(sec=int(sec), nanosec=nsec), frame_id=frame_id)

    def quaternion(self, theta: float) -> Any:
        return self.Quaternion(x=0.0, y=0.0, z=math.sin(theta / 2.0), w=math.cos(theta / 2.0))

    def scan(self, scan: Scan, frame_id: str) -> Any:
        inten = (
            np.asarray(scan.intensities, dtype=np.float32)
            if scan.intensities is not None
            else np.empty(0, dtype=np.float32)
        )
        return self.LaserScan(
            header=self.header(scan.stamp, frame_id),
            angle_min=float(scan.angle_min),
            angle_max=float(scan.angle_max),
            angle_increment=float(scan.angle_increment),
            time_increment=0.0,
            scan_time=0.0,
            range_min=float(scan.range_min),
            range_max=float(scan.range_max),
            ranges=np.asarray(scan.ranges, dtype=np.float32),
            intensities=inten,
        )

    def tf(self, stamp: float, pose: Pose2D, child: str) -> Any:
        transform = self.Transform(
            translation=self.Vector3(x=float(pose.x), y=float(pose.y), z=0.0),
            rotation=self.quaternion(pose.theta),
        )
        ts = self.TransformStamped(
            header=self.header(stamp, WORLD_FRAME_ID), child_frame_id=child, transform=transform
        )
        return self.TFMessage(transforms=[ts])

    def marker(
        self,
        header: Any,
        ns: str,
        marker_id: int,
        kind: int,
        *,
        action: int = ADD,
        xy: tuple[float, float] = (0.0, 0.0),
        z: float = 0.0,
        scale: tuple[float, float, float] = (1.0, 1.0, 1.0),
        rgba: tuple[float, float, float, float] = (1.0, 1.0, 1.0, 1.0),
        points: Iterable[tuple[float, float]] = (),
        text: str = "",
    ) -> Any:
        return self.Marker(
            header=header,
            ns=ns,
            id=int(marker_id),
            type=kind,
            action=action,
            pose=self.Pose(
                position=self.Point(x=float(xy[0]), y=float(xy[1]), z=float(z)),
                orientation=self.Quaternion(x=0.0, y=0.0, z=0.0, w=1.0),
            ),
            scale=self.Vector3(x=scale[0], y=scale[1], z=scale[2]),
            color=self.ColorRGBA(r=rgba[0], g=rgba[1], b=rgba[2], a=rgba[3]),
            lifetime=self.Duration(sec=0, nanosec=0),
            frame_locked=False,
            points=[self.Point(x=float(p[0]), y=float(p[1]), z=0.05) for p in points],
            colors=[],
            texture_resource="",
            texture=self.CompressedImage(header=header, format="", data=np.empty(0, np.uint8)),
            uv_coordinates=[],
            text=text,
            mesh_resource="",
            mesh_file=self.MeshFile(filename="", data=np.empty(0, np.uint8)),
            mesh_use_embedded_materials=False,
        )

    def track_markers(self, header: Any, kind: TrackKind, tracks: list[Track]) -> Any:
        markers = [self.marker(header, "", 0, 0, action=DELETEALL)]
        if tracks:
            pos = np.array([t.position for t in tracks])
            ellipses = covariance_ellipses(pos, np.array([t.covariance for t in tracks]))
        for t, ellipse in zip(tracks, ellipses if tracks else (), strict=True):
            r, g, b = to_unit(track_color(t.track_id, t.kind))
            xy = (float(t.position[0]), float(t.position[1]))
            tid = t.track_id
            if kind == "person":
                markers.append(
                    self.marker(header, "people", tid, CYLINDER, xy=xy, z=0.6,
                                scale=(0.35, 0.35, 1.2), rgba=(r, g, b, 0.8))
                )  # fmt: skip
                label = f"P{tid}"
            elif kind == "leg":
                markers.append(
                    self.marker(header, "legs", tid, SPHERE, xy=xy, z=0.1,
                                scale=(0.15, 0.15, 0.15), rgba=(r, g, b, 0.9))
                )  # fmt: skip
                label = f"L{tid}"
            else:
                outline = t.contour if t.contour.shape[0] >= 3 else ellipse
                closed = np.vstack([outline, outline[:1]])
                if np.all(np.isfinite(closed)):
                    markers.append(
                        self.marker(header, "group_contours", tid, LINE_STRIP,
                                    scale=(0.05, 0.0, 0.0), rgba=(r, g, b, 1.0),
                                    points=[(p[0], p[1]) for p in closed])
                    )  # fmt: skip
                label = f"G{tid} x{t.size}" + (f" [{t.labels}]" if t.labels else "")
            markers.append(
                self.marker(header, f"{kind}_labels", tid, TEXT, xy=xy, z=1.5 if kind != "leg"
                            else 0.4, scale=(0.0, 0.0, 0.3), rgba=(r, g, b, 1.0), text=label)
            )  # fmt: skip
            if np.all(np.isfinite(ellipse)):
                markers.append(
                    self.marker(header, f"{kind}_covariance", tid, LINE_STRIP,
                                scale=(0.02, 0.0, 0.0), rgba=(r, g, b, 1.0),
                                points=[(p[0], p[1]) for p in ellipse])
                )  # fmt: skip
            v = np.nan_to_num(t.velocity)
            if np.hypot(v[0], v[1]) > 0.05:
                markers.append(
                    self.marker(header, f"{kind}_velocity", tid, ARROW,
                                scale=(0.04, 0.08, 0.1), rgba=(r, g, b, 1.0),
                                points=[xy, (xy[0] + v[0], xy[1] + v[1])])
                )  # fmt: skip
        return self.MarkerArray(markers=markers)

    def truth_markers(self, header: Any, truth: TruthFrame | None) -> Any:
        markers = [self.marker(header, "", 0, 0, action=DELETEALL)]
        rgb = to_unit(TRUTH)
        if truth is not None:
            for pid, xy in zip(truth.person_ids, truth.positions, strict=True):
                p = (float(xy[0]), float(xy[1]))
                markers.append(
                    self.marker(header, "truth", int(pid), CYLINDER, xy=p, z=0.9,
                                scale=(0.5, 0.5, 1.8), rgba=(*rgb, 0.25))
                )  # fmt: skip
                markers.append(
                    self.marker(header, "truth_labels", int(pid), TEXT, xy=p, z=2.0,
                                scale=(0.0, 0.0, 0.25), rgba=(*rgb, 1.0), text=f"truth {pid}")
                )  # fmt: skip
        return self.MarkerArray(markers=markers)


def export_mcap(
    scene: Scene,
    out: str | Path,
    *,
    progress: Callable[[Iterable[SceneFrame], int | None], Iterable[SceneFrame]] | None = None,
    total: int | None = None,
) -> int:
    """Write ``scene`` to the MCAP file ``out``; returns the number of scans written.

    The file is assembled beside ``out`` and moved into place at the end, so an existing
    file is replaced only by a complete one.
    """
    from rosbags.rosbag2 import StoragePlugin, Writer

    p = Path(out)
    p.parent.mkdir(parents=True, exist_ok=True)
    msgs = _Messages()
    world = scene.frame == "world"
    frames: Iterable[SceneFrame] = scene.frames()
    if progress is not None:
        frames = progress(frames, total)
    n = 0
    with tempfile.TemporaryDirectory(prefix=".mcap-", dir=p.parent) as tmp:
        bag = Path(tmp) / p.stem
        writer = Writer(bag, version=9, storage_plugin=StoragePlugin.MCAP)
        writer.open()
        try:
            conns: dict[str, Any] = {}

            def conn(topic: str, msgtype: str) -> Any:
                if topic not in conns:
                    conns[topic] = writer.add_connection(topic, msgtype, typestore=msgs.store)
                return conns[topic]

            for f in frames:
                scan = f.scan
                stamp_ns = round(scan.stamp * 1e9)
                sensor_id = sensor_frame_id(scan.sensor)
                writer.write(
                    conn(sensor_topic(scan.sensor), SCAN_TYPE),
                    stamp_ns,
                    msgs.serialize(msgs.scan(scan, sensor_id), SCAN_TYPE),
                )
                if world:
                    writer.write(
                        conn(TF_TOPIC, TF_TYPE),
                        stamp_ns,
                        msgs.serialize(msgs.tf(scan.stamp, f.sensor_pose, sensor_id), TF_TYPE),
                    )
                header = msgs.header(scan.stamp, WORLD_FRAME_ID if world else sensor_id)
                for kind, topic in MARKER_TOPICS.items():
                    arr = msgs.track_markers(header, kind, list(f.tracks.of_kind(kind)))
                    writer.write(
                        conn(topic, MARKERS_TYPE), stamp_ns, msgs.serialize(arr, MARKERS_TYPE)
                    )
                if f.truth is not None or TRUTH_TOPIC in conns:
                    writer.write(
                        conn(TRUTH_TOPIC, MARKERS_TYPE),
                        stamp_ns,
                        msgs.serialize(msgs.truth_markers(header, f.truth), MARKERS_TYPE),
                    )
                n += 1
        finally:
            writer.close()
        if n == 0:
            raise LaserPeopleError(
                "no scans in the chosen window",
                path=scene.source_name or None,
                hint="check --topic, --start and --stop",
            )
        shutil.move(str(bag / f"{bag.name}.mcap"), str(p))
    return n
