"""The parts of ``laserpeople track`` outside the trackers on a real recording, for two
source trees in one process: reading the bag, the static world model of the people (with
its motion check in a sensor-frame run) and the tracks CSV.

Both trees are imported (the other as ``laserpeople_ab``, ``bench_track_ab.load_other``)
and each part runs for both over the same input, alternating tree by tree ``--passes``
times (who goes first alternates); printed per part: the median process CPU time per scan
of each tree and their ratio (other / this). Parts:

- read: open the bag and decode every scan of its first laser topic (in this process,
  so the imports are not counted; ``bench_track_process.py`` counts whole processes);
- points + static world: :class:`~laserpeople.pipeline.Fuse` and
  :class:`~laserpeople.pipeline.static_people.PeopleStaticModel` (``auto``: the occupancy
  grid, learning only, as ``track`` runs it for the leg MHT) over every scan;
- CSV: the tracks of ``--tracks`` (a tracks CSV of the recording, e.g. ``track -o``)
  written again scan by scan.

    PYTHONPATH=src .venv/bin/python benchmarks/bench_outside_mht_ab.py --other OLD/src
        --tracks tracks.csv [--bag demo.bag] [--passes 5]
"""

from __future__ import annotations

import argparse
import importlib
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_track_ab import PACKAGE, load_other

DEMO = "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag"


def read(package: str, bag: Path) -> list[Any]:
    """Every scan of the first laser topic of ``bag``, read by ``package``."""
    rec = importlib.import_module(f"{package}.io").open_recording(bag)
    try:
        return list(rec.scans())
    finally:
        rec.close()


def static_world(package: str, scans: list[Any]) -> None:
    """Fuse and the people's static world model (learning only) over ``scans``."""
    frame_mod = importlib.import_module(f"{package}.frame")
    fuse = importlib.import_module(f"{package}.pipeline.preprocess").Fuse()
    model = importlib.import_module(f"{package}.pipeline.static_people").PeopleStaticModel("auto")
    model.fill_foreground = False
    for k, scan in enumerate(scans):
        frame = frame_mod.Frame(
            index=k, stamp=scan.stamp, scans=(scan,), topic=scan.sensor, frame="sensor"
        )
        model(fuse(frame))


def write_csv(package: str, tracks: list[Any], out: Path) -> None:
    """``tracks`` written as a tracks CSV ``out`` by ``package``."""
    writer_cls = importlib.import_module(f"{package}.io.tracks_csv").TracksCsvWriter
    with writer_cls(out, frame="sensor") as writer:
        for t in tracks:
            writer.write(t)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--other", type=Path, required=True, help="the other version's src/")
    ap.add_argument("--tracks", type=Path, required=True, help="a tracks CSV of the bag")
    ap.add_argument("--bag", type=Path, default=None, help="default: the shared demo bag")
    ap.add_argument("--passes", type=int, default=5)
    args = ap.parse_args()
    data = Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "/work/shared/data"))
    bag = args.bag or data / DEMO
    from laserpeople.io.tracks_csv import iter_tracks_csv

    tracks = list(iter_tracks_csv(args.tracks))
    with tempfile.TemporaryDirectory() as tmp:
        load_other(args.other, Path(tmp))
        packages = {"this": "laserpeople", "other": PACKAGE}
        scans = {name: read(pkg, bag) for name, pkg in packages.items()}
        n = len(scans["this"])
        as_sensor = {  # (the CSV's tracks as each package's Tracks in the sensor frame)
            name: [
                importlib.import_module(f"{pkg}.tracks").Tracks(
                    t.stamp, t.scan_index, t.tracks, "sensor", None
                )
                for t in tracks
            ]
            for name, pkg in packages.items()
        }
        jobs = {
            "read": lambda name, pkg: read(pkg, bag),
            "points + static world": lambda name, pkg: static_world(pkg, scans[name]),
            "CSV": lambda name, pkg: write_csv(pkg, as_sensor[name], Path(tmp) / f"{name}.csv"),
        }
        cpu: dict[tuple[str, str], list[float]] = {(j, p): [] for j in jobs for p in packages}
        for p in range(args.passes):
            order = list(packages.items())
            if p % 2:
                order.reverse()
            for job, run in jobs.items():
                for name, pkg in order:
                    t0 = time.process_time()
                    run(name, pkg)
                    cpu[(job, name)].append(time.process_time() - t0)
        print(f"{bag.name}: {n} scans, {len(tracks)} scans of tracks; {args.passes} passes")
        print(f"{'part':24s} {'other ms/scan':>14s} {'this ms/scan':>13s} {'other/this':>11s}")
        for job in jobs:
            other = 1e3 * statistics.median(cpu[(job, "other")]) / n
            this = 1e3 * statistics.median(cpu[(job, "this")]) / n
            print(f"{job:24s} {other:14.3f} {this:13.3f} {other / this:10.2f}x")


if __name__ == "__main__":
    main()
