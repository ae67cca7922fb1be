"""Fit the history classifier of ``people.learned_confirm`` (tracking/confirm.py) on the
tuning seeds of the simulated families, and write it as JSON.

Each scene is simulated, its legs detected with the shipped detector and tracked by the
default ``track`` (its person layer records, on a moving robot, the feature row of every
unconfirmed candidate at every scan); a row is a person when the candidate lies within
``--near`` (0.5 m) of a true person of that scan. AdaBoost (000 Table 1) with ``--rounds``
stumps is fitted on all rows; the script prints, per margin, the share of person rows and of
clutter rows above it (by scan and by candidate: the first scan each passes), and writes the
model to ``--out`` (default: the package's model).

    PYTHONPATH=src python benchmarks/fit_confirm.py [--families moving-robot,randomised,
        furniture-only] [--seeds 0-19] [--seconds 30] [--rounds 40] [--out PATH]
        [--rows rows.npz]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

from laserpeople.config import load_config
from laserpeople.detection.adaboost import AdaBoostLegClassifier
from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams
from laserpeople.evaluation.suite import frames_for, prepare
from laserpeople.tracking.confirm import DEFAULT_MODEL, FEATURES, ConfirmModel

sys.path.insert(0, str(Path(__file__).resolve().parent))
from people_suite import make_factory, parse_seeds, suite_scenes  # noqa: E402

MODEL_PATH = (
    Path(__file__).resolve().parent.parent / "src/laserpeople/tracking/models" / DEFAULT_MODEL
)


def person_layer(tracker: Any) -> Any:
    """The :class:`~laserpeople.tracking.person_tracks.PersonTracker` inside a made tracker."""
    obj = tracker
    for _ in range(5):
        people = getattr(obj, "person_tracks", None)
        if people is not None:
            return people
        obj = getattr(obj, "tracker", None)
    raise ValueError("the tracker has no person layer of the tracks policy")


def scene_rows(prepared: Any, make: Any, near: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Feature rows (N, F), labels (N,) and candidate keys (N,) of one prepared scene."""
    tracker = make()
    people = person_layer(tracker)
    people.record_candidates = True
    rows: list[list[float]] = []
    labels: list[int] = []
    keys: list[int] = []
    inputs = frames_for(prepared, frozenset(tracker.consumes))
    for frame, truth in zip(inputs, prepared.truth, strict=True):
        tracker.update(frame)
        for pid, (x, y, row) in people.candidate_rows.items():
            d = np.hypot(truth.positions[:, 0] - x, truth.positions[:, 1] - y) if len(truth) else []
            labels.append(int(len(d) > 0 and float(np.min(d)) <= near))
            rows.append(row)
            keys.append(pid)
    return (
        np.array(rows, dtype=np.float64).reshape(-1, len(FEATURES)),
        np.array(labels, dtype=np.int64),
        np.array(keys, dtype=np.int64),
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--families", default="moving-robot,randomised,furniture-only")
    ap.add_argument("--seeds", default="0-19")
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--rounds", type=int, default=40)
    ap.add_argument("--near", type=float, default=0.5)
    ap.add_argument("--config", type=Path)
    ap.add_argument("--out", type=Path, default=MODEL_PATH)
    ap.add_argument("--rows", type=Path, help="also write (or, if it exists, read) the rows")
    ap.add_argument("--drop", default="", help="features left out (comma-separated names)")
    args = ap.parse_args()
    families = args.families.split(",")
    seeds = parse_seeds(args.seeds)
    if args.rows is not None and args.rows.exists():
        data = np.load(args.rows, allow_pickle=False)
        X, y, group = data["X"], data["y"], data["group"]
    else:
        detector = AdaBoostLegDetector.default(load_config(LegDetectorParams, args.config))
        make = make_factory("leg-mht", args.config)
        parts = []
        for k, scene in enumerate(suite_scenes(seeds, args.seconds, [], families)):
            X_s, y_s, keys = scene_rows(prepare(scene, detector), make, args.near)
            parts.append((X_s, y_s, keys + 1_000_000 * k))
            print(
                f"  {scene.family:15s} seed {scene.seed:3d}: {len(y_s)} rows, "
                f"{int(y_s.sum())} of a person",
                file=sys.stderr,
                flush=True,
            )
        X = np.concatenate([p[0] for p in parts])
        y = np.concatenate([p[1] for p in parts])
        group = np.concatenate([p[2] for p in parts])
        if args.rows is not None:
            np.savez(args.rows, X=X, y=y, group=group)
    dropped = [FEATURES.index(name) for name in args.drop.split(",") if name]
    X = X.copy()
    X[:, dropped] = 0.0  # a constant column is never split on
    clf = AdaBoostLegClassifier(args.rounds).fit(X, np.where(y > 0, 1, -1))
    margin = clf.decision_function(X)
    print(f"rows {len(y)}, of a person {int(y.sum())}; candidates {len(np.unique(group))}")
    print("margin  person rows above  clutter rows above  clutter candidates ever above")
    clutter_groups = np.unique(group[y == 0])
    for m in (0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0):
        above = margin > m
        ever = np.unique(group[above & (y == 0)])
        print(
            f"{m:6.1f}  {above[y > 0].mean():17.3f}  {above[y == 0].mean():18.3f}  "
            f"{len(ever)} of {len(clutter_groups)}"
        )
    imp = clf.feature_importances(len(FEATURES))
    for i in np.argsort(-imp):
        if imp[i] > 0:
            print(f"  {FEATURES[i]:18s} {imp[i]:.3f}")
    model = ConfirmModel(
        clf,
        {
            "families": families,
            "seeds": args.seeds,
            "seconds": args.seconds,
            "rounds": args.rounds,
            "dropped": args.drop.split(",") if args.drop else [],
            "near": args.near,
            "rows": int(len(y)),
            "person_rows": int(y.sum()),
        },
    )
    model.save(args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
