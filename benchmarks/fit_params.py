"""Learned vs default parameters (``laserpeople fit``, 000 Sec. 3.4 and 4.6).

Parts (``--part``, repeatable; all by default):

- ``legs-tune``: for development: learned on tuning seeds 0-6, default vs learned on tuning
  seeds 7-9 (all that may be looked at while changing the counting rules).
- ``legs-sim``: the leg MHT's parameters learned on the randomised *tuning* seeds 0-9
  (30 s each, every person labelled), then default vs learned on the *held-back* seeds
  100-119 (a final check: reported, never iterated on): mean MOTA and IDF1 over scenes.
- ``legs-dev``: the real dev recording of the leg_tracker benchmark (followed person):
  learned on its first 60 % (``--validation 0.4``), default vs learned on the rest
  (identity recall, recall, ids); also the parameters learned on the simulated seeds.
- ``groups``: the group tracker's probabilities learned on entrance-hall seeds 3-5 (60 s),
  default vs learned on seeds 1-2 (the seeds of docs/groups.md): clustering error and
  group-size error.

    PYTHONPATH=src LASERPEOPLE_SHARED_DATA=../shared/data nice -n 10 \\
        python benchmarks/fit_params.py [--part legs-sim] [--out-dir out/fit]
"""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path

import numpy as np

from laserpeople.config import load_config
from laserpeople.detection.detector import AdaBoostLegDetector
from laserpeople.fitting import data
from laserpeople.fitting.flow import FitResult, learn, write_result
from laserpeople.fitting.groups import GroupModelFitter
from laserpeople.fitting.legs import LegMHTFitter
from laserpeople.fitting.output import write
from laserpeople.fitting.validate import ValidationRow, validate_groups, validate_legs
from laserpeople.sim.scenarios import run_scenario
from laserpeople.tracking.groups.params import GroupTrackerParams
from laserpeople.tracking.legs import LegTrackerParams
from laserpeople.tracks import Detections

DEV = "leg_tracker_benchmarks/person_following_outdoor_1_first"


def simulated(scenario: str, seed: int, seconds: float, detect: object) -> data.LabelledRecording:
    """A simulated scene as a labelled recording (first sensor)."""
    r = run_scenario(scenario, seconds=seconds, seed=seed)
    first = r.scans[0].sensor
    scans = [s for s in r.scans if s.sensor == first]
    return data.build(
        f"{scenario} seed {seed}",
        scans,
        r.truth,
        detect,
        followed=False,  # type: ignore[arg-type]
    )


def no_legs(scan: object) -> Detections:
    return Detections.empty(scan.stamp, scan.index, "sensor", scan.pose)  # type: ignore[attr-defined]


def table(rows: list[ValidationRow], title: str) -> None:
    """Per-recording rows and the mean over recordings per parameter set."""
    print(f"\n{title}\n")
    metrics = list(dict.fromkeys(m for r in rows for m in r.scores))
    print("| recording | parameters | " + " | ".join(metrics) + " |")
    print("|---|---|" + "---|" * len(metrics))
    for r in rows:
        vals = " | ".join(f"{r.scores.get(m, math.nan):.3f}" for m in metrics)
        print(f"| {r.recording} | {r.label} | {vals} |")
    for label in dict.fromkeys(r.label for r in rows):
        mine = [r for r in rows if r.label == label]
        means = []
        for m in metrics:
            v = [r.scores[m] for r in mine if m in r.scores and math.isfinite(r.scores[m])]
            means.append(f"{np.mean(v):.3f}" if v else "–")
        print(f"| **mean of {len(mine)}** | {label} | " + " | ".join(means) + " |")


def legs_tune(seconds: float) -> None:
    detect = AdaBoostLegDetector.default().detect
    recs = [simulated("randomised", s, seconds, detect) for s in range(10)]
    fitter = LegMHTFitter().fit(recs[:7])
    for e in fitter.estimates_:
        print(f"  {e.key:28s} {e.value:.6g}   ({e.note})")
    rows = validate_legs(recs[7:], {"default": LegTrackerParams(), "learned": fitter.params_})
    table(rows, "Tuning seeds 7-9 (30 s): default vs learned on tuning seeds 0-6")


def legs_sim(out: Path, seconds: float) -> LegTrackerParams:
    detect = AdaBoostLegDetector.default().detect
    train = [simulated("randomised", s, seconds, detect) for s in range(10)]
    fitter = LegMHTFitter().fit(train)
    print("tuning seeds 0-9 counted:", fitter.counts_.summary())
    for e in fitter.estimates_:
        print(f"  {e.key:28s} {e.value:.6g}   ({e.note})")
    header = [
        "Learned by benchmarks/fit_params.py on randomised tuning seeds 0-9 (30 s each)",
        f"counts: {fitter.counts_.summary()}",
    ]
    write(out / "legs-sim.toml", fitter.params_, fitter.estimates_, fitter.kept_, header)
    base = LegTrackerParams()
    rows: list[ValidationRow] = []
    for seed in range(100, 120):
        rec = simulated("randomised", seed, seconds, detect)
        part = validate_legs([rec], {"default": base, "learned": fitter.params_})
        for r in part:
            scores = ", ".join(f"{k} {v:.3f}" for k, v in r.scores.items())
            print(f"  {r.recording} {r.label}: {scores}", flush=True)
        rows += part
    table(rows, "Held-back randomised seeds 100-119 (30 s): default vs learned on seeds 0-9")
    return fitter.params_


def legs_dev(out: Path, sim_params: LegTrackerParams | None) -> None:
    root = Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "../shared/data"))
    bag = root / f"{DEV}.bag"
    truth = f"{root / DEV}.people.csv"
    result: FitResult = learn([bag], [truth], validation=0.4, say=print)
    write_result(result, out / "legs-dev.toml")
    for e in result.estimates:
        print(f"  {e.key:28s} {e.value:.6g}   ({e.note})")
    rows = list(result.rows)
    if sim_params is not None:
        detect = AdaBoostLegDetector.default().detect
        rec = data.load(bag, truth, detect)
        _, held = data.split([rec], 0.4)
        rows += validate_legs(held, {"learned on sim seeds 0-9": sim_params})
    table(rows, "Dev recording, last 40 %: default vs learned on its first 60 %")


def groups(out: Path, seconds: float) -> None:
    train = [simulated("entrance-hall", s, seconds, no_legs) for s in (3, 4, 5)]
    fitter = GroupModelFitter().fit(train)
    print("entrance-hall seeds 3-5 counted:", fitter.counts_.summary())
    for e in fitter.estimates_:
        print(f"  {e.key:8s} {e.value:.6g}   ({e.note})")
    write(
        out / "groups.toml",
        fitter.params_,
        fitter.estimates_,
        fitter.kept_,
        [f"Learned by benchmarks/fit_params.py on entrance-hall seeds 3-5 ({seconds:g} s)"],
    )
    assert load_config(GroupTrackerParams, out / "groups.toml") == fitter.params_
    held = [simulated("entrance-hall", s, seconds, no_legs) for s in (1, 2)]
    rows = validate_groups(held, {"default": GroupTrackerParams(), "learned": fitter.params_})
    table(rows, "Entrance hall seeds 1-2: default vs learned on seeds 3-5")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    parts = ["legs-tune", "legs-sim", "legs-dev", "groups"]
    ap.add_argument("--part", action="append", choices=parts)
    ap.add_argument("--out-dir", type=Path, default=Path("out/fit"))
    ap.add_argument("--seconds", type=float, default=30.0, help="randomised scene length [s]")
    ap.add_argument("--group-seconds", type=float, default=60.0)
    args = ap.parse_args()
    parts = args.part or ["legs-sim", "legs-dev", "groups"]  # legs-tune: on request
    args.out_dir.mkdir(parents=True, exist_ok=True)
    sim = None
    if "legs-tune" in parts:
        legs_tune(args.seconds)
    if "legs-sim" in parts:
        sim = legs_sim(args.out_dir, args.seconds)
    elif (args.out_dir / "legs-sim.toml").exists():
        sim = load_config(LegTrackerParams, args.out_dir / "legs-sim.toml")
    if "legs-dev" in parts:
        legs_dev(args.out_dir, sim)
    if "groups" in parts:
        groups(args.out_dir, args.group_seconds)


if __name__ == "__main__":
    main()
