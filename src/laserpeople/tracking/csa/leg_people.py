"""The leg MHT's people as the CSA's births and detections on a moving laser.

002's Cluster Sorting Algorithm is a data association scheme (Kalman while people are apart,
Viterbi while they are close); it prescribes neither its detector nor how targets start
and stop. On a moving laser with poses the CSA's foreground is the points near leg
detections (``pipeline/leg_foreground.py``), which flicker, and a target started from
unselected points may stand on furniture the occupancy grid has not learned yet, so it is
reported only once it walked (``[csa] moving_travel``). The shipped people tracker (the leg
MHT of 000 with the people layer ``tracks`` and the people's static world model) starts a
person only from two legs, or one leg that walks, on a place not static for long.

:class:`LegPeople` runs that tracker on the frame's leg detections and tells the CSA
(``[csa] moving_people``) where its people and their legs are: on a moving laser the CSA
starts its targets where a person of it is that no object of the CSA holds (instead of
from unselected points), and a leg of such a person without a foreground point within
:data:`LEG_POINT_GAP` is one more measurement point (the leg the detector missed in this
scan but the MHT still tracks).

While the laser has not moved, none of that is used, so the frames are only held (the last
:data:`HOLD_SECONDS` of them) and the leg MHT runs over them when the laser first moves: its
people are confirmed at that moment as if it had run all along, at no cost per frame on a
laser that never moves.
"""

from __future__ import annotations

from collections import deque
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.background import StaticWorldModel
from laserpeople.frame import Frame

FloatArray = NDArray[np.float64]

BIRTH_GAP = 0.75
"""A person of the leg MHT starts a CSA target when no object of the CSA (a single target's
mean, an estimate of a cluster) lies within this distance [m] of it: the CLEAR MOT gate, so
one person seldom gets two rows. Measured on the moving tuning seeds (docs/csa.md): person
MOTA / ID switches per scene 0.284 / 35.8 at 0.75 m, 0.283 / 59.4 at 0.5 m (a second target
beside a person), 0.254 / 25.9 at 1.0 m (people beside a target never start one)."""

LEG_POINT_GAP = 0.2
"""A leg of a person of the leg MHT becomes a measurement point when no foreground point lies
within this distance [m] of it: a leg's own returns lie within about 0.1 m of its centre.
Measured on the moving tuning seeds (docs/csa.md): person MOTA / IDF1 0.284 / 0.383 at
0.2 m, 0.281 / 0.370 at 0.1 m, 0.282 / 0.381 at 0.3 m."""


HOLD_SECONDS = 2.0
"""While the laser has not moved, the frames of this many seconds [s] before the current one
are held (:meth:`LegPeople.hold`) and tracked when it first moves: the leg MHT confirms a
person seen with both legs in its fourth frame (0.3 s at 10 Hz), so 2 s give it every
person in view then (not one it would still coast on, unseen for 2-4 s, ``max_coast``).
On the real recordings (the lobby, whose robot moves from frame 10; the MiR front laser
and the corridor, which never move) and the moving random-groups seeds the CSA's tracks
are the same as with the leg MHT run on every frame (docs/csa.md, "The leg MHT's people
as births and detections")."""


class LegPeople:
    """The shipped leg MHT with its people layer, run on each frame's leg detections once
    the laser has moved (before, the frames are only held, see :meth:`hold`).

    Attributes:
        people: Positions (P, 2) [m] of its person tracks after the last frame.
        legs: Positions (L, 2) [m] of the leg tracks of those people after the last frame.
    """

    def __init__(self, hold_seconds: float = HOLD_SECONDS) -> None:
        from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams
        from laserpeople.tracking.registry import LegMHTAdapter

        self._tracker = LegMHTAdapter(LegMHTTracker(LegTrackerParams()))
        self.people: FloatArray = np.empty((0, 2))
        self.legs: FloatArray = np.empty((0, 2))
        self.hold_seconds = hold_seconds
        self._held: deque[Frame] = deque()
        self._watching = False

    def hold(self, frame: Frame) -> None:
        """Keep ``frame`` (which must hold legs) for the next :meth:`update` instead of
        tracking it now, and drop the held frames more than ``hold_seconds`` [s] older than
        it. The leg MHT's people layer measures the robot's motion from the first frame
        held, as if it had tracked every frame."""
        if not self._watching:
            self._tracker.watch_from(frame.sensor_pose)
            self._watching = True
        self._held.append(frame)
        while frame.stamp - self._held[0].stamp > self.hold_seconds:
            self._held.popleft()

    def use_static_model(self, model: StaticWorldModel | None) -> None:
        """Let the people layer ask ``model`` how long a place has been static (the pipeline
        feeds the model each frame; None: no model, every place 0 s static)."""
        self._tracker.use_static_model(model)

    def update(self, frame: Frame) -> None:
        """Track the legs of the held frames, then of ``frame`` (which must hold some)."""
        self._watching = True
        while self._held:
            self._tracker.update(self._held.popleft())
        tracks: Any = self._tracker.update(frame)
        persons = tracks.of_kind("person")
        members = {m for t in persons for m in t.members}
        self.people = np.array([t.position for t in persons], dtype=np.float64).reshape(-1, 2)
        self.legs = np.array(
            [t.position for t in tracks.of_kind("leg") if t.track_id in members],
            dtype=np.float64,
        ).reshape(-1, 2)


def missed_legs(points: FloatArray, legs: FloatArray, gap: float = LEG_POINT_GAP) -> FloatArray:
    """The ``legs`` (L, 2) [m] without one of ``points`` (N, 2) [m] within ``gap`` [m]
    (inclusive: a point exactly ``gap`` away holds the leg)."""
    legs = np.asarray(legs, dtype=np.float64).reshape(-1, 2)
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if len(legs) == 0 or len(pts) == 0:
        return legs
    d = np.linalg.norm(legs[:, None, :] - pts[None, :, :], axis=2).min(axis=1)
    return legs[d > gap]


def unheld_people(people: FloatArray, objects: FloatArray, gap: float = BIRTH_GAP) -> FloatArray:
    """The ``people`` (P, 2) [m] farther than ``gap`` [m] from every one of ``objects``
    (M, 2) [m] and from every person before them in the list (so two people of the MHT
    closer than ``gap`` start one target)."""
    out: list[FloatArray] = []
    held = np.asarray(objects, dtype=np.float64).reshape(-1, 2)
    for xy in np.asarray(people, dtype=np.float64).reshape(-1, 2):
        if len(held) and float(np.linalg.norm(held - xy, axis=1).min()) <= gap:
            continue
        out.append(xy)
        held = np.vstack([held, xy])
    return np.array(out, dtype=np.float64).reshape(-1, 2)


__all__ = [
    "BIRTH_GAP",
    "HOLD_SECONDS",
    "LEG_POINT_GAP",
    "LegPeople",
    "missed_legs",
    "unheld_people",
]
