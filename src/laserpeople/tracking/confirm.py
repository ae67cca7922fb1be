"""A learned confirmation of person candidates on a moving robot (``people.learned_confirm``).

The existence score of :mod:`laserpeople.tracking.person_tracks` sums per-scan evidence as
if the scans were independent; clutter's detections are not. Here a candidate is judged
from its history as a whole: :data:`FEATURES` (one row per unconfirmed candidate and scan,
:func:`candidate_features`) go through boosted decision stumps (000 Table 1's AdaBoost,
:class:`~laserpeople.detection.adaboost.AdaBoostLegClassifier`) trained on the tuning seeds
of the simulated families (``benchmarks/fit_confirm.py`` writes the model, a JSON file of
stumps, :data:`DEFAULT_MODEL`).
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.detection.adaboost import AdaBoostLegClassifier, Stump
from laserpeople.errors import ModelFileError
from laserpeople.scan import Segment

FloatArray = NDArray[np.float64]

FEATURES: tuple[str, ...] = (
    "age",  # s since the candidate's birth
    "detected_share",  # scans with a member leg detected / scans since birth
    "two_share",  # scans counted as both legs (pair, wide segment or moving leg) / scans
    "score_mean",  # mean detector score of its detected member legs
    "score_max",  # largest such score
    "score_last",  # the last such score
    "leg_net",  # m, largest net displacement of a member leg from its first detection
    "leg_straightness",  # that leg's net displacement / its path length (0 when still)
    "speed",  # m/s, the candidate's filtered speed
    "range",  # m, from the sensor
    "beams_per_leg",  # a 0.1 m leg's width over the beam spacing at that range
    "legs_now",  # member legs detected in this scan (a wide segment counts 2)
    "static_time",  # s, its place's static time in the static world model (capped)
    "sensor_speed",  # m/s, the laser's own speed
    "llr",  # its existence score
)
"""The features of a candidate's history, in column order."""

LEG_WIDTH = 0.1
"""Width [m] of a leg for :data:`FEATURES` ``beams_per_leg``."""
STATIC_CAP = 60.0
"""Static times [s] above this (``inf`` on a map's obstacle) are given as this."""

MODEL_FORMAT = "laserpeople-confirm-model"
MODEL_VERSION = 1
DEFAULT_MODEL = "confirm.json"
"""The shipped model, in ``laserpeople/tracking/models``."""


def candidate_features(
    age: float,
    scans: int,
    detected_scans: int,
    two_scans: int,
    score_sum: float,
    score_count: int,
    score_max: float,
    score_last: float,
    leg_net: float,
    leg_length: float,
    velocity: FloatArray,
    offset: FloatArray,
    angle_step: float,
    legs_now: int,
    static_time: float,
    sensor_speed: float,
    llr: float,
) -> list[float]:
    """One row of :data:`FEATURES` from a candidate's counts.

    Args:
        age: Time [s] since its birth.
        scans: Scans since its birth (at least 1).
        detected_scans: Of them, scans with a member leg detected.
        two_scans: Of them, scans counted as both legs.
        score_sum, score_count, score_max, score_last: Sum, count, largest and last of the
            detector scores of its detected member legs (0, 0, -inf, NaN when none).
        leg_net: Net displacement [m] of its member leg that moved farthest from its first
            detection; ``leg_length`` [m] that leg's path length.
        velocity: Filtered velocity (2,) [m/s].
        offset: Position minus the sensor's (2,) [m].
        angle_step: The scanner's angle between beams [rad] (NaN when unknown).
        legs_now: Member legs detected in this scan.
        static_time: Static time [s] of its place.
        sensor_speed: Speed [m/s] of the sensor.
        llr: Existence score.
    """
    rng = math.hypot(float(offset[0]), float(offset[1]))
    beams = (
        LEG_WIDTH / (max(rng, 0.05) * angle_step)
        if math.isfinite(angle_step) and angle_step > 0
        else 0.0
    )
    n = max(scans, 1)
    return [
        age,
        detected_scans / n,
        two_scans / n,
        score_sum / score_count if score_count else 0.0,
        score_max if score_count else 0.0,
        score_last if math.isfinite(score_last) else 0.0,
        leg_net,
        leg_net / leg_length if leg_length > 1e-9 else 0.0,
        math.hypot(float(velocity[0]), float(velocity[1])),
        rng,
        beams,
        float(legs_now),
        min(static_time, STATIC_CAP),
        sensor_speed,
        llr,
    ]


@dataclass(frozen=True, eq=False)
class ConfirmModel:
    """Boosted stumps over :data:`FEATURES` (the margin above which a candidate is
    confirmed is ``people.learned_margin``).

    Attributes:
        classifier: The stumps (columns: :data:`FEATURES` in order).
        training: Free-form provenance (seeds, counts, rounds, the margins tried).
    """

    classifier: AdaBoostLegClassifier
    training: dict[str, Any] = field(default_factory=dict)

    def scores(self, rows: FloatArray) -> FloatArray:
        """AdaBoost margins (N,) of feature rows (N, len(FEATURES))."""
        return self.classifier.decision_function(rows)

    def to_json(self) -> dict[str, Any]:
        """The JSON document of this model."""
        return {
            "format": MODEL_FORMAT,
            "version": MODEL_VERSION,
            "features": list(FEATURES),
            "stumps": [
                {
                    "feature": FEATURES[s.feature],
                    "threshold": s.threshold,
                    "polarity": s.polarity,
                    "alpha": s.alpha,
                    "r": s.r,
                }
                for s in self.classifier.stumps
            ],
            "training": self.training,
        }

    def save(self, path: str | Path) -> None:
        """Write the model as JSON."""
        Path(path).write_text(json.dumps(self.to_json(), indent=1) + "\n", encoding="utf-8")

    @classmethod
    def from_json(cls, doc: Any, source: str) -> ConfirmModel:
        """The model of a JSON document read from ``source`` (named in errors).

        Raises:
            ModelFileError: not a confirmation model, another feature list, or a bad stump.
        """
        if not isinstance(doc, dict) or doc.get("format") != MODEL_FORMAT:
            raise ModelFileError(f"{source}: not a {MODEL_FORMAT} file")
        if doc.get("version") != MODEL_VERSION:
            raise ModelFileError(f"{source}: version {doc.get('version')!r}, need {MODEL_VERSION}")
        if doc.get("features") != list(FEATURES):
            raise ModelFileError(
                f"{source}: features {doc.get('features')!r} are not this version's "
                f"{list(FEATURES)}; regenerate it with benchmarks/fit_confirm.py"
            )
        stumps = []
        for i, s in enumerate(doc.get("stumps", [])):
            try:
                stump = Stump(
                    FEATURES.index(s["feature"]),
                    float(s["threshold"]),
                    int(s["polarity"]),
                    float(s["alpha"]),
                    float(s["r"]),
                )
            except (KeyError, TypeError, ValueError) as exc:
                raise ModelFileError(f"{source}: stump {i} is malformed ({exc})") from exc
            if stump.polarity not in (-1, 1) or not (
                math.isfinite(stump.threshold) and math.isfinite(stump.alpha)
            ):
                raise ModelFileError(f"{source}: stump {i} has a bad polarity or value")
            stumps.append(stump)
        if not stumps:
            raise ModelFileError(f"{source}: no stumps")
        return cls(
            AdaBoostLegClassifier.from_stumps(stumps, len(FEATURES)),
            dict(doc.get("training", {})),
        )

    @classmethod
    def load(cls, path: str | Path) -> ConfirmModel:
        """Read a model file (JSON).

        Raises:
            ModelFileError: unreadable or not a confirmation model.
        """
        try:
            doc = json.loads(Path(path).read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise ModelFileError(f"{path}: cannot read a confirmation model ({exc})") from exc
        return cls.from_json(doc, str(path))


_DEFAULT: ConfirmModel | None = None


def default_confirm_model() -> ConfirmModel:
    """The shipped model (read once)."""
    global _DEFAULT
    if _DEFAULT is None:
        text = (
            resources.files("laserpeople.tracking")
            .joinpath("models", DEFAULT_MODEL)
            .read_text(encoding="utf-8")
        )
        _DEFAULT = ConfirmModel.from_json(
            json.loads(text), f"laserpeople/tracking/models/{DEFAULT_MODEL}"
        )
    return _DEFAULT


def angle_step(segments: Sequence[Segment]) -> float:
    """The scanner's angle [rad] between neighbouring beams, from the first segment (sensor
    frame points and beam indices) that spans two beams or more; NaN without one."""
    for seg in segments:
        if seg.beams.size >= 2 and seg.beams[-1] > seg.beams[0]:
            (x0, y0), (x1, y1) = seg.points[0].tolist(), seg.points[-1].tolist()
            turn = abs(math.remainder(math.atan2(y1, x1) - math.atan2(y0, x0), math.tau))
            return turn / float(seg.beams[-1] - seg.beams[0])
    return math.nan
