"""Learning the group tracker's probabilities by counting group events in simulated ground
truth (000 Sec. 4.6: "determined by counting the related events in the ground truth and
dividing by the total number of these events").

Truth groups per scan come from the simulator's per-beam labels as in
:func:`~laserpeople.evaluation.clustering.beam_group_labels`: the people with a beam on them
are *seen*; people of one group id form a group, a person walking alone a group of one. A
group is keyed by its group id, a lone person by their person id, so keys are stable over
time (the simulator gives a group a new id when it merges, and the old ids back when it
splits again).

Between consecutive scans every live group track (a key seen recently) takes one model
(000 Sec. 4.4): it *splits* when its members seen now carry two or more keys, it *merges*
when members of two or more previous keys now share one key (binary events as in 000:
a split into m parts or a merge of m groups counts m - 1), else it *continues* (seen or
not). Its data-association label (000 eq. 36) is *matched* when seen, *occluded* when not
seen but seen again within ``max_gap``, *obsolete* (terminated) after its last sighting
when none of its members is seen in the next scan (otherwise a split or merge replaced
it). A key first seen with none of its members seen in the scan before is a *new track*;
p_N = new tracks per scan (000: p_N = lambda_N V). False alarms need a foreground with
errors; on the labels' perfect foreground there are none, so p_F keeps its value.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from laserpeople.config import param
from laserpeople.fitting.data import LabelledRecording
from laserpeople.fitting.estimates import Estimate, FitError, multinomial, rate
from laserpeople.fitting.legs import with_learned
from laserpeople.scan import Scan
from laserpeople.tracking.groups.params import GroupTrackerParams

GroupKey = tuple[str, int]
"""("g", group id) or ("p", person id) of a person walking alone."""


@dataclass(frozen=True)
class GroupFitParams:
    """How group events are counted."""

    config_section = "fit_groups"

    max_gap: float = param(
        1.0,
        "assumption: the group tracker's prediction step is capped at max_dt = 1 s",
        "a group unseen for longer is terminated; when seen again it is a new track",
        "s",
    )
    min_events: int = param(
        50, "assumption", "least number of events behind any learned value", "events"
    )

    def __post_init__(self) -> None:
        if not self.max_gap > 0:
            raise ValueError("max_gap must be positive")
        if self.min_events < 1:
            raise ValueError("min_events must be at least 1")


def seen_groups(scan: Scan) -> dict[int, GroupKey]:
    """Person id -> group key of every person with a beam on them in ``scan``.

    Raises:
        FitError: the scan has no per-beam labels.
    """
    if scan.labels is None:
        raise FitError(
            f"scan {scan.index} has no per-beam labels",
            hint="learning the group tracker needs a simulated .npz (labels of every beam)",
        )
    person = scan.labels.person
    group = scan.labels.group
    hit = (person >= 0) & scan.valid
    out: dict[int, GroupKey] = {}
    for pid, gid in zip(person[hit].tolist(), group[hit].tolist(), strict=True):
        out[int(pid)] = ("g", int(gid)) if gid >= 0 else ("p", int(pid))
    return out


@dataclass
class GroupEventCounts:
    """Group events (summed over recordings with :meth:`merge`).

    Attributes:
        continued, split, merged: Model events (000 eq. 32).
        matched, occluded, terminated: Data-association labels of group tracks (eq. 36).
        new: New group tracks.
        transitions: Scan-to-scan transitions counted (the exposure of p_N).
        sources: The data counted.
    """

    continued: int = 0
    split: int = 0
    merged: int = 0
    matched: int = 0
    occluded: int = 0
    terminated: int = 0
    new: int = 0
    transitions: int = 0
    sources: list[str] = field(default_factory=list)

    def merge(self, o: GroupEventCounts) -> GroupEventCounts:
        """The counts of both."""
        return GroupEventCounts(
            self.continued + o.continued,
            self.split + o.split,
            self.merged + o.merged,
            self.matched + o.matched,
            self.occluded + o.occluded,
            self.terminated + o.terminated,
            self.new + o.new,
            self.transitions + o.transitions,
            self.sources + o.sources,
        )

    def summary(self) -> str:
        """One line of the counts."""
        return (
            f"continued/split/merged {self.continued}/{self.split}/{self.merged}, "
            f"matched/occluded/terminated {self.matched}/{self.occluded}/{self.terminated}, "
            f"new {self.new} in {self.transitions} transitions"
        )


def count_group_events(
    seen: Sequence[dict[int, GroupKey]], stamps: Sequence[float], max_gap: float
) -> GroupEventCounts:
    """Count group events in a sequence of per-scan truth partitions (rules in the module
    docstring).

    Args:
        seen: Per scan, person id -> group key of the people seen.
        stamps: Scan times [s].
        max_gap: A group unseen for longer than this [s] is terminated.
    """
    c = GroupEventCounts()
    live: dict[GroupKey, int] = {}  # group tracks: key -> scan position last seen
    for k, now in enumerate(seen):
        if k == 0:
            c.new += len(set(now.values()))
            live = {key: 0 for key in now.values()}
            continue
        c.transitions += 1
        before = seen[k - 1]
        members: dict[GroupKey, set[int]] = {}
        for pid, key in before.items():
            members.setdefault(key, set()).add(pid)
        # models (000 Sec. 4.4): splits and merges of the groups seen in the previous scan
        handled: set[GroupKey] = set()
        for key, pids in members.items():
            parts = {now[p] for p in pids if p in now}
            if len(parts) >= 2:
                c.split += len(parts) - 1
                handled.add(key)
        sources: dict[GroupKey, set[GroupKey]] = {}
        for pid, key in now.items():
            if pid in before:
                sources.setdefault(key, set()).add(before[pid])
        for srcs in sources.values():
            if len(srcs) >= 2:
                c.merged += len(srcs) - 1
                handled.update(srcs)
        c.continued += sum(1 for key in live if key not in handled)
        # data association (000 eq. 36)
        keys_now = set(now.values())
        for key in keys_now:
            if key in live:
                c.matched += 1
            elif not any(p in before for p, kk in now.items() if kk == key):
                c.new += 1
        for key in [key for key in live if key not in keys_now]:
            if any(p in now for p in members.get(key, ())):
                del live[key]  # replaced by a split, a merge or a new label
            elif _seen_again(seen, key, k, live[key], stamps, max_gap):
                c.occluded += 1
            else:
                c.terminated += 1
                del live[key]
        live.update({key: k for key in keys_now})
    return c


def _seen_again(
    seen: Sequence[dict[int, GroupKey]],
    key: GroupKey,
    k: int,
    last: int,
    stamps: Sequence[float],
    gap: float,
) -> bool:
    """``key`` is seen in a scan after ``k`` within ``gap`` [s] of its last sighting
    (scan ``last``)."""
    for j in range(k, len(seen)):
        if stamps[j] - stamps[last] > gap:
            return False
        if key in seen[j].values():
            return True
    return False


class GroupModelFitter:
    """Learns p_C, p_S, p_G, p_M, p_O, p_T and p_N of the group tracker from simulated
    recordings with per-beam group labels (scikit-learn style: :meth:`fit` returns the
    fitter; learned values end in ``_``).

    Attributes (after :meth:`fit`):
        counts_: The events counted.
        estimates_: The learned values.
        kept_: Keys left at their base value, with the reason.
        params_: :class:`GroupTrackerParams` with the learned values.
    """

    def __init__(
        self, base: GroupTrackerParams | None = None, settings: GroupFitParams | None = None
    ) -> None:
        self.base = base if base is not None else GroupTrackerParams()
        self.settings = settings if settings is not None else GroupFitParams()

    def fit(self, recordings: Sequence[LabelledRecording]) -> GroupModelFitter:
        """Count the group events of ``recordings`` and estimate the probabilities.

        Raises:
            FitError: no recording, scans without labels, or too few events.
        """
        if not recordings:
            raise FitError("no labelled recording to learn from")
        counts = GroupEventCounts()
        for rec in recordings:
            if not rec.has_labels:
                raise FitError(
                    "the recording has no per-beam labels (group truth)",
                    path=rec.name,
                    hint="learning the group tracker needs a simulated .npz",
                )
            part = count_group_events(
                [seen_groups(s) for s in rec.scans],
                [s.stamp for s in rec.scans],
                self.settings.max_gap,
            )
            part.sources = [rec.source]
            counts = counts.merge(part)
        self.counts_ = counts
        m = self.settings.min_events
        est: list[Estimate] = []
        est += multinomial(
            {"p_c": counts.continued, "p_s": counts.split, "p_g": counts.merged},
            "group model events",
            m,
        )
        est += multinomial(
            {"p_m": counts.matched, "p_o": counts.occluded, "p_t": counts.terminated},
            "group track-scans",
            m,
        )
        p_n = rate(
            "p_n", counts.new, counts.transitions, "new groups", "scans", counts.transitions, m
        )
        if not p_n.value < 1.0:
            raise FitError(
                f"{p_n.value:.3g} new groups per scan: p_n must be below 1",
                hint="the scans are too far apart for the group tracker",
            )
        est.append(p_n)
        self.estimates_ = tuple(est)
        self.kept_ = (("p_f", "the labels' foreground has no false-alarm clusters"),)
        self.params_ = with_learned(self.base, est)
        return self
