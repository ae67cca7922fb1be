"""The limit 002 names (Sec. 4): re-identification fails when the colours of the clothes
become too similar. Accuracy of the CSA + colour re-identification after the crossing as
the hue separation of the three people shrinks, with 6 (002 Table 1) and 36 hue bins and
three levels of lighting noise.

The three people wear hues 180, 180 + d, 180 + 2d degrees (cyan, a bin centre; the laser
does not see colour, so each simulated crossing is tracked once and re-identified under
every colour setting).
Accuracy = people with their identity after the crossing / people (chance is about 1/3 for
a random assignment, higher here because the laser alone keeps some identities).

    PYTHONPATH=src .venv/bin/python benchmarks/csa_hue_limit.py [--seeds 0] \
        [--out docs/figures/csa_hue_limit.png]
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np

from crossing_common import laser_runs, reidentify, score
from laserpeople.identity.appearance import AppearanceParams
from laserpeople.identity.reid import ReidParams
from laserpeople.sim.camera import CameraParams

SEPARATIONS = (0.0, 2.0, 4.0, 6.0, 8.0, 12.0, 20.0, 30.0, 60.0)
SETTINGS = (  # (label, bins, lighting_std)
    ("6 bins, lighting 0", 6, 0.0),
    ("6 bins, lighting 0.1", 6, 0.1),
    ("6 bins, lighting 0.3", 6, 0.3),
    ("36 bins, lighting 0.1", 36, 0.1),
)
BASE_HUE = 180.0
"""Cyan, the centre of a 6-bin (002 Table 1) and of a 36-bin histogram bin."""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seeds", type=int, nargs="+", default=[0])
    ap.add_argument("--out", default="docs/figures/csa_hue_limit.png")
    args = ap.parse_args()
    cases = [laser_runs(f"crossing-3-p{k}", s, ("csa",)) for k in range(6) for s in args.seeds]
    off = [score(c, c.tracks["csa"]) for c in cases]
    laser_only = sum(sum(s.correct) for s in off) / sum(s.people * len(s.correct) for s in off)
    acc: dict[str, list[float]] = {}
    for label, bins, light in SETTINGS:
        params = ReidParams(appearance=AppearanceParams(bins=bins))
        cam = replace(CameraParams(), lighting_std=light)
        row = []
        for d in SEPARATIONS:
            hues = {0: BASE_HUE, 1: BASE_HUE + d, 2: BASE_HUE + 2 * d}
            scores = [score(c, reidentify(c, "csa", cam, hues, params)) for c in cases]
            right = sum(sum(s.correct) for s in scores)
            total = sum(s.people * len(s.correct) for s in scores)
            row.append(right / total)
        acc[label] = row
    n = len(cases)
    print(f"Re-identification accuracy after the crossing, CSA + colour, {n} runs")
    print(f"(crossing-3-p0..p5 x seeds {args.seeds}); laser only: {laser_only:.2f}")
    print()
    print("| hue separation [deg] | " + " | ".join(label for label, _, _ in SETTINGS) + " |")
    print("|---|" + "---|" * len(SETTINGS))
    for k, d in enumerate(SEPARATIONS):
        cells = " | ".join(f"{acc[label][k]:.2f}" for label, _, _ in SETTINGS)
        print(f"| {d:g} | {cells} |")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for label, _, _ in SETTINGS:
        ax.plot(SEPARATIONS, acc[label], marker="o", label=label)
    ax.axhline(laser_only, color="grey", ls="--", label="laser only (CSA ids)")
    ax.set_xlabel("hue separation between neighbouring people [deg]")
    ax.set_ylabel("people re-identified after the crossing")
    ax.set_ylim(0.0, 1.02)
    ax.set_title(f"002's limit: similar clothes ({n} simulated crossings)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"\nwrote {out}")
    print("mean accuracy per setting:", {k: round(float(np.mean(v)), 3) for k, v in acc.items()})


if __name__ == "__main__":
    main()
