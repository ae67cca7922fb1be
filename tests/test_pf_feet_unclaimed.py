"""The feet tracker's births on objects no filter claims (``feet_pf.claim_distance``, a
departure from 004): a person-sized object with no filter's foot within ``claim_distance``
for ``claim_time`` starts a filter, so a walker beside a tracked person whose steps show
no merge -> split of their own still gets one; and the objects of the tracker's first scan
start filters at once (``first_scan_births``)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from laserpeople.tracking.particle.feet import XL, XR, YL, YR, FeetParams, FeetTracker
from laserpeople.tracking.particle.unclaimed import UnclaimedDetector, claimed_objects
from test_pf_feet_cells import frame_of
from test_pf_feet_independent import _leg, _person


def test_claimed_objects_by_the_nearest_foot() -> None:
    """Object 0 has a point 0.29 m from a foot (claimed at 0.3 m), object 1 its nearest
    point 0.31 m away (not claimed), object 2 none near; no feet: nothing claimed."""
    points = np.array([[0.29, 0.0], [0.5, 0.0], [0.0, 1.31], [0.0, 1.6], [5.0, 5.0]])
    labels = np.array([0, 0, 1, 1, 2])
    feet = np.array([[[0.0, 0.0], [0.0, 1.0]]])
    assert claimed_objects(points, labels, feet, 0.3).tolist() == [True, False, False]
    assert claimed_objects(points, labels, feet, 0.32).tolist() == [True, True, False]
    assert claimed_objects(points, labels, np.empty((0, 2, 2)), 0.3).tolist() == [False] * 3


def _walk(det: UnclaimedDetector, feet: np.ndarray, speed: float, scans: int) -> list[int]:
    """A person walking along x at ``speed`` [m/s], 10 Hz, with filter feet ``feet``
    (F, 2, 2) following at the same speed; the number of reports per scan."""
    out = []
    for k in range(scans):
        t = k / 10.0
        shift = np.array([speed * t, 0.0])
        out.append(len(det.detections(_person(*(np.array([0.0, 2.0]) + shift)), t, feet + shift)))
    return out


def test_an_unclaimed_walker_is_reported_after_claim_time() -> None:
    """At 1.2 m/s (0.12 m per scan) the object stays the same from scan to scan and is
    reported from 0.5 s on, the first scan at which it has been unclaimed for claim_time
    (it has moved 0.6 m, more than claim_move)."""
    p = FeetParams(claim_time=0.5, claim_distance=0.3, first_scan_births=False)
    counts = _walk(UnclaimedDetector(p), np.empty((0, 2, 2)), 1.2, 8)
    assert counts == [0, 0, 0, 0, 0, 1, 1, 1]


def test_a_claimed_object_or_claim_distance_zero_starts_nothing() -> None:
    """A filter's foot 0.25 m beside the person's leg claims it (within 0.3 m); the same
    foot 0.35 m away does not; ``claim_distance`` 0 switches the births off."""
    near = np.array([[[-0.35, 1.75], [-0.35, 1.65]]])  # nearest leg point ~0.25 m away
    det = UnclaimedDetector(FeetParams(claim_time=0.5, claim_distance=0.3))
    assert sum(_walk(det, near, 1.2, 10)) == 0
    far = near - np.array([0.1, 0.0])
    det = UnclaimedDetector(FeetParams(claim_time=0.5, claim_distance=0.3))
    assert sum(_walk(det, far, 1.2, 10)) > 0
    off = UnclaimedDetector(FeetParams(claim_distance=0.0))
    assert sum(_walk(off, np.empty((0, 2, 2)), 1.2, 10)) == 0


def test_an_object_that_jumps_farther_than_claim_speed_allows_is_new() -> None:
    """At 10 Hz the reach is claim_distance + claim_speed x 0.1 s = 0.5 m: a person-sized
    object 0.45 m per scan on is the same object (reported after claim_time), 0.6 m per
    scan a new one every scan (never reported)."""
    p = FeetParams(claim_time=0.5, claim_distance=0.3, claim_speed=2.0, first_scan_births=False)
    assert sum(_walk(UnclaimedDetector(p), np.empty((0, 2, 2)), 4.5, 10)) > 0
    assert sum(_walk(UnclaimedDetector(p), np.empty((0, 2, 2)), 6.0, 10)) == 0


def test_too_few_points_or_too_big_is_no_person() -> None:
    """Objects below ``blob_leg_points`` points or above ``still_eigenvalue`` start
    nothing."""
    p = FeetParams(claim_time=0.2, claim_distance=0.3, blob_leg_points=3)
    det = UnclaimedDetector(p)
    wall = np.column_stack([np.linspace(0, 1.0, 30), np.zeros(30)])  # 1 m: no person
    pair = np.array([[3.0, 3.0], [3.03, 3.0]])  # 2 points
    for k in range(10):
        assert det.detections(np.vstack([wall, pair]), k * 0.1, np.empty((0, 2, 2))) == []


def _tracked_neighbour(claim: float) -> tuple[int, int]:
    """Person A at y = 2 with a filter on its feet; person B walking 0.75 m beside it at
    1 m/s along x shows one leg only (4 points, no merge -> split of two clusters) at 10
    Hz for 1.5 s. The number of filters, and of filters within 0.3 m of B, at the end."""
    p = FeetParams(claim_distance=claim, claim_time=0.5, particles=200, seed=3, still_time=0.0)
    tracker = FeetTracker(p)
    init = tracker._initial(np.array([[-0.1, 2.0], [0.1, 2.0]]))
    init[:, 4] = 0.0  # stride 0: the filter on A stands
    tracker.bank.add(init[None], 0.0)
    for k in range(16):
        t = k / 10.0
        b = _leg(0.75 + 1.0 * t, 2.0, n=4)
        tracker.update(frame_of(np.vstack([_person(0.0, 2.0), b]), t, k))
    st = tracker.bank.states
    mids = 0.5 * (st[..., [XL, YL]] + st[..., [XR, YR]])
    est = np.einsum("fp,fpc->fc", tracker.bank.weights, mids)
    b_now = np.array([0.75 + 1.5, 2.0])
    return len(est), int((np.hypot(*(est - b_now).T) < 0.3).sum())


@pytest.mark.parametrize(("claim", "on_b"), [(0.3, 1), (0.0, 0)])
def test_a_walker_beside_a_tracked_person_gets_a_filter(claim: float, on_b: int) -> None:
    """With the births on unclaimed objects, B gets its own filter; without (004), B's one
    leg starts none and A's filter stays on A."""
    filters, near_b = _tracked_neighbour(claim)
    assert near_b == on_b
    assert filters == 1 + on_b


def test_an_unclaimed_object_that_does_not_walk_starts_nothing() -> None:
    """An unclaimed person-sized object that stays put (clutter the background has not
    learned, or a person the still detector is for) is never reported; moving at 0.4 m/s
    it is, once it has moved ``claim_move`` 0.25 m (from 0.7 s at 10 Hz)."""
    p = FeetParams(claim_time=0.5, claim_distance=0.3, claim_move=0.25, first_scan_births=False)
    assert sum(_walk(UnclaimedDetector(p), np.empty((0, 2, 2)), 0.0, 20)) == 0
    counts = _walk(UnclaimedDetector(p), np.empty((0, 2, 2)), 0.4, 10)
    assert counts.index(1) == 7


def test_the_objects_of_the_first_scan_start_filters_at_once() -> None:
    """In the detector's first scan a standing person (no claim_time, no claim_move yet)
    is reported at once, as two feet about their points' centre; a 1 m wall and a 2-point
    object are not. A person first seen in the second scan waits for claim_time and claim_move,
    and the first person, reported once, is not reported again while it stands. Without
    ``first_scan_births`` nothing is reported."""
    p = FeetParams(claim_time=0.5, claim_distance=0.3, claim_move=0.25, blob_leg_points=3)
    none = np.empty((0, 2, 2))
    wall = np.column_stack([np.linspace(5.0, 6.0, 30), np.zeros(30)])
    pair = np.array([[3.0, 3.0], [3.03, 3.0]])
    first = np.vstack([_person(0.0, 2.0), wall, pair])
    det = UnclaimedDetector(p)
    found = det.detections(first, 0.0, none)
    assert len(found) == 1
    centre = _person(0.0, 2.0).mean(axis=0)  # (the legs' front arcs: y 1.94)
    np.testing.assert_allclose(found[0].mean(axis=0), centre, atol=0.01)
    assert np.hypot(*(found[0][0] - found[0][1])) > 0.1  # two feet, not one point
    second = np.vstack([first, _person(2.0, 1.0)])
    assert det.detections(second, 0.1, none) == []
    off = UnclaimedDetector(replace(p, first_scan_births=False))
    assert off.detections(first, 0.0, none) == []
