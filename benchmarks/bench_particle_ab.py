"""Speed of the particle-filter trackers of 004 (``feet-pf``, ``upper-body-pf``) against
another version of the code, in one process (A/B), on real and simulated recordings.

Each recording is run once through this version's pipeline as ``laserpeople track`` runs
it (reading, the static world model, on a moving laser the points near legs), and the
frames the tracker got are kept; then a tracker of each version (the other one's
``src/laserpeople`` imported as ``laserpeople_ab``, ``bench_track_ab.load_other``), each
made afresh per pass, updates on the same frames alternately, frame by frame (who goes
first follows the Thue-Morse sequence, and flips from pass to pass), so both see the same
load. Printed per recording and tracker: the median process CPU time of one update (ms)
of each version, the mean over all frames, and their ratios (other / this); and whether
the two versions reported the same tracks (ids the same, positions within 1e-9 m) in
every frame.

    PYTHONPATH=src .venv/bin/python benchmarks/bench_particle_ab.py --other OLD/src
        [--recordings demo followed sim people-5] [--trackers feet-pf upper-body-pf]
        [--passes 3]

``demo`` is the leg_tracker demo bag, ``followed`` the followed-person dev recording
(``/scan_base2``), ``sim`` the held-back scene ``feet-crossing`` seed 100 (simulated here),
``people-5`` 004's scene of five people with 500 particles per filter, the frames made as
``bench_particle.py`` makes them (not in the default list); the real ones are read from
``--data`` (the shared data folder).
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

RECORDINGS = {
    "demo": ("leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag", None),
    "followed": (
        "leg_tracker_benchmarks/person_following_outdoor_1_first.bag",
        "/scan_base2",
    ),
}


def frames_of(path: Path, topic: str | None, tracker: str) -> list[Any]:
    """The frames ``tracker`` gets from this version's pipeline over the recording."""
    from laserpeople.pipeline import build

    pipe = build(path, tracker=tracker, topics=[topic] if topic else None)
    return [step.frame for step in pipe]


def schenk_frames(tracker: str, seed: int = 100) -> list[Any]:
    """The frames of 004's scene "5 pers." (``people-5``) as ``bench_particle.py`` makes
    them: the lasers at the tracker's height fused, the background learnt from the empty
    scene subtracted."""
    from laserpeople.background.beam_histogram import BeamHistogramBackground
    from laserpeople.evaluation.schenk_scenes import lasers_of, simulate_scene
    from laserpeople.tracking.particle.frames import fused_frames

    rec, empty = simulate_scene("people-5", seed)
    sensors = lasers_of(rec, "feet" if tracker == "feet-pf" else "torso")
    bg = BeamHistogramBackground().learn_scans(s for s in empty.scans if s.sensor in sensors)
    return list(fused_frames(rec.scans, sensors, bg))


def make(package: str, tracker: str) -> Any:
    """A new frame tracker of ``package`` with its default parameters (the point guard in
    front, as ``track`` makes it)."""
    return importlib.import_module(f"{package}.tracking.registry").get(tracker).make()


def same(a: Any, b: Any) -> bool:
    """Whether two scans' tracks have the same ids, kinds and positions within 1e-9 m."""
    ta, tb = list(a.tracks), list(b.tracks)
    if len(ta) != len(tb):
        return False
    for x, y in zip(ta, tb, strict=True):
        if x.track_id != y.track_id or str(x.kind) != str(y.kind):
            return False
        if any(
            abs(float(u) - float(v)) > 1e-9 for u, v in zip(x.position, y.position, strict=True)
        ):
            return False
    return True


def run(frames: list[Any], tracker: str, passes: int) -> dict[str, Any]:
    """Per version (this, other): the per-frame CPU times of every pass, and whether the
    tracks agreed."""
    times: dict[str, list[float]] = {"laserpeople": [], PACKAGE: []}
    agree = True
    clock = time.process_time
    for k in range(passes):
        order = ["laserpeople", PACKAGE] if k % 2 == 0 else [PACKAGE, "laserpeople"]
        trackers = {pkg: make(pkg, tracker) for pkg in order}
        for i, frame in enumerate(frames):
            out = {}
            # who goes first: the Thue-Morse sequence (the parity of the ones in i), so
            # that every pair, 2nd, 4th, ... frame has each first once (docs/speed.md)
            for pkg in order if bin(i).count("1") % 2 == 0 else order[::-1]:
                t0 = clock()
                out[pkg] = trackers[pkg].update(frame)
                times[pkg].append(clock() - t0)
            agree &= same(out["laserpeople"], out[PACKAGE])
    return {"times": times, "agree": agree}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--other", type=Path, required=True, help="the other version's src/")
    ap.add_argument("--recordings", nargs="+", default=["demo", "followed", "sim"])
    ap.add_argument("--trackers", nargs="+", default=["feet-pf", "upper-body-pf"])
    ap.add_argument("--passes", type=int, default=3)
    ap.add_argument(
        "--data",
        type=Path,
        default=Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "../shared/data")),
    )
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        load_other(args.other, Path(tmp))
        print(
            f"{'recording':<10s} {'tracker':<14s} {'frames':>6s} {'median ms: other':>17s}"
            f" {'this':>7s} {'ratio':>6s} {'mean ms: other':>15s} {'this':>7s} {'ratio':>6s}"
            f"  tracks"
        )
        for name in args.recordings:
            path: Path | None
            if name == "people-5":
                path, topic = None, None
            elif name == "sim":
                from laserpeople.sim import run_scenario

                path = run_scenario("feet-crossing", seed=100).write(Path(tmp) / "sim.npz")
                topic = None
            else:
                rel, topic = RECORDINGS[name]
                path = args.data / rel
                if not path.exists():
                    print(f"{name}: no recording at {path}: left out")
                    continue
            for tracker in args.trackers:
                frames = schenk_frames(tracker) if path is None else frames_of(path, topic, tracker)
                r = run(frames, tracker, args.passes)
                t = r["times"]
                med = {k: 1e3 * statistics.median(v) for k, v in t.items()}
                mean = {k: 1e3 * statistics.fmean(v) for k, v in t.items()}
                this, other = "laserpeople", PACKAGE
                print(
                    f"{name:<10s} {tracker:<14s} {len(frames):>6d} {med[other]:>17.3f}"
                    f" {med[this]:>7.3f} {med[other] / med[this]:>6.3f} {mean[other]:>15.3f}"
                    f" {mean[this]:>7.3f} {mean[other] / mean[this]:>6.3f}"
                    f"  {'the same' if r['agree'] else 'DIFFER'}",
                    flush=True,
                )


if __name__ == "__main__":
    main()
