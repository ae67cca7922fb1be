"""Tracks as ROS messages in a bag: what ROS users replay, and what ``evaluate`` reads back.

Topics written by :class:`TracksBagWriter` (ROS 1 ``.bag`` or ROS 2 ``.mcap``/``.db3``),
one message per frame on each:

=========================  ====================================  ==========================
topic                      type                                  content
=========================  ====================================  ==========================
``/<laser>``               ``sensor_msgs/LaserScan``             the scans of the frame
``/tf``                    ``tf2_msgs/TFMessage``                world -> laser (with poses)
``/laserpeople/people``    ``people_msgs/People``                person tracks
``/laserpeople/legs``      ``people_msgs/People``                leg tracks
``/laserpeople/groups``    ``people_msgs/People``                group tracks
``/laserpeople/markers``   ``visualization_msgs/MarkerArray``    all tracks, for rviz/Foxglove
=========================  ====================================  ==========================

``people_msgs/Person`` (as in ROS's ``people`` stack): ``name`` is the track id, ``position``
and ``velocity`` are in the header's frame [m, m/s], ``reliability`` the tracker's score,
and ``tagnames``/``tags`` carry ``kind``, ``scan`` (the frame index), ``frame``
(``world`` or ``sensor``: the frame of the positions, whatever the header's ``frame_id``
is named), ``size`` and ``members`` (the legs of a person, ``;``-separated). The types are
registered with rosbags from their ``.msg`` text, so no ROS installation is needed.
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from laserpeople.errors import RecordingError
from laserpeople.io.rosbag_writer import BagSink, sensor_frame_id, sensor_topic
from laserpeople.scan import CoordinateFrame, Scan
from laserpeople.tracks import TRACK_KINDS, Track, TrackKind, Tracks

PERSON_TYPE = "people_msgs/msg/Person"
PEOPLE_TYPE = "people_msgs/msg/People"
DRAWN_TYPE = "visualization_msgs/msg/MarkerArray"
"""The type of the tracks' topics in a Foxglove export (:mod:`laserpeople.viz.mcap_export`)."""
MARKERS_TYPE = "visualization_msgs/msg/MarkerArray"
PERSON_MSG = """string name
geometry_msgs/Point position
geometry_msgs/Point velocity
float64 reliability
string[] tagnames
string[] tags
"""
PEOPLE_MSG = """std_msgs/Header header
people_msgs/Person[] people
"""
TRACK_TOPICS: dict[TrackKind, str] = {
    "person": "/laserpeople/people",
    "leg": "/laserpeople/legs",
    "group": "/laserpeople/groups",
}
MARKER_TOPIC = "/laserpeople/markers"
WORLD_FRAME_ID = "world"

# visualization_msgs/Marker constants
_ARROW, _SPHERE, _CYLINDER, _TEXT = 0, 2, 3, 9
_ADD, _DELETEALL = 0, 3
_MARKER_LOOK: dict[TrackKind, tuple[int, float, float, tuple[float, float, float]]] = {
    # kind: (marker type, diameter [m], height [m], rgb)
    "leg": (_SPHERE, 0.15, 0.15, (0.2, 0.5, 1.0)),
    "person": (_CYLINDER, 0.35, 1.2, (1.0, 0.45, 0.1)),
    "group": (_CYLINDER, 1.0, 0.3, (0.3, 0.8, 0.3)),
}


def register_people_types(typestore: Any) -> None:
    """Add ``people_msgs/Person`` and ``People`` to a rosbags typestore (once)."""
    if PEOPLE_TYPE in typestore.types:
        return
    from rosbags.typesys import get_types_from_msg

    types = get_types_from_msg(PERSON_MSG, PERSON_TYPE)
    types.update(get_types_from_msg(PEOPLE_MSG, PEOPLE_TYPE))
    typestore.register(types)


def build_message(typestore: Any, msgtype: str, **given: Any) -> Any:
    """A message of ``msgtype`` with the ``given`` fields and zero/empty defaults for the
    rest, so that one call works for both ROS 1 and ROS 2 definitions of a type.

    The defaults come from a plan made once per type and typestore. A nested message left
    out is one shared instance when nothing in it can change size or value in place (only
    numbers, strings and empty numeric arrays, as a ``Duration`` or an empty
    ``CompressedImage``); lists and fixed-size arrays are new each time."""
    cls, plan, _ = _plan(typestore, msgtype)
    values = {name: given[name] if name in given else make() for name, make in plan}
    return cls(**values)


_Plan = tuple[Any, tuple[tuple[str, Callable[[], Any]], ...], bool]
"""Message class, per field what makes its default, whether a default instance may be
shared."""
_PLANS: weakref.WeakKeyDictionary[Any, dict[str, _Plan]] = weakref.WeakKeyDictionary()


def _plan(typestore: Any, msgtype: str) -> _Plan:
    """The plan of ``msgtype`` (see :func:`build_message`), made on first use."""
    plans = _PLANS.get(typestore)
    if plans is None:
        plans = _PLANS[typestore] = {}
    plan = plans.get(msgtype)
    if plan is None:
        _, fields = typestore.fielddefs[msgtype]
        made = [(name, _default(typestore, node, detail)) for name, (node, detail) in fields]
        plan = plans[msgtype] = (
            typestore.types[msgtype],
            tuple((name, make) for name, (make, _) in made),
            all(shareable for _, (_, shareable) in made),
        )
    return plan


def _default(typestore: Any, node: Any, detail: Any) -> tuple[Callable[[], Any], bool]:
    """What makes the default value of a field, and whether that value may be shared."""
    kind = int(node)
    if kind == 1:  # BASE
        base = detail[0]
        value: Any = "" if base == "string" else False if base == "bool" else 0
        if base in ("float32", "float64"):
            value = 0.0
        return (lambda: value), True
    if kind == 2:  # NAME (a nested message)
        if _plan(typestore, detail)[2]:
            nested = build_message(typestore, detail)
            return (lambda: nested), True
        return (lambda: build_message(typestore, detail)), False
    # ARRAY (3) or SEQUENCE (4): ((node, detail), length)
    (inner_node, inner_detail), length = detail
    size = length if kind == 3 else 0
    if int(inner_node) == 1 and inner_detail[0] not in ("string",):
        dtype = {"bool": np.bool_, "float32": np.float32, "float64": np.float64}.get(
            inner_detail[0], np.dtype(inner_detail[0]) if inner_detail[0] != "char" else np.uint8
        )
        return (lambda: np.zeros(size, dtype=dtype)), kind == 4  # empty: cannot change
    inner, _ = _default(typestore, inner_node, inner_detail)
    return (lambda: [inner() for _ in range(size)]), False


class TracksBagWriter:
    """Writes frames' scans and tracks into an open :class:`BagSink` as ROS messages.

    Args:
        sink: From :func:`laserpeople.io.rosbag_writer.open_reader`.
        scans: Also write the scans (and their poses on ``/tf`` when in the world frame).
    """

    def __init__(self, sink: BagSink, *, scans: bool = True) -> None:
        self.sink = sink
        self.scans = scans
        self.frames = 0
        register_people_types(sink.typestore)

    def write(self, scans: Sequence[Scan], tracks: Tracks) -> None:
        """One frame: its ``scans`` and its ``tracks`` (in ``tracks.frame``)."""
        if self.scans:
            self.write_scans(scans, tracks.frame == "world")
        self.write_tracks(scans, tracks)
        self.frames += 1

    def write_scans(self, scans: Sequence[Scan], world: bool) -> None:
        """The scans of one frame, and their poses on ``/tf`` when ``world``."""
        for scan in scans:
            sid = sensor_frame_id(scan.sensor)
            self.sink.scan(scan, sensor_topic(scan.sensor, ros1=self.sink.ros1), sid)
            if world and scan.pose is not None:
                self.sink.pose(scan.stamp, WORLD_FRAME_ID, sid, scan.pose, "/tf")

    def write_tracks(self, scans: Sequence[Scan], tracks: Tracks) -> None:
        """The People messages (one per kind) and the MarkerArray of one frame."""
        world = tracks.frame == "world"
        first = sensor_frame_id(scans[0].sensor) if scans else "laser"
        frame_id = WORLD_FRAME_ID if world else first
        stamp = tracks.stamp
        header = self.sink.header(stamp, frame_id)
        for kind, topic in TRACK_TOPICS.items():
            people = [
                self._person(t, tracks.scan_index, tracks.frame) for t in tracks.of_kind(kind)
            ]
            msg = build_message(self.sink.typestore, PEOPLE_TYPE, header=header, people=people)
            self.sink.write(topic, PEOPLE_TYPE, msg, stamp)
        self.sink.write(MARKER_TOPIC, MARKERS_TYPE, self._markers(header, tracks), stamp)

    def _point(self, xy: np.ndarray, z: float = 0.0) -> Any:
        return build_message(
            self.sink.typestore,
            "geometry_msgs/msg/Point",
            x=_finite(xy[0]),
            y=_finite(xy[1]),
            z=z,
        )

    def _person(self, track: Track, scan_index: int, frame: CoordinateFrame | None = None) -> Any:
        tags = {"kind": track.kind, "scan": str(scan_index)}
        if frame is not None:
            tags["frame"] = frame
        tags |= {
            "size": str(track.size),
            "members": ";".join(str(m) for m in track.members),
            "labels": track.labels,
        }
        return build_message(
            self.sink.typestore,
            PERSON_TYPE,
            name=str(track.track_id),
            position=self._point(track.position),
            velocity=self._point(track.velocity),
            reliability=float(track.score),
            tagnames=list(tags),
            tags=list(tags.values()),
        )

    def _markers(self, header: Any, tracks: Tracks) -> Any:
        ts = self.sink.typestore
        make = lambda t, **kw: build_message(ts, t, **kw)  # noqa: E731
        markers = [make("visualization_msgs/msg/Marker", header=header, action=_DELETEALL)]
        for track in tracks:
            shape, diameter, height, rgb = _MARKER_LOOK[track.kind]
            color = make("std_msgs/msg/ColorRGBA", r=rgb[0], g=rgb[1], b=rgb[2], a=0.85)
            pose = make(
                "geometry_msgs/msg/Pose",
                position=self._point(track.position, height / 2),
                orientation=make("geometry_msgs/msg/Quaternion", w=1.0),
            )
            tid = _marker_id(track.track_id)
            markers.append(
                make(
                    "visualization_msgs/msg/Marker",
                    header=header,
                    ns=f"{track.kind}s",
                    id=tid,
                    type=shape,
                    action=_ADD,
                    pose=pose,
                    scale=make("geometry_msgs/msg/Vector3", x=diameter, y=diameter, z=height),
                    color=color,
                )
            )
            markers.append(
                make(
                    "visualization_msgs/msg/Marker",
                    header=header,
                    ns=f"{track.kind}_ids",
                    id=tid,
                    type=_TEXT,
                    action=_ADD,
                    pose=make(
                        "geometry_msgs/msg/Pose",
                        position=self._point(track.position, height + 0.2),
                        orientation=make("geometry_msgs/msg/Quaternion", w=1.0),
                    ),
                    scale=make("geometry_msgs/msg/Vector3", z=0.25),
                    color=color,
                    text=f"{track.kind[0].upper()}{track.track_id}",
                )
            )
            v = np.array([_finite(track.velocity[0]), _finite(track.velocity[1])])
            if math.hypot(v[0], v[1]) > 0.05:
                markers.append(
                    make(
                        "visualization_msgs/msg/Marker",
                        header=header,
                        ns=f"{track.kind}_velocities",
                        id=tid,
                        type=_ARROW,
                        action=_ADD,
                        pose=make(
                            "geometry_msgs/msg/Pose",
                            orientation=make("geometry_msgs/msg/Quaternion", w=1.0),
                        ),
                        scale=make("geometry_msgs/msg/Vector3", x=0.04, y=0.08, z=0.1),
                        color=color,
                        points=[
                            self._point(track.position, 0.1),
                            self._point(track.position + v, 0.1),
                        ],
                    )
                )
        return make(MARKERS_TYPE, markers=markers)


def _finite(value: float) -> float:
    return float(value) if math.isfinite(value) else 0.0


def _marker_id(track_id: int) -> int:
    return int(track_id) % (2**31)


def iter_tracks_bag(
    path: str | Path, kinds: tuple[TrackKind, ...] | None = None
) -> Iterator[Tracks]:
    """Read the tracks a :class:`TracksBagWriter` wrote back, one :class:`Tracks` per frame
    with tracks, in frame order; positions in the frame of the messages: their people's
    ``frame`` tag, or without it ``world`` when the header's ``frame_id`` is ``world``, else
    ``sensor`` (``live`` names the robot's frames in its headers, e.g. ``odom``).

    The bag is opened and read through :func:`~laserpeople.io.bag_guard.open_reader` and
    :func:`~laserpeople.io.bag_guard.bag_messages`, as every other bag of this package.

    Raises:
        RecordingError: The bag is missing, damaged or truncated, has no ``/laserpeople/*``
            people topics, or a person lacks the ``kind``/``scan`` tags or carries a value
            that is not a number within bounds (the message names the file and message).
    """
    from laserpeople.io.bag_guard import bag_messages, open_reader

    p = Path(path)
    wanted = kinds or TRACK_KINDS
    topics = {TRACK_TOPICS[k] for k in wanted}
    reader = open_reader(p, register=register_people_types, hint=TRACKS_BAG_HINT)
    try:
        conns = [c for c in reader.connections if c.topic in topics]
        if not conns:
            raise RecordingError(
                f"no tracks in the bag (none of the topics {', '.join(sorted(topics))})",
                path=p,
                hint="give a bag written by `laserpeople track --bag`",
            )
        drawn = [c for c in conns if c.msgtype != PEOPLE_TYPE]
        if drawn:
            raise RecordingError(
                f"topic {drawn[0].topic} carries {drawn[0].msgtype}, not {PEOPLE_TYPE}: "
                + (
                    "this is a Foxglove export of `laserpeople view -o FILE.mcap`, drawings "
                    "of the tracks that cannot be read back as tracks"
                    if drawn[0].msgtype == DRAWN_TYPE
                    else "these are no tracks of `laserpeople track --bag`"
                ),
                path=p,
                hint="give the tracks CSV it was drawn from, or the bag of "
                "`laserpeople track -o tracks.csv --bag tracks.mcap`",
            )
        current: list[Track] = []
        key: tuple[int, float, CoordinateFrame] | None = None
        for number, (conn, _, msg) in enumerate(bag_messages(reader, conns, p, "the tracks")):
            try:
                stamp = float(msg.header.stamp.sec) + 1e-9 * float(msg.header.stamp.nanosec)
                frame = _message_frame(msg)
                people = [_person_track(person, wanted) for person in msg.people]
            except (AttributeError, KeyError, TypeError, ValueError, OverflowError) as exc:
                raise RecordingError(
                    f"topic {conn.topic}, message {number}: {exc}",
                    path=p,
                    hint=TRACKS_BAG_HINT,
                ) from exc
            for scan, track in people:
                if track is None:
                    continue
                if key is not None and scan != key[0]:
                    if current:
                        yield Tracks(key[1], key[0], tuple(current), key[2])
                    current = []
                key = (scan, stamp, frame)
                current.append(track)
        if key is not None and current:
            yield Tracks(key[1], key[0], tuple(current), key[2])
    finally:
        reader.close()


def _message_frame(msg: Any) -> CoordinateFrame:
    """The frame of a People message's positions (see :func:`iter_tracks_bag`).

    Raises:
        ValueError: The ``frame`` tag is neither ``world`` nor ``sensor``.
    """
    if msg.people:
        tags = dict(zip(msg.people[0].tagnames, msg.people[0].tags, strict=False))
        if "frame" in tags:
            if tags["frame"] not in ("world", "sensor"):
                raise ValueError(f"frame tag {tags['frame']!r} is not world or sensor")
            return "world" if tags["frame"] == "world" else "sensor"
    return "world" if msg.header.frame_id == WORLD_FRAME_ID else "sensor"


TRACKS_BAG_HINT = "give a bag written by `laserpeople track --bag`, whole and readable"


def _person_track(person: Any, wanted: tuple[TrackKind, ...]) -> tuple[int, Track | None]:
    """(scan index, track) of one ``people_msgs/Person`` (track None: a kind not wanted).

    Raises:
        ValueError: a tag is missing or a value is not a number within bounds.
    """
    from laserpeople.io.tracks_csv import ID_LIMIT

    tags = dict(zip(person.tagnames, person.tags, strict=False))
    if "scan" not in tags or "kind" not in tags:
        raise ValueError("a person lacks the kind/scan tags")
    scan = int(tags["scan"])
    if not 0 <= scan < ID_LIMIT:
        raise ValueError(f"scan tag {scan} is negative or too large")
    kind = tags["kind"]
    if kind not in wanted:
        if kind not in TRACK_KINDS:
            raise ValueError(f"kind {kind[:40]!r} is not one of {', '.join(TRACK_KINDS)}")
        return scan, None
    track_id = int(person.name)
    size = int(tags.get("size") or 1)
    if not (abs(track_id) < ID_LIMIT and 0 <= size <= 1_000_000):
        raise ValueError(f"track id {track_id} or size {size} out of bounds")
    members = tuple(int(m) for m in tags.get("members", "").split(";") if m)
    position = np.array([float(person.position.x), float(person.position.y)])
    if not np.all(np.isfinite(position)):
        raise ValueError(f"track {track_id}: position is not finite")
    return scan, Track(
        track_id=track_id,
        kind=kind,
        position=position,
        velocity=np.array([float(person.velocity.x), float(person.velocity.y)]),
        covariance=np.full((2, 2), np.nan),
        size=size,
        labels=str(tags.get("labels", "")),
        score=float(person.reliability),
        members=members,
    )


__all__ = [
    "MARKER_TOPIC",
    "TRACK_TOPICS",
    "TracksBagWriter",
    "build_message",
    "iter_tracks_bag",
    "register_people_types",
]
