"""DistinctIds: the same count and membership as a plain set, in runs of consecutive ids."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.distinct_ids import DistinctIds


def test_runs_merge_from_both_sides() -> None:
    ids = DistinctIds()
    for i in (5, 7, 6, 1, 3, 2):
        ids.add(i)
    # 5, 7 -> two runs; 6 joins them; 1, 3 -> two more; 2 joins those: {1..3}, {5..7}
    assert len(ids) == 6 and ids.runs == 2
    assert [i in ids for i in range(9)] == [False, True, True, True, False, True, True, True, False]
    ids.add(4)
    assert len(ids) == 7 and ids.runs == 1
    ids.add(4)
    assert len(ids) == 7
    assert "4" not in ids


@pytest.mark.parametrize("seed", range(5))
def test_same_as_a_set(seed: int) -> None:
    rng = np.random.default_rng(seed)
    ids = DistinctIds()
    plain: set[int] = set()
    for i in rng.integers(-20, 200, size=600).tolist():
        ids.add(i)
        plain.add(i)
        assert len(ids) == len(plain)
    assert all((i in ids) == (i in plain) for i in range(-25, 205))


def test_counted_up_ids_take_one_run() -> None:
    ids = DistinctIds()
    for scan in range(1000):
        for i in range(scan // 10, scan // 10 + 5):  # live tracks, ids counted up
            ids.add(i)
    assert len(ids) == 104 and ids.runs == 1
