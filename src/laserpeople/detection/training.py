"""Labelled segments for training and testing the leg classifier.

Every builder walks the scans of one recording in time order (so feature 14 sees the
previous scan), segments them, computes the 14 features and attaches a label to every
segment of at least three points (000 Sec. 2.2). The result is a
:class:`LabelledSegments` table whose ``group`` column names the recording (and topic) each
segment came from, so that train/test splits can keep whole recordings apart.

Label sources:

* leg_tracker positives (``positive_*_extracted.bag``): ``/training_scan`` paired one-to-one
  (by message order) with ``/leg_cluster_positions`` (PoseArray, laser frame). A segment
  whose centre is within ``match_radius`` of a label is a leg. The labels are the centres of
  the leg_tracker project's own clusters: with a 0.13 m jump distance
  (:data:`LEG_TRACKER_SEGMENTATION`) 95 % of the 1852 labels sit exactly (< 1 mm) on one of
  our segment centres and 1825 are matched, against 1779 with 0.1 m, which splits legs.
  By default (``unlabelled="drop"``, the leg_tracker project's own protocol) the other
  segments of these scans are *not* used: the scans show unlabelled people walking near the
  sensor (e.g. positive_2 scans 0-9, positive_3 scans 149-154, positive_6 scans 0-20), so
  calling them non-legs would inject wrong labels. ``unlabelled="negative"`` keeps the old
  behaviour (unmatched segments farther than ``ambiguous_radius`` from every label are
  negatives).
* leg_tracker negatives (``negative_*.bag``): every segment of every laser topic is negative.
* neko7055: the per-frame leg segment indices (the label rule is our segmentation with
  0.1 m and wrap-around, see :mod:`laserpeople.io.neko`).
* recordings with per-beam ground truth (``.npz``, the simulator): a segment is a leg when
  more than half of its beams hit a leg.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from laserpeople.detection.augment import (
    TRANSFER_VARIANTS,
    Variant,
    beam_classes,
    resampled_stream,
    segment_labels_from_beams,
)
from laserpeople.detection.features import (
    N_FEATURES,
    FeatureParams,
    SegmentFeatures,
    compute_features,
)
from laserpeople.errors import ConfigError, RecordingError
from laserpeople.io.damage import OnError
from laserpeople.scan import Scan
from laserpeople.segmentation import (
    JumpDistanceParams,
    JumpDistanceSegmenter,
    SegmentTable,
    covers_full_circle,
)

DEFAULT_FEATURE_PARAMS = FeatureParams()
DEFAULT_JUMP_DISTANCE_PARAMS = JumpDistanceParams()
LEG_TRACKER_SEGMENTATION = JumpDistanceParams(threshold=0.13)
"""Jump distance under which the leg_tracker labels are segment centres (see module doc)."""

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
Unlabelled = Literal["negative", "drop"]
InputKind = Literal["truth", "positive", "negative", "neko"]
"""Kinds of labelled input of ``laserpeople train`` (see :func:`augmented_input`)."""

# labels of one scan: +1 leg, -1 not a leg, 0 = leave out
Labeller = Callable[[Scan, SegmentTable, SegmentFeatures], IntArray]


_VARIANT_SUFFIX = re.compile(r"@\d+\.\d+deg x[^:@]+$")
"""The ``@0.50deg x1.4`` that :func:`augmented_segments` adds to a group's file name."""


@dataclass(frozen=True, eq=False)
class LabelledSegments:
    """Segments with features and labels, from one or many recordings.

    Attributes:
        features: Feature matrix (N, 14).
        max_beam_motion: Largest beam range change (N,) [m] since the previous scan.
        distance: Distance (N,) [m] of each segment's centre from the sensor.
        labels: +1 leg / -1 not a leg (N,).
        group: Index (N,) into ``groups`` of the recording each segment came from.
        scan: Scan index (N,) on its topic.
        groups: Recording names (``file`` or ``file:topic``).
    """

    features: FloatArray
    max_beam_motion: FloatArray
    distance: FloatArray
    labels: IntArray
    group: IntArray
    scan: IntArray
    groups: tuple[str, ...]

    def __len__(self) -> int:
        return int(self.labels.size)

    @property
    def n_positive(self) -> int:
        """Number of legs."""
        return int((self.labels > 0).sum())

    @property
    def n_negative(self) -> int:
        """Number of non-legs."""
        return int((self.labels < 0).sum())

    def recorded_counts(self) -> tuple[int, int]:
        """Legs and non-legs as recorded: ``train --augment`` shows every recorded segment
        to each scanner variant, so these are the counts of the variant with the most
        (the plain counts when there are no variants)."""
        variant = np.array(
            [
                m.group(0) if (m := _VARIANT_SUFFIX.search(g.rpartition(":")[0] or g)) else ""
                for g in self.groups
            ],
            dtype=object,
        )
        of_row = variant[self.group]
        seen = [self.labels[of_row == v] for v in set(of_row.tolist())] or [self.labels]
        return max(int((y > 0).sum()) for y in seen), max(int((y < 0).sum()) for y in seen)

    def select(self, mask: NDArray[np.bool_]) -> LabelledSegments:
        """The rows where ``mask`` is true (groups kept)."""
        return LabelledSegments(
            self.features[mask],
            self.max_beam_motion[mask],
            self.distance[mask],
            self.labels[mask],
            self.group[mask],
            self.scan[mask],
            self.groups,
        )

    def of_groups(self, names: Iterable[str]) -> LabelledSegments:
        """The segments of the named recordings (a name matches itself and ``name:topic``)."""
        wanted = tuple(names)
        keep = [
            i
            for i, g in enumerate(self.groups)
            if any(g == w or g.startswith(w + ":") for w in wanted)
        ]
        return self.select(np.isin(self.group, keep))

    def summary(self) -> str:
        """``N segments (a legs, b non-legs) from k recordings`` (and ``(m lasers)`` when
        a recording holds several: the groups are ``file:laser``; and ``in v scanner
        variants`` for ``train --augment``, whose groups are ``file@variant:laser``)."""
        groups = [self.groups[g] for g in sorted(set(self.group.tolist()))]
        parts = [g.rpartition(":") if ":" in g else (g, "", "") for g in groups]
        sources = {(_VARIANT_SUFFIX.sub("", file), laser) for file, _, laser in parts}
        files = len({file for file, _ in sources})
        variants = {m.group(0) for file, _, _ in parts if (m := _VARIANT_SUFFIX.search(file))}
        lasers = f" ({len(sources)} lasers)" if len(sources) != files else ""
        plural = "" if len(variants) == 1 else "s"
        varied = f" in {len(variants)} scanner variant{plural}" if variants else ""
        return (
            f"{len(self)} segments ({self.n_positive} legs, {self.n_negative} non-legs) "
            f"from {files} recording{'' if files == 1 else 's'}{lasers}{varied}"
        )

    @classmethod
    def empty(cls) -> LabelledSegments:
        """No segments."""
        return cls(
            np.empty((0, N_FEATURES)),
            np.empty(0),
            np.empty(0),
            np.empty(0, dtype=np.int64),
            np.empty(0, dtype=np.int64),
            np.empty(0, dtype=np.int64),
            (),
        )

    @classmethod
    def concat(cls, parts: Sequence[LabelledSegments]) -> LabelledSegments:
        """Join tables; group names are merged."""
        names: list[str] = []
        groups = []
        for part in parts:
            mapping = []
            for g in part.groups:
                if g not in names:
                    names.append(g)
                mapping.append(names.index(g))
            groups.append(np.asarray(mapping, dtype=np.int64)[part.group])
        if not parts:
            return cls.empty()
        return cls(
            np.concatenate([p.features for p in parts]),
            np.concatenate([p.max_beam_motion for p in parts]),
            np.concatenate([p.distance for p in parts]),
            np.concatenate([p.labels for p in parts]),
            np.concatenate(groups),
            np.concatenate([p.scan for p in parts]),
            tuple(names),
        )


def too_few_examples(data: LabelledSegments, minimum: int) -> str | None:
    """What ``data`` lacks to train on (``"3 legs"``, ``"0 legs and 12 non-legs"``), or None
    when it holds at least ``minimum`` legs and ``minimum`` non-legs as recorded (see
    :meth:`LabelledSegments.recorded_counts`)."""
    legs, others = data.recorded_counts()
    short = [f"{n} {name}" for n, name in ((legs, "legs"), (others, "non-legs")) if n < minimum]
    return " and ".join(short) or None


def label_scans(
    scans: Iterable[Scan],
    labeller: Labeller,
    group_of: Callable[[Scan], str],
    segmentation: JumpDistanceParams = DEFAULT_JUMP_DISTANCE_PARAMS,
    feature_params: FeatureParams = DEFAULT_FEATURE_PARAMS,
) -> LabelledSegments:
    """Segment, featurise and label a time-ordered stream of scans."""
    segmenter = JumpDistanceSegmenter(segmentation)
    previous: dict[str, Scan] = {}
    names: list[str] = []
    feats, motion, distance, labels, group, scan_idx = [], [], [], [], [], []
    for scan in scans:
        table = segmenter(scan)
        f = compute_features(
            table,
            scan,
            previous.get(scan.sensor),
            feature_params,
            full_circle=covers_full_circle(scan),
        )
        previous[scan.sensor] = scan
        if len(table) == 0:
            continue
        lab = labeller(scan, table, f)
        keep = (lab != 0) & f.classifiable
        if not keep.any():
            continue
        name = group_of(scan)
        if name not in names:
            names.append(name)
        feats.append(f.values[keep])
        motion.append(f.max_beam_motion[keep])
        distance.append(np.hypot(f.centres[keep, 0], f.centres[keep, 1]))
        labels.append(lab[keep])
        group.append(np.full(int(keep.sum()), names.index(name), dtype=np.int64))
        scan_idx.append(np.full(int(keep.sum()), scan.index, dtype=np.int64))
    if not feats:
        return LabelledSegments.empty()
    return LabelledSegments(
        np.concatenate(feats),
        np.concatenate(motion),
        np.concatenate(distance),
        np.concatenate(labels).astype(np.int64),
        np.concatenate(group),
        np.concatenate(scan_idx),
        tuple(names),
    )


def match_labels(
    centres: FloatArray,
    label_points: FloatArray,
    match_radius: float,
    ambiguous_radius: float,
    unlabelled: Unlabelled,
) -> IntArray:
    """Labels (M,) of segments with centres (M, 2) against labelled leg positions (L, 2)."""
    m = centres.shape[0]
    if label_points.shape[0] == 0:
        return np.full(m, -1 if unlabelled == "negative" else 0, dtype=np.int64)
    dist = np.hypot(
        centres[:, None, 0] - label_points[None, :, 0],
        centres[:, None, 1] - label_points[None, :, 1],
    ).min(axis=1)
    out = np.zeros(m, dtype=np.int64)
    out[dist <= match_radius] = 1
    if unlabelled == "negative":
        out[dist > ambiguous_radius] = -1
    return out


def leg_tracker_positive(
    path: str | Path,
    *,
    match_radius: float = 0.1,
    ambiguous_radius: float = 0.5,
    unlabelled: Unlabelled = "drop",
    segmentation: JumpDistanceParams = LEG_TRACKER_SEGMENTATION,
    scan_topic: str = "/training_scan",
    label_topic: str = "/leg_cluster_positions",
    on_error: OnError = "stop",
    damage: list[str] | None = None,
) -> LabelledSegments:
    """Labelled segments of a leg_tracker ``positive_*_extracted.bag`` (see module doc);
    ``on_error`` is the reader's policy for damaged scans, whose summary goes to
    ``damage``."""
    from laserpeople.io import open_recording

    p = Path(path)
    poses = read_pose_arrays(p, label_topic)
    rec = open_recording(p, on_error=on_error)
    try:
        scans = list(rec.scans([scan_topic]))
    finally:
        _note_damage(rec, damage)
        rec.close()
    if len(scans) != len(poses):
        raise RecordingError(
            f"{len(scans)} scans on {scan_topic} but {len(poses)} label messages on "
            f"{label_topic}; they must pair one to one",
            path=p,
        )
    scans.sort(key=lambda s: s.index)
    by_index = {s.index: poses[i] for i, s in enumerate(scans)}

    def labeller(scan: Scan, table: SegmentTable, f: SegmentFeatures) -> IntArray:
        return match_labels(
            f.centres, by_index[scan.index], match_radius, ambiguous_radius, unlabelled
        )

    return label_scans(scans, labeller, lambda s: p.name, segmentation)


def read_pose_arrays(path: Path, topic: str) -> list[FloatArray]:
    """The (x, y) of every pose (L, 2) of each ``geometry_msgs/PoseArray`` on ``topic``
    (the bag opened and read through :func:`~laserpeople.io.bag_guard.open_reader`)."""
    from laserpeople.io.bag_guard import bag_messages, open_reader

    reader = open_reader(path)
    try:
        cons = [c for c in reader.connections if c.topic == topic]
        if not cons:
            raise RecordingError(
                f"no topic {topic!r} with leg labels",
                path=path,
                hint="give a leg_tracker positive_*_extracted.bag",
            )
        out = []
        for _, _, msg in bag_messages(reader, cons, path, f"leg labels on {topic}"):
            try:
                xy = [[float(q.position.x), float(q.position.y)] for q in msg.poses]
            except (AttributeError, TypeError, ValueError) as exc:
                raise RecordingError(f"cannot read leg labels: {exc}", path=path) from exc
            out.append(np.array(xy, dtype=np.float64).reshape(-1, 2))
        return out
    finally:
        reader.close()


def all_negative(
    path: str | Path,
    topics: Sequence[str] | None = None,
    segmentation: JumpDistanceParams = DEFAULT_JUMP_DISTANCE_PARAMS,
    on_error: OnError = "stop",
    damage: list[str] | None = None,
) -> LabelledSegments:
    """Every segment of every (or the given) laser topic of a recording is a non-leg
    (``on_error``, ``damage``: as for :func:`leg_tracker_positive`)."""
    from laserpeople.io import open_recording

    p = Path(path)
    rec = open_recording(p, on_error=on_error)
    try:
        return label_scans(
            rec.scans(topics),
            lambda scan, table, f: np.full(len(table), -1, dtype=np.int64),
            lambda s: f"{p.name}:{s.sensor}",
            segmentation,
        )
    finally:
        _note_damage(rec, damage)
        rec.close()


def _note_damage(recording: object, damage: list[str] | None) -> None:
    """Append the reader's summary of the damaged scans it skipped to ``damage``."""
    damaged = getattr(recording, "damaged", None)
    text = damaged.summary() if damaged is not None else ""
    if text and damage is not None:
        damage.append(text)


def neko_frames(directory: str | Path, count: int, frames: Iterable[int] | None) -> set[int]:
    """The neko7055 frames asked for (all ``count`` when None), checked to be in the data.

    Raises:
        ConfigError: a frame is not in the data (``--neko-frames 200-300`` of 120 frames);
            names the directory and its frames.
    """
    if frames is None:
        return set(range(count))
    wanted = set(frames)
    outside = sorted(f for f in wanted if not 0 <= f < count)
    if outside:
        raise ConfigError(
            f"frame(s) {', '.join(map(str, outside[:3]))}{' ...' if len(outside) > 3 else ''} "
            f"not in the data: it has frames 0-{count - 1}",
            path=directory,
            hint="check --neko-frames / --test-neko-frames",
        )
    return wanted


def neko_segments(directory: str | Path, frames: Iterable[int] | None = None) -> LabelledSegments:
    """Labelled segments of the neko7055 data (all frames, or the given ones)."""
    from laserpeople.io.neko import NEKO_SEGMENT_THRESHOLD, neko_segment_labels, read_neko

    data = read_neko(directory)
    wanted = neko_frames(directory, len(data.scans), frames)

    def labeller(scan: Scan, table: SegmentTable, f: SegmentFeatures) -> IntArray:
        if scan.index not in wanted:
            return np.zeros(len(table), dtype=np.int64)
        legs = neko_segment_labels(data.leg_segments.get(scan.index, frozenset()), len(table))
        return np.where(legs, 1, -1).astype(np.int64)

    return label_scans(
        data.scans,
        labeller,
        lambda s: "neko7055",
        JumpDistanceParams(threshold=NEKO_SEGMENT_THRESHOLD, wrap_around=True),
    )


def beam_truth_labeller(scan: Scan, table: SegmentTable, f: SegmentFeatures) -> IntArray:
    """+1 for segments most of whose beams hit a leg (needs ``scan.labels``)."""
    if scan.labels is None:
        raise RecordingError(
            "scan has no per-beam ground truth",
            path=scan.source or None,
            scan=scan.index,
            hint="train from a simulated .npz or use --positives/--negatives bags",
        )
    is_leg = scan.labels.is_leg[table.beams % table.n_beams].astype(np.float64)
    frac = np.add.reduceat(is_leg, table.offsets[:-1]) / np.maximum(table.sizes, 1)
    return np.where(frac > 0.5, 1, -1).astype(np.int64)


def truth_segments(
    scans: Iterable[Scan],
    name: str,
    segmentation: JumpDistanceParams = DEFAULT_JUMP_DISTANCE_PARAMS,
) -> LabelledSegments:
    """Labelled segments of scans carrying per-beam ground truth (simulator, ``.npz``)."""
    return label_scans(scans, beam_truth_labeller, lambda s: f"{name}:{s.sensor}", segmentation)


# --------------------------------------------------------------------------- beam classes
# Scans with the class of every beam (+1 leg, -1 not a leg, 0 unknown), the form in which
# labelled scans can be resampled to other scanners (laserpeople.detection.augment).

ClassedScan = tuple[Scan, IntArray]


def classed_segments(
    pairs: Iterable[ClassedScan],
    name: str,
    segmentation: JumpDistanceParams = DEFAULT_JUMP_DISTANCE_PARAMS,
) -> LabelledSegments:
    """Labelled segments of time-ordered scans whose beams carry classes.

    A segment is labelled from its beams by
    :func:`~laserpeople.detection.augment.segment_labels_from_beams`; groups are
    ``name:sensor``.
    """
    current: dict[tuple[str, int], IntArray] = {}

    def scans() -> Iterable[Scan]:
        for scan, classes in pairs:
            current.clear()
            current[(scan.sensor, scan.index)] = classes
            yield scan

    def labeller(scan: Scan, table: SegmentTable, f: SegmentFeatures) -> IntArray:
        return segment_labels_from_beams(table, current[(scan.sensor, scan.index)])

    return label_scans(scans(), labeller, lambda s: f"{name}:{s.sensor}", segmentation)


def leg_tracker_positive_classes(
    path: str | Path,
    *,
    match_radius: float = 0.1,
    ambiguous_radius: float = 0.5,
    unlabelled: Unlabelled = "drop",
    segmentation: JumpDistanceParams = LEG_TRACKER_SEGMENTATION,
    scan_topic: str = "/training_scan",
    label_topic: str = "/leg_cluster_positions",
) -> list[ClassedScan]:
    """The scans of a leg_tracker ``positive_*_extracted.bag`` with beam classes: beams of
    segments within ``match_radius`` of a label are legs; the others are unknown, or (with
    ``unlabelled="negative"``) not legs when farther than ``ambiguous_radius`` from every
    label (as :func:`leg_tracker_positive`)."""
    from laserpeople.io import open_recording

    p = Path(path)
    poses = read_pose_arrays(p, label_topic)
    rec = open_recording(p)
    try:
        scans = list(rec.scans([scan_topic]))
    finally:
        rec.close()
    if len(scans) != len(poses):
        raise RecordingError(
            f"{len(scans)} scans on {scan_topic} but {len(poses)} label messages on "
            f"{label_topic}; they must pair one to one",
            path=p,
        )
    order = sorted(range(len(scans)), key=lambda i: scans[i].index)
    segmenter = JumpDistanceSegmenter(segmentation)
    out: list[ClassedScan] = []
    for rank, i in enumerate(order):
        scan = scans[i]
        table = segmenter(scan)
        labels = match_labels(
            table.centres(), poses[rank], match_radius, ambiguous_radius, unlabelled
        )
        out.append((scan, beam_classes(table, labels)))
    return out


def all_negative_classes(
    path: str | Path, topics: Sequence[str] | None = None
) -> list[ClassedScan]:
    """The scans of a recording without people; every beam with a return is not a leg."""
    from laserpeople.io import open_recording

    rec = open_recording(Path(path))
    try:
        return [(scan, np.where(scan.valid, -1, 0).astype(np.int64)) for scan in rec.scans(topics)]
    finally:
        rec.close()


def truth_classes(scans: Iterable[Scan]) -> list[ClassedScan]:
    """Scans with per-beam ground truth (simulator, ``.npz``) with beam classes: a beam that
    hit a leg is a leg, any other return is not, no return is unknown."""
    out: list[ClassedScan] = []
    for scan in scans:
        if scan.labels is None:
            raise RecordingError(
                "scan has no per-beam ground truth",
                path=scan.source or None,
                scan=scan.index,
                hint="train from a simulated .npz or use --positives/--negatives bags",
            )
        leg = scan.labels.is_leg
        out.append((scan, np.where(scan.valid, np.where(leg, 1, -1), 0).astype(np.int64)))
    return out


def neko_classes(directory: str | Path, frames: Iterable[int] | None = None) -> list[ClassedScan]:
    """The neko7055 scans with beam classes from the per-segment labels (frames not asked
    for are all unknown)."""
    from laserpeople.io.neko import NEKO_SEGMENT_THRESHOLD, neko_segment_labels, read_neko

    data = read_neko(directory)
    wanted = neko_frames(directory, len(data.scans), frames)
    segmenter = JumpDistanceSegmenter(
        JumpDistanceParams(threshold=NEKO_SEGMENT_THRESHOLD, wrap_around=True)
    )
    out: list[ClassedScan] = []
    for scan in data.scans:
        if scan.index not in wanted:
            out.append((scan, np.zeros(scan.n_beams, dtype=np.int64)))
            continue
        table = segmenter(scan)
        legs = neko_segment_labels(data.leg_segments.get(scan.index, frozenset()), len(table))
        out.append((scan, beam_classes(table, np.where(legs, 1, -1))))
    return out


def augmented_segments(
    pairs: Sequence[ClassedScan],
    name: str,
    variants: Sequence[Variant],
    segmentation: JumpDistanceParams = DEFAULT_JUMP_DISTANCE_PARAMS,
) -> LabelledSegments:
    """Labelled segments of ``pairs`` as each of ``variants`` sees them; groups are
    ``name@variant:sensor``, so a recording and its variants can be kept together."""
    return LabelledSegments.concat(
        [
            classed_segments(resampled_stream(pairs, v), f"{name}@{v.name}", segmentation)
            for v in variants
        ]
    )


def augmented_input(
    kind: InputKind,
    path: str | Path,
    segmentation: JumpDistanceParams,
    unlabelled: Unlabelled = "drop",
    frames: Iterable[int] | None = None,
    variants: Sequence[Variant] | None = None,
) -> LabelledSegments:
    """One labelled input of ``laserpeople train`` in every variant (default
    :data:`~laserpeople.detection.augment.TRANSFER_VARIANTS`).

    ``kind``: a recording with per-beam truth, a leg_tracker positive bag, a recording
    without people, or the neko7055 directory (its own 0.1 m label rule, ``frames``).
    """
    from laserpeople.io import open_recording

    grid = TRANSFER_VARIANTS if variants is None else variants
    p = Path(path)
    if kind == "neko":
        from laserpeople.io.neko import NEKO_SEGMENT_THRESHOLD

        neko_seg = JumpDistanceParams(threshold=NEKO_SEGMENT_THRESHOLD, wrap_around=True)
        return augmented_segments(neko_classes(p, frames), p.name, grid, neko_seg)
    if kind == "positive":
        pairs = leg_tracker_positive_classes(p, unlabelled=unlabelled, segmentation=segmentation)
        return augmented_segments(pairs, p.name, grid, segmentation)
    if kind == "negative":
        return augmented_segments(all_negative_classes(p), p.name, grid, segmentation)
    rec = open_recording(p)
    try:
        pairs = truth_classes(rec.scans())
    finally:
        rec.close()
    return augmented_segments(pairs, p.name, grid, segmentation)
