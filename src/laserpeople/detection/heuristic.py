"""The hand-tuned baseline classifier of 000 Sec. 2.3.3.

A segment is a person (leg) when all of these hold:

* both jump distances (features 4 and 5) exceed 30 cm (a local-minimum blob),
* its width (feature 6) is between 5 cm and 50 cm,
* it has at least four points (feature 1),
* some beam of it moved more than 2 cm since the previous, aligned scan (the motion cue
  behind feature 14; beam-wise range subtraction, the sensor assumed stationary),
* its standard deviation (feature 2) is below 0.5 m.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.detection.features import SegmentFeatures


@dataclass(frozen=True)
class HeuristicParams:
    """Thresholds of the heuristic baseline, all from 000 Sec. 2.3.3."""

    config_section = "heuristic"

    min_jump: float = param(0.30, "000 Sec. 2.3.3", "both jump distances exceed this", "m")
    min_width: float = param(0.05, "000 Sec. 2.3.3", "smallest accepted blob width", "m")
    max_width: float = param(0.50, "000 Sec. 2.3.3", "largest accepted blob width", "m")
    min_points: int = param(4, "000 Sec. 2.3.3", "fewer points are discarded")
    min_motion: float = param(
        0.02, "000 Sec. 2.3.3", "some beam must have moved more than this", "m"
    )
    max_std: float = param(0.5, "000 Sec. 2.3.3", "largest standard deviation", "m")


@dataclass(frozen=True)
class HeuristicLegClassifier:
    """Rule-based leg classifier over :class:`SegmentFeatures`."""

    params: HeuristicParams = HeuristicParams()

    def predict(self, features: SegmentFeatures) -> NDArray[np.int64]:
        """+1 for segments passing every rule, -1 otherwise (M,)."""
        f = features.values
        p = self.params
        ok = (
            (f[:, 3] > p.min_jump)
            & (f[:, 4] > p.min_jump)
            & (f[:, 5] > p.min_width)
            & (f[:, 5] < p.max_width)
            & (f[:, 0] >= p.min_points)
            & (features.max_beam_motion > p.min_motion)
            & (f[:, 1] < p.max_std)
        )
        return np.where(ok, 1, -1).astype(np.int64)
