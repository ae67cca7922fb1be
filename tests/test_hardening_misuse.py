"""Misuse by a demanding new user: every command on odd but readable input says what it did
(hardening, third round; docs/damaged-files.md)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.scan import PointSet, Scan


def _finer(scan: Scan) -> Scan:
    """``scan`` with twice the beams over the same field of view (a driver reconfigured to
    a finer resolution): each range repeated."""
    return Scan(
        stamp=scan.stamp,
        angle_min=scan.angle_min,
        angle_increment=scan.angle_increment / 2,
        ranges=np.repeat(scan.ranges, 2)[:-1].copy(),
        range_min=scan.range_min,
        range_max=scan.range_max,
        sensor=scan.sensor,
        pose=scan.pose,
        index=scan.index,
    )


def test_a_beam_layout_change_mid_recording_is_tracked_and_said(tmp_path: Path) -> None:
    from laserpeople.sim import SimResult
    from laserpeople.sim.scenarios import run_scenario

    result = run_scenario("figure-eight", seconds=6.0, seed=1)
    scans = [s if s.index < 120 else _finer(s) for s in result.scans]
    assert scans[0].n_beams == 361 and scans[-1].n_beams == 721
    path = tmp_path / "finer.npz"
    SimResult(scans, result.truth, result.meta).write(path)
    for tracker in ("leg-mht", "csa"):
        out = tmp_path / f"{tracker}.csv"
        run = CliRunner().invoke(
            app,
            ["track", str(path), "--tracker", tracker, "--background", "histogram", "-o", str(out)],
        )
        assert run.exit_code == 0, run.output
        assert "1 beam layout change(s)" in run.output
        assert "at scan 120: 361 beams from -90.00° every 0.500° before, 721 beams" in run.output
        assert out.read_text().count("\n") > 1


def test_the_beam_histogram_learns_again_after_a_layout_change() -> None:
    from laserpeople.background.beam_histogram import BeamHistogramBackground, BeamHistogramParams
    from laserpeople.frame import Frame

    def frame(k: int, n: int, person: slice = slice(0)) -> Frame:
        ranges = np.full(n, 3.0)
        ranges[person] = 1.5
        scan = Scan(
            stamp=0.1 * k,
            angle_min=-1.0,
            angle_increment=2.0 / (n - 1),
            ranges=ranges,
            range_min=0.05,
            range_max=8.0,
            sensor="laser",
            index=k,
        )
        return Frame(
            index=k,
            stamp=scan.stamp,
            scans=(scan,),
            topic="laser",
            points=PointSet.from_scans([scan], "sensor"),
        )

    params = BeamHistogramParams(learn_seconds=1.0)
    model = BeamHistogramBackground(params)
    for k in range(20):  # 2 s of a wall at 3 m: learnt and frozen
        assert not model.learn_foreground(frame(k, 41)).any()
    assert not model.learning and model.layout_changes == 0
    # the same wall seen by 21 beams, a person on beams 5-7: the 41-beam histograms say
    # nothing about these beams; the model learns again as a new one would
    new = BeamHistogramBackground(params)
    for k in range(20, 40):
        seen = frame(k, 21, slice(5, 8) if k >= 35 else slice(0))
        fg = model.learn_foreground(seen)
        assert np.array_equal(fg, new.learn_foreground(seen))
    assert model.layout_changes == 1 and not model.learning
    assert model.counts("laser").shape == new.counts("laser").shape
    assert np.flatnonzero(fg).tolist() == [5, 6, 7]
