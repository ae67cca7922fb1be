"""Evaluation of leg classifiers in the layout of 000 Tables 2-8.

* :class:`Confusion` — the confusion matrix of Tables 2-5 (rows: true label person / no
  person; columns: detected person / no person, with row percentages).
* :func:`error_table` — false negatives, false positives and overall error in percent, one
  column per classifier (Tables 7 and 8).
* :func:`best_features` — the features of the strongest weak classifiers (Table 6).
* :func:`errors_by_distance` — the same errors per band of distance from the sensor (not in
  000; it shows where a detector fails, since a leg far away has few points).
* :func:`evaluate` — train AdaBoost on one set, test it and the heuristic on another.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.detection.adaboost import AdaBoostLegClassifier
from laserpeople.detection.features import SegmentFeatures
from laserpeople.detection.heuristic import HeuristicLegClassifier, HeuristicParams
from laserpeople.detection.model_file import LegModel
from laserpeople.detection.training import LabelledSegments

DEFAULT_HEURISTIC_PARAMS = HeuristicParams()


@dataclass(frozen=True)
class Confusion:
    """Counts of a binary leg classifier on labelled segments."""

    tp: int
    fn: int
    fp: int
    tn: int

    @classmethod
    def of(cls, predicted: NDArray[np.integer], truth: NDArray[np.integer]) -> Confusion:
        """From predictions and true labels (both +1 leg / -1 not)."""
        p = np.asarray(predicted) > 0
        t = np.asarray(truth) > 0
        return cls(
            int((p & t).sum()), int((~p & t).sum()), int((p & ~t).sum()), int((~p & ~t).sum())
        )

    @property
    def positives(self) -> int:
        """True legs."""
        return self.tp + self.fn

    @property
    def negatives(self) -> int:
        """True non-legs."""
        return self.fp + self.tn

    @property
    def fn_rate(self) -> float:
        """False negatives / legs [%]."""
        return 100.0 * self.fn / self.positives if self.positives else float("nan")

    @property
    def fp_rate(self) -> float:
        """False positives / non-legs [%]."""
        return 100.0 * self.fp / self.negatives if self.negatives else float("nan")

    @property
    def detection_rate(self) -> float:
        """Detected legs / legs [%]."""
        return 100.0 - self.fn_rate

    @property
    def overall_error(self) -> float:
        """Misclassified / all segments [%]."""
        n = self.positives + self.negatives
        return 100.0 * (self.fn + self.fp) / n if n else float("nan")

    def table(self, title: str) -> str:
        """The confusion matrix as text, laid out like 000 Tables 2-5."""

        def pct(a: int, n: int) -> str:
            return f"{a} ({100.0 * a / n:.2f}%)" if n else f"{a} (-)"

        rows = [
            ("True label", "Detected: Person", "Detected: No Person", "Total"),
            (
                "Person",
                pct(self.tp, self.positives),
                pct(self.fn, self.positives),
                str(self.positives),
            ),
            (
                "No Person",
                pct(self.fp, self.negatives),
                pct(self.tn, self.negatives),
                str(self.negatives),
            ),
        ]
        return _format(title, rows)


def error_table(columns: Mapping[str, Confusion], title: str) -> str:
    """False negatives / false positives / overall error [%] per classifier (Tables 7, 8);
    "-" for a rate of no segments (no legs, or no non-legs, in the set)."""

    def pct(value: float) -> str:
        return f"{value:.2f}" if np.isfinite(value) else "-"

    names = list(columns)
    rows = [("", *names)]
    for label, attr in (
        ("False Negatives (%)", "fn_rate"),
        ("False Positives (%)", "fp_rate"),
        ("Overall Error (%)", "overall_error"),
    ):
        rows.append((label, *(pct(getattr(columns[n], attr)) for n in names)))
    return _format(title, rows)


DISTANCE_BANDS: tuple[float, ...] = (0.0, 1.0, 2.0, 3.0, 5.0, 8.0)
"""Band edges [m] of :func:`errors_by_distance`; the last band is open."""


def errors_by_distance(
    columns: Mapping[str, NDArray[np.integer]],
    data: LabelledSegments,
    edges: Sequence[float] = DISTANCE_BANDS,
    title: str = "",
) -> str:
    """Legs, non-legs and each classifier's FN / FP [%] per band of sensor distance.

    Args:
        columns: Decisions (N,) of each classifier on ``data`` (+1 leg / -1 not).
        data: The labelled segments the decisions are for.
        edges: Increasing band edges [m]; the last band has no upper limit.
        title: First line of the table.
    """
    names = list(columns)
    rows = [("distance [m]", "legs", "non-legs", *(f"{n} FN / FP (%)" for n in names))]
    bounds = [*edges, float("inf")]
    for lo, hi in itertools.pairwise(bounds):
        band = (data.distance >= lo) & (data.distance < hi)
        if not band.any():
            continue
        truth = data.labels[band]
        cells = []
        for n in names:
            c = Confusion.of(np.asarray(columns[n])[band], truth)
            fn = f"{c.fn_rate:.1f}" if c.positives else "-"
            fp = f"{c.fp_rate:.1f}" if c.negatives else "-"
            cells.append(f"{fn} / {fp}")
        label = f"{lo:g}-{hi:g}" if np.isfinite(hi) else f">= {lo:g}"
        rows.append((label, str(int((truth > 0).sum())), str(int((truth < 0).sum())), *cells))
    return _format(title, rows)


def best_features(model: LegModel, k: int = 5) -> list[int]:
    """Paper feature numbers of the ``k`` weak classifiers with the largest alpha (Table 6)."""
    stumps = sorted(model.classifier.stumps, key=lambda s: -s.alpha)
    return [model.features[s.feature] for s in stumps[:k]]


def heuristic_predictions(
    data: LabelledSegments, params: HeuristicParams = DEFAULT_HEURISTIC_PARAMS
) -> NDArray[np.int64]:
    """The heuristic baseline's decisions (N,) on labelled segments."""
    n = len(data)
    feats = SegmentFeatures(data.features, data.max_beam_motion, np.zeros((n, 2)), np.zeros((n, 2)))
    return HeuristicLegClassifier(params).predict(feats)


def train_model(
    data: LabelledSegments,
    features: Sequence[int],
    rounds: int,
    segmentation_threshold: float,
    provenance: Mapping[str, object] | None = None,
) -> LegModel:
    """Fit AdaBoost on ``data`` using the paper features ``features`` (1-based)."""
    cols = [f - 1 for f in features]
    clf = AdaBoostLegClassifier(rounds).fit(data.features[:, cols], data.labels)
    training = dict(provenance or {})
    training.update(
        {
            "rounds": rounds,
            "segments": len(data),
            "legs": data.n_positive,
            "non_legs": data.n_negative,
            "recordings": list(data.groups),
        }
    )
    return LegModel(clf, tuple(features), segmentation_threshold, training)


def predict(model: LegModel, data: LabelledSegments) -> NDArray[np.int64]:
    """The model's decisions (N,) on labelled segments."""
    return model.classifier.predict(data.features[:, model.columns])


@dataclass(frozen=True)
class Evaluation:
    """AdaBoost and heuristic on one test set."""

    model: LegModel
    adaboost: Confusion
    heuristic: Confusion


def evaluate(
    train: LabelledSegments,
    test: LabelledSegments,
    features: Sequence[int],
    rounds: int = 10,
    segmentation_threshold: float = 0.1,
) -> Evaluation:
    """Train on ``train``, test AdaBoost and the heuristic on ``test``."""
    model = train_model(train, features, rounds, segmentation_threshold)
    return Evaluation(
        model,
        Confusion.of(predict(model, test), test.labels),
        Confusion.of(heuristic_predictions(test), test.labels),
    )


def _format(title: str, rows: Sequence[Sequence[str]]) -> str:
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    lines = [title]
    for j, row in enumerate(rows):
        lines.append(
            "  ".join(
                c.ljust(w) if i == 0 else c.rjust(w)
                for i, (c, w) in enumerate(zip(row, widths, strict=True))
            )
        )
        if j == 0:
            lines.append("  ".join("-" * w for w in widths))
    return "\n".join(lines)
