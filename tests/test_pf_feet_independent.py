"""The feet tracker (004 Sec. 2.1) on scenes unlike 004's experiments: one 0.25 deg laser at
0.2 m, a scan rate below 004's 50 Hz, clutter and people who stop (``feet-crossing``,
``feet-office``).

End to end (the real pipeline as ``laserpeople track`` runs it, background learned from
the recording itself): ``feet-crossing`` seed 3 (15 Hz, four people, two of whom stand at
the end) scored 004's adapted MOTP 0.30 with the settings before and 0.66 with
``overlap_max``, ``still_time``, ``miss_time`` 1 s and ``report_time`` (measured when
written); the test asks for 0.5.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.tracking.particle.feet import (
    FeetParams,
    FeetTracker,
    StepDetector,
    StillDetector,
)
from laserpeople.tracking.particle.objects import two_feet
from test_pf_feet_cells import frame_of


def _leg(cx: float, cy: float, r: float = 0.07, n: int = 5) -> np.ndarray:
    """``n`` points on the front arc of a leg at (cx, cy) seen from -y."""
    a = np.linspace(-np.pi / 2 - 0.8, -np.pi / 2 + 0.8, n)
    return np.column_stack([cx + r * np.cos(a), cy + r * np.sin(a)])


def _person(cx: float, cy: float) -> np.ndarray:
    return np.vstack([_leg(cx - 0.1, cy), _leg(cx + 0.1, cy)])


def test_link_distance_bound_keeps_two_people_apart_at_a_low_scan_rate() -> None:
    """Two people standing 0.9 m apart (their nearest legs 0.56 m apart), scanned at
    15 Hz: the link distance scaled to 15 Hz (0.25 m x 50 / 15 = 0.83 m) links the
    clusters of one to those of the other (merges and splits every scan, 004 Fig. 1's
    step); bounded at ``overlap_max`` 0.5 m it links each only to itself. At 50 Hz the
    bound does not bite (0.25 m either way)."""
    pts = np.vstack([_person(0.0, 2.0), _person(0.9, 2.0)])
    for bound, expect in ((0.0, True), (0.5, False), (0.6, True)):
        det = StepDetector(FeetParams(overlap_max=bound))
        det.events(pts, 0.0)
        merges, splits = det.events(pts + 0.001, 1.0 / 15.0)
        assert bool(merges or splits) is expect, bound


def test_report_time_hides_a_coasting_filter() -> None:
    """A filter without points for 0.5 s (scans at 16 Hz) lives on (``miss_time`` 1 s)
    but is reported only within ``report_time`` 0.2 s of its last support."""
    tracker = FeetTracker(FeetParams(particles=50))
    tracker.bank.add(np.stack([tracker._initial(np.array([[0.0, 2.0], [0.2, 2.0]]))]), 0.0)
    seen = []
    for k in range(1, 11):
        t = k / 16.0  # exact in binary
        pts = _person(0.1, 2.0) if k <= 2 else np.empty((0, 2))
        seen.append((k, len(tracker.update(frame_of(pts, t, k)).tracks), len(tracker.bank)))
    assert all(n_filters == 1 for _, _, n_filters in seen)
    # last support at 2/16 s: shown up to 2/16 + 0.2 = 5.2/16 s
    assert [k for k, shown, _ in seen if shown] == [1, 2, 3, 4, 5]


def test_still_detector_finds_a_standing_person_after_still_time() -> None:
    p = FeetParams(still_time=1.0)
    det = StillDetector(p)
    rng = np.random.default_rng(0)
    standing = _person(2.0, 3.0)
    found: list[np.ndarray] = []
    for k in range(16):  # 15 Hz, 1.0 s
        t = k / 15.0
        walker = _person(0.0 + 1.2 * t, 1.0)  # 1.2 m/s: never still
        found = det.detections(np.vstack([standing + rng.normal(0, 0.005, (10, 2)), walker]), t)
        if t < 1.0 - 1e-9:
            assert found == [], t
    assert len(found) == 1
    feet = found[0]
    # the two legs, 0.2 m apart across the major axis (each foot within 2 cm of a leg centre
    # seen from the front: the arc's points lie up to 0.07 m in front of the centre)
    assert np.hypot(*(feet[0] - feet[1])) == pytest.approx(0.2, abs=0.02)
    assert np.allclose(np.sort(feet[:, 0]), [1.9, 2.1], atol=0.02)


def test_still_detector_off_and_size_bound() -> None:
    off = StillDetector(FeetParams(still_time=0.0))
    assert off.detections(_person(0.0, 0.0), 5.0) == []
    det = StillDetector(FeetParams(still_time=0.5))
    wall = np.column_stack([np.linspace(0, 1.0, 30), np.zeros(30)])  # 1 m: no person
    for k in range(20):
        assert det.detections(wall, k * 0.1) == []


def test_two_feet_of_one_side_only() -> None:
    pts = np.array([[0.0, 0.0], [0.02, 0.0], [0.04, 0.0]])
    cov = np.array([[1.0, 0.0], [0.0, 0.1]])
    feet = two_feet(pts, np.array([-0.5, 0.0]), cov)
    assert np.allclose(feet[0], [-0.6, 0.0]) or np.allclose(feet[1], [-0.4, 0.0])
    assert np.allclose(feet[1], pts.mean(axis=0)) or np.allclose(feet[0], pts.mean(axis=0))


@pytest.fixture(scope="module")
def crossing(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from laserpeople.sim.scenarios import run_scenario

    path = tmp_path_factory.mktemp("feet") / "crossing.npz"
    run_scenario("feet-crossing", seed=3).write(path)
    return path


def _motp(recording: Path, out: Path, *extra: str) -> float:
    runner = CliRunner()
    res = runner.invoke(
        app, ["-q", "track", str(recording), "--tracker", "feet-pf", "-o", str(out), *extra]
    )
    assert res.exit_code == 0, res.output
    res = runner.invoke(app, ["evaluate", str(out), "--truth", str(recording), "--json"])
    assert res.exit_code == 0, res.output
    return float(json.loads(res.stdout[res.stdout.index("{") :])["motp_schenk"])


@pytest.mark.slow
def test_feet_pf_on_a_crossing_with_one_low_laser(crossing: Path, tmp_path: Path) -> None:
    assert _motp(crossing, tmp_path / "t.csv") >= 0.5


@pytest.mark.slow
def test_feet_pf_before_the_departures_misses_the_crossing(crossing: Path, tmp_path: Path) -> None:
    """The same run with the settings before (no bound on the link distance, no still
    births nor births on unclaimed walkers nor splits, a filter dies after 0.2 s without
    points) stays far below."""
    cfg = tmp_path / "old.toml"
    cfg.write_text(
        "[feet_pf]\noverlap_max = 0.0\nstill_time = 0.0\nmiss_time = 0.2\nclaim_distance = 0.0\n"
        "split_distance = 0.0\n"
    )
    assert _motp(crossing, tmp_path / "p.csv", "--config", str(cfg)) < 0.5
