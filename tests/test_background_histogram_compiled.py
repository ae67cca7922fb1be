"""The beam histogram's foreground of a frozen model's frame of one laser, compiled
(``histogram_foreground`` of the MHT's C extension), against its Python reference: the
same foreground of every point and the same relearning."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest

from laserpeople.background import beam_histogram
from laserpeople.background.beam_histogram import BeamHistogramBackground, BeamHistogramParams
from laserpeople.frame import Frame
from laserpeople.scan import PointSet, Scan


def _compiled() -> Callable[..., object]:
    compiled = beam_histogram._compiled_foreground()
    if compiled is None:
        pytest.skip("the C extension is not built, or stale")
    return compiled


def _frame(ranges: np.ndarray, stamp: float, n_beams: int = 181) -> Frame:
    """A sensor-frame frame of one laser (range_min 0.05 m, range_max 30 m)."""
    scan = Scan(stamp, -math.pi / 2, math.pi / (n_beams - 1), ranges, 0.05, 30.0, sensor="a")
    return Frame(0, stamp, (scan,), "a", "sensor", points=PointSet.from_scans([scan], "sensor"))


def _room(seed: int) -> list[Frame]:
    """Walls seen for 4 s of learning and 36 s after: a walker, invalid returns (NaN, 0,
    below range_min, beyond range_max, inf), returns beyond the histogram's last bin, and
    a door that opens at 10 s (its beams see 3 m farther: candidates that relearn after
    ``relearn_seconds``) and a box put down at 25 s."""
    rng = np.random.default_rng(seed)
    n = 181
    walls = np.linspace(4.0, 9.0, n)
    frames = []
    for k in range(400):
        stamp = 0.1 * k
        r = walls + rng.normal(0.0, 0.01, n)
        if stamp >= 10.0:
            r[40:50] += 3.0  # the door
        if stamp >= 25.0:
            r[120:126] = 2.0  # the box
        w = 60 + (k % 80)
        r[w : w + 5] = rng.uniform(1.0, 3.0)
        r[rng.integers(0, n, 3)] = [np.nan, 0.0, 0.01]
        if k % 11 == 5:
            r[rng.integers(0, n, 2)] = [40.0, np.inf]
        if k % 13 == 7:
            r[rng.integers(0, n)] = 29.99  # (past the bins learnt: the last bin)
        frames.append(_frame(r, stamp))
    return frames


@pytest.mark.regression  # two code paths: CI runs it again on another CPU path
@pytest.mark.parametrize("relearn_seconds", [0.0, 3.0])
def test_compiled_foreground_is_the_python_one(
    monkeypatch: pytest.MonkeyPatch, relearn_seconds: float
) -> None:
    """Two models learn the same frames, one compiled and one in Python: every frame's
    foreground is the same, and so are the candidates, their stamps, the histograms and
    the static bins (the door's beams relearn: some frames have returns beyond their
    static world, which the Python relearning follows)."""
    compiled = _compiled()
    answered = {False: 0, True: 0}

    def counted(*args: object) -> object:
        out = compiled(*args)
        if out is not NotImplemented:
            answered[bool(out)] += 1
        return out

    params = BeamHistogramParams(relearn_seconds=relearn_seconds)
    fast, slow = BeamHistogramBackground(params), BeamHistogramBackground(params)
    for frame in _room(3):
        monkeypatch.setattr(beam_histogram, "_foreground_compiled", counted)
        got = fast.learn_foreground(frame)
        monkeypatch.setattr(beam_histogram, "_foreground_compiled", None)
        want = slow.learn_foreground(frame)
        assert got.dtype == want.dtype and got.tolist() == want.tolist()
    a, b = fast._tables["a"], slow._tables["a"]
    for name in ("counts", "static", "nearest", "candidate", "since"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert answered[False] > 100
    assert (answered[True] > 5) == (relearn_seconds > 0.0)  # (True: beyond, relearning)
    assert (a.relearned > 0) == (relearn_seconds > 0.0)


def test_the_foreground_of_a_frame_by_hand() -> None:
    """Three beams, four bins of 0.5 m (the last for every range past it): beam 0 at
    0.7 m (bin 1, static) is background, beam 1 at 1.2 m (bin 2, not static) foreground,
    beam 2 invalid (no point, never foreground) and beam 3 at 9 m (the last bin, static)
    background. Points on beams 1, 0, 1: True, False, True. With the candidates and
    nothing beyond the nearest static bins (by more than ``reach``): the valid beams'
    candidates end (-1), False. Beam 1's nearest static bin 0 with reach 1: bin 2 lies
    beyond: True, and the candidates are untouched."""
    compiled = _compiled()
    ranges = np.array([0.7, 1.2, np.nan, 9.0])
    valid = np.array([0, 1, 3])
    static = np.array([[0, 1, 0, 0], [0, 0, 0, 1], [1, 1, 1, 1], [0, 0, 0, 1]], dtype=bool)
    points = np.array([1, 0, 1])
    fg = np.zeros(3, dtype=bool)
    cand = np.array([5, 6, 7, 8])
    nearest = np.array([1, 2, 0, 3])
    args = (ranges, valid, static)
    assert compiled(*args, nearest, None, 0.5, 1, points, fg) is False
    assert fg.tolist() == [True, False, True]
    assert compiled(*args, nearest, cand, 0.5, 1, points, fg) is False
    assert cand.tolist() == [-1, -1, 7, -1]
    cand = np.array([5, 6, 7, 8])
    nearest[1] = 0
    assert compiled(*args, nearest, cand, 0.5, 1, points, fg) is True
    assert cand.tolist() == [5, 6, 7, 8]
    assert compiled(*args, nearest, cand, 0.5, 2, points, fg) is False  # (reach 2: not beyond)


def test_the_compiled_foreground_leaves_to_python_what_it_cannot_read() -> None:
    """NotImplemented, nothing written, for a beam outside the table or the scan, a point
    on a beam outside the scan, a range not finite, arrays of another dtype, or an output
    of another length than the points."""
    compiled = _compiled()
    ranges, valid = np.array([0.7, 1.2]), np.array([0, 1])
    static, nearest = np.zeros((2, 4), dtype=bool), np.zeros(2, dtype=np.int64)
    cand = np.array([3, 3])
    fg = np.zeros(2, dtype=bool)
    points = np.array([0, 1])
    cases = [
        (ranges, np.array([0, 2]), static, nearest, cand, points, fg),
        (ranges, valid, static[:1], nearest[:1], cand[:1], points, fg),
        (ranges, valid, static, nearest, cand, np.array([0, 2]), fg),
        (np.array([0.7, np.inf]), valid, static, nearest, cand, points, fg),
        (ranges.astype(np.float32), valid, static, nearest, cand, points, fg),
        (ranges, valid, static.astype(np.uint8), nearest, cand, points, fg),
        (ranges, valid, static, nearest, cand, points, np.zeros(3, dtype=bool)),
    ]
    for r, v, s, ne, c, pb, out in cases:
        assert compiled(r, v, s, ne, c, 0.5, 1, pb, out) is NotImplemented
        assert not out.any() and c.tolist() == [3, 3][: c.size]
