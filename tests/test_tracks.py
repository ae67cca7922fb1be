"""A reported track: its fields as given, arrays as float64 of the right shape, frozen."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from laserpeople.tracks import Track


def test_track_keeps_float64_arrays_and_converts_the_rest() -> None:
    """Float64 arrays of the right shape (what the trackers give) are kept as they are, not
    copied; lists, float32 and byte-swapped arrays, and flat covariances become float64
    arrays of shape (2,), (2,) and (2, 2) with the same values."""
    mean = np.array([1.0, 2.0, 0.5, -0.5])
    cov = np.arange(16.0).reshape(4, 4)
    pos, vel, pcov = mean[:2], mean[2:4], cov[:2, :2]
    t = Track(7, "leg", pos, vel, pcov, score=0.25)
    assert t.position is pos and t.velocity is vel and t.covariance is pcov
    assert (t.track_id, t.kind, t.size, t.labels, t.score, t.members) == (7, "leg", 1, "", 0.25, ())
    assert t.contour.shape == (0, 2)
    u = Track(
        8,
        "person",
        [3, 4],
        np.array([0.1, 0.2], dtype=np.float32),
        np.array([1.0, 0.5, 0.5, 2.0], dtype=">f8"),
        members=(1, 2),
    )
    assert u.position.dtype == np.float64 and u.position.tolist() == [3.0, 4.0]
    assert u.velocity.dtype == np.float64 and u.velocity.shape == (2,)
    np.testing.assert_allclose(u.velocity, [0.1, 0.2], rtol=1e-7)
    assert u.covariance.dtype == np.dtype(np.float64) and u.covariance.dtype.isnative
    assert u.covariance.tolist() == [[1.0, 0.5], [0.5, 2.0]]
    assert u.members == (1, 2)
    with pytest.raises(ValueError):
        Track(9, "leg", [1.0, 2.0, 3.0], [0.0, 0.0], np.eye(2))


def test_track_is_frozen_and_replace_keeps_the_rest() -> None:
    """A track cannot be changed in place; ``dataclasses.replace`` gives a new one with the
    other fields (the contour too); a track without a contour has an empty (0, 2) one."""
    contour = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    t = Track(3, "group", [1.0, 1.0], [0.0, 0.0], np.eye(2), size=2, labels="1|2", contour=contour)
    with pytest.raises(dataclasses.FrozenInstanceError):
        t.track_id = 4  # type: ignore[misc]
    r = dataclasses.replace(t, track_id=4)
    assert (r.track_id, r.size, r.labels) == (4, 2, "1|2") and r.contour is contour
    assert [f.name for f in dataclasses.fields(Track)][-1] == "contour"
    a = Track(1, "leg", [0.0, 0.0], [0.0, 0.0], np.eye(2))
    assert a.contour.shape == (0, 2) and a.contour.dtype == np.float64
