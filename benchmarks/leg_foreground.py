"""The foreground of the point trackers on simulated randomised scenes: the papers' (every
point the static world model does not explain, ``[leg_foreground] use = "never"``) against
the points near leg detections (``pipeline/leg_foreground.py``) with several settings.

Each scene is simulated and detected once (the shipped AdaBoost detector); every tracker runs
once per setting, as ``laserpeople track --tracker NAME`` with ``--background auto`` feeds
it. A setting is a name and a TOML text of ``[leg_foreground]`` (and other) sections. Prints
mean MOTA, IDF1, ID switches, static seconds and CPU ms per scan per tracker and setting, for
the scenes with a moving robot and those with a still laser apart.

Tune only on the tuning seeds 0-49; the held-back seeds 100-119 are for people_suite.py.

With ``--recording`` instead: the process CPU per frame of every stage and the tracker on a
recording (``laserpeople track`` as a pipeline), with the default and with ``use = "never"``.

    PYTHONPATH=src .venv/bin/python benchmarks/leg_foreground.py --seeds 0-49 \\
        [--tracker csa --tracker feet-pf --tracker upper-body-pf] [--seconds 30] \\
        [--setting never 'use = "never"' --setting r35 'radius = 0.35'] [--json out.json]
    PYTHONPATH=src .venv/bin/python benchmarks/leg_foreground.py --recording BAG \\
        --topic /scan_base2 [--setting NAME TOML ...] [--rounds 2]
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import tempfile
from pathlib import Path
from typing import Any

from laserpeople.detection.detector import AdaBoostLegDetector
from laserpeople.evaluation.suite import SuiteScene, prepare, track_scene

sys.path.insert(0, str(Path(__file__).resolve().parent))
from people_suite import make_factory, parse_seeds

DEFAULT_SETTINGS = (
    ("never", 'use = "never"'),
    ("r15", "radius = 0.15"),
    ("r35", "radius = 0.35"),
    ("r60", "radius = 0.6"),
)


def moved(scans: Any, distance: float = 0.05) -> bool:
    """Whether the scanner of ``scans`` moved farther than ``distance`` [m] from its first
    pose (False without poses)."""
    poses = [s.pose for s in scans if s.pose is not None]
    return any(math.hypot(p.x - poses[0].x, p.y - poses[0].y) > distance for p in poses)


def cpu_on_recording(
    recording: Path,
    topic: str | None,
    trackers: list[str],
    settings: list[tuple[str, str]] | None = None,
    rounds: int = 1,
) -> None:
    """Print the process CPU per frame [ms] of each stage and the tracker on ``recording``,
    with the default foreground and with ``[leg_foreground] use = "never"`` (or with each
    of ``settings``: name and ``[leg_foreground]`` TOML body), ``rounds`` times in turn."""
    import time

    from laserpeople.pipeline import build
    from laserpeople.pipeline.background import StaticWorldParams, load_static_world
    from laserpeople.pipeline.leg_foreground import LegForegroundParams

    never = StaticWorldParams(leg_foreground=LegForegroundParams(use="never"))
    chosen = [("default", StaticWorldParams()), ("never", never)]
    if settings:
        tmp = Path(tempfile.mkdtemp(prefix="leg_foreground_"))
        chosen = []
        for name, body in settings:
            path = tmp / f"{name}.toml"
            path.write_text(f"[leg_foreground]\n{body}\n")
            chosen.append((name, load_static_world(path)))
    for name, static in [c for _ in range(rounds) for c in chosen]:
        for t in trackers:
            pipe = build(recording, tracker=t, topics=[topic] if topic else None,
                         static_world=static)  # fmt: skip
            cpu: dict[str, float] = {}

            def timed(stage: Any, cpu: dict[str, float] = cpu) -> Any:
                def run(frame: Any) -> Any:
                    t0 = time.process_time()
                    out = stage(frame)
                    key = type(stage).__name__
                    cpu[key] = cpu.get(key, 0.0) + time.process_time() - t0
                    return out

                return run

            pipe.stages = tuple(timed(s) for s in pipe.stages)
            t0 = time.process_time()
            stats = pipe.run()
            total = time.process_time() - t0
            n = max(stats.frames, 1)
            parts = ", ".join(f"{k} {1e3 * v / n:.2f}" for k, v in cpu.items())
            print(
                f"{name:8s} {t:14s} {stats.frames} frames: {1e3 * total / n:.2f} ms/frame "
                f"(tracker {stats.mean_ms:.2f}; {parts})",
                flush=True,
            )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seeds", default="0-49", help="randomised seeds (tune on 0-49)")
    ap.add_argument("--tracker", action="append", help="registered tracker (repeatable)")
    ap.add_argument("--seconds", type=float, default=30.0, help="length of each scene [s]")
    ap.add_argument("--family", default="randomised", help="scenario (randomised or a named one)")
    ap.add_argument(
        "--setting",
        nargs=2,
        action="append",
        metavar=("NAME", "TOML"),
        help="a setting: name and the body of a [leg_foreground] section (repeatable)",
    )
    ap.add_argument("--json", type=Path, help="write every run's scores here")
    ap.add_argument(
        "--moving-only", action="store_true", help="only the scenes whose scanner rides a robot"
    )
    ap.add_argument("--recording", type=Path, help="time the stages on this recording instead")
    ap.add_argument("--topic", help="laser topic of --recording (default: the first)")
    ap.add_argument("--rounds", type=int, default=1, help="with --recording: runs per setting")
    args = ap.parse_args()
    trackers = args.tracker or ["csa", "feet-pf", "upper-body-pf"]
    if args.recording is not None:
        chosen = [(n, b) for n, b in args.setting] if args.setting else None
        cpu_on_recording(args.recording, args.topic, trackers, chosen, args.rounds)
        return
    settings = [tuple(s) for s in args.setting] if args.setting else list(DEFAULT_SETTINGS)
    tmp = Path(tempfile.mkdtemp(prefix="leg_foreground_"))
    factories: dict[tuple[str, str], Any] = {}
    for name, body in settings:
        path = tmp / f"{name}.toml"
        path.write_text(f"[leg_foreground]\n{body}\n")
        for t in trackers:
            factories[(t, name)] = make_factory(t, path, "auto")
    detector = AdaBoostLegDetector.default()
    rows: list[dict[str, Any]] = []
    seeds = parse_seeds(args.seeds)
    if args.moving_only:
        from laserpeople.sim.scenarios import build_scene

        seeds = [
            s for s in seeds
            if build_scene(args.family, seconds=args.seconds, seed=s).notes.get("moving_robot")
        ]  # fmt: skip
    for seed in seeds:
        scene = SuiteScene(args.family, args.family, seed, args.seconds)
        prepared = prepare(scene, detector)
        moving = moved(prepared.scans)
        for (t, name), factory in factories.items():
            score, _ = track_scene(prepared, factory, f"{t}[{name}]")
            row = {
                "seed": seed,
                "moving": moving,
                "tracker": t,
                "setting": name,
                "mota": score.mota,
                "idf1": score.idf1,
                "idsw": score.id_switches,
                "static_s": score.static.seconds,
                "ms": score.cpu_ms,
            }
            rows.append(row)
            print(
                f"seed {seed:3d} {'moving' if moving else 'still '} {t:14s} {name:8s} "
                f"MOTA {score.mota:7.3f} IDF1 {score.idf1:6.3f} IDsw {score.id_switches:3d} "
                f"static {score.static.seconds:6.1f} s {score.cpu_ms:6.2f} ms",
                file=sys.stderr,
                flush=True,
            )
    print("| robot | tracker | setting | scenes | MOTA | IDF1 | ID sw. | static s | ms/scan |")
    print("|---|---|---|---|---|---|---|---|---|")
    for moving in (True, False):
        for t in trackers:
            for name, _ in settings:
                sel = [
                    r for r in rows if r["moving"] == moving and r["tracker"] == t
                    and r["setting"] == name
                ]  # fmt: skip
                if not sel:
                    continue
                mean = {
                    k: statistics.fmean(float(r[k]) for r in sel if r[k] == r[k])
                    for k in ("mota", "idf1", "idsw", "static_s", "ms")
                }
                print(
                    f"| {'moving' if moving else 'still'} | {t} | {name} | {len(sel)} | "
                    f"{mean['mota']:.3f} | {mean['idf1']:.3f} | {mean['idsw']:.1f} | "
                    f"{mean['static_s']:.1f} | {mean['ms']:.2f} |"
                )
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
