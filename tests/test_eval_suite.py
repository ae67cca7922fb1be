"""The people suite's scoring (static-object track time, family means) and the leg pairing
of benchmarks/peers.py."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from laserpeople.evaluation.suite import (
    SceneScore,
    StaticTracks,
    SuiteScene,
    prepare,
    static_track_seconds,
    summarise,
    track_scene,
)
from laserpeople.scan import Pose2D, Scan
from laserpeople.tracks import Track, Tracks
from laserpeople.truth import BeamLabels, TruthFrame

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


def _scan(k: int, person: list[int]) -> Scan:
    """Four beams at 0, 30, 60, 90 deg from a sensor at (1, 0) facing +x, all 2 m long;
    ``person`` labels each beam (-1: a static object)."""
    inc = math.radians(30.0)
    lab = np.array(person, dtype=np.int32)
    none = np.full(4, -1, dtype=np.int32)
    return Scan(
        float(k),
        0.0,
        inc,
        np.full(4, 2.0),
        pose=Pose2D(1.0, 0.0, 0.0),
        index=k,
        labels=BeamLabels(lab, np.where(lab >= 0, 0, -1).astype(np.int32), none, none.copy()),
    )


def _tracks(k: int, rows: list[tuple[int, float, float]]) -> Tracks:
    return Tracks(
        float(k),
        k,
        tuple(Track(t, "person", np.array([x, y]), np.zeros(2), np.eye(2)) for t, x, y in rows),
    )


def test_static_track_seconds_by_hand() -> None:
    """World points of the beams: (3, 0), (1 + 2 cos 30, 1), (2, 1.732), (1, 2).
    Scan 0: beams 0-1 static, 2-3 person 7 (truth at (1.5, 1.9)). Track 1 at (3.1, 0) is
    0.1 m from a static return and 2 m from the person: on a static object. Track 2 at
    (2, 1.8) is near person 7's returns only (1.08 m from the nearest static one). Track 3 at
    (2.8, 0.9) is 0.12 m from the static return (2.73, 1) and 1.64 m from the person: static.
    Scan 1: the person stands at (3, 0.3) beside static beam 0: track 1 at (3.1, 0) is within
    0.75 m of the person, so it does not count."""
    scans = [_scan(0, [-1, -1, 7, 7]), _scan(1, [-1, -1, 7, 7])]
    truth = [
        TruthFrame.from_positions(0.0, 0, np.array([7]), np.array([[1.5, 1.9]])),
        TruthFrame.from_positions(1.0, 1, np.array([7]), np.array([[3.0, 0.3]])),
    ]
    tracks = [
        _tracks(0, [(1, 3.1, 0.0), (2, 2.0, 1.8), (3, 2.8, 0.9)]),
        _tracks(1, [(1, 3.1, 0.0)]),
    ]
    got = static_track_seconds(scans, tracks, truth, 0.1)
    assert got == StaticTracks(seconds=pytest.approx(0.2), track_scans=2, ids=2)
    # with nobody in the truth, scan 1's track counts too
    empty = [TruthFrame.from_positions(float(k), k, np.array([]), np.empty((0, 2))) for k in (0, 1)]
    got = static_track_seconds(scans, tracks, empty, 0.1)
    assert got.track_scans == 3 and got.ids == 2


def _score(family: str, mota: float, static: float, cpu: float, scans: int) -> SceneScore:
    return SceneScore(
        SuiteScene(family, family, 0),
        "t",
        mota,
        mota,
        0.1,
        0.5,
        0.5,
        2,
        3,
        4,
        StaticTracks(static, 0, 0),
        cpu,
        scans,
        scans * 0.1,
    )


def test_summarise_means_per_family() -> None:
    rows = summarise(
        [
            _score("a", 0.5, 1.0, 2.0, 100),
            _score("a", 0.7, 3.0, 4.0, 300),
            _score("b", math.nan, 6.0, 1.0, 600),
        ]
    )
    a, b = rows
    assert (a.family, a.scenes) == ("a", 2)
    assert a.mota == pytest.approx(0.6) and a.static_seconds == pytest.approx(2.0)
    assert a.cpu_ms == pytest.approx((2.0 * 100 + 4.0 * 300) / 400)  # per scan, not per scene
    assert a.static_per_minute == pytest.approx(60 * 4.0 / 40.0)
    assert math.isnan(b.mota) and b.static_per_minute == pytest.approx(60 * 6.0 / 60.0)


def test_suite_runs_a_tracker_on_a_furniture_scene() -> None:
    from laserpeople.detection.detector import AdaBoostLegDetector
    from laserpeople.tracking import registry

    entry = registry.get("nn")
    prepared = prepare(
        SuiteScene("furniture-only", "randomised-furniture", 3, 3.0), AdaBoostLegDetector.default()
    )
    score, outs = track_scene(prepared, lambda: entry.factory(entry.params_cls()), "nn")
    assert score.scans == len(prepared.scans) == len(outs)
    assert math.isnan(score.mota)  # nobody to score
    persons = sum(len(o.of_kind("person")) for o in outs)
    assert score.false_positives == persons
    assert score.static.track_scans <= persons
    assert score.cpu_ms >= 0.0


def test_pair_legs_closest_pairs_first() -> None:
    sys.path.insert(0, str(BENCH))
    try:
        from peers import pair_legs
    finally:
        sys.path.remove(str(BENCH))
    legs = np.array([[0.0, 0.0], [0.3, 0.0], [0.5, 0.0], [5.0, 5.0], [5.7, 5.0], [9.0, 9.0]])
    # (1, 2) are closest (0.2 m) and pair first; 0 is left alone; (3, 4) at 0.7 m pair; 5 alone
    np.testing.assert_allclose(pair_legs(legs), [[0.4, 0.0], [5.35, 5.0]])
    assert pair_legs(legs[:1]).shape == (0, 2)
    assert pair_legs(np.array([[0.0, 0.0], [0.8, 0.0]])).shape == (0, 2)


def test_peers_without_stone_soup_says_how_to_install_before_tracking(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Without the `peers` extra, benchmarks/peers.py stops at once naming the extra (exit
    2), instead of tracking a scene with our tracker and then failing in a traceback."""
    sys.path.insert(0, str(BENCH))
    try:
        import peers
    finally:
        sys.path.remove(str(BENCH))

    def no_run(*args: object) -> None:
        raise AssertionError("scenes were tracked before the missing extra was found")

    monkeypatch.setitem(sys.modules, "stonesoup", None)  # an import of it fails
    monkeypatch.setattr(peers, "run", no_run)
    monkeypatch.setattr(sys, "argv", ["peers.py", "--peer", "gnn", "--family", "crossing-3"])
    with pytest.raises(SystemExit) as stop:
        peers.main()
    assert stop.value.code == 2
    assert "pip install 'laserpeople[peers]'" in capsys.readouterr().err


class _FrameEcho:
    """A frame tracker that reports a person at every leg of the frame."""

    def __init__(self, consumes: frozenset[str]) -> None:
        self.consumes = consumes
        self.frames: list = []

    def update(self, frame) -> Tracks:  # type: ignore[no-untyped-def]
        self.frames.append(frame)
        legs = frame.legs
        rows = [(k, float(x), float(y)) for k, (x, y) in enumerate(legs.positions)]
        t = _tracks(frame.index, rows)
        return Tracks(t.stamp, t.scan_index, t.tracks, frame.frame, frame.sensor_pose)


def test_frame_trackers_get_frames_with_world_legs() -> None:
    from laserpeople.detection.detector import AdaBoostLegDetector

    prepared = prepare(
        SuiteScene("randomised", "randomised", 2, 1.0), AdaBoostLegDetector.default()
    )
    echo = _FrameEcho(frozenset({"scans", "legs"}))
    score, outs = track_scene(prepared, lambda: echo, "echo")
    assert [f.index for f in echo.frames] == [s.index for s in prepared.scans]
    first = echo.frames[0]
    assert first.frame == "world" and first.scans == (prepared.scans[0],)
    np.testing.assert_allclose(first.legs.positions, prepared.detections[0].to_world().positions)
    assert score.scans == len(outs)
    with pytest.raises(ValueError, match="points"):
        track_scene(prepared, lambda: _FrameEcho(frozenset({"points", "legs"})), "x")


def test_gnn_diagnose_splits_misses_and_false_positives_by_time() -> None:
    sys.path.insert(0, str(BENCH))
    try:
        from gnn_diagnose import split
    finally:
        sys.path.remove(str(BENCH))
    # person 1 over 7 scans: matched to track 7 on scans 2 and 3, to track 8 on scan 5 (one
    # switch); track 8 is born on scan 4; track 9 is reported on every scan, never matched
    matched = [
        ({}, [9]),
        ({}, [9]),
        ({1: 7}, [7, 9]),
        ({1: 7}, [7, 9]),
        ({}, [7, 8, 9]),
        ({1: 8}, [8, 9]),
        ({}, [8, 9]),
    ]
    # scans 0-1 approaching, unseen, in view; scan 6 passing and out of view, seen by one leg
    classes = [
        {1: ("approaching", False, False, True)},
        {1: ("approaching", False, False, True)},
        {1: ("approaching", True, True, True)},
        {1: ("approaching", True, True, True)},
        {1: ("passing", False, False, True)},
        {1: ("passing", True, False, True)},
        {1: ("passing", True, False, False)},
    ]
    c = split(matched, classes)
    assert c["match"] == 3  # scans 2, 3, 5
    assert (c["miss before"], c["miss gap"], c["miss after"], c["miss never"]) == (2, 1, 1, 0)
    assert c["miss after, out of view"] == 1 and c["miss before, out of view"] == 0
    assert (c["miss approaching"], c["miss passing"]) == (2, 2)
    assert (c["miss unseen"], c["miss seen, no pair"], c["miss pair"]) == (3, 1, 0)
    # track 9: 7 frames never matched; track 7 unmatched on scan 4 and track 8 on scan 6
    # (after their matches); track 8 on scan 4 (before its match)
    assert c["fp never matched"] == 7
    assert c["fp after match"] == 2 and c["fp before match"] == 1
    assert c["id switches"] == 1


def test_gnn_diagnose_counts_a_switch_back_to_an_earlier_track() -> None:
    """CLEAR MOT counts a switch against the track last matched: person 1 matched to
    tracks 7, 8, 8, 8, 7 (switches at the second and the last scan: 2; counted against
    the first track there would be 3); person 2 matched to track 5, missed, matched to 5
    again (no switch)."""
    sys.path.insert(0, str(BENCH))
    try:
        from gnn_diagnose import split
    finally:
        sys.path.remove(str(BENCH))
    matched = [
        ({1: 7, 2: 5}, [5, 7]),
        ({1: 8}, [8]),
        ({1: 8, 2: 5}, [5, 8]),
        ({1: 8, 2: 5}, [5, 8]),
        ({1: 7, 2: 5}, [5, 7]),
    ]
    seen = ("passing", True, True, True)
    c = split(matched, [{1: seen, 2: seen}] * 5)
    assert c["id switches"] == 2
    assert c["match"] == 9 and c["miss gap"] == 1
