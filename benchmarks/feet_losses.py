"""Where the feet tracker (``track --tracker feet-pf``) loses the people of the randomised
group scenes at feet height (``random-groups``, as ``feet_random.py``): every labelled
person-scan by what the tracker had of them, split by still or moving laser and by scanner
resolution.

Per person and scan (the tracks of the person kind as ``track`` writes them, the points as
the tracker got them, all in the world frame):

- *found*: a track within 0.2 m (004 eq. 10 gives 1);
- *(c) own*: the nearest track is 0.2-0.75 m off and nearer this person than any other;
- *(c) other*: the nearest track is 0.2-0.75 m off and nearer another person (one track
  between two people of a party);
- *(b)*: a foreground point within 0.5 m, no track within 0.75 m;
- *(a) background*: a laser return within 0.5 m, none of it foreground;
- *(a) hidden*: no laser return within 0.5 m.

For the moving lasers it also counts the person-scans not found whose nearest person track
of the leg MHT (``track --tracker leg-mht`` on the same recording) lies within 0.4 m of
them and has no feet track within 0.4 m: the most that births from the leg MHT's people
could find.

    PYTHONPATH=src python benchmarks/feet_losses.py [--seeds 0-19] [--seconds 10]
        [--config params.toml]
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from feet_random import COARSE_DEG  # type: ignore[import-not-found]
from groups_random import parse_seeds  # type: ignore[import-not-found]
from laserpeople.evaluation.recordings import track_frames, truth_frames
from laserpeople.frame import Frame
from laserpeople.pipeline import build
from laserpeople.sim.scenarios import build_scene
from laserpeople.tracking import registry
from laserpeople.tracks import Tracks

FOUND = 0.2
"""A track this close finds the person [m] (004 eq. 10: m = 1)."""
NEAR = 0.75
"""A track this close is off but on the person [m]."""
POINTS = 0.5
"""Points this close are the person's [m]."""
LEG_MHT = 0.4
"""A leg MHT person this close is the person [m]."""
CLASSES = ("found", "(c) own", "(c) other", "(b)", "(a) background", "(a) hidden")


def _cli() -> list[str]:
    return [sys.executable, "-m", "laserpeople.cli"]


def _world(frame: Frame, pts: NDArray[np.float64]) -> NDArray[np.float64]:
    if frame.frame == "sensor" and frame.sensor_pose is not None:
        return np.asarray(frame.sensor_pose.transform_points(pts), dtype=np.float64)
    return pts


def _positions(path: Path) -> dict[int, NDArray[np.float64]]:
    return {
        t.scan_index: np.asarray([x.position for x in t], dtype=np.float64).reshape(-1, 2)
        for t in track_frames(path, "person")
    }


def _nearest(points: NDArray[np.float64], x: NDArray[np.float64]) -> tuple[float, int]:
    if len(points) == 0:
        return np.inf, -1
    d = np.hypot(*(points - x).T)
    k = int(np.argmin(d))
    return float(d[k]), k


def run_seed(seed: int, seconds: float, workdir: Path, config: str | None) -> Counter[str]:
    """Simulate one scene, track it with feet-pf (recording what it got) and count."""
    npz, csv, legs = (workdir / f"g{seed}{ext}" for ext in (".npz", ".csv", "_legs.csv"))
    simulate = ["simulate", "random-groups", "--seed", str(seed), "-s", f"{seconds:g}"]
    subprocess.run([*_cli(), *simulate, "-o", str(npz)], check=True, capture_output=True)
    subprocess.run(
        [*_cli(), "track", str(npz), "--tracker", "leg-mht", "-o", str(legs)],
        check=True,
        capture_output=True,
    )
    params = None
    if config is not None:
        from laserpeople.config import load_config
        from laserpeople.tracking.particle.feet import FeetParams

        params = load_config(FeetParams, config)
    tracker: Any = registry.get("feet-pf").make(params)
    fg: dict[int, NDArray[np.float64]] = {}
    every: dict[int, NDArray[np.float64]] = {}
    update = tracker.update

    def recording(frame: Frame) -> Tracks:
        assert frame.points is not None
        pts = np.asarray(frame.points.points, dtype=np.float64)
        mask = np.ones(len(pts), bool) if frame.foreground is None else frame.foreground
        every[frame.index] = _world(frame, pts)
        fg[frame.index] = _world(frame, pts[mask])
        out: Tracks = update(frame)
        return out

    tracker.update = recording
    build(npz, tracker=tracker, outputs=[csv]).run()
    tracks, people = _positions(csv), _positions(legs)
    counts: Counter[str] = Counter()
    none = np.empty((0, 2))
    for truth in truth_frames(npz):
        k = truth.scan_index
        here, mht = tracks.get(k, none), people.get(k, none)
        for j, x in enumerate(truth.positions):
            d, t = _nearest(here, x)
            if d <= FOUND:
                kind = "found"
            elif d <= NEAR:
                others = np.delete(truth.positions, j, axis=0)
                mine = len(others) == 0 or _nearest(others, here[t])[0] > d
                kind = "(c) own" if mine else "(c) other"
            elif _nearest(fg.get(k, none), x)[0] <= POINTS:
                kind = "(b)"
            elif _nearest(every.get(k, none), x)[0] <= POINTS:
                kind = "(a) background"
            else:
                kind = "(a) hidden"
            counts[kind] += 1
            m, i = _nearest(mht, x)
            if kind != "found" and m <= LEG_MHT and _nearest(here, mht[i])[0] > LEG_MHT:
                counts["leg MHT, no track"] += 1
    return counts


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seeds", default="0-19", help="tune on 0-19; held back: 100-119")
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--config", default=None, help="TOML of [feet_pf] parameters")
    args = ap.parse_args()
    groups: dict[str, Counter[str]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for seed in parse_seeds(args.seeds):
            notes = build_scene("random-groups", seconds=args.seconds, seed=seed).notes
            if notes["scanner"]["level"] != "feet":
                continue
            counts = run_seed(seed, args.seconds, Path(tmp), args.config)
            moving = bool(notes["moving_robot"])
            coarse = notes["scanner"]["resolution_deg"] >= COARSE_DEG
            print(f"seed {seed} ({'moving' if moving else 'still'}): {dict(counts)}", flush=True)
            for name in (
                "all",
                "moving" if moving else "still",
                f">= {COARSE_DEG} deg" if coarse else f"< {COARSE_DEG} deg",
            ):
                groups.setdefault(name, Counter()).update(counts)
                groups.setdefault(name + " scenes", Counter())["n"] += 1
    print(f"\nfeet-pf on random-groups at feet height, seeds {args.seeds}: person-scans")
    print("| scenes | person-scans | " + " | ".join(CLASSES) + " | leg MHT, no track |")
    print("|---|---:|" + "---:|" * (len(CLASSES) + 1))
    for name, counts in groups.items():
        if name.endswith(" scenes"):
            continue
        total = sum(counts[c] for c in CLASSES)
        shares = " | ".join(f"{100 * counts[c] / total:.1f} %" for c in CLASSES)
        scenes = groups[name + " scenes"]["n"]
        print(
            f"| {name} ({scenes}) | {total:,} | {shares} | "
            f"{100 * counts['leg MHT, no track'] / total:.1f} % |"
        )


if __name__ == "__main__":
    main()
