"""`live` says when a laser stopped publishing before the run ended (the status line only
showed 0.0 scans/s, and the summary counted the scans as if all was well)."""

from __future__ import annotations

import pytest

from laserpeople.live.source import LiveCounts


def _counts(n: int, first: float, last: float) -> LiveCounts:
    counts = LiveCounts()
    counts.received["/scan"] = n
    counts.first_arrival["/scan"] = first
    counts.last_arrival["/scan"] = last
    return counts


@pytest.mark.parametrize(
    ("n", "span", "quiet", "said"),
    [
        # 10 Hz: ten periods are 1 s, so the floor of 1 s and the periods agree
        (11, 1.0, 1.05, True),
        (11, 1.0, 0.95, False),
        # 2 Hz: ten periods are 5 s, more than the floor
        (21, 10.0, 5.5, True),
        (21, 10.0, 4.9, False),  # the period is 10 s / 20 gaps, not / 21 scans
        (21, 10.0, 2.0, False),  # above the floor, below ten periods
        # 50 Hz: ten periods are 0.2 s, the floor of 1 s decides
        (51, 1.0, 0.5, False),
        (51, 1.0, 1.2, True),
        # one scan: no rate to judge by
        (1, 0.0, 30.0, False),
    ],
)
def test_a_laser_silent_for_ten_periods_and_a_second_has_stopped(
    n: int, span: float, quiet: float, said: bool
) -> None:
    counts = _counts(n, 100.0, 100.0 + span)
    got = counts.silence("/scan", 100.0 + span + quiet)
    if said:
        assert got == pytest.approx(quiet, abs=1e-9)
    else:
        assert got is None


def test_arrivals_are_kept_per_laser_as_scans_arrive() -> None:
    from laserpeople.live.source import LiveScans
    from test_live import _scan

    now = [10.0]
    scans = LiveScans(("/scan",), clock=lambda: now[0])
    for k, t in enumerate((10.0, 10.1, 10.2)):
        now[0] = t
        scans.put(_scan(1.0 + 0.1 * k, "/scan"), "laser")
    counts = scans.counts
    assert (counts.first_arrival["/scan"], counts.last_arrival["/scan"]) == (10.0, 10.2)
    assert counts.silence("/scan", 11.1) is None
    assert counts.silence("/scan", 11.3) == pytest.approx(1.1, abs=1e-9)
