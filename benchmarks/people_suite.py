"""People-tracking suite on scenes nobody tuned on: mean MOTA, IDF1, ID switches, person-
track-seconds on static objects per scene family, and CPU ms per scan.

Scenes (all simulated, then detected with the shipped AdaBoost leg detector, so every
tracker sees the same real-detector output):

- ``randomised``: the held-back seeds 100-119 of the randomised family
  (laserpeople.sim.scenarios.randomised). **Never tune on these seeds**; tune on 0-49.
- ``furniture-only``: ``randomised-furniture`` with the same held-back seeds (nobody there:
  every person track is false; the static-object column is the figure to read).
- ``moving-robot``: a robot driving down a hallway into a lobby among people
  (laserpeople.sim.scenarios.moving_robot, issue 29), the same seeds (tune on 0-9).
- ``crossing-3``, ``narrow-corridor``, ``entrance-hall``: the library scenes, seed 0 unless
  ``--named-seeds`` says otherwise.
- ``random-groups`` (only with ``--family random-groups``): parties that walk, split, meet
  and cross (laserpeople.sim.scenarios.random_groups), the same seeds (tune on 0-9).

Person-track-seconds on static objects: a person track within 0.3 m of a return from a
non-person object and farther than 0.75 m from every true person, times the scan period
(laserpeople.evaluation.suite.static_track_seconds). CPU ms per scan: process CPU time of the
tracker's update, detection excluded.

    PYTHONPATH=src .venv/bin/python benchmarks/people_suite.py --tracker leg-mht --tracker nn \\
        [--config params.toml] [--seconds 30] [--seeds 100-119] [--json out.json]
        [--background none --background auto]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from dataclasses import asdict
from pathlib import Path
from typing import Any

from laserpeople.config import load_config
from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.evaluation.suite import (
    PreparedScene,
    SceneScore,
    SuiteScene,
    format_table,
    prepare,
    summarise,
    track_scene,
)
from laserpeople.pipeline.background import load_static_world
from laserpeople.pipeline.recording import leg_reid_stage, tracker_stages
from laserpeople.pipeline.stages import Identifier
from laserpeople.pipeline.static_people import uses_static_model
from laserpeople.sim.scenarios.randomised import HELD_BACK_SEEDS, TUNING_SEEDS
from laserpeople.tracking import registry
from laserpeople.tracking.registry import POINT_FIELDS

NAMED = ("crossing-3", "narrow-corridor", "entrance-hall")


def parse_seeds(text: str) -> list[int]:
    """``"100-119"`` or ``"1,2,5"`` -> the seeds."""
    out: list[int] = []
    for part in text.split(","):
        if "-" in part:
            lo, hi = part.split("-")
            out += list(range(int(lo), int(hi) + 1))
        elif part.strip():
            out.append(int(part))
    return out


def suite_scenes(
    seeds: list[int], seconds: float, named_seeds: list[int], families: list[str] | None = None
) -> list[SuiteScene]:
    """The scenes of the suite, in report order."""
    scenes = [SuiteScene("randomised", "randomised", s, seconds) for s in seeds]
    scenes += [SuiteScene("furniture-only", "randomised-furniture", s, seconds) for s in seeds]
    scenes += [SuiteScene("moving-robot", "moving-robot", s, seconds) for s in seeds]
    for name in NAMED:
        scenes += [SuiteScene(name, name, s) for s in named_seeds]
    if families and "random-groups" in families:  # asked for by name only
        scenes += [SuiteScene("random-groups", "random-groups", s, seconds) for s in seeds]
    if families:
        scenes = [s for s in scenes if s.family in families]
    return scenes


class Staged:
    """A tracker behind the stages that :func:`laserpeople.pipeline.build` gives it: the
    points' stages of a tracker of points (fusion, background, clustering; the suite fills
    only scans and legs), the people's static world model, and its identify stages: the
    static-track filter of a tracker without a static world of its own
    (``pipeline/static_tracks.py``) and the re-identification by leg widths of a tracker of
    points (``identity/leg_width.py``)."""

    def __init__(self, tracker: Any, stages: list[Any], identify: list[Identifier]) -> None:
        self.tracker = tracker
        self.stages = stages
        self.identify = identify
        self.consumes = (frozenset(tracker.consumes) & {"legs"}) | {"scans"}

    def update(self, frame: Any) -> Any:
        """Run the stages on ``frame``, track it, run the identify stages (leave out the
        people on static places, re-identify)."""
        for stage in self.stages:
            frame = stage(frame)
        tracks = self.tracker.update(frame)
        for stage in self.identify:
            tracks = stage.update(tracks, frame)
        return tracks


def make_factory(name: str, config: Path | None, background: str = "auto") -> Any:
    """A maker of a new tracker; a tracker that asks a static world model (the leg MHT's
    people) gets the model ``background`` fed from each frame, a tracker of points its
    points' stages, and one without a model of its own the static-track filter
    (``[static_tracks]`` of ``config``), as the pipeline does."""
    from laserpeople.pipeline.static_people import StaticFed, people_static_model

    entry = registry.get(name)
    params = load_config(entry.params_cls, config)
    static = load_static_world(config)

    def make() -> Any:
        tracker = entry.factory(params)
        if uses_static_model(tracker) and not tracker.consumes & POINT_FIELDS:
            model = people_static_model(background, static=static)
            tracker.use_static_model(model)
            if model is not None:
                return StaticFed(tracker, model)
            return tracker
        stages, observe, hide = tracker_stages(  # the suite's frames hold legs already
            tracker,
            consumes=frozenset(tracker.consumes) - {"legs"},
            background=background,
            static_world=static,
        )
        identify = [s for s in (hide, leg_reid_stage(tracker, static)) if s is not None]
        if stages or observe or identify:
            return Staged(tracker, [*stages, *observe], identify)
        return tracker

    return make


def at_height(make: Any, height: float | None) -> Any:
    """A maker of ``make``'s trackers told the scene's laser height [m] (None: unknown)
    when they take torso-shaped runs, as :func:`laserpeople.pipeline.build` tells them the
    recording's."""
    from laserpeople.pipeline.background import set_laser_height
    from laserpeople.pipeline.leg_foreground import wants_torso_runs

    def made() -> Any:
        tracker = make()
        if wants_torso_runs(getattr(tracker, "tracker", None)):
            set_laser_height([*tracker.stages, tracker.tracker], height)
        return tracker

    return made


def _takes_model(tracker: Any) -> bool:
    """Whether ``background`` changes what ``tracker`` reports (it asks a model, or has none
    of its own and gets the static-track filter)."""
    return uses_static_model(tracker) or not callable(getattr(tracker, "use_static_model", None))


def run(
    trackers: list[str],
    config: Path | None,
    scenes: list[SuiteScene],
    extra: dict[str, Any] | None = None,
    log: Any = sys.stderr,
    backgrounds: list[str] | None = None,
) -> list[SceneScore]:
    """Prepare each scene once and run every tracker on it. ``extra`` maps more labels to
    callables ``(prepared) -> SceneScore`` (the peers script adds Stone Soup's trackers).
    With several ``backgrounds`` (static world models), a tracker that asks one runs once
    per model, labelled ``name[model]``."""
    detector = AdaBoostLegDetector.default(load_config(LegDetectorParams, config))
    factories: dict[str, Any] = {}
    for name in trackers:
        probe = registry.get(name).make()
        if backgrounds and len(backgrounds) > 1 and _takes_model(probe):
            for bg in backgrounds:
                factories[f"{name}[{bg}]"] = make_factory(name, config, bg)
        else:
            factories[name] = make_factory(name, config, (backgrounds or ["auto"])[0])
    scores: list[SceneScore] = []
    for scene in scenes:
        prepared: PreparedScene = prepare(scene, detector)
        for name, factory in factories.items():
            score, _ = track_scene(prepared, at_height(factory, prepared.laser_height), name)
            scores.append(score)
            _log(score, log)
        for fn in (extra or {}).values():
            score = fn(prepared)
            scores.append(score)
            _log(score, log)
    return scores


def _log(s: SceneScore, log: Any) -> None:
    print(
        f"  {s.scene.family:15s} {s.scene.scenario:22s} seed {s.scene.seed:3d} {s.tracker:12s} "
        f"MOTA {s.mota:6.3f} IDF1 {s.idf1:6.3f} IDsw {s.id_switches:3d} "
        f"static {s.static.seconds:6.1f} s  {s.cpu_ms:6.2f} ms/scan",
        file=log,
        flush=True,
    )


def to_json(scores: list[SceneScore]) -> list[dict[str, Any]]:
    def clean(v: Any) -> Any:
        if isinstance(v, float) and not math.isfinite(v):
            return None
        if isinstance(v, dict):
            return {k: clean(x) for k, x in v.items()}
        return v

    return [clean(asdict(s)) for s in scores]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--tracker", action="append", help="registered tracker (repeatable)")
    ap.add_argument("--config", type=Path, help="TOML with the trackers' and detector's sections")
    ap.add_argument("--seconds", type=float, default=30.0, help="length of randomised scenes [s]")
    ap.add_argument("--seeds", default="100-119", help="randomised seeds (held back: 100-119)")
    ap.add_argument("--named-seeds", default="0", help="seeds of crossing-3 etc.")
    ap.add_argument("--family", action="append", help="run only these families")
    ap.add_argument("--json", type=Path, help="write every scene's scores here")
    ap.add_argument(
        "--background",
        action="append",
        help="static world model of the leg MHT's people (auto, histogram, occupancy, none; "
        "repeatable: one run per model; default auto, as `laserpeople track`)",
    )
    args = ap.parse_args()
    seeds = parse_seeds(args.seeds)
    tuning = sorted(set(seeds) & set(TUNING_SEEDS))
    if tuning and set(seeds) != set(HELD_BACK_SEEDS):
        print(f"note: seeds {tuning} are tuning seeds, not the held-back set", file=sys.stderr)
    scenes = suite_scenes(seeds, args.seconds, parse_seeds(args.named_seeds), args.family)
    scores = run(args.tracker or ["leg-mht"], args.config, scenes, backgrounds=args.background)
    print(format_table(summarise(scores)))
    if args.json:
        args.json.write_text(json.dumps(to_json(scores), indent=1))


if __name__ == "__main__":
    main()
