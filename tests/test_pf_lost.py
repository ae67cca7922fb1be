"""Lost identities of the feet tracker: a filter that died for want of support gives its
identity to a new filter that starts where the lost one would be now."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.tracking.particle.bank import FilterBank
from laserpeople.tracking.particle.feet import FeetParams, FeetTracker
from laserpeople.tracking.particle.lost import LostIdentities
from test_pf_feet_cells import frame_of


def test_bank_reports_starved_filters_with_their_last_support() -> None:
    bank = FilterBank(2, 2)
    bank.add(np.zeros((2, 2, 2)), 0.0)  # ids 0, 1
    bank.support(np.array([True, True]), 0.5, np.array([[1.0, 2.0], [3.0, 4.0]]))
    bank.support(np.array([False, True]), 0.9, np.array([[9.0, 9.0], [5.0, 6.0]]))
    starved = bank.cull(1.2, 0.5, [], by_quality=True)  # id 0 last seen 0.7 s ago
    assert starved.ids.tolist() == [0]
    assert starved.last_seen.tolist() == [0.5]
    assert starved.anchors.tolist() == [[1.0, 2.0]]  # not the unsupported 9, 9
    assert np.isnan(starved.velocities).all()
    assert bank.ids.tolist() == [1]


def _lost(anchor: list[float], velocity: list[float], seen: float) -> LostIdentities:
    from laserpeople.tracking.particle.bank import Starved

    lost = LostIdentities(distance=0.5, duration=2.0)
    lost.add(
        Starved(
            np.array([7]),
            np.array([0.1]),
            np.array([seen]),
            np.array([anchor]),
            np.array([velocity]),
        )
    )
    return lost


def test_claim_near_the_moved_on_place_within_the_time() -> None:
    """Lost at (0, 0) at 1 m/s along +x, last seen at t = 1; at t = 2.5 it would be at
    (1.5, 0): a start at (1.5, 0.4) (0.4 m off the segment) takes id 7 and birth 0.1; one
    at (2.1, 0) (0.6 m beyond) does not, nor one at (1.5, 0.4) after 2 s (t = 3.1)."""
    lost = _lost([0.0, 0.0], [1.0, 0.0], 1.0)
    assert lost.claim(np.array([[2.1, 0.0]]), 2.5) == []
    assert lost.claim(np.array([[2.1, 0.0], [1.5, 0.4]]), 2.5) == [(1, 7, 0.1)]
    assert len(lost) == 0  # claimed once
    late = _lost([0.0, 0.0], [1.0, 0.0], 1.0)
    assert late.claim(np.array([[1.5, 0.4]]), 3.1) == []
    assert len(late) == 0  # expired
    still = _lost([0.0, 0.0], [0.0, 0.0], 1.0)
    assert still.claim(np.array([[0.3, 0.39]]), 2.0) == [(0, 7, 0.1)]  # 0.49 m


def test_nearest_start_claims_first() -> None:
    lost = _lost([0.0, 0.0], [0.0, 0.0], 1.0)
    got = lost.claim(np.array([[0.4, 0.0], [0.1, 0.0]]), 1.5)
    assert got == [(1, 7, 0.1)]


def test_off_remembers_nothing() -> None:
    from laserpeople.tracking.particle.bank import Starved

    lost = LostIdentities(distance=0.5, duration=0.0)
    one = np.array([[0.0, 0.0]])
    lost.add(Starved(np.array([1]), np.zeros(1), np.zeros(1), one, one))
    assert len(lost) == 0 and lost.claim(one, 0.0) == []


def _person(x: float, y: float) -> np.ndarray:
    """Two legs 0.2 m apart along x, five points each on the front arc."""
    a = np.linspace(-2.4, -0.8, 5)
    legs = [
        np.column_stack([cx + 0.06 * np.cos(a), y + 0.06 * np.sin(a)]) for cx in (x - 0.1, x + 0.1)
    ]
    return np.vstack(legs)


@pytest.mark.parametrize(("reclaim", "same"), [(3.0, True), (0.0, False)])
def test_a_person_hidden_longer_than_miss_time_keeps_the_identity(
    reclaim: float, same: bool
) -> None:
    """A person stands at (0, 2) for 1.5 s (15 Hz), is hidden for 1.5 s (the filter dies
    after ``miss_time`` 1 s) and stands there again: the still detector starts a new
    filter after ``still_time``, under the old identity with ``reclaim_time`` 3 s, under
    a new one with 0 (004)."""
    tr = FeetTracker(FeetParams(particles=200, reclaim_time=reclaim, still_time=0.5))
    ids: list[set[int]] = []
    for k in range(75):
        t = k / 15.0
        hidden = 1.5 <= t < 3.0
        pts = np.empty((0, 2)) if hidden else _person(0.0, 2.0)
        ids.append({tr_.track_id for tr_ in tr.update(frame_of(pts, t, k)).tracks})
    before = set().union(*ids[:22])
    after = set().union(*ids[60:])
    assert len(before) == 1 and len(after) == 1
    assert (before == after) is same
