"""Person MOTA and IDF1 of the CSA with colour over whole crossing runs (002's scenes).

For each of the six crossing-3 permutations (``crossing-3-p0`` .. ``p5``) at one seed, the
CSA (``csa``) with the colour re-identification stage (``--appearance on``) is scored
against the truth by CLEAR MOT and IDF1 (0.75 m) on its person tracks, two ways:

- ``cli``: as ``laserpeople simulate crossing-3-pK --seed S -o x.npz`` and
  ``laserpeople track x.npz --tracker csa --appearance on`` run it (front laser, the
  pipeline's static world model for the foreground; the people stand still while it learns,
  so they are background for the first 1.5-2.7 s);
- ``sim``: both lasers with the simulator's per-beam labels as foreground
  (``benchmarks/crossing_common.py``, as ``benchmarks/csa_crossings.py``).

    PYTHONPATH=src .venv/bin/python benchmarks/csa_identity.py [--seed 7] [--way cli sim]
        [--preset paper] [--config FILE] [--appearance on|off]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from crossing_common import laser_runs, reidentify
from laserpeople.config import load_config
from laserpeople.evaluation import evaluate
from laserpeople.identity.reid import ReidParams
from laserpeople.io import open_recording
from laserpeople.pipeline import build
from laserpeople.sim.scenarios import run_scenario
from laserpeople.tracking.csa import CSAParams
from laserpeople.tracks import Tracks


def _persons(tracks: list[Tracks]) -> list[Tracks]:
    return [replace(t, tracks=t.of_kind("person")) for t in tracks]


def score_cli(
    variant: str, seed: int, csa: CSAParams, reid: ReidParams, colour: bool, tmp: Path
) -> dict[str, float]:
    """MOTA and IDF1 of the pipeline run (as ``laserpeople track``)."""
    path = run_scenario(variant, seed=seed).write(tmp / f"{variant}-{seed}.npz")
    pipe = build(path, tracker="csa", params=csa, reidentify=colour, reid=reid)
    tracks = _persons([step.tracks for step in pipe if step.tracks is not None])
    summary = evaluate(list(open_recording(path).truth()), tracks).result().summary()
    return {k: float(summary[k] or 0.0) for k in ("mota", "idf1", "recall", "precision")}


def score_sim(
    variant: str, seed: int, csa: CSAParams, reid: ReidParams, colour: bool
) -> dict[str, float]:
    """MOTA and IDF1 on both lasers with the simulator's foreground."""
    case = laser_runs(variant, seed, ("csa",), csa)
    tracks = reidentify(case, "csa", params=reid) if colour else case.tracks["csa"]
    summary = evaluate(case.result.truth, _persons(tracks)).result().summary()
    return {k: float(summary[k] or 0.0) for k in ("mota", "idf1", "recall", "precision")}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--way", nargs="+", default=["cli", "sim"], choices=["cli", "sim"])
    ap.add_argument("--appearance", default="on", choices=["on", "off"])
    ap.add_argument("--config", type=Path, default=None, help="[csa] and [reid] parameters")
    ap.add_argument("--preset", default=None, help="paper: 002's CSA and colour stage")
    args = ap.parse_args()
    csa = load_config(CSAParams, args.config, args.preset)
    reid = load_config(ReidParams, args.config, args.preset)
    colour = args.appearance == "on"
    print("| way | permutation | MOTA | IDF1 | recall | precision |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory(prefix="csa-identity-") as tmp:
        for way in args.way:
            idf1 = []
            for k in range(6):
                variant = f"crossing-3-p{k}"
                s = (
                    score_cli(variant, args.seed, csa, reid, colour, Path(tmp))
                    if way == "cli"
                    else score_sim(variant, args.seed, csa, reid, colour)
                )
                idf1.append(s["idf1"])
                print(
                    f"| {way} | p{k} | {s['mota']:.3f} | {s['idf1']:.3f} | {s['recall']:.3f} | "
                    f"{s['precision']:.3f} |",
                    flush=True,
                )
            print(f"| {way} | worst / mean IDF1 | | {min(idf1):.3f} / {sum(idf1) / 6:.3f} | | |")


if __name__ == "__main__":
    main()
