"""The feet tracker's refresh from its Voronoi cell (``cell_refresh``): a filter left
behind by its person (standing still, it walks off) restarts a share of its particles from
the points of its cell."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.tracking.particle.feet import FeetParams, FeetTracker, S
from test_pf_feet_cells import frame_of


def _person(x: float, y: float) -> np.ndarray:
    """Two legs 0.2 m apart along x, five points each on the front arc (radius 0.06 m)."""
    a = np.linspace(-2.4, -0.8, 5)
    legs = [
        np.column_stack([cx + 0.06 * np.cos(a), y + 0.06 * np.sin(a)]) for cx in (x - 0.1, x + 0.1)
    ]
    return np.vstack(legs)


@pytest.mark.parametrize(("refresh", "caught"), [(0.2, True), (0.0, False)])
def test_a_filter_left_behind_is_refreshed_from_its_cell(refresh: float, caught: bool) -> None:
    """A filter whose feet stand at (0, 2) with stride 0 while the person's legs are at
    (0.45, 2) (0.45 m off, inside the 0.7 m gate, so the points are in its cell): with
    ``cell_refresh`` 0.2 m a share of its particles restarts from the cell's points and
    within 10 scans (15 Hz) the track is within 0.1 m of the person; with 0 it stays
    farther."""
    tr = FeetTracker(FeetParams(particles=300, cell_refresh=refresh, still_time=0.0))
    tr.bank.add(np.stack([tr._initial(np.array([[-0.1, 2.0], [0.1, 2.0]]))]), 0.0)
    tr.bank.states[..., S] = 0.0  # stride 0: the filter stands
    pts = _person(0.45, 2.0)
    for k in range(1, 11):
        out = tr.update(frame_of(pts, k / 15.0, k))
    pos = np.array([t.position for t in out.tracks])
    assert len(pos) == 1
    assert bool(np.hypot(*(pos[0] - [0.45, 2.0])) <= 0.1) is caught


def test_no_refresh_while_the_cell_is_centred_on_the_feet() -> None:
    """A filter on its standing person (cell centred within ``cell_refresh`` of its feet
    midpoint) is not refreshed: the tracker draws the same particles as with 0."""
    pts = _person(0.0, 2.0)
    runs = []
    for refresh in (0.2, 0.0):
        tr = FeetTracker(FeetParams(particles=100, cell_refresh=refresh, still_time=0.0))
        tr.bank.add(np.stack([tr._initial(np.array([[-0.1, 2.0], [0.1, 2.0]]))]), 0.0)
        for k in range(1, 6):
            tr.update(frame_of(pts, k / 15.0, k))
        runs.append(tr.bank.states.copy())
    assert np.allclose(runs[0], runs[1], atol=1e-12)


def test_a_refresh_restarts_refresh_share_of_the_particles_at_the_mean_weight() -> None:
    """``_refresh`` with 100 particles and ``refresh_share`` 0.2: exactly 20 particles are
    restarted (the other 80 keep their states and their weights relative to each other),
    each with weight 1/100 before the filter's weights are normalised again. The old
    weights are 0.02 on particles 0-49 and 0 on 50-99, so after the refresh a restarted
    particle weighs 0.01 / (1 - 0.02 a + 0.2), a the restarted ones among 0-49."""
    tr = FeetTracker(FeetParams(particles=100, refresh_share=0.2))
    tr.bank.add(np.stack([tr._initial(np.array([[-0.1, 2.0], [0.1, 2.0]]))]), 0.0)
    old_w = np.r_[np.full(50, 0.02), np.zeros(50)]
    tr.bank.weights[0] = old_w
    before = tr.bank.states[0].copy()
    tr._refresh(0, np.array([[1.9, 0.0], [2.1, 0.0]]))  # feet 2 m away: every draw differs
    changed = np.flatnonzero(np.any(np.abs(tr.bank.states[0] - before) > 1e-9, axis=1))
    assert changed.size == 20
    a = int(np.count_nonzero(changed < 50))
    total = 1.0 - 0.02 * a + 0.2
    w = tr.bank.weights[0]
    assert w.sum() == pytest.approx(1.0, abs=1e-9)
    np.testing.assert_allclose(w[changed], 0.01 / total, rtol=1e-9)
    kept = np.setdiff1d(np.arange(100), changed)
    np.testing.assert_allclose(w[kept], old_w[kept] / total, rtol=1e-9, atol=1e-15)
