"""The leg tracker's results are unchanged by changes to the MHT core (the reference was
recorded before the core learnt per-branch observations for the group tracker)."""

from __future__ import annotations

import numpy as np
import pytest

from leg_mht_reference import REFERENCE, SCENES, run_scene


@pytest.mark.parametrize(("name", "seconds", "seed"), SCENES)
def test_leg_mht_output_identical_to_reference(name: str, seconds: float, seed: int) -> None:
    expected = np.load(REFERENCE)[f"{name}_{seed}"]
    got = run_scene(name, seconds, seed)[f"{name}_{seed}"]
    assert got.shape == expected.shape
    np.testing.assert_array_equal(got, expected)
