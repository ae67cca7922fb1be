"""How fast the occupancy grid asks a prior map whether a frame's points lie near an
obstacle (``OccupancyGrid.static_time``): the map dilated once to the grid's reach
(:meth:`~laserpeople.background.occupancy.OccupancyMap.dilated`, what the grid does)
against looking up the (2r + 1)^2 window of pixels around every point in every frame (what
it did before), side by side in one process, runs interleaved, medians.

Run: ``PYTHONPATH=src .venv/bin/python benchmarks/bench_prior_lookup.py [--runs 5]``

On the lobby bag of a robot driving among people (``../shared/data``), with the map of what
stayed put in it (:func:`~laserpeople.pipeline.prelearn.count_recording_map`) and the reach
of the default grid (0.2 m: 4 pixels of 0.05 m). Both give the same answer for every point.
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np
from numpy.typing import NDArray

from bench_prelearn import RECORDINGS, frames_of  # type: ignore[import-not-found]
from laserpeople.background.occupancy import OccupancyMap
from laserpeople.pipeline.background import StaticWorldParams
from laserpeople.pipeline.prelearn import count_recording_map
from laserpeople.pipeline.preprocess import Fuse

REACH = 4
"""Pixels of 0.05 m the default grid looks around a point ((1 + 1) cells of 0.1 m)."""


def window_lookup(grid: OccupancyMap, pos: NDArray[np.float64], radius: int) -> NDArray[np.bool_]:
    """The reference: every pixel of the window around each position, one pass each."""
    x0, y0, yaw = grid.origin
    c, s = math.cos(yaw), math.sin(yaw)
    dx, dy = pos[:, 0] - x0, pos[:, 1] - y0
    u = (c * dx + s * dy) / grid.resolution
    v = (-s * dx + c * dy) / grid.resolution
    h, w = grid.occupied.shape
    col = np.floor(u).astype(np.int64)
    row = h - 1 - np.floor(v).astype(np.int64)
    hit = np.zeros(pos.shape[0], dtype=bool)
    for dr in range(-radius, radius + 1):
        for dc in range(-radius, radius + 1):
            r, q = row + dr, col + dc
            ok = (r >= 0) & (r < h) & (q >= 0) & (q < w)
            hit[ok] |= grid.occupied[r[ok], q[ok]]
    return hit


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    path = RECORDINGS["lobby (moving)"]
    if not path.exists():
        print(f"skipped: {path} not found")
        return
    frames = list(frames_of(path)())
    grid, _ = count_recording_map(frames, StaticWorldParams())
    assert grid is not None
    fuse = Fuse()
    points = [fuse(f).points.points for f in frames]  # type: ignore[union-attr]
    start = time.process_time()
    near = grid.dilated(REACH)
    dilation = time.process_time() - start
    windows, dilated = [], []
    for _ in range(args.runs):
        start = time.process_time()
        expect = [window_lookup(grid, p, REACH) for p in points]
        windows.append(time.process_time() - start)
        start = time.process_time()
        got = [near.contains_obstacle(p) for p in points]
        dilated.append(time.process_time() - start)
    same = sum(bool((a == b).all()) for a, b in zip(expect, got, strict=True))
    n = len(points)
    a, b = statistics.median(windows), statistics.median(dilated)
    print(
        f"lobby: {n} frames, {np.mean([len(p) for p in points]):.0f} points a frame, map "
        f"{grid.occupied.shape[0]} x {grid.occupied.shape[1]} pixels"
    )
    print(f"window per point   {1e3 * a / n:.3f} ms a frame")
    print(f"dilated once       {1e3 * b / n:.3f} ms a frame (dilation {1e3 * dilation:.1f} ms)")
    print(f"ratio              {a / b:.1f}; the same answer in {same} of {n} frames")


if __name__ == "__main__":
    main()
