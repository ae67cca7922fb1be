"""The static world model fed to the leg MHT's people through the pipeline (issue 10): a
static 4-post chair is not a person, a walker who stops keeps their track, the pipeline
wires the model to leg-mht, and no sensor-frame model is used on a moving laser."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import ConfigError
from laserpeople.frame import Frame
from laserpeople.pipeline import build
from laserpeople.pipeline.preprocess import Fuse
from laserpeople.pipeline.static_people import (
    PeopleStaticModel,
    SensorMotionCheck,
    StaticFed,
    describe_static_cost,
    people_static_model,
    static_world_cpu,
)
from laserpeople.scan import Pose2D, Scan
from laserpeople.tracking import registry
from laserpeople.tracking.legs import LegTrackerParams
from laserpeople.tracks import Detections, Tracks

RATE = 10.0
N_BEAMS = 720
INC = 2 * math.pi / N_BEAMS
CHAIR = np.array([[2.0, 1.0], [2.4, 1.0], [2.0, 1.4], [2.4, 1.4]])  # posts, 0.4 m apart
POST_R, LEG_R, ROOM_R = 0.02, 0.06, 6.0


def _ranges(discs: np.ndarray, radii: np.ndarray, origin: np.ndarray, heading: float) -> np.ndarray:
    """Ranges of a 360 deg scan from ``origin`` hitting discs (K, 2) of ``radii`` (K,) inside
    a round room of radius ROOM_R (ray-disc intersections, computed independently of the
    simulator)."""
    ang = heading + np.arange(N_BEAMS) * INC
    d = np.stack([np.cos(ang), np.sin(ang)], axis=1)  # (B, 2)
    rel = discs - origin  # (K, 2)
    b = d @ rel.T  # (B, K) projection of the centre on the beam
    c = np.sum(rel**2, axis=1)[None, :] - radii[None, :] ** 2
    disc = b**2 - c
    hit = np.where((disc >= 0) & (b > 0), b - np.sqrt(np.maximum(disc, 0.0)), np.inf)
    # the room wall: |origin + r d| = ROOM_R
    ob = d @ origin
    wall = -ob + np.sqrt(ob**2 - (origin @ origin - ROOM_R**2))
    return np.minimum(hit.min(axis=1), wall)


def _walker(t: float) -> np.ndarray:
    """Legs (2, 2) of a person who walks along +y at 0.8 m/s for 4 s from (3.5, -2.5) (feet
    alternating, 0.25 m apart sideways) and then stands still."""
    walk = min(t, 4.0)
    body = np.array([3.5, -2.5 + 0.8 * walk])
    swing = 0.15 * math.sin(2 * math.pi * walk) if t < 4.0 else 0.0
    return np.array([[body[0] - 0.125, body[1] + swing], [body[0] + 0.125, body[1] - swing]])


def _frames(seconds: float, robot_speed: float = 0.0) -> list[Frame]:
    """Frames (world frame, the sensor's pose known) of the chair and the walker; every post
    and leg is detected as a leg (a detector that calls chair posts legs)."""
    out = []
    for k in range(int(seconds * RATE)):
        t = k / RATE
        pose = Pose2D(robot_speed * t, 0.0, 0.0)
        origin = np.array([pose.x, pose.y])
        legs = _walker(t)
        discs = np.vstack([CHAIR, legs])
        radii = np.array([POST_R] * 4 + [LEG_R] * 2)
        scan = Scan(
            t, 0.0, INC, _ranges(discs, radii, origin, 0.0), sensor="laser", index=k, pose=pose
        )
        m = len(discs)
        dets = Detections(
            t,
            k,
            discs,
            np.tile(np.eye(2) * 0.02**2, (m, 1, 1)),
            np.full(m, 2.0),
            frame="world",
            sensor_pose=pose,
        )
        out.append(Frame(k, t, (scan,), "laser", frame="world", sensor_pose=pose, legs=dets))
    return out


def _people(tracker: object, frames: list[Frame]) -> list[Tracks]:
    return [tracker.update(f) for f in frames]  # type: ignore[attr-defined]


def _on_chair(out: Tracks) -> list[int]:
    centre = CHAIR.mean(axis=0)
    return [t.track_id for t in out.of_kind("person") if np.hypot(*(t.position - centre)) < 0.6]


def _near_walker(out: Tracks, t: float) -> list[int]:
    body = _walker(t).mean(axis=0)
    return [t.track_id for t in out.of_kind("person") if np.hypot(*(t.position - body)) < 0.5]


def test_ray_caster_by_hand() -> None:
    r = _ranges(np.array([[2.0, 0.0]]), np.array([0.5]), np.zeros(2), 0.0)
    assert r[0] == pytest.approx(1.5)  # beam 0 along +x hits the disc's near side
    assert r[N_BEAMS // 2] == pytest.approx(ROOM_R)  # beam along -x hits the wall


def test_leg_mht_with_the_model_does_not_confirm_a_chair_but_keeps_a_walker_who_stops() -> None:
    frames = _frames(30.0)
    params = LegTrackerParams()  # people policy "tracks"
    static_after = params.people.static_time + 1.0  # s: the chair's place is static by then
    bare = _people(registry.get("leg-mht").make(params), frames)
    fed = StaticFed(registry.get("leg-mht").make(params), PeopleStaticModel("auto"))
    with_model = _people(fed, frames)
    late = [k for k, f in enumerate(frames) if f.stamp > static_after]
    # without the model the chair's posts make a person for the whole run ...
    assert sum(bool(_on_chair(bare[k])) for k in late) > 0.8 * len(late)
    # ... with it, nobody on the chair once its place is static
    assert not any(_on_chair(with_model[k]) for k in late)
    # the walker is one person from shortly after it appears to the end, standing for 26 s
    ids = [_near_walker(with_model[k], frames[k].stamp) for k in range(len(frames))]
    seen = [k for k, i in enumerate(ids) if i]
    assert seen and frames[seen[0]].stamp < 2.0
    assert {i for k in seen for i in ids[k]} == {ids[seen[0]][0]}
    assert len(seen) >= len(frames) - seen[0] - 2  # reported in (nearly) every scan


def test_a_map_blocks_the_chair_from_the_start(tmp_path: Path) -> None:
    """With a ROS map that has the chair, no person is confirmed on it at any time."""
    from PIL import Image

    res = 0.05
    img = np.full((160, 160), 254, dtype=np.uint8)  # x, y in [0, 8) m, origin (0, 0)
    for x, y in CHAIR:
        img[159 - int(y / res), int(x / res)] = 0
    Image.fromarray(img).save(tmp_path / "map.pgm")
    (tmp_path / "map.yaml").write_text(
        "image: map.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    frames = _frames(8.0)
    fed = StaticFed(
        registry.get("leg-mht").make(), PeopleStaticModel("occupancy", tmp_path / "map.yaml")
    )
    out = _people(fed, frames)
    assert not any(_on_chair(o) for o in out)
    assert any(_near_walker(o, f.stamp) for o, f in zip(out, frames, strict=True))


def test_sensor_frame_model_is_dropped_when_the_laser_moves() -> None:
    """In the sensor frame (no poses) a moving laser sees its scene change: the model is
    dropped (static time 0 everywhere); a standing laser keeps it."""

    def sensor_frames(speed: float) -> list[Frame]:
        frames = []
        for f in _frames(15.0, robot_speed=speed):
            scan = Scan(f.stamp, 0.0, INC, f.scans[0].ranges, sensor="laser", index=f.index)
            frames.append(Fuse()(Frame(f.index, f.stamp, (scan,), "laser")))
        return frames

    moving = PeopleStaticModel("occupancy")
    for f in sensor_frames(0.3):
        moving(f)
    assert moving.dropped_at is not None and 20 < moving.dropped_at < 100
    assert moving.static_time(CHAIR).tolist() == [0.0] * 4
    assert "the laser moves" in moving.describe()
    still = PeopleStaticModel("occupancy")
    for f in sensor_frames(0.0):
        still(f)
    assert still.dropped_at is None and (still.static_time(CHAIR) > 5.0).all()
    assert "sensor frame" in still.describe()


def test_a_model_nobody_reads_leaves_the_frames_foreground() -> None:
    """A people's model with ``fill_foreground`` False never overwrites the foreground an
    earlier stage gave (the trackers' own model): not while it runs a histogram, and not
    once it is dropped on a moving laser (it used to mark every point foreground then)."""
    for speed, kind in ((0.0, "histogram"), (0.3, "occupancy")):
        model = PeopleStaticModel(kind)
        model.fill_foreground = False
        for f in _frames(15.0, robot_speed=speed):
            scan = Scan(f.stamp, 0.0, INC, f.scans[0].ranges, sensor="laser", index=f.index)
            frame = Fuse()(Frame(f.index, f.stamp, (scan,), "laser"))
            assert frame.points is not None
            given = np.arange(len(frame.points)) % 3 == 0
            out = model(frame.with_fields(foreground=given))
            assert out.foreground is not None
            np.testing.assert_array_equal(out.foreground, given)
        assert (model.dropped_at is not None) == (speed > 0)


def test_motion_check_share_by_hand() -> None:
    """The share of returns off the learned ranges: half the beams moved -> 0.5."""
    check = SensorMotionCheck()
    ranges = np.full(N_BEAMS, 4.0)
    for k in range(25):  # learning (2 s) and a few scans after it
        frame = Fuse()(
            Frame(k, 0.1 * k, (Scan(0.1 * k, 0.0, INC, ranges, sensor="l", index=k),), "l")
        )
        assert not check(frame)
    assert check.share == 0.0
    moved = ranges.copy()
    moved[: N_BEAMS // 2 + 2] = 2.0
    for k in range(25, 60):
        scan = Scan(0.1 * k, 0.0, INC, moved, sensor="l", index=k)
        check(Fuse()(Frame(k, 0.1 * k, (scan,), "l")))
    assert check.moved_at is not None and check.share == pytest.approx((N_BEAMS // 2 + 2) / N_BEAMS)


def test_a_map_in_a_sensor_frame_run_is_refused(tmp_path: Path) -> None:
    model = PeopleStaticModel("auto")
    model.map_path = tmp_path / "map.yaml"  # as if given: refused before the file is read
    scan = Scan(0.0, 0.0, INC, np.full(N_BEAMS, 3.0), sensor="l", index=0)
    with pytest.raises(ConfigError, match="sensor frame"):
        model(Fuse()(Frame(0, 0.0, (scan,), "l")))


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from laserpeople.sim.scenarios import run_scenario

    path = tmp_path_factory.mktemp("rec") / "walk.npz"
    run_scenario("demo", seconds=2.0, seed=3).write(path)
    return path


def test_build_wires_the_model_to_leg_mht(recording: Path, tmp_path: Path) -> None:
    pipe = build(recording, tracker="leg-mht")
    model = next(s for s in pipe.stages if isinstance(s, PeopleStaticModel))
    tracker = pipe.tracker
    assert tracker is not None
    assert tracker.tracker.person_tracks.static_model is model  # type: ignore[attr-defined]
    stats = pipe.run()
    assert stats.frames > 10 and model.frame == "world" and model.dropped_at is None
    assert "occupancy grid in the world frame" in model.describe()
    # none: no stage, no model; arras: no stage (000's people have none)
    pipe = build(recording, tracker="leg-mht", background="none")
    assert not any(isinstance(s, PeopleStaticModel) for s in pipe.stages)
    assert pipe.tracker.tracker.person_tracks.static_model is None  # type: ignore[union-attr]
    arras = LegTrackerParams(people_policy="arras")
    pipe = build(recording, tracker="leg-mht", params=arras)
    assert not any(isinstance(s, PeopleStaticModel) for s in pipe.stages)
    with pytest.raises(ConfigError, match="--map"):
        build(recording, tracker="leg-mht", params=arras, map_path=tmp_path / "m.yaml")
    with pytest.raises(ConfigError, match="--map"):
        people_static_model("none", tmp_path / "m.yaml")


def test_track_prints_the_model(recording: Path, tmp_path: Path) -> None:
    out = tmp_path / "t.csv"
    result = CliRunner().invoke(app, ["track", str(recording), "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert "static world model for people: occupancy grid in the world frame" in result.output
    result = CliRunner().invoke(
        app, ["track", str(recording), "-o", str(out), "--people-policy", "arras"]
    )
    assert "the arras people policy has none" in result.output


def test_the_model_cost_is_counted_and_said(recording: Path, tmp_path: Path) -> None:
    import time

    pipe = build(recording, tracker="leg-mht")
    model = next(s for s in pipe.stages if isinstance(s, PeopleStaticModel))
    start = time.process_time()
    pipe.run()
    loop = time.process_time() - start
    assert len(pipe.stats.stage_cpu) == len(pipe.stages)
    learn = pipe.stage_cpu(model)
    cpu = static_world_cpu(pipe)
    assert learn > 0.0 and model.query_cpu > 0.0
    assert cpu == pytest.approx(learn + model.query_cpu, abs=1e-12) and cpu < loop
    line = describe_static_cost(pipe, loop)
    assert line.startswith(f"static world model cost: {cpu:.2f} s CPU (")
    assert f"{1e3 * cpu / pipe.stats.frames:.2f} ms per frame" in line
    assert f"{cpu / loop:.0%} of the tracking loop's CPU" in line
    none = build(recording, tracker="leg-mht", background="none")
    none.run()
    assert static_world_cpu(none) == 0.0 and describe_static_cost(none, loop) == ""
    out = tmp_path / "t.csv"
    result = CliRunner().invoke(app, ["track", str(recording), "-o", str(out)])
    assert "static world model cost: " in result.output
    result = CliRunner().invoke(
        app, ["track", str(recording), "-o", str(out), "--background", "none"]
    )
    assert "static world model cost" not in result.output


# ------------------------------------------------------------------ --config sections


def test_static_world_sections_are_read_from_the_config(tmp_path: Path) -> None:
    from laserpeople.pipeline.background import StaticWorldParams, load_static_world

    path = tmp_path / "p.toml"
    path.write_text(
        "[occupancy]\ndecay_time = 3\nfree_range = 0.0\n[beam_histogram]\nbin_width = 0.1\n"
        "[auto_background]\nmoved_distance = 0.2\n[sensor_motion]\nmoved_share = 0.6\n"
    )
    p = load_static_world(path)
    assert p.occupancy.decay_time == 3.0 and isinstance(p.occupancy.decay_time, float)
    assert p.occupancy.free_range == 0.0 and p.occupancy.resolution == 0.1  # default kept
    assert p.beam_histogram.bin_width == 0.1 and p.auto_background.moved_distance == 0.2
    assert p.sensor_motion.moved_share == 0.6 and p.sensor_motion.window == 2.0
    assert load_static_world(None) == StaticWorldParams()


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("[occupancy]\ndecay_tme = 3.0\n", "decay_tme"),
        ("[occupancy]\nneighbourhood = 1.5\n", "neighbourhood"),
        ("[occupancy]\nfirst_sight_hold = nan\n", "first_sight_hold is NaN"),
        ("[occupancy]\nfree_range = inf\n", "free_range is infinite"),
        ("[occupancy]\nmax_evidence = 1.0\n", "occupied_evidence <= max_evidence"),
        ('[beam_histogram]\nlearn_seconds = "x"\n', "learn_seconds"),
        ("[auto_background]\nmoved_angle = nan\n", "moved_angle is NaN"),
        ("[sensor_motion]\nwindow = -inf\n", "window is infinite"),
        ("[sensor_motion]\nmoved_share = 1.5\n", "moved_share must be in"),
        ("[sensor_motion]\nstill = 1.0\n", "still"),
    ],
)
def test_bad_static_world_values_are_config_errors(tmp_path: Path, text: str, match: str) -> None:
    from laserpeople.pipeline.background import load_static_world

    path = tmp_path / "p.toml"
    path.write_text(text)
    with pytest.raises(ConfigError, match=match):
        load_static_world(path)


def test_build_hands_the_static_world_parameters_to_the_models(recording: Path) -> None:
    from laserpeople.background.occupancy import OccupancyGrid, OccupancyParams
    from laserpeople.pipeline.background import (
        AutoBackground,
        SensorMotionParams,
        StaticWorldParams,
        background_stage,
    )

    static = StaticWorldParams(
        occupancy=OccupancyParams(free_range=0.0, decay_time=3.0),
        sensor_motion=SensorMotionParams(moved_share=0.6),
    )
    pipe = build(recording, tracker="leg-mht", static_world=static)
    model = next(s for s in pipe.stages if isinstance(s, PeopleStaticModel))
    assert isinstance(model.model, OccupancyGrid) and model.model.params is static.occupancy
    pipe.run()
    assert not model.model.casting  # free_range 0: no free space was cast
    # the default casts
    pipe = build(recording, tracker="leg-mht")
    model = next(s for s in pipe.stages if isinstance(s, PeopleStaticModel))
    pipe.run()
    assert model.model.casting
    # the sensor-frame motion check and the foreground trackers' models get theirs too
    people = PeopleStaticModel("auto", static=static)
    scan = Scan(0.0, 0.0, INC, np.full(N_BEAMS, 3.0), sensor="l", index=0)
    people(Fuse()(Frame(0, 0.0, (scan,), "l")))
    assert people.motion is not None and people.motion.params.moved_share == 0.6
    auto = background_stage("auto", None, static)
    assert isinstance(auto, AutoBackground)
    assert auto.params is static.auto_background and auto.static is static
    grid = background_stage("occupancy", None, static)
    assert isinstance(grid, OccupancyGrid) and grid.params is static.occupancy


def test_track_reads_the_static_world_sections(recording: Path, tmp_path: Path) -> None:
    out = tmp_path / "t.csv"
    cfg = tmp_path / "p.toml"
    cfg.write_text("[occupancy]\ndecay_time = 3.0\n[sensor_motion]\nwindow = 4.0\n")
    result = CliRunner().invoke(
        app, ["track", str(recording), "-o", str(out), "--config", str(cfg)]
    )
    assert result.exit_code == 0, result.output
    shown = CliRunner().invoke(app, ["track", "--print-config", "--config", str(cfg)])
    assert "decay_time = 3.0" in shown.output and "window = 4.0" in shown.output
    cfg.write_text("[occupancy]\ndecay_time = nan\n")
    result = CliRunner().invoke(
        app, ["track", str(recording), "-o", str(out), "--config", str(cfg)]
    )
    assert result.exit_code != 0 and "decay_time is NaN" in f"{result.exception}{result.output}"
    cfg.write_text("[occupancy]\nhold = 1.0\n")
    result = CliRunner().invoke(app, ["track", "--print-config", "--config", str(cfg)])
    assert result.exit_code != 0 and "hold" in f"{result.exception}{result.output}"
    # another command sharing the file says it ignores the section, and does not fail
    cfg.write_text("[sensor_motion]\nwindow = 4.0\n")
    result = CliRunner().invoke(
        app, ["detect", str(recording), "-o", str(tmp_path / "d.csv"), "--config", str(cfg)]
    )
    assert result.exit_code == 0, result.output
    assert "[sensor_motion] is read by another command" in result.output


def test_the_foreground_is_skipped_only_when_nobody_reads_it(recording: Path) -> None:
    """The leg MHT does not read the foreground: its people model then learns without
    computing it, and answers the same static times."""
    frames = _frames(7.0)  # the walls are background after the first-sight hold (6 s)
    full, lean = PeopleStaticModel("auto"), PeopleStaticModel("auto")
    lean.fill_foreground = False
    fuse = Fuse()
    for f in frames:
        a, b = full(fuse(f)), lean(fuse(f))
        assert a.foreground is not None and b.foreground is not None
        assert b.foreground.all()  # Fuse's, untouched
        q = np.vstack([CHAIR, _walker(f.stamp)])
        np.testing.assert_array_equal(full.static_time(q), lean.static_time(q))
    assert not full(fuse(frames[-1])).foreground.all()  # the grid's: walls are static
    pipe = build(recording, tracker="leg-mht")
    model = next(s for s in pipe.stages if isinstance(s, PeopleStaticModel))
    assert model.fill_foreground is False

    class ReadsForeground:  # a tracker of foreground points that also asks the model
        consumes = frozenset({"scans", "foreground"})

        def use_static_model(self, model: object) -> None:
            self.model = model

    fed = StaticFed(ReadsForeground(), PeopleStaticModel("auto"))
    assert fed.model.fill_foreground is True


def test_track_says_how_many_furniture_legs_it_left_out(tmp_path: Path) -> None:
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "furniture.npz"
    run_scenario("randomised-furniture", seconds=15.0, seed=3).write(rec)
    out = tmp_path / "t.csv"
    result = CliRunner().invoke(app, ["track", str(rec), "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert re.search(r"\d+ leg detections on places static for longer", result.output)
    config = tmp_path / "keep.toml"
    config.write_text("[leg_tracker]\npeople.static_legs = true\n")
    result = CliRunner().invoke(app, ["track", str(rec), "-o", str(out), "--config", str(config)])
    assert result.exit_code == 0, result.output
    assert "leg detections on places static" not in result.output
