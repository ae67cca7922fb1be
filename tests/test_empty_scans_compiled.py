"""A scan's beams without a valid return by kind, compiled (``beam_kinds`` of the MHT's C
extension), against its numpy reference: the same counts, and the same number of beams
left out, on scans made of every kind and of the values on either side of the limits."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest

from laserpeople.pipeline import empty_scans
from laserpeople.pipeline.empty_scans import (
    BEAM_KINDS,
    EmptyScanCheck,
    beam_kinds,
    beam_kinds_python,
)
from laserpeople.scan import Scan


def _compiled() -> Callable[..., object]:
    import laserpeople.tracking.mht.listing  # noqa: F401  (loads the extension)

    compiled = empty_scans._compiled_beam_kinds()
    if compiled is None:
        pytest.skip("the C extension is not built, or stale")
    return compiled


def _scan(ranges: np.ndarray, range_min: float, range_max: float) -> Scan:
    return Scan(1.0, -1.0, 0.01, ranges, range_min, range_max, sensor="a")


def _limits(rng: np.random.Generator) -> tuple[float, float]:
    """Limits of every sort a driver writes: zero, negative or positive range_min, a finite
    or infinite range_max, equal limits."""
    lo = float(rng.choice([0.0, -1.0, 0.02, 0.1, 1.5]))
    hi = float(rng.choice([5.6, 30.0, math.inf, max(lo, 0.5)]))
    return lo, max(lo, hi)


def _ranges(rng: np.random.Generator, lo: float, hi: float, n: int) -> np.ndarray:
    """Ranges drawn from every kind and from the limits and their neighbouring floats."""
    special = [math.nan, math.inf, -math.inf, 0.0, -0.0, -2.0, -1e-300, 5e-324]
    edges = [lo, hi, np.nextafter(lo, -math.inf), np.nextafter(lo, math.inf)]
    edges += [np.nextafter(hi, -math.inf), np.nextafter(hi, math.inf)]
    pool = np.array([*special, *edges], dtype=np.float64)
    r = rng.uniform(-1.0, 40.0, n)
    pick = rng.random(n) < 0.5
    r[pick] = rng.choice(pool, int(pick.sum()))
    return r


def test_compiled_counts_are_the_references() -> None:
    """2000 random scans: the same counts of each kind, and the same beams left out."""
    compiled = _compiled()
    rng = np.random.default_rng(35)
    for _ in range(2000):
        lo, hi = _limits(rng)
        scan = _scan(_ranges(rng, lo, hi, int(rng.integers(0, 60))), lo, hi)
        counts = np.zeros(len(BEAM_KINDS), dtype=np.int64)
        bad = compiled(scan.ranges, scan.range_min, scan.range_max, counts)
        assert counts.tolist() == beam_kinds_python(scan).tolist()
        assert bad == scan.n_invalid
        assert beam_kinds(scan).tolist() == counts.tolist()


def test_compiled_counts_by_hand() -> None:
    """Each kind where a wrong test would move it: NaN is no negative, +inf no 'over
    range_max', -0.0 is zero, a range equal to a limit is a return, the float above
    range_max is over it and the one below range_min under it."""
    compiled = _compiled()
    lo, hi = 0.1, 8.0
    below, above = float(np.nextafter(lo, 0.0)), float(np.nextafter(hi, 9.0))
    r = np.array([math.nan, math.inf, -math.inf, -0.0, 0.0, -3.0, lo, hi, 4.0, below, above, 1e300])
    counts = np.zeros(7, dtype=np.int64)
    assert compiled(r, lo, hi, counts) == 9
    assert dict(zip(BEAM_KINDS, counts.tolist(), strict=True)) == {
        "NaN": 1,
        "+inf": 1,
        "-inf": 1,
        "negative": 1,
        "zero": 2,
        "under range_min": 1,
        "over range_max": 2,
    }


def test_compiled_refuses_what_it_does_not_expect() -> None:
    """Limits that are not Python floats, ranges not float64 or not one row, a counts array
    of another size or type: NotImplemented, nothing written (the reference runs)."""
    compiled = _compiled()
    r = np.array([1.0, math.nan, 0.0, 9.0])
    for args in (
        (r, 0, 8.0),  # an int limit
        (r, np.float64(0.1), 8.0),  # a numpy scalar
        (r.astype(np.float32), 0.1, 8.0),
        (np.stack([r, r]), 0.1, 8.0),
        (r[::2], 0.1, 8.0),  # not contiguous
    ):
        counts = np.full(7, -1, dtype=np.int64)
        assert compiled(*args, counts) is NotImplemented
        assert counts.tolist() == [-1] * 7
    assert compiled(r, 0.1, 8.0, np.zeros(6, dtype=np.int64)) is NotImplemented
    assert compiled(r, 0.1, 8.0, np.zeros(7, dtype=np.float64)) is NotImplemented


def test_check_counts_empty_scans_either_way(monkeypatch: pytest.MonkeyPatch) -> None:
    """The check counts the same kinds and the same empty scans compiled and in numpy, and
    as many empty scans as have no valid beam."""
    rng = np.random.default_rng(7)
    scans = []
    for k in range(300):
        lo, hi = _limits(rng)
        r = _ranges(rng, lo, hi, int(rng.integers(0, 12)))
        if k % 5 == 0:
            r[:] = math.nan  # no valid beam
        scans.append(_scan(r, lo, hi))
    checks = []
    for compiled in (_compiled(), None):
        monkeypatch.setattr(empty_scans, "_compiled", compiled)
        check = EmptyScanCheck()
        list(check(iter(scans)))
        checks.append((check.kinds.tolist(), check.empty, check.first, check.beams))
    assert checks[0] == checks[1]
    empty = [k for k, scan in enumerate(scans) if not scan.valid.any()]
    assert checks[0][1] == len(empty) >= 60  # (those of all NaN, and those of no beam)
    assert checks[0][2] == ("a", scans[empty[0]].index)
    assert checks[0][0] == np.sum([beam_kinds_python(s) for s in scans], axis=0).tolist()


def test_not_compiled_before_the_listing_is_imported(monkeypatch: pytest.MonkeyPatch) -> None:
    """Without the leg MHT's listing imported (``detect``), the count runs in numpy and is
    asked again at the next scan; once imported, the compiled one is found."""
    compiled = _compiled()
    monkeypatch.setattr(empty_scans, "_compiled", empty_scans._UNLOADED)
    monkeypatch.setattr(empty_scans, "LISTING", "laserpeople.not_imported")
    assert empty_scans._compiled_beam_kinds() is None
    assert empty_scans._compiled is empty_scans._UNLOADED
    monkeypatch.setattr(empty_scans, "LISTING", "laserpeople.tracking.mht.listing")
    assert empty_scans._compiled_beam_kinds() is compiled
