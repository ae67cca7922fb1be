"""Regressions from the acceptance pass of `laserpeople simulate`."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from laserpeople.errors import LaserPeopleError, RecordingError
from laserpeople.sim import run_scenario


@pytest.mark.parametrize(("seconds", "rate"), [(math.inf, None), (1.0, math.inf)])
def test_infinite_seconds_or_rate_is_a_user_error(seconds: float, rate: float | None) -> None:
    with pytest.raises(LaserPeopleError, match="must be positive and finite"):
        run_scenario("demo", seconds=seconds, rate=rate)


def test_unwritable_npz_output_is_one_line_error(tmp_path: Path) -> None:
    result = run_scenario("demo", seconds=0.1)
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    target = blocker / "out.npz"
    with pytest.raises(RecordingError, match=r"out\.npz: cannot write the recording"):
        result.write(target)
