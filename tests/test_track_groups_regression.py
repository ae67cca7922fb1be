"""The group tracker's decisions are unchanged by changes to its speed: tracks, sizes,
labels, events, point groups, hypothesis counts and errors equal the recorded reference
(tests/group_tracker_reference.py; regenerate with ``python tests/group_tracker_reference.py``
when a change of decisions is intended)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from numpy.typing import NDArray

from group_tracker_reference import (
    DEMO_BAG,
    REFERENCE,
    bag_arrays,
    extensions_arrays,
    people_only_arrays,
    sim_arrays,
)

FLOAT_TOL = 1e-9


def _assert_same(got: dict[str, NDArray], prefix: str) -> None:  # type: ignore[type-arg]
    expected = np.load(REFERENCE, allow_pickle=False)
    for name in ("labels", "events", "points", "point_frames", "stats"):
        np.testing.assert_array_equal(got[prefix + name], expected[prefix + name], err_msg=name)
    rows, ref = got[prefix + "rows"], expected[prefix + "rows"]
    assert rows.shape == ref.shape
    np.testing.assert_array_equal(rows[:, :3], ref[:, :3])  # frame, track id, size
    np.testing.assert_allclose(rows[:, 3:], ref[:, 3:], rtol=0.0, atol=FLOAT_TOL)


@pytest.mark.slow
def test_group_tracker_output_identical_on_simulated_hall() -> None:
    got = sim_arrays()
    _assert_same(got, "sim_")
    expected = np.load(REFERENCE, allow_pickle=False)["sim_errors"]
    np.testing.assert_allclose(got["sim_errors"], expected, rtol=0.0, atol=FLOAT_TOL)


@pytest.mark.slow
def test_people_only_tracker_output_identical_on_simulated_hall() -> None:
    _assert_same(people_only_arrays(), "people_")


@pytest.mark.slow
def test_optional_paths_output_identical_on_simulated_hall() -> None:
    _assert_same(extensions_arrays(), "ext_")


def test_group_tracker_output_identical_on_demo_bag(shared_data: Path) -> None:
    if not (shared_data / DEMO_BAG).is_file():
        import pytest

        pytest.skip(f"{DEMO_BAG} not in the shared data")
    _assert_same(bag_arrays(shared_data), "bag_")
