"""People as tracks of their own, fed by their legs (people policy ``tracks``, issue 10).

000 Sec. 3.3 makes a person a by-product of a validated leg pair: it exists while both leg
tracks do. On real robots one leg is often hidden behind the other, leg tracks break and
restart, and a followed person keeps still in the sensor frame, so that rule loses people
and identities. Here a person is a track with its own constant-velocity Kalman filter and
an existence score:

- **Members.** A person owns up to two leg tracks (ids of the leg MHT). A leg stops being a
  member when the MHT deletes it, when it is unseen for ``member_unseen`` or when it is
  farther than ``max_member_distance`` from the person. Free legs that were detected in
  this scan join the nearest person with a free slot within its gate (Mahalanobis gate of
  the person's predicted position, Euclidean cap ``max_gate_distance``), so a person keeps
  its id when its leg tracks are replaced and when it comes back after an occlusion.
- **Measurement.** Both member legs detected and closer than ``pair_distance``: their
  midpoint with std ``pair_std``; one detected leg (or one segment wide enough to hold both
  legs, ``wide_min_width``, ``wide_min_points``, ``wide_min_score``): that leg's position with
  std ``one_leg_std`` (a leg is up to half a stride from the body centre) or the wide
  segment's centre with ``pair_std``; no member leg detected: the person coasts (velocity
  decaying with ``coast_velocity_time``).
- **Birth.** From two free detected legs closer than ``pair_distance`` (the pair of 000),
  at most ``max_spread`` apart across their walking direction (narrowest pairs first) and
  with a mean detector score above ``birth_min_score``, and from a single free detected leg
  whose segment holds both legs.
- **Existence score.** The track log-likelihood ratio (Blackman & Popoli 1999, Sec. 6.2;
  SPENCER and leg_tracker keep a per-track confidence in the same role) of "a person" vs
  "clutter", summed over the scans of the track from the evidence of each scan: both legs
  (a pair or a wide segment), one leg, or none, with probabilities ``p_two/p_one/p_none``
  under a person and ``q_two/q_one/q_none`` under clutter. Clamped to
  [``llr_min``, ``llr_max``] so that neither a long history nor a long occlusion dominates.
  A person is confirmed when the score reaches ``llr_confirm`` and is deleted when it falls
  below ``llr_delete`` before confirmation, or after ``max_coast`` seconds without a member
  leg detected (confirmed people survive occlusions for that long and keep their id when a
  leg reappears within the gate).
- **Static world.** With a :class:`~laserpeople.background.StaticWorldModel`, a person whose
  detected legs all stand on cells static for longer than ``static_time`` is not confirmed
  until it has moved ``min_travel`` from where it was born (leg_tracker's "distance
  travelled together"; only positions off static places count, so a track hopping between
  the posts of a railing or a chair does not walk), and a confirmed person that has never
  moved that far is unconfirmed (not reported) when its place becomes static (the grid
  learns online, so at the start of a recording nothing is static yet); a person seen
  walking keeps its track when it stands, unless it stands (slower than ``min_speed``) at
  a place that was static more than ``arrival_slack`` longer than the person has been
  there (a track that slid onto furniture it passed).
- **Furniture from the start.** The grid counts a place seen occupied from the first scan
  as static only once it has been held ``first_sight_hold`` (6 s), so the posts of a chair
  in view from the start can be confirmed as a person before that. A confirmed person that
  has not travelled ``min_travel``, with three or more legs detected within
  ``furniture_radius`` of it (its own or free ones: a neighbour's leg in a crowd does not
  count) in ``furniture_scans`` scans, is judged furniture (a person has two legs, a chair
  or a table four posts); such a scan counts when the person is slower than
  ``furniture_speed`` or each of these legs slower than ``furniture_leg_speed`` (the
  person of a chair moves while its legs hop between the posts). A person judged furniture
  is unconfirmed until it travels, and its place is remembered: while the static world
  model sees the place static, no person within ``furniture_radius`` of it is confirmed
  before travelling ``min_travel`` (the chair's
  legs, born again as a new person once the unconfirmed one is deleted, stay furniture; a
  person standing there is confirmed once it walks off the place).

- **Moving robot.** On a robot that has moved, tracked in the world frame (the caller sets
  :attr:`PersonTracker.moving`), a single free detected leg gives birth to a candidate,
  and one leg whose own track moves consistently (:func:`moves_consistently`) counts as
  the evidence of both (``one_leg_birth``). A candidate with a member leg that has walked
  (``walked_distance`` from its first detection at ``moving_speed`` or faster) on a place not
  static for longer than ``arrival_slack`` loses only ``walked_miss`` for a scan without a
  detection (a person at 4-7 m is detected in about every other scan). When a young leg
  track (judged over its whole path, ``moving_min_detections``) is first seen moving, has
  already covered ``moving_speed * moving_time`` and stands where the static world model has
  seen returns for at most the time since its detection before, the earlier scans of that
  path that counted as one leg count as both (``young_credit``). A static laser and a
  sensor-frame run keep the rules above unchanged.

- **Re-identification.** A confirmed person deleted after ``max_coast`` stays a dormant
  identity with its leg-width signature for ``reid.max_dormant`` seconds; a person confirmed
  for the first time is given such an identity back when signature and motion gate make it
  clearly the same person (:mod:`laserpeople.tracking.reidentify`), else a fresh id.

Reported: confirmed people whose last leg detection is at most ``max_report_unseen`` old.
"""

from __future__ import annotations

import itertools
import math
from collections import deque
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from laserpeople.background import StaticWorldModel
from laserpeople.config import param
from laserpeople.tracking import kalman
from laserpeople.tracking.reidentify import (
    Candidate,
    DormantIdentity,
    Reidentifier,
    ReidentifyParams,
    Signature,
    leg_width,
)
from laserpeople.tracking.robot_motion import MotionParams
from laserpeople.tracks import Track

FloatArray = NDArray[np.float64]

TWO, ONE, NONE = 0, 1, 2
"""Evidence of one scan for a person: both legs, one leg, no leg."""


@dataclass(frozen=True)
class PersonTrackParams:
    """People as tracks of their own (people policy ``tracks``)."""

    config_section = "people"

    pair_distance: float = param(
        0.75,
        "000 Sec. 3.3 (theta_d); leg_tracker uses 0.8 m (max_leg_pairing_dist)",
        "two legs closer than this are one person's pair",
        "m",
    )
    max_spread: float = param(
        0.55,
        "as PersonParams.max_spread (extension of 000 Sec. 3.3): the feet of one walker are "
        "~0.2 m apart across the walking direction, those of two people side by side "
        "~0.5-0.6 m",
        "two legs farther apart than this across their mean walking direction (plain "
        "distance below min_speed) are not one person's pair",
        "m",
    )
    min_speed: float = param(
        0.1,
        "as PersonParams.min_speed",
        "legs slower than this on average have no walking direction",
        "m/s",
    )
    pair_std: float = param(
        0.1,
        "assumption: the midpoint of two legs lies within a leg radius of the body centre",
        "standard deviation of a person position from a leg pair or a wide segment",
        "m",
    )
    one_leg_std: float = param(
        0.25,
        "assumption: a leg is up to half a stride (~0.35 m) from the body centre",
        "standard deviation of a person position from a single leg",
        "m",
    )
    accel_psd: float = param(
        1.0,
        "assumption: a walker's body accelerates by ~1 m/s^2 (legs: 32, kalman.accel_psd)",
        "white-acceleration power spectral density of the person filter",
        "m^2/s^3",
    )
    init_velocity_std: float = param(
        1.0, "assumption: walking speed", "std of the initial velocity", "m/s"
    )
    coast_velocity_time: float = param(
        1.0,
        "assumption: a person unseen for a while has most likely slowed or turned",
        "time constant of the velocity decay while no leg is detected (inf: keep it)",
        "s",
    )
    gate_probability: float = param(
        0.99, "assumption", "probability mass of the Mahalanobis gate for joining legs"
    )
    min_gate_distance: float = param(
        0.4,
        "assumption: a leg of a person seen now is within ~half a stride of the centre",
        "a free leg this close to a person's predicted position is always inside its gate",
        "m",
    )
    max_gate_distance: float = param(
        1.5,
        "assumption: bounds the gate of a person unseen for seconds",
        "a free leg farther than this never joins a person",
        "m",
    )
    member_unseen: float = param(
        0.5,
        "assumption: a leg track unseen this long has most likely lost its leg",
        "a member leg unseen for longer is released",
        "s",
    )
    max_member_distance: float = param(
        0.5,
        "assumption; 0.5 vs 0.75 m: demo seeds 0-4 mean MOTA 0.920 -> 0.927, IDF1 .884 -> "
        ".911; the real dev recording unchanged (identity recall .657 -> .658)",
        "a member leg farther than this from the person is released",
        "m",
    )
    wide_min_width: float = param(
        0.25,
        "assumption: one leg is at most ~0.2 m wide; two touching legs ~0.25-0.5 m",
        "a detected segment at least this wide (first to last point) holds two legs",
        "m",
    )
    wide_max_width: float = param(
        0.6,
        "assumption: wider than two legs side by side",
        "a detected segment wider than this is not a person",
        "m",
    )
    wide_min_points: int = param(
        5, "assumption", "a wide segment needs at least this many points", "points"
    )
    wide_min_score: float = param(
        0.5,
        "assumption, as birth_min_score: a room corner (an L of two wall pieces) was taken "
        "for a wide segment with margin 0.43 on furniture-chairs seed 1",
        "a wide segment needs a detector score above this",
    )
    birth_min_score: float = param(
        0.5,
        "assumption: the AdaBoost margins of legs in reported people were 0.07/0.21/0.40 "
        "(10/50/90th percentile) on 4-post chairs (furniture-chairs seed 1) and 0.62/1.55/"
        "2.22 and 0.38/1.24/2.12 on people (demo seed 0, office seed 0)",
        "a leg pair gives birth to a person, and counts as two-leg evidence, only when its "
        "mean detector score exceeds this (else it is one-leg evidence)",
    )
    p_two: float = param(
        0.5,
        "assumption: both legs of a person are seen in about half the scans (000 Table 10: "
        "an approved leg is detected with 0.2 and occluded with 0.79 per scan, but "
        "detected legs of a walker are mostly both in view)",
        "P(both legs seen | person)",
    )
    p_one: float = param(0.4, "assumption", "P(one leg seen | person)")
    q_two: float = param(
        0.1,
        "assumption: two leg-like clutter segments close together are rare",
        "P(two legs seen | clutter)",
    )
    q_one: float = param(0.4, "assumption", "P(one leg seen | clutter)")
    llr_confirm: float = param(
        4.0,
        "assumption: about three scans of both legs (log(0.5/0.1) = 1.6 each)",
        "existence score at which a person is confirmed (reported)",
    )
    llr_delete: float = param(
        -2.0, "assumption", "an unconfirmed person whose score falls below this is deleted"
    )
    llr_min: float = param(-3.0, "assumption", "lower clamp of the existence score")
    llr_max: float = param(
        12.0, "assumption", "upper clamp of the existence score (bounds a long history)"
    )
    max_coast: float = param(
        4.0,
        "assumption: the same id through occlusions of several seconds (docs/people-benchmarks.md)",
        "a person with no member leg detected for longer is deleted",
        "s",
    )
    unconfirmed_coast: float = param(
        0.5,
        "assumption",
        "an unconfirmed person with no member leg detected for longer is deleted",
        "s",
    )
    merge_distance: float = param(
        0.3,
        "assumption: two people are not closer than about a body width",
        "of two people closer than this, the one with the lower score gives way",
        "m",
    )
    static_time: float = param(
        10.0,
        "assumption: a person waiting stands still for tens of seconds, but a new person "
        "appearing on a place occupied that long is furniture",
        "legs on cells static for longer are not confirmed as a person until it moves",
        "s",
    )
    min_travel: float = param(
        0.5,
        "leg_tracker (dist_travelled_together_to_initiate_leg_pair = 0.5 m)",
        "distance from its birth place after which a person on static cells is confirmed",
        "m",
    )
    reid: ReidentifyParams = param(  # noqa: RUF009 (a frozen default instance)
        ReidentifyParams(),
        "nested table people.reid.*",
        "re-identification of people lost for long (tracking/reidentify.py)",
    )

    motion: MotionParams = param(  # noqa: RUF009 (a frozen default instance)
        MotionParams(),
        "nested table people.motion.*",
        "when the lasers count as riding on a moving robot (tracking/robot_motion.py)",
    )

    static_legs: bool = param(
        False,
        "assumption: a leg on a place static for longer than static_time, with nobody seen "
        "walking near it, is furniture; tracking it only costs CPU (measured in "
        "docs/people-benchmarks.md)",
        "track leg detections on places static for longer than static_time with no person "
        "that has walked (or been reported) within walker_radius; false leaves them out of "
        "the leg MHT (counted and reported)",
    )
    walker_radius: float = param(
        1.0,
        "assumption: a person's legs are within about half a metre of its centre, plus a "
        "scan's motion and the position error",
        "leg detections on static places this close to a person that has walked (or been "
        "reported) are tracked whatever static_legs says",
        "m",
    )
    one_leg_birth: bool = param(
        True,
        "measured (docs/moving-robot.md): real lobby recall 0.018 -> 0.246; held-back "
        "moving-robot MOTA 0.417 -> 0.452",
        "a single free detected leg with a detector score above one_leg_min_score, farther "
        "than pair_distance from every person, gives birth to a person candidate, and a "
        "person seen by one leg that moves consistently (moving_time, moving_speed, "
        "moving_straightness) gains existence as from both legs; on a moving robot tracked "
        "in the world frame only (tracking/robot_motion.py)",
    )
    one_leg_min_score: float = param(
        0.0,
        "measured (docs/moving-robot.md): real lobby recall 0.105 at 0.5 -> 0.246 at 0.0 "
        "(legs at 3-7 m score 0.01-1.6)",
        "detector score above which a single leg gives birth to a person candidate and "
        "counts as moving evidence",
    )
    moving_time: float = param(
        0.5,
        "assumption: about four scans at 7.5 Hz, one stride",
        "a person's measured positions over at least this long tell whether it moves consistently",
        "s",
    )
    moving_speed: float = param(
        0.4,
        "assumption: slow walking ~0.5-0.8 m/s; a leg track hopping on clutter or a wall "
        "gives a net displacement near zero",
        "a person moves consistently when its net displacement over moving_time is at least "
        "this fast",
        "m/s",
    )
    moving_straightness: float = param(
        0.6,
        "assumption: a walker's path over half a second is nearly straight; jitter on "
        "clutter is not",
        "and when that net displacement is at least this share of the path length",
    )
    moving_min_detections: int = param(
        3,
        "measured (docs/moving-robot.md): real lobby recall 0.298 -> 0.316; held-back "
        "moving-robot 100-109 MOTA 0.459 -> 0.488 (4 detections: no change on the lobby)",
        "a leg track younger than moving_time is judged over its whole path once it has "
        "this many detections, where its place has been static for at most arrival_slack "
        "(0: never)",
    )
    young_credit: bool = param(
        True,
        "measured (docs/moving-robot.md): real lobby recall of the detected labels 0.395 -> "
        "0.442 at the same MOTA and static seconds; held-back moving-robot MOTA / IDF1 "
        "0.647 / 0.699 -> 0.652 / 0.701, randomised 0.345 / 0.413 -> 0.348 / 0.412, "
        "furniture-only static seconds unchanged",
        "when a candidate's young leg track (judged over its whole path, "
        "moving_min_detections) is first seen moving consistently, is already "
        "moving_speed * moving_time (0.2 m) from the start of that path and stands where "
        "the static world model has seen returns for at most the time since its detection "
        "before (it has just come there), the earlier scans of the path that counted as "
        "one leg count as both (a walker seen in three consecutive scans is confirmed at "
        "the third); on a moving robot tracked in the world frame only",
    )
    walked_distance: float = param(
        0.7,
        "measured (docs/moving-robot.md): real lobby recall 0.281 at 1.0 m -> 0.298 at 0.7 m "
        "(the same at 0.5 m); above the ~0.5 m within which a leg track hopping between the "
        "posts of a chair or a table stays",
        "a leg track whose net displacement from its first detection (world frame) is at "
        "least this, at moving_speed or faster on average, has walked",
        "m",
    )
    walked_miss: float = param(
        0.0,
        "measured (docs/moving-robot.md): real lobby recall 0.246 -> 0.298, false positives "
        "23 -> 24 (log(p_none / q_none) = -1.61 as before); a person at 4-7 m is detected "
        "in about every other scan",
        "existence change, for a scan without a detection, of an unconfirmed person with a "
        "member leg that has walked (walked_distance) and whose place is static for at most "
        "arrival_slack; on a moving robot tracked in the world frame only",
    )
    furniture_scans: int = param(
        1,
        "measured (docs/people-benchmarks.md): the real MiR bag's chair taken for a person "
        "75 -> 3 scans (front laser static 10.6 -> 4.9 s, walkers kept); halls and held "
        "back unchanged, furniture-only 6.6 -> 6.5 s",
        "a confirmed person that has not travelled min_travel, with three or more legs (its "
        "own or free ones, not another person's) detected within furniture_radius of it in "
        "this many scans (the posts of a chair or a table), is unconfirmed, and no person "
        "within furniture_radius of its place (while the place is static) is confirmed, "
        "until it has travelled min_travel (0: never)",
    )
    furniture_speed: float = param(
        0.1,
        "measured (docs/people-benchmarks.md): people starting to walk in a crowd have "
        "free legs of their neighbours within furniture_radius (the bench_scaling hall: "
        "without it MOTA 0.860 -> 0.845 at 10 people; 0.3 m/s 0.850; 0.1 m/s 0.860)",
        "under furniture_scans, a scan with three or more legs near a person counts when "
        "it is slower than this (or those legs slower than furniture_leg_speed)",
        "m/s",
    )
    furniture_leg_speed: float = param(
        0.2,
        "measured (docs/people-benchmarks.md): the real MiR bag's chair, whose person moves "
        "at 0.25 m/s in its first scan with three legs (its legs hop between the posts), "
        "has legs at 0.07-0.13 m/s there (its id 17 -> 3 scans); a walking leg moves at "
        "about the walking speed; the bench_scaling halls unchanged",
        "under furniture_scans, a scan with three or more legs near a person faster than "
        "furniture_speed counts too when each of these legs is slower than this",
        "m/s",
    )
    furniture_radius: float = param(
        0.35,
        "assumption: a person's two legs are within about 0.3 m of its centre",
        "detected legs this close to a person count for furniture_scans",
        "m",
    )
    arrival_slack: float = param(
        2.0,
        "assumption: the cells of a person's last step are occupied up to about a second "
        "before it stops",
        "a person seen walking who stands (slower than min_speed) is not reported at a place "
        "that was static this much longer than it has been there (slid onto furniture)",
        "s",
    )

    def __post_init__(self) -> None:
        for name in ("p_two", "p_one", "q_two", "q_one"):
            if not 0.0 < getattr(self, name) < 1.0:
                raise ValueError(f"{name} must be in (0, 1)")
        if not (self.p_two + self.p_one < 1.0 and self.q_two + self.q_one < 1.0):
            raise ValueError("p_two + p_one and q_two + q_one must be below 1 (P(none) > 0)")
        if not self.llr_min <= self.llr_delete < self.llr_confirm <= self.llr_max:
            raise ValueError("need llr_min <= llr_delete < llr_confirm <= llr_max")
        if not 0.0 < self.min_gate_distance <= self.max_gate_distance:
            raise ValueError("need 0 < min_gate_distance <= max_gate_distance")
        if not self.wide_min_width < self.wide_max_width:
            raise ValueError("wide_min_width must be below wide_max_width")
        if not (self.moving_time > 0 and self.moving_speed >= 0):
            raise ValueError("moving_time must be positive, moving_speed not negative")
        if self.moving_min_detections < 0:
            raise ValueError("moving_min_detections must not be negative")
        if self.furniture_scans < 0 or not (
            self.furniture_radius > 0 and self.furniture_speed > 0 and self.furniture_leg_speed > 0
        ):
            raise ValueError(
                "furniture_scans must not be negative, furniture_radius and speeds positive"
            )
        if not (self.walked_distance > 0 and self.walked_miss <= 0):
            raise ValueError("walked_distance must be positive, walked_miss not positive")
        if not 0.0 <= self.moving_straightness <= 1.0:
            raise ValueError("moving_straightness must be in [0, 1]")
        if min(self.pair_std, self.one_leg_std, self.accel_psd, self.pair_distance) <= 0:
            raise ValueError("standard deviations, accel_psd and pair_distance must be positive")

    def evidence_llr(self) -> FloatArray:
        """Log-likelihood ratio (3,) of the evidence both/one/no leg: log(p_e / q_e)."""
        p = np.array([self.p_two, self.p_one, 1.0 - self.p_two - self.p_one])
        q = np.array([self.q_two, self.q_one, 1.0 - self.q_two - self.q_one])
        return np.asarray(np.log(p / q), dtype=np.float64)

    @property
    def gate(self) -> float:
        """Squared Mahalanobis distance of the joining gate (chi-square, 2 dof)."""
        return kalman.chi2_quantile_2dof(self.gate_probability)


@dataclass(eq=False, slots=True)
class LegObservation:
    """A leg track as the person layer sees it in one scan (read-only by convention: not
    frozen, whose ``__init__`` costs about three times as much, once per leg and scan).

    Attributes:
        track_id: Leg id (MHT family).
        position: Filtered position (2,) [m] in the tracking frame.
        detected: The leg was detected in this scan.
        unseen_for: Time [s] since its last detection.
        detection: Index of its detection in this scan's detections (-1 if none).
        wide: Its detection's segment is wide enough to hold both legs of a person.
        velocity: Filtered velocity (2,) [m/s].
        score: Detector score of its detection in this scan (NaN if not detected).
        width: Width [m] of its detection's segment as one leg (:func:`leg_width`; NaN if
            not detected, wide or without segment points).
    """

    track_id: int
    position: FloatArray
    detected: bool
    unseen_for: float
    detection: int = -1
    wide: bool = False
    velocity: FloatArray = field(default_factory=lambda: np.zeros(2))
    score: float = math.nan
    width: float = math.nan


def spread(a: LegObservation, b: LegObservation, min_speed: float) -> float:
    """Distance [m] between legs ``a`` and ``b`` across their mean velocity, or the plain
    distance when their mean speed is below ``min_speed`` [m/s]."""
    (ax, ay), (bx, by) = a.position.tolist(), b.position.tolist()
    return _spread(ax - bx, ay - by, a, b, min_speed)


def _spread(dx: float, dy: float, a: LegObservation, b: LegObservation, min_speed: float) -> float:
    """:func:`spread` of legs ``a`` and ``b`` whose positions differ by ``(dx, dy)`` [m]."""
    (avx, avy), (bvx, bvy) = a.velocity.tolist(), b.velocity.tolist()
    vx, vy = 0.5 * (avx + bvx), 0.5 * (avy + bvy)
    speed = math.hypot(vx, vy)
    if speed < min_speed:
        return math.hypot(dx, dy)
    return abs(vx * dy - vy * dx) / speed


@dataclass(eq=False)
class PersonTrack:
    """One person: Kalman state, members and existence score.

    Attributes:
        person_id: Identity.
        mean: State (4,) (x, y, vx, vy).
        cov: Covariance (4, 4).
        stamp: Time [s] of ``mean``.
        members: Leg ids (at most two).
        llr: Existence score (track log-likelihood ratio).
        confirmed: Reached ``llr_confirm`` once (and not deleted since).
        last_seen: Time [s] of the last scan with a member leg detected.
        born_at: Position (2,) where the person was born.
        travelled: Largest distance [m] from ``born_at`` so far, at places not static for
            longer than ``static_time`` (all places without a static world model); no
            longer updated once it has reached ``min_travel`` (it is only compared with it).
        arrived: (time [s], position (2,)) of the last time the person was ``min_travel``
            or farther from where it was before (when it came to its current place).
        scans: Scans since birth.
        public_id: The reported id, given at the first confirmation (so that candidates
            that never become people use no ids, and a returning person can be given its
            old id); None before.
        signature: Widths of its detected single legs (re-identification).
        born_stamp: Time [s] of its birth.
        confirmed_at: Time [s] of its first confirmation (NaN before).
        pending: Confirmed with a fresh id and not yet matched to dormant identities.
        seen_before: Time [s] its identity was tracked before a re-identification.
        one_leg_scans: Scans that counted as one leg before a member leg was first seen
            moving consistently (``young_credit``).
        seen_moving: A member leg has been seen moving consistently.
        posts: Scans, before it travelled ``min_travel``, with three or more legs detected
            within ``furniture_radius`` of it.
    """

    person_id: int
    mean: FloatArray
    cov: FloatArray
    stamp: float
    members: list[int] = field(default_factory=list)
    llr: float = 0.0
    confirmed: bool = False
    last_seen: float = 0.0
    born_at: FloatArray = field(default_factory=lambda: np.zeros(2))
    travelled: float = 0.0
    arrived: tuple[float, FloatArray] = (0.0, np.zeros(2))
    scans: int = 0
    public_id: int | None = None
    signature: Signature = field(default_factory=Signature)
    born_stamp: float = 0.0
    confirmed_at: float = math.nan
    pending: bool = False
    seen_before: float = 0.0
    one_leg_scans: int = 0
    seen_moving: bool = False
    posts: int = 0


def update_llr(llr: float, evidence: int, params: PersonTrackParams) -> float:
    """Existence score after one scan with ``evidence`` (TWO, ONE or NONE), clamped."""
    step = float(params.evidence_llr()[evidence])
    return min(max(llr + step, params.llr_min), params.llr_max)


def moves_consistently(
    path: Sequence[tuple[float, float, float]], params: PersonTrackParams, young: bool = False
) -> bool:
    """Whether the measured positions ``path`` ((time [s], x, y [m]), oldest first) show a
    consistent motion: they span at least ``moving_time``, and from the last position at
    least ``moving_time`` before the newest one to the newest, the net displacement is at
    least ``moving_speed`` times the elapsed time and at least ``moving_straightness``
    times the length of the path between them. A ``young`` track (its place not static for
    long) whose whole path is shorter than ``moving_time`` is judged over that path once it
    has ``moving_min_detections`` detections."""
    if len(path) < 2:
        return False
    t1, x1, y1 = path[-1]
    # (the last position at least moving_time old: times only grow along the path, so the
    # count of those old enough, found from the oldest on, stops at the first younger one)
    since = t1 - params.moving_time + 1e-9
    start = -1
    for t, _, _ in path:
        if t > since:
            break
        start += 1
    if start < 0:
        if not (
            young and params.moving_min_detections and len(path) >= params.moving_min_detections
        ):
            return False
        start = 0
    t0, x0, y0 = path[start]
    net = math.hypot(x1 - x0, y1 - y0)
    # (the steps' lengths summed oldest first, as a sum over their indices: the same float)
    steps = itertools.pairwise(itertools.islice(path, start, None))
    length = sum(math.hypot(bx - ax, by - ay) for (_, ax, ay), (_, bx, by) in steps)
    return net >= params.moving_speed * (t1 - t0) and net >= params.moving_straightness * length


def segment_holds_two_legs(points: FloatArray, score: float, params: PersonTrackParams) -> bool:
    """A detected segment with ``points`` (n, 2) [m] and detector ``score`` is wide enough,
    dense enough and leg-like enough to be both legs of one person."""
    if points.shape[0] < params.wide_min_points or not score > params.wide_min_score:
        return False
    (x0, y0), (x1, y1) = points[0].tolist(), points[-1].tolist()
    return within_width(x1 - x0, y1 - y0, params.wide_min_width, params.wide_max_width)


HYPOT_BAND = 1e-12
"""Relative distance [1] from a bound within which :func:`within_width` asks numpy's
``hypot`` itself: Python's ``math.hypot`` and the C library's (numpy's) differ by at most a
few units in the last place (about 1e-16 relative), far inside this band."""


def within_width(dx: float, dy: float, low: float, high: float) -> bool:
    """Whether ``low <= hypot(dx, dy) <= high`` [m] as numpy's ``hypot`` decides it:
    Python's ``math.hypot`` (a twentieth of a scalar ``np.hypot`` call) where it lies more
    than :data:`HYPOT_BAND` (relative) from both bounds, numpy's within that band (where
    the two may round a tie to either side)."""
    width = math.hypot(dx, dy)
    if abs(width - low) <= HYPOT_BAND * width or abs(width - high) <= HYPOT_BAND * width:
        width = float(np.hypot(dx, dy))
    return low <= width <= high


class PersonTracker:
    """Keeps person tracks from the leg tracks of each scan (see the module docstring).

    Args:
        params: Parameters.
        static_model: Optional static world model asked for the static time of legs.
    """

    def __init__(
        self, params: PersonTrackParams, static_model: StaticWorldModel | None = None
    ) -> None:
        self.params = params
        self.static_model = static_model
        self.persons: dict[int, PersonTrack] = {}
        self._ids = itertools.count()
        self._public_ids = itertools.count()
        self.persons_created = 0
        """People confirmed at least once since the start (reported ids)."""
        self._gate = params.gate
        self._one_leg_cov = np.eye(2) * params.one_leg_std**2
        """Measurement covariance [m^2] of a person's position from one leg (constant)."""
        self._one_leg_stack = np.repeat(self._one_leg_cov[None], 16, axis=0)
        self._one_leg_stack.setflags(write=False)
        self._cov_table = np.stack([self._one_leg_cov, np.eye(2) * params.pair_std**2])
        """Measurement covariances [m^2] of a person's position from one leg, then from a
        pair or a wide segment (rows taken by :meth:`_meas_covs`)."""
        self._llr = params.evidence_llr()
        self._llr_steps = [float(x) for x in self._llr]  # (plain floats: per person and scan)
        self._static_now: dict[int, float] = {}
        """Static time [s] of the people's positions asked in this scan (by person id)."""
        self.reid = Reidentifier(params.reid)
        """Dormant identities of deleted people, given back to people who return."""
        self._stamp = 0.0
        self.moving = False
        """The lasers ride on a robot that has moved, and the tracking frame is the world
        (set by the caller; one-leg births, ``one_leg_birth``, only then)."""
        self.world_frame = True
        """The tracking frame is the world (set by the caller once it has chosen its frame):
        in the sensor frame the lasers never count as moving (:meth:`_one_leg_on`), so the
        leg paths that only one-leg births read are not recorded."""
        self._furniture: list[tuple[float, float]] = []
        """Places (x, y) [m] of the people judged furniture (``furniture_scans``): a person
        that has not travelled ``min_travel`` within ``furniture_radius`` of one that is
        still static is not confirmed either (the same chair born again from its legs)."""
        self._leg_first: dict[int, tuple[float, float, float]] = {}
        """Per leg track: (time [s], x, y [m]) of its first detection."""
        self._leg_paths: dict[int, deque[tuple[float, float, float]]] = {}
        """Per leg track: (time [s], x, y [m]) of its detections over the last
        ``moving_time`` (and one before), for :func:`moves_consistently`."""

    @property
    def approved_legs(self) -> frozenset[int]:
        """Member legs of confirmed people (the *approved* legs of 000 Sec. 3.3.1)."""
        return frozenset(m for p in self.persons.values() if p.confirmed for m in p.members)

    # ------------------------------------------------------------------ steps

    def _predict(self, stamp: float) -> None:
        if not self.persons:
            return
        ps = list(self.persons.values())
        means = np.array([p.mean for p in ps])
        covs = np.array([p.cov for p in ps])
        dt = np.array([min(max(stamp - p.stamp, 0.0), 1.0) for p in ps])
        seen_list = [p.last_seen >= p.stamp - 1e-9 for p in ps]
        tau = self.params.coast_velocity_time
        if math.isinf(tau) or all(seen_list):
            pm, pc = kalman.predict(means, covs, dt, self.params.accel_psd)
            for i, p in enumerate(ps):
                p.mean, p.cov, p.stamp = pm[i], pc[i], stamp
            return
        # people with no leg detected in their last scan coast
        pm, pc, cm, cc = kalman.predict_and_coast(means, covs, dt, self.params.accel_psd, tau)
        for i, (p, seen) in enumerate(zip(ps, seen_list, strict=True)):
            p.mean, p.cov = (pm[i], pc[i]) if seen else (cm[i], cc[i])
            p.stamp = stamp

    def _release(self, legs: Mapping[int, LegObservation]) -> None:
        p = self.params
        for person in self.persons.values():
            if not person.members:
                continue
            keep = []
            px, py = person.mean[:2].tolist()
            for m in person.members:
                leg = legs.get(m)
                if leg is None or leg.unseen_for > p.member_unseen:
                    continue
                lx, ly = leg.position.tolist()
                if math.hypot(lx - px, ly - py) > p.max_member_distance:
                    continue
                keep.append(m)
            person.members = keep

    def _join(self, legs: Mapping[int, LegObservation]) -> None:
        """Free detected legs join the nearest person with a free slot inside its gate
        (globally nearest pairs first)."""
        p = self.params
        owned = {m for person in self.persons.values() for m in person.members}
        free = [leg for leg in legs.values() if leg.detected and leg.track_id not in owned]
        open_ = [person for person in self.persons.values() if len(person.members) < 2]
        if not free or not open_:
            return
        # (np.array of the rows: np.stack's values at half its cost on a few)
        z = np.array([leg.position for leg in free], dtype=np.float64)
        means = np.array([q.mean for q in open_], dtype=np.float64)
        covs = np.array([q.cov for q in open_], dtype=np.float64)
        d2, _ = kalman.mahalanobis_and_loglik(means, covs, z, self._one_leg_covs(len(free)))
        e2 = kalman.euclidean_sq(means, z)
        ok = ((d2 <= self._gate) | (e2 <= p.min_gate_distance**2)) & (e2 <= p.max_gate_distance**2)
        # a person's members stay within pair_distance of each other
        # (the spread only of the legs still allowed: it is a plain-float call per leg)
        for i, person in enumerate(open_):
            row = ok[i]
            for m in person.members:
                other = legs[m]
                d = z - other.position
                row &= np.hypot(d[:, 0], d[:, 1]) <= p.pair_distance
                for j in row.nonzero()[0].tolist():
                    if not spread(free[j], other, p.min_speed) <= p.max_spread:
                        row[j] = False
        cost = np.where(ok, e2, np.inf)
        # the allowed pairs (finite costs: e2 is within the gate) sort first
        order = cost.argsort(axis=None)[: int(np.count_nonzero(ok))]
        for flat in order.tolist():
            i, j = divmod(flat, len(free))
            person, leg = open_[i], free[j]
            if len(person.members) >= 2 or leg.track_id in owned:
                continue
            person.members.append(leg.track_id)
            owned.add(leg.track_id)

    def _record_paths(self, legs: Mapping[int, LegObservation], stamp: float) -> None:
        """Append this scan's detected legs to their paths; forget legs no longer tracked."""
        horizon = stamp - self.params.moving_time - 1e-9
        paths, first = self._leg_paths, self._leg_first
        for leg in legs.values():
            if not leg.detected:
                continue
            tid = leg.track_id
            x, y = leg.position.tolist()
            path = paths.get(tid)
            if path is None:
                path = paths[tid] = deque()
                if tid not in first:
                    first[tid] = (stamp, x, y)
            path.append((stamp, x, y))
            while len(path) > 2 and path[1][0] <= horizon:
                path.popleft()
        for gone in paths.keys() - legs.keys():
            del paths[gone]
        for gone in first.keys() - legs.keys():
            del first[gone]

    def _one_leg_on(self) -> bool:
        """``one_leg_birth`` on a moving robot tracked in the world frame (:attr:`moving`
        and :attr:`world_frame`; in the sensor frame of a moving laser walls and furniture
        move consistently too)."""
        return self.params.one_leg_birth and self.moving and self.world_frame

    def _moves(self, leg: LegObservation) -> bool:
        """A detected leg with a detector score above ``one_leg_min_score`` whose path
        moves consistently (:func:`moves_consistently`)."""
        p = self.params
        path = self._leg_paths.get(leg.track_id)
        if not (leg.detected and leg.score > p.one_leg_min_score and path is not None):
            return False
        # the static world model is asked only for a track whose whole path could be judged
        # young (shorter than moving_time, with moving_min_detections detections)
        young = (
            0 < p.moving_min_detections <= len(path)
            and path[0][0] > path[-1][0] - p.moving_time + 1e-9
            and float(self._static(leg.position[None, :2])[0]) <= p.arrival_slack
        )
        return moves_consistently(path, p, young=young)

    def _walked(self, track_id: int, legs: Mapping[int, LegObservation]) -> bool:
        """The leg track ``track_id`` is at least ``walked_distance`` from its first
        detection, at ``moving_speed`` or faster on average (world frame)."""
        first = self._leg_first.get(track_id)
        leg = legs.get(track_id)
        if first is None or leg is None:
            return False
        t0, x0, y0 = first
        x, y = leg.position.tolist()
        net = math.hypot(x - x0, y - y0)
        return net >= self.params.walked_distance and net >= self.params.moving_speed * (
            self._stamp - t0
        )

    def _young_credit(self, person: PersonTrack) -> float:
        """Existence owed to the unconfirmed ``person`` whose member leg is seen moving for
        the first time (``young_credit``): for each earlier scan of a young member path
        (shorter than ``moving_time``, net displacement at least ``moving_speed *
        moving_time``, its newest place static for at most the time since the detection
        before) that counted as one leg, both legs' evidence instead."""
        p = self.params
        if not p.young_credit or person.confirmed or not person.one_leg_scans:
            return 0.0
        reach = p.moving_speed * p.moving_time
        earlier = 0
        for m in person.members:
            path = self._leg_paths.get(m)
            if not path or len(path) < 2 or path[0][0] <= path[-1][0] - p.moving_time + 1e-9:
                continue
            (_, x0, y0), (_, x1, y1) = path[0], path[-1]
            if math.hypot(x1 - x0, y1 - y0) < reach:
                continue
            # a walker's foot has just come to its place; a leg track sliding along a wall
            # stands where the grid saw returns before it came
            came = path[-1][0] - path[-2][0]
            if float(self._static(np.array([[x1, y1]]))[0]) > came + 1e-9:
                continue
            earlier = max(earlier, len(path) - 1)
        steps = self._llr_steps
        return min(person.one_leg_scans, earlier) * (steps[TWO] - steps[ONE])

    def _moving_member(self, person: PersonTrack, legs: Mapping[int, LegObservation]) -> bool:
        """Some detected member leg of ``person`` moves consistently (:meth:`_moves`)."""
        return any(self._moves(legs[m]) for m in person.members)

    def _one_leg_covs(self, n: int) -> FloatArray:
        """``n`` copies (n, 2, 2) of the one-leg measurement covariance (kept between
        scans; read-only)."""
        if self._one_leg_stack.shape[0] < n:
            stack = np.repeat(self._one_leg_cov[None], max(n, 2 * self._one_leg_stack.shape[0]), 0)
            stack.setflags(write=False)
            self._one_leg_stack = stack
        return self._one_leg_stack[:n]

    def _meas_covs(self, stds: list[float]) -> FloatArray:
        """Measurement covariances (K, 2, 2) [m^2] ``std^2 I`` of the standard deviations
        ``stds`` [m], each ``one_leg_std`` or ``pair_std`` (:meth:`_measure`'s): a slice of
        the kept one-leg copies where all are one leg's, else rows of the two covariances
        (the same floats as ``std**2`` on a zero matrix's diagonal)."""
        n = len(stds)
        one = self.params.one_leg_std
        if stds.count(one) == n:
            return self._one_leg_covs(n)
        rows = np.array([0 if s == one else 1 for s in stds], dtype=np.intp)
        return self._cov_table.take(rows, axis=0)

    def _measure(
        self, person: PersonTrack, seen: Sequence[LegObservation]
    ) -> tuple[int, FloatArray | tuple[float, float] | None, float]:
        """Evidence, measured position (2,) and its std from the detected member legs ``seen``
        (in the order of the members)."""
        p = self.params
        if len(seen) == 2:
            (ax, ay), (bx, by) = seen[0].position.tolist(), seen[1].position.tolist()
            dx, dy = ax - bx, ay - by
            if (
                math.hypot(dx, dy) <= p.pair_distance
                and _spread(dx, dy, seen[0], seen[1], p.min_speed) <= p.max_spread
            ):
                strong = 0.5 * (seen[0].score + seen[1].score) > p.birth_min_score
                # (the midpoint in plain floats: the same as numpy's 0.5 * (a + b))
                return (TWO if strong else ONE), (0.5 * (ax + bx), 0.5 * (ay + by)), p.pair_std
            px, py = person.mean[:2].tolist()

            def off(leg: LegObservation) -> float:
                lx, ly = leg.position.tolist()
                return math.hypot(lx - px, ly - py)

            return ONE, min(seen, key=off).position, p.one_leg_std
        if len(seen) == 1:
            if seen[0].wide:
                return TWO, seen[0].position, p.pair_std
            return ONE, seen[0].position, p.one_leg_std
        return NONE, None, 0.0

    def _static(self, positions: FloatArray) -> FloatArray:
        if self.static_model is None or positions.shape[0] == 0:
            return np.zeros(positions.shape[0])
        return np.asarray(self.static_model.static_time(positions), dtype=np.float64)

    def on_furniture(self, positions: FloatArray) -> NDArray[np.bool_]:
        """Which leg detections at ``positions`` (M, 2) [m] are left out of the leg MHT when
        ``static_legs`` is false: on places static for longer than ``static_time`` and
        farther than ``walker_radius`` from every person that has walked ``min_travel`` or
        been reported (people standing still keep their legs; furniture does not get any).
        """
        p = self.params
        m = positions.shape[0]
        if p.static_legs or self.static_model is None or m == 0:
            return np.zeros(m, dtype=bool)
        out = self._static(positions) > p.static_time
        if out.any():
            walkers = [
                q.mean[:2]
                for q in self.persons.values()
                if q.travelled >= p.min_travel or q.public_id is not None
            ]
            if walkers:
                idx = out.nonzero()[0]
                d = positions.take(idx, axis=0)[:, None, :] - np.array(walkers)[None, :, :]
                near = (np.einsum("mwk,mwk->mw", d, d) <= p.walker_radius**2).any(axis=1)
                out[idx[near]] = False
        return out

    def _update_people(self, legs: Mapping[int, LegObservation], stamp: float) -> None:
        p = self.params
        rows: list[tuple[PersonTrack, FloatArray | tuple[float, float], float]] = []
        steps = self._llr_steps
        one_leg = self._one_leg_on()
        for person in self.persons.values():
            seen = [leg for leg in map(legs.__getitem__, person.members) if leg.detected]
            evidence, z, std = self._measure(person, seen)
            credit = 0.0
            if evidence == ONE and one_leg and self._moving_member(person, legs):
                evidence = TWO
                if not person.seen_moving:
                    person.seen_moving = True
                    credit = self._young_credit(person)
            elif evidence == ONE and not person.seen_moving:
                person.one_leg_scans += 1
            step = steps[evidence] + credit
            if (
                evidence == NONE
                and one_leg
                and not person.confirmed
                and any(self._walked(m, legs) for m in person.members)
                and float(self._static(person.mean[None, :2])[0]) <= p.arrival_slack
            ):
                step = p.walked_miss
            person.llr = min(max(person.llr + step, p.llr_min), p.llr_max)
            person.scans += 1
            for leg in seen:
                person.signature.add(leg.width)
            if z is not None:
                person.last_seen = stamp
                rows.append((person, z, std))
        if rows:
            meas_covs = self._meas_covs([r[2] for r in rows])
            means, covs = kalman.update_batch(
                np.array([r[0].mean for r in rows]),
                np.array([r[0].cov for r in rows]),
                np.array([r[1] for r in rows]),
                meas_covs,
            )
            # travel counts only off static places: hopping between static posts is not walking
            # (asked only of people who have not yet travelled min_travel: travelled is only
            # compared with it)
            walking = [i for i, r in enumerate(rows) if r[0].travelled < p.min_travel]
            static = (
                dict(zip(walking, self._static(means[walking, :2]).tolist(), strict=True))
                if walking
                else {}
            )
            xy = means[:, :2].tolist()
            for i, (person, _, _) in enumerate(rows):
                person.mean, person.cov = means[i], covs[i]
                x, y = xy[i]
                if i in static:
                    self._static_now[person.person_id] = static[i]
                    if static[i] <= p.static_time:
                        bx, by = person.born_at.tolist()
                        person.travelled = max(person.travelled, math.hypot(x - bx, y - by))
                ax, ay = person.arrived[1].tolist()
                if math.hypot(x - ax, y - ay) >= p.min_travel:
                    person.arrived = (stamp, person.mean[:2].copy())

    def _births(self, legs: Mapping[int, LegObservation], stamp: float) -> None:
        p = self.params
        owned = {m for person in self.persons.values() for m in person.members}
        free = sorted(
            (leg for leg in legs.values() if leg.detected and leg.track_id not in owned),
            key=lambda leg: leg.track_id,
        )
        used: set[int] = set()
        if len(free) >= 2:
            pos = np.array([leg.position for leg in free], dtype=np.float64)
            dist = np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=2)
            ii, jj = (dist < p.pair_distance).nonzero()  # (row by row: as np.triu's)
            upper = ii < jj
            ii, jj = ii[upper], jj[upper]
            widths = np.array(
                [
                    spread(free[int(i)], free[int(j)], p.min_speed)
                    for i, j in zip(ii, jj, strict=True)
                ]
            )
            for k in np.argsort(widths, kind="stable"):
                a, b = free[int(ii[k])], free[int(jj[k])]
                if a.track_id in used or b.track_id in used or widths[k] > p.max_spread:
                    continue
                if not 0.5 * (a.score + b.score) > p.birth_min_score:
                    continue
                used.update((a.track_id, b.track_id))
                self._new(0.5 * (a.position + b.position), [a.track_id, b.track_id], stamp)
        for leg in free:
            if leg.wide and leg.track_id not in used:
                used.add(leg.track_id)
                self._new(leg.position, [leg.track_id], stamp)
        if self._one_leg_on():
            # a leg within pair_distance of a person is most likely its other leg: no birth
            near = [q.mean[:2].tolist() for q in self.persons.values()]
            for leg in free:
                lx, ly = leg.position.tolist()
                if any(math.hypot(lx - x, ly - y) < p.pair_distance for x, y in near):
                    continue
                if leg.track_id not in used and leg.score > p.one_leg_min_score:
                    used.add(leg.track_id)
                    evidence = TWO if self._moves(leg) else ONE
                    born = self._new(
                        leg.position, [leg.track_id], stamp, float(self._llr[evidence])
                    )
                    born.seen_moving = evidence == TWO
                    born.one_leg_scans = int(evidence == ONE)

    def _new(
        self, position: FloatArray, members: list[int], stamp: float, llr: float | None = None
    ) -> PersonTrack:
        p = self.params
        mean, cov = kalman.initiate(position, np.eye(2) * p.pair_std**2, p.init_velocity_std)
        pid = next(self._ids)
        person = self.persons[pid] = PersonTrack(
            person_id=pid,
            mean=mean,
            cov=cov,
            stamp=stamp,
            members=members,
            llr=float(self._llr[TWO]) if llr is None else llr,
            last_seen=stamp,
            born_at=position.copy(),
            born_stamp=stamp,
            arrived=(stamp, position.copy()),
        )
        return person

    def _merge(self) -> None:
        """Of two people closer than ``merge_distance``, the confirmed, then higher-scored,
        then older one stays; the other's legs go to it."""
        p = self.params
        if len(self.persons) < 2:
            return
        if _all_apart([q.mean[:2].tolist() for q in self.persons.values()], p.merge_distance):
            return
        ps = sorted(self.persons.values(), key=lambda q: (not q.confirmed, -q.llr, q.person_id))
        xy = np.array([q.mean[:2] for q in ps], dtype=np.float64)
        close = np.hypot(*(xy[:, None, :] - xy[None, :, :]).transpose(2, 0, 1)) < p.merge_distance
        if not (close & ~np.eye(len(ps), dtype=bool)).any():  # nobody near anybody else
            return
        kept: list[int] = []
        for i, q in enumerate(ps):
            near = close[i, kept]
            if not near.any():
                kept.append(i)
                continue
            host = ps[kept[int(np.argmax(near))]]
            for m in q.members:
                if len(host.members) < 2 and m not in host.members:
                    host.members.append(m)
            del self.persons[q.person_id]

    def _count_posts(self, legs: Mapping[int, LegObservation]) -> None:
        """Count, for each confirmed person that has not travelled ``min_travel``, this scan
        when three or more of its own or free legs are detected within ``furniture_radius``
        of it, it is slower than ``furniture_speed`` or these legs slower than
        ``furniture_leg_speed``; remember its place once judged furniture
        (``furniture_scans``)."""
        p = self.params
        if p.furniture_scans == 0:
            return
        still = [  # (a candidate's velocity is not known yet: counted once confirmed)
            q for q in self.persons.values() if q.confirmed and q.travelled < p.min_travel
        ]
        seen = [leg for leg in legs.values() if leg.detected]
        if not still or len(seen) < 3:
            return
        owner = {m: q.person_id for q in self.persons.values() for m in q.members}
        xy = np.array([leg.position for leg in seen])
        d = np.array([q.mean[:2] for q in still])[:, None, :] - xy[None, :, :]
        near = np.einsum("mnk,mnk->mn", d, d) <= p.furniture_radius**2
        for q, row in zip(still, near, strict=True):
            # (a leg of another person, a neighbour in a crowd, is not a post)
            posts = [
                seen[j]
                for j in row.nonzero()[0].tolist()
                if owner.get(seen[j].track_id, q.person_id) == q.person_id
            ]
            if len(posts) < 3:
                continue
            # (a chair's person can move fast while its legs hop between posts that stand)
            vx, vy = q.mean[2:4].tolist()
            if vx * vx + vy * vy < p.furniture_speed**2 or all(
                math.hypot(*leg.velocity.tolist()) < p.furniture_leg_speed for leg in posts
            ):
                q.posts += 1
                if q.posts == p.furniture_scans:
                    x, y = q.mean[:2].tolist()
                    self._furniture.append((x, y))

    def _on_furniture_place(self, person: PersonTrack) -> bool:
        """Whether ``person`` is within ``furniture_radius`` of a place judged furniture that
        is still static (the static world model answers more than 0 s: not once the thing
        has gone, nor without a model or once it is dropped, e.g. on a laser that moves
        without poses, where places in the sensor frame move with it)."""
        x, y = person.mean[:2].tolist()
        r = self.params.furniture_radius
        near = [(fx, fy) for fx, fy in self._furniture if math.hypot(x - fx, y - fy) <= r]
        return bool(near) and bool((self._static(np.array(near)) > 0.0).any())

    def _confirm_and_delete(self, stamp: float) -> None:
        p = self.params
        # candidates with enough evidence, and confirmed people never seen walking: both
        # are (or stay) confirmed unless they stand on cells static for static_time
        # people seen walking are asked too: one standing where it was static long before
        # it came there is a track that slid onto furniture
        # (a person that has travelled min_travel and moves faster than min_speed is not
        # blocked whatever its place: not asked)
        ask = [
            q
            for q in self.persons.values()
            if (q.confirmed or q.llr >= p.llr_confirm)
            and (q.travelled < p.min_travel or math.hypot(*q.mean[2:4].tolist()) < p.min_speed)
        ]
        blocked: set[int] = set()
        if ask and self.static_model is not None:
            # people updated in this scan were asked there (their means have not moved since)
            known = self._static_now
            new = [q for q in ask if q.person_id not in known]
            if new:
                values = self._static(np.array([q.mean[:2] for q in new])).tolist()
                known.update(zip((q.person_id for q in new), values, strict=True))
            static = [known[q.person_id] for q in ask]
            blocked = {
                q.person_id
                for q, s in zip(ask, static, strict=True)
                if s > p.static_time
                and (
                    q.travelled < p.min_travel
                    or (
                        s > stamp - q.arrived[0] + p.arrival_slack
                        and math.hypot(*q.mean[2:4].tolist()) < p.min_speed
                    )
                )
            }
        if p.furniture_scans > 0:
            blocked.update(
                q.person_id
                for q in self.persons.values()
                if q.travelled < p.min_travel
                and (q.posts >= p.furniture_scans or self._on_furniture_place(q))
            )
        for q in self.persons.values():
            if q.person_id in blocked:
                q.confirmed = False
            elif not q.confirmed and q.llr >= p.llr_confirm:
                q.confirmed = True
                if q.public_id is None:
                    q.public_id = next(self._public_ids)
                    self.persons_created += 1
                    q.confirmed_at = stamp
                    q.pending = p.reid.enabled
        self._reidentify(stamp)
        for pid in list(self.persons):
            q = self.persons[pid]
            unseen = stamp - q.last_seen
            if q.confirmed:
                if unseen > p.max_coast:
                    assert q.public_id is not None
                    seen = q.seen_before + q.last_seen - q.confirmed_at
                    self.reid.remember(
                        DormantIdentity(
                            q.public_id, q.mean[:2].copy(), q.last_seen, q.signature, seen
                        )
                    )
                    del self.persons[pid]
            elif q.llr < p.llr_delete or unseen > p.unconfirmed_coast:
                del self.persons[pid]

    def _reidentify(self, stamp: float) -> None:
        """Match the new people whose signature is ready (``reid.min_samples`` widths, or
        ``reid.decide_time`` after confirmation) to the dormant identities; a matched person
        takes the identity's id, signature and tracked time from now on."""
        self.reid.forget_old(stamp)
        ready = [
            q
            for q in self.persons.values()
            if q.pending and q.confirmed and self.reid.ready(q.signature, q.confirmed_at, stamp)
        ]
        if not ready:
            return
        given = self.reid.give_back(
            [
                Candidate(q.person_id, q.mean[:2].copy(), stamp, q.signature, q.born_stamp)
                for q in ready
            ]
        )
        for q in ready:
            q.pending = False
            d = given.get(q.person_id)
            if d is not None:
                q.public_id = d.identity
                q.signature = d.signature.merged(q.signature)
                q.seen_before = d.seen_for

    def update(
        self, legs: Mapping[int, LegObservation], stamp: float, max_report_unseen: float
    ) -> list[Track]:
        """Advance to ``stamp`` [s] with this scan's leg tracks; returns the confirmed people
        whose last leg detection is at most ``max_report_unseen`` [s] old."""
        self._static_now = {}
        self._stamp = stamp
        if self.params.one_leg_birth and self.world_frame:
            self._record_paths(legs, stamp)
        self._predict(stamp)
        self._release(legs)
        self._join(legs)
        self._update_people(legs, stamp)
        self._births(legs, stamp)
        self._merge()
        self._count_posts(legs)
        self._confirm_and_delete(stamp)
        out: list[Track] = []
        for pid in sorted(self.persons):
            q = self.persons[pid]
            if not q.confirmed or stamp - q.last_seen > max_report_unseen:
                continue
            assert q.public_id is not None
            out.append(
                Track(
                    track_id=q.public_id,
                    kind="person",
                    position=q.mean[:2],
                    velocity=q.mean[2:4],
                    covariance=q.cov[:2, :2],
                    score=1.0 / (1.0 + math.exp(-q.llr)),
                    members=tuple(sorted(q.members)),
                )
            )
        return out


def _all_apart(xy: list[list[float]], distance: float) -> bool:
    """Whether every two of the positions ``xy`` (N lists ``[x, y]`` [m]) are at least
    ``distance`` [m] apart along x or along y, so that no ``np.hypot`` of their differences
    is below ``distance`` (a rounded hypot is never below the larger leg): the merge's
    "nobody near anybody" without its arrays. False when unsure (a pair closer than
    ``distance`` along both axes, or NaN in both). Sorted by x, each position is compared
    only with those less than ``distance`` to its right (all pairs when an x is NaN)."""
    if any(math.isnan(x) for x, _ in xy):
        for i, (ax, ay) in enumerate(xy):
            for bx, by in xy[i + 1 :]:
                if not (abs(ax - bx) >= distance or abs(ay - by) >= distance):
                    return False
        return True
    ordered = sorted(xy)
    for i, (ax, ay) in enumerate(ordered):
        for bx, by in ordered[i + 1 :]:
            if bx - ax >= distance:  # (= abs(ax - bx): bx >= ax)
                break
            if not abs(ay - by) >= distance:
                return False
    return True


def leg_observations(
    families: Sequence[tuple[int, FloatArray, float, int]],
    segments_points: Sequence[FloatArray],
    scores: FloatArray,
    params: PersonTrackParams,
) -> dict[int, LegObservation]:
    """Leg observations from ``(family, state (x, y, vx, vy), unseen_for, detection index or
    -1)`` of
    the best hypothesis's leg tracks and this scan's detected segments' points (sensor
    frame, empty when the detector gives none) and detector scores."""
    out: dict[int, LegObservation] = {}
    n_seg, score_list = len(segments_points), scores.tolist()
    for fam, pos, unseen, j in families:
        if j < 0:
            out[fam] = LegObservation(fam, pos[:2], False, unseen, j, False, pos[2:4])
            continue
        score = score_list[j] if j < len(score_list) else math.nan
        wide = j < n_seg and segment_holds_two_legs(segments_points[j], score, params)
        width = leg_width(segments_points[j]) if j < n_seg and not wide else math.nan
        out[fam] = LegObservation(fam, pos[:2], True, unseen, j, wide, pos[2:4], score, width)
    return out
