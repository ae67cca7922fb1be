"""Who steps first in benchmarks/bench_scaling.py's side-by-side loop: balanced on every
pair of scans and on every subsequence of scans whose period is a power of two."""

from __future__ import annotations

import sys
from pathlib import Path
from types import ModuleType


def bench_scaling() -> ModuleType:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    import bench_scaling

    return bench_scaling


def test_first_scans_are_the_thue_morse_sequence() -> None:
    first = [bench_scaling().goes_first(s) for s in range(16)]
    assert first == [0, 1, 1, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 1, 1, 0]


def test_each_pair_of_scans_has_one_of_each() -> None:
    goes_first = bench_scaling().goes_first
    for k in range(512):
        assert {goes_first(2 * k), goes_first(2 * k + 1)} == {0, 1}


def test_every_power_of_two_period_is_balanced() -> None:
    """Every 2nd, 4th, ... 64th scan from any offset: as many firsts for each tree over
    1024 scans (a plain alternation gives the same tree every 2nd and every 16th scan)."""
    goes_first = bench_scaling().goes_first
    for period in (2, 4, 8, 16, 32, 64):
        for offset in range(period):
            picked = [goes_first(s) for s in range(offset, 1024, period)]
            assert sum(picked) * 2 == len(picked), (period, offset)
