"""002's experiment on the simulator: three people crossing (Kräußling et al., Sec. 3).

For every variant of 002 Sec. 3 — the six permutations 123 -> abc (``crossing-3-p0`` ..
``p5``), the start swap 213 -> 123 (``crossing-3-swap``) and the consecutive crossings
123 -> 213 -> 231 (``crossing-3-twice``) — and several seeds, runs

- the Cluster Sorting Algorithm (``csa``) on the raw foreground points of both lasers, and
- the leg MHT (``leg-mht``) on the shipped AdaBoost detector's legs of the front laser,

each without appearance (the tracker's own ids) and with the colour re-identification
stage (``identity.reid``, simulated camera with the default noise), and prints how many
people keep their identity after every crossing (see benchmarks/crossing_common.py) and
the CLEAR MOT identity switches over the run::

    PYTHONPATH=src .venv/bin/python benchmarks/csa_crossings.py [--seeds 0 1 2 3 4]
        [--config FILE ([csa] and [reid] sections)] [--preset paper] [--trackers csa]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from crossing_common import laser_runs, reidentify, score
from laserpeople.config import load_config
from laserpeople.identity.reid import ReidParams
from laserpeople.tracking.csa import CSAParams

VARIANTS = (
    *(f"crossing-3-p{k}" for k in range(6)),
    "crossing-3-swap",
    "crossing-3-twice",
)
LABEL = {
    "crossing-3-p0": "123 -> 123",
    "crossing-3-p1": "123 -> 132",
    "crossing-3-p2": "123 -> 213",
    "crossing-3-p3": "123 -> 231",
    "crossing-3-p4": "123 -> 312",
    "crossing-3-p5": "123 -> 321",
    "crossing-3-swap": "213 -> 123",
    "crossing-3-twice": "123 -> 213 -> 231",
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2, 3, 4])
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS))
    ap.add_argument("--config", type=Path, default=None, help="[csa] and [reid] parameters")
    ap.add_argument("--preset", default=None, help="paper: 002's CSA (docs/papers.md)")
    ap.add_argument("--trackers", nargs="+", default=["csa", "leg-mht"])
    args = ap.parse_args()
    csa_params = load_config(CSAParams, args.config, args.preset)
    reid_params = load_config(ReidParams, args.config, args.preset)
    # totals[(tracker, appearance)] = [correct, people, all-correct crossings, crossings, idsw]
    totals: dict[tuple[str, str], list[int]] = {}
    print(
        "| variant | tracker | appearance | people correct after each crossing "
        "(per seed) | correct | ID switches |"
    )
    print("|---|---|---|---|---|---|")
    for variant in args.variants:
        cases = [laser_runs(variant, s, args.trackers, csa_params) for s in args.seeds]
        for tracker in args.trackers:
            for appearance in ("off", "on"):
                scores = [
                    score(
                        c,
                        c.tracks[tracker]
                        if appearance == "off"
                        else reidentify(c, tracker, params=reid_params),
                    )
                    for c in cases
                ]
                tot = totals.setdefault((tracker, appearance), [0, 0, 0, 0, 0])
                per_seed = []
                for sc in scores:
                    per_seed.append("/".join(str(x) for x in sc.correct))
                    tot[0] += sum(sc.correct)
                    tot[1] += sc.people * len(sc.correct)
                    tot[2] += sum(1 for x in sc.correct if x == sc.people)
                    tot[3] += len(sc.correct)
                    tot[4] += sc.id_switches
                right = sum(sum(sc.correct) for sc in scores)
                of = sum(sc.people * len(sc.correct) for sc in scores)
                print(
                    f"| {LABEL.get(variant, variant)} | {tracker} | {appearance} | "
                    f"{' '.join(per_seed)} | {right}/{of} | "
                    f"{sum(sc.id_switches for sc in scores)} |"
                )
    print()
    print(f"Totals over {len(args.seeds)} seeds x {len(args.variants)} variants")
    print("| tracker | appearance | people correct | crossings all correct | ID switches |")
    print("|---|---|---|---|---|")
    for (tracker, appearance), (c, p, a, n, s) in totals.items():
        print(
            f"| {tracker} | {appearance} | {c}/{p} ({100 * c / max(p, 1):.0f} %) | {a}/{n} | {s} |"
        )


if __name__ == "__main__":
    main()
