"""Shared fixtures: where the real recordings are, and skipping when they are absent."""

from __future__ import annotations

import os
from pathlib import Path

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


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Mark every test that reads the real recordings ``shared``, also through a fixture.

    ``.ci/run`` selects them with ``-m shared`` in a fresh clone with nothing beside it,
    where each one must skip with its reason instead of failing.
    """
    for item in items:
        if "shared_data" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.shared)
