"""Sensor poses from transforms as they arrive (``/tf``, ``/tf_static``, odometry).

:class:`LiveTransforms` collects the samples and answers lookups with the recordings'
:class:`~laserpeople.io.poses.TransformTree` (the same interpolation, tolerance and gaps as
``track`` uses on a bag), rebuilt only when a sample arrived since the last lookup. Memory is
bounded: a time-varying transform keeps its samples of the last :attr:`keep` seconds.
A lookup also says whether the pose is *settled*: every time-varying transform on the chain
has a sample at or after the scan's stamp, so the pose is interpolated rather than held
from the last sample (a live source waits a little for that, see
:class:`~laserpeople.live.source.LiveScans`).
"""

from __future__ import annotations

import itertools
import threading
from collections import deque
from collections.abc import Iterable, Mapping

import numpy as np

from laserpeople.io.poses import (
    PoseParams,
    TransformTree,
    add_mounts,
    mounts_to_use,
    normalise_frame,
)
from laserpeople.live.messages import TransformSample
from laserpeople.scan import Pose2D


class LiveTransforms:
    """Thread-safe store of the transforms seen so far (see the module notes).

    Args:
        world_frame: The world frame; None picks it as ``track`` does (``map``, else
            ``odom``, else the lasers' common root) at the first lookup after a transform
            of the robot's arrived (not from the given mounts alone).
        mounts: Fixed laser mounts (child -> (parent, pose)), as ``--mount`` gives them.
        params: Interpolation tolerance and largest gap (as for bags).
        keep: Seconds of samples kept per time-varying transform [s].
    """

    def __init__(
        self,
        world_frame: str | None = None,
        mounts: Mapping[str, tuple[str, Pose2D]] | None = None,
        params: PoseParams | None = None,
        keep: float = 30.0,
    ) -> None:
        self.params = params or PoseParams()
        self.requested_world = normalise_frame(world_frame) if world_frame else None
        self.world_frame = self.requested_world
        self.mounts = dict(mounts or {})
        self.keep = keep
        self._lock = threading.Lock()
        self._static: dict[tuple[str, str], tuple[Pose2D, float, str]] = {}
        self._series: dict[tuple[str, str], deque[tuple[float, float, float, float]]] = {}
        self._tilt: dict[tuple[str, str], float] = {}
        self._source: dict[tuple[str, str], str] = {}
        self._tree: TransformTree | None = None
        self.samples = 0
        self.mount_notes: list[str] = []
        """Given mounts left out at the last lookup, as ``track`` leaves them out of a
        recording (see :func:`~laserpeople.io.poses.mounts_to_use`)."""

    def add(self, samples: Iterable[TransformSample], *, static: bool, source: str) -> None:
        """Add transform samples (``static``: from ``/tf_static``, kept for ever)."""
        with self._lock:
            for s in samples:
                key = (s.parent, s.child)
                self.samples += 1
                self._tilt[key] = max(self._tilt.get(key, 0.0), s.tilt)
                self._source.setdefault(key, source)
                if static:
                    self._static[key] = (s.pose, s.tilt, source)
                    continue
                rows = self._series.setdefault(key, deque())
                rows.append((s.stamp, s.pose.x, s.pose.y, s.pose.theta))
                while rows and rows[0][0] < s.stamp - self.keep:
                    rows.popleft()
            self._tree = None

    def reset(self) -> None:
        """Forget the time-varying transforms (after a time jump); static ones stay."""
        with self._lock:
            self._series.clear()
            self._tree = None

    def _build(self) -> TransformTree:
        tree = TransformTree(self.params)
        received = [(p, c, src) for (p, c), (_, _, src) in self._static.items()]
        received += [(p, c, self._source[(p, c)]) for (p, c), rows in self._series.items() if rows]
        mounts, self.mount_notes = mounts_to_use(self.mounts, received)
        add_mounts(tree, mounts)
        for (parent, child), (pose, tilt, source) in self._static.items():
            tree.add_static(parent, child, pose, tilt=tilt, source=source)
        for (parent, child), rows in self._series.items():
            if rows:
                arr = np.asarray(rows, dtype=np.float64)
                tree.add_track(
                    parent,
                    child,
                    arr[:, 0],
                    arr[:, 1:],
                    tilt=self._tilt[(parent, child)],
                    source=self._source[(parent, child)],
                )
        return tree

    def lookup(self, frame_id: str, stamp: float) -> tuple[Pose2D | None, str, bool]:
        """Pose of the laser frame ``frame_id`` in the world frame at ``stamp`` [s], the
        reason when there is none, and whether it is settled (see the module notes)."""
        with self._lock:
            if self._tree is None:
                self._tree = self._build()
            tree = self._tree
            if self.world_frame is None and (
                self._series or any(w in tree.frames() for w in self.params.world_frames)
            ):
                # not from the mounts alone: the robot's own transforms may not have come yet
                self.world_frame = tree.pick_world([frame_id])
            world = self.world_frame
            if world is None:
                if not self._series and not self._static:
                    return None, "no transforms received yet (/tf, /tf_static, odometry)", False
                return None, "no world frame: laser frame not connected to map or odom", False
            pose, reason = tree.lookup(world, frame_id, stamp)
            path = tree.chain(world, frame_id) or []
            settled = all(
                self._settled(parent, child, stamp) for child, parent in itertools.pairwise(path)
            )
            return pose, reason, settled

    def _settled(self, parent: str, child: str, stamp: float) -> bool:
        rows = self._series.get((parent, child))
        return rows is None or (bool(rows) and rows[-1][0] >= stamp)

    @property
    def has_any(self) -> bool:
        """Whether any transform or mount is known."""
        return bool(self._static or self._series or self.mounts)


__all__ = ["LiveTransforms"]
