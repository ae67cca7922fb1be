"""Export a scene to ``.mcap`` for Foxglove Studio (and ROS 2 tools).

Written with :func:`laserpeople.io.rosbag_writer.open_bag` (rosbags' ROS 2 MCAP writer,
CDR-encoded, with the message definitions embedded), so Foxglove decodes everything
without a ROS installation. Channels, one message per drawn scan on each:

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
A track is a cylinder (person), sphere (leg) or its outline (group, a closed LINE_STRIP
round its contour points; a circle of the covariance when the contour is unknown), a text
label with its id (and a group's size), a LINE_STRIP 95 % covariance ellipse, and an
ARROW for 1 s of velocity.
Colours are the same as in the pictures.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

from laserpeople.errors import LaserPeopleError
from laserpeople.io.rosbag_writer import open_bag, sensor_frame_id, sensor_topic
from laserpeople.tracks import Track, TrackKind
from laserpeople.truth import TruthFrame
from laserpeople.viz.colors import TRUTH, to_unit, track_color
from laserpeople.viz.geometry import covariance_ellipses, group_outline
from laserpeople.viz.scene import ProgressFn, Scene, SceneFrame, track_positions

WORLD_FRAME_ID = "world"
MARKER_TOPICS: dict[TrackKind, str] = {
    "leg": "/laserpeople/legs",
    "person": "/laserpeople/people",
    "group": "/laserpeople/groups",
}
TRUTH_TOPIC = "/laserpeople/truth"
TF_TOPIC = "/tf"
MARKERS_TYPE = "visualization_msgs/msg/MarkerArray"

# visualization_msgs/Marker constants
ARROW, SPHERE, CYLINDER, LINE_STRIP, TEXT = 0, 2, 3, 4, 9
ADD, DELETEALL = 0, 3


class _Markers:
    """Builders of ``visualization_msgs/MarkerArray`` messages from a ROS 2 typestore."""

    def __init__(self, typestore: Any) -> None:
        t = typestore.types
        self.Duration = t["builtin_interfaces/msg/Duration"]
        self.ColorRGBA = t["std_msgs/msg/ColorRGBA"]
        self.Point = t["geometry_msgs/msg/Point"]
        self.Vector3 = t["geometry_msgs/msg/Vector3"]
        self.Quaternion = t["geometry_msgs/msg/Quaternion"]
        self.Pose = t["geometry_msgs/msg/Pose"]
        self.Marker = t["visualization_msgs/msg/Marker"]
        self.MarkerArray = t[MARKERS_TYPE]
        self.CompressedImage = t["sensor_msgs/msg/CompressedImage"]
        self.MeshFile = t["visualization_msgs/msg/MeshFile"]

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
        ellipses = covariance_ellipses(
            track_positions(tracks), np.array([t.covariance for t in tracks]).reshape(-1, 2, 2)
        )
        for t, ellipse in zip(tracks, ellipses, strict=True):
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
                closed = (
                    group_outline(t.contour)
                    if t.contour.shape[0]
                    else np.vstack([ellipse, ellipse[:1]])
                )
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
    progress: ProgressFn | None = None,
    total: int | None = None,
) -> int:
    """Write ``scene`` to the MCAP file ``out``; returns the number of scans written.

    The file is assembled beside ``out`` and moved into place at the end, so an existing
    file is replaced only by a complete one.
    """
    path = Path(out)
    if path.suffix.lower() != ".mcap":
        raise LaserPeopleError("an MCAP export needs a name ending in .mcap", path=path)
    world = scene.frame == "world"
    frames: Iterable[SceneFrame] = scene.frames()
    if progress is not None:
        frames = progress(frames, total)
    with open_bag(path) as sink:
        markers = _Markers(sink.typestore)
        truth_seen = False
        for f in frames:
            scan = f.scan
            sensor_id = sensor_frame_id(scan.sensor)
            sink.scan(scan, sensor_topic(scan.sensor), sensor_id)
            if world:
                sink.pose(scan.stamp, WORLD_FRAME_ID, sensor_id, f.sensor_pose, TF_TOPIC)
            header = sink.header(scan.stamp, WORLD_FRAME_ID if world else sensor_id)
            for kind, topic in MARKER_TOPICS.items():
                arr = markers.track_markers(header, kind, list(f.tracks.of_kind(kind)))
                sink.write(topic, MARKERS_TYPE, arr, scan.stamp)
            truth_seen = truth_seen or f.truth is not None
            if truth_seen:
                sink.write(
                    TRUTH_TOPIC, MARKERS_TYPE, markers.truth_markers(header, f.truth), scan.stamp
                )
        if sink.count == 0:
            raise scene.empty_window_error()
    return sink.count
