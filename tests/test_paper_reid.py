"""Colour re-identification (002 Sec. 2, eqs. 6-8) through :class:`ColourReidentifier`:
identities re-assigned only after ``min_observations`` clean observations of every track
(eq. 7 sums them), and close colours (two hues one histogram bin apart) told apart.

002 re-assigns once the crossing has ended (``early=False``, its setting under
``--preset paper``); the default's early re-assignment is tested in test_identity_reid.py."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from laserpeople.frame import Frame
from laserpeople.identity.reid import ColourReidentifier, ReidParams
from laserpeople.sim.camera import CameraParams, SimulatedCamera
from laserpeople.tracks import Track, Tracks


def _truth_xy(t: float) -> np.ndarray:
    """Two people 6 m apart walk through each other along x (crossing at t = 5 s)."""
    x = -3.0 + 0.6 * t
    return np.array([[x, 2.0], [-x, 2.0]])


def _run(
    params: ReidParams, hues: tuple[float, float], track_ids: Callable[[float], tuple[int, int]]
) -> tuple[ColourReidentifier, list[Tracks]]:
    cam = SimulatedCamera(CameraParams(miss_probability=0.0), seed=5)
    reid = ColourReidentifier(params)
    outs = []
    for k in range(140):
        t = k / 10
        xy = _truth_xy(t)
        obs = cam.observe(t, np.array([0, 1]), xy, np.array(hues))
        ids = track_ids(t)
        tracks = tuple(
            Track(ids[i], "person", xy[i], np.zeros(2), np.eye(2) * 0.01) for i in range(2)
        )
        outs.append(
            reid.update(Tracks(t, k, tracks), Frame(k, t, (), "synthetic", "world", appearance=obs))
        )
    return reid, outs


def _apart_at(params: ReidParams) -> float:
    """First time [s] after the crossing at which the tracks are separation_distance apart."""
    for k in range(50, 140):
        xy = _truth_xy(k / 10)
        if np.linalg.norm(xy[0] - xy[1]) > params.separation_distance:
            return k / 10
    raise AssertionError("never apart")


@pytest.mark.parametrize("n", [2, 6, 12])
def test_identities_wait_for_min_observations(n: int) -> None:
    params = ReidParams(min_observations=n, max_wait=30.0, early=False)
    reid, outs = _run(params, (0.0, 240.0), lambda t: (0, 1) if t < 5.0 else (1, 0))
    assert len(reid.reassignments) == 1
    # the end is seen one scan after the tracks are apart; observations are counted from
    # there, one per scan, and the identities change once every track has n
    waited = reid.reassignments[0].stamp - _apart_at(params)
    assert waited == pytest.approx(0.1 * n, abs=0.11)
    last = outs[-1].of_kind("person")
    left = min(last, key=lambda tr: tr.position[0])
    assert left.track_id == 1  # person 1 (walking to -x) has its identity back


def test_close_colours_one_bin_apart_are_told_apart() -> None:
    """Orange-red (20 deg, bin 0) and yellow-orange (40 deg, bin 1): eq. 6 with the learnt
    covariances still picks the right person."""
    reid, outs = _run(
        ReidParams(early=False), (15.0, 45.0), lambda t: (0, 1) if t < 5.0 else (1, 0)
    )
    assert len(reid.reassignments) == 1
    last = outs[-1].of_kind("person")
    left = min(last, key=lambda tr: tr.position[0])
    assert left.track_id == 1


def test_default_early_reassignment_ends_with_the_same_identities() -> None:
    """The default re-assigns already while the crossing goes on, and may do so more than
    once; it ends where 002's rule ends: each person with its identity back."""
    reid, outs = _run(ReidParams(), (15.0, 45.0), lambda t: (0, 1) if t < 5.0 else (1, 0))
    assert reid.reassignments
    first = reid.reassignments[0].stamp
    assert first < _apart_at(ReidParams())  # 002 waits until they are apart
    last = outs[-1].of_kind("person")
    left = min(last, key=lambda tr: tr.position[0])
    assert left.track_id == 1
