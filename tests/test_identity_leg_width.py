"""Re-identification by leg widths after the trackers of points (identity/leg_width.py)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from laserpeople.config import ConfigError, load_config
from laserpeople.frame import Frame
from laserpeople.identity.leg_width import (
    FRESH_IDS,
    LegReidParams,
    LegWidthReidentifier,
    occluded,
)
from laserpeople.pipeline.background import StaticWorldParams, load_static_world
from laserpeople.pipeline.core import Pipeline
from laserpeople.pipeline.recording import leg_reid_stage, tracker_stages
from laserpeople.scan import Scan
from laserpeople.segmentation import SegmentTable
from laserpeople.tracking import registry
from laserpeople.tracking.reidentify import (
    Candidate,
    DormantIdentity,
    Reidentifier,
    ReidentifyParams,
    Signature,
)
from laserpeople.tracks import Track, Tracks

INC = math.radians(0.5)
ANGLE_MIN = -math.radians(60.0)
N_BEAMS = 241


def cast(legs: list[tuple[float, float, float]]) -> np.ndarray:
    """Ranges (N_BEAMS,) [m] of a laser at the origin seeing circles ``(x, y, radius)``
    (inf where a beam hits nothing)."""
    ranges = np.full(N_BEAMS, np.inf)
    angles = ANGLE_MIN + INC * np.arange(N_BEAMS)
    d = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    for x, y, r in legs:
        b = d @ np.array([x, y])
        disc = b * b - (x * x + y * y - r * r)
        hit = disc >= 0
        t = np.where(hit, b - np.sqrt(np.where(hit, disc, 0.0)), np.inf)
        ranges = np.minimum(ranges, np.where(t > 0, t, np.inf))
    return ranges


def frame_of(index: int, legs: list[tuple[float, float, float]]) -> Frame:
    stamp = 0.1 * index
    scan = Scan(stamp, ANGLE_MIN, INC, cast(legs), 0.05, 30.0, index=index)
    return Frame(index, stamp, (scan,), "scan")


def person(tid: int, x: float, y: float) -> Track:
    return Track(tid, "person", np.array([x, y]), np.zeros(2), np.eye(2) * 0.01)


def tracks_of(index: int, *ts: Track) -> Tracks:
    return Tracks(0.1 * index, index, ts)


def two_legs(x: float, y: float, radius: float) -> list[tuple[float, float, float]]:
    """Two legs side by side across the beams (0.3 m apart)."""
    return [(x, y - 0.15, radius), (x, y + 0.15, radius)]


# --------------------------------------------------------------------- widths


def test_width_of_a_leg_is_the_chord_plus_one_beam_step() -> None:
    # a leg of radius 0.08 m at 2 m: hand-computed from the beams that hit it
    stage = LegWidthReidentifier()
    frame = frame_of(0, [(2.0, 0.0, 0.08)])
    out = stage.widths((person(7, 2.0, 0.0),), frame)
    assert len(out) == 1
    tid, width = out[0]
    assert tid == 7
    r = frame.scans[0].ranges
    hit = np.flatnonzero(np.isfinite(r))
    a0, a1 = ANGLE_MIN + INC * hit[0], ANGLE_MIN + INC * hit[-1]
    p0 = r[hit[0]] * np.array([math.cos(a0), math.sin(a0)])
    p1 = r[hit[-1]] * np.array([math.cos(a1), math.sin(a1)])
    chord = float(np.hypot(*(p1 - p0)))
    step = 0.5 * (r[hit[0]] + r[hit[-1]]) * (a1 - a0) / (len(hit) - 1)
    assert width == pytest.approx(chord + step, abs=1e-9)
    assert 0.14 < width < 0.19  # about the 0.16 m diameter


def test_segments_shared_far_or_out_of_range_give_no_width() -> None:
    stage = LegWidthReidentifier()
    leg = [(2.0, 0.0, 0.08)]
    # a second person within leg_distance of the leg: whose it is, is unknown
    assert stage.widths((person(1, 2.0, 0.2), person(2, 2.0, -0.2)), frame_of(0, leg)) == []
    # the track 0.6 m away (> leg_distance 0.5 m)
    assert stage.widths((person(1, 2.0, 0.6),), frame_of(0, leg)) == []
    # too narrow (0.04 m < min_width 0.1 m) and too wide (0.5 m > max_width 0.25 m)
    assert stage.widths((person(1, 2.0, 0.0),), frame_of(0, [(2.0, 0.0, 0.02)])) == []
    assert stage.widths((person(1, 2.0, 0.0),), frame_of(0, [(2.0, 0.0, 0.25)])) == []


def test_a_leg_cut_by_one_in_front_is_occluded() -> None:
    # beams 0-3 at 2 m, beams 4-6 at 1 m (in front), beams 7-9 at 2 m
    beams = np.arange(10)
    rng = np.array([2.0] * 4 + [1.0] * 3 + [2.0] * 3)
    pts = np.stack([rng * np.cos(0.01 * beams), rng * np.sin(0.01 * beams)], axis=1)
    table = SegmentTable(beams, pts, np.array([0, 4, 7, 10]), 10)
    assert occluded(table).tolist() == [True, False, True]
    # a gap of one invalid beam between them: nothing says the leg goes on
    table = SegmentTable(np.array([0, 1, 2, 4, 5]), pts[[0, 1, 2, 4, 5]], np.array([0, 3, 5]), 10)
    assert occluded(table).tolist() == [False, False]


# ------------------------------------------------------------ the shared model


def test_ready_and_give_back_follow_the_rules() -> None:
    r = Reidentifier(ReidentifyParams(min_samples=3, decide_time=5.0))
    sig = Signature()
    for w in (0.15, 0.16):
        sig.add(w)
    assert not r.ready(sig, since=10.0, stamp=14.9)
    assert r.ready(sig, since=10.0, stamp=15.0)  # decide_time reached
    sig.add(0.155)
    assert r.ready(sig, since=10.0, stamp=10.1)  # min_samples reached
    old = Signature()
    for w in (0.15, 0.16) * 25:
        old.add(w)
        sig.add(w)
    # 53 widths each, means 0.1550 and 0.1550: llr = 0.5 log(v_diff / v_same) ~ 0.94 with
    # v_same ~ 2 * 0.02^2 / 50 + 2 * 0.008^2: posterior e^0.94 / (1 + e^0.94) ~ 0.72
    r.remember(DormantIdentity(4, np.zeros(2), 1.0, old, seen_for=60.0))
    given = r.give_back([Candidate(9, np.zeros(2), 12.0, sig, born=11.0)])
    assert list(given) == [9] and given[9].identity == 4 and given[9].seen_for == 60.0
    assert r.dormant == {}


# --------------------------------------------------------------------- the stage


def run_stage(
    stage: LegWidthReidentifier, first: int, last: int, tid: int, radius: float, x: float
) -> list[int]:
    """Frames ``first``..``last`` - 1 of one person ``tid`` with legs of ``radius`` at
    (x, 0); the output person ids."""
    out = []
    for i in range(first, last):
        tr = stage.update(tracks_of(i, person(tid, x, 0.0)), frame_of(i, two_legs(x, 0.0, radius)))
        out += [t.track_id for t in tr.of_kind("person")]
    return out


def test_returning_person_gets_old_id_a_stranger_does_not() -> None:
    stage = LegWidthReidentifier()
    # 30 s (familiar_time: no lower prior), two widths a scan
    assert run_stage(stage, 0, 300, 3, 0.08, 2.0) == [3] * 300
    # gone for 3 s (> lost_after 1 s): dormant
    stage.update(tracks_of(330), frame_of(330, []))
    assert list(stage.reid.dormant) == [3]
    # a stranger with wider legs (0.22 m against 0.16 m) for 40 s: keeps its id
    assert set(run_stage(stage, 331, 731, 8, 0.11, 2.0)) == {8}
    assert list(stage.reid.dormant) == [3]
    # the person comes back as id 9 while the stranger is still about: reported as 9
    # until 100 widths (50 scans), then as 3
    both = []
    for i in range(731, 800):
        tr = tracks_of(i, person(9, 2.0, 0.0), person(8, 5.0, 2.0))
        legs = [*two_legs(2.0, 0.0, 0.08), *two_legs(5.0, 2.0, 0.11)]
        both.append({t.track_id: t.track_id for t in stage.update(tr, frame_of(i, legs))})
    ids = [next(iter(k for k in b if k != 8)) for b in both]
    assert ids[0] == 9
    switch = ids.index(3)
    assert switch == 49 and set(ids[switch:]) == {3}  # 2 widths a scan: 100 after 50
    assert all(8 in b for b in both)
    assert stage.reid.reidentified == 1


def test_an_id_back_while_dormant_takes_its_identity_back() -> None:
    stage = LegWidthReidentifier()
    run_stage(stage, 0, 300, 3, 0.08, 2.0)
    stage.update(tracks_of(320), frame_of(320, []))
    assert 3 in stage.reid.dormant
    assert set(run_stage(stage, 321, 330, 3, 0.08, 2.0)) == {3}
    assert stage.reid.dormant == {}


def test_an_id_back_after_its_identity_was_given_gets_a_fresh_one() -> None:
    stage = LegWidthReidentifier()
    run_stage(stage, 0, 300, 3, 0.08, 2.0)
    stage.update(tracks_of(320), frame_of(320, []))
    assert set(run_stage(stage, 321, 440, 9, 0.08, 2.0)[60:]) == {3}
    # the tracker's id 3 comes back beside the person who took its identity
    frame = frame_of(440, [*two_legs(2.0, 0.0, 0.08), *two_legs(4.0, 2.0, 0.08)])
    out = stage.update(tracks_of(440, person(9, 2.0, 0.0), person(3, 4.0, 2.0)), frame)
    assert [t.track_id for t in out] == [3, FRESH_IDS]


def test_group_members_are_rewritten() -> None:
    stage = LegWidthReidentifier()
    run_stage(stage, 0, 300, 3, 0.08, 2.0)
    stage.update(tracks_of(320), frame_of(320, []))
    run_stage(stage, 321, 440, 9, 0.08, 2.0)
    group = Track(50, "group", np.array([2.0, 0.0]), np.zeros(2), np.eye(2), 2, members=(9, 12))
    out = stage.update(
        tracks_of(440, person(9, 2.0, 0.0), group), frame_of(440, two_legs(2.0, 0.0, 0.08))
    )
    assert [t.track_id for t in out] == [3, 50]
    assert out.tracks[1].members == (3, 12)


def test_disabled_rules_change_nothing() -> None:
    stage = LegWidthReidentifier(replace(LegReidParams(), rules=ReidentifyParams(enabled=False)))
    run_stage(stage, 0, 300, 3, 0.08, 2.0)
    stage.update(tracks_of(320), frame_of(320, []))
    assert set(run_stage(stage, 321, 440, 9, 0.08, 2.0)) == {9}


# ------------------------------------------------------------------- configuration


def test_switch_per_tracker_and_paper_preset(tmp_path) -> None:
    for name, section in (
        ("csa", "csa"),
        ("feet-pf", "feet_pf"),
        ("upper-body-pf", "upper_body_pf"),
    ):
        entry = registry.get(name)
        assert isinstance(leg_reid_stage(entry.make(None)), LegWidthReidentifier)
        paper = load_config(entry.params_cls, None, "paper")
        assert paper.leg_reid is False
        assert leg_reid_stage(entry.make(paper)) is None
        cfg = tmp_path / f"{section}.toml"
        cfg.write_text(f"[{section}]\nleg_reid = false\n")
        assert leg_reid_stage(entry.make(load_config(entry.params_cls, cfg))) is None
    assert leg_reid_stage(registry.get("leg-mht").make(None)) is None  # re-identifies itself
    cfg = tmp_path / "leg_reid.toml"
    cfg.write_text("[leg_reid]\nleg_distance = 0.4\n[leg_reid.rules]\nmin_samples = 30\n")
    static = load_static_world(cfg)
    assert static.leg_reid.leg_distance == pytest.approx(0.4)
    assert static.leg_reid.rules.min_samples == 30
    stage = leg_reid_stage(registry.get("csa").make(None), static)
    assert stage is not None and stage.params.rules.min_samples == 30
    cfg.write_text("[leg_reid]\nmin_width = 0.3\n")
    with pytest.raises(ConfigError):
        load_static_world(cfg)


# -------------------------------------------------------------------- end to end


def walk(i: int, radius: float, y: float) -> list[tuple[float, float, float]]:
    """A person at scan ``i`` walking to and fro between 2 and 4 m along the beams at
    ``y`` [m] (0.5 m/s), legs side by side 0.24 m apart, swinging +-0.12 m."""
    phase = (0.05 * i) % 4.0
    x = 2.0 + (phase if phase < 2.0 else 4.0 - phase)
    swing = 0.12 * math.sin(2 * math.pi * i / 10)
    return [(x + swing, y - 0.12, radius), (x - swing, y + 0.12, radius)]


def person_ids(stage_on: bool) -> tuple[set[int], set[int]]:
    """The CSA through the pipeline's stages (as the live runner and build give them) on a
    person who walks for 30 s, is gone for 5 s and comes back for 10 s elsewhere: the
    person ids of the last second before and of the last second after."""
    params = replace(load_config(registry.get("csa").params_cls, None), leg_reid=stage_on)
    tracker = registry.get("csa").make(params)
    pre, obs, hide = tracker_stages(tracker, background="none")
    identify = [s for s in (hide, leg_reid_stage(tracker, StaticWorldParams())) if s is not None]
    frames = []
    for i in range(450):
        legs = [] if 300 <= i < 350 else walk(i, 0.08, -0.5 if i < 300 else 0.5)
        frames.append(frame_of(i, legs))
    pipe = Pipeline(frames, preprocess=pre, observe=obs, tracker=tracker, identify=identify)
    seen: list[set[int]] = []
    for step in pipe:
        assert step.tracks is not None
        seen.append({t.track_id for t in step.tracks.of_kind("person")})
    return set().union(*seen[290:300]), set().union(*seen[440:450])


def test_csa_keeps_the_identity_of_a_person_who_comes_back() -> None:
    before_off, after_off = person_ids(False)
    assert len(before_off) == 1 and len(after_off) == 1 and before_off != after_off
    before, after = person_ids(True)
    assert len(before) == 1 and after == before
