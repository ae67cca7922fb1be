"""Leg detection by range on held-out leg_tracker recordings, with and without range
augmentation (training scans moved out along each segment's bearing and re-cast on the
same scanner: ``laserpeople.detection.augment.shift_scan_out``).

Run: ``PYTHONPATH=src python benchmarks/detector_range.py [--rounds 2000]``

Split as ``detector_tables.py`` (the leg_tracker protocol, jump distance 0.13 m): train on
``positive_{1,2,3,4}_extracted.bag`` + the left and right lasers of ``negative_2.bag``;
test on ``positive_{6,7}`` + the rear laser. Two models, features 1-13, the same rounds:
trained on the training scans (before) and on them plus the same scans moved out by
:data:`~laserpeople.detection.augment.RANGE_SHIFTS` (after). Each is tested on the held-out
scans as recorded (legs at 0.5-5 m) and on the held-out scans moved out the same way with
another noise seed (legs at 2.5-8.5 m): false negatives and false positives per range.
"""

from __future__ import annotations

import argparse
import itertools
import time
from pathlib import Path

import numpy as np

from laserpeople.detection.augment import RANGE_SHIFTS
from laserpeople.detection.report import Confusion, predict, train_model
from laserpeople.detection.training import (
    LEG_TRACKER_SEGMENTATION,
    ClassedScan,
    LabelledSegments,
    all_negative_classes,
    classed_segments,
    leg_tracker_positive_classes,
    shifted_segments,
)

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"
LT = DATA / "leg_tracker" / "rosbags" / "training_scans_res=0.33"
GEOMETRY = tuple(range(1, 14))
BINS = (0.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.5)
SELF_HIT_DISTANCE = 0.4
"""[m] The rear laser sees two parts of its robot at 0.2-0.3 m (as detector_tables.py)."""


def classed(names: tuple[int, ...], topics: tuple[str, ...]) -> dict[str, list[ClassedScan]]:
    """Classed scans of the positive bags ``names`` and the negative lasers ``topics``."""
    out = {
        f"positive_{i}_extracted.bag": leg_tracker_positive_classes(
            LT / f"positive_{i}_extracted.bag"
        )
        for i in names
    }
    neg = all_negative_classes(LT / "negative_2.bag", topics)
    out["negative_2.bag"] = neg
    return out


def segments(parts: dict[str, list[ClassedScan]], shifts: tuple[float, ...], seed: int):
    """As recorded (no shifts) or moved out by ``shifts``."""
    seg = LEG_TRACKER_SEGMENTATION
    if not shifts:
        data = [classed_segments(p, n, seg) for n, p in parts.items()]
    else:
        data = [shifted_segments(p, n, shifts, seg, seed) for n, p in parts.items()]
    out = LabelledSegments.concat(data)
    return out.select(~((out.labels < 0) & (out.distance < SELF_HIT_DISTANCE)))


def scores(model, data: LabelledSegments) -> np.ndarray:
    """AdaBoost margins (N,) of the segments."""
    return model.classifier.decision_function(data.features[:, model.columns])


def auc(score: np.ndarray, labels: np.ndarray) -> float:
    """Area under the ROC curve: the chance that a leg outscores a non-leg (ties half)."""
    pos, neg = score[labels > 0], score[labels < 0]
    if pos.size == 0 or neg.size == 0:
        return float("nan")
    order = np.sort(neg)
    below = np.searchsorted(order, pos, side="left")
    ties = np.searchsorted(order, pos, side="right") - below
    return float((below + 0.5 * ties).sum() / (pos.size * neg.size))


def by_range(name: str, predicted: np.ndarray, data: LabelledSegments) -> None:
    """A row per range bin: legs, FN %, non-legs, FP %."""
    print(f"  {name}")
    for lo, hi in itertools.pairwise(BINS):
        m = (data.distance >= lo) & (data.distance < hi)
        if not m.any():
            continue
        c = Confusion.of(predicted[m], data.labels[m])
        print(
            f"    {lo:3.1f}-{hi:3.1f} m: legs {c.positives:5d} FN {c.fn_rate:6.2f} %  "
            f"non-legs {c.negatives:6d} FP {c.fp_rate:6.2f} %"
        )
    c = Confusion.of(predicted, data.labels)
    print(
        f"    all      : legs {c.positives:5d} FN {c.fn_rate:6.2f} %  non-legs "
        f"{c.negatives:6d} FP {c.fp_rate:6.2f} %  overall {c.overall_error:5.2f} %"
    )


def main() -> None:
    """Train both models and print the tables."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=300, help="boosting rounds T")
    ap.add_argument(
        "--weight", type=float, default=1.0, help="initial weight of a moved-out segment"
    )
    args = ap.parse_args()
    t0 = time.perf_counter()
    train = classed((1, 2, 3, 4), ("/left_scan", "/right_scan"))
    test = classed((6, 7), ("/rear_scan",))
    plain = segments(train, (), 0)
    far = segments(train, RANGE_SHIFTS, 0)
    test_plain = segments(test, (), 0)
    test_far = segments(test, RANGE_SHIFTS, 1)
    print(f"train: {plain.summary()}; moved out {RANGE_SHIFTS} m: {far.summary()}")
    print(f"test: {test_plain.summary()}; moved out: {test_far.summary()}")
    print(f"data {time.perf_counter() - t0:.0f} s")
    models = {
        "before (recorded scans)": train_model(plain, GEOMETRY, args.rounds, 0.13),
        "after (recorded + moved out)": train_model(
            LabelledSegments.concat([plain, far]),
            GEOMETRY,
            args.rounds,
            0.13,
            sample_weight=np.concatenate((np.ones(len(plain)), np.full(len(far), args.weight))),
        ),
    }
    print(f"trained {time.perf_counter() - t0:.0f} s, T = {args.rounds}")
    before, after = models.values()
    both = LabelledSegments.concat([test_plain, test_far])
    neg = scores(before, both)[both.labels < 0]
    fp = float((neg > 0.0).mean())
    # the after model's margin at which it makes as many false alarms on all held-out
    # non-legs (recorded and moved out) as the before model does at 0
    s_after = np.sort(scores(after, both)[both.labels < 0])
    matched = float(s_after[min(int(np.ceil((1.0 - fp) * s_after.size)), s_after.size - 1)])
    print(f"after's threshold at before's false-alarm rate ({100 * fp:.2f} %): {matched:+.3f}")
    for test_name, data in (
        ("held-out, as recorded", test_plain),
        ("held-out, moved out", test_far),
    ):
        print(f"\n{test_name}")
        for name, model in models.items():
            by_range(name, predict(model, data), data)
        by_range(
            f"after, margin above {matched:+.3f}",
            np.where(scores(after, data) > matched, 1, -1),
            data,
        )
        print("  area under the ROC curve, before / after:")
        sb, sa = scores(before, data), scores(after, data)
        for lo, hi in itertools.pairwise(BINS):
            m = (data.distance >= lo) & (data.distance < hi)
            if (data.labels[m] > 0).any():
                print(
                    f"    {lo:3.1f}-{hi:3.1f} m: {auc(sb[m], data.labels[m]):.3f} / "
                    f"{auc(sa[m], data.labels[m]):.3f}"
                )


if __name__ == "__main__":
    main()
