"""People from leg pairs (000 Sec. 3.3): weighted mean, validation, deletion, ids."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.tracking.people import LegState, PersonFuser, PersonParams, fuse_legs


def leg(i: int, x: float, y: float, cov: np.ndarray | None = None) -> LegState:
    return LegState(i, np.array([x, y, 0.0, 0.0]), np.eye(4) * 0.01 if cov is None else cov)


def test_fuse_legs_is_covariance_weighted_mean() -> None:
    a = LegState(0, np.array([0.0, 0.0, 1.0, 0.0]), np.diag([0.01, 0.04, 0.1, 0.1]))
    b = LegState(1, np.array([0.3, 0.2, 0.0, 0.0]), np.diag([0.03, 0.04, 0.3, 0.1]))
    mean, cov = fuse_legs(a, b)
    # diagonal covariances: per component x = (x_a / v_a + x_b / v_b) / (1/v_a + 1/v_b)
    va, vb = np.diag(a.cov), np.diag(b.cov)
    np.testing.assert_allclose(mean, (a.mean / va + b.mean / vb) / (1 / va + 1 / vb))
    np.testing.assert_allclose(np.diag(cov), 1 / (1 / va + 1 / vb))
    np.testing.assert_allclose(mean[:2], [0.075, 0.1])


def walk(fuser: PersonFuser, steps: int, dt: float, sep: float, v: float = 1.0) -> list[list]:
    out = []
    for k in range(steps):
        t = k * dt
        legs = {
            1: LegState(1, np.array([v * t, 0.0, v, 0.0]), np.eye(4) * 0.01),
            2: LegState(2, np.array([v * t, sep, v, 0.0]), np.eye(4) * 0.01),
            3: LegState(3, np.array([2.0 - v * t, 0.4, -v, 0.0]), np.eye(4) * 0.01),
        }
        out.append(fuser.update(legs, t))
    return out


def test_person_validated_from_near_legs_moving_alike() -> None:
    p = PersonParams()
    fuser = PersonFuser(p)
    out = walk(fuser, 40, 0.1, 0.3)
    assert out[0] == []
    final = out[-1]
    assert len(final) == 1
    assert final[0].members == (1, 2)
    np.testing.assert_allclose(final[0].position, [3.9, 0.15], atol=1e-9)
    assert fuser.approved_legs == frozenset({1, 2})
    # leg 3 moves the other way: never paired with 1 or 2
    assert all(3 not in person.members for step in out for person in step)


def test_far_legs_never_form_a_person() -> None:
    fuser = PersonFuser(PersonParams())
    out = walk(fuser, 40, 0.1, 0.9)
    assert all(step == [] for step in out)


def test_person_keeps_id_and_is_deleted_with_its_leg() -> None:
    fuser = PersonFuser(PersonParams())
    out = walk(fuser, 40, 0.1, 0.3)
    pid = out[-1][0].track_id
    # the legs stay tracked (also as occluded legs): same person id
    more = walk(fuser, 5, 0.1, 0.3)
    assert more[-1][0].track_id == pid
    # leg 2 deleted by the tracker: the person goes
    legs = {1: leg(1, 5.0, 0.0)}
    assert fuser.update(legs, 10.0) == []
    assert fuser.approved_legs == frozenset()


def test_person_deleted_after_window_of_far_steps() -> None:
    p = PersonParams(window=5, min_agreement=3.0)
    fuser = PersonFuser(p)
    walk(fuser, 40, 0.1, 0.3)
    for k in range(p.window - 1):
        out = fuser.update({1: leg(1, 0.0, 0.0), 2: leg(2, 0.0, 2.0)}, 5.0 + 0.1 * k)
        assert len(out) == 1
    out = fuser.update({1: leg(1, 0.0, 0.0), 2: leg(2, 0.0, 2.0)}, 6.0)
    assert out == []


def test_params_validation() -> None:
    with pytest.raises(ValueError):
        PersonParams(window=0)
