"""Ceiling of the walkers' point split (``tracking/groups/leg_split.py``) on the simulated
entrance hall: memory-less single linkage at d_P, and the same linkage with the links
between two parts cut when their TRUE velocities differ by ``v`` or more, where the parts
are (a) the true people, (b) the blobs at d_hs (each given its main person's velocity),
(c) the walkers of :mod:`.walkers` (blob unions), (d) the walkers of the point split
(each given its main person's velocity). Also the share of points whose part's main
person is not their own (the partition's impurity), and with ``--flip`` the true people
with a share of the points moved to a neighbour's part (how pure a partition must be).

``--tracker`` runs the group tracker (000's setting) on observations cut that way instead
of memory-less clustering, for the parts (a) and (d): what the MHT keeps of the ceiling.
docs/groups.md "Third round".

    PYTHONPATH=src python benchmarks/groups_split_ceiling.py [--seeds 0 1] [--seconds 30]
        [--v 0.6] [--flip 0.1 0.25] [--tracker] [--set segment_distance=0.1 ...]
"""

from __future__ import annotations

import argparse
from dataclasses import fields, replace

import numpy as np

from laserpeople.clustering import single_linkage
from laserpeople.evaluation.clustering import ClusteringError
from laserpeople.evaluation.groups import LabelledFrame, frames_from_scans
from laserpeople.sim.scenarios import run_scenario
from laserpeople.tracking.groups.leg_split import SplitSettings, SplitWalkerTracker
from laserpeople.tracking.groups.observations import close_pairs, component_labels
from laserpeople.tracking.groups.tracker import GroupMHTTracker, GroupTrackerParams
from laserpeople.tracking.groups.walkers import WalkerSettings, walker_detections

IntArray = np.ndarray


def main_person(part: IntArray, person: IntArray) -> IntArray:
    """The person (N,) most points of each point's ``part`` belong to."""
    _, part_index = np.unique(part, return_inverse=True)
    people, person_index = np.unique(person, return_inverse=True)
    counts = np.zeros((part_index.max() + 1, people.size), dtype=np.int64)
    np.add.at(counts, (part_index, person_index), 1)
    return people[np.argmax(counts, axis=1)][part_index]


class TruthCut:
    """A link filter for the group tracker's observations (as the walkers'): the links
    between two parts whose main people's TRUE velocities differ by ``v`` or more are cut;
    the parts are the true people (``split`` None) or the split walkers' parts. Set
    ``person`` (N,) and ``velocity`` (person id -> (2,) [m/s]) before every frame."""

    def __init__(self, v: float, split: SplitWalkerTracker | None, d_hs: float) -> None:
        self.v, self.split, self.d_hs = v, split, d_hs
        self.person = np.empty(0, dtype=np.int64)
        self.velocity: dict[int, np.ndarray] = {}

    def coherent_links(
        self,
        points: np.ndarray,
        blobs: np.ndarray,
        links: np.ndarray,
        stamp: float,
        d_hs: float | None = None,
    ) -> np.ndarray:
        if len(points) != len(self.person):
            raise ValueError("the tracker left points out: the truth no longer lines up")
        length = np.hypot(*(points[links[:, 0]] - points[links[:, 1]]).T)
        part = self.person
        if self.split is not None:
            part = self.split.assign(points, links, length, self.d_hs, stamp)
        if len(points) == 0 or len(links) == 0:
            return np.ones(len(links), dtype=bool)
        main = main_person(part, self.person)
        v = np.array([self.velocity[int(p)] for p in main]).reshape(-1, 2)
        return np.hypot(*(v[links[:, 0]] - v[links[:, 1]]).T) < self.v


def through_tracker(
    frames: list[LabelledFrame], truth: dict, cut: TruthCut, d_p: float
) -> tuple[ClusteringError, ClusteringError, dict[str, int]]:
    """Clustering errors of 000's group tracker and of its observations (the cut clusters)
    when ``cut`` cuts the observations' links, and counts of the true group-scans the
    tracker does not keep together, by kind (they overlap)."""
    tracker = GroupMHTTracker(GroupTrackerParams.paper_likelihood(cluster_distance=d_p))
    tracker.walkers = cut  # type: ignore[assignment]
    tracked, observed = ClusteringError(), ClusteringError()
    kinds = {"group-scans": 0, "cut observations": 0, "observation divided": 0, "unreported": 0}
    for lf in frames:
        fg = np.asarray(lf.frame.foreground)
        assert lf.frame.points is not None
        t = truth[lf.frame.index]
        cut.person = lf.true_person[fg]
        cut.velocity = {int(p): t.velocities[i] for i, p in enumerate(t.person_ids)}
        tracker.update(lf.frame)
        est = tracker.point_labels(len(lf.frame.points))
        tracked.accumulate_labels(lf.true_group[fg], est[fg], lf.frame.stamp)
        obs = tracker.last_observations
        labels = np.full(len(lf.frame.points), -1, dtype=np.int64)
        labels[obs.members] = obs.point_cluster
        observed.accumulate_labels(lf.true_group[fg], labels[fg], lf.frame.stamp)
        group, own, seen = lf.true_group[fg], est[fg], labels[fg]
        for g in np.unique(group[group >= 0]).tolist():
            mine = group == g
            n_obs = np.unique(seen[mine]).size
            n_tracks = np.unique(own[mine][own[mine] >= 0]).size
            kinds["group-scans"] += 1
            kinds["cut observations"] += int(n_obs > 1)
            kinds["observation divided"] += int(n_obs == 1 and n_tracks > 1)
            kinds["unreported"] += int((own[mine] < 0).any())
    return tracked, observed, kinds


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--d-p", type=float, default=1.3)
    ap.add_argument("--d-hs", type=float, default=0.3)
    ap.add_argument("--v", type=float, nargs="+", default=[0.6])
    ap.add_argument("--psd", type=float, default=0.2, help="walker_accel_psd, m^2/s^3")
    ap.add_argument("--std", type=float, default=0.3, help="walker_measurement_std, m")
    ap.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE")
    ap.add_argument(
        "--flip",
        type=float,
        nargs="*",
        default=[],
        help="also the true people with this share [%%] of all points moved to the part of "
        "another person's point within d_hs (how pure a partition must be)",
    )
    ap.add_argument(
        "--tracker", action="store_true", help="also through 000's group tracker (slower)"
    )
    args = ap.parse_args()
    split = SplitSettings()
    kinds = {f.name: f.type for f in fields(SplitSettings)}
    for item in args.set:
        name, value = item.split("=")
        split = replace(split, **{name: float(value) if kinds[name] != "int" else int(value)})
    print(f"split settings: {split}")
    for seed in args.seeds:
        result = run_scenario("entrance-hall", seconds=args.seconds, seed=seed)
        truth = {t.scan_index: t for t in result.truth}
        walkers = WalkerSettings(on=True, accel_psd=args.psd, measurement_std=args.std)
        tracker = SplitWalkerTracker(walkers, split)
        flips = [f"flip {f:.2f} %" for f in args.flip]
        names = ("person", "blob", "seg 0.10", "seg 0.15", "walker", "split", *flips)
        rng = np.random.default_rng(seed)
        errors = {(k, v): ClusteringError() for k in names for v in args.v}
        memoryless = ClusteringError()
        impure = {k: [0, 0, 0] for k in names}
        for lf in frames_from_scans(result.scans):
            fg = np.asarray(lf.frame.foreground)
            assert lf.frame.points is not None
            pts = lf.frame.points.points[fg]
            group = lf.true_group[fg]
            person = lf.true_person[fg]
            stamp = lf.frame.stamp
            memoryless.accumulate_labels(group, single_linkage(pts, args.d_p), stamp)
            if len(pts) == 0:
                tracker.assign(pts, np.empty((0, 2), np.int64), np.empty(0), args.d_hs, stamp)
                continue
            pairs, length = close_pairs(pts, args.d_p)
            links, length = pairs[length < args.d_p], length[length < args.d_p]
            blobs = component_labels(len(pts), links[length < args.d_hs])
            _, walker_of_blob = walker_detections(pts, blobs, 0.7, 0.12)
            parts = {
                "person": person,
                "blob": blobs,
                "seg 0.10": component_labels(len(pts), links[length < 0.1]),
                "seg 0.15": component_labels(len(pts), links[length < 0.15]),
                "walker": walker_of_blob[blobs],
                "split": tracker.assign(pts, links, length, args.d_hs, stamp),
            }
            near = links[(length < args.d_hs) & (person[links[:, 0]] != person[links[:, 1]])]
            for name, share in zip(flips, args.flip, strict=True):
                # each point near another person is moved with the probability that
                # makes the expected share of all points ``share``
                flipped = person.copy()
                if len(near):
                    chance = min(1.0, share / 100 * len(person) / len(near))
                    pick = near[rng.random(len(near)) < chance]
                    flipped[pick[:, 0]] = person[pick[:, 1]]
                parts[name] = flipped
            t = truth[lf.frame.index]
            velocity = {int(p): t.velocities[i] for i, p in enumerate(t.person_ids)}
            for name, part in parts.items():
                main = main_person(part, person)
                impure[name][0] += int(np.count_nonzero(main != person))
                impure[name][1] += len(person)
                impure[name][2] += int(np.count_nonzero(main_person(part, group) != group))
                v_point = np.array([velocity[int(p)] for p in main]).reshape(-1, 2)
                dv = np.hypot(*(v_point[links[:, 0]] - v_point[links[:, 1]]).T)
                for v in args.v:
                    labels = component_labels(len(pts), links[dv < v])
                    errors[(name, v)].accumulate_labels(group, labels, stamp)
        if args.tracker:
            frames = list(frames_from_scans(result.scans))
            for name in ("person", "split"):
                for v in args.v:
                    walkers = WalkerSettings(on=True, accel_psd=args.psd, measurement_std=args.std)
                    parts = None if name == "person" else SplitWalkerTracker(walkers, split)
                    cut = TruthCut(v, parts, args.d_hs)
                    run = through_tracker(frames, truth, cut, args.d_p)
                    tracked, observed, kinds = run[0].result(), run[1].result(), run[2]
                    print(
                        f"  tracker on observations cut by {name} parts at {v:.2f} m/s: "
                        f"{tracked.error:.3f} (under {tracked.under_rate:.3f}, over "
                        f"{tracked.over_rate:.3f}); the observations {observed.error:.3f} "
                        f"(under {observed.under_rate:.3f}, over {observed.over_rate:.3f}); "
                        f"group-scans not kept together: {kinds}",
                        flush=True,
                    )
        ml = memoryless.result()
        print(f"seed {seed}: memory-less {ml.error:.3f} (under {ml.under_rate:.3f})", flush=True)
        for (name, v), err in errors.items():
            r = err.result()
            bad, total, bad_group = impure[name]
            print(
                f"  parts {name:12s} cut at {v:.2f} m/s: {r.error:.3f} (under {r.under_rate:.3f}, "
                f"over {r.over_rate:.3f}); points not of their part's main person "
                f"{100 * bad / max(total, 1):.2f} %, of its main group "
                f"{100 * bad_group / max(total, 1):.2f} %",
                flush=True,
            )


if __name__ == "__main__":
    main()
