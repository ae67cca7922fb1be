"""Estimators for learning tracker parameters by counting events (000 Sec. 3.4, 4.6).

000 learns its probabilities "by counting the related events in the ground truth and dividing
by the total number of these events" (Sec. 4.6). With a finite count a category that never
happened would get probability 0, which the trackers cannot take (a log of 0); the
estimators here therefore add half an event to every category (the Jeffreys prior):
``p_i = (k_i + 1/2) / (n + K/2)`` for K categories, ``rate = (k + 1/2) / exposure``. The
estimate stays inside (0, 1), the categories still sum to 1, and with many events it
equals the plain ratio.

An estimate needs a minimum number of events (``min_events``); below it a
:class:`NotEnoughEventsError` says how many were counted and how many are needed.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.errors import LaserPeopleError

FloatArray = NDArray[np.float64]

PRIOR = 0.5
"""Events added to every category (Jeffreys prior)."""

UNLEARNED = "none"
"""Key of a :func:`multinomial` category that is counted but is no parameter (e.g. the
person-scans with no leg seen, the rest of ``p_two`` and ``p_one``): its estimate is not
written, and errors do not name it."""


class FitError(LaserPeopleError):
    """Parameters cannot be learned from the data given."""


class NotEnoughEventsError(FitError):
    """Too few events were counted to estimate a parameter."""


@dataclass(frozen=True)
class Estimate:
    """One learned parameter.

    Attributes:
        key: Dotted name in the tracker's TOML section (``p_det_free``, ``kalman.accel_psd``).
        value: The learned value.
        note: What was counted, for the TOML comment (e.g. ``"812 of 1024 free leg-scans"``).
        events: Number of events the estimate rests on.
    """

    key: str
    value: float
    note: str
    events: int


def need(events: int, min_events: int, what: str, keys: Sequence[str]) -> None:
    """Raise :class:`NotEnoughEventsError` if ``events < min_events``."""
    if events < min_events:
        raise NotEnoughEventsError(
            f"too few {what} to learn {', '.join(keys)}: {events} counted, at least "
            f"{min_events} needed",
            hint="give more or longer labelled recordings, or lower --min-events",
        )


def multinomial(
    counts: Mapping[str, int], what: str, min_events: int, prior: float = PRIOR
) -> list[Estimate]:
    """Probabilities of K exclusive categories from their counts (Jeffreys estimate).

    Args:
        counts: Key -> events of that category (the keys become the estimates' keys).
        what: What one event is, plural, for notes and errors (``"free leg-scans"``).
        min_events: Least total number of events.
        prior: Events added to each category.

    Returns:
        One estimate per key, ``(k_i + prior) / (n + K prior)``; they sum to 1.
    """
    keys = list(counts)
    n = int(sum(counts.values()))
    need(n, min_events, what, [k for k in keys if k != UNLEARNED])
    denom = n + prior * len(keys)
    return [Estimate(k, (counts[k] + prior) / denom, f"{counts[k]} of {n} {what}", n) for k in keys]


def rate(
    key: str,
    count: int,
    exposure: float,
    what: str,
    per: str,
    exposure_events: int,
    min_events: int,
    prior: float = PRIOR,
) -> Estimate:
    """A Poisson rate ``(count + prior) / exposure`` (e.g. false alarms per m^2 per scan).

    Args:
        key: Parameter name.
        count: Events counted.
        exposure: Total exposure (e.g. m^2 x scans summed over scans).
        what: The events, plural.
        per: The exposure's unit for the note (``"m^2 scans"``).
        exposure_events: Units of exposure checked against ``min_events`` (e.g. scans).
        min_events: Least ``exposure_events``.
    """
    need(exposure_events, min_events, f"scans ({what})", [key])
    if not exposure > 0:
        raise FitError(f"no exposure to learn {key} from ({what})", hint="the scans see nothing")
    return Estimate(
        key,
        (count + prior) / exposure,
        f"{count} {what} in {exposure:.6g} {per}",
        exposure_events,
    )


def quantile(key: str, values: Sequence[float], q: float, what: str, min_events: int) -> Estimate:
    """The ``q`` quantile of ``values`` (a gate that lets ``q`` of the cases through)."""
    arr = np.asarray(values, dtype=np.float64)
    arr = arr[np.isfinite(arr)]
    need(int(arr.size), min_events, what, [key])
    return Estimate(
        key,
        float(np.quantile(arr, q)),
        f"{q:g} quantile of {arr.size} {what}",
        int(arr.size),
    )


@dataclass
class AccelTally:
    """Sums for the white-noise acceleration estimate of a trajectory's process noise.

    For the continuous white-noise acceleration model with power spectral density q per axis
    (the model of :mod:`laserpeople.tracking.kalman`), three samples x0, x1, x2 at times t0,
    t1, t2 (h1 = t1 - t0, h2 = t2 - t1) give the change of mean velocity
    ``d = (x2 - x1) / h2 - (x1 - x0) / h1 = int a(s) w(s) ds`` with the triangular weight
    ``w`` (``(s - t0)/h1`` on [t0, t1], ``(t2 - s)/h2`` on [t1, t2]), so
    ``E[d^2] = q (h1 + h2) / 3`` per axis. Pooled over triples and both axes:
    ``q = sum d^2 / sum (2 (h1 + h2) / 3)``.

    Attributes:
        sum_sq: Sum of d^2 over triples and axes [m^2/s^2].
        weight: Sum of 2 (h1 + h2) / 3 [s].
        triples: Triples counted.
    """

    sum_sq: float = 0.0
    weight: float = 0.0
    triples: int = 0

    def add(self, positions: FloatArray, stamps: FloatArray) -> None:
        """Add the consecutive triples of one trajectory: positions (T, 2) [m] at stamps (T,)
        [s], strictly increasing."""
        x = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
        t = np.asarray(stamps, dtype=np.float64).reshape(-1)
        if x.shape[0] < 3:
            return
        h = np.diff(t)
        if not (h > 0).all():
            raise FitError("trajectory stamps must increase strictly")
        v = np.diff(x, axis=0) / h[:, None]
        d = np.diff(v, axis=0)
        ok = np.isfinite(d).all(axis=1)
        self.sum_sq += float(np.sum(d[ok] ** 2))
        self.weight += float(np.sum(2.0 * (h[:-1] + h[1:])[ok] / 3.0))
        self.triples += int(np.count_nonzero(ok))

    def merge(self, other: AccelTally) -> AccelTally:
        """The sums of both tallies."""
        return AccelTally(
            self.sum_sq + other.sum_sq, self.weight + other.weight, self.triples + other.triples
        )

    def estimate(self, key: str, what: str, min_events: int) -> Estimate:
        """The pooled power spectral density q [m^2/s^3]."""
        need(self.triples, min_events, f"{what} (position triples)", [key])
        if not self.weight > 0:
            raise FitError(f"no time span to learn {key} from")
        return Estimate(
            key,
            self.sum_sq / self.weight,
            f"white-acceleration fit to {self.triples} position triples of {what}",
            self.triples,
        )
