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

Extensions of 000 (each can be switched off in :class:`PersonParams`):

- Relinking (``relink_time``, ``relink_distance``): a newly validated pair near where a
  recently deleted person would now be continues that person's id instead of a new one.
- Legs very far apart (``max_leg_separation``): a person is not reported while its legs
  are implausibly far apart (an estimate has coasted away while occluded); it keeps its id.

- Standing people (``validate_still``): the orientation of a standing leg is undefined, so
  000's rule never validates a person who stands still; two close legs that have both stood
  still for ``still_time`` are validated too. Two leg-like static objects closer than
  theta_d (chair legs) then also make a person unless the detector rejects them.
- Side-by-side walkers (``max_spread``): the feet of two people walking side by side are
  close and move alike, so 000's rule can pair legs of different people, putting the person
  between them. Pairs are formed narrowest first (distance across the walking direction,
  plus the mean distance over the recent past), pairs wider than ``max_spread`` are not
  formed, and a person wider than ``max_spread`` on average over the window is dissolved
  when another leg nearby would pair narrower with one of its legs.
"""

from __future__ import annotations

import itertools
from collections import deque
from collections.abc import Mapping, Sequence
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

    max_leg_separation: float = param(
        2.0,
        "departure from 000 Sec. 3.3 (inf; --preset paper), an assumption: 000 keeps a "
        "person whose legs are apart "
        "for L steps at any distance, at their weighted mean; on the real "
        "demo_stationary_simple_environment.bag two legs coasting apart while occluded made "
        "persons jump up to 4 m between scans. Hiding them: max jump 4.0 -> 1.6 m there, "
        "demo seeds 0-4 MOTA -0.003 on two seeds (1.5 m: -0.007 on average; deleting such "
        "persons instead: up to -0.05)",
        "a person whose legs are farther apart than this is not reported (it keeps its id "
        "and reappears when they come together; inf: 000's rule only)",
        "m",
    )

    relink_time: float = param(
        1.0,
        "departure from 000 Sec. 3.3 (0; --preset paper), an assumption: 000 gives every "
        "newly validated pair a new "
        "id, so a walker whose leg track was lost for a moment returns as someone else. With "
        "1 s / 0.8 m, demo seeds 0-4: ID switches 24 -> 12, mean IDF1 .700 -> .794, MOTA "
        "+0.002..+0.007; entrance-hall seed 1: 36 -> 28 switches; real demo bag: 37 -> 33 ids. "
        "0.5/1/2 s gave the same on the demo seeds",
        "a new person near where a person lost at most this long ago would now be takes "
        "that person's id (0: never)",
        "s",
    )
    relink_distance: float = param(
        0.8,
        "extension (assumption, chosen from 0.5/0.8/1.0/1.3 m on demo seeds 0-2, checked on "
        "seeds 3-4 and on entrance-hall: 1.3 m relinked more but lowered IDF1 in the crowd)",
        "largest distance between a new person and the position a lost person would have "
        "reached at its last velocity (capped at max_relink_speed)",
        "m",
    )
    max_relink_speed: float = param(
        1.5,
        "assumption: brisk walking",
        "speed cap when extrapolating a lost person for relinking",
        "m/s",
    )

    validate_still: bool = param(
        True,
        "departure from 000 Sec. 3.3 (false; --preset paper): the paper validates moving legs "
        "only; the orientation agreement of standing legs is undefined",
        "also validate two close legs that have both stood still for still_time",
    )
    still_time: float = param(
        1.0,
        "assumption: longer than a stance phase (~0.6 s), so walking legs never qualify",
        "how long both legs must have stood still to be validated as a standing person",
        "s",
    )
    still_radius: float = param(
        0.08,
        "assumption: detector noise of a leg centre (~0.03 m) plus some sway",
        "a leg stands still when all its positions over still_time lie this close to the "
        "current one",
        "m",
    )
    max_spread: float = param(
        0.55,
        "departure from 000 Sec. 3.3 (inf, or any value of at least theta_d; --preset paper), "
        "an assumption: the feet of one walker are ~0.2 m apart "
        "across the walking direction, those of two people side by side ~0.5-0.6 m; chosen "
        "from 0.4/0.55/none on the simulated demo and figure-eight scenes, seeds 0-1",
        "a person whose legs are farther apart than this across their walking direction "
        "(plain distance when standing), on average over the window, is dissolved when "
        "another leg nearby would pair narrower with one of them; candidate pairs wider "
        "than this are not formed, the narrowest pairs are formed first (inf: no limit)",
        "m",
    )
    dissolve_wide: bool = param(
        True,
        "departure from 000 Sec. 3.3 (false; --preset paper; see max_spread)",
        "dissolve persons whose legs are wider apart than max_spread (else only new pairs "
        "are checked)",
    )
    position: str = param(
        "weighted",
        "000 Sec. 3.3 (weighted); midpoint is an alternative for comparison",
        "person position: weighted (covariance-weighted mean of the legs) or midpoint",
    )

    def __post_init__(self) -> None:
        if self.position not in ("weighted", "midpoint"):
            raise ValueError("position must be 'weighted' or 'midpoint'")
        if not (self.still_time > 0 and self.still_radius > 0 and self.max_spread > 0):
            raise ValueError("still_time and still_radius must be positive")
        if self.relink_time < 0 or self.relink_distance <= 0 or self.max_relink_speed < 0:
            raise ValueError(
                "relink_time and max_relink_speed must be >= 0, relink_distance positive"
            )
        if not self.max_leg_separation >= self.max_leg_distance:
            raise ValueError("max_leg_separation must be at least max_leg_distance")
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
    spreads: deque[float] = field(default_factory=deque)
    state: FloatArray | None = None  # last (x, y, vx, vy) reported
    stamp: float = 0.0  # time [s] of that state


@dataclass(frozen=True, eq=False)
class _Lost:
    """A deleted person that a new pair may continue (extension ``relink_time``)."""

    person_id: int
    state: FloatArray
    stamp: float


@dataclass(eq=False)
class _History:
    """Per leg: orientation per step (window L), positions with stamps (the longer of the
    orientation span and still_time), and the pair distances are kept per person pair."""

    steps: deque[tuple[int, FloatArray | None]] = field(default_factory=deque)
    positions: deque[tuple[float, FloatArray]] = field(default_factory=deque)
    first_stamp: float = 0.0


def fuse_legs(a: LegState, b: LegState) -> tuple[FloatArray, FloatArray]:
    """Covariance-weighted mean of two leg states: P = (P_a^-1 + P_b^-1)^-1,
    x = P (P_a^-1 x_a + P_b^-1 x_b) (000 Sec. 3.3, point 1)."""
    # the same with one solve: P = P_a S^-1 P_b, x = P_b S^-1 x_a + P_a S^-1 x_b, S = P_a + P_b
    sol = np.linalg.solve(a.cov + b.cov, np.column_stack([a.mean, b.mean, b.cov]))
    mean = b.cov @ sol[:, 0] + a.cov @ sol[:, 1]
    cov = a.cov @ sol[:, 2:]
    return mean, 0.5 * (cov + cov.T)


def fuse_legs_batch(pairs: Sequence[tuple[LegState, LegState]]) -> tuple[FloatArray, FloatArray]:
    """:func:`fuse_legs` of every pair at once: means (K, 4), covariances (K, 4, 4)."""
    if not pairs:
        return np.empty((0, 4)), np.empty((0, 4, 4))
    ma = np.stack([a.mean for a, _ in pairs])
    mb = np.stack([b.mean for _, b in pairs])
    pa = np.stack([a.cov for a, _ in pairs])
    pb = np.stack([b.cov for _, b in pairs])
    rhs = np.concatenate([ma[:, :, None], mb[:, :, None], pb], axis=2)
    sol = np.linalg.solve(pa + pb, rhs)
    means = np.einsum("kij,kj->ki", pb, sol[:, :, 0]) + np.einsum("kij,kj->ki", pa, sol[:, :, 1])
    covs = pa @ sol[:, :, 2:]
    return means, 0.5 * (covs + covs.transpose(0, 2, 1))


def midpoint_legs_batch(
    pairs: Sequence[tuple[LegState, LegState]],
) -> tuple[FloatArray, FloatArray]:
    """:func:`midpoint_legs` of every pair at once: means (K, 4), covariances (K, 4, 4)."""
    if not pairs:
        return np.empty((0, 4)), np.empty((0, 4, 4))
    fused = [midpoint_legs(a, b) for a, b in pairs]
    return np.stack([f[0] for f in fused]), np.stack([f[1] for f in fused])


def leg_spread(a: LegState, b: LegState, min_speed: float) -> float:
    """Distance [m] between legs ``a`` and ``b`` across their mean walking direction (their
    mean velocity), or the plain distance when they move slower than ``min_speed`` [m/s]."""
    d = a.mean[:2] - b.mean[:2]
    v = 0.5 * (a.mean[2:4] + b.mean[2:4])
    speed = float(np.hypot(v[0], v[1]))
    if speed < min_speed:
        return float(np.hypot(d[0], d[1]))
    return abs(float(v[0] * d[1] - v[1] * d[0])) / speed


def midpoint_legs(a: LegState, b: LegState) -> tuple[FloatArray, FloatArray]:
    """Unweighted mean of two leg states, covariance (P_a + P_b) / 4."""
    return 0.5 * (a.mean + b.mean), 0.25 * (a.cov + b.cov)


class PersonFuser:
    """Keeps person tracks over time from the leg tracks of each step."""

    def __init__(self, params: PersonParams) -> None:
        self.params = params
        self._ids = itertools.count()
        self._persons: dict[int, _Person] = {}
        self._lost: list[_Lost] = []
        self._history: dict[int, _History] = {}
        self._step = 0
        self.persons_created = 0
        self._keep = max(params.orientation_span, params.still_time)

    @property
    def approved_legs(self) -> frozenset[int]:
        """Leg ids associated with a validated person (000 Sec. 3.3.1: *approved*)."""
        return frozenset(leg for p in self._persons.values() for leg in p.legs)

    def _record(self, hist: _History, stamp: float, position: FloatArray) -> None:
        hist.positions.append((stamp, position))
        while len(hist.positions) > 1 and hist.positions[1][0] <= stamp - self._keep:
            hist.positions.popleft()

    def _orientation(self, hist: _History, stamp: float) -> FloatArray | None:
        """Unit direction of the displacement over the last ``orientation_span`` seconds
        (since the track's start when it is younger, but at least ``min_orientation_age``);
        None when the leg moved slower than ``min_speed`` on average."""
        p = self.params
        position = hist.positions[-1][1]
        t0, p0 = hist.positions[0]
        for t, q in hist.positions:
            if t > stamp - p.orientation_span:
                break
            t0, p0 = t, q
        elapsed = stamp - t0
        if elapsed < p.min_orientation_age or elapsed <= 0:
            return None
        d = position - p0
        dist = float(np.hypot(d[0], d[1]))
        return d / dist if dist >= p.min_speed * elapsed else None

    def is_still(self, leg: int, stamp: float) -> bool:
        """Leg ``leg`` has been tracked for ``still_time`` and all its positions over that
        time lie within ``still_radius`` of the current one (extension, see PersonParams)."""
        hist = self._history.get(leg)
        p = self.params
        if hist is None or stamp - hist.first_stamp < p.still_time - 1e-9:
            return False
        pts = np.stack([q for t, q in hist.positions if t >= stamp - p.still_time - 1e-9])
        d2 = np.sum((pts - pts[-1]) ** 2, axis=1)
        return bool(d2.max() <= p.still_radius**2)

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

    def mean_distance(self, a: int, b: int) -> float:
        """Mean distance [m] of legs ``a`` and ``b`` over the positions both have (within
        the kept history), used to pair the closest legs first."""
        ha, hb = self._history.get(a), self._history.get(b)
        if ha is None or hb is None:
            return float("inf")
        pb = dict(hb.positions)
        d = [float(np.hypot(*(q - pb[t]))) for t, q in ha.positions if t in pb]
        return float(np.mean(d)) if d else float("inf")

    def _has_narrower_partner(self, pair: tuple[int, int], legs: Mapping[int, LegState]) -> bool:
        """Some other leg is within theta_d of a leg of ``pair`` and would make a pair
        narrower than max_spread with it (so dissolving ``pair`` lets them re-pair)."""
        p = self.params
        for a in pair:
            la = legs[a]
            for c, lc in legs.items():
                if c in pair:
                    continue
                d = float(np.hypot(*(la.mean[:2] - lc.mean[:2])))
                if d < p.max_leg_distance and leg_spread(la, lc, p.min_speed) <= p.max_spread:
                    return True
        return False

    def _lose(self, pid: int) -> None:
        """Delete person ``pid``, remembering where it was for relinking."""
        person = self._persons.pop(pid)
        if person.state is not None and self.params.relink_time > 0:
            self._lost.append(_Lost(pid, person.state, person.stamp))

    def _relinked_id(self, position: FloatArray, stamp: float) -> int | None:
        """The id of the lost person whose extrapolated position is nearest to ``position``
        (within ``relink_distance``), which is then no longer lost; None if there is none."""
        p = self.params
        best, best_d = None, p.relink_distance
        for lost in self._lost:
            v = lost.state[2:4]
            speed = float(np.hypot(v[0], v[1]))
            if speed > p.max_relink_speed:
                v = v * (p.max_relink_speed / speed)
            predicted = lost.state[:2] + v * (stamp - lost.stamp)
            d = float(np.hypot(*(position[:2] - predicted)))
            if d <= best_d:
                best, best_d = lost, d
        if best is None:
            return None
        self._lost.remove(best)
        return best.person_id

    def update(self, legs: Mapping[int, LegState], stamp: float) -> list[Track]:
        """Advance one step (time ``stamp`` [s]) with the current leg tracks; returns the
        person tracks."""
        p = self.params
        self._step += 1
        for leg_id, leg in legs.items():
            hist = self._history.get(leg_id)
            if hist is None:
                hist = self._history[leg_id] = _History(first_stamp=stamp)
            self._record(hist, stamp, leg.mean[:2].copy())
            hist.steps.append((self._step, self._orientation(hist, stamp)))
            while hist.steps and hist.steps[0][0] <= self._step - p.window:
                hist.steps.popleft()
        for leg_id in [k for k in self._history if k not in legs]:
            del self._history[leg_id]

        # existing persons: deletion rules
        for pid in list(self._persons):
            person = self._persons[pid]
            a, b = person.legs
            if a not in legs or b not in legs:
                self._lose(pid)
                continue
            d = float(np.hypot(*(legs[a].mean[:2] - legs[b].mean[:2])))
            person.far_steps = person.far_steps + 1 if d > p.max_leg_distance else 0
            person.spreads.append(leg_spread(legs[a], legs[b], p.min_speed))
            if len(person.spreads) > p.window:
                person.spreads.popleft()
            wide = (
                p.dissolve_wide
                and len(person.spreads) == p.window
                and sum(person.spreads) / len(person.spreads) > p.max_spread
                and self._has_narrower_partner(person.legs, legs)
            )
            if person.far_steps >= p.window or wide:
                self._lose(pid)

        # new persons from free legs that are near and agree (or both stand still); the
        # pairs closest on average over the recent past first, so that the legs of two
        # people walking side by side are not crossed
        used = {leg for person in self._persons.values() for leg in person.legs}
        free = sorted(k for k in legs if k not in used)
        candidates: list[tuple[float, int, int]] = []
        if len(free) >= 2:
            pos = np.stack([legs[k].mean[:2] for k in free])
            dist = np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=2)
            still: dict[int, bool] = {}
            for i, j in zip(*np.nonzero(np.triu(dist < p.max_leg_distance, k=1)), strict=True):
                a, b = free[i], free[j]
                ok = self.agreement(a, b) > p.min_agreement
                if not ok and p.validate_still:
                    for leg_id in (a, b):
                        if leg_id not in still:
                            still[leg_id] = self.is_still(leg_id, stamp)
                    ok = still[a] and still[b]
                spread = leg_spread(legs[a], legs[b], p.min_speed)
                if ok and spread <= p.max_spread:
                    candidates.append((spread + self.mean_distance(a, b), a, b))
        candidates.sort()
        combine = fuse_legs if p.position == "weighted" else midpoint_legs
        self._lost = [lost for lost in self._lost if stamp - lost.stamp <= p.relink_time]
        for _, a, b in candidates:
            if a in used or b in used:
                continue
            relinked = self._relinked_id(combine(legs[a], legs[b])[0], stamp)
            if relinked is None:
                relinked = next(self._ids)
                self.persons_created += 1
            self._persons[relinked] = _Person(relinked, (a, b))
            used.update((a, b))

        shown: list[tuple[_Person, LegState, LegState]] = []
        for pid in sorted(self._persons):
            person = self._persons[pid]
            la, lb = legs[person.legs[0]], legs[person.legs[1]]
            if float(np.hypot(*(la.mean[:2] - lb.mean[:2]))) <= p.max_leg_separation:
                shown.append((person, la, lb))
        fuse = fuse_legs_batch if p.position == "weighted" else midpoint_legs_batch
        means, covs = fuse([(la, lb) for _, la, lb in shown])
        out: list[Track] = []
        for (person, la, lb), mean, cov in zip(shown, means, covs, strict=True):
            person.state, person.stamp = mean, stamp
            out.append(
                Track(
                    track_id=person.person_id,
                    kind="person",
                    position=mean[:2],
                    velocity=mean[2:4],
                    covariance=cov[:2, :2],
                    score=min(la.score, lb.score),
                    members=person.legs,
                )
            )
        return out
