"""Learning the leg and people tracker's parameters by counting events (000 Sec. 3.4).

000 Sec. 3.4: the label probabilities of Table 10 "can be learned from a labeled data set".
Per scan the leg detections are associated with the true legs (an optimal assignment with a
distance gate, :func:`associate`); then every true leg is an *ideal track*: born with its
first detection (a new track), detected in the scans with a matched detection, occluded in
the scans between two detections, and deleted in the scan after its last one (a gap longer
than ``max_gap`` ends the track and the next detection starts a new one, as the tracker's
gate could not bridge it). A leg is *approved* in a scan when its person's other leg has a
live ideal track in the previous scan (a person candidate exists, 000 Sec. 3.3), else
*free*. Counting the labels gives p_det, p_occ, p_del per class (000 eqs. 9-10).
Detections matched to no true leg that recur at one place are the leg tracks the tracker
makes of clutter (:func:`clutter_tracks`): free tracks, born as new tracks; the others are
false alarms. Births and false alarms divided by the scans and the area the laser saw give
lambda_new and lambda_fal per m^2 (000 eq. 5).

Beyond the labels: the white-acceleration process noise of legs and people from the true
trajectories (:class:`~laserpeople.fitting.estimates.AccelTally`), the gate on a leg's
displacement between two detections (``kalman.max_gate_distance``), the distance between
the two legs of one person (``people.pair_distance``, ``person.max_leg_distance``: 000's
theta_d), and the evidence behind the person layer's existence score log(p_e / q_e): how
often an ideal person candidate sees both, one or none of its legs (``people.p_two``,
``p_one``) and how often a candidate on a clutter site sees two, one or no false alarm
(``people.q_two``, ``q_one``), learned together (:func:`candidate_evidence`).

With *followed-person* truth (only one person labelled, positions only) the detections
within ``person_radius`` of the label are taken as that person's legs, both approved: it
gives the approved probabilities, the pair distance and the people's process noise; free
legs, false alarms, new tracks and clutter (so neither p_e nor q_e) cannot be counted there
and keep their defaults.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment

from laserpeople.config import param
from laserpeople.fitting.data import LabelledRecording
from laserpeople.fitting.estimates import (
    UNLEARNED,
    AccelTally,
    Estimate,
    FitError,
    multinomial,
    quantile,
    rate,
)
from laserpeople.tracking.legs import LegTrackerParams

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

DET, OCC, DEL = 0, 1, 2
"""Columns of the label counts: detected, occluded, deleted."""


@dataclass(frozen=True)
class LegFitParams:
    """How events are counted for the leg and people tracker."""

    config_section = "fit_legs"

    leg_gate: float = param(
        0.2,
        "assumption: a detection's centre lies on the leg's visible surface, a leg radius "
        "(0.05-0.09 m) plus noise from the leg's centre",
        "a detection farther than this from a true leg is not that leg",
        "m",
    )
    person_radius: float = param(
        0.5,
        "assumption: a foot is up to half a stride (~0.35 m) from the body centre, plus the "
        "label's own error",
        "followed-person truth: detections this close to the label are the person's legs",
        "m",
    )
    max_gap: float = param(
        1.0,
        "assumption: the leg tracker's gate is capped at kalman.max_gate_distance = 1 m, "
        "about what a leg moves in 1 s",
        "a true leg undetected for longer ends its ideal track; the next detection is new",
        "s",
    )
    gate_quantile: float = param(
        0.99,
        "assumption",
        "learned distance gates let this share of the true cases through",
    )
    person_span: float = param(
        0.5,
        "assumption: hand or automatic labels carry centimetres of noise, which dominates "
        "second differences over 0.1 s (variance 6 sigma^2 / h^2)",
        "time between the samples of a person's trajectory for its process noise",
        "s",
    )
    site_distance: float = param(
        0.5,
        "assumption: the posts of one chair or table (0.3-0.5 m apart) are one place where "
        "a false person may be born",
        "false alarms closer than this (single linkage over the whole recording, world "
        "frame) belong to one clutter site",
        "m",
    )
    min_site_scans: int = param(
        5,
        "assumption: a site that fires in fewer scans does not keep a person candidate",
        "a clutter site needs false alarms in at least this many scans",
        "scans",
    )
    min_events: int = param(
        50, "assumption", "least number of events behind any learned value", "events"
    )

    def __post_init__(self) -> None:
        if self.min_site_scans < 1:
            raise ValueError("min_site_scans must be at least 1")
        if (
            min(
                self.leg_gate,
                self.person_radius,
                self.max_gap,
                self.person_span,
                self.site_distance,
            )
            <= 0
        ):
            raise ValueError("leg_gate, person_radius, max_gap and person_span must be positive")
        if not 0.0 < self.gate_quantile < 1.0:
            raise ValueError("gate_quantile must be in (0, 1)")
        if self.min_events < 1:
            raise ValueError("min_events must be at least 1")


def associate(truth: FloatArray, detections: FloatArray, gate: float) -> tuple[IntArray, IntArray]:
    """Optimal one-to-one assignment of ``truth`` (T, 2) and ``detections`` (M, 2) points
    minimising the summed distance, pairs farther than ``gate`` [m] left out.

    Returns:
        ``(ti, di)``: indices of the matched truth points and their detections.
    """
    t = np.asarray(truth, dtype=np.float64).reshape(-1, 2)
    d = np.asarray(detections, dtype=np.float64).reshape(-1, 2)
    empty = np.empty(0, dtype=np.int64)
    if t.shape[0] == 0 or d.shape[0] == 0:
        return empty, empty
    dist = np.hypot(t[:, None, 0] - d[None, :, 0], t[:, None, 1] - d[None, :, 1])
    cost = np.where(dist <= gate, dist, gate * 1e3 + 1.0)
    ti, di = linear_sum_assignment(cost)
    ok = dist[ti, di] <= gate
    return ti[ok].astype(np.int64), di[ok].astype(np.int64)


@dataclass
class LegEventCounts:
    """Events counted on labelled recordings (summed over recordings with :meth:`merge`).

    Attributes:
        free, approved: Label counts (3,) detected/occluded/deleted of leg-scans per class.
        new: Leg tracks born (full truth only): ideal tracks of true legs and clutter
            tracks.
        clutter_tracks: Of ``new``, the tracks of clutter (:func:`clutter_tracks`).
        false: Detections matched to no true leg (full truth only).
        scans: Scans with full truth (the exposure of the rates).
        area: Visible area summed over those scans [m^2 x scans].
        matched: Detections matched to a true leg (or to the followed person).
        persons: Scans (3,) of ideal person candidates with two, one or no leg detected
            (:func:`candidate_evidence`).
        clutter: Clutter-site-scans (3,) with two or more, one or no false alarm.
        leg_steps: Distances [m] between consecutive detections of one ideal leg track.
        pair_distances: Distances [m] between the two detected legs of one person.
        leg_accel: Process-noise sums of the true leg trajectories.
        person_accel: Process-noise sums of the true person trajectories.
        sources: The data counted.
    """

    free: IntArray = field(default_factory=lambda: np.zeros(3, dtype=np.int64))
    approved: IntArray = field(default_factory=lambda: np.zeros(3, dtype=np.int64))
    new: int = 0
    clutter_tracks: int = 0
    false: int = 0
    scans: int = 0
    area: float = 0.0
    matched: int = 0
    persons: IntArray = field(default_factory=lambda: np.zeros(3, dtype=np.int64))
    clutter: IntArray = field(default_factory=lambda: np.zeros(3, dtype=np.int64))
    leg_steps: list[float] = field(default_factory=list)
    pair_distances: list[float] = field(default_factory=list)
    leg_accel: AccelTally = field(default_factory=AccelTally)
    person_accel: AccelTally = field(default_factory=AccelTally)
    sources: list[str] = field(default_factory=list)

    def merge(self, other: LegEventCounts) -> LegEventCounts:
        """The counts of both."""
        return LegEventCounts(
            self.free + other.free,
            self.approved + other.approved,
            self.new + other.new,
            self.clutter_tracks + other.clutter_tracks,
            self.false + other.false,
            self.scans + other.scans,
            self.area + other.area,
            self.matched + other.matched,
            self.persons + other.persons,
            self.clutter + other.clutter,
            self.leg_steps + other.leg_steps,
            self.pair_distances + other.pair_distances,
            self.leg_accel.merge(other.leg_accel),
            self.person_accel.merge(other.person_accel),
            self.sources + other.sources,
        )

    def summary(self) -> str:
        """One line of the counts."""
        return (
            f"free leg-scans det/occ/del {self.free.tolist()}, approved {self.approved.tolist()}, "
            f"new legs {self.new} ({self.clutter_tracks} on clutter), "
            f"false alarms {self.false} in {self.scans} scans, "
            f"person-scans two/one/no legs {self.persons.tolist()}, clutter-site-scans "
            f"{self.clutter.tolist()}"
        )


def _ideal_tracks(
    scans: Sequence[int], stamps: FloatArray, max_gap: float
) -> list[tuple[int, int]]:
    """Detected scan positions (sorted) of one leg split into ideal tracks ``(first,
    last)`` where detections are more than ``max_gap`` seconds apart."""
    out: list[tuple[int, int]] = []
    for k in scans:
        if out and stamps[k] - stamps[out[-1][1]] <= max_gap:
            out[-1] = (out[-1][0], k)
        else:
            out.append((k, k))
    return out


def count_legs(
    stamps: FloatArray,
    detected: dict[tuple[int, int], dict[int, FloatArray]],
    max_gap: float,
    counts: LegEventCounts,
) -> None:
    """Count the labels of ideal leg tracks.

    Args:
        stamps: Scan times (S,) [s].
        detected: ``(person, leg)`` -> {scan position: detected position (2,)} of every true
            leg's matched detections.
        max_gap: Longest time [s] between two detections of one ideal track.
        counts: Added to (free/approved labels, new, leg_steps).
    """
    n = len(stamps)
    live: dict[tuple[int, int], list[tuple[int, int]]] = {
        leg: _ideal_tracks(sorted(hits), stamps, max_gap) for leg, hits in detected.items()
    }

    def alive(leg: tuple[int, int], k: int) -> bool:
        return any(a <= k <= b for a, b in live.get(leg, ()))

    for leg, tracks in live.items():
        partner = (leg[0], 1 - leg[1])
        hits = detected[leg]
        for first, last in tracks:
            counts.new += 1
            prev = first
            for k in range(first + 1, last + 1):
                cls = counts.approved if alive(partner, k - 1) else counts.free
                if k in hits:
                    cls[DET] += 1
                    step = hits[k] - hits[prev]
                    counts.leg_steps.append(float(math.hypot(step[0], step[1])))
                    prev = k
                else:
                    cls[OCC] += 1
            if last + 1 < n:
                cls = counts.approved if alive(partner, last) else counts.free
                cls[DEL] += 1


def count_full(rec: LabelledRecording, p: LegFitParams) -> LegEventCounts:
    """Events of a recording whose truth labels every person with leg positions."""
    counts = LegEventCounts(sources=[rec.source])
    stamps = np.array([s.stamp for s in rec.scans])
    detected: dict[tuple[int, int], dict[int, FloatArray]] = {}
    leg_paths: dict[tuple[int, int], list[tuple[int, FloatArray]]] = {}
    person_paths: dict[int, list[tuple[int, FloatArray]]] = {}
    false_at: list[tuple[int, FloatArray]] = []
    person_legs: dict[int, dict[int, int]] = {}
    for k, (scan, dets) in enumerate(zip(rec.scans, rec.detections, strict=True)):
        frame = rec.truth.get(scan.index)
        if frame is None:
            continue
        counts.scans += 1
        counts.area += float(rec.areas[k])
        legs = frame.leg_positions.reshape(-1, 2)
        ids = [(int(pid), side) for pid in frame.person_ids for side in (0, 1)]
        ok = np.isfinite(legs).all(axis=1)
        rows = np.flatnonzero(ok)
        ti, di = associate(legs[rows], dets.positions, p.leg_gate)
        counts.matched += int(ti.size)
        counts.false += len(dets) - int(ti.size)
        unmatched = np.setdiff1d(np.arange(len(dets)), di)
        false_at.append((k, dets.positions[unmatched]))
        hit_of: dict[tuple[int, int], FloatArray] = {}
        for t, d in zip(rows[ti].tolist(), di.tolist(), strict=True):
            hit_of[ids[t]] = dets.positions[d]
            detected.setdefault(ids[t], {})[k] = dets.positions[d]
        for j, pid in enumerate(frame.person_ids.tolist()):
            a, b = hit_of.get((pid, 0)), hit_of.get((pid, 1))
            n_legs = (a is not None) + (b is not None)
            if n_legs:
                person_legs.setdefault(pid, {})[k] = n_legs
            if a is not None and b is not None:
                counts.pair_distances.append(float(math.hypot(*(a - b))))
            if np.isfinite(frame.positions[j]).all():
                person_paths.setdefault(pid, []).append((k, frame.positions[j]))
        for t in rows.tolist():
            leg_paths.setdefault(ids[t], []).append((k, legs[t]))
    count_legs(stamps, detected, p.max_gap, counts)
    count_clutter_tracks(false_at, stamps, p, counts)
    for seen in person_legs.values():
        counts.persons += candidate_evidence(seen, stamps, p.max_gap)
    counts.clutter += clutter_evidence(
        false_at, stamps, p.site_distance, p.min_site_scans, p.max_gap
    )
    for path in leg_paths.values():
        _add_paths(counts.leg_accel, path, stamps, 1)
    span = _span_scans(stamps, p.person_span)
    for path in person_paths.values():
        _add_paths(counts.person_accel, path, stamps, span)
    return counts


def clutter_tracks(
    false_at: Sequence[tuple[int, FloatArray]], stamps: FloatArray, gate: float, max_gap: float
) -> list[dict[int, FloatArray]]:
    """False alarms linked scan by scan into the leg tracks the tracker makes of clutter.

    A detection of no true leg that lies within ``gate`` [m] of the last detection of a
    clutter track seen at most ``max_gap`` [s] before (optimal assignment, as for true
    legs) continues that track; any other starts one. Only tracks with detections in two or
    more scans are returned: from its second detection on, such a track explains a
    detection with p_det N(z) (tens per m^2 for a still object) where a false alarm has
    lambda_fal (thousandths per m^2), so the tracker keeps it as a leg track (000 Sec. 3.5:
    "two of the four tracks are due to false alarms extracted in the clutter").

    Args:
        false_at: ``(scan position, positions (F, 2))`` of the false alarms of each scan,
            in scan order, one frame for the whole recording.
        stamps: Scan times (S,) [s].
        gate: Largest distance [m] between consecutive detections of one track.
        max_gap: Longest time [s] between two detections of one track.

    Returns:
        Scan position -> position (2,) of each clutter track's detections.
    """
    tracks: list[dict[int, FloatArray]] = []
    last: list[int] = []  # scan position of each track's last detection
    live: list[int] = []
    for k, xy in false_at:
        live = [i for i in live if stamps[k] - stamps[last[i]] <= max_gap]
        xy = xy.reshape(-1, 2)
        ends = np.array([tracks[i][last[i]] for i in live]).reshape(-1, 2)
        ti, di = associate(ends, xy, gate)
        for t, d in zip(ti.tolist(), di.tolist(), strict=True):
            tracks[live[t]][k] = xy[d]
            last[live[t]] = k
        for d in np.setdiff1d(np.arange(len(xy)), di).tolist():
            live.append(len(tracks))
            tracks.append({k: xy[d]})
            last.append(k)
    return [t for t in tracks if len(t) >= 2]


def count_clutter_tracks(
    false_at: Sequence[tuple[int, FloatArray]],
    stamps: FloatArray,
    p: LegFitParams,
    counts: LegEventCounts,
) -> None:
    """Count the leg tracks the tracker makes of clutter (:func:`clutter_tracks`) as it
    makes them: each is a new track (``lambda_new``), its detections are not false alarms
    (``lambda_fal``), and it is labelled as a free track (no person's other leg).

    In the MHT a detection explained by no track is a new track against a false alarm,
    lambda_new against lambda_fal (000 eq. 14); counting repeated clutter as false alarms
    and never as births makes that ratio the share of true legs among all unexplained
    detections (22 / 4791 on three 60 s demo scenes), below the ratio pruning of the
    tracker, so that no track could start."""
    tracks = clutter_tracks(false_at, stamps, p.leg_gate, p.max_gap)
    tally = LegEventCounts()
    count_legs(stamps, {(-1 - i, 0): t for i, t in enumerate(tracks)}, p.max_gap, tally)
    counts.false -= sum(len(t) for t in tracks)
    counts.new += tally.new
    counts.clutter_tracks += tally.new
    counts.free += tally.free + tally.approved


def candidate_evidence(seen: dict[int, int], stamps: FloatArray, max_gap: float) -> IntArray:
    """Evidence counts (3,) two / one / no leg of one ideal person candidate, the quantity
    whose ratio is the person layer's existence score (``people.p_*`` over ``q_*``).

    Args:
        seen: Scan position -> legs seen there (1 or 2; at least one leg-like detection);
            scans not listed saw none.
        stamps: Scan times (S,) [s].
        max_gap: A candidate lives from a scan with evidence to its last evidence before a
            pause longer than this [s] (as an ideal leg track); its scans after the first
            are counted.
    """
    out = np.zeros(3, dtype=np.int64)
    for first, last in _ideal_tracks(sorted(seen), stamps, max_gap):
        n = np.array([seen.get(k, 0) for k in range(first + 1, last + 1)], dtype=np.int64)
        out += np.bincount(np.clip(2 - n, 0, 2), minlength=3)
    return out


def clutter_evidence(
    false_at: Sequence[tuple[int, FloatArray]],
    stamps: FloatArray,
    distance: float,
    min_scans: int,
    max_gap: float,
) -> IntArray:
    """What a person candidate on clutter sees: the evidence counts (3,) two / one / no
    leg-like detection of ideal candidates on clutter sites (:func:`candidate_evidence`).

    The false alarms of all scans (``(scan position, positions (F, 2))``, one frame for the
    whole recording) are linked by single linkage at ``distance`` into sites; a site with
    false alarms in at least ``min_scans`` scans is a place where candidates live; two or
    more false alarms there in a scan are two-leg evidence, one is one-leg evidence.
    """
    from laserpeople.clustering import single_linkage

    out = np.zeros(3, dtype=np.int64)
    ks = np.concatenate(
        [np.full(len(xy), k, dtype=np.int64) for k, xy in false_at] or [np.empty(0, np.int64)]
    )
    if ks.size == 0:
        return out
    xy = np.concatenate([xy.reshape(-1, 2) for _, xy in false_at])
    site = single_linkage(xy, distance)
    for s in np.unique(site[site >= 0]):
        fired = np.bincount(ks[site == s], minlength=len(stamps))
        scans = np.flatnonzero(fired)
        if scans.size < min_scans:
            continue
        seen = {int(k): min(2, int(fired[k])) for k in scans}
        out += candidate_evidence(seen, stamps, max_gap)
    return out


def count_followed(rec: LabelledRecording, p: LegFitParams) -> LegEventCounts:
    """Events of a recording whose truth labels only followed people (positions only):
    the detections within ``person_radius`` of a label are that person's legs."""
    counts = LegEventCounts(sources=[rec.source])
    stamps = np.array([s.stamp for s in rec.scans])
    position = {s.index: k for k, s in enumerate(rec.scans)}
    paths: dict[int, list[tuple[int, FloatArray]]] = {}
    seen: dict[tuple[int, int], int] = {}
    for index, frame in sorted(rec.truth.items()):
        k = position[index]
        dets = rec.detections[k].positions
        for j, pid in enumerate(frame.person_ids.tolist()):
            label = frame.positions[j]
            if not np.isfinite(label).all():
                continue
            paths.setdefault(pid, []).append((k, label))
            d = np.hypot(*(dets - label).T) if len(dets) else np.empty(0)
            near = np.argsort(d)[: int(np.count_nonzero(d <= p.person_radius))][:2]
            n_legs = int(near.size)
            seen[(pid, k)] = n_legs
            counts.matched += n_legs
            if n_legs == 2:
                counts.pair_distances.append(float(math.hypot(*(dets[near[0]] - dets[near[1]]))))
    span = _span_scans(stamps, p.person_span)
    for pid, path in paths.items():
        _add_paths(counts.person_accel, path, stamps, span)
        # both legs of a followed person are approved: detected or occluded while labelled,
        # deleted after each labelled stretch (the person left the view)
        ks = [k for k, _ in path]
        counts.persons += candidate_evidence(
            {k: seen[(pid, k)] for k in ks if seen[(pid, k)]}, stamps, p.max_gap
        )
        for first, last in _ideal_tracks(ks, stamps, p.max_gap):
            legs = [seen[(pid, k)] for k in ks if first < k <= last]
            counts.approved[DET] += sum(legs)
            counts.approved[OCC] += 2 * len(legs) - sum(legs)
            if last + 1 < len(stamps):
                counts.approved[DEL] += 2
    return counts


def _span_scans(stamps: FloatArray, span: float) -> int:
    """Scans that cover ``span`` seconds at the median scan period (at least 1)."""
    if stamps.size < 2:
        return 1
    period = float(np.median(np.diff(stamps)))
    return max(1, round(span / period)) if period > 0 else 1


def _add_paths(
    tally: AccelTally, path: list[tuple[int, FloatArray]], stamps: FloatArray, step: int
) -> None:
    """Add the runs of consecutive scans of ``path`` (scan position, position) to ``tally``,
    sampled every ``step`` scans."""
    if len(path) < 3:
        return
    ks = np.array([k for k, _ in path])
    xs = np.array([x for _, x in path])
    breaks = np.flatnonzero(np.diff(ks) != 1) + 1
    for run_k, run_x in zip(np.split(ks, breaks), np.split(xs, breaks), strict=True):
        for offset in range(step):
            sel = slice(offset, None, step)
            tally.add(run_x[sel], stamps[run_k[sel]])


def count_events(rec: LabelledRecording, p: LegFitParams) -> LegEventCounts:
    """Events of one recording (full truth needs leg positions)."""
    if rec.followed:
        return count_followed(rec, p)
    if not rec.has_legs:
        raise FitError(
            "the ground truth has no leg positions",
            path=rec.name,
            hint="give a simulated .npz, or label only the followed person (CSV or bag topic)",
        )
    return count_full(rec, p)


@dataclass(frozen=True)
class LearnedParams:
    """Learned values and the tracker parameters that hold them.

    Attributes:
        params: The tracker's parameters with the learned values (others: the base's).
        estimates: Every learned value with what it was counted from.
        kept: Keys not learned, with the reason.
    """

    params: Any
    estimates: tuple[Estimate, ...]
    kept: tuple[tuple[str, str], ...] = ()


def with_learned(params: Any, estimates: Sequence[Estimate]) -> Any:
    """``params`` with the learned values.

    Raises:
        FitError: the values are not valid parameters of the tracker (e.g. a process noise
            of 0 from people who never move).
    """
    try:
        return set_dotted(params, {e.key: e.value for e in estimates})
    except ValueError as exc:
        notes = "; ".join(f"{e.key} = {e.value:.4g} ({e.note})" for e in estimates)
        raise FitError(
            f"the learned values are not valid parameters: {exc}",
            hint=f"learned: {notes[:600]}",
        ) from exc


def set_dotted(params: Any, values: dict[str, float]) -> Any:
    """``params`` with dotted keys (``kalman.accel_psd``) replaced."""
    top: dict[str, Any] = {}
    nested: dict[str, dict[str, float]] = {}
    for key, value in values.items():
        head, _, rest = key.partition(".")
        if rest:
            nested.setdefault(head, {})[rest] = value
        else:
            top[head] = value
    for head, inner in nested.items():
        top[head] = set_dotted(getattr(params, head), inner)
    names = {f.name for f in fields(params)}
    unknown = set(top) - names
    if unknown:
        raise KeyError(f"unknown parameters {sorted(unknown)}")
    return replace(params, **top)


class LegMHTFitter:
    """Learns the leg MHT's probabilities, rates, process noise and gates from labelled
    recordings (scikit-learn style: :meth:`fit` returns the fitter; learned values end in
    ``_``).

    Attributes (after :meth:`fit`):
        counts_: The events counted.
        estimates_: The learned values.
        kept_: Keys left at their base value, with the reason.
        params_: :class:`LegTrackerParams` with the learned values.
    """

    def __init__(
        self, base: LegTrackerParams | None = None, settings: LegFitParams | None = None
    ) -> None:
        self.base = base if base is not None else LegTrackerParams()
        self.settings = settings if settings is not None else LegFitParams()

    def fit(self, recordings: Sequence[LabelledRecording]) -> LegMHTFitter:
        """Count the events of ``recordings`` and estimate the parameters.

        Raises:
            FitError: no recording, truth without legs, or too few events for a value.
        """
        if not recordings:
            raise FitError("no labelled recording to learn from")
        counts = LegEventCounts()
        for rec in recordings:
            counts = counts.merge(count_events(rec, self.settings))
        self.counts_ = counts
        full = any(not r.followed for r in recordings)
        estimates, kept = estimate(counts, self.settings, full)
        self.estimates_ = tuple(estimates)
        self.kept_ = tuple(kept)
        self.params_ = with_learned(self.base, estimates)
        return self

    def learned(self) -> LearnedParams:
        """The result of :meth:`fit`."""
        return LearnedParams(self.params_, self.estimates_, self.kept_)


def estimate(
    c: LegEventCounts, p: LegFitParams, full: bool
) -> tuple[list[Estimate], list[tuple[str, str]]]:
    """Learned values from the counts; ``full``: some recording labels every person (free
    legs, false alarms and new tracks are countable)."""
    m = p.min_events
    out: list[Estimate] = []
    kept: list[tuple[str, str]] = []
    out += multinomial(
        {
            "p_det_approved": int(c.approved[DET]),
            "p_occ_approved": int(c.approved[OCC]),
            "p_del_approved": int(c.approved[DEL]),
        },
        "approved leg-scans",
        m,
    )
    if full:
        out += multinomial(
            {
                "p_det_free": int(c.free[DET]),
                "p_occ_free": int(c.free[OCC]),
                "p_del_free": int(c.free[DEL]),
            },
            "free leg-scans",
            m,
        )
        out.append(rate("lambda_new", c.new, c.area, "new leg tracks", "m^2 scans", c.scans, m))
        out.append(rate("lambda_fal", c.false, c.area, "false alarms", "m^2 scans", c.scans, m))
        out.append(c.leg_accel.estimate("kalman.accel_psd", "true legs", m))
        out.append(
            quantile(
                "kalman.max_gate_distance",
                c.leg_steps,
                p.gate_quantile,
                "steps between detections of a leg",
                m,
            )
        )
    else:
        why = "followed-person truth: other people are not labelled"
        for key in ("p_det_free", "p_occ_free", "p_del_free", "lambda_new", "lambda_fal"):
            kept.append((key, why))
        kept.append(("kalman.accel_psd", "no leg positions in the truth"))
        kept.append(("kalman.max_gate_distance", "no leg identities in the truth"))
    if full:
        # the existence score is log(p_e / q_e): learn both sides or neither
        on_people = multinomial(
            {
                "people.p_two": int(c.persons[0]),
                "people.p_one": int(c.persons[1]),
                UNLEARNED: int(c.persons[2]),
            },
            "person-scans",
            m,
        )
        on_clutter = multinomial(
            {
                "people.q_two": int(c.clutter[0]),
                "people.q_one": int(c.clutter[1]),
                UNLEARNED: int(c.clutter[2]),
            },
            "clutter-site-scans",
            m,
        )
        out += [e for e in on_people + on_clutter if e.key != UNLEARNED]
    else:
        why = (
            "followed-person truth: clutter is not labelled, and the existence score "
            "log(p/q) needs both sides"
        )
        kept += [(k, why) for k in ("people.p_two", "people.p_one", "people.q_two", "people.q_one")]
    pair = quantile(
        "people.pair_distance",
        c.pair_distances,
        p.gate_quantile,
        "distances between the legs of a person",
        m,
    )
    out += [pair, replace(pair, key="person.max_leg_distance")]
    out.append(c.person_accel.estimate("people.accel_psd", "true people", m))
    return out, kept
