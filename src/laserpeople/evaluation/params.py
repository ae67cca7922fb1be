"""Parameters of the tracking metrics."""

from __future__ import annotations

from dataclasses import dataclass

from laserpeople.config import param
from laserpeople.errors import ConfigError
from laserpeople.tracks import TRACK_KINDS


@dataclass(frozen=True)
class EvaluationParams:
    """How tracks are scored against ground truth.

    ``gate`` is the distance threshold T of the CLEAR MOT correspondence (Bernardin &
    Stiefelhagen 2008, Sec. 2.1) and also decides an identity match in IDF1; ``schenk_h``
    is the threshold h of the adapted MOTP of 004 (eq. 10).
    """

    config_section = "evaluation"

    gate: float = param(
        0.75,
        "the leg_tracker benchmark's scorer (0.75 m; docs/evaluation.md)",
        "largest truth-to-track distance that still counts as a match (CLEAR MOT, IDF1)",
        "m",
    )
    schenk_h: float = param(
        0.008,
        "004 Sec. 3.2, eq. 10",
        "h of the matching value m = min(1, h / d^3); 0.008 m^3 scores d <= 0.2 m as 1",
        "m^3",
    )
    kind: str = param(
        "person",
        "assumption: people are what the benchmarks label",
        "track kind that is compared with the people of the ground truth",
    )

    def __post_init__(self) -> None:
        if not (self.gate > 0.0):
            raise ConfigError(f"gate must be a positive distance in metres, got {self.gate}")
        if not (self.schenk_h > 0.0):
            raise ConfigError(f"schenk_h must be positive, got {self.schenk_h}")
        if self.kind not in TRACK_KINDS:
            raise ConfigError(
                f"kind {self.kind!r} is not one of {', '.join(TRACK_KINDS)}",
                hint="use --kind person (or leg / group)",
            )
