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


def test_time_per_item_cpu_is_not_wall_time() -> None:
    """A step that sleeps 5 ms takes at least 5 ms of wall time but almost no CPU time: the
    CPU columns are the process's own cost, not the clock."""
    import time

    def make() -> Callable[[int], None]:
        return lambda _: time.sleep(0.005)

    t = time_per_item("sleep", make, [1, 2, 3, 4], repeats=1)
    assert t.median_ms >= 4.9
    assert 0.0 <= t.cpu_median_ms < 1.0
    assert t.cpu_scans_per_s > 4 * t.scans_per_s
    assert set(t.as_dict()) >= {"cpu_median_ms", "cpu_scans_per_s"}


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
    assert all(s["cpu_median_ms"] >= 0.0 for s in data["stages"])
    # which listing the leg MHT ran: the compiled one where it is built, else Python's
    from laserpeople.tracking.mht.listing import COMPILED

    compiled = data["mht_listing"] == "compiled (C extension)"
    assert compiled == (COMPILED is not None)
    assert compiled or data["mht_listing"].startswith("pure Python (")
    # and which leg detection: the compiled features and margins where built, else Python's
    from laserpeople.detection.compiled import EXTENSION

    features = data["leg_detection"] == "compiled (C extension)"
    assert features == (EXTENSION is not None)
    assert features or data["leg_detection"].startswith("pure Python (")
    # and which Kalman steps: the compiled ones where built, else numpy's
    from laserpeople.tracking import kalman

    steps = data["kalman_steps"] == "compiled (C extension)"
    assert steps == (kalman._extension is not None)
    assert steps or data["kalman_steps"].startswith("pure Python (")
