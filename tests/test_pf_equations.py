"""The equations of 004 Sec. 2 (eqs. 1-9) against hand-computed values."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.tracking.particle.feet import (
    FeetParams,
    StepDetector,
    body_offset,
    feet_weights,
    foot_likelihood,
    repelling,
    stride_likelihood,
    walking_model,
)
from laserpeople.tracking.particle.upper_body import (
    cell_weights,
    gather_cells,
    largest_eigenvalue,
    linear_motion,
    voronoi_cells,
)


def state(xl, yl, xr, yr, s, t, gamma, alpha) -> np.ndarray:
    return np.array([xl, yl, xr, yr, s, t, gamma, alpha], dtype=float)


def test_eq1_2_right_foot_moves_in_the_first_half_period() -> None:
    # gamma 0 -> 2 pi * 0.25 / 1.0 = pi/2: mod <= pi, the right foot moves s |cos(pi/2) - cos 0|
    z = state(0.0, 0.0, -0.5, 0.2, 0.5, 1.0, 0.0, math.pi / 2)
    out = walking_model(z, 0.25)
    assert out[:4] == pytest.approx([0.0, 0.0, -0.5, 0.2 + 0.5])
    assert out[6] == pytest.approx(math.pi / 2)
    assert out[[4, 5, 7]] == pytest.approx([0.5, 1.0, math.pi / 2])


def test_eq1_2_left_foot_moves_in_the_second_half_period() -> None:
    # gamma pi -> 1.25 pi: mod > pi, the left foot moves 0.4 |cos(1.25 pi) - cos(pi)|
    z = state(1.0, 2.0, 3.0, 4.0, 0.4, 2.0, math.pi, 0.0)
    out = walking_model(z, 0.25)
    move = 0.4 * abs(math.cos(1.25 * math.pi) - math.cos(math.pi))
    assert out[:4] == pytest.approx([1.0 + move, 2.0, 3.0, 4.0])
    assert out[6] == pytest.approx(1.25 * math.pi)


def test_eq1_2_each_foot_moves_2s_per_period() -> None:
    z = state(0.0, 0.0, -0.6, 0.0, 0.3, 1.0, 0.0, 0.0)
    for _ in range(100):
        z = walking_model(z, 0.01)
    # eq. 1 gives a whole step to the foot of gamma_t, so the step that straddles gamma = pi
    # moves the wrong foot by at most s |cos(pi) - cos(pi - 2 pi dt / T)| ~ 6e-4 m
    assert z[0] == pytest.approx(0.6, abs=1e-3) and z[2] == pytest.approx(0.0, abs=1e-3)
    assert z[0] - z[2] == pytest.approx(0.6, abs=2e-3)


def test_eq3_4_kernel_sum_and_floor() -> None:
    feet = np.array([[[0.0, 0.0], [5.0, 5.0]]])  # one filter, two particles
    pts = np.array([[[0.1, 0.0], [0.0, 0.2], [9.0, 9.0]]])
    mask = np.array([[True, True, False]])  # the third point is padding
    o = foot_likelihood(feet, pts, mask, 0.1, 0.05)
    expect = math.exp(-0.01 / 0.02) + math.exp(-0.04 / 0.02)
    assert o[0, 0] == pytest.approx(expect, rel=1e-5)
    assert o[0, 1] == 0.05  # P_0


def test_eq5_6_stride_term() -> None:
    # right foot 0.3 ahead along alpha = 0: s_d = 0.3; s cos(gamma) = 0.5 cos(2.0)
    z = state(0.0, 0.0, 0.3, 0.1, 0.5, 1.0, 2.0, 0.0)
    s_d = 0.3
    expect = math.exp(-((s_d + 0.5 * math.cos(2.0)) ** 2) / (2 * 0.1**2))
    assert stride_likelihood(z, 0.1) == pytest.approx(expect)
    # along alpha = pi/2 only the y difference counts
    z2 = state(0.0, 0.0, 5.0, 0.3, 0.5, 1.0, 2.0, math.pi / 2)
    assert stride_likelihood(z2, 0.1) == pytest.approx(expect)


def test_eq7_is_the_product() -> None:
    p = FeetParams(delta=0.1, p0=0.05, h=0.1, h_width=0.0)  # 004's eq. 7 exactly
    z = state(0.0, 0.0, 0.3, 0.0, 0.5, 1.0, 2.0, 0.0).reshape(1, 1, 8)
    pts = np.array([[[0.05, 0.0], [0.3, 0.05]]])
    mask = np.ones((1, 2), bool)
    o_l = foot_likelihood(z[..., 0:2], pts, mask, 0.1, 0.05)
    o_r = foot_likelihood(z[..., 2:4], pts, mask, 0.1, 0.05)
    o_b = stride_likelihood(z, 0.1)
    assert feet_weights(z, pts, mask, p) == pytest.approx(o_l * o_r * o_b)
    # the default adds the sideways step-width factor (feet 0 m apart across alpha = 0)
    q = FeetParams(delta=0.1, p0=0.05, h=0.1)
    o_w = math.exp(-(q.step_width**2) / (2 * q.h_width**2))
    assert feet_weights(z, pts, mask, q) == pytest.approx(o_l * o_r * o_b * o_w)


def test_repelling_term() -> None:
    mids = np.array([[[0.0, 0.0], [1.0, 0.0]], [[3.0, 0.0], [3.0, 0.0]]])
    est = np.array([[0.0, 0.0], [0.2, 0.0]])
    r = repelling(mids, est, 0.2)
    # filter 0 is repelled by filter 1 only; filter 1 by filter 0 only
    assert r[0, 0] == pytest.approx(1 - math.exp(-0.04 / 0.08))
    assert r[0, 1] == pytest.approx(1 - math.exp(-0.64 / 0.08))
    assert r[1, 0] == pytest.approx(1 - math.exp(-9.0 / 0.08))


def test_body_offset_vanishes_at_quarter_periods_and_matches_a_uniform_body() -> None:
    for g in (0.0, math.pi / 2, math.pi, 1.5 * math.pi):
        z = state(0, 0, 0, 0, 0.6, 1.0, g, 0.3)
        assert body_offset(z) == pytest.approx([0.0, 0.0], abs=1e-12)
    # walk a quarter period from gamma 0 and compare with a body at constant speed 2s/T
    z = state(0.0, 0.0, -0.6, 0.0, 0.6, 1.0, 0.0, 0.0)
    start_mid = 0.5 * (z[0] + z[2])
    for _ in range(25):
        z = walking_model(z, 0.01)  # gamma = pi/2 ... then go on to 3/8 period
    for _ in range(12):
        z = walking_model(z, 0.01)
    t = 0.37
    body = start_mid + 2 * 0.6 * t / 1.0
    assert 0.5 * (z[0] + z[2]) + body_offset(z)[0] == pytest.approx(body, abs=1e-9)


def test_eq8_linear_motion() -> None:
    z = np.array([[1.0, 2.0, math.pi / 6, 1.5]])
    out = linear_motion(z, 0.2)
    assert out[0] == pytest.approx(
        [1.0 + 0.3 * math.cos(math.pi / 6), 2.0 + 0.15, math.pi / 6, 1.5]
    )


def test_eq9_sum_over_the_cell_only() -> None:
    particles = np.array([[[0.0, 0.0]], [[2.0, 0.0]]])
    points = np.array([[0.1, 0.0], [0.0, 0.3], [2.0, 0.1], [9.0, 9.0]])
    cell = voronoi_cells(points, np.array([[0.0, 0.0], [2.0, 0.0]]), 1.0)
    assert cell.tolist() == [0, 0, 1, -1]
    pts, mask = gather_cells(points, cell, 2)
    w = cell_weights(particles, pts, mask, 0.25)
    assert w[0, 0] == pytest.approx(math.exp(-0.01 / 0.0625) + math.exp(-0.09 / 0.0625), rel=1e-5)
    assert w[1, 0] == pytest.approx(math.exp(-0.01 / 0.0625), rel=1e-5)


def test_largest_eigenvalue_closed_form() -> None:
    rng = np.random.default_rng(0)
    a = rng.normal(size=(10, 2, 2))
    cov = a @ a.transpose(0, 2, 1)
    assert largest_eigenvalue(cov) == pytest.approx(np.linalg.eigvalsh(cov)[:, -1])


def test_step_detector_finds_merge_then_split() -> None:
    det = StepDetector(FeetParams(bandwidth=0.2, overlap_distance=0.12))
    ring = 0.04 * np.column_stack([np.cos(np.arange(6)), np.sin(np.arange(6))])

    def feet(gap: float) -> np.ndarray:
        return np.vstack([ring, ring + np.array([gap, 0.0])])

    found = []
    gaps = [0.5, 0.44, 0.38, 0.32, 0.26, 0.2, 0.14, 0.08, 0.02, 0.04, 0.1, 0.16, 0.22, 0.28]
    for k, gap in enumerate(gaps):
        found += det.detections(feet(gap), 0.02 * k)
    assert len(found) == 1
    assert found[0].feet[:, 0].min() == pytest.approx(0.0, abs=0.01)
    assert found[0].feet[:, 0].max() > 0.2


def test_sideways_step_width_term() -> None:
    from laserpeople.tracking.particle.feet import width_likelihood

    # walking along +x (alpha 0): the sideways distance is |y_r - y_l| = 0.3
    z = state(0.0, 0.1, 0.4, -0.2, 0.5, 1.0, 0.0, 0.0)
    assert width_likelihood(z, 0.2, 0.05) == pytest.approx(math.exp(-(0.1**2) / (2 * 0.05**2)))
    # along +y (alpha pi/2) the sideways distance is |x_r - x_l| = 0.4
    z[7] = math.pi / 2
    assert width_likelihood(z, 0.4, 0.05) == pytest.approx(1.0)
    assert width_likelihood(z, 0.2, 0.0) == 1.0  # 004: no such term


def test_small_objects_drops_a_cart_side_and_keeps_a_torso() -> None:
    from laserpeople.tracking.particle.objects import small_objects

    torso = np.column_stack([np.linspace(0.0, 0.4, 15), np.zeros(15)])  # eig 0.4^2/12
    cart = np.column_stack([np.linspace(2.0, 3.0, 30), np.ones(30)])  # eig ~1/12
    keep = small_objects(np.vstack([torso, cart]), 0.1, 0.03)
    assert keep[:15].all() and not keep[15:].any()
    assert small_objects(np.vstack([torso, cart]), 0.1, 0.0).all()
    # a gap wider than the link distance splits the cart into two small objects
    split = np.column_stack(
        [np.r_[np.linspace(2.0, 2.4, 12), np.linspace(2.6, 3.0, 12)], np.ones(24)]
    )
    assert small_objects(split, 0.1, 0.03).all()


def test_points_move_along_their_beams() -> None:
    from laserpeople.frame import Frame
    from laserpeople.scan import PointSet, Pose2D, Scan
    from laserpeople.tracking.particle.frames import shifted_foreground

    # a laser at (1, 1) looking along +x sees a wall 2 m ahead in beams at 0 and 90 deg
    scan = Scan(
        0.0,
        0.0,
        math.pi / 2,
        np.array([2.0, 3.0]),
        0.05,
        30.0,
        sensor="a",
        pose=Pose2D(1.0, 1.0, 0.0),
    )
    pts = PointSet.from_scans([scan], "world")
    frame = Frame(0, 0.0, (scan,), "fused", "world", points=pts, foreground=np.array([True, True]))
    moved = shifted_foreground(frame, 0.15, "test")
    assert moved == pytest.approx(np.array([[3.15, 1.0], [1.0, 4.15]]))
    assert shifted_foreground(frame, 0.0, "test") == pytest.approx(
        np.array([[3.0, 1.0], [1.0, 4.0]])
    )


def test_bank_cull_removes_unsupported_and_the_worse_of_a_pair() -> None:
    from laserpeople.tracking.particle.bank import FilterBank

    bank = FilterBank(3, 2)
    bank.add(np.zeros((3, 3, 2)), 0.0)  # ids 0, 1, 2 born at 0
    bank.add(np.ones((1, 3, 2)), 0.5)  # id 3 born later
    bank.support(np.array([True, True, False, True]), 1.0)
    bank.quality[:] = [-5.0, 0.0, 0.0, -1.0]
    # id 2 unsupported for 1 s; pair (0, 3): 3 has the better likelihood and takes id 0
    bank.cull(1.0, 0.2, [(3, 0)], by_quality=True)
    assert bank.ids.tolist() == [1, 0]
    assert bank.hits.tolist() == [2, 2]
    young = FilterBank(3, 2)
    young.add(np.zeros((2, 3, 2)), 0.0)
    young.add(np.zeros((1, 3, 2)), 1.0)
    young.cull(1.0, 5.0, [(0, 2)], by_quality=False)  # the younger (id 2) goes
    assert young.ids.tolist() == [0, 1]


@pytest.mark.parametrize(
    ("age", "born_late", "ids"),
    [
        (1.0, 0.5, [1, 3]),  # both 1 s old or more at 2 s: the survivor keeps id 3
        (1.0, 1.5, [1, 0]),  # id 3 only 0.5 s old: a second filter on one person
        (0.0, 0.5, [1, 0]),  # 0: always the older identity
    ],
)
def test_bank_cull_keeps_own_identities_of_two_old_filters(
    age: float, born_late: float, ids: list[int]
) -> None:
    """Filters 0 (born at 0 s) and 3 (born at ``born_late``) merge at 2 s, and 3 has the
    better likelihood: it survives under its own identity when both are at least
    ``keep_identity_age`` old, else under the older identity 0."""
    from laserpeople.tracking.particle.bank import FilterBank

    bank = FilterBank(3, 2)
    bank.add(np.zeros((3, 3, 2)), 0.0)  # ids 0, 1, 2
    bank.add(np.ones((1, 3, 2)), born_late)  # id 3
    bank.support(np.array([True, True, False, True]), 2.0)
    bank.quality[:] = [-5.0, 0.0, 0.0, -1.0]
    bank.cull(2.0, 0.2, [(0, 3)], by_quality=True, keep_identity_age=age)
    assert bank.ids.tolist() == ids
