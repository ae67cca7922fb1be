"""Speed of the drawings: a 300-scan GIF and MP4, a PNG overview, MCAP and rerun exports.

Run: ``.venv/bin/python benchmarks/bench_viz.py [--repeat 3]``; prints the median wall time
of each over the repeats. The scene is synthetic (a room, a 360-beam scanner, two walking
people with person and group tracks and ground truth), so the figures do not depend on the
shared data.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from laserpeople.errors import LaserPeopleError
from laserpeople.viz import Scene, render
from test_viz_support import write_scene


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--scans", type=int, default=300)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        rec, csv = write_scene(d, n=args.scans)
        cases = {
            f"gif {args.scans} scans 640x480": d / "a.gif",
            "png overview 800x600": d / "a.png",
            f"mp4 {args.scans} scans 640x480": d / "a.mp4",
            f"mcap {args.scans} scans": d / "a.mcap",
            f"rrd {args.scans} scans": d / "a.rrd",
        }
        for label, out in cases.items():
            times = []
            try:
                for _ in range(args.repeat):
                    t0 = time.perf_counter()
                    render(Scene(rec, csv), out)
                    times.append(time.perf_counter() - t0)
            except LaserPeopleError as exc:  # no ffmpeg / rerun-sdk here: say so, go on
                print(f"{label:32s} skipped: {exc}")
                continue
            size = out.stat().st_size / 1e6
            print(
                f"{label:32s} median {statistics.median(times):6.2f} s  ({args.repeat} runs), "
                f"{size:.2f} MB"
            )


if __name__ == "__main__":
    main()
