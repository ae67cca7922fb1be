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


def test_track_refuses_a_stuck_clock_and_restamps_on_request(tmp_path: Path) -> None:
    from laserpeople.io.tracks_csv import iter_tracks_csv
    from laserpeople.sim.scenarios import run_scenario

    result = run_scenario("figure-eight", seconds=8.0, seed=1)  # 37.5 Hz
    good = tmp_path / "good.npz"
    result.write(good)
    scans = [replace(s, stamp=5.0) if s.index >= 220 else s for s in result.scans]
    path = tmp_path / "equal.npz"
    SimResult(scans, result.truth, result.meta).write(path)
    out = tmp_path / "t.csv"
    run = CliRunner().invoke(app, ["track", str(path), "-o", str(out)])
    assert run.exit_code != 0
    message = str(run.exception)
    assert "scans 220-239" in message and "--restamp HZ" in message
    written = list(iter_tracks_csv(out))  # what was written before stays valid
    assert written and written[-1].scan_index < 239

    runs = {}
    for name, rec, extra in [("recorded", good, []), ("restamped", path, ["--restamp", "37.5"])]:
        csv = tmp_path / f"{name}.csv"
        run = CliRunner().invoke(app, ["track", str(rec), "-o", str(csv), *extra])
        assert run.exit_code == 0, run.output
        runs[name] = [(t.scan_index, len(t)) for t in iter_tracks_csv(csv)]
    assert "re-stamped 301 scans at 37.5 Hz" in run.output
    assert runs["restamped"] == runs["recorded"]  # the simulator's own rate: same tracks
    assert any(n for _, n in runs["restamped"])


def test_restamp_counts_per_laser_and_rejects_nonsense() -> None:
    import math

    import numpy as np
    import pytest

    from laserpeople.errors import ConfigError, LaserPeopleError
    from laserpeople.pipeline.stamps import Restamp, StampCheck
    from laserpeople.scan import Scan

    def scan(sensor: str, stamp: float, index: int) -> Scan:
        return Scan(stamp, -1.0, 0.1, np.ones(21), sensor=sensor, index=index)

    seq = [scan("a", 3.0, 0), scan("b", 3.05, 0), scan("a", 3.0, 1), scan("b", 9.0, 1)]
    restamp = Restamp(20.0)
    assert [s.stamp for s in restamp(seq)] == pytest.approx([3.0, 3.05, 3.05, 3.1])
    assert (restamp.restamped, restamp.changed) == (4, 2)
    for bad in (0.0, -1.0, math.nan, math.inf):
        with pytest.raises(ConfigError, match="--restamp"):
            Restamp(bad)
    check = StampCheck(limit=3)
    assert len(list(check(seq))) == 4  # two laser, each advancing: fine
    with pytest.raises(LaserPeopleError, match="scans 1-3 of laser 'a'"):
        list(check([scan("a", 1.0, 0), scan("a", 2.0, 1), scan("a", 2.0, 2), scan("a", 2.0, 3)]))


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


def test_scans_recorded_twice_are_dropped_and_said(tmp_path: Path) -> None:
    """Copies of a scan (the same laser, stamp and ranges, as a bag recorded from two
    subscribers holds) are dropped and counted; the tracks are those of the recording
    without them. A scan with the previous stamp but its own ranges is no copy."""
    import numpy as np

    from laserpeople.io.tracks_csv import iter_tracks_csv
    from laserpeople.pipeline.duplicate_scans import DuplicateScanCheck
    from laserpeople.scan import Scan
    from laserpeople.sim.scenarios import run_scenario

    result = run_scenario("figure-eight", seconds=3.0, seed=1)
    scans = list(result.scans)
    twice = [*scans[:11], scans[10], scans[10], *scans[11:40], scans[39], *scans[40:]]
    paths = {"once": tmp_path / "once.npz", "twice": tmp_path / "twice.npz"}
    SimResult(scans, result.truth, result.meta).write(paths["once"])
    SimResult(twice, result.truth, result.meta).write(paths["twice"])
    rows = {}
    for name, path in paths.items():
        out = tmp_path / f"{name}.csv"
        run = CliRunner().invoke(app, ["track", str(path), "-o", str(out)])
        assert run.exit_code == 0, run.output
        rows[name] = [
            [(t.track_id, t.kind, *np.round(t.position, 9)) for t in tracks]
            for tracks in iter_tracks_csv(out)
        ]
        if name == "twice":
            said = " ".join(run.output.split())
            assert f"3 of {len(twice)} scans were copies of the scan before them" in said
            assert "the first: scan 10 of laser" in said  # (the npz keeps the copy's index)
    assert rows["twice"] == rows["once"] and any(rows["once"])

    def scan(stamp: float, ranges: list[float], intensities: list[float] | None = None) -> Scan:
        return Scan(stamp, -1.0, 0.5, np.array(ranges), intensities=None
                    if intensities is None else np.array(intensities))  # fmt: skip

    check = DuplicateScanCheck()
    seq = [
        scan(1.0, [1.0, np.nan, 2.0]),
        scan(1.0, [1.0, np.nan, 2.0]),  # a copy (NaN where NaN)
        scan(1.0, [1.0, np.nan, 2.5]),  # the same stamp, other ranges: kept
        scan(1.0, [1.0, np.nan, 2.5], [5.0, 0.0, 7.0]),  # intensities now: kept
        scan(1.0, [1.0, np.nan, 2.5], [5.0, 0.0, 8.0]),  # other intensities: kept
        scan(1.1, [1.0, np.nan, 2.5], [5.0, 0.0, 8.0]),  # another stamp: kept
        replace(scan(1.1, [1.0, np.nan, 2.5], [5.0, 0.0, 8.0]), sensor="b"),  # another laser
    ]
    kept = list(check(seq))
    assert [s.stamp for s in kept] == [1.0, 1.0, 1.0, 1.0, 1.1, 1.1]
    assert (check.scans, check.dropped) == (7, 1)
    assert DuplicateScanCheck().summary() == ""
