"""People ground truth stored in a bag: ``leg_tracker/Person``, ``spencer_tracking_msgs/
TrackedPersons`` and ``people_msgs/People`` topics, paired with the scans of a laser topic.

The three message types are defined here from their ``.msg`` text and registered with the
rosbags type system (:func:`register_people_types`), so a bag that lacks their
definitions (a ROS 2 bag, a filtered bag) still reads, and tests write such bags with
rosbags' own writer.

Pairing a label with its scan (the scan index is what the tracks CSV carries):

- ``leg_tracker/Person`` has no header. As in the leg_tracker benchmark, each label is
  written just after its scan: it belongs to the latest scan of the laser topic received
  before it (bag log time). Several Person messages after one scan are the people of that
  scan.
- ``TrackedPersons`` and ``People`` carry a header stamp: the message belongs to the scan
  of the laser topic whose header stamp is nearest, if that is within half the median scan
  interval (otherwise it is counted in :attr:`BagTruth.unpaired`). A zero stamp falls back
  to the log-time rule above.

Positions are taken as they are (``x, y`` of the message, in its ``header.frame_id`` or
the laser frame for Person); no transform is applied, so the tracks to compare with must be
in that frame (for a recording without poses: the sensor frame, as ``track`` writes it).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from laserpeople.errors import ConfigError, MessageTypeError, RecordingError, TopicNotFoundError
from laserpeople.scan import CoordinateFrame
from laserpeople.truth import TruthFrame

LEG_TRACKER_PERSON = "leg_tracker/msg/Person"
SPENCER_TRACKED_PERSONS = "spencer_tracking_msgs/msg/TrackedPersons"
PEOPLE_MSGS_PEOPLE = "people_msgs/msg/People"

PEOPLE_MSG_DEFINITIONS: dict[str, str] = {
    # leg_tracker (Leigh et al.), msg/Person.msg
    LEG_TRACKER_PERSON: "geometry_msgs/Pose pose\nuint32 id\n",
    # SPENCER, spencer_tracking_msgs/msg/TrackedPerson.msg and TrackedPersons.msg
    "spencer_tracking_msgs/msg/TrackedPerson": (
        "uint64 track_id\nbool is_occluded\nbool is_matched\nuint64 detection_id\n"
        "duration age\ngeometry_msgs/PoseWithCovariance pose\n"
        "geometry_msgs/TwistWithCovariance twist\n"
    ),
    SPENCER_TRACKED_PERSONS: "std_msgs/Header header\nTrackedPerson[] tracks\n",
    # wg-perception people, people_msgs/msg/Person.msg and People.msg
    "people_msgs/msg/Person": (
        "string name\ngeometry_msgs/Point position\ngeometry_msgs/Point velocity\n"
        "float64 reliability\nstring[] tagnames\nstring[] tags\n"
    ),
    PEOPLE_MSGS_PEOPLE: "std_msgs/Header header\npeople_msgs/Person[] people\n",
}
"""The ``.msg`` text of every people message type read here (ROS 1 field layout)."""

TRUTH_TYPES = (LEG_TRACKER_PERSON, SPENCER_TRACKED_PERSONS, PEOPLE_MSGS_PEOPLE)
"""Message types a ground-truth topic may carry."""

BAG_SUFFIXES = frozenset({".bag", ".mcap", ".db3"})


def register_people_types(typestore: Any) -> None:
    """Add the people message types of :data:`PEOPLE_MSG_DEFINITIONS` to a rosbags
    typestore (types it already has are left as they are)."""
    from rosbags.typesys import get_types_from_msg

    for name, text in PEOPLE_MSG_DEFINITIONS.items():
        if name not in typestore.fielddefs:
            typestore.register(get_types_from_msg(text, name))


def is_bag_path(path: Path) -> bool:
    """Whether ``path`` names a bag (by extension, or a ROS 2 bag folder)."""
    return path.suffix.lower() in BAG_SUFFIXES or (path / "metadata.yaml").is_file()


def split_truth_spec(spec: str) -> tuple[Path, str | None]:
    """``BAG[:TOPIC]`` -> (path, topic or None). A spec that names an existing file or
    folder is a path even when it contains a colon.

    Raises:
        ConfigError: the path before ``:TOPIC`` is empty (``:/people``, an unset shell
            variable), which would name the current folder."""
    whole = Path(spec)
    if whole.exists() or ":" not in spec:
        return whole, None
    head, _, topic = spec.rpartition(":")
    if not head:
        raise ConfigError(
            f"truth {spec!r} names no bag before ':{topic}'",
            hint=f"give BAG:TOPIC, e.g. run.bag:{topic or '/people'}",
        )
    return Path(head), topic or None


@dataclass
class BagTruth:
    """Ground truth read from a bag.

    Attributes:
        frames: One frame per labelled scan, in scan order (``scan_index`` on the laser
            topic, ``stamp`` that scan's header stamp).
        topic: The truth topic.
        msgtype: Its message type.
        laser_topic: The laser topic the labels were paired with.
        frame_id: ``header.frame_id`` of the truth messages (None for Person, which has
            no header: its positions are in the laser frame).
        laser_frame_id: ``header.frame_id`` of the laser's scans.
        messages: Truth messages read.
        labels: Person labels read (one per person per message).
        unpaired: Labels that found no scan (before the first scan, or no scan stamp near).
        duplicates: Labels dropped because the same person was labelled twice for one scan
            (the later label is kept).
        names: Person id -> original name, for ``people_msgs`` whose ids are strings.
    """

    frames: list[TruthFrame]
    topic: str
    msgtype: str
    laser_topic: str
    frame_id: str | None = None
    laser_frame_id: str = ""
    messages: int = 0
    labels: int = 0
    unpaired: int = 0
    duplicates: int = 0
    names: dict[int, str] = field(default_factory=dict)

    @property
    def frame(self) -> CoordinateFrame | None:
        """``sensor`` when the labels are in the laser's frame (Person, or a header naming
        the laser's frame id); None when they name another frame, which may or may not be
        the tracking world frame."""
        if self.frame_id is None or self.frame_id == self.laser_frame_id:
            return "sensor"
        return None

    def summary(self) -> str:
        """One line: what was read and how it was paired."""
        where = f"frame {self.frame_id!r}" if self.frame_id else "the laser frame"
        people = len({i for f in self.frames for i in f.person_ids})
        text = (
            f"{self.labels} labels of {people} {'person' if people == 1 else 'people'} "
            f"on {len(self.frames)} scans of {self.laser_topic} from {self.topic} "
            f"({self.msgtype.replace('/msg/', '/')}, {where})"
        )
        if self.unpaired:
            text += f"; {self.unpaired} labels had no scan to pair with"
        if self.duplicates:
            text += f"; {self.duplicates} repeated labels dropped"
        return text


def _stamp(header: Any) -> float:
    return float(header.stamp.sec) + 1e-9 * float(header.stamp.nanosec)


class _PersonIds:
    """People ids from names: numbers stay, other names get 0, 1, 2, ... (recorded)."""

    def __init__(self) -> None:
        self.names: dict[int, str] = {}
        self._by_name: dict[str, int] = {}

    def __call__(self, name: str) -> int:
        got = self._by_name.get(name)
        if got is None:
            got = len(self._by_name)
            self._by_name[name] = got
            self.names[got] = name
        return got


def _people(msg: Any, msgtype: str, ids: _PersonIds) -> list[tuple[int, float, float]]:
    """(id, x, y) of every person in one truth message."""
    if msgtype == LEG_TRACKER_PERSON:
        p = msg.pose.position
        return [(int(msg.id), float(p.x), float(p.y))]
    if msgtype == SPENCER_TRACKED_PERSONS:
        return [
            (int(t.track_id), float(t.pose.pose.position.x), float(t.pose.pose.position.y))
            for t in msg.tracks
        ]
    return [(ids(str(p.name)), float(p.position.x), float(p.position.y)) for p in msg.people]


def _open(path: Path) -> Any:
    from laserpeople.io.bag_guard import open_reader

    if not path.exists():
        raise RecordingError("file not found", path=path, hint="check the path of --truth")
    return open_reader(path, register=register_people_types, hint="give a readable .bag/.mcap/.db3")


DRAWN_TRUTH = "/laserpeople/truth"
"""The topic of the drawn ground truth in a Foxglove export (:mod:`laserpeople.viz.mcap_export`)."""


def _pick_topic(
    path: Path, topics: dict[str, str], wanted: str | None, allowed: Sequence[str], what: str
) -> str:
    listing = ", ".join(f"{t} ({m.replace('/msg/', '/')})" for t, m in topics.items()) or "none"
    if wanted is not None:
        for name in (wanted, "/" + wanted.lstrip("/"), wanted.lstrip("/")):
            if name in topics:
                if topics[name] not in allowed:
                    raise MessageTypeError(
                        f"topic {name!r} carries {topics[name]}, not {what}",
                        path=path,
                        hint=f"topics here: {listing}",
                    )
                return name
        raise TopicNotFoundError(
            f"no topic {wanted!r} in this bag", path=path, hint=f"topics here: {listing}"
        )
    found = [t for t, m in topics.items() if m in allowed]
    if not found and topics.get(DRAWN_TRUTH) == "visualization_msgs/msg/MarkerArray":
        raise TopicNotFoundError(
            f"no {what} topic in this bag: it is a Foxglove export of "
            f"`laserpeople view -o FILE.mcap`, whose {DRAWN_TRUTH} draws the truth",
            path=path,
            hint="give the recording or the truth CSV it was drawn from",
        )
    if len(found) != 1:
        raise TopicNotFoundError(
            f"{'no' if not found else 'more than one'} {what} topic in this bag",
            path=path,
            hint=f"name it as BAG:TOPIC; topics here: {listing}",
        )
    return found[0]


def read_truth_bag(
    path: str | Path, topic: str | None = None, laser_topic: str | None = None
) -> BagTruth:
    """Read people ground truth from ``topic`` of a bag, paired with the scans of
    ``laser_topic`` (see the module docstring for the pairing rules).

    Args:
        path: The bag.
        topic: The truth topic; the bag's only topic of a type in :data:`TRUTH_TYPES` when
            None.
        laser_topic: The laser topic whose scan indices label the frames; the bag's only
            laser topic when None.

    Raises:
        TopicNotFoundError: a topic is missing, or it is not given and the bag has none or
            several candidates (the message lists the topics).
        MessageTypeError: the truth topic carries another message type.
        RecordingError: the bag cannot be read, or no label pairs with a scan.
    """
    from laserpeople.io.bag_guard import bag_messages, describe
    from laserpeople.io.rosbag import LASERSCAN

    p = Path(path)
    reader = _open(p)
    try:
        topics = {c.topic: c.msgtype for c in reader.connections}
        truth_topic = _pick_topic(p, topics, topic, TRUTH_TYPES, "people ground-truth")
        laser = _pick_topic(p, topics, laser_topic, (LASERSCAN,), "sensor_msgs/LaserScan")
        msgtype = topics[truth_topic]
        conns = [c for c in reader.connections if c.topic in (truth_topic, laser)]
        out = BagTruth([], truth_topic, msgtype, laser)
        ids = _PersonIds()
        scan_stamps: list[float] = []
        by_log: dict[int, list[tuple[int, float, float]]] = {}
        by_stamp: list[tuple[float, list[tuple[int, float, float]]]] = []
        try:
            what = f"{truth_topic} or {laser}"
            for conn, log_time, msg in bag_messages(reader, conns, p, what):
                if conn.topic == laser:
                    out.laser_frame_id = out.laser_frame_id or str(msg.header.frame_id)
                    stamp = _stamp(msg.header)
                    scan_stamps.append(stamp if stamp != 0.0 else log_time * 1e-9)
                    continue
                people = _people(msg, msgtype, ids)
                out.messages += 1
                out.labels += len(people)
                header = getattr(msg, "header", None)
                if header is not None:
                    out.frame_id = out.frame_id or str(header.frame_id) or None
                if header is not None and _stamp(header) != 0.0:
                    by_stamp.append((_stamp(header), people))
                elif scan_stamps:
                    by_log.setdefault(len(scan_stamps) - 1, []).extend(people)
                else:
                    out.unpaired += len(people)
        except RecordingError:
            raise
        except Exception as exc:  # any failure of the third-party parser on a damaged file
            raise RecordingError(
                f"cannot read {truth_topic} or {laser}: {describe(exc)}",
                path=p,
                hint="the bag is corrupt or truncated",
            ) from exc
    finally:
        reader.close()
    _pair_by_stamp(by_stamp, np.asarray(scan_stamps), by_log, out)
    out.names = ids.names
    out.frames = _frames(by_log, scan_stamps, out)
    if not out.frames:
        raise RecordingError(
            f"no label of {truth_topic} pairs with a scan of {laser}",
            path=p,
            hint="check that the truth and laser topics come from the same recording",
        )
    return out


def _pair_by_stamp(
    stamped: list[tuple[float, list[tuple[int, float, float]]]],
    scans: np.ndarray,
    by_scan: dict[int, list[tuple[int, float, float]]],
    out: BagTruth,
) -> None:
    """Put each stamped message on the scan with the nearest header stamp (within half the
    median scan interval)."""
    if not stamped:
        return
    if scans.size == 0:
        out.unpaired += sum(len(p) for _, p in stamped)
        return
    tol = 0.5 * float(np.median(np.diff(scans))) if scans.size > 1 else math.inf
    order = np.argsort(scans, kind="stable")
    sorted_stamps = scans[order]
    for stamp, people in stamped:
        k = int(np.searchsorted(sorted_stamps, stamp))
        near = [j for j in (k - 1, k) if 0 <= j < sorted_stamps.size]
        j = min(near, key=lambda j: abs(sorted_stamps[j] - stamp))
        if abs(sorted_stamps[j] - stamp) > tol:
            out.unpaired += len(people)
            continue
        by_scan.setdefault(int(order[j]), []).extend(people)


def _frames(
    by_scan: dict[int, list[tuple[int, float, float]]], stamps: list[float], out: BagTruth
) -> list[TruthFrame]:
    frames = []
    for scan in sorted(by_scan):
        latest: dict[int, tuple[float, float]] = {}
        for pid, x, y in by_scan[scan]:
            if pid in latest:
                out.duplicates += 1
            latest[pid] = (x, y)
        ids = np.array(sorted(latest), dtype=np.int64)
        xy = np.array([latest[int(i)] for i in ids], dtype=np.float64).reshape(-1, 2)
        frames.append(TruthFrame.from_positions(stamps[scan], scan, ids, xy, out.frame))
    return frames
