"""The per-beam histogram of still lasers learned from the whole recording before tracking
(``pipeline/prelearn.py``, ``[auto_background] prelearn``)."""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from laserpeople.frame import Frame
from laserpeople.pipeline.background import (
    AutoBackground,
    AutoBackgroundParams,
    StaticWorldParams,
    load_static_world,
)
from laserpeople.pipeline.prelearn import PASS_DESCRIPTION, learn_recording, prelearn
from laserpeople.pipeline.preprocess import Fuse
from laserpeople.scan import Pose2D, Scan

N_BEAMS = 181
PERSON = slice(90, 96)  # the beams a person standing 2 m in front of the laser hides


def _walls() -> np.ndarray:
    return np.linspace(4.0, 6.0, N_BEAMS)


def _scan(ranges: np.ndarray, k: int, pose: Pose2D | None, increment: float) -> Scan:
    return Scan(
        0.1 * k, -math.pi / 2, increment, ranges, 0.05, 30.0, sensor="a", pose=pose, index=k
    )


def _recording(
    seconds: float = 10.0,
    stand: float = 3.0,
    walls: np.ndarray | None = None,
    pose_at: object = None,
    world: bool = True,
    increment_at: object = None,
) -> list[Frame]:
    """Frames at 10 Hz of one laser: a person stands on beams 90-95 at 2 m for the first
    ``stand`` seconds, then the beams see ``walls`` (default: walls 4-6 m away; NaN: no
    return). ``pose_at(k)`` gives the laser's pose of frame k (default: (1, 2, 0.3)), in
    the world frame unless ``world`` is false; ``increment_at(k)`` the beam spacing."""
    base = _walls() if walls is None else walls
    out = []
    for k in range(round(10 * seconds)):
        ranges = base.copy()
        if 0.1 * k < stand:
            ranges[PERSON] = 2.0
        pose = Pose2D(1.0, 2.0, 0.3) if pose_at is None else pose_at(k)  # type: ignore[operator]
        inc = math.pi / 180 if increment_at is None else increment_at(k)  # type: ignore[operator]
        scan = _scan(ranges, k, pose if world else None, inc)
        frame = "world" if world else "sensor"
        out.append(Frame(k, scan.stamp, (scan,), "a", frame, sensor_pose=scan.pose))
    return out


def _first_foreground(frames: list[Frame], static: StaticWorldParams | None = None) -> list[int]:
    """The beams foreground in the first frame of ``frames`` under ``auto`` after the pass
    over ``frames``."""
    fuse = Fuse()
    auto = AutoBackground(static=static)
    prelearn([fuse, auto], lambda: frames)
    out = auto(fuse(frames[0]))
    assert out.foreground is not None and out.points is not None
    return sorted(set(out.points.beams[out.foreground].tolist()))


def test_a_person_standing_for_the_first_seconds_is_foreground_from_the_first_scan() -> None:
    """A person stands on beams 90-95 for the first 3 s of a 10 s recording, the wall
    behind them: after the pass those beams, and only those, are foreground in the first
    scan; learning online (``prelearn`` false) they are background (the first 2 s see
    only the person)."""
    frames = _recording()
    assert _first_foreground(frames) == list(range(90, 96))
    off = replace(StaticWorldParams(), auto_background=AutoBackgroundParams(prelearn=False))
    assert _first_foreground(frames, off) == []


def _foreground_at(frames: list[Frame], k: int) -> list[int]:
    """The beams foreground in frame ``k`` under ``auto`` after the pass over ``frames``."""
    fuse = Fuse()
    auto = AutoBackground()
    prelearn([fuse, auto], lambda: frames)
    for frame in frames[: k + 1]:
        out = auto(fuse(frame))
    assert out.foreground is not None and out.points is not None
    return sorted(set(out.points.beams[out.foreground].tolist()))


def test_the_whole_recording_adds_only_what_lies_beyond() -> None:
    """Beams 80-109 return nothing (open space) but for the people on them: a person who
    stands on beams 90-95 for the first 3 s is background in the first scan, as learning
    online has it (nothing beyond them); one who stands there from 3 s to the end (70 % of
    the recording, frequent in it) is foreground, since the first seconds saw nothing
    static there; an object the first seconds saw on beam 100 at 5 m in every 4th scan,
    and then twice (7 % of the recording), stays background."""
    walls = _walls()
    walls[80:110] = np.nan
    assert _first_foreground(_recording(10.0, walls=walls)) == []
    late = _recording(10.0, walls=walls, stand=0.0)
    late = [
        replace(f, scans=(replace(f.scans[0], ranges=_with_person(f.scans[0].ranges)),))
        if f.index >= 30
        else f
        for f in late
    ]
    assert _foreground_at(late, 50) == list(range(90, 96))
    flicker = _recording(10.0, walls=walls, stand=0.0)
    flicker = [
        replace(f, scans=(replace(f.scans[0], ranges=_with_object(f.scans[0].ranges)),))
        if (f.index < 20 and f.index % 4 == 0) or f.index in (70, 90)
        else f
        for f in flicker
    ]
    assert _foreground_at(flicker, 90) == []


def _with_person(ranges: np.ndarray) -> np.ndarray:
    out = ranges.copy()
    out[PERSON] = 2.0
    return out


def _with_object(ranges: np.ndarray) -> np.ndarray:
    out = ranges.copy()
    out[100] = 5.0
    return out


def test_the_pass_says_from_how_many_frames_it_learned_and_samples_long_recordings() -> None:
    """100 frames, at most 30 learned: every 4th (ceil(100 / 30)), 25 of them; with the
    bound above the count every frame."""
    frames = _recording()
    few = replace(StaticWorldParams(), auto_background=AutoBackgroundParams(prelearn_scans=30))
    learned = learn_recording(frames, few, total=len(frames))
    assert (learned.learned, learned.read, learned.why_not) == (25, 100, "")
    assert learned.model is not None
    assert int(learned.model.counts("a")[0].sum()) == 25
    every = learn_recording(frames, StaticWorldParams(), total=len(frames))
    assert (every.learned, every.read) == (100, 100)
    fuse, auto = Fuse(), AutoBackground()
    prelearn([fuse, auto], lambda: frames)
    assert "beyond its ranges from all 100 frames of the whole recording" in auto.describe()


def test_the_pass_shows_its_progress_over_every_frame_it_reads() -> None:
    """With ``show`` the pass's frames go through it, named and with the count to expect
    (what ``track`` turns into a progress bar), and the same histogram is learned."""
    frames = _recording()
    seen: list[tuple[int | None, str]] = []
    passed: list[int] = []

    def show(items: Iterable[Frame], total: int | None, description: str) -> Iterator[Frame]:
        seen.append((total, description))
        for item in items:
            passed.append(item.index)
            yield item

    fuse, auto = Fuse(), AutoBackground()
    learned = prelearn([fuse, auto], lambda: frames, total=len(frames), show=show)
    assert seen == [(100, PASS_DESCRIPTION)]
    assert passed == list(range(100))
    assert learned is not None and (learned.learned, learned.read) == (100, 100)
    out = auto(fuse(frames[0]))
    assert out.foreground is not None and out.points is not None
    assert sorted(set(out.points.beams[out.foreground].tolist())) == list(range(90, 96))


def test_a_moving_laser_is_not_learned_before_tracking() -> None:
    """The laser drives off 0.2 m at frame 50 (world frame): nothing is learned, the
    model learns online as before and says why; it stands still within
    ``moved_distance`` (0.03 m): learned."""
    moving = _recording(pose_at=lambda k: Pose2D(1.0 + (0.2 if k >= 50 else 0.0), 2.0, 0.3))
    learned = learn_recording(moving, StaticWorldParams(), total=len(moving))
    assert learned.model is None and "frame 50" in learned.why_not
    fuse, auto = Fuse(), AutoBackground()
    prelearn([fuse, auto], lambda: moving)
    assert auto.describe().endswith(f"learned online over the first 2 s: {learned.why_not})")
    assert auto(fuse(moving[0])).foreground is not None
    assert getattr(auto.model, "learning", False)  # learning online
    jitter = _recording(pose_at=lambda k: Pose2D(1.0 + 0.03 * (k % 2), 2.0, 0.3))
    assert learn_recording(jitter, StaticWorldParams()).model is not None


def test_a_moving_laser_without_poses_is_not_learned_before_tracking() -> None:
    """Sensor frame, a cluttered room (ranges 2-8 m): from 3 s the laser turns by one
    beam per scan; the share of returns off the histogram of its first seconds tells it
    moved. Standing still it is learned."""
    rng = np.random.default_rng(1)
    room = rng.uniform(2.0, 8.0, N_BEAMS)
    still = _recording(world=False, stand=0.0, walls=room)
    turning = [
        f if f.index < 30 else replace(f, scans=(replace(f.scans[0], ranges=np.roll(room, k)),))
        for k, f in enumerate(still)
    ]
    learned = learn_recording(turning, StaticWorldParams())
    assert learned.model is None and "(sensor frame)" in learned.why_not
    assert learn_recording(still, StaticWorldParams()).model is not None


def test_a_new_beam_layout_is_not_learned_before_tracking() -> None:
    frames = _recording(increment_at=lambda k: math.pi / (180 if k < 60 else 360))
    learned = learn_recording(frames, StaticWorldParams())
    assert learned.model is None and "beam layout" in learned.why_not


def test_the_paper_preset_learns_online() -> None:
    assert AutoBackgroundParams().prelearn is True
    assert load_static_world(None, "paper").auto_background.prelearn is False
    fuse, auto = Fuse(), AutoBackground(static=load_static_world(None, "paper"))
    assert prelearn([fuse, auto], lambda: _recording()) is None
    assert auto.prelearned is None
    assert auto.describe().endswith("first 2 s ([auto_background] prelearn = false))")
    with pytest.raises(ValueError, match="prelearn_scans"):
        AutoBackgroundParams(prelearn_scans=0)


def test_the_wall_beyond_is_kept_after_learning_and_in_a_saved_model(tmp_path: Path) -> None:
    """The histogram learns the first 2 s (the person standing), with the whole
    recording's wall beyond them: after learning the person is foreground and the wall
    background on beams 90-95, with no relearning needed, also once saved and loaded."""
    from laserpeople.background.beam_histogram import BeamHistogramBackground

    frames = _recording()
    learned = learn_recording(frames, StaticWorldParams())
    assert learned.model is not None
    model = BeamHistogramBackground()
    model.use_whole_recording(learned.model)
    fuse = Fuse()
    for frame in frames[:25]:  # learning ends at 2 s (frame 20); the person stands
        out = model(fuse(frame))
    assert not model.learning and model.relearned("a") == 0
    assert out.foreground is not None and out.points is not None
    assert sorted(out.points.beams[out.foreground].tolist()) == list(range(90, 96))
    again = BeamHistogramBackground.load(model.save(tmp_path / "bg.npz"))
    person, wall = frames[0].scans[0], frames[-1].scans[0]
    assert np.flatnonzero(again.foreground_of(person)).tolist() == list(range(90, 96))
    assert not again.foreground_of(wall).any()


def _driving_past_a_wall(frames: int = 60) -> list[Frame]:
    """A laser facing +y drives along x at 0.5 m/s (10 Hz) past a straight wall at
    y = 3 m, beams -60..60 deg, world frame: every frame sees the wall where it is."""
    angles = np.radians(np.arange(-60.0, 60.5, 1.0))
    ranges = 3.0 / np.cos(angles)
    out = []
    for k in range(frames):
        pose = Pose2D(0.05 * k, 0.0, math.pi / 2)
        scan = Scan(
            0.1 * k,
            angles[0],
            math.radians(1.0),
            ranges,
            0.05,
            30.0,
            sensor="a",
            pose=pose,
            index=k,
        )
        out.append(Frame(k, scan.stamp, (scan,), "a", "world", sensor_pose=pose))
    return out


def test_a_moving_lasers_recording_seeds_the_occupancy_grid_with_what_stayed_put() -> None:
    """The laser moves from frame 2: the pass finds no histogram and a second pass counts
    the map; once the model switches to the occupancy grid the wall is static (for ever,
    as a prior map's obstacles) from the first frame on, 0.5 m before it is not, and the
    model says what seeded the grid. With ``--map`` or ``prelearn`` false no map is counted."""
    frames = _driving_past_a_wall()
    opened: list[int] = []

    def open_frames() -> list[Frame]:
        opened.append(1)
        return frames

    fuse, auto = Fuse(), AutoBackground()
    learned = prelearn([fuse, auto], open_frames)
    assert learned is not None and learned.laser_moved and learned.model is None
    assert learned.grid_map is not None and learned.map_frames == len(frames)
    assert len(opened) == 2
    for frame in frames[:3]:
        auto(fuse(frame))
    assert auto.chosen == "occupancy" and auto.switched_at == 2
    wall = np.array([[0.0, 3.0], [1.5, 3.0], [2.9, 3.0]])
    assert np.isinf(auto.static_time(wall)).all()
    assert (auto.static_time(wall - [0.0, 0.5]) == 0.0).all()
    assert "seeded by what stayed put in the whole recording" in auto.describe()
    assert f"or more of {len(frames)} frames and in 97 % of those" in auto.describe()

    with_map = AutoBackground(map_path="site.yaml")
    learned = prelearn([fuse, with_map], open_frames)
    assert learned is not None and learned.grid_map is None and len(opened) == 3
    off = replace(StaticWorldParams(), auto_background=AutoBackgroundParams(prelearn=False))
    online = AutoBackground(static=off)
    assert prelearn([fuse, online], open_frames) is None
    for frame in frames[:3]:
        online(fuse(frame))
    assert online.chosen == "occupancy" and not np.isinf(online.static_time(wall)).any()
    assert "seeded" not in online.describe()


def test_the_map_rule_is_checked() -> None:
    with pytest.raises(ValueError, match="map_min_hits"):
        AutoBackgroundParams(map_min_hits=0)
    with pytest.raises(ValueError, match="map_hit_share"):
        AutoBackgroundParams(map_hit_share=0.0)


def test_a_map_pass_that_cannot_read_the_recording_whole_says_so() -> None:
    """The second pass meets a damaged frame: no map, the occupancy grid learns online and
    the model's line says why (tracking meets the damage again at its frame)."""
    from laserpeople.errors import RecordingError

    frames = _driving_past_a_wall()
    passes: list[int] = []

    def open_frames() -> Iterator[Frame]:
        passes.append(1)
        for frame in frames:
            if len(passes) == 2 and frame.index == 30:
                raise RecordingError("scan 30 is damaged", path="run.bag")
            yield frame

    fuse, auto = Fuse(), AutoBackground()
    learned = prelearn([fuse, auto], open_frames)
    assert learned is not None and learned.grid_map is None and len(passes) == 2
    assert "could not be read whole" in learned.map_why_not
    assert "scan 30 is damaged" in learned.map_why_not
    for frame in frames[:3]:
        auto(fuse(frame))
    assert auto.chosen == "occupancy"
    assert not np.isinf(auto.static_time(np.array([[1.5, 3.0]]))).any()
    assert ", not seeded by the whole recording (the recording could not" in auto.describe()
