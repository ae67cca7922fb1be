"""The feet tracker's identity handover (``feet_pf.handover_time``, a departure from 004):
a new filter that starts near where a track stopped being reported, soon after, takes over
that track's identity, so that 004's trajectory matching (eq. 11) sees one person one
track."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.errors import ConfigError
from laserpeople.tracking.particle.feet import FeetParams, FeetTracker
from laserpeople.tracking.particle.handover import LostIdentities
from test_pf_feet_cells import frame_of
from test_pf_feet_independent import _person


def _lost(time: float = 2.0) -> LostIdentities:
    """Identity 7 last reported at (0, 0) at 1 s (born 0.2 s), identity 8 at (3, 0)."""
    lost = LostIdentities(time, 0.5, 1.5)
    lost.reported(np.array([7, 8]), np.array([[0.0, 0.0], [3.0, 0.0]]), np.array([0.2, 0.4]), 1.0)
    return lost


def test_the_reach_grows_with_the_time_since() -> None:
    """1 s after it was last reported, identity 7 reaches 0.5 + 1.5 x 1 = 2.0 m: a start
    1.99 m away takes it (with its birth stamp), one 2.01 m away does not; 0.5 s after,
    the reach is 1.25 m."""
    assert _lost().take(np.array([[-1.99, 0.0]]), np.empty(0, np.int64), 2.0) == [(7, 0.2)]
    assert _lost().take(np.array([[-2.01, 0.0]]), np.empty(0, np.int64), 2.0) == [None]
    assert _lost().take(np.array([[-1.24, 0.0]]), np.empty(0, np.int64), 1.5) == [(7, 0.2)]
    assert _lost().take(np.array([[-1.26, 0.0]]), np.empty(0, np.int64), 1.5) == [None]


def test_too_late_still_shown_or_taken_is_not_handed_over() -> None:
    """After ``handover_time`` (2 s) identity 7 is gone; an identity reported in the last
    scan is not lost; each identity is taken once, by the nearer start first in order;
    ``handover_time`` 0 hands nothing over."""
    none = np.empty(0, np.int64)
    assert _lost().take(np.array([[0.1, 0.0]]), none, 3.01) == [None]
    assert _lost().take(np.array([[0.1, 0.0]]), np.array([7]), 1.5) == [None]
    both = _lost().take(np.array([[0.1, 0.0], [0.2, 0.0]]), none, 1.5)
    assert both == [(7, 0.2), None]
    assert _lost(0.0).take(np.array([[0.1, 0.0]]), none, 1.5) == [None]


def test_the_nearest_lost_identity_is_taken() -> None:
    """A start at (2, 0) 1 s later lies 2 m from identity 7 and 1 m from 8: it takes 8."""
    assert _lost().take(np.array([[2.0, 0.0]]), np.empty(0, np.int64), 2.0) == [(8, 0.4)]


def test_a_report_refreshes_and_old_identities_are_forgotten() -> None:
    """Identity 7 reported again at (1, 0) at 1.5 s is lost from there; identity 8, last
    reported at 1 s, is forgotten once a report comes more than 2 s later."""
    lost = _lost()
    lost.reported(np.array([7]), np.array([[1.0, 0.0]]), np.array([0.2]), 1.5)
    none = np.empty(0, np.int64)
    # at 1.6 s identity 7 reaches 0.65 m around (1, 0): (0.3, 0) is 0.7 m away
    assert lost.take(np.array([[0.3, 0.0]]), none, 1.6) == [None]
    lost.reported(np.array([7]), np.array([[1.0, 0.0]]), np.array([0.2]), 3.1)
    assert lost.take(np.array([[3.0, 0.0]]), none, 3.2) == [None]


def _stand_hide_stand(
    p: FeetParams, scans: int, hidden: tuple[float, float], moved: float
) -> tuple[FeetTracker, list[set[int]]]:
    """A person standing at (0, 2) at 10 Hz, hidden from ``hidden[0]`` to ``hidden[1]``
    [s], then standing ``moved`` [m] to the side: the tracker after ``scans`` scans and
    the identities it reported per scan."""
    tracker = FeetTracker(p)
    out = []
    for k in range(scans):
        t = k / 10.0
        if t < hidden[0]:
            pts = _person(0.0, 2.0)
        elif t < hidden[1]:
            pts = np.empty((0, 2))
        else:
            pts = _person(moved, 2.0)
        out.append({tr.track_id for tr in tracker.update(frame_of(pts, t, k))})
    return tracker, out


def _run(handover: float) -> list[set[int]]:
    """The person stands for 2 s (a filter starts after ``still_time`` 0.5 s), is hidden
    for 1.5 s (the filter dies after ``miss_time`` 1 s), then stands 0.3 m to the side for
    2 s: the identities reported per scan."""
    p = FeetParams(handover_time=handover, still_time=0.5, miss_time=1.0, particles=100, seed=2)
    return _stand_hide_stand(p, 55, (2.0, 3.5), 0.3)[1]


@pytest.mark.parametrize("handover", [2.0, 0.0])
def test_a_person_found_again_keeps_the_identity(handover: float) -> None:
    """With the handover the filter that starts on the person again reports the identity
    of the one that was lost (one identity over the run); without it (004) a second one."""
    ids = _run(handover)
    assert ids[10] and ids[-1]
    assert not any(ids[30:35])  # hidden: nothing reported
    every = set().union(*ids)
    assert len(every) == (1 if handover > 0.0 else 2)


def test_a_coasting_filter_whose_identity_is_taken_is_removed() -> None:
    """The person hides for 0.6 s and stands again 1 m to the side; the first filter,
    unreported after ``report_time`` but alive (``miss_time`` 3 s), hands its identity to
    the filter that starts there and is removed: one filter, one identity. Without the
    handover both filters live on under two identities."""
    for handover, filters in ((2.0, 1), (0.0, 2)):
        p = FeetParams(
            handover_time=handover,
            still_time=0.5,
            miss_time=3.0,
            cell_refresh=0.0,
            particles=100,
            seed=2,
        )
        tracker, _ = _stand_hide_stand(p, 40, (1.5, 2.1), 1.0)
        assert len(tracker.bank) == filters
        assert len(set(tracker.bank.ids.tolist())) == filters


@pytest.mark.parametrize("name", ["handover_time", "handover_distance", "handover_speed"])
def test_negative_handover_settings_are_refused(name: str) -> None:
    """A negative time, distance or speed is a configuration error; 0 is allowed."""
    with pytest.raises(ConfigError, match=name):
        FeetParams(**{name: -0.1})
    assert getattr(FeetParams(**{name: 0.0}), name) == 0.0
