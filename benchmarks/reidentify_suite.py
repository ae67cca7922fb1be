"""Re-identification of lost people on the people suite: the leg MHT's default people
policy with re-identification off and on (and the paper's ``arras`` policy), on the same
prepared scenes in one run. A wrong re-identification shows up as an ID switch.

Scenes as in ``benchmarks/people_suite.py`` (held-back randomised seeds 100-119, furniture
only, crossing-3, narrow-corridor, entrance-hall); **never tune on seeds 100-119**.

    PYTHONPATH=src .venv/bin/python benchmarks/reidentify_suite.py [--seeds 100-119]
        [--family randomised] [--no-arras] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

from laserpeople.detection.detector import AdaBoostLegDetector
from laserpeople.evaluation.suite import (
    PreparedScene,
    format_table,
    prepare,
    summarise,
    track_scene,
)
from laserpeople.tracking import registry
from laserpeople.tracking.legs import LegTrackerParams
from people_suite import _log, parse_seeds, suite_scenes, to_json


def variants(with_arras: bool) -> dict[str, LegTrackerParams]:
    """Label -> leg MHT parameters of each variant."""
    on = LegTrackerParams()
    off = replace(on, people=replace(on.people, reid=replace(on.people.reid, enabled=False)))
    out = {"tracks, no reid": off, "tracks + reid": on}
    if with_arras:
        out["arras"] = replace(on, people_policy="arras")
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--seeds", default="100-119")
    ap.add_argument("--named-seeds", default="0")
    ap.add_argument("--family", action="append")
    ap.add_argument("--no-arras", action="store_true")
    ap.add_argument("--json", type=Path)
    args = ap.parse_args()
    scenes = suite_scenes(
        parse_seeds(args.seeds), args.seconds, parse_seeds(args.named_seeds), args.family
    )
    entry = registry.get("leg-mht")
    detector = AdaBoostLegDetector.default()
    scores = []
    for scene in scenes:
        prepared: PreparedScene = prepare(scene, detector)
        for label, params in variants(not args.no_arras).items():

            def factory(p: LegTrackerParams = params) -> Any:
                return entry.factory(p)

            score, _ = track_scene(prepared, factory, label)
            scores.append(score)
            _log(score, sys.stderr)
    print(format_table(summarise(scores)))
    if args.json:
        args.json.write_text(json.dumps(to_json(scores), indent=1))


if __name__ == "__main__":
    main()
