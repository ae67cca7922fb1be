"""Ceiling of the walkers' point split (``tracking/groups/leg_split.py``) on the simulated
entrance hall: memory-less single linkage at d_P, and the same linkage with the links
between two parts cut when their TRUE velocities differ by ``v`` or more, where the parts
are (a) the true people, (b) the blobs at d_hs (each given its main person's velocity),
(c) the walkers of :mod:`.walkers` (blob unions), (d) the walkers of the point split
(each given its main person's velocity). Also the share of points whose part's main
person is not their own (the partition's impurity). docs/groups.md "Third round".

    PYTHONPATH=src python benchmarks/groups_split_ceiling.py [--seeds 0 1] [--seconds 30]
        [--v 0.6] [--set segment_distance=0.1 point_gate=0.25 ...]
"""

from __future__ import annotations

import argparse
from dataclasses import fields, replace

import numpy as np

from laserpeople.clustering import single_linkage
from laserpeople.evaluation.clustering import ClusteringError
from laserpeople.evaluation.groups import frames_from_scans
from laserpeople.sim.scenarios import run_scenario
from laserpeople.tracking.groups.leg_split import SplitSettings, SplitWalkerTracker
from laserpeople.tracking.groups.observations import close_pairs, component_labels
from laserpeople.tracking.groups.walkers import WalkerSettings, walker_detections

IntArray = np.ndarray


def main_person(part: IntArray, person: IntArray) -> IntArray:
    """The person (N,) most points of each point's ``part`` belong to."""
    _, part_index = np.unique(part, return_inverse=True)
    people, person_index = np.unique(person, return_inverse=True)
    counts = np.zeros((part_index.max() + 1, people.size), dtype=np.int64)
    np.add.at(counts, (part_index, person_index), 1)
    return people[np.argmax(counts, axis=1)][part_index]


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
