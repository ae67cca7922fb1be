from __future__ import annotations

import json
from collections.abc import Callable

import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.evaluation.speed import time_per_item, time_reading


def test_time_per_item_uses_a_fresh_step_per_repeat() -> None:
    made: list[list[int]] = []

    def make() -> Callable[[int], None]:
        seen: list[int] = []
        made.append(seen)
        return seen.append

    t = time_per_item("stage", make, [1, 2, 3], repeats=2)
    assert made == [[1, 2, 3], [1, 2, 3]]
    assert (t.scans, t.repeats) == (3, 2)
    assert 0.0 <= t.median_ms <= t.p95_ms
    assert t.scans_per_s > 0
    with pytest.raises(ValueError, match="no input"):
        time_per_item("empty", make, [])


def test_time_reading_counts_scans() -> None:
    t = time_reading("read", lambda: iter(range(5)), repeats=3)  # type: ignore[arg-type,return-value]
    assert (t.scans, t.repeats) == (5, 3)


def test_bench_command_json() -> None:
    result = CliRunner().invoke(
        app, ["--quiet", "bench", "--seconds", "1", "--repeat", "1", "--tracker", "nn", "--json"]
    )
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert [s["stage"] for s in data["stages"]] == ["detect", "track nn"]
    assert data["scans"] > 5 and data["peak_memory_mib"] > 0
