"""Re-identification of people who were lost for a long time, from a laser signature.

The person layer (:mod:`laserpeople.tracking.person_tracks`) deletes a person after
``max_coast`` seconds without a leg detection: the person left the scanner's view, or stayed
hidden. Without more, a person who comes back gets a new id. Here a deleted confirmed person
becomes a *dormant identity* for ``max_dormant`` seconds, with the last state and a laser
signature; a newly confirmed person is matched against the dormant identities before it is
given a fresh id.

**Signature.** The width of a single leg's segment, corrected for the beam spacing (the
distance between the first and last point plus one beam step at the leg's range,
:func:`leg_width`), averaged over every scan of the person (Welford's running mean and
variance). On the real person-following recording of the leg_tracker benchmark the median
widths of the five people seen lay between 0.138 and 0.166 m with a per-scan spread of
~0.02 m; leg spacing, speed and step figures vary with the gait and, in the sensor frame of
a moving robot, with the robot's motion, so they are not used. Widths need the detections'
segments (the shipped detectors give them; detections without segments, e.g. read back from
a CSV, give no widths, so nobody is remembered and re-identification does nothing).

**Likelihood.** For a newly confirmed person ``n`` and a dormant identity ``d`` the log
likelihood ratio of "same person" against "a stranger" is the sum of

- ``prior_llr``: log prior odds that a new person is one given lost identity;
- the signature term, the two-sample test of Gaussian means: with the difference of the
  mean widths ``delta``, their sample variances ``V = s_n^2/k_n + s_d^2/k_d + 2
  signature_floor^2`` (a floor for what varies between sightings of one person: range,
  incidence, clothing in motion) and the spread of leg widths between people
  ``population_std``; the variance of a mean is the sample variance (at least
  ``width_std^2``) over the count::

      llr_sig = log N(delta; 0, V) - log N(delta; 0, V + 2 population_std^2)

  (0 when either has no width: no signature, no evidence);
- the prior lowered for identities seen only briefly: ``+ min(0, log(seen_for /
  familiar_time))`` (a passer-by seen for 3 s rarely comes back; the followed person or
  someone talking to the robot does);
- the motion gate: an identity seen after the new person was born is someone else; and the
  new person must be within ``gate_distance + max_speed * gap`` of the
  identity's last position (``gap`` = time since it was last seen), else the pair is
  infeasible. Beyond a few seconds the gate covers the whole view; the signature decides.

**When.** A newly confirmed person is reported with a fresh id at once, and matched when it
has ``min_samples`` widths or ``decide_time`` after its confirmation, whichever comes first;
when matched, its id becomes the dormant identity's from then on (one id change in the
output, instead of a second identity for the rest of the recording).

**Assignment.** The new people of one scan and the dormant identities are assigned by the
Hungarian algorithm (:func:`scipy.optimize.linear_sum_assignment`) on ``-llr``, each new
person also having a "stranger" column of llr 0. A pair is accepted only when the posterior
of that identity among the stranger and every feasible dormant identity,
``exp(llr) / (1 + sum_d exp(llr_d))``, reaches ``min_posterior``: an ambiguous match (two
lost people with the same legs) is a new id rather than a wrong one.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.lazy_scipy import linear_sum_assignment

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class ReidentifyParams:
    """Re-identification of people lost for long (people policy ``tracks``)."""

    config_section = "reidentify"

    enabled: bool = param(
        True,
        "measured (docs/people-benchmarks.md): the real followed person leaves the view for 86 "
        "s; identity recall 0.66 -> 0.98",
        "keep deleted people as dormant identities and give them back to people who return",
    )
    max_dormant: float = param(
        120.0,
        "assumption: a person who walked out of view returns within about two minutes "
        "(the dev recording: 86 s)",
        "a dormant identity is forgotten after this long unseen",
        "s",
    )
    min_samples: int = param(
        20,
        "assumption: the mean of 20 widths with ~0.02 m per-scan spread is within ~0.005 m; "
        "with 4 widths a real stranger (mean 0.166 m over its track) looked like the "
        "followed person (0.149 vs 0.143 m) on the dev recording",
        "leg widths a new person needs before it is matched, and a deleted person before "
        "it is remembered",
    )
    decide_time: float = param(
        5.0,
        "assumption: a walker shows ~20 leg widths in 2-3 s",
        "a new person with fewer widths is matched with what it has this long after its "
        "confirmation",
        "s",
    )
    width_std: float = param(
        0.02,
        "real person-following recording (leg_tracker benchmark): per-scan spread of one "
        "person's leg widths 0.014-0.03 m",
        "lower bound of the per-scan standard deviation of a leg width",
        "m",
    )
    population_std: float = param(
        0.02,
        "measured (docs/people-benchmarks.md): median leg widths of five real people 0.138-0.166 m",
        "spread of mean leg widths between people",
        "m",
    )
    signature_floor: float = param(
        0.008,
        "the same recording: one person's median width falls from 0.148 m at 1 m range to "
        "0.135 m at 2 m",
        "standard deviation of one person's mean width between sightings",
        "m",
    )
    prior_llr: float = param(
        0.0,
        "assumption: a new person is as likely one given lost person as a stranger",
        "log prior odds that a new person is a given dormant identity seen for at least "
        "familiar_time",
    )
    familiar_time: float = param(
        30.0,
        "assumption: people who stay around (a followed person, someone talking to the "
        "robot) come back; passers-by seen for a few seconds rarely do",
        "an identity seen for t < this has its prior odds scaled by t / familiar_time",
        "s",
    )
    min_posterior: float = param(
        0.667,
        "assumption: odds of 2:1 (0.6 gave a stranger the followed person's id on the dev "
        "recording: leg widths 0.154 vs 0.143 m after 20 scans)",
        "posterior of the best dormant identity needed to give its id back",
    )
    max_speed: float = param(
        3.0,
        "assumption: a brisk walk (~1.5 m/s) plus the robot's own motion in the sensor frame",
        "the motion gate grows by this per second since the identity was last seen",
        "m/s",
    )
    gate_distance: float = param(
        1.0,
        "assumption: about the evaluation gate and a person's extent",
        "the motion gate's radius at zero gap",
        "m",
    )

    def __post_init__(self) -> None:
        for name in (
            "max_dormant",
            "population_std",
            "signature_floor",
            "width_std",
            "max_speed",
            "familiar_time",
        ):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be positive")
        if self.gate_distance < 0 or self.min_samples < 1 or self.decide_time < 0:
            raise ValueError("need gate_distance >= 0, min_samples >= 1, decide_time >= 0")
        if not 0.5 <= self.min_posterior < 1.0:
            raise ValueError("min_posterior must be in [0.5, 1)")


def leg_width(points: FloatArray) -> float:
    """Width [m] of a leg's segment with ``points`` (n, 2) [m] in the sensor frame, in scan
    order: the first-to-last distance plus one beam step at the segment's range (a segment
    of n beams spans n - 1 steps of a leg that fills n; the step is the angle between the
    first and last point over n - 1, the range their mean distance). NaN for fewer than 2
    points."""
    n = points.shape[0]
    if n < 2:
        return math.nan
    x0, y0 = float(points[0, 0]), float(points[0, 1])
    x1, y1 = float(points[-1, 0]), float(points[-1, 1])
    angle = math.atan2(abs(x0 * y1 - y0 * x1), x0 * x1 + y0 * y1)
    rng = 0.5 * (math.hypot(x0, y0) + math.hypot(x1, y1))
    return math.hypot(x1 - x0, y1 - y0) + rng * angle / (n - 1)


@dataclass
class Signature:
    """Running mean and variance of a person's leg widths (Welford 1962).

    Attributes:
        count: Widths so far.
        mean: Their mean [m].
        m2: Sum of squared deviations from the mean [m^2].
    """

    count: int = 0
    mean: float = 0.0
    m2: float = 0.0

    def add(self, width: float) -> None:
        """Add one width [m] (NaN is ignored)."""
        if not math.isfinite(width):
            return
        self.count += 1
        d = width - self.mean
        self.mean += d / self.count
        self.m2 += d * (width - self.mean)

    def merged(self, other: Signature) -> Signature:
        """The signature of both sets of widths (Chan et al.'s pairwise update)."""
        n = self.count + other.count
        if n == 0:
            return Signature()
        d = other.mean - self.mean
        mean = self.mean + d * other.count / n
        m2 = self.m2 + other.m2 + d * d * self.count * other.count / n
        return Signature(n, mean, m2)

    def variance_of_mean(self, min_std: float) -> float:
        """Variance of the mean [m^2]: the unbiased sample variance, at least ``min_std^2``,
        over the count (inf without widths)."""
        if self.count == 0:
            return math.inf
        var = self.m2 / (self.count - 1) if self.count > 1 else 0.0
        return max(var, min_std**2) / self.count


def signature_llr(a: Signature, b: Signature, params: ReidentifyParams) -> float:
    """Log likelihood ratio of "same person" against "two people" for two signatures (see
    the module docstring); 0 when either has no width."""
    if min(a.count, b.count) == 0:
        return 0.0
    s = params.width_std
    v_same = a.variance_of_mean(s) + b.variance_of_mean(s) + 2.0 * params.signature_floor**2
    v_diff = v_same + 2.0 * params.population_std**2
    d2 = (a.mean - b.mean) ** 2
    return 0.5 * (math.log(v_diff / v_same) - d2 / v_same + d2 / v_diff)


@dataclass
class DormantIdentity:
    """A person who was deleted, kept for re-identification.

    Attributes:
        identity: The reported id.
        position: Last estimated position (2,) [m] in the tracking frame.
        last_seen: Time [s] of its last leg detection.
        signature: Its leg widths.
        seen_for: How long it was tracked [s], summed over its re-identifications.
    """

    identity: int
    position: FloatArray
    last_seen: float
    signature: Signature
    seen_for: float = 0.0

    def prior_llr(self, params: ReidentifyParams) -> float:
        """Log prior odds of this identity returning: ``prior_llr``, lowered by
        log(seen_for / familiar_time) for identities seen for less than familiar_time."""
        t = max(self.seen_for, 1e-3)
        return params.prior_llr + min(0.0, math.log(t / params.familiar_time))


@dataclass(frozen=True)
class Candidate:
    """A newly confirmed person to be matched.

    Attributes:
        key: The caller's handle (the person's internal id).
        position: Position (2,) [m] in the tracking frame.
        stamp: Time [s].
        signature: Its leg widths so far.
        born: Time [s] it was first seen: only identities last seen before can be it.
    """

    key: int
    position: FloatArray
    stamp: float
    signature: Signature
    born: float = -math.inf


class Reidentifier:
    """Dormant identities and their matching to new people (see the module docstring).

    Attributes:
        dormant: Identity -> dormant identity.
        reidentified: Identities given back so far.
    """

    def __init__(self, params: ReidentifyParams) -> None:
        self.params = params
        self.dormant: dict[int, DormantIdentity] = {}
        self.reidentified = 0

    def remember(self, identity: DormantIdentity) -> None:
        """Keep a deleted person (when enabled and its signature has ``min_samples``)."""
        if self.params.enabled and identity.signature.count >= self.params.min_samples:
            self.dormant[identity.identity] = identity

    def ready(self, signature: Signature, since: float, stamp: float) -> bool:
        """Whether a new person first reported at ``since`` [s] is matched at ``stamp`` [s]:
        its ``signature`` has ``min_samples`` widths, or ``decide_time`` has passed."""
        p = self.params
        return signature.count >= p.min_samples or stamp - since >= p.decide_time

    def forget_old(self, stamp: float) -> None:
        """Drop identities unseen for longer than ``max_dormant``."""
        limit = self.params.max_dormant
        for k in [k for k, d in self.dormant.items() if stamp - d.last_seen > limit]:
            del self.dormant[k]

    def llr_matrix(
        self, new: Sequence[Candidate], dormant: Sequence[DormantIdentity]
    ) -> FloatArray:
        """Log likelihood ratios (N, D) of new person n being dormant identity d; -inf
        outside the motion gate."""
        p = self.params
        out = np.full((len(new), len(dormant)), -np.inf)
        for i, c in enumerate(new):
            for j, d in enumerate(dormant):
                if d.last_seen >= c.born:
                    continue  # seen at the same time as the new person: someone else
                gap = c.stamp - d.last_seen
                dist = float(np.hypot(*(c.position - d.position)))
                if dist > p.gate_distance + p.max_speed * gap:
                    continue
                out[i, j] = d.prior_llr(p) + signature_llr(c.signature, d.signature, p)
        return out

    def give_back(self, new: Sequence[Candidate]) -> dict[int, DormantIdentity]:
        """:meth:`match` with the identities given back: key -> the dormant identity (its
        id, signature and tracked time) that the new person continues."""
        dormant = dict(self.dormant)
        return {key: dormant[ident] for key, ident in self.match(new).items()}

    def match(self, new: Sequence[Candidate]) -> dict[int, int]:
        """Identities given back to the new people: key -> identity (the rest are
        strangers). Each given identity leaves the dormant set."""
        if not self.params.enabled or not new or not self.dormant:
            return {}
        dormant = list(self.dormant.values())
        llr = self.llr_matrix(new, dormant)
        n, m = llr.shape
        # columns: the dormant identities, then one "stranger" column per new person
        big = 1e9
        cost = np.full((n, m + n), big)
        cost[:, :m] = np.where(np.isfinite(llr), -llr, big)
        cost[np.arange(n), m + np.arange(n)] = 0.0
        rows, cols = linear_sum_assignment(cost)
        out: dict[int, int] = {}
        for i, j in zip(rows.tolist(), cols.tolist(), strict=True):
            if j >= m or not np.isfinite(llr[i, j]):
                continue
            feasible = llr[i][np.isfinite(llr[i])]
            top = float(feasible.max())
            posterior = math.exp(llr[i, j] - top) / (
                math.exp(-top) + float(np.exp(feasible - top).sum())
            )
            if posterior >= self.params.min_posterior:
                out[new[i].key] = dormant[j].identity
        for ident in out.values():
            del self.dormant[ident]
        self.reidentified += len(out)
        return out
