"""Text a user gave (file names, topics, track ids, notes) is printed as written: rich takes
``[a]`` for markup and drops it, and draws ``:fire:`` as an emoji, unless told not to."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest
from typer.testing import CliRunner

from laserpeople.cli import app

NAME = "run[a]:fire:"
"""A file name rich would print as ``run🔥`` (markup tag dropped, emoji code drawn)."""


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from laserpeople.sim.scenarios import run_scenario

    path = tmp_path_factory.mktemp("text") / f"{NAME}.npz"
    run_scenario("figure-eight", seconds=4.0, seed=3).write(path)
    return path


@pytest.fixture(scope="module")
def tracks(recording: Path) -> Path:
    """Tracks of ``recording`` whose ids are text with brackets (``[b]0``)."""
    plain = recording.with_name("plain.csv")
    run = CliRunner().invoke(app, ["--quiet", "track", str(recording), "-o", str(plain)])
    assert run.exit_code == 0, run.output
    with plain.open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    out = recording.with_name(f"{NAME}.csv")
    with out.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        for row in rows:
            writer.writerow({**row, "track_id": f"[b]{row['track_id']}"})
    return out


def test_info_prints_the_file_name_as_written(recording: Path) -> None:
    run = CliRunner().invoke(app, ["info", str(recording)])
    assert run.exit_code == 0, run.output
    assert f"{NAME}.npz" in run.output


def test_bench_prints_the_file_name_as_written(recording: Path) -> None:
    run = CliRunner().invoke(
        app, ["--quiet", "bench", str(recording), "--tracker", "nn", "--repeat", "1"]
    )
    assert run.exit_code == 0, run.output
    assert f"{NAME}.npz: " in run.output


def test_evaluate_of_many_prints_each_name_as_written(recording: Path, tracks: Path) -> None:
    other = tracks.with_name("[c]other.csv")
    other.write_bytes(tracks.read_bytes())
    run = CliRunner().invoke(
        app,
        ["evaluate", str(tracks), str(other), "--truth", str(recording), "--truth", str(recording)],
    )
    assert run.exit_code == 0, run.output
    table = run.stdout
    assert f"│ {NAME} " in table and "│ [c]other " in table


def test_evaluate_followed_person_prints_text_track_ids_as_written(
    recording: Path, tracks: Path
) -> None:
    run = CliRunner().invoke(
        app, ["evaluate", str(tracks), "--truth", str(recording), "--followed-person", "auto"]
    )
    assert run.exit_code == 0, run.output
    assert "frames per id: [b]" in run.stdout


def test_fit_prints_recordings_and_notes_as_written(capsys: pytest.CaptureFixture[str]) -> None:
    from laserpeople.cli.fit import _print
    from laserpeople.fitting.estimates import Estimate
    from laserpeople.fitting.flow import FitResult
    from laserpeople.fitting.validate import ValidationRow

    result = FitResult(
        tracker="leg-mht",
        params=None,
        estimates=(Estimate("p_det_free", 0.5, "12 of 24 scans of [leg] tracks", 24),),
        kept=(),
        counts="",
        training=(NAME,),
        validation=(NAME,),
        rows=(ValidationRow(NAME, "default", {"MOTA": 0.5}),),
    )
    _print(result)
    out = capsys.readouterr().out
    assert "12 of 24 scans of [leg] tracks" in out and f"│ {NAME} " in out


def test_an_error_names_the_file_as_written(tmp_path: Path) -> None:
    """The error line (a pipe or a terminal alike) keeps ``[a]`` and ``:fire:``."""
    import os
    import subprocess
    import sys

    src = Path(__file__).resolve().parents[1] / "src"
    missing = tmp_path / f"{NAME}.bag"
    done = subprocess.run(
        [sys.executable, "-m", "laserpeople.cli", "info", str(missing)],
        env=dict(os.environ, PYTHONPATH=str(src)),
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 1
    assert done.stderr.startswith(f"error: {missing}: file not found"), done.stderr


def test_status_lines_on_a_terminal_keep_the_text(monkeypatch: pytest.MonkeyPatch) -> None:
    """On a terminal status lines go through rich: still no markup and no emoji."""
    import io

    from rich.console import Console

    from laserpeople.cli import common

    buf = io.StringIO()
    monkeypatch.setattr(common, "_isatty", lambda stream: True)
    monkeypatch.setattr(common.STATE, "quiet", False)
    monkeypatch.setattr(common.err_console, "_console", Console(file=buf, width=200))
    common.say(f"wrote {NAME}.csv")
    common.warn("bad value of [leg_tracker] people.gate")
    assert buf.getvalue() == (
        f"wrote {NAME}.csv\nwarning: bad value of [leg_tracker] people.gate\n"
    )
