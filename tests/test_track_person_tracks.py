"""People as tracks of their own (people policy ``tracks``): existence score, person filter,
births, occlusions, static world, against hand-computed values."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.typing import NDArray

from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams
from laserpeople.tracking.person_tracks import (
    NONE,
    ONE,
    TWO,
    LegObservation,
    PersonTracker,
    PersonTrackParams,
    segment_holds_two_legs,
    update_llr,
)
from laserpeople.tracks import Detections

P = PersonTrackParams()


def leg(
    track_id: int, x: float, y: float, detected: bool = True, wide: bool = False
) -> LegObservation:
    return LegObservation(
        track_id,
        np.array([x, y]),
        detected,
        0.0 if detected else 0.2,
        0,
        wide,
        score=1.0 if detected else math.nan,
    )


def legs(*obs: LegObservation) -> dict[int, LegObservation]:
    return {o.track_id: o for o in obs}


def test_evidence_llr_by_hand() -> None:
    # p = (0.5, 0.4, 0.1), q = (0.1, 0.4, 0.5)
    llr = P.evidence_llr()
    assert llr == pytest.approx([math.log(5.0), 0.0, math.log(0.2)])
    assert update_llr(0.0, TWO, P) == pytest.approx(1.6094379)
    assert update_llr(11.0, TWO, P) == P.llr_max  # clamped above
    assert update_llr(-2.5, NONE, P) == P.llr_min  # clamped below
    assert update_llr(1.0, ONE, P) == pytest.approx(1.0)


def test_params_are_checked() -> None:
    with pytest.raises(ValueError):
        PersonTrackParams(p_two=0.7, p_one=0.4)
    with pytest.raises(ValueError):
        PersonTrackParams(llr_confirm=-5.0)


def test_wide_segment_holds_two_legs() -> None:
    def seg(width: float, n: int = 8) -> NDArray[np.float64]:
        return np.column_stack([np.full(n, 2.0), np.linspace(0.0, width, n)])

    assert segment_holds_two_legs(seg(0.3), 1.0, P)
    assert not segment_holds_two_legs(seg(0.15), 1.0, P)  # one leg
    assert not segment_holds_two_legs(seg(0.8), 1.0, P)  # a wall piece
    assert not segment_holds_two_legs(seg(0.3, n=3), 1.0, P)  # too few points
    assert not segment_holds_two_legs(seg(0.3), 0.4, P)  # the detector is not sure enough


def test_pair_birth_confirmation_after_three_scans() -> None:
    """llr after k scans of both legs = k log 5: 1.61, 3.22 (< 4), 4.83 (confirmed)."""
    t = PersonTracker(P)
    for k in range(3):
        out = t.update(legs(leg(1, 1.0, 0.0), leg(2, 1.0, 0.3)), 0.1 * k, 1.0)
        assert (len(out) == 1) == (k == 2)
    (person,) = out
    assert person.track_id == 0 and person.members == (1, 2)
    assert person.position == pytest.approx([1.0, 0.15], abs=1e-9)
    (q,) = t.persons.values()
    assert q.llr == pytest.approx(3 * math.log(5.0))
    assert person.score == pytest.approx(1.0 / (1.0 + math.exp(-3 * math.log(5.0))))
    assert t.approved_legs == frozenset({1, 2})


def test_person_filter_update_by_hand() -> None:
    """Second scan: the position variance is predicted over dt = 0.1 s (P0 = pair_std^2,
    velocity variance init_velocity_std^2, white acceleration q) and corrected with a pair
    midpoint of variance pair_std^2; x moves by K * innovation."""
    t = PersonTracker(P)
    t.update(legs(leg(1, 1.0, 0.0), leg(2, 1.0, 0.3)), 0.0, 1.0)
    t.update(legs(leg(1, 1.1, 0.0), leg(2, 1.1, 0.3)), 0.1, 1.0)
    (q,) = t.persons.values()
    dt, r = 0.1, P.pair_std**2
    pxx = r + dt**2 * P.init_velocity_std**2 + P.accel_psd * dt**3 / 3.0
    pxv = dt * P.init_velocity_std**2 + P.accel_psd * dt**2 / 2.0
    k_pos, k_vel = pxx / (pxx + r), pxv / (pxx + r)
    assert q.mean[0] == pytest.approx(1.0 + k_pos * 0.1)
    assert q.mean[2] == pytest.approx(k_vel * 0.1)
    assert q.mean[1] == pytest.approx(0.15)
    assert q.cov[0, 0] == pytest.approx(pxx * r / (pxx + r))


def test_wide_segment_births_a_person() -> None:
    t = PersonTracker(P)
    for k in range(3):
        out = t.update(legs(leg(5, 2.0, 0.0, wide=True)), 0.1 * k, 1.0)
    assert [p.members for p in out] == [(5,)]
    # a single narrow leg gives no person
    t2 = PersonTracker(P)
    for k in range(10):
        assert t2.update(legs(leg(5, 2.0, 0.0)), 0.1 * k, 1.0) == []
    assert t2.persons == {}


def test_low_score_pair_gives_no_birth() -> None:
    """Mean score 0.3 <= birth_min_score 0.5: no person (chair legs score ~0.2)."""
    t = PersonTracker(P)
    weak = [
        LegObservation(1, np.array([1.0, 0.0]), True, 0.0, 0, score=0.2),
        LegObservation(2, np.array([1.0, 0.3]), True, 0.0, 1, score=0.4),
    ]
    for k in range(10):
        assert t.update({o.track_id: o for o in weak}, 0.1 * k, 1.0) == []
    assert t.persons == {}


def _confirmed(t: PersonTracker) -> None:
    for k in range(4):
        t.update(legs(leg(1, 1.0, 0.0), leg(2, 1.0, 0.3)), 0.1 * k, 1.0)


def test_one_visible_leg_keeps_the_person() -> None:
    t = PersonTracker(P)
    _confirmed(t)
    (q,) = t.persons.values()
    llr = q.llr
    for k in range(4, 40):  # 3.6 s with only leg 1 seen (leg 2 deleted by the MHT)
        out = t.update(legs(leg(1, 1.0, 0.0)), 0.1 * k, 1.0)
        assert [p.track_id for p in out] == [0]
    assert q.llr == pytest.approx(llr)  # one leg is neutral evidence: log(0.4 / 0.4) = 0
    assert q.members == [1]


def test_occlusion_of_seconds_keeps_the_id_when_the_motion_agrees() -> None:
    t = PersonTracker(P)
    _confirmed(t)
    for k in range(4, 30):  # 2.6 s without any leg: not reported after 1 s, kept
        out = t.update({}, 0.1 * k, 1.0)
        assert (out == []) == (0.1 * k - 0.3 > 1.0 + 1e-9)
    # new leg tracks (new MHT ids) near where the person stood
    for k in range(30, 33):
        out = t.update(legs(leg(7, 1.1, 0.1), leg(8, 1.0, 0.4)), 0.1 * k, 1.0)
    assert [p.track_id for p in out] == [0]
    assert sorted(t.persons[0].members) == [7, 8]
    assert t.persons_created == 1


def test_person_deleted_after_max_coast_and_new_id_after() -> None:
    t = PersonTracker(P)
    _confirmed(t)
    t.update({}, 0.3 + P.max_coast + 0.05, 1.0)
    assert t.persons == {}
    for k in range(3):
        out = t.update(legs(leg(7, 1.0, 0.0), leg(8, 1.0, 0.3)), 10.0 + 0.1 * k, 1.0)
    assert [p.track_id for p in out] == [1]


def test_far_leg_does_not_join() -> None:
    t = PersonTracker(P)
    _confirmed(t)
    t.update(legs(leg(1, 1.0, 0.0), leg(9, 3.0, 0.0)), 0.4, 1.0)
    assert t.persons[0].members == [1]


class FakeStatic:
    """Everything static for a minute, except x > 1.5 m."""

    consumes = frozenset({"points"})

    def __call__(self, frame):  # type: ignore[no-untyped-def]
        return frame

    def static_time(self, positions: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.where(positions[:, 0] > 1.5, 0.0, 60.0)


def test_static_place_blocks_confirmation_until_the_person_moves() -> None:
    t = PersonTracker(P, FakeStatic())
    for k in range(20):
        out = t.update(legs(leg(1, 1.0, 0.0), leg(2, 1.0, 0.3)), 0.1 * k, 1.0)
        assert out == []
    # walks off: 0.05 m per scan; confirmed once 0.5 m from its birth place
    x = 1.0
    seen = False
    for k in range(20, 40):
        x += 0.05
        out = t.update(legs(leg(1, x, 0.0), leg(2, x, 0.3)), 0.1 * k, 1.0)
        seen = seen or bool(out)
    assert seen
    # stands where it is (x > 1.5: not static): keeps its track
    for k in range(40, 60):
        out = t.update(legs(leg(1, x, 0.0), leg(2, x, 0.3)), 0.1 * k, 1.0)
    assert [p.track_id for p in out] == [0]
    # walks back onto the place static for 60 s, longer than it has been there (+ slack):
    # a track that slid onto furniture is not reported (a person who stops at a place
    # that becomes static as it stands keeps its track: tests/test_pipeline_static_people.py)
    for k in range(60, 100):
        x = max(x - 0.05, 1.0)
        out = t.update(legs(leg(1, x, 0.0), leg(2, x, 0.3)), 0.1 * k, 1.0)
    assert out == []
    # and walks off again: reported with its id
    for k in range(100, 130):
        x += 0.05
        out = t.update(legs(leg(1, x, 0.0), leg(2, x, 0.3)), 0.1 * k, 1.0)
    assert [p.track_id for p in out] == [0]


def test_confirmed_clutter_is_dropped_once_its_place_is_static() -> None:
    class LaterStatic(FakeStatic):
        def __init__(self) -> None:
            self.value = 0.0

        def static_time(self, positions: NDArray[np.float64]) -> NDArray[np.float64]:
            return np.full(positions.shape[0], self.value)

    model = LaterStatic()
    t = PersonTracker(P, model)
    _confirmed(t)
    assert t.update(legs(leg(1, 1.0, 0.0), leg(2, 1.0, 0.3)), 0.4, 1.0) != []
    model.value = 60.0  # the grid has learnt the place
    assert t.update(legs(leg(1, 1.0, 0.0), leg(2, 1.0, 0.3)), 0.5, 1.0) == []


def _three_legs(t: PersonTracker, third_x: float, k0: int, k1: int) -> list[int]:
    """Scans k0..k1-1 of a pair at x = 1.0 m (centre (1.0, 0.15)) and a third detected
    leg at (third_x, 0.15); the ids reported in the last scan."""
    out: list = []
    for k in range(k0, k1):
        scan = legs(leg(1, 1.0, 0.0), leg(2, 1.0, 0.3), leg(3, third_x, 0.15))
        out = t.update(scan, 0.1 * k, 1.0)
    return [p.track_id for p in out]


def test_three_legs_near_a_person_that_never_walked_are_furniture() -> None:
    """A confirmed pair with a third leg 0.30 m from its centre (within furniture_radius
    0.35 m) in one scan is not reported; at 0.40 m (outside) it is, as with
    furniture_scans = 0; with furniture_scans = 2 one scan is not enough, two are."""
    assert P.furniture_scans == 1 and P.furniture_radius == pytest.approx(0.35)
    t = PersonTracker(P)
    _confirmed(t)
    assert _three_legs(t, 1.3, 4, 5) == []
    far = PersonTracker(P)
    _confirmed(far)
    assert _three_legs(far, 1.4, 4, 10) == [0]
    off = PersonTracker(PersonTrackParams(furniture_scans=0))
    _confirmed(off)
    assert _three_legs(off, 1.3, 4, 10) == [0]
    two = PersonTracker(PersonTrackParams(furniture_scans=2))
    _confirmed(two)
    assert _three_legs(two, 1.3, 4, 5) == [0]
    assert _three_legs(two, 1.3, 5, 6) == []
    # a candidate with three legs near it is not confirmed in the first place
    young = PersonTracker(P)
    assert _three_legs(young, 1.3, 0, 10) == []
    # walks off (0.05 m per scan, min_travel 0.5 m): reported again with its id
    out: list = []
    x = 1.0
    for k in range(5, 25):
        x += 0.05
        out = t.update(legs(leg(1, x, 0.0), leg(2, x, 0.3)), 0.1 * k, 1.0)
    assert [p.track_id for p in out] == [0]
    # and once it has walked, three legs near it (a person by a chair) do not hide it
    out = t.update(legs(leg(1, x, 0.0), leg(2, x, 0.3), leg(3, x + 0.3, 0.15)), 2.5, 1.0)
    assert [p.track_id for p in out] == [0]


class SecondStatic(FakeStatic):
    """Every place static for ``value`` seconds (1 s: static, below static_time)."""

    def __init__(self, value: float = 1.0) -> None:
        self.value = value

    def static_time(self, positions: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.full(positions.shape[0], self.value)


def _judged_and_gone(model: SecondStatic | None = None) -> PersonTracker:
    """A tracker (static world ``model``, default 1 s everywhere) whose confirmed pair at
    (1.0, 0.15) was judged furniture (a third leg 0.30 m off in scan 4) and then deleted
    (no leg for 0.7 s > unconfirmed_coast)."""
    t = PersonTracker(P, SecondStatic() if model is None else model)
    _confirmed(t)
    assert _three_legs(t, 1.3, 4, 5) == []
    for k in range(5, 12):
        assert t.update({}, 0.1 * k, 1.0) == []
    assert not t.persons
    return t


def _pair_at(t: PersonTracker, x: float, k0: int, k1: int) -> list[int]:
    """Scans k0..k1-1 of a pair of new leg tracks (11, 12) at x [m], y = 0 and 0.3 m; the
    ids reported in the last scan."""
    out: list = []
    for k in range(k0, k1):
        out = t.update(legs(leg(11, x, 0.0), leg(12, x, 0.3)), 0.1 * k, 1.0)
    return [p.track_id for p in out]


def test_a_furniture_verdict_holds_for_its_place() -> None:
    """The legs of a chair judged furniture come back as new leg tracks after its person was
    deleted: a pair born within furniture_radius (0.35 m) of the judged place, static for
    1 s, is not confirmed in 10 scans (0.0 and 0.30 m off), one 0.40 m off is, as is the
    same pair without the verdict; the pair on the place is reported once it walks off it.
    The verdict holds only while its place is static: not once the static world answers
    0 s there (the chair gone, or no model, as on a laser moving without poses)."""
    assert _pair_at(PersonTracker(P, SecondStatic()), 1.0, 12, 22) == [0]
    assert _pair_at(_judged_and_gone(), 1.3, 12, 22) == []
    assert _pair_at(_judged_and_gone(), 1.4, 12, 22) == [1]
    gone = SecondStatic()
    t = _judged_and_gone(gone)
    gone.value = 0.0
    assert _pair_at(t, 1.0, 12, 22) == [1]
    t = _judged_and_gone()
    assert _pair_at(t, 1.0, 12, 22) == []
    out: list = []
    x = 1.0
    for k in range(22, 37):  # walks off at 0.5 m/s: 0.75 m
        x += 0.05
        out = t.update(legs(leg(11, x, 0.0), leg(12, x, 0.3)), 0.1 * k, 1.0)
        (q,) = t.persons.values()
        off = math.hypot(q.mean[0] - 1.0, q.mean[1] - 0.15) > P.furniture_radius
        assert bool(out) == off, k  # (off the place before it has travelled min_travel)
    assert [p.track_id for p in out] == [1]


def test_a_person_starting_to_walk_beside_a_free_leg_is_not_furniture() -> None:
    """A pair walking at 0.5 m/s from its first scan with a free leg walking beside it
    (0.30 m from its centre; all three legs at 0.5 m/s) has not yet travelled min_travel
    after 0.8 s, but moves faster than furniture_speed (0.1 m/s) and its legs faster than
    furniture_leg_speed (0.2 m/s): reported; counting posts at any speed hides it. Legs at
    0.15 m/s (slower than furniture_leg_speed, as a chair's legs whose person moves because
    they hop between its posts) count: hidden; at 0.25 m/s, or with the third leg at
    0.5 m/s, they do not."""
    assert P.furniture_speed == pytest.approx(0.1)
    assert P.furniture_leg_speed == pytest.approx(0.2)

    def walk(t: PersonTracker, pair: float = 0.5, third: float | None = None) -> list[int]:
        """Speeds [m/s] of the pair's legs and of the third (as the pair's when None)."""
        third = pair if third is None else third
        out: list = []
        for k in range(9):
            x = 1.0 + 0.05 * k
            scan = {
                i: LegObservation(
                    i, np.array([lx, ly]), True, 0.0, 0, velocity=np.array([v, 0.0]), score=1.0
                )
                for i, lx, ly, v in (
                    (1, x, 0.0, pair),
                    (2, x, 0.3, pair),
                    (3, x + 0.3, 0.15, third),
                )
            }
            out = t.update(scan, 0.1 * k, 1.0)
        assert all(q.travelled < P.min_travel for q in t.persons.values())
        return [p.track_id for p in out]

    assert walk(PersonTracker(P)) == [0]
    assert walk(PersonTracker(PersonTrackParams(furniture_speed=10.0))) == []
    assert walk(PersonTracker(P), 0.15) == []
    assert walk(PersonTracker(P), 0.25) == [0]
    assert walk(PersonTracker(P), 0.15, 0.5) == [0]  # (every leg: the pair's alone do not)


def test_a_neighbours_leg_is_not_a_post() -> None:
    """Two people standing side by side: a leg of the other within furniture_radius of each
    centre (0.304 m; the other's second leg 0.39 m off) makes three legs, but not three
    of its own or free ones: both are reported."""
    t = PersonTracker(P)
    out: list = []
    for k in range(10):
        scan = legs(leg(1, 1.0, 0.0), leg(2, 1.0, 0.3), leg(3, 1.3, 0.1), leg(4, 1.3, 0.4))
        out = t.update(scan, 0.1 * k, 1.0)
    assert sorted(p.members for p in out) == [(1, 2), (3, 4)]


def test_furniture_params_are_checked() -> None:
    with pytest.raises(ValueError, match="furniture"):
        PersonTrackParams(furniture_scans=-1)
    with pytest.raises(ValueError, match="furniture"):
        PersonTrackParams(furniture_radius=0.0)
    with pytest.raises(ValueError, match="furniture"):
        PersonTrackParams(furniture_speed=0.0)
    with pytest.raises(ValueError, match="furniture"):
        PersonTrackParams(furniture_leg_speed=0.0)


# ------------------------------------------------------------------ through the leg MHT


def _dets(stamp: float, k: int, pts: list[tuple[float, float]]) -> Detections:
    arr = np.array(pts, dtype=np.float64).reshape(-1, 2)
    return Detections(stamp, k, arr, np.repeat(np.eye(2)[None] * 0.03**2, len(arr), 0),
                      np.ones(len(arr)))  # fmt: skip


def test_leg_mht_tracks_policy_reports_a_standing_pair_and_keeps_it_on_one_leg() -> None:
    tracker = LegMHTTracker(LegTrackerParams(people_policy="tracks"))
    for k in range(10):
        out = tracker.update(_dets(0.1 * k, k, [(2.0, 0.0), (2.0, 0.3)]))
    (person,) = out.of_kind("person")
    assert person.position == pytest.approx([2.0, 0.15], abs=0.02)
    for k in range(10, 40):  # the second leg hidden for 3 s
        out = tracker.update(_dets(0.1 * k, k, [(2.0, 0.0)]))
        assert [p.track_id for p in out.of_kind("person")] == [person.track_id]


def test_arras_policy_needs_both_legs() -> None:
    tracker = LegMHTTracker(LegTrackerParams(people_policy="arras"))
    for k in range(60):  # a standing pair: validated after still_time
        out = tracker.update(_dets(0.1 * k, k, [(2.0, 0.0), (2.0, 0.3)]))
    assert len(out.of_kind("person")) == 1
    assert tracker.person_tracks is None


def test_unknown_policy_is_refused() -> None:
    with pytest.raises(ValueError, match="people_policy"):
        LegTrackerParams(people_policy="magic")


def test_people_policy_option_and_toml(tmp_path) -> None:  # type: ignore[no-untyped-def]
    from laserpeople.config import load_config
    from laserpeople.errors import ConfigError
    from laserpeople.tracking.nearest import NearestNeighbourParams
    from laserpeople.tracking.registry import with_people_policy

    assert LegTrackerParams().people_policy == "tracks"
    p = with_people_policy(LegTrackerParams(), "arras", "leg-mht")
    assert p.people_policy == "arras"
    with pytest.raises(ConfigError, match="people_policy"):
        with_people_policy(LegTrackerParams(), "magic", "leg-mht")
    with pytest.raises(ConfigError, match="applies to leg-mht"):
        with_people_policy(NearestNeighbourParams(), "arras", "nn")
    path = tmp_path / "p.toml"
    path.write_text('[leg_tracker]\npeople_policy = "arras"\npeople.max_coast = 2.5\n')
    q = load_config(LegTrackerParams, path)
    assert q.people_policy == "arras" and q.people.max_coast == 2.5


def test_each_person_is_asked_once_per_scan() -> None:
    """The static time of a person updated in a scan is not asked again when it is
    confirmed in the same scan (the grid has not changed in between)."""

    class Counting(FakeStatic):
        def __init__(self) -> None:
            self.asked: list[tuple[float, float]] = []

        def static_time(self, positions: NDArray[np.float64]) -> NDArray[np.float64]:
            self.asked += [(float(x), float(y)) for x, y in positions]
            return np.zeros(positions.shape[0])

    model = Counting()
    t = PersonTracker(P, model)
    for k in range(10):
        model.asked = []
        out = t.update(legs(leg(1, 1.0 + 0.05 * k, 0.0), leg(2, 1.0 + 0.05 * k, 0.3)), 0.1 * k, 1.0)
        assert len(model.asked) == len(set(model.asked)) <= 1
    assert [p.track_id for p in out] == [0]


# ------------------------------------------------------------------ furniture legs left out


def test_on_furniture_leaves_out_static_legs_far_from_walkers() -> None:
    t = PersonTracker(P, FakeStatic())  # static for 60 s where x <= 1.5 m
    pos = np.array([[1.0, 0.0], [2.0, 0.0], [0.1, 0.0]])
    assert t.on_furniture(pos).tolist() == [True, False, True]
    # a person that has walked min_travel keeps the static legs within walker_radius
    t._new(np.array([1.2, 0.0]), [7], 0.0)
    (q,) = t.persons.values()
    q.travelled = P.min_travel
    assert t.on_furniture(pos).tolist() == [False, False, True]  # 0.2 m and 1.1 m away
    q.travelled = 0.0  # a candidate that never walked: furniture for all we know
    assert t.on_furniture(pos).tolist() == [True, False, True]
    q.public_id = 3  # ... unless it was reported: people standing still keep their legs
    assert t.on_furniture(pos).tolist() == [False, False, True]
    # tracked as before when asked to, or without a static world model
    assert not PersonTracker(P, None).on_furniture(pos).any()
    kept = PersonTracker(PersonTrackParams(static_legs=True), FakeStatic())
    assert not kept.on_furniture(pos).any()


def test_leg_mht_counts_the_furniture_legs_it_leaves_out() -> None:
    tracker = LegMHTTracker(LegTrackerParams(people_policy="tracks"))
    tracker.person_tracks.static_model = FakeStatic()  # type: ignore[union-attr]
    # two posts on a static place (x <= 1.5) and a pair of legs off it
    for k in range(10):
        out = tracker.update(_dets(0.1 * k, k, [(1.0, 0.0), (1.0, 0.3), (2.0, 0.0), (2.0, 0.3)]))
    assert tracker.static_legs_left_out == 20
    assert all(t.position[0] > 1.5 for t in out.of_kind("leg"))
    (person,) = out.of_kind("person")
    assert person.position == pytest.approx([2.0, 0.15], abs=0.02)
    # with static_legs the posts are tracked as legs (and not confirmed as a person)
    both = LegMHTTracker(
        LegTrackerParams(people_policy="tracks", people=PersonTrackParams(static_legs=True))
    )
    both.person_tracks.static_model = FakeStatic()  # type: ignore[union-attr]
    for k in range(10):
        out = both.update(_dets(0.1 * k, k, [(1.0, 0.0), (1.0, 0.3), (2.0, 0.0), (2.0, 0.3)]))
    assert both.static_legs_left_out == 0
    assert sum(t.position[0] <= 1.5 for t in out.of_kind("leg")) == 2
    assert len(out.of_kind("person")) == 1


def test_all_apart_never_misses_a_pair_np_hypot_finds_close() -> None:
    """``_all_apart`` (the merge's plain-float pre-check) says "all apart" only when no
    ``np.hypot`` of two positions' differences is below the distance; on random sets with
    pairs at the distance, along an axis and diagonally, and NaN coordinates, it also says
    so for most sets where that holds."""
    from laserpeople.tracking.person_tracks import _all_apart

    rng = np.random.default_rng(21)
    d = 0.4
    said_apart = 0
    for _ in range(3000):
        n = int(rng.integers(2, 7))
        xy = rng.uniform(-2.0, 2.0, size=(n, 2))
        if rng.random() < 0.3:  # a pair exactly at the distance along x, or diagonally
            xy[1] = xy[0] + (np.array([d, 0.0]) if rng.random() < 0.5 else d / np.sqrt(2.0))
        if rng.random() < 0.05:
            xy[-1, int(rng.integers(2))] = np.nan
        near = np.hypot(*(xy[:, None, :] - xy[None, :, :]).transpose(2, 0, 1)) < d
        any_close = bool((near & ~np.eye(n, dtype=bool)).any())
        apart = _all_apart(xy.tolist(), d)
        assert not (apart and any_close)
        said_apart += apart
    assert said_apart > 300
    assert _all_apart([[0.0, 0.0], [0.4, 0.0]], 0.4)
    assert not _all_apart([[0.0, 0.0], [0.3, 0.3]], 0.4)  # (0.42 m apart, but not along an axis)
    assert not _all_apart([[0.0, 0.0], [float("nan"), float("nan")]], 0.4)


def test_all_apart_sweep_agrees_with_every_pair_compared() -> None:
    """The sweep over x of ``_all_apart`` gives what comparing every two positions gives
    (apart along x or along y), on crowds of 2-30 with pairs at the distance, equal x and
    NaN; both answers occur."""
    from laserpeople.tracking.person_tracks import _all_apart

    def every_pair(xy: list[list[float]], d: float) -> bool:
        return all(
            abs(ax - bx) >= d or abs(ay - by) >= d
            for i, (ax, ay) in enumerate(xy)
            for bx, by in xy[i + 1 :]
        )

    rng = np.random.default_rng(35)
    d = 0.3
    answers = set()
    for _ in range(2000):
        n = int(rng.integers(2, 31))
        xy = rng.uniform(-4.0, 4.0, size=(n, 2))
        if rng.random() < 0.3:
            xy[1] = xy[0] + np.array([d, float(rng.uniform(-0.2, 0.2))])
        if rng.random() < 0.2:
            xy[-1, 0] = xy[0, 0]  # equal x
        if rng.random() < 0.05:
            xy[int(rng.integers(n)), int(rng.integers(2))] = np.nan
        got = _all_apart(xy.tolist(), d)
        assert got == every_pair(xy.tolist(), d)
        answers.add(got)
    assert answers == {True, False}
