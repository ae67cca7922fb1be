"""Commands that changed what they worked on without a word: what they used is said."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app


@pytest.fixture(scope="module")
def poses_stop(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, int, int]:
    """A simulated walk whose last 20 scans have no sensor pose: (path, scans, posed)."""
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path_factory.mktemp("bench") / "walk.npz"
    run_scenario("figure-eight", seconds=2.0, seed=1).write(rec)
    with np.load(rec) as z:
        arrays = {k: z[k] for k in z.files}
    n = len(arrays["scan_stamp"])
    arrays["scan_pose"][n - 20 :] = np.nan
    np.savez(rec, **arrays)  # type: ignore[arg-type]
    return rec, n, n - 20


def test_bench_says_the_frame_and_the_frames_it_timed(poses_stop: tuple[Path, int, int]) -> None:
    rec, n, posed = poses_stop
    run = CliRunner().invoke(app, ["bench", str(rec), "--tracker", "nn", "--repeat", "1"])
    assert run.exit_code == 0, run.output
    assert f"trackers timed on {posed} frames, working in the world frame" in run.output
    assert "20 frames skipped and 0 scans dropped for lack of a sensor pose" in run.output
    as_json = CliRunner().invoke(
        app, ["--quiet", "bench", str(rec), "--tracker", "nn", "--repeat", "1", "--json"]
    )
    doc = json.loads(as_json.stdout)
    assert (doc["scans"], doc["tracking_frame"], doc["tracked_frames"]) == (n, "world", posed)


@pytest.mark.parametrize(
    ("window", "said"),
    [
        (["--start", "5000"], "(scans from 5000): topic laser holds scans 0-{last}"),
        (["--start", "500", "--stop", "600"], "(scans 500-599): topic laser holds scans 0-{last}"),
    ],
)
@pytest.mark.parametrize("out", ["v.png", "v.gif"])
def test_view_of_a_window_beyond_the_recording_names_the_scans_it_holds(
    poses_stop: tuple[Path, int, int], tmp_path: Path, window: list[str], said: str, out: str
) -> None:
    rec, n, _ = poses_stop
    run = CliRunner().invoke(app, ["view", str(rec), "-o", str(tmp_path / out), *window])
    assert run.exit_code == 1
    assert f"no scans in the chosen window {said.format(last=n - 1)}" in str(run.exception)
    assert not (tmp_path / out).exists()
