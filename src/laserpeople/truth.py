"""Ground truth: per-beam labels of a scan and the true state of every person per frame.

Ids are non-negative integers; ``-1`` means "none" (a background beam, a person
that is in no group, ...). Positions are in the world frame [m], velocities in
[m/s], hues in degrees [0, 360).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from laserpeople.errors import ScanFormatError

if TYPE_CHECKING:
    from laserpeople.scan import CoordinateFrame

NONE_ID = -1
"""The id that stands for "no person / no leg / no group / no object"."""


@dataclass(frozen=True, eq=False)
class BeamLabels:
    """What each beam of one scan hit (all arrays (N,), int32, ``-1`` = nothing of that kind).

    Attributes:
        person: Id of the person whose leg, torso or accessory the beam hit.
        leg: 0 or 1 for the person's left/right leg, -1 for torso, accessory or no person.
        group: Id of the group of that person (-1 if the person walks alone or no person).
        obj: Id of the static or moving non-person object the beam hit (-1 for walls/people).
    """

    person: NDArray[np.int32]
    leg: NDArray[np.int32]
    group: NDArray[np.int32]
    obj: NDArray[np.int32]

    def __post_init__(self) -> None:
        arrays = [
            np.asarray(getattr(self, k), dtype=np.int32) for k in ("person", "leg", "group", "obj")
        ]
        n = arrays[0].shape
        if any(a.ndim != 1 or a.shape != n for a in arrays):
            raise ScanFormatError("beam label arrays must all be one-dimensional and equally long")
        for key, arr in zip(("person", "leg", "group", "obj"), arrays, strict=True):
            object.__setattr__(self, key, arr)

    def __len__(self) -> int:
        return int(self.person.size)

    @classmethod
    def background(cls, n_beams: int) -> BeamLabels:
        """Labels for a scan in which every beam hit the background."""
        none = np.full(n_beams, NONE_ID, dtype=np.int32)
        return cls(none, none.copy(), none.copy(), none.copy())

    @property
    def is_leg(self) -> NDArray[np.bool_]:
        """Mask (N,) of beams that hit a person's leg."""
        return (self.person >= 0) & (self.leg >= 0)


@dataclass(frozen=True, eq=False)
class TruthFrame:
    """The true state of all people at one instant.

    Attributes:
        stamp: Time [s].
        scan_index: Index of the scan (on the recording's first sensor) this frame belongs to.
        person_ids: Ids (P,) of the people present.
        positions: Body centres (P, 2) [m], world frame (midpoint between the hips).
        velocities: Velocities (P, 2) [m/s].
        group_ids: Group (P,) of each person; -1 for a person that walks alone.
        leg_positions: Leg centres (P, 2, 2) [m]: person, leg (0 left, 1 right), xy.
        hues: Clothing hue (P,) [degrees, 0-360), the appearance signature for re-identification.
        frame: The frame of ``positions`` when the source states it (a simulated recording:
            ``world``; a truth CSV with a ``frame`` column); None when it does not.
    """

    stamp: float
    scan_index: int
    person_ids: NDArray[np.int64]
    positions: NDArray[np.float64]
    velocities: NDArray[np.float64]
    group_ids: NDArray[np.int64]
    leg_positions: NDArray[np.float64]
    hues: NDArray[np.float64]
    frame: CoordinateFrame | None = None

    def __post_init__(self) -> None:
        ids = np.asarray(self.person_ids, dtype=np.int64).reshape(-1)
        p = ids.size
        shapes = {
            "positions": (p, 2),
            "velocities": (p, 2),
            "group_ids": (p,),
            "leg_positions": (p, 2, 2),
            "hues": (p,),
        }
        object.__setattr__(self, "person_ids", ids)
        for key, shape in shapes.items():
            dtype = np.int64 if key == "group_ids" else np.float64
            arr = np.asarray(getattr(self, key), dtype=dtype).reshape(shape)
            object.__setattr__(self, key, arr)

    def __len__(self) -> int:
        return int(self.person_ids.size)

    @classmethod
    def from_positions(
        cls,
        stamp: float,
        scan_index: int,
        person_ids: NDArray[np.int64],
        positions: NDArray[np.float64],
        frame: CoordinateFrame | None = None,
    ) -> TruthFrame:
        """A frame that knows only positions (e.g. a sparse CSV annotation) in ``frame``
        (None: not stated)."""
        ids = np.asarray(person_ids, dtype=np.int64).reshape(-1)
        pos = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
        p = ids.size
        return cls(
            stamp=stamp,
            scan_index=scan_index,
            person_ids=ids,
            positions=pos,
            velocities=np.full((p, 2), np.nan),
            group_ids=np.full(p, NONE_ID, dtype=np.int64),
            leg_positions=np.full((p, 2, 2), np.nan),
            hues=np.full(p, np.nan),
            frame=frame,
        )

    def groups(self) -> dict[int, NDArray[np.int64]]:
        """Group id -> person ids; every person walking alone forms a group of one with a
        negative key ``-(person_id + 1)``."""
        out: dict[int, NDArray[np.int64]] = {}
        for gid in np.unique(self.group_ids[self.group_ids >= 0]):
            out[int(gid)] = self.person_ids[self.group_ids == gid]
        for pid in self.person_ids[self.group_ids < 0]:
            out[-int(pid) - 1] = np.array([pid], dtype=np.int64)
        return out
