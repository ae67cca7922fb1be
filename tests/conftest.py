"""Shared fixtures: where the real recordings are, and skipping when they are absent."""

from __future__ import annotations

import os
import sys
from pathlib import Path
from types import ModuleType

import pytest

REPO = Path(__file__).resolve().parents[1]


def shared_data_dir() -> Path:
    """``../shared/data`` beside the repository, or ``$LASERPEOPLE_SHARED_DATA``."""
    env = os.environ.get("LASERPEOPLE_SHARED_DATA")
    return Path(env) if env else REPO.parent / "shared" / "data"


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """The real recordings; the test is skipped with a reason when they are not there."""
    path = shared_data_dir()
    if not (path / "README.md").exists():
        pytest.skip(
            f"real recordings not found at {path} (clone ../shared beside the repo "
            "or set LASERPEOPLE_SHARED_DATA)"
        )
    return path


@pytest.fixture(scope="module")
def cfeatures() -> ModuleType:
    """The leg detector's built C extension; the test is skipped when it is not built or
    is stale (nothing compiled to compare with the Python references)."""
    from laserpeople import extensions
    from laserpeople.detection import compiled

    try:
        from laserpeople.detection import _cfeatures
    except ImportError:
        pytest.skip("the C extension is not built (`pip install -e .` with a C compiler)")
    if extensions.source_hash(compiled.SOURCE) != _cfeatures.SOURCE_HASH:
        pytest.skip("the C extension is stale (`pip install -e .` rebuilds it)")
    return _cfeatures


@pytest.fixture(autouse=True)
def _global_flags_reset() -> None:
    """Each test starts with the command line's global flags off: a command run with
    ``--quiet`` or ``--debug`` sets them for the process, and a later test that calls a
    command's functions directly (not through the app) would inherit them. Only when the
    command line is imported already: some tests check what reading imports."""
    common = sys.modules.get("laserpeople.cli.common")
    if common is not None:
        common.STATE.quiet = False
        common.STATE.debug = False


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Mark every test that reads the real recordings ``shared``, also through a fixture.

    ``.ci/run`` selects them with ``-m shared`` in a fresh clone with nothing beside it,
    where each one must skip with its reason instead of failing.
    """
    for item in items:
        if "shared_data" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.shared)
