"""Sensor poses over time from transform trees (ROS ``/tf``) and odometry.

A recording's pose data is a tree of frames: every *child* frame hangs off one *parent*
frame through either a static transform (``/tf_static``, a fixed laser mount) or a
time series of transforms (``/tf``, ``nav_msgs/Odometry``). The pose of a laser in the
world frame at time ``t`` is the composition of the transforms along the chain from the
world frame (``map`` or ``odom``) down to the laser's ``header.frame_id``.

Everything is planar: a 3D transform keeps its translation x, y and its yaw about z.
A transform tilted by more than :attr:`PoseParams.max_tilt` (for instance a laser mounted
upside down, which mirrors its scan) cannot be represented this way; lookups through it
report the tilt instead of returning a wrong pose.

Time series are interpolated linearly in x, y and on the circle in the heading. A time
outside the samples by more than :attr:`PoseParams.tolerance`, or between two samples
further apart than :attr:`PoseParams.max_gap`, has no pose: nothing is extrapolated.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.scan import Pose2D, wrap_angle
from laserpeople.spelling import did_you_mean

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class PoseParams:
    """How sensor poses are looked up at scan time."""

    world_frames: tuple[str, ...] = param(
        ("map", "odom"),
        "ROS REP 105",
        "fixed frames tried in order as the world frame when none is given",
    )
    tolerance: float = param(
        0.05,
        "this project",
        "how far before the first / after the last pose sample a pose is still given "
        "(held constant, never extrapolated)",
        "s",
    )
    max_gap: float = param(
        0.5,
        "this project",
        "largest time between two pose samples that is interpolated across",
        "s",
    )
    max_tilt: float = param(
        0.2,
        "this project",
        "largest tilt of a transform's z axis from vertical still treated as planar",
        "rad",
    )


def yaw_and_tilt(qx: float, qy: float, qz: float, qw: float) -> tuple[float, float]:
    """Heading about z [rad] and tilt of the rotated z axis from vertical [rad] of a quaternion.

    The quaternion need not be normalised.
    """
    n = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    if n == 0.0 or not math.isfinite(n):
        return math.nan, math.nan
    qx, qy, qz, qw = qx / n, qy / n, qz / n, qw / n
    yaw = math.atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
    r22 = 1.0 - 2.0 * (qx * qx + qy * qy)
    tilt = math.acos(max(-1.0, min(1.0, r22)))
    return (yaw if yaw > -math.pi else math.pi), tilt  # atan2 gives [-pi, pi]


class PoseTrack:
    """A time series of planar poses of one frame in its parent frame.

    Args:
        stamps: Sample times (T,) [s]; sorted here if they are not.
        poses: Samples (T, 3) as x [m], y [m], theta [rad].
    """

    def __init__(self, stamps: NDArray[np.floating], poses: NDArray[np.floating]) -> None:
        s = np.asarray(stamps, dtype=np.float64).reshape(-1)
        p = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
        if s.size != p.shape[0]:
            raise ValueError(f"{s.size} stamps for {p.shape[0]} poses")
        order = np.argsort(s, kind="stable")
        self.stamps: FloatArray = s[order]
        self.poses: FloatArray = p[order]
        theta = self.poses[:, 2]
        outside = (theta <= -np.pi) | (theta > np.pi)  # wrap only these: keeps exact values
        theta[outside] = wrap_angle(theta[outside])

    def __len__(self) -> int:
        return int(self.stamps.size)

    @property
    def start(self) -> float:
        """Time of the first sample [s]."""
        return float(self.stamps[0])

    @property
    def end(self) -> float:
        """Time of the last sample [s]."""
        return float(self.stamps[-1])

    def at(self, t: float, tolerance: float, max_gap: float) -> Pose2D | None:
        """The pose at time ``t`` [s], or None when the samples do not cover ``t``."""
        s = self.stamps
        n = s.size
        if n == 0:
            return None
        hi = int(np.searchsorted(s, t, side="right"))
        if hi == 0:
            return Pose2D.from_array(self.poses[0]) if s[0] - t <= tolerance else None
        if hi == n:
            return Pose2D.from_array(self.poses[-1]) if t - s[-1] <= tolerance else None
        lo = hi - 1
        gap = float(s[hi] - s[lo])
        if gap > max_gap:  # only a sample within the tolerance may stand in
            if t - float(s[lo]) <= tolerance:
                return Pose2D.from_array(self.poses[lo])
            if float(s[hi]) - t <= tolerance:
                return Pose2D.from_array(self.poses[hi])
            return None
        w = (t - float(s[lo])) / gap if gap > 0.0 else 0.0
        x0, y0, a0 = (float(v) for v in self.poses[lo])
        x1, y1, a1 = (float(v) for v in self.poses[hi])
        dtheta = float(wrap_angle(a1 - a0))
        return Pose2D(
            x0 + w * (x1 - x0),
            y0 + w * (y1 - y0),
            float(wrap_angle(a0 + w * dtheta)),
        )


@dataclass(frozen=True)
class _Edge:
    parent: str
    static: Pose2D | None
    track: PoseTrack | None
    tilt: float
    source: str


def normalise_frame(frame: str) -> str:
    """A tf frame id without the leading slash that ROS 1 allowed."""
    return frame.strip().lstrip("/")


class TransformTree:
    """Frames linked by static and time-varying planar transforms.

    Each child frame has one parent; the first source that names a child's parent wins
    and a later conflicting parent is recorded in :attr:`conflicts` (tf itself forbids
    two parents).
    """

    def __init__(self, params: PoseParams | None = None) -> None:
        self.params = params or PoseParams()
        self._edges: dict[str, _Edge] = {}
        self.conflicts: list[str] = []

    def __contains__(self, frame: str) -> bool:
        return normalise_frame(frame) in self.frames()

    def frames(self) -> set[str]:
        """Every frame named as parent or child."""
        out = set(self._edges)
        out.update(e.parent for e in self._edges.values())
        return out

    def edges(self) -> list[tuple[str, str, str]]:
        """``(parent, child, source)`` of every transform."""
        return [(e.parent, c, e.source) for c, e in sorted(self._edges.items())]

    def _add(self, child: str, edge: _Edge) -> None:
        child = normalise_frame(child)
        old = self._edges.get(child)
        if old is not None:
            if old.parent != edge.parent:
                self.conflicts.append(
                    f"{child!r} has parent {old.parent!r} ({old.source}) and "
                    f"{edge.parent!r} ({edge.source}); kept {old.parent!r}"
                )
            return
        self._edges[child] = edge

    def add_static(
        self, parent: str, child: str, pose: Pose2D, *, tilt: float = 0.0, source: str = "static"
    ) -> None:
        """Add a fixed transform: ``pose`` of ``child`` in ``parent``."""
        self._add(child, _Edge(normalise_frame(parent), pose, None, tilt, source))

    def add_track(
        self,
        parent: str,
        child: str,
        stamps: NDArray[np.floating],
        poses: NDArray[np.floating],
        *,
        tilt: float = 0.0,
        source: str = "tf",
    ) -> None:
        """Add a time-varying transform: ``poses`` (T, 3) of ``child`` in ``parent``."""
        track = PoseTrack(stamps, poses)
        if len(track) == 0:
            return
        self._add(child, _Edge(normalise_frame(parent), None, track, tilt, source))

    def chain(self, world: str, frame: str) -> list[str] | None:
        """Frames from ``frame`` up to ``world`` (both included), or None if not connected."""
        world, frame = normalise_frame(world), normalise_frame(frame)
        path = [frame]
        seen = {frame}
        while path[-1] != world:
            edge = self._edges.get(path[-1])
            if edge is None or edge.parent in seen:
                return None
            path.append(edge.parent)
            seen.add(edge.parent)
        return path

    def root_of(self, frame: str) -> str:
        """The topmost ancestor of ``frame`` (``frame`` itself when it has no parent)."""
        frame = normalise_frame(frame)
        seen = {frame}
        while (edge := self._edges.get(frame)) is not None and edge.parent not in seen:
            frame = edge.parent
            seen.add(frame)
        return frame

    def pick_world(self, laser_frames: Iterable[str]) -> str | None:
        """The first of :attr:`PoseParams.world_frames` in the tree, else the common root
        of the laser frames, else None."""
        frames = self.frames()
        for candidate in self.params.world_frames:
            if candidate in frames:
                return candidate
        roots = {self.root_of(f) for f in laser_frames if normalise_frame(f) in frames}
        return roots.pop() if len(roots) == 1 else None

    def lookup(self, world: str, frame: str, t: float) -> tuple[Pose2D | None, str]:
        """Pose of ``frame`` in ``world`` at time ``t`` [s], and why not when it is None."""
        path = self.chain(world, frame)
        if path is None:
            return None, f"no transform chain from {world!r} to {normalise_frame(frame)!r}"
        p = self.params
        pose = Pose2D()
        # path runs child -> world; compose from the world end down to the child.
        for child in reversed(path[:-1]):
            edge = self._edges[child]
            if edge.tilt > p.max_tilt:
                return None, (
                    f"transform {edge.parent!r} -> {child!r} is tilted by "
                    f"{math.degrees(edge.tilt):.0f} deg (not planar)"
                )
            if edge.static is not None:
                step: Pose2D | None = edge.static
            else:
                assert edge.track is not None
                step = edge.track.at(t, p.tolerance, p.max_gap)
            if step is None:
                return None, f"stamp not covered by {edge.parent!r} -> {child!r} ({edge.source})"
            pose = pose.compose(step)
        return pose, ""


MIR100_LASER_MOUNTS: dict[str, tuple[str, Pose2D]] = {
    "front_laser_link": ("base_footprint", Pose2D(0.429646, 0.2358, 0.25 * math.pi)),
    "back_laser_link": ("base_footprint", Pose2D(-0.354354, -0.2358, -0.75 * math.pi)),
}
"""Laser mounts of a MiR100 (DFKI-NI/mir_robot, ``mir_description/urdf/include/mir_v1.urdf.xacro``:
laser_dx 0.392 + wheel_dx 0.037646, laser_dy 0.2358, yaw +45 / -135 deg; base_link coincides
with base_footprint). The MiR bag in ../shared/data records no /tf_static; with these mounts
its two lasers see the same walls (tests/test_io_rosbag_real.py checks the overlap)."""

KNOWN_MOUNTS: dict[str, dict[str, tuple[str, Pose2D]]] = {"mir100": MIR100_LASER_MOUNTS}


class PoseSamples:
    """Transform samples collected per (parent, child) edge while a recording is read."""

    def __init__(self) -> None:
        self._rows: dict[tuple[str, str], list[tuple[float, float, float, float]]] = {}
        self._tilt: dict[tuple[str, str], float] = {}
        self._source: dict[tuple[str, str], str] = {}
        self.dropped = 0
        """Samples left out because a value is not finite (NaN/inf, a zero quaternion)."""

    def add(
        self,
        parent: str,
        child: str,
        stamp: float,
        xy: tuple[float, float],
        yaw_tilt: tuple[float, float],
        source: str,
    ) -> None:
        """One sample of ``child`` in ``parent`` at ``stamp`` [s]: position [m], yaw and tilt
        [rad] (as :func:`yaw_and_tilt` gives them). A sample with a value that is not finite
        (a NaN or infinite translation, a zero quaternion) is left out and counted in
        :attr:`dropped`."""
        if not all(math.isfinite(v) for v in (stamp, xy[0], xy[1], yaw_tilt[0])):
            self.dropped += 1
            return
        key = (normalise_frame(parent), normalise_frame(child))
        self._rows.setdefault(key, []).append((stamp, xy[0], xy[1], yaw_tilt[0]))
        self._tilt[key] = max(self._tilt.get(key, 0.0), yaw_tilt[1])
        self._source.setdefault(key, source)

    def add_to(self, tree: TransformTree, *, static: bool = False) -> None:
        """Add every edge to ``tree``: as a fixed transform (its last sample) when ``static``,
        else as a time series."""
        for (parent, child), rows in self._rows.items():
            arr = np.asarray(rows, dtype=np.float64)
            tilt, source = self._tilt[(parent, child)], self._source[(parent, child)]
            if static:
                tree.add_static(
                    parent, child, Pose2D.from_array(arr[-1, 1:]), tilt=tilt, source=source
                )
            else:
                tree.add_track(parent, child, arr[:, 0], arr[:, 1:], tilt=tilt, source=source)


MAX_MOUNT_OFFSET = 1000.0
"""Largest |x|, |y| [m] of a laser mount given on the command line (a mount of 1e308 m
made every point NaN)."""


def parse_mounts(specs: Iterable[str]) -> dict[str, tuple[str, Pose2D]]:
    """Parse laser mounts ``CHILD=PARENT:x,y,theta`` (metres, radians) as given on a command
    line, the name of a known robot (``mir100``, see :data:`KNOWN_MOUNTS`), or a ``.toml``
    file of mounts written by ``laserpeople align -o``
    (:func:`laserpeople.alignment.read_mounts`).

    Example: ``front_laser_link=base_footprint:0.43,0.24,0.785``.
    """
    from laserpeople.errors import ConfigError

    out: dict[str, tuple[str, Pose2D]] = {}
    for spec in specs:
        if spec.strip().lower() in KNOWN_MOUNTS:
            out.update(KNOWN_MOUNTS[spec.strip().lower()])
            continue
        if spec.strip().lower().endswith(".toml"):
            from laserpeople.alignment import read_mounts

            for child, (parent, pose) in read_mounts(spec.strip()).items():
                out[normalise_frame(child)] = (normalise_frame(parent), pose)
            continue
        try:
            child, rest = spec.split("=", 1)
            parent, numbers = rest.split(":", 1)
            values = [float(v) for v in numbers.split(",")]
            if len(values) != 3 or not child.strip() or not parent.strip():
                raise ValueError
        except ValueError:
            raise ConfigError(
                f"bad mount {spec!r}",
                hint="write CHILD=PARENT:x,y,theta, e.g. laser=base_link:0.2,0,0, "
                f"or one of {', '.join(KNOWN_MOUNTS)}",
            ) from None
        pose = mount_pose(*values, what=f"mount {spec!r}")
        out[normalise_frame(child)] = (normalise_frame(parent), pose)
    return out


def mount_pose(
    x: float, y: float, theta: float, *, what: str, path: str | Path | None = None
) -> Pose2D:
    """The pose of a laser on its robot, checked: ``x`` and ``y`` [m] within
    :data:`MAX_MOUNT_OFFSET`, ``theta`` [rad] finite (at most 100 in magnitude).

    Raises:
        ConfigError: names ``what`` (``mount 'front'``) and ``path`` (a mounts file).
    """
    from laserpeople.errors import ConfigError

    if not (abs(x) <= MAX_MOUNT_OFFSET and abs(y) <= MAX_MOUNT_OFFSET and abs(theta) <= 100.0):
        raise ConfigError(
            f"{what} is off its robot: x and y must be within "
            f"{MAX_MOUNT_OFFSET:g} m and theta a finite angle in radians",
            path=path,
            hint="give the laser's offset from its parent frame in metres, e.g. 0.2,0,0",
        )
    return Pose2D(x, y, theta)


def mounts_to_use(
    mounts: Mapping[str, tuple[str, Pose2D]], own: Iterable[tuple[str, str, str]]
) -> tuple[dict[str, tuple[str, Pose2D]], list[str]]:
    """The given laser ``mounts`` (child -> (parent, pose)) that fit the recording's own
    transforms ``own`` (``(parent, child, source)`` each, as :meth:`TransformTree.edges`
    gives them; the first parent of a child counts), and one note per mount left out.

    A given mount wins over the recording's own transform of its laser (to correct a wrong
    ``/tf_static``), except when the recording already places the laser under a parent and
    names the mount's parent frame nowhere. The mount would then cut the laser off from the
    recording's chain: its poses would be in the mount's parent (the robot's frame), not in
    the world frame. A recording written by ``live --record`` or ``track --bag`` is such a
    case: its ``/tf`` holds the pose of each laser in the world frame at each scan, with the
    mount already in it.
    """
    parents: dict[str, tuple[str, str]] = {}
    frames: set[str] = set()
    for parent, child, source in own:
        parent, child = normalise_frame(parent), normalise_frame(child)
        parents.setdefault(child, (parent, source))
        frames.update((parent, child))
    use: dict[str, tuple[str, Pose2D]] = {}
    notes: list[str] = []
    for child, (parent, pose) in mounts.items():
        key, parent_key = normalise_frame(child), normalise_frame(parent)
        held = parents.get(key)
        if held is not None and held[0] != parent_key and parent_key not in frames:
            notes.append(
                f"mount of {key!r} on {parent_key!r} not used: {held[1]} already places "
                f"{key!r} in {held[0]!r} and names no frame {parent_key!r}, so the mount "
                f"would have cut the laser off from {held[0]!r} (a recording of "
                "`live --record` or `track --bag` holds the lasers' poses in the world "
                "frame: it needs no --mount)"
            )
            continue
        use[child] = (parent, pose)
    return use, notes


def stray_mount_notes(
    mounts: Mapping[str, tuple[str, Pose2D]],
    lasers: Mapping[str, str],
    frames: Iterable[str] = (),
) -> list[str]:
    """One note per given mount whose child frame no laser of the recording has and no
    other frame names: a misspelt CHILD, or a topic given where the frame id is meant.

    ``lasers`` maps each laser topic to its scans' ``header.frame_id``; ``frames`` are the
    other frames the recording's transforms name. A child that is the parent of another
    given mount (a chain such as ``base_link=base_footprint:...``) is not stray.
    """
    known = {normalise_frame(f) for f in (*lasers.values(), *frames)}
    known |= {normalise_frame(parent) for parent, _ in mounts.values()}
    have = ", ".join(f"{topic} {frame!r}" for topic, frame in lasers.items()) or "none"
    laser_frames = sorted({normalise_frame(f) for f in lasers.values()})
    notes = []
    for child in mounts:
        if normalise_frame(child) in known:
            continue
        guess = did_you_mean(normalise_frame(child), laser_frames)
        notes.append(
            f"mount of {normalise_frame(child)!r} not used: no laser's scans have that frame "
            f"id and no transform names it{f' ({guess})' if guess else ''} (CHILD is the "
            f"header.frame_id of the laser's scans; the lasers' frames here: {have})"
        )
    return notes


def add_mounts(tree: TransformTree, mounts: Mapping[str, tuple[str, Pose2D]]) -> None:
    """Add user-given fixed laser mounts (child -> (parent, pose)) to ``tree``."""
    for child, (parent, pose) in mounts.items():
        tree.add_static(parent, child, pose, source="given mount")
