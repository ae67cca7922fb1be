"""Why the shipped leg detector misses people: label by label on the real lobby recording,
and by cause over simulated scenes with per-beam truth.

``lobby``: every label of ``general_tracking_moving_1_first`` (the recording of
``moving_people.py``) with no leg detection within :data:`moving_people.NEAR` gets a row:
the segment with the point nearest to the label, its points, first-to-last width, mean
range and AdaBoost margin, what the beam just outside it on each side returns (``-``: no
return; else how far behind the segment's end point, negative in front), how many of its
neighbouring beams repeat the same reading, and the feature that, set to the median of the
detected labels' legs, raises its margin most (:func:`lifting_feature`). Then the count by
cause (:func:`label_cause`)::

    PYTHONPATH=src .venv/bin/python benchmarks/leg_misses.py lobby

``sim``: on simulated scenes (``--family``, ``--seeds``; tuning seeds only), every leg a beam
hits (counted once per scan) is found (a leg segment holds one of its beams) or missed, by
cause (:func:`sim_cause`)::

    PYTHONPATH=src .venv/bin/python benchmarks/leg_misses.py sim --family moving-robot --seeds 0-49
"""

from __future__ import annotations

import argparse
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from laserpeople.detection.detector import AdaBoostLegDetector, ScanClassification
from laserpeople.detection.features import FEATURE_NAMES, MIN_POINTS
from laserpeople.scan import Scan
from moving_people import NEAR, default_paths, raw_scans, read_labels

WIDE = 0.15  # m, first to last point: wider than one leg (median labelled leg 0.137 m)


@dataclass(frozen=True)
class Beside:
    """What the beams just outside a segment return.

    Attributes:
        behind: Per side (before, after): how far behind the segment's end point the beam
            returns [m] (negative: in front), NaN for no return or no beam.
        repeats: Neighbouring beams of the segment with exactly the same range.
    """

    behind: tuple[float, float]
    repeats: int


def beside(scan: Scan, beams: np.ndarray) -> Beside:
    """:class:`Beside` of the segment of ``scan`` on ``beams`` (in scan order)."""
    ranges = np.asarray(scan.ranges, dtype=np.float64)
    out = []
    for nb, end in ((int(beams[0]) - 1, int(beams[0])), (int(beams[-1]) + 1, int(beams[-1]))):
        ok = 0 <= nb < scan.n_beams and bool(scan.valid[nb])
        out.append(float(ranges[nb] - ranges[end]) if ok else float("nan"))
    with np.errstate(invalid="ignore"):  # (inf - inf)
        repeats = int(np.count_nonzero(np.diff(ranges[beams]) == 0.0))
    return Beside((out[0], out[1]), repeats)


def lifting_feature(
    detector: AdaBoostLegDetector, values: np.ndarray, typical: np.ndarray
) -> tuple[str, float]:
    """The feature (name) of the segment with features ``values`` (14,) that, set to
    ``typical`` (14,), raises the margin most, and by how much."""
    cols = np.array(detector.model.columns, dtype=np.int64)
    base = float(detector.model.classifier.decision_function(values[None, cols])[0])
    trial = np.repeat(values[None, :], len(values), axis=0)
    np.fill_diagonal(trial, typical)
    gain = detector.model.classifier.decision_function(trial[:, cols]) - base
    k = int(np.argmax(gain))
    return FEATURE_NAMES[k], float(gain[k])


def label_cause(size: int, side: Beside, feature: str) -> str:
    """The cause of a missed label from its nearest segment: fewer than three points, a
    beam beside it returning in front of it (partly hidden), or the margin under the
    threshold, named by the feature that lifts it most (``width``: narrower than a leg;
    ``boundary_length`` / ``std_dev``: wider; ``mean_angular_diff`` /
    ``boundary_regularity``: an arc about the laser, repeated readings)."""
    if size < MIN_POINTS:
        return "fewer than 3 points"
    if any(b < 0.0 for b in side.behind):
        return "a beam beside it returns in front of it"
    return f"margin under the threshold, lifted most by {feature}"


def lobby() -> Counter[str]:
    """The ``lobby`` table (printed) and its count by cause."""
    bag, lab = default_paths()
    labels = read_labels(lab)
    detector = AdaBoostLegDetector.default()
    got: dict[int, tuple[Scan, ScanClassification]] = {}
    for scan in raw_scans(bag):
        got[scan.index] = (scan, detector.classify(scan))
    found, missed = [], []
    for index, people in sorted(labels.items()):
        scan, c = got[index]
        legs = detector._positions(c.features.centres[c.is_leg])
        for pid, pos in people.items():
            near = len(legs) > 0 and float(np.hypot(*(legs - pos).T).min()) <= NEAR
            (found if near else missed).append((index, pid, pos))
    typical = np.median(
        [_nearest(got[i][1], pos)[1] for i, _, pos in found if _nearest(got[i][1], pos)[0] >= 0],
        axis=0,
    )
    print("scan person range_m points width_m margin  beside_m      repeats  lifted most by")
    causes: Counter[str] = Counter()
    for index, pid, pos in missed:
        scan, c = got[index]
        i, values = _nearest(c, pos)
        if i < 0:
            causes["no segment within 0.5 m"] += 1
            continue
        t = c.table
        beams, pts = (
            t.beams[t.offsets[i] : t.offsets[i + 1]],
            t.points[t.offsets[i] : t.offsets[i + 1]],
        )
        side = beside(scan, beams)
        name, gain = lifting_feature(detector, values, typical)
        sides = " ".join("-" if np.isnan(b) else f"{b:+.2f}" for b in side.behind)
        print(
            f"{index:4d} {pid:6d} {float(np.hypot(*pos)):7.1f} {beams.size:6d} "
            f"{float(np.hypot(*(pts[-1] - pts[0]))):7.2f} {c.scores[i]:+6.2f}  {sides:12s} "
            f"{side.repeats:8d}  {name} (+{gain:.2f})"
        )
        causes[label_cause(beams.size, side, name)] += 1
    print(
        f"labels {sum(len(p) for p in labels.values())}, with a leg detection within "
        f"{NEAR} m {len(found)}, without {len(missed)}; typical (median) width of the "
        f"detected labels' legs {typical[FEATURE_NAMES.index('width')]:.3f} m"
    )
    return causes


def _nearest(c: ScanClassification, pos: np.ndarray) -> tuple[int, np.ndarray]:
    """The scored segment of ``c`` with the point nearest to ``pos`` (within
    :data:`moving_people.NEAR`; -1 if none) and its features."""
    t = c.table
    if len(t) == 0:
        return -1, np.empty(0)
    d = np.hypot(*(t.points - pos).T)
    best = np.full(len(t), np.inf)
    np.minimum.at(best, t.segment_ids, d)
    best[~np.isfinite(c.scores)] = np.inf
    i = int(np.argmin(best))
    return (i, c.features.values[i]) if best[i] <= NEAR else (-1, np.empty(0))


def sim_cause(scan: Scan, c: ScanClassification, person: int, leg: int, jump: float) -> str:
    """Why the leg ``(person, leg)`` a beam of ``scan`` hits is found or missed in the
    classified scan ``c`` (the largest segment holding its beams decides; ``jump``: the
    segmentation's jump distance [m], a beam beside a segment standing alone returns at
    least that far behind it or not at all)."""
    labels = scan.labels
    assert labels is not None
    t = c.table
    seg = np.full(scan.n_beams, -1)
    seg[t.beams] = t.segment_ids
    mine = np.flatnonzero((labels.person == person) & (labels.leg == leg))
    held = seg[mine][seg[mine] >= 0]
    if held.size == 0:
        return "missed: no valid return"
    if c.is_leg[np.unique(held)].any():
        return "found"
    i = int(np.bincount(held).argmax())
    beams = t.beams[t.offsets[i] : t.offsets[i + 1]]
    others = labels.person[beams] != person
    if others.any() or (labels.leg[beams] < 0).any():
        return "missed: in one segment with another person or object"
    if (labels.leg[beams] != leg).any():
        return "missed: both legs in one segment"
    if np.unique(held).size > 1:
        return "missed: split into segments"
    if beams.size < MIN_POINTS:
        return "missed: fewer than 3 points"
    side = beside(scan, beams)
    alone = all(np.isnan(b) or b >= jump for b in side.behind)
    if not alone:
        return "missed: margin under the threshold, a beam beside it in front"
    pts = t.points[t.offsets[i] : t.offsets[i + 1]]
    wide = float(np.hypot(*(pts[-1] - pts[0]))) > WIDE
    size = "wider" if wide else "no wider"
    return f"missed: margin under the threshold, standing alone, {size} than {WIDE} m"


def sim(family: str, seeds: Sequence[int], seconds: float) -> Counter[str]:
    """The ``sim`` count over ``family``'s scenes ``seeds`` (first sensor of each)."""
    from laserpeople.sim.scenarios import run_scenario

    detector = AdaBoostLegDetector.default()
    jump = detector.segmenter.params.threshold
    total: Counter[str] = Counter()
    for seed in seeds:
        result = run_scenario(family, seconds=seconds, seed=seed)
        first = result.scans[0].sensor
        for scan in (s for s in result.scans if s.sensor == first):
            assert scan.labels is not None
            c = detector.classify(scan)
            hit = scan.labels.is_leg
            keys = set(
                zip(scan.labels.person[hit].tolist(), scan.labels.leg[hit].tolist(), strict=True)
            )
            total["legs hit"] += len(keys)
            total.update(sim_cause(scan, c, p, g, jump) for p, g in keys)
    return total


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="what", required=True)
    sub.add_parser("lobby", help="the lobby's labels without a leg detection")
    s = sub.add_parser("sim", help="legs missed in simulated scenes, by cause")
    s.add_argument("--family", default="moving-robot")
    s.add_argument("--seeds", default="0-49", help="A-B (tuning seeds only)")
    s.add_argument("--seconds", type=float, default=30.0)
    args = ap.parse_args()
    if args.what == "lobby":
        counts = lobby()
    else:
        a, _, b = args.seeds.partition("-")
        counts = sim(args.family, range(int(a), int(b or a) + 1), args.seconds)
    for cause, n in sorted(counts.items(), key=lambda kv: -kv[1]):
        print(f"  {cause:70s} {n:6d}")


if __name__ == "__main__":
    main()
