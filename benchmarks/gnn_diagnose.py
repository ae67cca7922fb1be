"""Where the default people tracker and Stone Soup's GNN differ, scene by scene.

Both trackers get the same leg detections (the shipped detector) of the same simulated
scenes; every frame is matched as CLEAR MOT matches it (0.75 m, earlier correspondences
kept first). The errors are then split:

- misses: *before* the tracker's first match of that person (late confirmation, or never),
  in a *gap* between two matches, or *after* its last match (lost, deleted);
- false positives: a track-frame of a track *before* its first match (born early beside a
  person, or on clutter: *never* matched), or *after* a match (a track left behind);
- each person-frame also by what the person does relative to the scanner: *standing*
  (under 0.3 m/s), *approaching* (range falling by more than 0.3 m/s), or *passing*
  (everything else: walking across, or away after passing the robot), whether a leg
  detection lies within 0.5 m of it (*seen*) or a pair of legs (GNN's person detection),
  and whether its centre is outside the scanner's field of view (*out of view*; the
  moving-robot truth counts a person only while the scanner can see them, so these are
  people at the edge of the view with a leg inside it).

    PYTHONPATH=../src python gnn_diagnose.py --family moving-robot --seeds 0-19 [--config X]

The table gives per seed MOTA of each tracker and the counts by class; the summary the
sums. Use the tuning seeds (0-19) only: the held-back seeds are for scoring.
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from laserpeople.config import load_config
from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.evaluation.matching import frame_points, gated_assignment
from laserpeople.evaluation.suite import PreparedScene, prepare, track_scene
from laserpeople.tracks import Tracks
from peers import StoneSoupParams, pair_legs, peer_tracks
from people_suite import make_factory, parse_seeds, suite_scenes

GATE = 0.75
"""CLEAR MOT gate [m], the suite's."""
STANDING = 0.3
"""Slower than this [m/s] is standing; range falling faster than this is approaching."""
SEEN = 0.5
"""A leg detection this close [m] to a person sees them."""


def person_classes(prepared: PreparedScene) -> list[dict[int, tuple[str, bool, bool, bool]]]:
    """Per scan, per person id: (motion class, seen by a leg, seen by a leg pair, inside
    the scanner's field of view)."""
    out = []
    for scan, dets, truth in zip(prepared.scans, prepared.detections, prepared.truth, strict=True):
        pose = scan.pose
        sensor = np.zeros(2) if pose is None else np.array([pose.x, pose.y])
        heading = 0.0 if pose is None else pose.theta
        ends = (scan.angle_min, scan.angle_min + (len(scan.ranges) - 1) * scan.angle_increment)
        lo, hi = min(ends), max(ends)
        legs = dets.to_world().positions if pose is not None else dets.positions
        pairs = pair_legs(legs)
        row: dict[int, tuple[str, bool, bool, bool]] = {}
        for pid, xy, v in zip(truth.person_ids, truth.positions, truth.velocities, strict=True):
            rel = xy - sensor
            rng = float(np.hypot(*rel))
            speed = float(np.hypot(*v))
            closing = -float(np.dot(v, rel) / max(rng, 1e-6))
            kind = (
                "standing"
                if speed < STANDING
                else "approaching"
                if closing > STANDING
                else "passing"
            )
            seen = bool(legs.size and np.hypot(*(legs - xy).T).min() <= SEEN)
            pair = bool(pairs.size and np.hypot(*(pairs - xy).T).min() <= SEEN)
            bearing = math.remainder(math.atan2(rel[1], rel[0]) - heading, math.tau)
            row[int(pid)] = (kind, seen, pair, lo <= bearing <= hi)
        out.append(row)
    return out


def match(prepared: PreparedScene, outs: list[Tracks]) -> list[tuple[dict[int, int], list[int]]]:
    """Per scan: person id -> matched track id, and every reported person track id."""
    last: dict[int, int] = {}
    result = []
    for truth, tracks in zip(prepared.truth, outs, strict=True):
        pts = frame_points(truth, tracks, "person")
        d = pts.distances
        tids = pts.track_ids.tolist()
        oids = pts.truth_ids.tolist()
        col = {t: j for j, t in enumerate(tids)}
        pairs: dict[int, int] = {}
        used: set[int] = set()
        for i, oid in enumerate(oids):
            j = col.get(last.get(oid, -(10**9)))
            if j is not None and d[i, j] <= GATE and j not in used:
                pairs[i] = j
                used.add(j)
        fi = [i for i in range(len(oids)) if i not in pairs]
        fj = [j for j in range(len(tids)) if j not in used]
        r, c = gated_assignment(d[np.ix_(fi, fj)], GATE)
        for a, b in zip(r.tolist(), c.tolist(), strict=True):
            pairs[fi[a]] = fj[b]
        m = {oids[i]: tids[j] for i, j in pairs.items()}
        last.update(m)
        result.append((m, tids))
    return result


def split(
    matched: list[tuple[dict[int, int], list[int]]],
    classes: list[dict[int, tuple[str, bool, bool, bool]]],
) -> Counter[str]:
    """Counts of misses and false positives by class (see the module doc)."""
    first: dict[int, int] = {}
    lastm: dict[int, int] = {}
    tfirst: dict[int, int] = {}
    for k, (m, _) in enumerate(matched):
        for oid, tid in m.items():
            first.setdefault(oid, k)
            lastm[oid] = k
            tfirst.setdefault(tid, k)
    ever = set(tfirst)
    c: Counter[str] = Counter()
    for k, ((m, tids), cls) in enumerate(zip(matched, classes, strict=True)):
        for oid, (kind, seen, pair, inside) in cls.items():
            if oid in m:
                c["match"] += 1
                continue
            when = (
                "never"
                if oid not in first
                else "before"
                if k < first[oid]
                else "after"
                if k > lastm[oid]
                else "gap"
            )
            c[f"miss {when}"] += 1
            if not inside:
                c[f"miss {when}, out of view"] += 1
            c[f"miss {kind}"] += 1
            c["miss unseen" if not seen else "miss seen, no pair" if not pair else "miss pair"] += 1
        got = set(m.values())
        for tid in tids:
            if tid in got:
                continue
            if tid not in ever:
                c["fp never matched"] += 1
            elif k < tfirst[tid]:
                c["fp before match"] += 1
            else:
                c["fp after match"] += 1
    # identity switches as CLEAR MOT counts them
    last: dict[int, int] = {}
    for m, _ in matched:
        for oid, tid in m.items():
            if oid in last and last[oid] != tid:
                c["id switches"] += 1
            last[oid] = tid
    return c


COLUMNS = (
    "match",
    "miss never",
    "miss before",
    "miss gap",
    "miss after",
    "miss before, out of view",
    "miss gap, out of view",
    "miss after, out of view",
    "miss approaching",
    "miss passing",
    "miss standing",
    "miss unseen",
    "miss seen, no pair",
    "miss pair",
    "fp never matched",
    "fp before match",
    "fp after match",
    "id switches",
)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--family", action="append", default=None)
    ap.add_argument("--seeds", default="0-19")
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--config", type=Path)
    args = ap.parse_args()
    scenes = suite_scenes(parse_seeds(args.seeds), args.seconds, [], args.family)
    detector = AdaBoostLegDetector.default(load_config(LegDetectorParams, args.config))
    ours = make_factory("leg-mht", args.config)
    p = StoneSoupParams()
    totals: dict[str, Counter[str]] = {"ours": Counter(), "gnn": Counter()}
    truth_total = 0
    with tempfile.TemporaryDirectory() as tmp:
        for scene in scenes:
            prep = prepare(scene, detector)
            classes = person_classes(prep)
            n = sum(len(c) for c in classes)
            truth_total += n
            if not n:
                continue
            runs: dict[str, Any] = {
                "ours": track_scene(prep, ours, "leg-mht")[1],
                "gnn": peer_tracks(prep, "gnn", p, Path(tmp))[0],
            }
            line = [f"{scene.scenario} {scene.seed:3d} n={n:4d}"]
            for name, outs in runs.items():
                c = split(match(prep, outs), classes)
                totals[name] += c
                misses = n - c["match"]
                fps = c["fp never matched"] + c["fp before match"] + c["fp after match"]
                mota = 1 - (misses + fps + c["id switches"]) / n
                line.append(
                    f"{name} MOTA {mota:6.3f} miss {misses:4d} "
                    f"(bef {c['miss never'] + c['miss before']:4d} gap {c['miss gap']:3d} "
                    f"aft {c['miss after']:3d}) fp {fps:3d} "
                    f"(nev {c['fp never matched']:3d} bef {c['fp before match']:3d} "
                    f"aft {c['fp after match']:3d}) ids {c['id switches']:2d}"
                )
            print(" | ".join(line), flush=True)
    print(f"\nperson-frames: {truth_total}")
    print(f"{'class':22s} {'ours':>7s} {'gnn':>7s}")
    for col in COLUMNS:
        print(f"{col:22s} {totals['ours'][col]:7d} {totals['gnn'][col]:7d}")


if __name__ == "__main__":
    main()
