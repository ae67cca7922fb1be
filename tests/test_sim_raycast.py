"""Ray casting against hand-computed hits: circles, ellipses, segments, occlusion, wrap-round."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.sim.raycast import BeamFan, Primitives, cast


def _shapes(
    circles: list[tuple[float, float, float]] = (),  # type: ignore[assignment]
    ellipses: list[tuple[float, float, float, float, float]] = (),  # type: ignore[assignment]
    segments: list[tuple[float, float, float, float]] = (),  # type: ignore[assignment]
) -> Primitives:
    c = np.asarray(circles, float).reshape(-1, 3)
    e = np.asarray(ellipses, float).reshape(-1, 5)
    s = np.asarray(segments, float).reshape(-1, 4)

    def lab(n: int, base: int) -> np.ndarray:
        out = np.full((n, 4), -1, dtype=np.int32)
        out[:, 3] = base + np.arange(n)
        return out

    return Primitives(
        c[:, :2], c[:, 2], lab(len(c), 0),
        e[:, :2], e[:, 2:4], e[:, 4], lab(len(e), 100),
        s[:, :2], s[:, 2:], lab(len(s), 200),
    )  # fmt: skip


def test_single_circle_hits_match_hand_computation() -> None:
    # circle of radius 0.1 m at 2 m straight ahead; beams every 0.5 deg from -10 deg
    inc = math.radians(0.5)
    fan = BeamFan(math.radians(-10.0), inc, 41)
    hit = cast(fan, _shapes(circles=[(2.0, 0.0, 0.1)]))
    angles = fan.angles
    # ray t*u meets |x - c| = r at t = 2 cos a - sqrt(r^2 - 4 sin^2 a)
    disc = 0.1**2 - (2.0 * np.sin(angles)) ** 2
    expected = np.where(disc >= 0, 2.0 * np.cos(angles) - np.sqrt(np.clip(disc, 0, None)), np.inf)
    # half-width asin(0.05) = 2.87 deg: the 11 beams from -2.5 to +2.5 deg hit
    assert np.count_nonzero(np.isfinite(expected)) == 11
    np.testing.assert_allclose(hit.ranges, expected, atol=1e-12)
    assert hit.ranges[20] == pytest.approx(1.9)
    assert set(hit.labels[np.isfinite(hit.ranges), 3]) == {0}
    assert np.all(hit.labels[~np.isfinite(hit.ranges)] == -1)


def test_nearer_circle_occludes_the_one_behind() -> None:
    fan = BeamFan(math.radians(-5.0), math.radians(0.25), 41)
    hit = cast(fan, _shapes(circles=[(4.0, 0.0, 0.1), (2.0, 0.0, 0.1)]))
    seen = set(hit.labels[np.isfinite(hit.ranges), 3].tolist())
    assert seen == {1}  # the far circle (id 0) lies wholly in the near one's shadow
    assert hit.ranges[20] == pytest.approx(1.9)


def test_segment_and_ellipse_distances() -> None:
    fan = BeamFan(0.0, math.radians(1.0), 1)  # one beam along +x
    wall = cast(fan, _shapes(segments=[(3.0, -1.0, 3.0, 1.0)]))
    assert wall.ranges[0] == pytest.approx(3.0)
    assert wall.labels[0, 3] == 200
    # ellipse at (2, 0), semi-axes 0.2 (along its x) and 0.14, turned 90 deg: the beam
    # meets it at 2 - 0.14
    ell = cast(fan, _shapes(ellipses=[(2.0, 0.0, 0.2, 0.14, math.pi / 2)]))
    assert ell.ranges[0] == pytest.approx(1.86)
    unturned = cast(fan, _shapes(ellipses=[(2.0, 0.0, 0.2, 0.14, 0.0)]))
    assert unturned.ranges[0] == pytest.approx(1.8)


def test_oblique_segment_hit_distance() -> None:
    # the line x + y = 2 meets the beam at 45 deg at distance sqrt(2)
    fan = BeamFan(math.radians(45.0), math.radians(1.0), 1)
    hit = cast(fan, _shapes(segments=[(2.0, 0.0, 0.0, 2.0)]))
    assert hit.ranges[0] == pytest.approx(math.sqrt(2.0))


def test_circle_across_angle_min_wraps_round_a_full_turn() -> None:
    # a 360 deg scanner starting at -pi: a circle straight behind (bearing pi) is hit by
    # the first and the last beams
    inc = math.radians(0.5)
    fan = BeamFan(-math.pi, inc, 720)
    hit = cast(fan, _shapes(circles=[(-2.0, 0.0, 0.1)]))
    hits = np.flatnonzero(np.isfinite(hit.ranges))
    assert set(hits.tolist()) == {0, 1, 2, 3, 4, 5, 715, 716, 717, 718, 719}
    assert hit.ranges[0] == pytest.approx(1.9)


def test_nothing_hit_gives_inf_and_no_labels() -> None:
    fan = BeamFan(-1.0, 0.01, 201)
    hit = cast(fan, Primitives.empty())
    assert np.all(np.isinf(hit.ranges))
    assert np.all(hit.labels == -1)


def test_shape_behind_the_sensor_is_not_hit() -> None:
    fan = BeamFan(math.radians(-10.0), math.radians(0.5), 41)
    hit = cast(fan, _shapes(circles=[(-2.0, 0.0, 0.1)], segments=[(-3.0, -1.0, -3.0, 1.0)]))
    assert np.all(np.isinf(hit.ranges))
