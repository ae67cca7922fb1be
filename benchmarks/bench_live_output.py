"""Per-frame cost of `laserpeople live`'s outputs: encoding the tracks, publishing them and
writing them to the `--record` MCAP, without Zenoh and without the tracker.

A recording is tracked once with `track`'s pipeline (leg-mht) and the frames and their
tracks are kept; then they go, frame by frame, through the sinks `live --record` runs: the
publisher (here a publish function that only keeps the bytes) and the recording. Printed:
frames, tracks per frame, and the median / p90 wall and CPU (process) time per frame of the
outputs [ms], over several passes (on a loaded machine the CPU time is the steadier).

    PYTHONPATH=src .venv/bin/python benchmarks/bench_live_output.py
    PYTHONPATH=src .venv/bin/python benchmarks/bench_live_output.py --frames 300 --passes 5
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from laserpeople.frame import Frame
from laserpeople.samples import quantile
from laserpeople.tracks import Tracks

DATA = Path("/work/shared/data")
BAGS = {
    "MiR (2 lasers, world)": (
        DATA / "mir/rosbags/mir_data/legs-test-split-2022-11-21-15-51-02-topic-split.bag",
        ["front_laser_link", "back_laser_link"],
        ["mir100"],
    ),
    "demo (1 laser, sensor)": (
        DATA / "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag",
        ["/scan"],
        [],
    ),
}


class Keep:
    """A pipeline sink keeping every frame and its tracks."""

    def __init__(self) -> None:
        self.frames: list[tuple[Frame, Tracks]] = []

    def write(self, frame: Frame, tracks: Tracks | None) -> None:
        if tracks is not None:
            self.frames.append((frame, tracks))

    def close(self) -> None:
        """Nothing to close: the frames are kept in memory."""


def tracked(
    bag: Path, topics: list[str], mounts: list[str], frames: int
) -> list[tuple[Frame, Tracks]]:
    """The first ``frames`` frames of ``bag`` and their tracks (`track`'s pipeline)."""
    from laserpeople.pipeline import build

    keep = Keep()
    build(bag, topics=topics, mounts=mounts, outputs=[keep], max_frames=frames).run()
    return keep.frames


def one_pass(frames: list[tuple[Frame, Tracks]], out: Path) -> list[tuple[float, float]]:
    """Wall and CPU time per frame [ms] of the publisher's and the recording's sinks."""
    from laserpeople.live.messages import TrackEncoder, ros2_typestore
    from laserpeople.live.sinks import LiveStats, PublishSink, RecordSink
    from laserpeople.live.source import LiveScans

    wire: list[bytes] = []
    scans = LiveScans(tuple(sorted({s.sensor for f, _ in frames for s in f.scans})), None)
    encoder = TrackEncoder(ros2_typestore())
    publish = PublishSink(lambda ms: wire.extend(m.data for m in ms), encoder, scans, LiveStats())
    record = RecordSink(out, encoder)
    sinks = [publish, record]
    times = []
    for frame, tracks in frames:
        start, cpu = time.perf_counter(), time.process_time()
        for sink in sinks:
            sink.write(frame, tracks)
        times.append((1e3 * (time.perf_counter() - start), 1e3 * (time.process_time() - cpu)))
    for sink in sinks:
        sink.close()
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=300, help="frames per recording")
    parser.add_argument("--passes", type=int, default=5, help="passes over the frames")
    args = parser.parse_args()
    print(
        f"{'recording':<24} {'frames':>6} {'tracks':>6} {'wall ms':>9} {'p90':>7} "
        f"{'CPU ms':>9} {'p90':>7}"
    )
    for name, (bag, topics, mounts) in BAGS.items():
        if not bag.exists():
            print(f"{name:<24} missing: {bag}")
            continue
        frames = tracked(bag, topics, mounts, args.frames)
        per_frame = statistics.mean(len(t) for _, t in frames)
        times: list[tuple[float, float]] = []
        with tempfile.TemporaryDirectory() as tmp:
            for i in range(args.passes):
                times += one_pass(frames, Path(tmp) / f"run{i}.mcap")
        wall, cpu = [w for w, _ in times], [c for _, c in times]
        print(
            f"{name:<24} {len(frames):>6} {per_frame:>6.1f} {quantile(wall, 0.5):>9.2f} "
            f"{quantile(wall, 0.9):>7.2f} {quantile(cpu, 0.5):>9.2f} {quantile(cpu, 0.9):>7.2f}",
            flush=True,
        )


if __name__ == "__main__":
    main()
