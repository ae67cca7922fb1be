"""Where the feet tracker (``track --tracker feet-pf``) loses the people of the randomised
group scenes at feet height (``random-groups``, as ``feet_random.py``) before their track
starts: every labelled person-scan whose track under 004's trajectory matching (eq. 11) is
absent, split by why, and the birth latency per person.

Per person and scan (tracks of the person kind as ``track`` writes them, in the world
frame), when the person's matched track (eq. 11) is absent:

- *after or in a gap*: the matched track has started before;
- else, *before it starts*, one of
  - *not yet shown*: no laser return within 0.15 m of either leg centre so far (as
    ``feet_ceiling.py``'s oracle);
  - *latency, nothing near*: no track has come within 0.3 m of the person so far and none
    lies within 0.75 m now;
  - *latency, a track off*: none within 0.3 m so far, one 0.3-0.75 m off now;
  - *another id now*: a track other than the matched one lies within 0.3 m now
    (``--why`` tells whether eq. 11 gives it to another person or to no one);
  - *another id before*: none within 0.3 m now, but some track was before.

Birth latency per person: from the first scan in which the laser shows them to the first
scan with any track within 0.3 m, split by still or moving laser and by whether the person
is shown from the scene's start (within 0.3 s) or arrives later.

    PYTHONPATH=src python benchmarks/feet_births.py [--seeds 0-19] [--seconds 10]
        [--config params.toml] [--keep DIR] [--jobs 2]

With ``--keep DIR`` the recordings and tracks of ``feet_random.py --keep DIR`` are reused.
**Seeds 100-119 are held back**: measure there, never tune there.
"""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

sys.path.insert(0, str(Path(__file__).resolve().parent))

from feet_ceiling import scene_shown  # type: ignore[import-not-found]
from feet_random import feet_scene_parser, tracked_feet_scenes  # type: ignore[import-not-found]
from laserpeople.evaluation.recordings import track_frames, truth_frames
from laserpeople.evaluation.report import evaluate

NEAR = 0.3
"""A track this close is on the person [m]."""
OFF = 0.75
"""A track this close is off but on the person [m] (the CLEAR MOT gate)."""
START = 0.3
"""A person first shown this soon after the scene's start was there from the start [s]."""
CLASSES = (
    "present",
    "after or in a gap",
    "not yet shown",
    "latency, nothing near",
    "latency, a track off",
    "another id now",
    "another id before",
)


def person_scans(npz: Path, csv: Path) -> tuple[Counter[str], list[tuple[bool, float]]]:
    """The person-scans of one scene by class (:data:`CLASSES`; ``another id now`` also
    split into ``... of another person`` and ``... of no one``), and per person shown
    (from the start?, latency [s] to a track within :data:`NEAR`; inf: never)."""
    result = evaluate(truth_frames(npz), track_frames(csv, "person", truth=npz)).result()
    match = {person: track for track, person in result.schenk.matched}
    owner = {track: person for track, person in result.schenk.matched}
    tracks: dict[int, dict[int, NDArray[np.float64]]] = {
        f.scan_index: {t.track_id: np.asarray(t.position) for t in f.tracks}
        for f in track_frames(csv, "person", truth=npz)
    }
    started: dict[int, int] = {}
    for k in sorted(tracks):
        for tid in tracks[k]:
            started.setdefault(tid, k)
    counts: Counter[str] = Counter()
    first_shown: dict[int, float] = {}
    first_near: dict[int, float] = {}
    for k, stamp, ids, xy, shown in scene_shown(npz):
        here = tracks.get(k, {})
        for pid, p, s in zip(ids.tolist(), xy, shown.tolist(), strict=True):
            if s:
                first_shown.setdefault(pid, stamp)
            d = {t: float(np.hypot(*(q - p))) for t, q in here.items()}
            nearest = min(d, key=lambda t: d[t], default=None)
            dmin = d[nearest] if nearest is not None else np.inf
            was_near = pid in first_near
            if dmin <= NEAR:
                first_near.setdefault(pid, stamp)
            tid = match.get(pid)
            if tid is not None and tid in here:
                kind = "present"
            elif tid is not None and started.get(tid, k + 1) <= k:
                kind = "after or in a gap"
            elif pid not in first_shown:
                kind = "not yet shown"
            elif dmin <= NEAR:
                kind = "another id now"
                whose = "of another person" if nearest in owner else "of no one"
                counts[f"another id now, {whose}"] += 1
            elif was_near:
                kind = "another id before"
            elif dmin <= OFF:
                kind = "latency, a track off"
            else:
                kind = "latency, nothing near"
            counts[kind] += 1
    latency = [(t0 < START, first_near.get(pid, np.inf) - t0) for pid, t0 in first_shown.items()]
    return counts, latency


def main() -> None:
    args = feet_scene_parser(__doc__).parse_args()
    groups: dict[str, Counter[str]] = {}
    latencies: dict[str, list[tuple[bool, float]]] = {}
    with tracked_feet_scenes(args) as scenes:
        for seed, (moving, stem) in scenes.items():
            counts, latency = person_scans(stem.with_suffix(".npz"), stem.with_suffix(".csv"))
            total = sum(counts[c] for c in CLASSES)
            shares = ", ".join(f"{c} {100 * counts[c] / total:.1f} %" for c in CLASSES[1:])
            print(f"seed {seed} ({'moving' if moving else 'still'}): {shares}", flush=True)
            for name in ("all", "moving" if moving else "still"):
                groups.setdefault(name, Counter()).update(counts)
                latencies.setdefault(name, []).extend(latency)
    print(f"\nfeet-pf on random-groups at feet height, seeds {args.seeds}: person-scans")
    names = [*CLASSES, "another id now, of another person", "another id now, of no one"]
    print("| scenes | person-scans | " + " | ".join(names) + " |")
    print("|---|---:|" + "---:|" * len(names))
    for name, counts in groups.items():
        total = sum(counts[c] for c in CLASSES)
        shares = " | ".join(f"{100 * counts[c] / total:.1f} %" for c in names)
        print(f"| {name} | {total:,} | {shares} |")
    print("\nbirth latency: first shown -> first track within 0.3 m [s]")
    print(
        "| scenes | people from the start | median | mean | never | arriving later | median "
        "| mean | never |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, rows in latencies.items():
        cells = []
        for start in (True, False):
            lat = np.array([t for s, t in rows if s == start])
            done = lat[np.isfinite(lat)]
            med = f"{np.median(done):.2f}" if done.size else "-"
            mean = f"{done.mean():.2f}" if done.size else "-"
            cells += [str(lat.size), med, mean, str(int((~np.isfinite(lat)).sum()))]
        print(f"| {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
