"""The ``laserpeople`` program ends its process without the interpreter's finalisation
(``cli.run``, ``cli.end_process``): the exit status, the ``atexit`` functions and the
output are those of a usual exit."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]

# an object whose finaliser speaks: the interpreter's finalisation would run it
WITNESS = (
    "import atexit, sys\n"
    "class Witness:\n"
    "    def __del__(self):\n"
    "        print('FINALISED', flush=True)\n"
    "sys.modules['__main__'].witness = Witness()\n"
    "atexit.register(lambda: print('AT EXIT'))\n"
)


def _python(code: str, *args: str) -> subprocess.CompletedProcess[str]:
    env = dict(os.environ, PYTHONPATH=str(REPO / "src"))
    return subprocess.run(
        [sys.executable, "-c", code, *args], env=env, capture_output=True, text=True, timeout=300
    )


def _program(*args: str, before: str = WITNESS) -> subprocess.CompletedProcess[str]:
    code = (
        before
        + f"sys.argv = ['laserpeople', *{list(args)!r}]\nfrom laserpeople.cli import run\nrun()\n"
    )
    return _python(code)


def test_a_run_ends_with_its_output_and_atexit_but_no_finalisation() -> None:
    done = _program("scenarios")
    assert done.returncode == 0, done.stderr[-500:]
    lines = done.stdout.splitlines()
    assert "crossing-3" in done.stdout  # the listing, piped (block-buffered) and flushed
    assert lines[-1] == "AT EXIT"
    assert "FINALISED" not in done.stdout


def test_exit_statuses_are_the_commands() -> None:
    missing = _program("track", "/nonexistent/r.bag", "-o", "/nonexistent/t.csv")
    assert missing.returncode == 1
    assert "error:" in missing.stderr
    usage = _program("track", "--no-such-option")
    assert usage.returncode == 2
    assert "No such option" in usage.stderr or "no such option" in usage.stderr.lower()
    for out in (missing, usage):
        assert out.stdout.splitlines()[-1:] == ["AT EXIT"]


def test_with_another_thread_alive_the_usual_exit_ends_it() -> None:
    """Another thread (here a daemon waiting for ever) leaves the exit to ``sys.exit``."""
    thread = (
        WITNESS + "import threading\n"
        "threading.Thread(target=threading.Event().wait, daemon=True).start()\n"
    )
    done = _program("scenarios", before=thread)
    assert done.returncode == 0, done.stderr[-500:]
    assert "AT EXIT" in done.stdout and "FINALISED" in done.stdout


def test_the_usual_exit_finalises() -> None:
    """(The witness of the tests above speaks on a usual exit.)"""
    done = _python(WITNESS + "sys.exit(3)\n")
    assert done.returncode == 3 and "FINALISED" in done.stdout


def test_python_dash_m_runs_the_program() -> None:
    env = dict(os.environ, PYTHONPATH=str(REPO / "src"))
    done = subprocess.run(
        [sys.executable, "-m", "laserpeople.cli", "track", "--no-such-option"],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 2
