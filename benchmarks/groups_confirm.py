"""Confirmed groups on real recordings: the counts of ``real_people.py --groups`` for
candidate settings of ``group_tracker.confirm_scans`` (``confirm_window``,
``confirm_event_scans``), one run of the tracker per candidate and recording.

Each run is the library's flow of ``laserpeople track --tracker group-mht`` (:func:`build`
with the candidate's parameters), so what is counted is what the command reports:
confirmation decides which groups get reported, and with ``reuse_ids`` also which ids the
reported ones get (a group merged back takes the id of the group reported before), so one
setting's output cannot be replayed from another's. ``--check`` also runs the command's
own function (:func:`laserpeople.cli.track.run_tracking`, with the last candidate's
settings written to a config file) and asserts the same ids in every scan and positions
within 1e-4 m (the CSV's precision). ``000-walker-s`` counts the group-seconds of the
walkers of 000's setting (every group reported: ``1/1/1``, run once more when it is not a
candidate).

    PYTHONPATH=src python benchmarks/groups_confirm.py [--bags demo mir mir-all corridor dev]
        [--candidates 1/1/1 3/3/1 ...] [--check] [--set NAME=VALUE ...]
    PYTHONPATH=src python benchmarks/groups_confirm.py --sim-seeds 0 1 [--seconds 60]

With ``--sim-seeds`` the simulated entrance hall instead (``run_groups``, the default d_P, one run
per candidate and seed, pooled over the seeds): clustering error of the reported groups
against memory-less clustering (the points of a group not reported are in no cluster:
a true group with no reported point is *missed*, not an error), group size, split/merge
events.

A candidate is ``scans/window/event_scans``.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import numpy as np

from groups_table import _with  # type: ignore[import-not-found]
from laserpeople.config import to_toml
from laserpeople.evaluation.clustering import ClusteringErrorResult
from laserpeople.evaluation.groups import GroupRunResult, run_groups
from laserpeople.pipeline import build
from laserpeople.sim.scenarios import run_scenario
from laserpeople.tracking import registry
from laserpeople.tracking.groups.confirm import ConfirmSettings
from laserpeople.tracking.groups.params import GroupTrackerParams
from laserpeople.tracking.groups.tracker import GroupMHTTracker
from laserpeople.tracks import Tracks
from real_people import BAGS, ROOT, count

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
EVERY_GROUP = "1/1/1"
"""000's setting: every group of the best hypothesis reported from its first scan."""


@dataclass
class Run:
    """One run of the group tracker over a recording.

    Attributes:
        tracks: Every frame's tracks, as ``laserpeople track`` writes them.
        tracker: The group tracker (its counters: ``confirmation.withheld_born`` ...).
        event_of: Reported id -> "split"/"merge" when a model made the group, else "".
        ms: Process CPU per frame [ms].
    """

    tracks: list[Tracks]
    tracker: GroupMHTTracker
    event_of: dict[int, str]
    ms: float


def parse(text: str) -> ConfirmSettings:
    scans, window, event = (int(v) for v in text.split("/"))
    return ConfirmSettings(scans=scans, window=window, event_scans=event)


def with_candidate(params: GroupTrackerParams, text: str) -> GroupTrackerParams:
    """``params`` with the confirmation of candidate ``text`` (``scans/window/event``)."""
    c = parse(text)
    return replace(
        params, confirm_scans=c.scans, confirm_window=c.window, confirm_event_scans=c.event_scans
    )


def run(key: str, params: GroupTrackerParams) -> Run:
    """Track recording ``key`` with ``params`` as ``laserpeople track --tracker group-mht``
    does (the library's :func:`build`)."""
    bag, topics, mounts = ALL_BAGS[key]
    tracker = registry.get("group-mht").make(params)
    inner = getattr(tracker, "tracker", tracker)  # the input guard's tracker
    assert isinstance(inner, GroupMHTTracker)
    out: list[Tracks] = []
    event_of: dict[int, str] = {}
    t0 = time.process_time()
    for step in build(bag, tracker=tracker, topics=topics, mounts=mounts):
        assert step.tracks is not None
        groups = step.tracks.of_kind("group")
        # the groups of the best hypothesis reported, in order, then the coasted ones
        assert len(groups) >= len(inner.last_groups)
        for x, g in zip(groups[: len(inner.last_groups)], inner.last_groups, strict=True):
            event_of.setdefault(x.track_id, g.event)
        out.append(step.tracks)
    ms = 1e3 * (time.process_time() - t0) / max(len(out), 1)
    return Run(out, inner, event_of, ms)


def check(key: str, params: GroupTrackerParams, expected: list[Tracks]) -> None:
    """Assert that ``laserpeople track``'s own function, with ``params`` in a config file,
    reports the groups of ``expected`` (ids per scan; positions within 1e-4 m, the CSV's
    precision)."""
    from laserpeople.cli.track import run_tracking
    from laserpeople.io.tracks_csv import iter_tracks_csv

    bag, topics, mounts = ALL_BAGS[key]
    with tempfile.TemporaryDirectory() as tmp:
        config, csv = Path(tmp) / "groups.toml", Path(tmp) / "groups.csv"
        config.write_text(to_toml(params))
        run_tracking(bag, csv, "group-mht", topics, config, mounts=mounts)
        written = {t.scan_index: t for t in iter_tracks_csv(csv)}
    for t in expected:
        got = written.get(t.scan_index)
        rows = () if got is None else got.of_kind("group")
        ids = [x.track_id for x in t.of_kind("group")]
        assert [x.track_id for x in rows] == ids, (key, t.scan_index, ids, rows)
        for x, y in zip(rows, t.of_kind("group"), strict=True):
            assert np.allclose(x.position, y.position, atol=1e-4), (key, t.scan_index)


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
        runs = {text: run(key, with_candidate(base, text)) for text in args.candidates}
        every = runs.get(EVERY_GROUP) or run(key, with_candidate(base, EVERY_GROUP))
        walkers = walker_ids(every.tracks, args.walk)  # of 000's setting: every group reported
        truth = dev_truth() if key == "dev" else {}
        for text, r in runs.items():
            c = count(r.tracks, args.walk, kind="group")
            conf = r.tracker.confirmation
            print(
                f"{key:8s} {text:18s} {c.ids:4d} {c.walker_ids:8d} {c.short_ids:6d} "
                f"{short_events(r.tracks, r.event_of):11d} "
                f"{c.person_seconds:8.1f} {c.walker_seconds:9.1f} {c.static_seconds:9.1f} "
                f"{walker_seconds(r.tracks, walkers):13.1f} "
                f"{conf.withheld_born:8d} {conf.withheld_event:6d}"
                + (f"  followed person {followed(r.tracks, truth)}" if truth else "")
                + f"  ({len(r.tracks)} frames, {r.ms:.1f} ms/frame)",
                flush=True,
            )
        if args.check:
            last = args.candidates[-1]
            check(key, with_candidate(base, last), runs[last].tracks)
            print(f"{key:8s} check: {last} reports what laserpeople track reports", flush=True)


if __name__ == "__main__":
    main()
