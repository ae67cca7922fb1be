"""`laserpeople live`'s status line: the scan rate it prints."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

pytest.importorskip("zenoh", reason="needs the live extra (eclipse-zenoh)")

from laserpeople.live import runner


class _Recent:
    def recent(self, n: int) -> list[float]:
        return [4.0, 6.0, 5.0][:n]


def _session(received: dict[str, int]) -> SimpleNamespace:
    counts = SimpleNamespace(received=received, dropped={"/scan": 2})
    stats = SimpleNamespace(arrival_ms=_Recent(), frames=99)
    return SimpleNamespace(
        scans=SimpleNamespace(counts=counts),
        run=SimpleNamespace(last_step=None, stats=stats),
    )


def test_first_status_line_gives_the_rate_since_the_meter_started(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Off a terminal the first line comes 10 s in: it must count the scans received since
    the start (100 in 10 s = 10 scans/s), not print 0 for want of an earlier mark."""
    clock = [100.0]
    monkeypatch.setattr(runner.time, "monotonic", lambda: clock[0])
    received = {"/scan": 3}
    meter = runner.StatusMeter(_session(received))  # type: ignore[arg-type]
    clock[0], received["/scan"] = 110.0, 103
    first = meter.line()
    assert first.split("scans/s")[0].strip() == "10.0"
    assert "latency    5.0 ms" in first and "dropped 2" in first and "frames 99" in first
    # The next line measures over the last interval only (40 scans in 10 s), not since the
    # start ((143 - 3) / 20 = 7.0).
    clock[0], received["/scan"] = 120.0, 143
    assert meter.line().split("scans/s")[0].strip() == "4.0"
