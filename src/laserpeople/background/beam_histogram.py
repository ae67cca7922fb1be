"""Per-beam range histograms as the static world of a static laser (004 Sec. 2).

For every beam of every laser the model counts how often each range bin was measured while
learning. Bins seen in at least ``min_fraction`` of the learning scans are *static* (the
wall, a table leg, the far end of a door that is sometimes open); a later return is
background when it falls within ``tolerance`` of a static bin of its beam and foreground
otherwise. People stand in front of walls, never behind them: with ``farthest`` only the
farthest frequent range of a beam (and the bins within twice the tolerance before it) is
static, so a person who stood in view for part of the learning is foreground from the start
(a beam that saw only the person keeps the person's range until it relearns, below).
Learning runs over the first ``learn_seconds`` of the frames it sees (people
walking through are rare in any one bin) or from a separate background recording
(:meth:`BeamHistogramBackground.learn_scans`), and the histograms are saved to and loaded
from ``.npz`` without pickle.

004 Sec. 2 learns the background before tracking and says no more. A person who stands
still while the model learns would stay background for good (and the wall behind them
foreground once they leave). So the model keeps learning per beam after it froze: a return
*farther* than a static bin of its beam proves that nothing static stands there, and when
a beam shows such a farther return steadily (within ``tolerance`` of where it first
appeared, for ``relearn_seconds``), the static bins nearer than it are dropped and its bin
becomes static (the histogram of that beam is rewritten, so a saved model keeps it). A
beam never relearns towards nearer returns: a person who stands still after learning
stays foreground. The price: something static only part of the time (a door that was
closed while learning and stands open for ``relearn_seconds``) is foreground once it
comes back.

A caller that can tell people (``learn_foreground(frame, people, legs)``: the points near
the legs of the people a leg MHT confirms, as ``--background auto`` gives the CSA, ``[csa]
background_people``) marks their returns while the model learns. A bin whose returns lay
on people in at least ``people_share`` of them is not static: a person who stands through
the learning is foreground from the first scan. The wall behind them, never seen, is guessed: on the
straight line between the farthest static returns of the nearest beams without people on
either side, where it lies beyond the person; when no such line exists, the beam relearns
towards the first steady farther return as above. With a guess, the beam relearns only
beyond the guess, so a person who later stands farther along the same beams stays
foreground. A beam that keeps returning the people's range for ``people_settle_seconds``
after learning, never farther, saw something static after all (a leg detection on
furniture) and is learned as static; a beam that saw people at two ranges (someone who
passed in front of the furniture) is watched on at the farther once it returns there.
Returns that only may be people (``legs``: near any leg detection, furniture the detector
fires on too) stay static, but the wall behind them is guessed as well, so that it is
background at once when a person there leaves.
The people counts are saved with the histograms.

A recording on disk can be read whole before it is tracked
(:mod:`laserpeople.pipeline.prelearn`): with :meth:`BeamHistogramBackground.use_whole_recording`
the ranges frequent in the whole recording that lie beyond a beam's static bins of the
learning period are static too (the wall behind a person who stood in view from the start
and left for ``min_fraction`` of the recording), and are written into the histograms when
learning ends.

Shapes: per laser ``counts`` (B, K) int32 for B beams and K range bins of width
``bin_width``; bin k covers ranges [k w, (k + 1) w).
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable
from dataclasses import dataclass, replace
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.errors import LaserPeopleError
from laserpeople.frame import Frame, FrameField
from laserpeople.scan import Layout, PointSet, Pose2D, Scan, same_layout

FORMAT = "laserpeople-beam-histogram"
VERSION = 1


class BackgroundModelError(LaserPeopleError):
    """A background model file is missing, malformed, or does not fit the lasers."""


@dataclass(frozen=True)
class BeamHistogramParams:
    """Parameters of the per-beam histogram background."""

    config_section = "beam_histogram"
    paper_preset = MappingProxyType({"farthest": False})  # 004: every frequent bin is static

    bin_width: float = param(
        0.05, "assumed (004 Sec. 2 gives no numbers)", "width of a range bin", "m"
    )
    learn_seconds: float = param(
        2.0,
        "assumed; 004 Sec. 2 learns the background before tracking",
        "length of the learning period at the start of a recording",
        "s",
    )
    min_fraction: float = param(
        0.1,
        "assumed",
        "a bin measured in at least this fraction of the learning scans is static",
    )
    tolerance: float = param(
        0.10,
        "assumed: range noise of an LMS151 is ~0.03 m; people stand > 0.1 m off walls",
        "a return this close to a static bin is background",
        "m",
    )
    relearn_seconds: float = param(
        0.5,
        "assumed (not in 004): a wall uncovered by a person who stood while learning is "
        "foreground this long; measured on crossing-3 (docs/schenk-tables.md)",
        "a beam whose returns stay farther than its static bins this long relearns: the "
        "nearer static bins are dropped and the farther return becomes static",
        "s",
    )

    farthest: bool = param(
        True,
        "assumed (not in 004): people stand in front of walls, never behind them; measured "
        "on feet-crossing / feet-office (docs/schenk-tables.md)",
        "per beam only the farthest frequent range (bins within twice the tolerance of the "
        "farthest static bin) is static, so that a person who stood in front of the wall "
        "for part of the learning is foreground; false: every frequent bin (004)",
    )

    people_share: float = param(
        0.2,
        "assumed (not in 004): the leg detector finds a person standing 3-7 m away in most "
        "scans; measured on crossing-3 (docs/csa.md)",
        "while learning, a frequent bin of a beam whose returns lay on a person (points the "
        "caller marks, e.g. near leg detections) in at least this share of them is not "
        "static, and a steady farther return of that beam relearns as if it were",
    )

    people_settle_seconds: float = param(
        5.0,
        "assumption (not in 004): the people of crossing-3 leave within 1 s of the "
        "learning; on the real demo bag a leg detection on furniture while learning kept a "
        "place foreground for the whole run (docs/csa.md)",
        "a beam that saw people while learning and keeps returning their range this long "
        "after learning saw something static after all and is learned as static",
        "s",
    )

    def __post_init__(self) -> None:
        if not (0.0 < self.people_share <= 1.0) or self.people_settle_seconds < 0.0:
            raise LaserPeopleError(
                "people_share must be in (0, 1] and people_settle_seconds not negative"
            )
        if not (self.bin_width > 0.0 and math.isfinite(self.bin_width)):
            raise LaserPeopleError(f"bin_width must be positive, got {self.bin_width}")
        if not (0.0 < self.min_fraction <= 1.0):
            raise LaserPeopleError(f"min_fraction must be in (0, 1], got {self.min_fraction}")
        if self.tolerance < 0.0 or self.learn_seconds < 0.0 or self.relearn_seconds < 0.0:
            raise LaserPeopleError(
                "tolerance, learn_seconds and relearn_seconds must not be negative"
            )


@dataclass
class _BeamTable:
    """The histograms of one laser."""

    counts: NDArray[np.int32]  # (B, K)
    scans: int
    seconds: float
    relearned: int = 0  # beams relearned after freezing
    settled: int = 0  # beams on people while learning found static after all
    marked: int = 0  # beams with a bin on people when the static bins were last marked
    people: NDArray[np.int32] | None = None  # (B, K) of counts: returns on people
    legs: NDArray[np.int32] | None = None  # (B, K) of counts: returns near any leg detection
    angles: NDArray[np.float64] | None = None  # (B,) beam angles [rad] in the laser frame
    person_bin: NDArray[np.int64] | None = None  # (B,) nearest bin on people (-1: none)
    settling: NDArray[np.float64] | None = None  # (B,) stamp it was first seen again (nan)
    people_bins: NDArray[np.bool_] | None = None  # (B, K) bins on people, widened
    static: NDArray[np.bool_] | None = None  # (B, K) dilated by the tolerance
    nearest: NDArray[np.int64] | None = None  # (B,) nearest static core bin (K: none)
    candidate: NDArray[np.int64] | None = None  # (B,) bin of a farther return (-1: none)
    since: NDArray[np.float64] | None = None  # (B,) stamp the candidate first appeared
    beyond: NDArray[np.bool_] | None = None  # (B, K) frequent in a whole recording, until frozen

    def finish(self, p: BeamHistogramParams) -> None:
        """Mark static bins and widen them by the tolerance (vectorised over beams)."""
        core = _core(self.counts, self.scans, p, self.people, self.beyond)
        k = core.shape[1]
        on_people = _on_people(self.counts, self.scans, p, self.people)
        seen = core | on_people
        self.nearest = np.where(seen.any(axis=1), np.argmax(seen, axis=1), k).astype(np.int64)
        behind = on_people | _on_people(self.counts, self.scans, p, self.legs)
        if self.angles is not None and behind.any():
            beams, bins = _behind_people(core & ~behind, behind, self.angles, p)
            core[beams, bins] = True
            people = on_people[beams].any(axis=1)  # (the others keep their bin static)
            self.nearest[beams[people]] = bins[people]
        self.static = _dilate(core, math.ceil(p.tolerance / p.bin_width))
        if self.candidate is None or self.since is None:
            self.candidate = np.full(core.shape[0], -1, dtype=np.int64)
            self.since = np.zeros(core.shape[0])
        self.person_bin = np.where(on_people.any(axis=1), np.argmax(on_people, axis=1), -1)
        self.marked = int(np.count_nonzero(self.person_bin >= 0))
        self.settling = np.full(core.shape[0], np.nan)
        self.people_bins = _dilate(on_people, math.ceil(p.tolerance / p.bin_width))

    def settle(
        self,
        beams: NDArray[np.int64],
        bins: NDArray[np.int64],
        stamp: float,
        p: BeamHistogramParams,
    ) -> None:
        """Follow the returns (``beams`` (M,), range ``bins`` (M,)) of one scan on the beams
        that saw people while learning: a beam that keeps returning the people's range
        (within the tolerance; nearer returns, someone passing in front, do not count
        against it) for ``people_settle_seconds`` saw something static after all (a leg
        detection on furniture): its people counts are dropped and its histogram marks it
        static. A beam that saw people at more than one range (a person who passed in
        front of a chair taken for a person) is watched at the nearest: a farther return
        on another range of its people is watched from then on, with the clock started
        afresh. A return farther than every range of its people shows the people have
        left: the beam is no longer watched (someone who later stands on the same place
        stays foreground)."""
        if (
            self.person_bin is None
            or self.settling is None
            or self.people is None
            or self.people_bins is None
        ):
            return
        on = self.person_bin[beams] >= 0
        if not on.any():
            return
        beams, bins = beams[on], bins[on]
        reach = math.ceil(p.tolerance / p.bin_width)
        person = self.person_bin[beams]
        farther = bins > person + reach
        moved = farther & self.people_bins[beams, bins]  # on a farther range of its people
        self.person_bin[beams[moved]] = bins[moved]
        self.settling[beams[moved]] = stamp
        person = self.person_bin[beams]
        same = np.abs(bins - person) <= reach
        start = same & np.isnan(self.settling[beams])
        self.settling[beams[start]] = stamp
        gone = beams[farther & ~moved]  # the people left: they were people
        self.settling[gone] = np.nan
        self.person_bin[gone] = -1
        ripe = beams[same & (stamp - self.settling[beams] >= p.people_settle_seconds)]
        if ripe.size == 0:
            return
        self.people[ripe] = 0
        self._mark(ripe, p)
        self.person_bin[ripe] = -1
        self.settling[ripe] = np.nan
        self.settled += int(ripe.size)

    def _mark(self, rows: NDArray[np.int64], p: BeamHistogramParams) -> None:
        """Static bins and nearest static bin of the beams ``rows`` (M,) anew from their
        histograms (after :meth:`relearn` or :meth:`settle` rewrote them)."""
        assert self.static is not None and self.nearest is not None
        people = None if self.people is None else self.people[rows]
        core = _core(self.counts[rows], self.scans, p, people)
        self.static[rows] = _dilate(core, math.ceil(p.tolerance / p.bin_width))
        k = core.shape[1]
        self.nearest[rows] = np.where(core.any(axis=1), np.argmax(core, axis=1), k)

    def relearn(
        self,
        beams: NDArray[np.int64],
        bins: NDArray[np.int64],
        stamp: float,
        p: BeamHistogramParams,
    ) -> None:
        """Follow the returns (``beams`` (M,), range ``bins`` (M,)) of one scan: a return
        farther than its beam's nearest static bin (by more than the tolerance; itself on a
        static bin or not: a wall the person hid for part of the learning) starts or
        continues that beam's candidate; a candidate that held for ``relearn_seconds``
        replaces the beam's nearer static bins. Vectorised over beams."""
        assert self.static is not None and self.nearest is not None
        assert self.candidate is not None and self.since is not None
        reach = math.ceil(p.tolerance / p.bin_width)
        beyond = bins > self.nearest[beams] + reach
        if not beyond.any():  # (most scans of a still laser: every beam sees its static
            # world, which ends their candidates; what the steps below do then)
            self.candidate[beams] = -1
            return
        cand = self.candidate[beams]
        same = beyond & (cand >= 0) & (np.abs(bins - cand) <= reach)
        fresh = beyond & ~same
        self.candidate[beams[fresh]] = bins[fresh]
        self.since[beams[fresh]] = stamp
        self.candidate[beams[~beyond]] = -1  # the beam sees its static world again
        ripe = beams[same & (stamp - self.since[beams] >= p.relearn_seconds)]
        if ripe.size == 0:
            return
        k_new = self.candidate[ripe]
        cols = np.arange(self.counts.shape[1])
        drop = cols[None, :] < (k_new - reach)[:, None]
        self.counts[ripe] = np.where(drop, 0, self.counts[ripe])
        need = max(1, math.ceil(p.min_fraction * self.scans))
        self.counts[ripe, k_new] = np.maximum(self.counts[ripe, k_new], need)
        for marks in (self.people, self.legs):
            if marks is not None:
                marks[ripe] = np.where(drop, 0, marks[ripe])
                marks[ripe, k_new] = 0
        self._mark(ripe, p)
        self.candidate[ripe] = -1
        self.relearned += int(ripe.size)


def _on_people(
    counts: NDArray[np.int32],
    scans: int,
    p: BeamHistogramParams,
    people: NDArray[np.int32] | None,
) -> NDArray[np.bool_]:
    """Frequent bins (B, K) of ``counts`` (B, K) that were on a person (``people`` (B, K):
    how many of the returns of a bin lay on a person) in at least ``people_share`` of their
    returns (all False without ``people``)."""
    if people is None:
        return np.zeros(counts.shape, dtype=bool)
    frequent = counts >= max(1.0, p.min_fraction * scans)
    return frequent & (people > 0) & (people >= p.people_share * counts)


def _behind_people(
    core: NDArray[np.bool_],
    on_people: NDArray[np.bool_],
    angles: NDArray[np.float64],
    p: BeamHistogramParams,
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """The static world guessed behind the people of the learning period: beams (M,) with
    no static bin beyond their nearest bin on a person (``on_people`` (B, K), ``core``
    (B, K) the static bins) and the bins (M,) where the straight line between the farthest
    static returns of the nearest beams on either side without people (``angles`` (B,)
    [rad]) crosses them, where that is not nearer than the person (a return within the
    tolerance of the line, seen through a gap between legs and itself taken for a leg, is
    the wall)."""
    n, k = core.shape
    idx = np.arange(n)
    has = core.any(axis=1)
    far = np.where(has, k - 1 - np.argmax(core[:, ::-1], axis=1), -1)
    seen = on_people.any(axis=1)
    person = np.where(seen, np.argmax(on_people, axis=1), k)  # the nearest bin on people
    anchor = has & ~seen
    left = np.maximum.accumulate(np.where(anchor, idx, -1))
    right = np.minimum.accumulate(np.where(anchor, idx, n)[::-1])[::-1]
    need = idx[seen & (far <= person) & (left >= 0) & (right < n)]
    if need.size == 0:
        return need, need
    w = p.bin_width
    lo, hi = left[need], right[need]
    r_lo, r_hi = (far[lo] + 0.5) * w, (far[hi] + 0.5) * w
    a_lo, a_hi = angles[lo], angles[hi]
    p_lo = np.stack([r_lo * np.cos(a_lo), r_lo * np.sin(a_lo)], axis=1)
    d = np.stack([r_hi * np.cos(a_hi), r_hi * np.sin(a_hi)], axis=1) - p_lo
    u = np.stack([np.cos(angles[need]), np.sin(angles[need])], axis=1)
    cross_ud = u[:, 0] * d[:, 1] - u[:, 1] * d[:, 0]
    cross_pd = p_lo[:, 0] * d[:, 1] - p_lo[:, 1] * d[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = cross_pd / cross_ud  # range along the beam to the line
    ok = np.isfinite(t) & (t >= person[need] * w - p.tolerance) & (t < k * w)
    return need[ok], (t[ok] / w).astype(np.int64)


def _core(
    counts: NDArray[np.int32],
    scans: int,
    p: BeamHistogramParams,
    people: NDArray[np.int32] | None = None,
    beyond: NDArray[np.bool_] | None = None,
) -> NDArray[np.bool_]:
    """Static bins (B, K) of the histograms ``counts`` (B, K) of ``scans`` scans: bins seen
    in at least ``min_fraction`` of the scans and not on people (:func:`_on_people`), and
    the bins of ``beyond`` (B, K) farther than a beam's farthest of them (by more than
    twice the tolerance); with ``farthest`` only those of them within twice the tolerance
    of each beam's farthest such bin (a beam without one keeps none)."""
    core = counts >= max(1.0, p.min_fraction * scans)
    if people is not None:
        core &= ~_on_people(counts, scans, p, people)
    if beyond is not None and core.shape[1]:
        k = core.shape[1]
        far = np.where(core.any(axis=1), k - 1 - np.argmax(core[:, ::-1], axis=1), k)
        width = 2 * math.ceil(p.tolerance / p.bin_width)
        core |= beyond & (np.arange(k)[None, :] > (far + width)[:, None])
    if not p.farthest or core.shape[1] == 0:
        return core
    k = core.shape[1]
    far = k - 1 - np.argmax(core[:, ::-1], axis=1)  # (B,) farthest static bin
    width = 2 * math.ceil(p.tolerance / p.bin_width)
    return core & (np.arange(k)[None, :] >= (far - width)[:, None])


def _beams_of(
    frame: Frame, scan: Scan, people: NDArray[np.bool_] | None
) -> NDArray[np.bool_] | None:
    """The beams (``scan.n_beams``,) of ``scan`` whose points ``people`` (N,) over
    ``frame.points`` marks (None without ``people``)."""
    if people is None or frame.points is None:
        return None
    pts = frame.points
    if len(people) != len(pts):
        raise BackgroundModelError(
            f"{len(people)} people flags for {len(pts)} points",
            scan=frame.index,
            hint="mark each point of the frame",
        )
    out = np.zeros(scan.n_beams, dtype=bool)
    if scan.sensor not in pts.sensors:
        return out
    sel = (pts.sensor_ids == pts.sensors.index(scan.sensor)) & people
    out[pts.beams[sel]] = True
    return out


_UNLOADED = object()
_foreground_compiled: object = _UNLOADED


def _compiled_foreground() -> Any:
    """The compiled foreground of a frozen model's frame (``histogram_foreground`` of the
    MHT's C extension, beside the occupancy grid's), or None."""
    global _foreground_compiled
    if _foreground_compiled is _UNLOADED:
        from laserpeople.background.occupancy import compiled_function

        _foreground_compiled = compiled_function("histogram_foreground")
    return _foreground_compiled


def _dilate(core: NDArray[np.bool_], reach: int) -> NDArray[np.bool_]:
    """``core`` (B, K) widened by ``reach`` bins either way (loop over offsets, not beams)."""
    static = core.copy()
    for k in range(1, reach + 1):
        static[:, k:] |= core[:, :-k]
        static[:, :-k] |= core[:, k:]
    return static


class BeamHistogramBackground:
    """The static world model of static lasers by per-beam range histograms.

    Call it on every frame (:class:`~laserpeople.background.StaticWorldModel`): while
    learning it adds the frame's scans to the histograms; after that it fills ``foreground``.
    During learning the foreground comes from the histograms so far.
    """

    consumes: frozenset[FrameField] = frozenset({"scans", "points"})

    def __init__(self, params: BeamHistogramParams | None = None) -> None:
        self.params = params or BeamHistogramParams()
        self._tables: dict[str, _BeamTable] = {}
        self._first_stamp: float | None = None
        self._frozen = False
        self._poses: dict[str, Pose2D | None] = {}
        self._geometry: dict[str, Layout] = {}
        self._watch: tuple[float, float] | None = None  # (first, last) stamp of the frames seen
        self._offline_seconds = 0.0  # seconds learned from a separate background recording
        self.layout_changes = 0  # lasers' histograms dropped for a new beam layout
        self._whole: dict[str, tuple[Layout, NDArray[np.bool_]]] = {}  # use_whole_recording

    # ----------------------------------------------------------------- learning
    @property
    def learning(self) -> bool:
        """True while the model still adds scans to its histograms."""
        return not self._frozen

    @property
    def sensors(self) -> tuple[str, ...]:
        """Names of the lasers the model knows."""
        return tuple(self._tables)

    def counts(self, sensor: str) -> NDArray[np.int32]:
        """The histogram (B, K) of laser ``sensor``."""
        return self._table(sensor).counts

    def _table(self, sensor: str) -> _BeamTable:
        try:
            return self._tables[sensor]
        except KeyError:
            raise BackgroundModelError(
                f"the background model has no laser {sensor!r}",
                hint=f"it knows {', '.join(self._tables) or 'none'}; learn it from this "
                "recording or a background recording of the same lasers",
            ) from None

    def _n_bins(self, scan: Scan) -> int:
        top = scan.range_max if math.isfinite(scan.range_max) else 80.0
        return math.ceil(min(top, 80.0) / self.params.bin_width) + 1

    def _add(
        self,
        scan: Scan,
        on_people: NDArray[np.bool_] | None = None,
        on_legs: NDArray[np.bool_] | None = None,
    ) -> None:
        table = self._tables.get(scan.sensor)
        if table is None:
            table = _BeamTable(np.zeros((scan.n_beams, self._n_bins(scan)), np.int32), 0, 0.0)
            table.angles = scan.angle_min + scan.angle_increment * np.arange(
                scan.n_beams, dtype=np.float64
            )
            self._tables[scan.sensor] = table
            self._geometry[scan.sensor] = scan.layout
            whole = self._whole.get(scan.sensor)
            if (
                whole is not None
                and same_layout(whole[0], scan.layout)
                and whole[1].shape == table.counts.shape
            ):
                table.beyond = whole[1]
        elif table.counts.shape[0] != scan.n_beams:
            raise BackgroundModelError(
                f"laser {scan.sensor!r} has {scan.n_beams} beams, the model "
                f"{table.counts.shape[0]}",
                path=scan.source or None,
                scan=scan.index,
                hint="learn the background from scans of the same laser",
            )
        idx = np.flatnonzero(scan.valid)
        bins = np.minimum(
            (scan.ranges[idx] / self.params.bin_width).astype(np.int64), -1 + table.counts.shape[1]
        )
        np.add.at(table.counts, (idx, bins), 1)
        if on_people is not None:
            if table.people is None:
                table.people = np.zeros_like(table.counts)
            hit = on_people[idx]
            np.add.at(table.people, (idx[hit], bins[hit]), 1)
        if on_legs is not None:
            if table.legs is None:
                table.legs = np.zeros_like(table.counts)
            hit = on_legs[idx]
            np.add.at(table.legs, (idx[hit], bins[hit]), 1)
        table.scans += 1
        table.static = None

    def learn_scans(self, scans: Iterable[Scan]) -> BeamHistogramBackground:
        """Learn from a background recording (all of ``scans``) and stop learning."""
        stamps: dict[str, list[float]] = {}
        for scan in scans:
            self._add(scan)
            stamps.setdefault(scan.sensor, []).append(scan.stamp)
        if not self._tables:
            raise BackgroundModelError(
                "no scans to learn the background from", hint="give a background recording"
            )
        for name, st in stamps.items():
            self._tables[name].seconds = max(st) - min(st)
        self._offline_seconds = max(t.seconds for t in self._tables.values())
        self.freeze()
        return self

    def freeze(self) -> None:
        """Stop learning; later frames only get their foreground. The bins a whole
        recording adds (:meth:`use_whole_recording`) are written into the histograms as seen
        in ``min_fraction`` of the scans, so that relearning and a saved model keep them."""
        self._frozen = True
        for table in self._tables.values():
            if table.beyond is not None:
                added = _core(table.counts, table.scans, self.params, table.people, table.beyond)
                added &= table.counts < max(1.0, self.params.min_fraction * table.scans)
                need = max(1, math.ceil(self.params.min_fraction * table.scans))
                table.counts[added] = need
                table.beyond = None
            table.finish(self.params)

    def use_whole_recording(self, whole: BeamHistogramBackground) -> None:
        """Learn with what ``whole`` (a histogram learned from the whole recording,
        :meth:`learn_scans`) saw beyond: a bin frequent in ``whole`` that lies farther
        than every static bin of the scans learned so far on its beam (by more than twice
        the tolerance) is static too, so that the wall behind a person who stands in view
        from the start, and leaves their place for ``min_fraction`` of the recording, is
        background and the person foreground from the first scan; what the learning period
        alone finds static stays static. A laser of another beam layout than in ``whole``
        learns without. Call it before the first frame."""
        for name, table in whole._tables.items():
            frequent = table.counts >= max(1.0, self.params.min_fraction * table.scans)
            self._whole[name] = (whole._geometry[name], frequent)

    # --------------------------------------------------------------- foreground
    def foreground_of(self, scan: Scan) -> NDArray[np.bool_]:
        """Foreground mask (N,) over the beams of ``scan``; invalid beams are False."""
        return self._foreground_and_bins(scan)[0]

    def _foreground_and_bins(
        self, scan: Scan
    ) -> tuple[NDArray[np.bool_], tuple[NDArray[np.int64], NDArray[np.int64]] | None]:
        """:meth:`foreground_of` and the valid beams (M,) with their range bins (M,) (None
        without a table for the laser), which :meth:`_relearn` takes as they are."""
        table = self._tables.get(scan.sensor)
        valid = scan.valid
        if table is None:
            return valid.copy(), None
        if table.static is None:
            table.finish(self.params)
        assert table.static is not None
        out = np.zeros(scan.n_beams, dtype=bool)
        idx = scan.valid_beams
        bins = np.minimum(
            (scan.ranges[idx] / self.params.bin_width).astype(np.int64), table.static.shape[1] - 1
        )
        out[idx] = ~table.static[idx, bins]
        return out, (idx, bins)

    def _relearn(
        self, scan: Scan, beams: tuple[NDArray[np.int64], NDArray[np.int64]] | None = None
    ) -> None:
        """After learning: let beams that see farther than their static bins relearn
        (``beams``: the valid beams and their bins, as :meth:`_foreground_and_bins` gives
        them; computed when None)."""
        table = self._tables.get(scan.sensor)
        if table is None or table.static is None or table.counts.shape[0] != scan.n_beams:
            return
        if beams is None:
            idx = np.flatnonzero(scan.valid)
            bins = np.minimum(
                (scan.ranges[idx] / self.params.bin_width).astype(np.int64),
                table.static.shape[1] - 1,
            )
        else:
            idx, bins = beams
        table.relearn(idx, bins, scan.stamp, self.params)

    def people_beams(self) -> tuple[int, int]:
        """Over all lasers: beams whose ranges on people were not learned as static, and
        how many of them were found static after all (``people_settle_seconds``)."""
        tables = self._tables.values()
        return sum(t.marked for t in tables), sum(t.settled for t in tables)

    def settled(self, sensor: str) -> int:
        """How many beams of laser ``sensor`` that saw people while learning were found
        static after all (``people_settle_seconds``)."""
        return self._table(sensor).settled

    def relearned(self, sensor: str) -> int:
        """How many times a beam of laser ``sensor`` relearned after learning."""
        return self._table(sensor).relearned

    def __call__(self, frame: Frame) -> Frame:
        """Learn from ``frame`` (during the learning period) and set its ``foreground``."""
        return replace(frame, foreground=self.learn_foreground(frame))

    def learn_foreground(
        self,
        frame: Frame,
        people: NDArray[np.bool_] | None = None,
        legs: NDArray[np.bool_] | None = None,
    ) -> NDArray[np.bool_]:
        """Learn from ``frame`` as :meth:`__call__` does and return the foreground (N,) of
        its points (without building a new frame). ``people`` (N,) marks the points that
        lie on people (e.g. near the legs of people a leg tracker confirmed): while
        learning, a bin whose returns were on people in ``people_share`` of them does not
        become static, and the wall behind it is guessed. ``legs`` (N,) marks the points
        that may lie on people (e.g. near any leg detection, furniture the detector fires
        on too): such a bin stays static, but the wall behind it is guessed as well, so it
        is background at once when a person there leaves."""
        if frame.points is None:
            raise BackgroundModelError(
                "the frame has no points", scan=frame.index, hint="fill points before"
            )
        for scan in frame.scans:
            self._forget_changed_layout(scan)
        first = frame.stamp if self._watch is None else self._watch[0]
        self._watch = (first, max(frame.stamp, first))
        if not self._frozen:
            if self._first_stamp is None:
                self._first_stamp = frame.stamp
            for scan in frame.scans:
                self._add(scan, _beams_of(frame, scan, people), _beams_of(frame, scan, legs))
                self._tables[scan.sensor].seconds = frame.stamp - self._first_stamp
            if frame.stamp - self._first_stamp >= self.params.learn_seconds:
                self.freeze()
        for scan in frame.scans:
            self._poses[scan.sensor] = scan.pose
        if self._frozen and len(frame.scans) == 1:
            fast = self._frozen_foreground(frame.scans[0], frame.points)
            if fast is not None:
                return fast
        by_name: dict[str, NDArray[np.bool_]] = {}
        valid_bins = []
        for scan in frame.scans:
            by_name[scan.sensor], beams = self._foreground_and_bins(scan)
            valid_bins.append(beams)
        if self._frozen:  # (after every foreground)
            for scan, beams in zip(frame.scans, valid_bins, strict=True):
                table = self._tables.get(scan.sensor)
                if beams is not None and table is not None and table.people is not None:
                    table.settle(beams[0], beams[1], scan.stamp, self.params)
                if self.params.relearn_seconds > 0.0:
                    self._relearn(scan, beams)
        pts = frame.points
        if len(pts.sensors) == 1 and pts.sensors[0] in by_name:  # one laser: no masks
            one: NDArray[np.bool_] = by_name[pts.sensors[0]][pts.beams]
            return one
        fg = np.zeros(len(pts), dtype=bool)
        for i, name in enumerate(pts.sensors):
            if name not in by_name:
                continue
            sel = pts.sensor_ids == i
            fg[sel] = by_name[name][pts.beams[sel]]
        return fg

    def _frozen_foreground(self, scan: Scan, pts: PointSet) -> NDArray[np.bool_] | None:
        """The rest of :meth:`learn_foreground` for a frozen model's frame of one laser
        (its points all of that laser), compiled where the MHT's C extension is built: the
        same foreground, the same relearning. None where the Python code runs (no compiled
        function, no table or no static bins yet, beams that saw people while learning, or
        input it leaves to Python)."""
        compiled = _compiled_foreground()
        table = self._tables.get(scan.sensor)
        if (
            compiled is None
            or table is None
            or table.static is None
            or table.people is not None
            or pts.sensors != (scan.sensor,)
        ):
            return None
        p = self.params
        relearn = p.relearn_seconds > 0.0 and table.counts.shape[0] == scan.n_beams
        fg = np.empty(len(pts.beams), dtype=bool)
        beyond = compiled(
            scan.ranges,
            scan.valid_beams,
            table.static,
            table.nearest,
            table.candidate if relearn else None,
            float(p.bin_width),
            math.ceil(p.tolerance / p.bin_width),
            pts.beams,
            fg,
        )
        if beyond is NotImplemented:
            return None
        if beyond:  # (a return beyond its static world: the Python relearning follows it)
            self._relearn(scan)
        return fg

    def _forget_changed_layout(self, scan: Scan) -> None:
        """Start the model afresh when ``scan``'s laser has a beam layout (``Scan.layout``)
        other than the one its histograms were learnt with: every laser's histograms are
        dropped and learnt again over ``learn_seconds``, as at the start of a recording.
        Counted in :attr:`layout_changes`; :mod:`laserpeople.pipeline.layout` tells the
        user."""
        known = self._geometry.get(scan.sensor)
        if known is None or same_layout(known, scan.layout):
            return
        self._tables.clear()
        self._geometry.clear()
        self._first_stamp = None
        self._frozen = False
        self._watch = (scan.stamp, scan.stamp)
        self._offline_seconds = 0.0
        self.layout_changes += 1

    def watched_seconds(self) -> float:
        """Seconds the static bins have been known to be static at the last frame: the
        seconds of a separate background recording (:meth:`learn_scans`) plus the time from
        the first to the last frame this model was called on."""
        seen = 0.0 if self._watch is None else self._watch[1] - self._watch[0]
        return self._offline_seconds + seen

    def static_time(self, positions: NDArray[np.float64]) -> NDArray[np.float64]:
        """How long [s] ``positions`` (M, 2) [m] (frame of the last frame) have been static:
        on a static bin of a laser that looks at them, :meth:`watched_seconds` (the bin was
        static when learned, and the model assumes it has been ever since); 0 elsewhere."""
        pos = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
        out = np.zeros(len(pos))
        watched = self.watched_seconds()
        for name, table in self._tables.items():
            pose = self._poses.get(name)
            if pose is None or name not in self._geometry:
                continue
            if table.static is None:
                table.finish(self.params)
            assert table.static is not None
            a0, inc, n = self._geometry[name]
            local = pose.inverse_transform_points(pos)
            rng = np.hypot(local[:, 0], local[:, 1])
            ang = np.arctan2(local[:, 1], local[:, 0])
            turn = np.mod((ang - a0) * math.copysign(1.0, inc), 2 * np.pi)
            beam = np.rint(turn / abs(inc)).astype(np.int64)
            k = (rng / self.params.bin_width).astype(np.int64)
            ok = (beam >= 0) & (beam < n) & (k < table.static.shape[1])
            hit = np.zeros(len(pos), dtype=bool)
            hit[ok] = table.static[beam[ok], k[ok]]
            out = np.where(hit, np.maximum(out, max(watched, table.seconds)), out)
        return out

    # ------------------------------------------------------------------ storage
    def save(self, path: str | Path) -> Path:
        """Write the histograms to ``path`` (.npz; metadata as a JSON string, no pickle)."""
        p = Path(path)
        if p.suffix.lower() != ".npz":
            raise BackgroundModelError(
                "background models are saved as .npz", path=p, hint="use a .npz file name"
            )
        meta = {
            "format": FORMAT,
            "version": VERSION,
            "params": {
                "bin_width": self.params.bin_width,
                "learn_seconds": self.params.learn_seconds,
                "min_fraction": self.params.min_fraction,
                "tolerance": self.params.tolerance,
                "relearn_seconds": self.params.relearn_seconds,
                "farthest": self.params.farthest,
                "people_share": self.params.people_share,
                "people_settle_seconds": self.params.people_settle_seconds,
            },
            "sensors": [
                {
                    "name": name,
                    "scans": t.scans,
                    "seconds": t.seconds,
                    "angle_min": self._geometry[name][0],
                    "angle_increment": self._geometry[name][1],
                }
                for name, t in self._tables.items()
            ],
        }
        arrays = {f"counts_{i}": t.counts for i, t in enumerate(self._tables.values())}
        for name in ("people", "legs"):
            arrays.update(
                {
                    f"{name}_{i}": getattr(t, name)
                    for i, t in enumerate(self._tables.values())
                    if getattr(t, name) is not None
                }
            )
        try:
            np.savez_compressed(p, meta=np.array(json.dumps(meta)), **arrays)  # type: ignore[arg-type]
        except OSError as exc:
            raise BackgroundModelError(
                f"cannot write the background model: {exc}", path=p, hint="check the directory"
            ) from exc
        return p

    @classmethod
    def load(cls, path: str | Path) -> BeamHistogramBackground:
        """Read a model written by :meth:`save`; it does not learn any more."""
        p = Path(path)
        try:
            with np.load(p, allow_pickle=False) as data:
                meta = json.loads(str(data["meta"]))
                if meta.get("format") != FORMAT:
                    raise BackgroundModelError(
                        "not a laserpeople background model", path=p, hint="save one first"
                    )
                if int(meta.get("version", 0)) > VERSION:
                    raise BackgroundModelError(
                        f"model version {meta['version']} is newer than {VERSION}",
                        path=p,
                        hint="update laserpeople",
                    )
                # a model saved before ``farthest`` existed keeps every frequent bin
                model = cls(BeamHistogramParams(**{"farthest": False, **meta["params"]}))
                for i, s in enumerate(meta["sensors"]):
                    counts = np.asarray(data[f"counts_{i}"], dtype=np.int32)
                    table = _BeamTable(counts, int(s["scans"]), float(s["seconds"]))
                    for name in ("people", "legs"):  # returns on (maybe) people while learning
                        if f"{name}_{i}" in data:
                            marks = np.asarray(data[f"{name}_{i}"], dtype=np.int32)
                            if marks.shape != counts.shape:
                                raise ValueError(f"{name}_{i} does not fit counts_{i}")
                            setattr(table, name, marks)
                    table.angles = float(s["angle_min"]) + float(s["angle_increment"]) * np.arange(
                        counts.shape[0], dtype=np.float64
                    )
                    model._tables[s["name"]] = table
                    model._geometry[s["name"]] = (
                        float(s["angle_min"]),
                        float(s["angle_increment"]),
                        counts.shape[0],
                    )
        except (OSError, KeyError, ValueError, TypeError) as exc:
            raise BackgroundModelError(
                f"cannot read the background model: {exc}", path=p, hint="save it again"
            ) from exc
        model._offline_seconds = max((t.seconds for t in model._tables.values()), default=0.0)
        model.freeze()
        return model


__all__ = ["BackgroundModelError", "BeamHistogramBackground", "BeamHistogramParams"]
