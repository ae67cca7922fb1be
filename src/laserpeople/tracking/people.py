"""People from pairs of leg tracks (000 Sec. 3.3).

The model: a person has two legs (1), which are close (2: distance below theta_d) and move
in a similar direction (3: the orientation agreement S = sum_t <theta_i^t, theta_j^t> over
a sliding window of the last L steps exceeds theta_a). The orientation theta_i^t of a leg is
taken as a unit vector, so <.,.> is the cosine of the angle between two legs' directions.
Deviation from 000: 000 uses the direction of the leg track's velocity; a leg in stance has
a velocity estimate near zero pointing anywhere (and a constant-velocity filter overshoots
backwards when the foot lands), so here the direction is that of the leg's displacement over
the last ``orientation_span`` seconds (about two steps), in which both legs of a walking
person advance along the walking direction. A person's state is the covariance-weighted
(multivariate) mean of its two leg states. A person is deleted when one of its legs is no
longer tracked or when the legs are farther apart than theta_d for L consecutive steps;
while its legs are tracked (including as occluded) the person keeps its id.
"""

from __future__ import annotations

import itertools
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.tracks import Track

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class PersonParams:
    """Person-from-legs model (000 Sec. 3.3)."""

    config_section = "person"

    max_leg_distance: float = param(
        0.75, "000 Sec. 3.3 (theta_d)", "legs closer than this form a person candidate", "m"
    )
    window: int = param(
        10,
        "assumption (000 Sec. 3.3 names the sliding window L without a value)",
        "L: steps of the orientation window and of the far-apart deletion rule",
        "scans",
    )
    min_agreement: float = param(
        3.0,
        "assumption, tuned on the simulated 000 Sec. 3.4 scenes (000 Sec. 3.3: theta_a "
        "determined experimentally, value not given)",
        "theta_a: orientation agreement S (sum of cosines over the window) to validate",
    )
    orientation_span: float = param(
        2.0,
        "assumption: about two steps, so both legs have moved even when turning round the "
        "stance leg (000 Sec. 3.4.2)",
        "time over which a leg's displacement gives its orientation",
        "s",
    )
    min_orientation_age: float = param(
        0.2,
        "assumption, tuned on the simulated turn-on-stance-leg scene (000 Sec. 3.4.2)",
        "a leg track younger than this has no orientation yet",
        "s",
    )
    min_speed: float = param(
        0.1,
        "assumption",
        "a leg whose mean speed over orientation_span is lower has no orientation (adds 0)",
        "m/s",
    )

    def __post_init__(self) -> None:
        if self.max_leg_distance <= 0 or self.window < 1:
            raise ValueError("max_leg_distance must be positive and window at least 1")
        if not self.min_agreement < self.window:
            raise ValueError("min_agreement must be below window (S is a sum of window cosines)")


@dataclass(frozen=True, eq=False)
class LegState:
    """A leg track as the person layer sees it.

    Attributes:
        track_id: Leg id.
        mean: State (4,) (x, y, vx, vy).
        cov: Covariance (4, 4).
        score: Tracker confidence in [0, 1].
    """

    track_id: int
    mean: FloatArray
    cov: FloatArray
    score: float = 1.0


@dataclass(eq=False)
class _Person:
    person_id: int
    legs: tuple[int, int]
    far_steps: int = 0


@dataclass(eq=False)
class _History:
    """Orientation per step (window L) and positions with stamps (orientation span)."""

    steps: deque[tuple[int, FloatArray | None]] = field(default_factory=deque)
    positions: deque[tuple[float, FloatArray]] = field(default_factory=deque)


def fuse_legs(a: LegState, b: LegState) -> tuple[FloatArray, FloatArray]:
    """Covariance-weighted mean of two leg states: P = (P_a^-1 + P_b^-1)^-1,
    x = P (P_a^-1 x_a + P_b^-1 x_b) (000 Sec. 3.3, point 1)."""
    ia = np.linalg.inv(a.cov)
    ib = np.linalg.inv(b.cov)
    cov = np.linalg.inv(ia + ib)
    mean = cov @ (ia @ a.mean + ib @ b.mean)
    return mean, 0.5 * (cov + cov.T)


class PersonFuser:
    """Keeps person tracks over time from the leg tracks of each step."""

    def __init__(self, params: PersonParams) -> None:
        self.params = params
        self._ids = itertools.count()
        self._persons: dict[int, _Person] = {}
        self._history: dict[int, _History] = {}
        self._step = 0
        self.persons_created = 0

    @property
    def approved_legs(self) -> frozenset[int]:
        """Leg ids associated with a validated person (000 Sec. 3.3.1: *approved*)."""
        return frozenset(leg for p in self._persons.values() for leg in p.legs)

    def _orientation(self, hist: _History, stamp: float, position: FloatArray) -> FloatArray | None:
        """Unit direction of the displacement over the last ``orientation_span`` seconds
        (since the track's start when it is younger, but at least ``min_orientation_age``);
        None when the leg moved slower than ``min_speed`` on average."""
        p = self.params
        hist.positions.append((stamp, position))
        while len(hist.positions) > 1 and hist.positions[1][0] <= stamp - p.orientation_span:
            hist.positions.popleft()
        t0, p0 = hist.positions[0]
        elapsed = stamp - t0
        if elapsed < p.min_orientation_age or elapsed <= 0:
            return None
        d = position - p0
        dist = float(np.hypot(d[0], d[1]))
        return d / dist if dist >= p.min_speed * elapsed else None

    def agreement(self, a: int, b: int) -> float:
        """S of legs ``a`` and ``b`` over the window: the sum of cosines of their orientation
        differences at the steps both were tracked and moving."""
        ha, hb = self._history.get(a), self._history.get(b)
        if ha is None or hb is None:
            return 0.0
        ob = dict(hb.steps)
        total = 0.0
        for step, ua in ha.steps:
            ub = ob.get(step)
            if ua is not None and ub is not None:
                total += float(ua @ ub)
        return total

    def update(self, legs: Mapping[int, LegState], stamp: float) -> list[Track]:
        """Advance one step (time ``stamp`` [s]) with the current leg tracks; returns the
        person tracks."""
        p = self.params
        self._step += 1
        for leg_id, leg in legs.items():
            hist = self._history.setdefault(leg_id, _History())
            hist.steps.append((self._step, self._orientation(hist, stamp, leg.mean[:2].copy())))
            while hist.steps and hist.steps[0][0] <= self._step - p.window:
                hist.steps.popleft()
        for leg_id in [k for k in self._history if k not in legs]:
            del self._history[leg_id]

        # existing persons: deletion rules
        for pid in list(self._persons):
            person = self._persons[pid]
            a, b = person.legs
            if a not in legs or b not in legs:
                del self._persons[pid]
                continue
            d = float(np.hypot(*(legs[a].mean[:2] - legs[b].mean[:2])))
            person.far_steps = person.far_steps + 1 if d > p.max_leg_distance else 0
            if person.far_steps >= p.window:
                del self._persons[pid]

        # new persons from free legs: near, and the pairs that agree best first
        used = {leg for person in self._persons.values() for leg in person.legs}
        free = sorted(k for k in legs if k not in used)
        candidates: list[tuple[float, int, int]] = []
        if len(free) >= 2:
            pos = np.stack([legs[k].mean[:2] for k in free])
            dist = np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=2)
            for i, j in zip(*np.nonzero(np.triu(dist < p.max_leg_distance, k=1)), strict=True):
                s = self.agreement(free[i], free[j])
                if s > p.min_agreement:
                    candidates.append((s, free[i], free[j]))
        candidates.sort(key=lambda c: -c[0])
        for _, a, b in candidates:
            if a in used or b in used:
                continue
            pid = next(self._ids)
            self.persons_created += 1
            self._persons[pid] = _Person(pid, (a, b))
            used.update((a, b))

        out: list[Track] = []
        for pid in sorted(self._persons):
            a, b = self._persons[pid].legs
            mean, cov = fuse_legs(legs[a], legs[b])
            out.append(
                Track(
                    track_id=pid,
                    kind="person",
                    position=mean[:2],
                    velocity=mean[2:4],
                    covariance=cov[:2, :2],
                    score=min(legs[a].score, legs[b].score),
                    members=(a, b),
                )
            )
        return out
