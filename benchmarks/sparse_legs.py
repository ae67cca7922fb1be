"""Legs of one or two points (detection/sparse.py): what the rule finds, and coarse copies of
real recordings to measure it on.

``count``: on simulated ``randomised`` scenes (per-beam truth), the legs a beam hits that the
classifier finds, the legs it or the sparse-leg rule finds (a leg counted once per scan),
and how many of the rule's segments hold a leg beam (its precision) against the
classifier's::

    PYTHONPATH=src .venv/bin/python benchmarks/sparse_legs.py count --seeds 0-9

``decimate``: a copy of a ROS1 bag whose ``LaserScan`` messages keep every k-th beam (angle
increment and time increment times k), every other message as it is: what a coarser scanner
with the same beam angles records. Its label CSV stays valid (labels are positions)::

    PYTHONPATH=src .venv/bin/python benchmarks/sparse_legs.py decimate IN.bag OUT.bag 2
    PYTHONPATH=src .venv/bin/python benchmarks/followed_person.py --bag OUT.bag \\
        --labels ../shared/data/leg_tracker_benchmarks/person_following_outdoor_1_first.people.csv
"""

from __future__ import annotations

import argparse
from collections import Counter
from pathlib import Path

import numpy as np

from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.detection.sparse import SparseLegParams, sparse_legs
from laserpeople.scan import Scan
from laserpeople.segmentation import SegmentTable

LegKey = tuple[int, int]


def legs_in(table: SegmentTable, scan: Scan, rows: list[int]) -> set[LegKey]:
    """The (person, leg) whose beams are in the segments ``rows`` of ``table``."""
    assert scan.labels is not None
    is_leg = scan.labels.is_leg
    out: set[LegKey] = set()
    for i in rows:
        b = table.beams[table.offsets[i] : table.offsets[i + 1]]
        m = is_leg[b]
        out |= set(
            zip(scan.labels.person[b][m].tolist(), scan.labels.leg[b][m].tolist(), strict=True)
        )
    return out


def count(seeds: list[int], seconds: float) -> Counter[str]:
    """The counts of :func:`main`'s ``count`` over the ``randomised`` scenes ``seeds``."""
    from laserpeople.sim.scenarios import run_scenario

    off = LegDetectorParams(sparse=SparseLegParams(enabled=False))
    det = AdaBoostLegDetector.default(off)
    jump = det.segmenter.params.threshold
    total: Counter[str] = Counter()
    for seed in seeds:
        result = run_scenario("randomised", seconds=seconds, seed=seed)
        first = result.scans[0].sensor
        c: Counter[str] = Counter()
        for scan in (s for s in result.scans if s.sensor == first):
            assert scan.labels is not None
            got = det.classify(scan)
            table = got.table
            sparse = sparse_legs(table, scan, jump, SparseLegParams()).tolist()
            classified = np.flatnonzero(got.is_leg).tolist()
            holds_leg = np.zeros(len(table), dtype=bool)
            np.logical_or.at(holds_leg, table.segment_ids, scan.labels.is_leg[table.beams])
            is_leg = scan.labels.is_leg
            hit = set(
                zip(
                    scan.labels.person[is_leg].tolist(),
                    scan.labels.leg[is_leg].tolist(),
                    strict=True,
                )
            )
            c["legs hit"] += len(hit)
            c["found by the classifier"] += len(legs_in(table, scan, classified))
            c["found with sparse legs"] += len(legs_in(table, scan, classified + sparse))
            c["classifier segments"] += len(classified)
            c["classifier segments on a leg"] += int(holds_leg[classified].sum())
            c["sparse segments"] += len(sparse)
            c["sparse segments on a leg"] += int(holds_leg[sparse].sum())
        increment = np.degrees(abs(result.scans[0].angle_increment))
        print(f"seed {seed:3d} ({increment:.2f} deg): {dict(c)}", flush=True)
        total.update(c)
    return total


def decimate(src: Path, dst: Path, k: int) -> None:
    """Write ``src`` to ``dst`` with every ``k``-th beam of each ``LaserScan``."""
    from rosbags.rosbag1 import Reader, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    with Reader(src) as reader, Writer(dst) as writer:
        out = {
            c.id: writer.add_connection(
                c.topic,
                c.msgtype,
                msgdef=c.msgdef.data,
                md5sum=c.digest,
                callerid=c.ext.callerid,
                latching=c.ext.latching,
            )
            for c in reader.connections
        }
        for c, stamp, raw in reader.messages():
            if c.msgtype == "sensor_msgs/msg/LaserScan":
                m = store.deserialize_ros1(raw, c.msgtype)
                ranges = np.asarray(m.ranges)[::k].copy()
                intensities = np.asarray(m.intensities)
                m.ranges = ranges
                m.intensities = intensities[::k].copy() if intensities.size else intensities
                m.angle_increment = float(m.angle_increment * k)
                m.angle_max = float(m.angle_min + (ranges.size - 1) * m.angle_increment)
                m.time_increment = float(m.time_increment * k)
                raw = store.serialize_ros1(m, c.msgtype)
            writer.write(out[c.id], stamp, raw)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="command", required=True)
    cp = sub.add_parser("count", help="legs found on simulated randomised scenes")
    cp.add_argument("--seeds", default="0-9", help="randomised seeds (tuning: 0-49)")
    cp.add_argument("--seconds", type=float, default=30.0)
    dp = sub.add_parser("decimate", help="a ROS1 bag with every k-th beam")
    dp.add_argument("src", type=Path)
    dp.add_argument("dst", type=Path)
    dp.add_argument("k", type=int)
    args = ap.parse_args()
    if args.command == "decimate":
        decimate(args.src, args.dst, args.k)
        return
    a, _, b = args.seeds.partition("-")
    t = count(list(range(int(a), int(b or a) + 1)), args.seconds)
    print(
        f"legs found: classifier {t['found by the classifier'] / t['legs hit']:.3f}, "
        f"with sparse legs {t['found with sparse legs'] / t['legs hit']:.3f} "
        f"(of {t['legs hit']} leg-scans)"
    )
    print(
        f"segments on a leg: classifier {t['classifier segments on a leg']} of "
        f"{t['classifier segments']}, sparse legs {t['sparse segments on a leg']} of "
        f"{t['sparse segments']}"
    )


if __name__ == "__main__":
    main()
