"""`batch` interrupted with Ctrl-C: the workers do not take the signal (the command shuts
them down), and the command says what was kept and how to go on."""

from __future__ import annotations

import signal
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

pytest.importorskip("dask.distributed")

from laserpeople.batch.run import workers_deaf_to_ctrl_c
from laserpeople.cli import app

CHILD_SAYS = "import signal; print(signal.getsignal(signal.SIGINT) == signal.SIG_IGN)"


def _child_ignores() -> bool:
    """Whether a Python process started now ignores SIGINT."""
    run = subprocess.run([sys.executable, "-c", CHILD_SAYS], capture_output=True, text=True)
    assert run.stdout.strip() in ("True", "False"), run.stderr
    return run.stdout.strip() == "True"


def test_worker_processes_start_with_ctrl_c_ignored_and_this_one_keeps_it() -> None:
    # as a command started from a terminal: Python's handler (a test runner's worker may
    # have been started with Ctrl-C ignored)
    outer = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        assert not _child_ignores()
        with workers_deaf_to_ctrl_c():
            assert _child_ignores()
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
        assert not _child_ignores()
    finally:
        signal.signal(signal.SIGINT, outer)


def test_batch_interrupted_says_what_is_kept_and_how_to_go_on(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import laserpeople.batch

    recordings = []
    for name in ("a", "b", "c"):
        (tmp_path / f"{name}.npz").write_bytes(b"")
        recordings.append(str(tmp_path / f"{name}.npz"))

    def interrupted(*_args: Any, on_done: Any = None, **_kwargs: Any) -> None:
        from laserpeople.batch.task import TopicRow

        on_done([TopicRow(recording=recordings[0], name="a", topic="laser", status="done")])
        raise KeyboardInterrupt

    monkeypatch.setattr(laserpeople.batch, "run_batch", interrupted)
    out = tmp_path / "out"
    run = CliRunner().invoke(app, ["batch", *recordings, "-o", str(out)])
    assert run.exit_code == 130
    assert "1 of 3 recordings finished before the interruption" in run.output
    assert f"{out / 'manifest.jsonl'} are kept" in run.output
    assert "the same command again tracks the rest" in run.output
    assert "interrupted (Ctrl-C)" in run.output


def test_a_second_batch_into_a_folder_in_use_is_refused(tmp_path: Path) -> None:
    """Two runs into one folder took each other's task starts for dead workers ("started 2
    times") and wrote one summary over the other; the second is refused before it starts."""
    from laserpeople.batch import TrackOptions, run_batch
    from laserpeople.batch.run import one_run_in
    from laserpeople.errors import ConfigError

    out = tmp_path / "out"
    out.mkdir()
    with one_run_in(out):
        with pytest.raises(ConfigError) as info:
            run_batch([tmp_path / "a.npz"], out, TrackOptions(), client=object())
        assert str(info.value) == (
            f"{out}: another batch run is writing into this folder now (wait until it has "
            "finished, or give --out another folder)"
        )
        assert sorted(p.name for p in out.iterdir()) == [".batch"]
    with one_run_in(out):  # free again once the first has finished
        pass
