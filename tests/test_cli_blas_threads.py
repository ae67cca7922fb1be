"""The command line starts numpy's OpenBLAS with one thread unless the user chose a count."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from laserpeople.cli import BLAS_THREAD_VARIABLES, one_blas_thread

REPO = Path(__file__).resolve().parents[1]


def test_one_thread_unless_a_count_is_chosen() -> None:
    env: dict[str, str] = {"PATH": "/bin"}
    one_blas_thread(env)
    assert env == {"PATH": "/bin", "OPENBLAS_NUM_THREADS": "1"}
    for name in BLAS_THREAD_VARIABLES:
        chosen = {name: "3"}
        one_blas_thread(chosen)
        assert chosen == {name: "3"}, name  # the user's choice, nothing added


@pytest.mark.skipif(
    not Path("/proc/self/status").exists() or (os.cpu_count() or 1) < 2,
    reason="counts threads through /proc on a machine with two cores or more",
)
def test_the_program_sets_it_before_numpy_starts_its_threads() -> None:
    """In a fresh interpreter ``main`` runs a command that imports numpy: the process then
    has one thread (OpenBLAS would start one per core when numpy is imported first)."""
    code = (
        "import sys; sys.argv = ['laserpeople', 'scenarios']\n"
        "from laserpeople.cli import main\n"
        "assert 'numpy' not in sys.modules\n"
        "try:\n    main()\nexcept SystemExit as exc:\n    assert not exc.code, exc.code\n"
        "import numpy, os\n"
        "status = open('/proc/self/status').read()\n"
        "print('THREADS', status.split('Threads:')[1].split()[0], "
        "os.environ['OPENBLAS_NUM_THREADS'])"
    )
    env = {k: v for k, v in os.environ.items() if k not in BLAS_THREAD_VARIABLES}
    env["PYTHONPATH"] = str(REPO / "src")
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120
    )
    assert out.returncode == 0, out.stderr[-500:]
    assert out.stdout.rstrip().endswith("THREADS 1 1"), out.stdout[-300:]
