"""CPU of the people layer (person tracks) against another version's, replayed in one process.

The leg MHT (this version) tracks the synthetic crowd of ``bench_track.py`` once, and every
call of the people layer is recorded: the leg observations built from the best
hypothesis (``leg_observations``) and the person tracker's update with them. Both are then
replayed into this version's and the other version's ``person_tracks`` module (the other's
file loaded as a module of its own), alternately scan by scan (which goes first alternating
scan by scan: the first on a scan's objects pays more), timed by process CPU. It prints per
crowd and round the CPU per scan of each and their ratio, and checks that both give the
same observations and the same person tracks (ids, members; positions, velocities and
covariances within 1e-12 m).

    PYTHONPATH=src .venv/bin/python benchmarks/bench_people_ab.py --other /path/to/old/src
        [--people 4 20 40] [--seconds 30] [--rounds 3]
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import time
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import laserpeople.tracking.person_tracks as this
import laserpeople.tracking.synthetic as syn
from bench_track import crowd_scene
from laserpeople.tracking.registry import get

RATE = 37.5
"""Scan rate of the scene [Hz], as bench_track's default."""


def load_other(src: Path) -> ModuleType:
    """The other version's ``tracking/person_tracks.py`` as the module ``person_tracks_ab``
    (its imports of the rest of the package are this version's)."""
    path = src / "laserpeople" / "tracking" / "person_tracks.py"
    spec = importlib.util.spec_from_file_location("person_tracks_ab", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def record(n_people: int, seconds: float) -> tuple[list[Any], list[Any], Any]:
    """The calls of ``leg_observations`` and ``PersonTracker.update`` (with the tracker's
    ``moving``) while this version's default leg MHT tracks the crowd, and its parameters."""
    obs_calls: list[Any] = []
    update_calls: list[Any] = []
    saved_obs, saved_update = this.leg_observations, this.PersonTracker.update

    def obs(*args: Any) -> Any:
        obs_calls.append(args)
        return saved_obs(*args)

    def update(self: Any, legs: Any, stamp: float, max_report_unseen: float) -> Any:
        update_calls.append((legs, stamp, max_report_unseen, self.moving))
        return saved_update(self, legs, stamp, max_report_unseen)

    import laserpeople.tracking.legs as legs_module

    entry = get("leg-mht")
    frame_tracker = entry.factory(entry.params_cls())
    tracker = getattr(frame_tracker, "tracker", None) or frame_tracker
    scene = crowd_scene(n_people, seconds, RATE, synthetic=syn)
    legs_module.leg_observations = obs  # type: ignore[assignment]
    this.PersonTracker.update = update  # type: ignore[method-assign]
    try:
        for detections in scene.detections:
            tracker.update(detections)
    finally:
        legs_module.leg_observations = saved_obs
        this.PersonTracker.update = saved_update  # type: ignore[method-assign]
    return obs_calls, update_calls, tracker.params.people


def same_tracks(a: list[Any], b: list[Any]) -> bool:
    """Whether two scans' person tracks agree (ids and members exactly, arrays to 1e-12)."""
    if [(t.track_id, t.members) for t in a] != [(t.track_id, t.members) for t in b]:
        return False
    return all(
        np.allclose(x.position, y.position, rtol=0, atol=1e-12)
        and np.allclose(x.velocity, y.velocity, rtol=0, atol=1e-12)
        and np.allclose(x.covariance, y.covariance, rtol=0, atol=1e-12)
        for x, y in zip(a, b, strict=True)
    )


def same_observations(a: dict[int, Any], b: dict[int, Any]) -> bool:
    """Whether two scans' leg observations agree field by field (NaN equal to NaN)."""
    if list(a) != list(b):
        return False
    for k, x in a.items():
        y = b[k]
        for name in ("track_id", "detected", "unseen_for", "detection", "wide"):
            if getattr(x, name) != getattr(y, name):
                return False
        for name in ("score", "width"):
            u, v = getattr(x, name), getattr(y, name)
            if not (u == v or (u != u and v != v)):
                return False
        if not (np.array_equal(x.position, y.position) and np.array_equal(x.velocity, y.velocity)):
            return False
    return True


def replay(
    modules: list[ModuleType],
    obs_calls: list[Any],
    update_calls: list[Any],
    params: Any,
    first: int,
) -> tuple[list[float], list[float], int, int]:
    """CPU s of each module's leg observations and updates over the recorded calls (the
    order of the two alternating scan by scan, the module ``first`` first in the first: the
    first to run on a scan's objects pays more), and the scans whose outputs differ."""
    clock = time.process_time
    obs_cpu = [0.0, 0.0]
    upd_cpu = [0.0, 0.0]
    orders = [[first, 1 - first], [1 - first, first]]
    bad_obs = 0
    for s, args in enumerate(obs_calls):
        order = orders[s % 2]
        out: list[Any] = [None, None]
        for i in order:
            t0 = clock()
            out[i] = modules[i].leg_observations(*args)
            obs_cpu[i] += clock() - t0
        bad_obs += not same_observations(out[0], out[1])
    trackers = [m.PersonTracker(params) for m in modules]
    bad_tracks = 0
    for s, (legs, stamp, max_unseen, moving) in enumerate(update_calls):
        order = orders[s % 2]
        out = [None, None]
        for i in order:
            trackers[i].moving = moving
            t0 = clock()
            out[i] = trackers[i].update(legs, stamp, max_unseen)
            upd_cpu[i] += clock() - t0
        bad_tracks += not same_tracks(out[0], out[1])
    return obs_cpu, upd_cpu, bad_obs, bad_tracks


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--other", type=Path, required=True, help="the other version's src/")
    ap.add_argument("--people", type=int, nargs="+", default=[4, 20, 40])
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    modules = [this, load_other(args.other)]
    for n in args.people:
        obs_calls, update_calls, params = record(n, args.seconds)
        scans = len(update_calls)
        for r in range(args.rounds):
            obs_cpu, upd_cpu, bad_obs, bad_tracks = replay(
                modules, obs_calls, update_calls, params, r % 2
            )
            o = [1e3 * c / scans for c in obs_cpu]
            u = [1e3 * c / scans for c in upd_cpu]
            print(
                f"{n:3d} people, round {r + 1} ({scans} scans): person tracker this {u[0]:.3f} "
                f"other {u[1]:.3f} ms/scan, this/other {u[0] / u[1]:.3f}; leg observations "
                f"this {o[0]:.3f} other {o[1]:.3f} ms/scan, this/other {o[0] / o[1]:.3f}; "
                f"scans with different observations {bad_obs}, tracks {bad_tracks}",
                flush=True,
            )


if __name__ == "__main__":
    main()
