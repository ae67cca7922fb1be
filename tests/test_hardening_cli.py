"""`track` says what the tracker's input guard changed (issue 16)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.sim import SimResult


def test_track_prints_the_input_guard_summary(tmp_path: Path) -> None:
    from laserpeople.sim.scenarios import run_scenario

    result = run_scenario("figure-eight", seconds=3.0, seed=1)
    scans = list(result.scans)
    for k in range(5, 9):  # four scans with the stamp of scan 4
        scans[k] = replace(scans[k], stamp=scans[4].stamp)
    path = tmp_path / "repeated.npz"
    SimResult(scans, result.truth, result.meta).write(path)
    out = tmp_path / "t.csv"
    run = CliRunner().invoke(app, ["track", str(path), "-o", str(out)])
    assert run.exit_code == 0, run.output
    assert "input guard: 4 scans with the same stamp as the one before" in run.output


def test_train_on_error_skips_damaged_scans(tmp_path: Path) -> None:
    import numpy as np

    from laserpeople.errors import RecordingError
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "walk.npz"
    run_scenario("figure-eight", seconds=3.0, seed=2).write(rec)
    with np.load(rec) as z:
        arrays = {k: z[k] for k in z.files}
    arrays["scan_stamp"][3] = np.nan
    np.savez(rec, **arrays)  # type: ignore[arg-type]
    model = tmp_path / "m.json"
    stop = CliRunner().invoke(app, ["train", str(rec), "-o", str(model), "--rounds", "2"])
    assert isinstance(stop.exception, RecordingError) and "scan 3" in str(stop.exception)
    skip = CliRunner().invoke(
        app, ["train", str(rec), "-o", str(model), "--rounds", "2", "--on-error", "skip"]
    )
    assert skip.exit_code == 0, skip.output
    assert "skipped 1 damaged scan" in skip.output and model.exists()


def test_track_reports_all_equal_stamps(tmp_path: Path) -> None:
    from laserpeople.sim.scenarios import run_scenario

    result = run_scenario("figure-eight", seconds=2.0, seed=1)
    scans = [replace(s, stamp=5.0) for s in result.scans]
    path = tmp_path / "equal.npz"
    SimResult(scans, result.truth, result.meta).write(path)
    run = CliRunner().invoke(app, ["track", str(path), "-o", str(tmp_path / "t.csv")])
    assert run.exit_code == 0, run.output
    assert f"{len(scans) - 1} scans with the same stamp as the one before" in run.output


def test_nonsense_parameters_and_mounts_are_errors() -> None:
    import math

    import pytest

    from laserpeople.detection.detector import LegDetectorParams
    from laserpeople.errors import ConfigError
    from laserpeople.io.poses import parse_mounts
    from laserpeople.tracking.kalman import KalmanParams
    from laserpeople.tracking.legs import LegTrackerParams

    with pytest.raises(ValueError, match="finite"):
        LegTrackerParams(lambda_new=math.inf)
    with pytest.raises(ValueError, match="finite"):
        KalmanParams(accel_psd=math.inf)
    with pytest.raises(ValueError, match="centre_offset must be finite"):
        LegDetectorParams(centre_offset=math.nan)
    with pytest.raises(ValueError, match="score_threshold must be finite"):
        LegDetectorParams(score_threshold=-math.inf)
    for bad in ("laser=base:1e308,0,0", "laser=base:0,nan,0", "laser=base:0,0,inf"):
        with pytest.raises(ConfigError, match="off its robot"):
            parse_mounts([bad])
    assert parse_mounts(["laser=base:0.2,0,1.57"])["laser"][1].x == 0.2
