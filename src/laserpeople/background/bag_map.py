"""A prior map from a bag topic: ``nav_msgs/OccupancyGrid`` (``track --map BAG:/map``).

A recording of a robot that navigates with a map often carries it on ``/map`` (latched, one
message). :func:`occupancy_grid_map` turns such a message into the same
:class:`~laserpeople.background.occupancy.OccupancyMap` as a ROS ``map.yaml``: cells whose
occupancy (0-100, -1 unknown) reaches ``occupied_thresh`` (65, map_server's default
``occupied_thresh`` 0.65) are obstacles; unknown cells are not. The message's data is row
major from the origin's row (lowest y) up; the map's rows run from the largest y down, as
the image of a ``map.yaml``. The last message on the topic is used (a map that was updated
while recording is taken as it was at the end); the map's frame (``header.frame_id``) must
be the tracking world frame: no transform is applied, and :func:`check_map_frame` refuses a
map in another frame.
"""

from __future__ import annotations

import math
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from laserpeople.background.occupancy import MapFileError, OccupancyMap, load_ros_map

OCCUPIED_THRESH = 65
"""Occupancy (0-100) from which a cell is an obstacle (map_server: occupied_thresh 0.65)."""

MAP_TYPE = "nav_msgs/msg/OccupancyGrid"


def occupancy_grid_map(
    msg: Any, source: str = "", occupied_thresh: int = OCCUPIED_THRESH
) -> OccupancyMap:
    """The obstacles of a ``nav_msgs/OccupancyGrid`` message (``info.width``,
    ``info.height``, ``info.resolution``, ``info.origin``, ``data``; its frame from
    ``header.frame_id`` when the message has a header).

    Raises:
        MapFileError: the sizes do not match the data, or the resolution is not positive.
    """
    info = msg.info
    width, height = int(info.width), int(info.height)
    resolution = float(info.resolution)
    data = np.asarray(msg.data, dtype=np.int16).reshape(-1)
    if width <= 0 or height <= 0 or data.size != width * height:
        raise MapFileError(
            f"the OccupancyGrid is {width} x {height} cells but holds {data.size} values",
            path=source,
            hint="the map message is damaged; give a map.yaml instead",
        )
    if not (math.isfinite(resolution) and resolution > 0):
        raise MapFileError(f"the OccupancyGrid resolution is {resolution}", path=source)
    q = info.origin.orientation
    yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
    grid = data.reshape(height, width)[::-1]  # rows from the largest y down
    return OccupancyMap(
        occupied=grid >= occupied_thresh,
        resolution=resolution,
        origin=(float(info.origin.position.x), float(info.origin.position.y), yaw),
        path=source,
        frame=str(getattr(getattr(msg, "header", None), "frame_id", "")).lstrip("/"),
    )


def read_bag_map(path: str | Path, topic: str) -> OccupancyMap:
    """The last ``nav_msgs/OccupancyGrid`` on ``topic`` of the bag ``path`` (its frame in
    :attr:`OccupancyMap.frame`).

    Raises:
        MapFileError: the bag cannot be opened, the topic is missing or holds no map.
    """
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    p = Path(path)
    if not p.exists():
        raise MapFileError("bag not found", path=p, hint="give BAG:/topic of an existing bag")
    try:
        reader = AnyReader([p], default_typestore=get_typestore(Stores.LATEST))
        reader.open()
    except Exception as exc:  # any failure of the third-party parser
        raise MapFileError(f"cannot open the bag ({exc})", path=p) from exc
    try:
        conns = [c for c in reader.connections if c.topic == topic]
        if not conns:
            maps = sorted({c.topic for c in reader.connections if c.msgtype == MAP_TYPE})
            raise MapFileError(
                f"the bag has no topic {topic!r}",
                path=p,
                hint=f"map topics in it: {', '.join(maps) or 'none'}",
            )
        wrong = [c.msgtype for c in conns if c.msgtype != MAP_TYPE]
        if wrong:
            raise MapFileError(
                f"topic {topic!r} holds {wrong[0]}, not {MAP_TYPE}",
                path=p,
                hint="give the topic of the map (nav_msgs/OccupancyGrid)",
            )
        last: Any = None
        for conn, _, raw in reader.messages(connections=conns):
            last = reader.deserialize(raw, conn.msgtype)
        if last is None:
            raise MapFileError(f"topic {topic!r} holds no message", path=p)
        return occupancy_grid_map(last, f"{p}:{topic}")
    finally:
        reader.close()


def split_bag_spec(spec: str | Path) -> tuple[Path, str] | None:
    """``(bag, topic)`` of a ``BAG:/topic`` map argument, None for a ``map.yaml`` path."""
    text = str(spec)
    head, sep, topic = text.rpartition(":")
    if not sep or not topic.startswith("/") or not head:
        return None
    if Path(head).suffix.lower() not in (".bag", ".mcap", ".db3") and not Path(head).is_dir():
        return None
    return Path(head), topic


def load_map(spec: str | Path) -> OccupancyMap:
    """A prior map from a ROS ``map.yaml`` or from a bag topic ``BAG:/topic``
    (``nav_msgs/OccupancyGrid``, :func:`read_bag_map`). A run's stages that use the map
    share one copy: it is read again only when its file changed.

    Raises:
        MapFileError: the map cannot be read.
    """
    parts = split_bag_spec(spec)
    file = Path(spec) if parts is None else parts[0]
    try:
        changed = file.stat().st_mtime_ns
    except OSError:
        changed = -1  # missing: the reader names it
    return _read_map(str(spec), changed)


@lru_cache(maxsize=4)
def _read_map(spec: str, changed: int) -> OccupancyMap:
    """:func:`load_map` of ``spec`` whose file was last changed at ``changed`` [ns]."""
    parts = split_bag_spec(spec)
    if parts is None:
        return load_ros_map(spec)
    return read_bag_map(*parts)


def check_map_frame(grid: OccupancyMap, world_frame: str | None) -> None:
    """Refuse a map whose frame is known and is not the tracking world frame
    ``world_frame`` (None or empty: unknown, nothing to check); a ``map.yaml`` names no
    frame and is taken to be in the world frame.

    Raises:
        MapFileError: the frames differ (the map's obstacles would be drawn in the wrong
            place: no transform between them is applied).
    """
    world = (world_frame or "").lstrip("/")
    if not grid.frame or not world or grid.frame == world:
        return
    raise MapFileError(
        f"the map is in frame {grid.frame!r}, but the scans' poses are in {world!r}",
        path=grid.path,
        hint=(
            f"track in the map's frame with --world-frame {grid.frame} (the recording's "
            f"/tf must hold {grid.frame} -> {world}), or leave out --map"
        ),
    )


def world_frame_with_map(map_path: str | Path | None, world_frame: str | None) -> str | None:
    """The world frame for a run whose poses' frame is chosen as the transforms arrive (a
    live run) with the map ``map_path``: ``world_frame`` when given (refused when the map
    names another), else the frame the map names, else None (chosen as without a map).

    Raises:
        MapFileError: the map cannot be read, or names another frame than ``world_frame``.
    """
    if map_path is None:
        return world_frame
    grid = load_map(map_path)
    if world_frame:
        check_map_frame(grid, world_frame)
        return world_frame
    return grid.frame or None
