"""`laserpeople track` with the trackers of foreground points, end to end on simulated
recordings, and the static world model the pipeline gives them.

Thresholds (seed 3, measured when written): group-mht on 12 s of entrance-hall scores
group MOTA 0.47 with the per-beam histogram and 0.13 without a static world model;
csa on the same 0.33; feet-pf and upper-body-pf on speed-normal (8.8 s, the two feet /
torso lasers) 0.68 and 0.92, both far below zero (-43) without the model.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import ConfigError
from laserpeople.frame import Frame
from laserpeople.io.tracks_csv import iter_tracks_csv
from laserpeople.pipeline import (
    AppearanceUnavailableError,
    AutoBackground,
    Fuse,
    background_of,
    background_stage,
    observe_stages_for,
)
from laserpeople.pipeline.background import StaticWorldParams
from laserpeople.pipeline.leg_foreground import LegForegroundParams
from laserpeople.scan import Pose2D, Scan


@pytest.fixture(scope="module")
def hall(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from laserpeople.sim.scenarios import run_scenario

    path = tmp_path_factory.mktemp("hall") / "hall.npz"
    run_scenario("entrance-hall", seconds=12.0, seed=3).write(path)
    return path


@pytest.fixture(scope="module")
def schenk(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from laserpeople.sim.scenarios import run_scenario

    path = tmp_path_factory.mktemp("schenk") / "walk.npz"
    run_scenario("speed-normal", seed=3).write(path)
    return path


def _track_and_score(
    recording: Path, out: Path, tracker: str, kind: str, *extra: str
) -> tuple[str, float]:
    runner = CliRunner()
    result = runner.invoke(
        app, ["track", str(recording), "--tracker", tracker, "-o", str(out), *extra]
    )
    assert result.exit_code == 0, result.output
    scored = runner.invoke(
        app, ["evaluate", str(out), "--truth", str(recording), "--kind", kind, "--json"]
    )
    assert scored.exit_code == 0, scored.output
    return result.output, float(json.loads(scored.stdout)["mota"])


def test_group_mht_end_to_end_needs_the_static_world(hall: Path, tmp_path: Path) -> None:
    out = tmp_path / "groups.csv"
    said, mota = _track_and_score(hall, out, "group-mht", "group")
    assert "per-beam range histogram" in " ".join(said.split())
    assert mota > 0.35
    groups = [t for f in iter_tracks_csv(out, frame="world") for t in f]
    assert groups and {t.kind for t in groups} == {"group"}
    assert max(t.size for t in groups) >= 2 and all(t.labels for t in groups)
    assert all(t.contour.shape[0] >= 1 for t in groups)  # outlines for `view`
    said, walls = _track_and_score(hall, tmp_path / "all.csv", "group-mht", "group",
                                   "--background", "none")  # fmt: skip
    assert "none" in said and walls < 0.3


def test_csa_end_to_end(hall: Path, tmp_path: Path) -> None:
    _, mota = _track_and_score(hall, tmp_path / "csa.csv", "csa", "person")
    assert mota > 0.25


@pytest.mark.parametrize(
    ("tracker", "lasers", "bound"),
    [("feet-pf", ("feet_a", "feet_b"), 0.5), ("upper-body-pf", ("torso_a", "torso_b"), 0.75)],
)
def test_particle_filters_end_to_end(
    schenk: Path, tmp_path: Path, tracker: str, lasers: tuple[str, str], bound: float
) -> None:
    topics = [a for name in lasers for a in ("-t", name)]
    _, mota = _track_and_score(schenk, tmp_path / "pf.csv", tracker, "person", *topics)
    assert mota > bound


# ------------------------------------------------------------ the model chosen


def _scan(stamp: float, index: int, pose: Pose2D | None, near: float = 3.0) -> Scan:
    ranges = np.full(90, 3.0)
    ranges[40:45] = near
    return Scan(
        stamp, -np.pi / 4, np.pi / 180, ranges, 0.1, 10.0, sensor="l", index=index, pose=pose
    )


def _frame(scan: Scan) -> Frame:
    frame = "world" if scan.pose is not None else "sensor"
    return Fuse()(Frame(scan.index, scan.stamp, (scan,), "l", frame, scan.pose))


def test_auto_keeps_the_histogram_while_the_laser_stands() -> None:
    model = AutoBackground()
    for i in range(30):  # 3 s at 10 Hz: learned after 2 s
        out = model(_frame(_scan(0.1 * i, i, Pose2D(1.0, 2.0, 0.3))))
    assert model.chosen == "histogram" and model.switched_at is None
    assert out.foreground is not None and not out.foreground.any()  # the wall
    late = model(_frame(_scan(3.1, 31, Pose2D(1.0, 2.0, 0.3), near=1.5)))
    assert late.foreground is not None and np.count_nonzero(late.foreground) == 5
    assert "did not move" in model.describe()


def test_auto_switches_to_the_grid_when_the_laser_moves() -> None:
    model = AutoBackground()
    for i in range(10):
        model(_frame(_scan(0.1 * i, i, Pose2D(0.03 * i, 0.0, 0.0))))
    assert model.chosen == "occupancy" and model.switched_at == 2  # 0.06 m > 0.05 m
    assert type(model.model).__name__ == "OccupancyGrid"
    assert "frame 2" in model.describe()


def _rotating_scan(index: int, turn: int) -> Scan:
    """A sensor-frame scan of a room whose walls stand at a range that changes with the
    beam, the whole pattern turned by ``turn`` beams (a laser turning on the spot)."""
    ranges = 3.0 + 2.0 * np.abs(np.sin(np.arange(90) * np.pi / 30.0))
    return Scan(
        0.1 * index,
        -np.pi / 4,
        np.pi / 180,
        np.roll(ranges, turn),
        0.1,
        10.0,
        sensor="l",
        index=index,
    )


def test_auto_in_the_sensor_frame_keeps_the_histogram_while_the_laser_stands() -> None:
    model = AutoBackground()
    for i in range(60):
        out = model(_frame(_rotating_scan(i, 0)))
    assert model.chosen == "histogram" and model.motion is not None
    assert model.motion.moved_at is None
    assert out.foreground is not None and not out.foreground.any()
    assert "did not move" in model.describe()


def test_auto_in_the_sensor_frame_drops_the_model_when_the_laser_moves() -> None:
    """Without poses the laser's motion shows as returns the histogram does not explain:
    the model is dropped, every point is foreground (``[leg_foreground] use = never``, the
    papers' setting; the default's points near legs: test_pipeline_leg_foreground), and the
    user is told from when."""
    papers = StaticWorldParams(leg_foreground=LegForegroundParams(use="never"))
    model = AutoBackground(static=papers)
    for i in range(25):  # still for 2.5 s: learned over the first 2 s
        model(_frame(_rotating_scan(i, 0)))
    assert model.chosen == "histogram"
    for i in range(25, 80):  # then it turns 3 beams a scan
        out = model(_frame(_rotating_scan(i, 3 * (i - 24))))
    assert model.chosen == "none" and model.model is None
    assert model.switched_at is not None and 25 < model.switched_at < 60
    assert out.foreground is not None and out.foreground.all()
    np.testing.assert_array_equal(model.static_time(np.zeros((3, 2))), np.zeros(3))
    assert f"none from frame {model.switched_at} (the laser moves" in model.describe()


def test_background_choices() -> None:
    assert background_stage("none") is None
    assert type(background_stage("histogram")).__name__ == "BeamHistogramBackground"
    assert type(background_stage("occupancy")).__name__ == "OccupancyGrid"
    with pytest.raises(ConfigError):
        background_stage("walls")
    with pytest.raises(ConfigError):
        background_stage("histogram", map_path="map.yaml")
    pre, _ = observe_stages_for(frozenset({"points", "foreground"}), None)
    assert isinstance(pre[0], Fuse) and isinstance(background_of(pre), AutoBackground)
    pre, _ = observe_stages_for(frozenset({"points", "foreground"}), None, background="none")
    assert background_of(pre) is None
    pre, _ = observe_stages_for(frozenset({"points"}), None)
    assert background_of(pre) is None  # nobody asked for a foreground


# ------------------------------------------------------------------ appearance


def test_appearance_on_adds_colour_reidentification(tmp_path: Path) -> None:
    from laserpeople.pipeline import build
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "cross.npz"
    run_scenario("crossing-3-p3", seconds=4.0, seed=1).write(rec)
    result = CliRunner().invoke(
        app,
        ["track", str(rec), "--tracker", "csa", "--topics", "all", "--appearance", "on",
         "-o", str(tmp_path / "t.csv")],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "simulated camera" in " ".join(result.output.split())
    pipe = build(rec, tracker="leg-mht", reidentify=True, max_frames=20)
    seen = [step.frame.appearance for step in pipe]
    assert type(pipe.identify[0]).__name__ == "ColourReidentifier"
    assert sum(len(a) for a in seen) > 20  # three people, a few misses


def test_appearance_is_refused_without_truth(tmp_path: Path) -> None:
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "scans.mcap"
    run_scenario("crossing-3-p3", seconds=1.0, seed=1).write(rec)
    out = tmp_path / "t.csv"
    args = ["track", str(rec), "--topics", "all", "-o", str(out)]
    for extra in (["--tracker", "csa", "--appearance", "on"], ["--reidentify", "colour"]):
        result = CliRunner().invoke(app, [*args, *extra])
        assert isinstance(result.exception, AppearanceUnavailableError)
    result = CliRunner().invoke(app, [*args, "--tracker", "nn", "--appearance", "on"])
    assert isinstance(result.exception, ConfigError)
    assert "--reidentify colour" in str(result.exception.hint)


# ------------------------------------------------------------------ group outlines


def test_group_outline_is_the_padded_hull() -> None:
    from laserpeople.viz.geometry import group_outline

    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.5, 0.2]])
    out = group_outline(pts, margin=0.1)
    assert np.allclose(out[0], out[-1])
    # the 12-gon has vertices at 0, 90, 180 and 270 degrees: the extremes are exact
    assert out[:, 0].min() == pytest.approx(-0.1) and out[:, 0].max() == pytest.approx(1.1)
    assert out[:, 1].min() == pytest.approx(-0.1) and out[:, 1].max() == pytest.approx(0.3)
    # every vertex lies on a 0.1 m circle round one of the points
    d = np.linalg.norm(out[:, None, :] - pts[None], axis=2).min(axis=1)
    assert d == pytest.approx(np.full(len(out), 0.1))
    assert group_outline(np.empty((0, 2))).shape == (0, 2)


def test_tracks_csv_carries_group_contours(tmp_path: Path) -> None:
    from laserpeople.io.tracks_csv import TracksCsvWriter
    from laserpeople.tracks import Track, Tracks

    contour = np.array([[1.0, 2.0], [1.5, 2.25], [2.0, 2.0]])
    group = Track(7, "group", np.array([1.5, 2.1]), np.zeros(2), np.eye(2), 2, "A",
                  contour=contour)  # fmt: skip
    person = Track(8, "person", np.array([0.0, 0.0]), np.zeros(2), np.eye(2))
    with TracksCsvWriter(tmp_path / "t.csv", frame="world", topic="l", contours=True) as out:
        out.write(Tracks(0.0, 0, (group, person), "world"))
    (back,) = iter_tracks_csv(tmp_path / "t.csv", frame="world")
    g, p = back.tracks
    assert g.contour == pytest.approx(contour) and g.size == 2 and g.labels == "A"
    assert p.contour.shape == (0, 2)
