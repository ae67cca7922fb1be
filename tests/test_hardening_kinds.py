"""What a demanding user meets: the kinds of beams left out, truth with text ids, the
evaluation's public views, options and config values that cannot be, outputs that cannot
be written."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from typer.testing import CliRunner

from laserpeople.cli import app

if TYPE_CHECKING:
    from laserpeople.scan import Scan


def _scan(ranges: list[float], range_min: float = 0.1, range_max: float = 8.0) -> Scan:
    from laserpeople.scan import Scan

    return Scan(
        stamp=10.0,
        angle_min=-1.0,
        angle_increment=2.0 / max(len(ranges) - 1, 1),
        ranges=np.array(ranges),
        range_min=range_min,
        range_max=range_max,
        sensor="/front",
        index=0,
    )


def test_each_kind_of_beam_left_out_is_counted_apart() -> None:
    """NaN is no negative, +inf no 'over range_max', zero no 'under range_min'; the limits
    themselves are returns; the kinds add up to the scan's invalid beams."""
    from laserpeople.pipeline.empty_scans import BEAM_KINDS, beam_kinds

    nan, inf = float("nan"), float("inf")
    ranges = [nan, nan, nan, inf, inf, -inf, -1.0, -0.5, -2.0, -3.0, 0.0, 0.0]
    ranges += [0.05, 0.09, 0.02, 0.01, 0.07, 8.5, 9.0, 1e6, 20.0, 30.0, 40.0, 50.0]
    ranges += [0.1, 8.0, 4.0]  # range_min and range_max count as returns
    scan = _scan(ranges)
    counts = beam_kinds(scan)
    assert dict(zip(BEAM_KINDS, counts.tolist(), strict=True)) == {
        "NaN": 3,
        "+inf": 2,
        "-inf": 1,
        "negative": 4,
        "zero": 2,
        "under range_min": 5,
        "over range_max": 7,
    }
    assert int(counts.sum()) == scan.n_invalid
    # range_min 0: a zero range is still 'zero', never 'under range_min'
    zero_min = beam_kinds(_scan([0.0, 0.0, 1.0], range_min=0.0))
    assert zero_min.tolist() == [0, 0, 0, 0, 2, 0, 0]
    assert beam_kinds(_scan([1.0, 2.0])).tolist() == [0] * 7


def test_check_sums_kinds_over_scans_and_says_each() -> None:
    from laserpeople.pipeline.empty_scans import EmptyScanCheck

    nan = float("nan")
    check = EmptyScanCheck()
    list(check(iter([_scan([nan, 1.0, -1.0]), _scan([nan, 9.0, 0.0, 2.0])])))
    assert (check.beams, check.left_out) == (7, 5)
    assert check.beam_summary().startswith(
        "5 of 7 beams had no valid return and were left out "
        "(NaN 2, negative 1, zero 1, over range_max 1;"
    )
    clean = EmptyScanCheck()
    list(clean(iter([_scan([1.0, 2.0])])))
    assert clean.beam_summary() == ""


def test_track_says_each_kind_of_beam_left_out(tmp_path: Path) -> None:
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "bad ranges.npz"
    run_scenario("figure-eight", seconds=2.0, seed=5).write(rec)
    with np.load(rec) as z:
        arrays = {k: z[k] for k in z.files}
    ranges = arrays["ranges"]
    start = int(arrays["scan_offset"][3])
    bad = [np.nan] * 3 + [-np.inf] + [-1.0] * 4 + [0.0] * 2 + [1e6] * 5
    ranges[start : start + len(bad)] = bad
    after = int(np.count_nonzero(np.isposinf(ranges)))
    limit = np.repeat(arrays["scan_range_max"], np.diff(arrays["scan_offset"]))
    over = int(np.count_nonzero(np.isfinite(ranges) & (ranges > limit)))
    np.savez(rec, **arrays)
    run = CliRunner().invoke(app, ["track", str(rec), "-o", str(tmp_path / "t.csv")])
    assert run.exit_code == 0, run.output
    text = " ".join(run.output.split())
    assert f"NaN 3, +inf {after:,}, -inf 1, negative 4, zero 2, over range_max {over};" in text
    assert over >= 5  # the counts are the file's, after the edit
