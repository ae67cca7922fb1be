"""Leg detection of a block of frames at once (``Pipeline(lookahead=...)``, the
detector's ``detect_many``) gives what detection scan by scan gives, and an error of the
source still comes after the frames read before it."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pytest

from laserpeople.detection.detector import AdaBoostLegDetector
from laserpeople.frame import Frame
from laserpeople.pipeline import DetectLegs, FrameChooser, Pipeline, laser_frames
from laserpeople.pipeline.recording import tracker_stages
from laserpeople.scan import Scan
from laserpeople.sim import run_scenario
from laserpeople.tracking import registry


@pytest.fixture(scope="module")
def scans() -> list[Scan]:
    every = run_scenario("crossing-3", seconds=4.0, seed=1).scans
    return [s for s in every if s.sensor == every[0].sensor]  # one laser


def _same(a: object, b: object) -> None:
    """Two Detections: the same legs, positions within 1e-12 m, scores within 1e-12."""
    assert len(a) == len(b)  # type: ignore[arg-type]
    np.testing.assert_allclose(a.positions, b.positions, rtol=0, atol=1e-12)  # type: ignore[attr-defined]
    np.testing.assert_allclose(a.scores, b.scores, rtol=0, atol=1e-12)  # type: ignore[attr-defined]
    for s, t in zip(a.segments, b.segments, strict=True):  # type: ignore[attr-defined]
        assert (s.start, s.stop) == (t.start, t.stop)
        assert np.array_equal(s.beams, t.beams)


def test_detect_many_gives_the_detections_of_one_scan_at_a_time(scans: list[Scan]) -> None:
    one, many = AdaBoostLegDetector.default(), AdaBoostLegDetector.default()
    singly = [one.detect(s) for s in scans]
    blocks = [many.detect_many(scans[i : i + 7]) for i in range(0, len(scans), 7)]
    together = [d for block in blocks for d in block]
    assert sum(len(d) for d in singly) > 20
    for a, b in zip(singly, together, strict=True):
        _same(a, b)
    # classify_many: every segment's features and score, not only the legs
    one.reset()
    many.reset()
    got = many.classify_many(scans[:10])
    for scan, c in zip(scans[:10], got, strict=True):
        want = one.classify(scan)
        np.testing.assert_allclose(c.features.values, want.features.values, rtol=1e-12)
        np.testing.assert_allclose(c.scores, want.scores, rtol=0, atol=1e-12)
        assert np.array_equal(c.is_leg, want.is_leg)


def _tracks(scans: list[Scan], lookahead: int) -> tuple[list[list[tuple]], int]:
    tracker = registry.get("leg-mht").make()
    pre, obs, hide = tracker_stages(
        tracker, detector=AdaBoostLegDetector.default(), background="auto"
    )
    pipe = Pipeline(
        FrameChooser()(laser_frames(scans)),
        preprocess=pre,
        observe=obs,
        tracker=tracker,
        identify=[hide] if hide is not None else [],
        lookahead=lookahead,
    )
    out = []
    legs = 0
    for step in pipe:
        assert step.frame.legs is not None
        legs += len(step.frame.legs)
        out.append(
            [(t.track_id, t.kind, *np.round(t.position, 9).tolist()) for t in step.tracks.tracks]
        )
    return out, legs


def test_a_pipeline_reading_ahead_tracks_the_same(scans: list[Scan]) -> None:
    ahead, legs_ahead = _tracks(scans, 16)
    singly, legs = _tracks(scans, 1)
    assert legs_ahead == legs > 20
    assert ahead == singly
    assert sum(len(rows) for rows in ahead) > 50


class _Counting:
    """A detector that counts how its scans were asked for."""

    def __init__(self) -> None:
        self.inner = AdaBoostLegDetector.default()
        self.single = 0
        self.blocks: list[int] = []

    def detect(self, scan: Scan) -> object:
        self.single += 1
        return self.inner.detect(scan)

    def detect_many(self, scans: list[Scan]) -> list[object]:
        self.blocks.append(len(scans))
        return list(self.inner.detect_many(scans))


def test_blocks_go_to_detection_and_an_error_of_the_source_comes_after_its_frames(
    scans: list[Scan],
) -> None:
    def source() -> Iterator[Frame]:
        for k, frame in enumerate(laser_frames(scans[:20])):
            if k == 13:
                raise RuntimeError("damaged frame 13")
            yield frame

    detector = _Counting()
    pipe = Pipeline(source(), observe=[DetectLegs(detector)], lookahead=8)
    seen = []
    with pytest.raises(RuntimeError, match="damaged frame 13"):
        for step in pipe:
            seen.append(step.frame.index)
    assert seen == list(range(13))  # every frame before the error went through
    assert detector.blocks == [8, 5] and detector.single == 0
    assert pipe.stats.stage_cpu[0] > 0.0  # the blocks' CPU is the stage's


def test_no_reading_ahead_past_a_stage_that_provides_scans(scans: list[Scan]) -> None:
    class Replaces:
        consumes = frozenset({"scans"})
        provides = frozenset({"scans"})

        def __call__(self, frame: Frame) -> Frame:
            return frame

    detector = _Counting()
    frames = list(laser_frames(scans[:6]))
    pipe = Pipeline(iter(frames), preprocess=[Replaces()], observe=[DetectLegs(detector)],
                    lookahead=4)  # fmt: skip
    assert len(list(pipe)) == 6
    assert detector.blocks == [] and detector.single == 6


def test_a_failing_block_leaves_detection_to_each_frame(scans: list[Scan]) -> None:
    """When detecting a block fails, each frame is detected on its own (where a scan's
    own error would be raised at its frame), with the previous scans as before."""

    class Failing(_Counting):
        def detect_many(self, scans: list[Scan]) -> list[object]:
            self.blocks.append(len(scans))
            raise ValueError("no block today")

    detector = Failing()
    pipe = Pipeline(iter(list(laser_frames(scans[:10]))), observe=[DetectLegs(detector)],
                    lookahead=4)  # fmt: skip
    got = [step.frame.legs for step in pipe]
    assert detector.blocks == [4, 4, 2] and detector.single == 10
    reference = AdaBoostLegDetector.default()
    for scan, legs in zip(scans[:10], got, strict=True):
        _same(legs, reference.detect(scan))


def test_stump_groups_are_added_in_order_for_one_row_as_for_many() -> None:
    """A row's score does not depend on the rows scored with it: the groups' sums are added
    in group order for a single row too. 16 groups whose sums for x = 1 are 2^53, seven 1s,
    -2^53, seven 1s: in order, 2^53 + 1 rounds back to 2^53 (ties to even) seven times, then
    -2^53 leaves 0, then + 7 = 7. numpy's pairwise sum of 16 values (8 partial sums a_j +
    a_(j+8)) would give 0 + 7 * 2 = 14."""
    from laserpeople.detection.adaboost import _StumpTables

    sums = np.array([2.0**53] + [1.0] * 7 + [-(2.0**53)] + [1.0] * 7)
    tables = _StumpTables(
        columns=np.array([0]),
        group_column=np.zeros(16, dtype=np.int64),
        right=np.ones(16, dtype=bool),
        grid=np.array([0.0]),
        values=np.column_stack([np.zeros(16), sums]),  # rank 0 (x < 0): 0; rank 1: sums
    )
    tol = 0.5  # the two orders differ by 7
    np.testing.assert_allclose(tables.evaluate(np.array([[1.0]])), [7.0], rtol=0, atol=tol)
    np.testing.assert_allclose(
        tables.evaluate(np.array([[1.0], [-1.0], [1.0]])), [7.0, 0.0, 7.0], rtol=0, atol=tol
    )
