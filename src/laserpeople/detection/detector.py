"""Leg detectors: segment a scan, compute the 14 features, classify each segment.

``detect(scan) -> Detections`` with one detection per segment classified as a leg:
position = segment centre (mean of its points) in the sensor frame, a fixed diagonal
measurement covariance, score = AdaBoost margin F(e) (1.0 for the heuristic). A detector
keeps the previous scan of each sensor for the motion feature (#14), so feed it the scans
of a recording in time order; :meth:`reset` forgets them.
"""

from __future__ import annotations

import abc
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from types import MappingProxyType

import numpy as np
from numpy.typing import NDArray

from laserpeople.config import param
from laserpeople.detection.features import (
    DEFERRED,
    FeatureParams,
    SegmentFeatures,
    compute_features_deferred,
    compute_features_joined,
    split_features,
)
from laserpeople.detection.heuristic import HeuristicLegClassifier, HeuristicParams
from laserpeople.detection.model_file import LegModel, load_model, model_from_json
from laserpeople.detection.sparse import SparseLegParams, sparse_legs_of_block
from laserpeople.scan import Scan
from laserpeople.segmentation import (
    JumpDistanceParams,
    JumpDistanceSegmenter,
    SegmentBlock,
    SegmentTable,
)
from laserpeople.tracks import Detections

DEFAULT_FEATURE_PARAMS = FeatureParams()
DEFAULT_HEURISTIC_PARAMS = HeuristicParams()
DEFAULT_JUMP_DISTANCE_PARAMS = JumpDistanceParams()

DEFAULT_MODEL = "default.json"

BOUND_MIN_POINTS = 16
"""Segments with fewer points have their deferred features computed without asking
:meth:`_SegmentDetector._may_pass` first: for them the margin's bound costs more than the
features it could save."""


@dataclass(frozen=True)
class LegDetectorParams:
    """Parameters shared by the segment-based leg detectors."""

    config_section = "leg_detector"
    paper_preset = MappingProxyType(
        {  # 000 Sec. 2: 3+ points a leg, the leg at its segment's centre
            "sparse": MappingProxyType({"enabled": False}),
            "centre_offset": 0.0,
        }
    )

    leg_position_std: float = param(
        0.1,
        "our choice: about a leg radius; 000 Sec. 4.7 uses sigma_x = sigma_y = 0.1 m for new "
        "tracks",
        "standard deviation of a leg centre measurement along x and y",
        "m",
    )
    score_threshold: float = param(
        0.0,
        "000 Table 1 (H(e) = sign(F(e)))",
        "segments with AdaBoost margin above this are legs",
    )
    min_distance: float = param(
        0.0,
        "extension (000 classifies every segment): 0 keeps that",
        "segments whose centre is closer to the sensor are never legs; set it just beyond the "
        "robot's own body when the laser sees parts of its robot (leg_tracker's rear laser "
        "does, at 0.2-0.3 m)",
        "m",
    )
    max_distance: float = param(
        float("inf"),
        "extension (000 classifies every segment): no limit keeps that",
        "segments whose centre is farther from the sensor are never legs (few beams hit a far "
        "leg, so far clutter is easily mistaken for one)",
        "m",
    )
    centre_offset: float = param(
        0.045,
        "departure from 000 Sec. 2 (0: the segment centre; --preset paper), our choice: the "
        "scanner sees the near half of a leg of "
        "radius ~0.07 m, whose points' centroid lies 2r/pi ~ 0.045 m before the leg's axis",
        "distance a leg's position is moved from its points' centroid away from the sensor",
        "m",
    )
    sparse: SparseLegParams = param(  # noqa: RUF009 (a frozen default instance)
        SparseLegParams(),
        "extension (docs/leg-detection.md, Legs of one or two points)",
        "legs a coarse scanner shows by one or two points (detection/sparse.py)",
    )

    def __post_init__(self) -> None:
        if not 0.0 <= self.min_distance < self.max_distance:
            raise ValueError("need 0 <= min_distance < max_distance")
        for name in ("score_threshold", "centre_offset"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"{name} must be finite, got {getattr(self, name)}")


DEFAULT_LEG_DETECTOR_PARAMS = LegDetectorParams()


@dataclass(frozen=True, eq=False)
class ScanClassification:
    """Everything a detector computed for one scan (for reports and --all-segments).

    Attributes:
        table: The segments.
        features: Their features.
        scores: Score (M,) of every segment (NaN for segments not classified: fewer than 3
            points and no sparse leg, or outside the detector's distance limits).
        is_leg: Decision (M,) for every segment (False for unclassified segments).
    """

    table: SegmentTable
    features: SegmentFeatures
    scores: NDArray[np.float64]
    is_leg: NDArray[np.bool_]


class _SegmentDetector(abc.ABC):
    """Shared machinery: segmentation, features, previous scan, building Detections."""

    def __init__(
        self,
        segmentation: JumpDistanceParams,
        params: LegDetectorParams,
        feature_params: FeatureParams,
    ) -> None:
        self.segmenter = JumpDistanceSegmenter(segmentation)
        self.params = params
        self.feature_params = feature_params
        self._previous: dict[str, Scan] = {}

    def reset(self) -> None:
        """Forget previous scans (start of a new recording)."""
        self._previous.clear()

    @abc.abstractmethod
    def _scores(self, features: SegmentFeatures) -> NDArray[np.float64]:
        """Score (M,) of every classifiable segment; larger means more leg-like."""

    def _may_pass(self, features: SegmentFeatures, rows: NDArray[np.int64]) -> NDArray[np.bool_]:
        """Whether each of the segments ``rows`` (R,) may score above ``score_threshold``
        whatever its features :data:`~laserpeople.detection.features.DEFERRED` (NaN in
        ``features``); those that cannot are no legs, and their deferred features are
        never computed. Here: all of them."""
        return np.ones(rows.size, dtype=bool)

    def classify(self, scan: Scan) -> ScanClassification:
        """Segment, featurise and score ``scan``; remembers it as the previous scan."""
        return self.classify_many([scan])[0]

    def classify_many(self, scans: Sequence[Scan]) -> list[ScanClassification]:
        """:meth:`classify` of each of ``scans`` in turn (the same results), their features
        and scores computed for all of them at once."""
        block, feats, scores, is_leg = self._classify_block(scans)
        if len(scans) == 1:
            return [ScanClassification(block.tables[0], feats, scores, is_leg)]
        first = block.table_starts.tolist()
        parts = split_features(feats, [b - a for a, b in itertools.pairwise(first)])
        return [
            ScanClassification(table, part, scores[a:b], is_leg[a:b])
            for table, part, a, b in zip(block.tables, parts, first[:-1], first[1:], strict=True)
        ]

    def _classify_block(
        self, scans: Sequence[Scan], legs_only: bool = False
    ) -> tuple[SegmentBlock, SegmentFeatures, NDArray[np.float64], NDArray[np.bool_]]:
        """The segments of ``scans`` as one block, with the features (M, ...), scores (M,)
        and decisions (M,) of all its segments; remembers the scans as previous ones. With
        ``legs_only`` the decisions are the same, but the segments that :meth:`_may_pass`
        rules out are not scored (score NaN, and NaN in the columns
        :data:`~laserpeople.detection.features.DEFERRED` where the extension computes the
        features)."""
        block = self.segmenter.block(scans)
        previous = []
        last = dict(self._previous)
        for scan in scans:
            previous.append(last.get(scan.sensor))
            last[scan.sensor] = scan
        joined = (block.points, block.offsets)
        args = (block.tables, scans, previous, self.feature_params, block.full_circle, joined)
        deferred = compute_features_deferred(*args) if legs_only else None
        feats = compute_features_joined(*args) if deferred is None else deferred.features
        scores = np.full(len(feats), np.nan)
        ok = feats.classifiable
        sparse = sparse_legs_of_block(
            block, scans, self.segmenter.params.threshold, self.params.sparse
        )
        scores[sparse] = self.params.sparse.score
        if self.params.min_distance > 0.0 or self.params.max_distance < math.inf:
            distance = np.hypot(feats.centres[:, 0], feats.centres[:, 1])
            within = (distance >= self.params.min_distance) & (distance <= self.params.max_distance)
            ok &= within
            scores[sparse[~within[sparse]]] = np.nan
        if deferred is not None:
            rows = np.flatnonzero(ok & (feats.values[:, 0] >= BOUND_MIN_POINTS))
            ok[rows] = self._may_pass(feats, rows)
            deferred.complete(np.flatnonzero(ok))
        n_ok = int(np.count_nonzero(ok))
        if n_ok == len(feats):  # (every segment: the features as they are, no copies)
            scores[:] = self._scores(feats)
        elif n_ok:
            scores[ok] = self._scores(_subset(feats, ok))
        is_leg = scores > self.params.score_threshold  # (NaN, unscored, compares False)
        self._previous.update(last)  # (only once all of them are classified)
        return block, feats, scores, is_leg

    def detect(self, scan: Scan) -> Detections:
        """The legs found in ``scan`` (sensor frame)."""
        return self.detections_from(scan, self.classify(scan))

    def detect_many(self, scans: Sequence[Scan]) -> list[Detections]:
        """:meth:`detect` of each of ``scans`` in turn (the same detections), classified all
        at once: the legs, their positions, scores and segments picked out of the whole
        block, then split by scan."""
        block, feats, scores, is_leg = self._classify_block(scans, legs_only=True)
        idx = np.flatnonzero(is_leg)
        positions = self._positions(feats.centres[idx])
        cov = self._covariances(idx.size)
        legs = scores[idx]
        segments = block.segments_at(idx)
        cuts = np.searchsorted(idx, block.table_starts).tolist()
        out = []
        for k, scan in enumerate(scans):
            a, b = cuts[k], cuts[k + 1]
            out.append(
                Detections(
                    stamp=scan.stamp,
                    scan_index=scan.index,
                    positions=positions[a:b],
                    covariances=cov[a:b],
                    scores=legs[a:b],
                    frame="sensor",
                    sensor_pose=scan.pose,
                    segments=tuple(segments[a:b]),
                )
            )
        return out

    def _positions(self, centroids: NDArray[np.float64]) -> NDArray[np.float64]:
        """Leg positions (L, 2) [m] from the centroids (L, 2) of their segments: moved
        ``centre_offset`` further along the beam (the centroid of a leg's visible half
        lies in front of the leg's axis)."""
        distance = np.maximum(np.hypot(centroids[:, 0], centroids[:, 1]), 1e-9)
        return np.asarray(centroids * (1.0 + self.params.centre_offset / distance)[:, None])

    def _covariances(self, count: int) -> NDArray[np.float64]:
        """Position covariances (count, 2, 2) [m^2]: ``leg_position_std`` squared on the
        diagonal."""
        var = self.params.leg_position_std**2
        cov = np.zeros((count, 2, 2))
        cov[:, 0, 0] = var
        cov[:, 1, 1] = var
        return cov

    def detections_from(self, scan: Scan, result: ScanClassification) -> Detections:
        """The detections of an already classified scan."""
        idx = np.flatnonzero(result.is_leg)
        return Detections(
            stamp=scan.stamp,
            scan_index=scan.index,
            positions=self._positions(result.features.centres[idx]),
            covariances=self._covariances(idx.size),
            scores=result.scores[idx],
            frame="sensor",
            sensor_pose=scan.pose,
            segments=result.table.segments_at(idx),
        )


def _subset(features: SegmentFeatures, mask: NDArray[np.bool_]) -> SegmentFeatures:
    return SegmentFeatures(
        features.values[mask],
        features.max_beam_motion[mask],
        features.centres[mask],
        features.circle_centres[mask],
    )


class AdaBoostLegDetector(_SegmentDetector):
    """Leg detector with a boosted classifier (000 Sec. 2).

    Args:
        model: The trained model; its jump-distance threshold is used for segmentation
            unless ``segmentation`` is given.
    """

    def __init__(
        self,
        model: LegModel,
        params: LegDetectorParams = DEFAULT_LEG_DETECTOR_PARAMS,
        segmentation: JumpDistanceParams | None = None,
        feature_params: FeatureParams = DEFAULT_FEATURE_PARAMS,
    ) -> None:
        seg = segmentation or JumpDistanceParams(threshold=model.segmentation_threshold)
        super().__init__(seg, params, feature_params)
        self.model = model
        self._columns = np.array(model.columns, dtype=np.int64)
        self._deferred = tuple(i for i, c in enumerate(model.columns) if c in DEFERRED)

    def _scores(self, features: SegmentFeatures) -> NDArray[np.float64]:
        return self.model.classifier.decision_function(features.values[:, self._columns])

    def _may_pass(self, features: SegmentFeatures, rows: NDArray[np.int64]) -> NDArray[np.bool_]:
        """Whether the margin's upper bound over the deferred features (each of their
        stumps at its best) is above ``score_threshold``: the margin never is when its
        bound is not."""
        X = features.values[rows][:, self._columns]
        X[:, list(self._deferred)] = 0.0  # (not read: any finite value)
        bounds = self.model.classifier.margin_bounds(X, self._deferred)
        return np.asarray(bounds > self.params.score_threshold)

    @classmethod
    def default(
        cls, params: LegDetectorParams = DEFAULT_LEG_DETECTOR_PARAMS
    ) -> AdaBoostLegDetector:
        """The detector with the model shipped in the package."""
        return cls(default_model(), params)

    @classmethod
    def from_file(
        cls, path: str | Path, params: LegDetectorParams = DEFAULT_LEG_DETECTOR_PARAMS
    ) -> AdaBoostLegDetector:
        """The detector with the model in ``path`` (raises ModelFileError if unusable)."""
        return cls(load_model(path), params)


class HeuristicLegDetector(_SegmentDetector):
    """The hand-tuned baseline of 000 Sec. 2.3.3 (score 1.0 for every detection)."""

    def __init__(
        self,
        heuristic: HeuristicParams = DEFAULT_HEURISTIC_PARAMS,
        params: LegDetectorParams = DEFAULT_LEG_DETECTOR_PARAMS,
        segmentation: JumpDistanceParams = DEFAULT_JUMP_DISTANCE_PARAMS,
        feature_params: FeatureParams = DEFAULT_FEATURE_PARAMS,
    ) -> None:
        super().__init__(segmentation, params, feature_params)
        self.classifier = HeuristicLegClassifier(heuristic)

    def _scores(self, features: SegmentFeatures) -> NDArray[np.float64]:
        return np.where(self.classifier.predict(features) > 0, 1.0, -1.0)


def default_model() -> LegModel:
    """The model shipped in ``laserpeople/detection/models/default.json``."""
    import json

    ref = resources.files("laserpeople.detection").joinpath("models", DEFAULT_MODEL)
    where = str(ref)
    try:
        doc = json.loads(ref.read_text(encoding="utf-8"))
    except (FileNotFoundError, json.JSONDecodeError) as exc:
        from laserpeople.errors import ModelFileError

        raise ModelFileError(
            f"the shipped default model is missing or broken: {exc}",
            path=where,
            hint="reinstall laserpeople or pass --model",
        ) from exc
    return model_from_json(doc, where)


def make_leg_detector(
    name: str = "adaboost", model: str | Path | None = None, params: LegDetectorParams | None = None
) -> AdaBoostLegDetector | HeuristicLegDetector:
    """The leg detector ``adaboost`` (the shipped model, or the model file ``model``) or
    ``heuristic``, with ``params`` (None: defaults); what ``track --detector`` builds."""
    from laserpeople.errors import ConfigError

    params = params if params is not None else LegDetectorParams()
    if name == "adaboost":
        if model is not None:
            return AdaBoostLegDetector.from_file(model, params)
        return AdaBoostLegDetector.default(params)
    if name == "heuristic":
        if model is not None:
            raise ConfigError("--model applies to the adaboost detector only")
        return HeuristicLegDetector(params=params)
    from laserpeople.spelling import did_you_mean

    raise ConfigError(
        f"unknown detector {name!r}{did_you_mean(name, ('adaboost', 'heuristic'), lead=': ')}",
        hint="choose adaboost or heuristic",
    )
