"""Regressions from the acceptance pass of `laserpeople evaluate`: bad tracks files and
per-frame outputs give one-line errors naming the file."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import EvaluationError, RecordingError
from laserpeople.evaluation.detail import FrameTable
from test_viz_support import write_scene

runner = CliRunner()


def _evaluate(*args: str) -> BaseException | None:
    res = runner.invoke(app, ["evaluate", *args])
    assert res.exit_code != 0
    return res.exception


def test_tracks_directory_binary_and_unsorted(tmp_path: Path) -> None:
    rec, csv = write_scene(tmp_path, n=6)
    folder = tmp_path / "dir.csv"
    folder.mkdir()
    exc = _evaluate(str(folder), "--truth", str(rec))
    assert isinstance(exc, EvaluationError)
    assert "is a folder but not the --out folder of `laserpeople batch`" in str(exc)
    exc = _evaluate(str(rec), "--truth", str(rec))  # the .npz given as tracks
    assert isinstance(exc, EvaluationError) and "is a recording (.npz), not tracks" in str(exc)
    binary = tmp_path / "binary.csv"  # binary bytes under a tracks file's name
    binary.write_bytes(rec.read_bytes())
    exc = _evaluate(str(binary), "--truth", str(rec))
    assert isinstance(exc, RecordingError) and "not a text CSV" in str(exc)
    lines = csv.read_text().splitlines()
    unsorted = tmp_path / "unsorted.csv"
    unsorted.write_text("\n".join([lines[0], *reversed(lines[1:])]) + "\n")
    exc = _evaluate(str(unsorted), "--truth", str(rec))
    assert isinstance(exc, RecordingError)
    assert str(exc).startswith(f"{unsorted}: scan ")


def test_per_frame_unwritable(tmp_path: Path) -> None:
    rec, csv = write_scene(tmp_path, n=6)
    exc = _evaluate(str(csv), "--truth", str(rec), "--per-frame", str(tmp_path))
    assert isinstance(exc, EvaluationError) and "is a directory" in str(exc)
    blocker = tmp_path / "file"
    blocker.write_text("x")
    table = FrameTable(("scan", "stamp"), ((0, 0.0),))
    with pytest.raises(EvaluationError, match="cannot write the per-frame table"):
        table.to_csv(blocker / "pf.csv")
