"""Reading and writing AdaBoost leg-detector models as JSON.

Layout (format ``laserpeople-leg-model``, version 1)::

    {
      "format": "laserpeople-leg-model",
      "version": 1,
      "features": [1, 2, ..., 13],          # paper feature numbers, the model's columns
      "stumps": [{"feature": 9, "threshold": 0.08, "polarity": 1, "alpha": 0.9, "r": 0.7}],
      "segmentation": {"method": "jump_distance", "threshold": 0.1},
      "training": {...}                      # free-form provenance: data, rounds, date, counts
    }

``stumps[].feature`` is the paper's feature number (1..14) and must be in ``features``.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NoReturn

from laserpeople.detection.adaboost import AdaBoostLegClassifier, Stump
from laserpeople.detection.features import N_FEATURES
from laserpeople.errors import ModelFileError

MODEL_FORMAT = "laserpeople-leg-model"
MODEL_VERSION = 1
MODEL_LIMIT = 64 * 2**20
"""Largest model file [characters] that is read (the default model is ~20 KB)."""
VALUE_LIMIT = 1e12
"""Largest magnitude of a stump's threshold or weight (real ones are below 1e3)."""


@dataclass(frozen=True, eq=False)
class LegModel:
    """A trained classifier with the feature subset it reads and its provenance.

    Attributes:
        classifier: The fitted boosted stumps; its columns are ``features`` in order.
        features: Paper feature numbers (1-based) the classifier uses, e.g. 1..13.
        segmentation_threshold: Jump distance [m] the model was trained with.
        training: Free-form provenance (data sets, counts, rounds, date).
    """

    classifier: AdaBoostLegClassifier
    features: tuple[int, ...]
    segmentation_threshold: float
    training: dict[str, Any] = field(default_factory=dict)

    @property
    def columns(self) -> list[int]:
        """0-based columns of the full (M, 14) feature matrix this model reads."""
        return [f - 1 for f in self.features]

    def to_json(self) -> dict[str, Any]:
        """The JSON document of this model."""
        return {
            "format": MODEL_FORMAT,
            "version": MODEL_VERSION,
            "features": list(self.features),
            "stumps": [
                {
                    "feature": self.features[s.feature],
                    "threshold": s.threshold,
                    "polarity": s.polarity,
                    "alpha": s.alpha,
                    "r": s.r,
                }
                for s in self.classifier.stumps
            ],
            "segmentation": {"method": "jump_distance", "threshold": self.segmentation_threshold},
            "training": self.training,
        }

    def save(self, path: str | Path) -> None:
        """Write the model as JSON (its folder created; written whole or not at all).

        Raises:
            ModelFileError: The file cannot be written.
        """
        from laserpeople.io.paths import write_text_file

        text = json.dumps(self.to_json(), indent=1) + "\n"
        write_text_file(path, text, "model", ModelFileError)


def parse_feature_set(text: str) -> tuple[int, ...]:
    """``"1-13"`` / ``"1-14"`` / ``"1,2,9"`` -> feature numbers; raises ValueError."""
    numbers: list[int] = []
    for part in text.split(","):
        part = part.strip()
        if "-" in part:
            a, b = (int(x) for x in part.split("-", 1))
            numbers.extend(range(a, b + 1))
        elif part:
            numbers.append(int(part))
    if not numbers or any(not 1 <= f <= N_FEATURES for f in numbers):
        raise ValueError(f"feature numbers must be in 1..{N_FEATURES}, got {text!r}")
    if len(set(numbers)) != len(numbers):
        raise ValueError(f"feature {text!r} lists a feature twice")
    return tuple(numbers)


def load_model(path: str | Path) -> LegModel:
    """Read a model file; anything malformed, foreign or newer raises :class:`ModelFileError`."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError as exc:
        raise ModelFileError("model file not found", path=p, hint="check the path") from exc
    except (OSError, UnicodeDecodeError) as exc:
        raise ModelFileError(f"cannot read model file: {exc}", path=p) from exc
    if len(text) > MODEL_LIMIT:
        raise ModelFileError(
            f"model file is larger than {MODEL_LIMIT} characters",
            path=p,
            hint="give a model written by `laserpeople train`",
        )
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ModelFileError(
            f"not JSON ({exc.msg} at line {exc.lineno})",
            path=p,
            hint="give a model written by `laserpeople train`",
        ) from exc
    except (ValueError, RecursionError) as exc:  # e.g. a 5,000-digit number, deep nesting
        raise ModelFileError(
            f"not a readable model JSON ({type(exc).__name__}: {str(exc)[:80]})",
            path=p,
            hint="give a model written by `laserpeople train`",
        ) from exc
    return model_from_json(doc, p)


def model_from_json(doc: Any, path: str | Path | None = None) -> LegModel:
    """Build a model from its parsed JSON document (see the module docstring)."""

    def bad(message: str, hint: str = "give a model written by `laserpeople train`") -> NoReturn:
        raise ModelFileError(message, path=path, hint=hint)

    if not isinstance(doc, dict) or doc.get("format") != MODEL_FORMAT:
        found = doc.get("format") if isinstance(doc, dict) else type(doc).__name__
        bad(f"not a laserpeople leg model (format {found!r}, expected {MODEL_FORMAT!r})")
    version = doc.get("version")
    if not isinstance(version, int) or isinstance(version, bool):
        bad(f"model version must be an integer, got {version!r}")
    if version > MODEL_VERSION:
        bad(
            f"model file version {version} is newer than this laserpeople reads ({MODEL_VERSION})",
            hint="upgrade laserpeople or retrain the model with this version",
        )
    if version < 1:
        bad(f"unknown model file version {version}")
    feats = doc.get("features")
    if (
        not isinstance(feats, list)
        or not feats
        or not all(
            isinstance(f, int) and not isinstance(f, bool) and 1 <= f <= N_FEATURES for f in feats
        )
        or len(set(feats)) != len(feats)
    ):
        bad(f"'features' must be distinct feature numbers 1..{N_FEATURES}, got {feats!r}")
    seg = doc.get("segmentation", {})
    threshold = seg.get("threshold") if isinstance(seg, dict) else None
    if (
        not isinstance(threshold, int | float)
        or isinstance(threshold, bool)
        or not 0.0 < threshold < VALUE_LIMIT
    ):
        bad(f"'segmentation.threshold' must be a positive number, got {threshold!r}")
    raw = doc.get("stumps")
    if not isinstance(raw, list) or not raw:
        bad("'stumps' must be a non-empty list")
    stumps: list[Stump] = []
    for i, s in enumerate(raw):
        try:
            feature = s["feature"]
            if isinstance(s["polarity"], float | str):
                raise TypeError(f"polarity {s['polarity']!r} is not 1 or -1")
            values = [float(s[k]) for k in ("threshold", "alpha")]
            polarity = int(s["polarity"])
            r = float(s.get("r", math.nan))
        except (TypeError, KeyError, ValueError, OverflowError) as exc:
            bad(
                f"stump {i} is malformed ({str(exc)[:80]}); "
                "it needs feature, threshold, polarity, alpha"
            )
        if isinstance(feature, bool) or feature not in feats:
            bad(f"stump {i} uses feature {feature!r:.40}, which is not in 'features' {feats}")
        if polarity not in (1, -1) or not all(abs(v) <= VALUE_LIMIT for v in values):
            bad(
                f"stump {i} has polarity {polarity} or a threshold/alpha that is not finite "
                f"or beyond {VALUE_LIMIT:g}"
            )
        stumps.append(Stump(feats.index(feature), values[0], polarity, values[1], r))
    training = doc.get("training", {})
    clf = AdaBoostLegClassifier.from_stumps(stumps, len(feats))
    return LegModel(
        clf, tuple(feats), float(threshold), training if isinstance(training, dict) else {}
    )
