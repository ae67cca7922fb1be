"""Confirmed groups on real recordings: the counts of ``real_people.py --groups`` for
candidate settings of ``group_tracker.confirm_scans`` (``confirm_window``,
``confirm_event_scans``), all from one pipeline run per recording.

Confirmation changes only which groups of the MHT's best hypothesis are reported, never the
hypotheses, so one run with 000's setting (every group reported) fans the best hypothesis
of every scan out to one :class:`~laserpeople.tracking.groups.confirm.Confirmation` per
candidate and keeps, per scan, the groups each of them reports. ``--check`` also runs the
tracker with the last candidate as its own parameters and asserts the same reported tracks.

    PYTHONPATH=src python benchmarks/groups_confirm.py [--bags demo mir mir-all corridor dev]
        [--candidates 1/1/1 3/3/1 ...] [--check] [--set NAME=VALUE ...]
    PYTHONPATH=src python benchmarks/groups_confirm.py --sim-seeds 0 1 [--seconds 60]

With ``--sim-seeds`` the simulated entrance hall instead (``run_groups``, d_P 1.3 m, one run
per candidate and seed, pooled over the seeds): clustering error of the reported groups
against memory-less clustering (the points of a group not reported are in no cluster:
a true group with no reported point is *missed*, not an error), group size, split/merge
events.

A candidate is ``scans/window/event_scans``.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterable, Sequence
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import numpy as np

from groups_table import _with  # type: ignore[import-not-found]
from laserpeople.evaluation.clustering import ClusteringErrorResult
from laserpeople.evaluation.groups import GroupRunResult, run_groups
from laserpeople.pipeline import build
from laserpeople.sim.scenarios import run_scenario
from laserpeople.tracking import registry
from laserpeople.tracking.groups.confirm import (
    Candidate,
    Confirmation,
    ConfirmSettings,
)
from laserpeople.tracking.groups.tracker import GroupMHTTracker, GroupTrackerParams
from laserpeople.tracks import Tracks
from real_people import BAGS, ROOT, count, track_all

DEV = ROOT / "leg_tracker_benchmarks/person_following_outdoor_1_first.bag"
ALL_BAGS = {**BAGS, "dev": (DEV, None, [])}
DEFAULT_CANDIDATES = [
    "1/1/1",
    "2/2/1",
    "3/3/1",
    "3/4/1",
    "3/5/1",
    "4/4/1",
    "4/5/1",
    "5/5/1",
    "2/2/2",
    "3/3/2",
    "3/4/2",
    "3/3/3",
]


class Fanout:
    """Stands in for a tracker's confirmation: answers as ``main`` and feeds ``others``,
    keeping the families each reports per scan."""

    def __init__(self, main: Confirmation, others: Sequence[Confirmation]) -> None:
        self.main = main
        self.others = list(others)
        self.reported: list[list[set[int]]] = [[] for _ in self.others]
        self.event_of: dict[int, str] = {}

    @property
    def withheld(self) -> int:
        return self.main.withheld

    def select(self, index: int, candidates: Sequence[Candidate]) -> list[bool]:
        self.event_of.update((c.family, c.event) for c in candidates)
        for conf, kept in zip(self.others, self.reported, strict=True):
            flags = conf.select(index, candidates)
            kept.append({c.family for c, f in zip(candidates, flags, strict=True) if f})
        return self.main.select(index, candidates)

    def prune(self, families: Iterable[int], roots: Iterable[str] | None = None) -> None:
        """Forget gone families and roots in every confirmation (the tracker's
        ``forget_gone``)."""
        alive, stems = set(families), None if roots is None else set(roots)
        for conf in (self.main, *self.others):
            conf.prune(alive, stems)


def parse(text: str) -> ConfirmSettings:
    scans, window, event = (int(v) for v in text.split("/"))
    return ConfirmSettings(scans=scans, window=window, event_scans=event)


def run(key: str, params: GroupTrackerParams, others: Sequence[Confirmation]) -> tuple:
    """Tracks of one recording with ``params``, the fan-out and CPU ms per frame."""
    bag, topics, mounts = ALL_BAGS[key]
    tracker = registry.get("group-mht").make(params)
    inner = getattr(tracker, "tracker", tracker)  # the input guard's tracker
    assert isinstance(inner, GroupMHTTracker)
    fan = Fanout(inner.confirmation, others)
    inner.confirmation = fan  # type: ignore[assignment]
    out, ms = track_all(build(bag, tracker=tracker, topics=topics, mounts=mounts))
    return out, fan, inner, ms


def only(tracks: list[Tracks], families: list[set[int]]) -> list[Tracks]:
    """``tracks`` with the groups of scan k kept only when in ``families[k]``."""
    assert len(tracks) == len(families)
    return [
        replace(t, tracks=tuple(x for x in t.tracks if x.track_id in f))
        for t, f in zip(tracks, families, strict=True)
    ]


def short_events(tracks: list[Tracks], event_of: dict[int, str]) -> int:
    """Group ids reported in at most 3 scans whose family a split or merge made."""
    scans: dict[int, int] = {}
    for t in tracks[1:]:  # as count() does
        for x in t.of_kind("group"):
            scans[x.track_id] = scans.get(x.track_id, 0) + 1
    return sum(1 for f, n in scans.items() if n <= 3 and event_of.get(f))


def pooled(results: Sequence[ClusteringErrorResult]) -> tuple[float, float, float, int, int]:
    """(error, under, over, missed, true groups) summed over runs."""
    groups = sum(r.true_groups for r in results)
    under = sum(r.under_segmented for r in results) / groups
    over = sum(r.over_segmented for r in results) / groups
    return under + over, under, over, sum(r.missed_groups for r in results), groups


def walker_seconds(tracks: list[Tracks], walkers: set[int]) -> float:
    """Group-seconds of the ids in ``walkers`` (as count() sums them)."""
    total = 0.0
    for k in range(1, len(tracks)):
        dt = tracks[k].stamp - tracks[k - 1].stamp
        total += dt * sum(1 for x in tracks[k].of_kind("group") if x.track_id in walkers)
    return total


def walker_ids(tracks: list[Tracks], walk: float) -> set[int]:
    """Ids whose positions span at least ``walk`` metres (as count() finds walkers)."""
    positions: dict[int, list[np.ndarray]] = {}
    for t in tracks[1:]:
        for x in t.of_kind("group"):
            positions.setdefault(x.track_id, []).append(x.position)
    out = set()
    for i, pts in positions.items():
        arr = np.stack(pts)
        if 2.0 * float(np.max(np.linalg.norm(arr - arr.mean(axis=0), axis=1))) >= walk:
            out.add(i)
    return out


def followed(tracks: list[Tracks], truth: dict[int, np.ndarray], radius: float = 0.75) -> str:
    """Recall of the labelled person of the dev recording (scans with a reported group
    whose centroid or a contour point is within ``radius`` of the label, out of the
    labelled scans) and the number of group ids that cover it."""
    covered = 0
    ids: set[int] = set()
    for t in tracks:
        at = truth.get(t.scan_index)
        if at is None:
            continue
        near = [
            x.track_id
            for x in t.of_kind("group")
            if float(np.linalg.norm(x.position - at)) < radius
            or (
                x.contour is not None
                and float(np.linalg.norm(x.contour - at, axis=1).min()) < radius
            )
        ]
        covered += bool(near)
        ids.update(near)
    return f"{covered}/{len(truth)} by {len(ids)} ids"


def dev_truth() -> dict[int, np.ndarray]:
    """Scan -> (x, y) of the labelled person of the dev recording (sensor frame)."""
    rows = np.loadtxt(f"{DEV.with_suffix('')}.people.csv", delimiter=",", skiprows=1)
    return {int(r[0]): r[3:5] for r in np.atleast_2d(rows)}


def main_sim(seeds: list[int], seconds: float, candidates: list[str]) -> None:
    """The simulated hall (``--sim-seeds``)."""
    print(
        "scans/window/event  error  under  over  missed  error+missed  memory-less  size err  "
        "exact  splits  merges"
    )
    scans = {s: run_scenario("entrance-hall", seconds=seconds, seed=s).scans for s in seeds}
    for text in candidates:
        c = parse(text)
        params = GroupTrackerParams(
            confirm_scans=c.scans, confirm_window=c.window, confirm_event_scans=c.event_scans
        )
        runs: list[GroupRunResult] = [run_groups(scans[s], params) for s in seeds]
        err, under, over, missed, groups = pooled([r.clustering for r in runs])
        ml = pooled([r.memoryless for r in runs])[0]
        n = sum(r.size.count for r in runs)
        size = sum(r.size.mean_error * r.size.count for r in runs) / n
        exact = sum(r.size.exact_share * r.size.count for r in runs) / n
        per_seed = " ".join(f"{r.clustering.error:.4f}" for r in runs)
        print(
            f"{text:18s} {err:.4f} {under:.4f} {over:.4f} {missed:5d}/{groups} "
            f"{err + missed / groups:.4f} {ml:.4f} "
            f"{size:.3f} {100 * exact:.1f} {sum(r.splits for r in runs):5d} "
            f"{sum(r.merges for r in runs):5d}   per seed {per_seed}",
            flush=True,
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bags", nargs="+", default=list(ALL_BAGS), choices=list(ALL_BAGS))
    ap.add_argument("--candidates", nargs="+", default=DEFAULT_CANDIDATES)
    ap.add_argument("--walk", type=float, default=1.0, help="m")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--sim-seeds", type=int, nargs="*", default=[])
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument(
        "--set", nargs="*", default=[], metavar="NAME=VALUE", help="other group settings"
    )
    args = ap.parse_args()
    base = _with(GroupTrackerParams(), args.set)
    if args.sim_seeds:
        main_sim(args.sim_seeds, args.seconds, args.candidates)
        return
    print(
        "bag      scans/window/event  ids  walkers  short  (of events)  group-s  walker-s  "
        "static-s  000-walker-s  withheld born  event"
    )
    for key in args.bags:
        settings = [parse(c) for c in args.candidates]
        others = [Confirmation(s) for s in settings]
        out, fan, _, ms = run(key, replace(base, confirm_scans=1), others)
        walkers = walker_ids(out, args.walk)  # of 000's setting: every group reported
        truth = dev_truth() if key == "dev" else {}
        for text, conf, fams in zip(args.candidates, others, fan.reported, strict=True):
            kept = only(out, fams)
            c = count(kept, args.walk, kind="group")
            print(
                f"{key:8s} {text:18s} {c.ids:4d} {c.walker_ids:8d} {c.short_ids:6d} "
                f"{short_events(kept, fan.event_of):11d} "
                f"{c.person_seconds:8.1f} {c.walker_seconds:9.1f} {c.static_seconds:9.1f} "
                f"{walker_seconds(kept, walkers):13.1f} "
                f"{conf.withheld_born:8d} {conf.withheld_event:6d}"
                + (f"  followed person {followed(kept, truth)}" if truth else ""),
                flush=True,
            )
        print(f"{key:8s} ({len(out)} frames, {ms:.1f} ms/frame)", flush=True)
        if args.check:
            s = settings[-1]
            params = replace(
                base,
                confirm_scans=s.scans,
                confirm_window=s.window,
                confirm_event_scans=s.event_scans,
            )
            real, _, checked, _ = run(key, params, [])
            expected = only(out, fan.reported[-1])
            for a, b in zip(real, expected, strict=True):
                assert [x.track_id for x in a.tracks] == [x.track_id for x in b.tracks]
            assert checked.unconfirmed_groups_withheld == others[-1].withheld
            print(f"{key:8s} check: {args.candidates[-1]} run on its own reports the same")


if __name__ == "__main__":
    main()
