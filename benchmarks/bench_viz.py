"""Speed and memory of the drawings.

Speed: ``.venv/bin/python benchmarks/bench_viz.py [--repeat 3] [--scans 300]`` prints the
median wall time of a GIF and an MP4 of ``--scans`` scans, a PNG overview, and the MCAP and
rerun exports, with the output sizes.

Memory: ``.venv/bin/python benchmarks/bench_viz.py --memory 1000,10000`` writes a 640x480
GIF of each number of scans in a fresh interpreter and prints its peak resident memory
(``ru_maxrss``) and wall time. ``--src DIR`` imports laserpeople from another source tree
(an older checkout's ``src`` gives the "before" figures).

Figures on the project machine (2 cores shared with 7 other jobs, load ~20; issue 15).
Before (Pillow's multi-frame writer keeps every frame until the file is closed): 500 scans
424 MB, 1,000 scans 766 MB, 2,000 scans 1,434 MB peak RSS, i.e. +0.67 MB per frame, so
10,000 scans would need about 6.9 GB. After (``viz/gif.py``: each frame's changed
rectangle is coded and appended to the open file): 1,000 scans 83 MB, 10,000 scans 127 MB
(1,206 s on the loaded machine, 4.3 MB file). What still grows is not the animation: the
``.npz`` is memory-mapped (pages read count as resident) and the extent pass keeps a few
numbers per scan. Files are smaller too: 1,000 scans 1.4 MB instead of 2.2 MB.

The scene is synthetic (a room, a 360-beam scanner, two walking people with person and
group tracks and ground truth), so the figures do not depend on the shared data.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def _scene(d: Path, n: int) -> tuple[Path, Path]:
    sys.path.insert(0, str(REPO / "tests"))
    from test_viz_support import write_scene

    return write_scene(d, n=n)


def speed(repeat: int, scans: int) -> None:
    """Median wall time of every output kind."""
    from laserpeople.errors import LaserPeopleError
    from laserpeople.viz import Scene, render

    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        rec, csv = _scene(d, scans)
        cases = {
            f"gif {scans} scans 640x480": d / "a.gif",
            "png overview 800x600": d / "a.png",
            f"mp4 {scans} scans 640x480": d / "a.mp4",
            f"mcap {scans} scans": d / "a.mcap",
            f"rrd {scans} scans": d / "a.rrd",
        }
        for label, out in cases.items():
            times = []
            try:
                for _ in range(repeat):
                    t0 = time.perf_counter()
                    render(Scene(rec, csv), out)
                    times.append(time.perf_counter() - t0)
            except LaserPeopleError as exc:  # no ffmpeg / rerun-sdk here: say so, go on
                print(f"{label:32s} skipped: {exc}")
                continue
            size = out.stat().st_size / 1e6
            print(
                f"{label:32s} median {statistics.median(times):6.2f} s  ({repeat} runs), "
                f"{size:.2f} MB"
            )


def gif_child(directory: Path) -> None:
    """Draw the scene in ``directory`` as a GIF; print frames, seconds, peak RSS [MB] (of
    this process: reading, drawing and writing, not making the scene) and file size [MB]."""
    import resource

    from laserpeople.viz import Scene, render

    out = directory / "a.gif"
    t0 = time.perf_counter()
    result = render(Scene(directory / "scene.npz", directory / "tracks.csv"), out)
    seconds = time.perf_counter() - t0
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # KiB on Linux
    print(f"{result.frames} {seconds:.1f} {peak_mb:.0f} {out.stat().st_size / 1e6:.1f}")


def memory(counts: list[int], src: Path) -> None:
    """Peak memory of a GIF of each number of scans, each drawn in a fresh interpreter (the
    scene is written beforehand by this one)."""
    env = dict(os.environ, PYTHONPATH=str(src.resolve()))
    print(f"source: {src}")
    for n in counts:
        with tempfile.TemporaryDirectory() as tmp:
            _scene(Path(tmp), n)
            done = subprocess.run(
                [sys.executable, __file__, "--gif-child", tmp],
                env=env,
                capture_output=True,
                text=True,
            )
        if done.returncode != 0:
            print(f"gif {n:6d} scans 640x480: failed: {done.stderr.strip()[-300:]}")
            continue
        frames, seconds, peak, size = done.stdout.split()[-4:]
        print(
            f"gif {n:6d} scans 640x480: peak RSS {peak:>5s} MB, {seconds:>6s} s, "
            f"{frames} frames, {size} MB file"
        )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--scans", type=int, default=300)
    parser.add_argument(
        "--memory", type=str, default=None, help="comma-separated scan counts, e.g. 1000,10000"
    )
    parser.add_argument("--src", type=Path, default=REPO / "src")
    parser.add_argument("--gif-child", type=Path, default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.gif_child is not None:
        gif_child(args.gif_child)
    elif args.memory is not None:
        memory([int(v) for v in args.memory.split(",")], args.src)
    else:
        speed(args.repeat, args.scans)


if __name__ == "__main__":
    main()
