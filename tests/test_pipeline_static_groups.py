"""The group tracker through the pipeline's stages with the people static model: a chair put
down after the background was learned is not a group once its place is static, a person
who walked in and stands stays one group, and ``laserpeople track`` says how many group-scans
it did not report."""

from __future__ import annotations

import math
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.frame import Frame
from laserpeople.pipeline.background import background_of
from laserpeople.pipeline.recording import add_people_static_model, observe_stages_for
from laserpeople.pipeline.static_people import PeopleStaticModel
from laserpeople.scan import Pose2D, Scan
from laserpeople.tracking import registry
from laserpeople.tracking.groups import GroupTrackerParams
from laserpeople.tracks import Tracks
from test_pipeline_static_people import CHAIR, INC, LEG_R, POST_R, RATE, _ranges

CHAIR_FROM = 3.0  # s: put down after the background's 2 s of learning


def _walker(t: float) -> np.ndarray:
    """Legs (2, 2) of a person walking along -y at 0.8 m/s for 4 s from (-3, 2.5), then
    standing."""
    walk = min(t, 4.0)
    body = np.array([-3.0, 2.5 - 0.8 * walk])
    swing = 0.15 * math.sin(2 * math.pi * walk) if t < 4.0 else 0.0
    return np.array([[body[0] - 0.125, body[1] + swing], [body[0] + 0.125, body[1] - swing]])


def _frames(seconds: float) -> list[Frame]:
    pose = Pose2D(0.0, 0.0, 0.0)
    out = []
    for k in range(int(seconds * RATE)):
        t = k / RATE
        chair = CHAIR if t >= CHAIR_FROM else np.empty((0, 2))
        discs = np.vstack([chair, _walker(t)])
        radii = np.array([POST_R] * len(chair) + [LEG_R] * 2)
        ranges = _ranges(discs, radii, np.zeros(2), 0.0)
        scan = Scan(t, 0.0, INC, ranges, sensor="laser", index=k, pose=pose)
        out.append(Frame(k, t, (scan,), "laser", frame="world", sensor_pose=pose))
    return out


def _track(params: GroupTrackerParams, frames: list[Frame]) -> tuple[object, list[Tracks]]:
    tracker = registry.get("group-mht").make(params)
    preprocess, _ = observe_stages_for(frozenset(tracker.consumes), None)
    model = add_people_static_model(tracker, preprocess, "auto")
    if params.static_groups:
        assert model is None
    else:
        # before the group tracker's own model, whose foreground it must not undo
        assert isinstance(model, PeopleStaticModel) and model is preprocess[-2]
        assert background_of(preprocess) is preprocess[-1]
        assert tracker.static_model is model  # type: ignore[attr-defined]
        assert model.fill_foreground is False  # the histogram's foreground is kept
    out = []
    for f in frames:
        for stage in preprocess:
            f = stage(f)
        out.append(tracker.update(f))  # type: ignore[attr-defined]
    return tracker, out


def _holds(tracks: Tracks, place: np.ndarray, radius: float) -> list[int]:
    return [
        t.track_id
        for t in tracks.of_kind("group")
        if t.contour is not None and (np.linalg.norm(t.contour - place, axis=1) < radius).any()
    ]


def test_a_chair_put_down_is_not_a_group_once_static_but_a_person_who_stands_is() -> None:
    frames = _frames(30.0)
    paper = replace(GroupTrackerParams(), static_groups=True)
    _, bare = _track(paper, frames)
    tracker, fed = _track(GroupTrackerParams(), frames)
    chair = CHAIR.mean(axis=0)
    after = [k for k, f in enumerate(frames) if f.stamp > CHAIR_FROM + 1.0]
    # 000 (every group): the chair is a group from soon after it is put down to the end
    assert sum(bool(_holds(bare[k], chair, 0.5)) for k in after) > 0.9 * len(after)
    # the default: not once its place has been static for static_time (10 s)
    static = [k for k, f in enumerate(frames) if f.stamp > CHAIR_FROM + 10.0 + 1.0]
    assert not any(_holds(fed[k], chair, 0.5) for k in static)
    assert tracker.static_groups_hidden >= len(static)  # type: ignore[attr-defined]
    # the walker: one group from its first scans to the end (26 s standing)
    ids = [_holds(fed[k], _walker(f.stamp).mean(axis=0), 0.4) for k, f in enumerate(frames)]
    seen = [k for k, i in enumerate(ids) if i]
    assert seen and frames[seen[0]].stamp < 2.5  # (the background learns for 2 s)
    assert len({i for k in seen for i in ids[k]}) == 1
    assert len(seen) >= len(frames) - seen[0] - 2


def test_track_says_how_many_group_scans_it_did_not_report(tmp_path: Path) -> None:
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "furniture.npz"
    run_scenario("randomised-furniture", seconds=14.0, seed=3).write(rec)
    out = tmp_path / "g.csv"
    # the grid learns online (the map of the whole recording makes this scene's furniture
    # background from the first scan, and no group forms on it to be hidden)
    online = tmp_path / "online.toml"
    online.write_text("[auto_background]\nprelearn = false\n")
    track = ["track", str(rec), "-o", str(out), "--tracker", "group-mht", "--config"]
    result = CliRunner().invoke(app, [*track, str(online)])
    assert result.exit_code == 0, result.output
    assert "static world model for people: occupancy grid" in result.output
    assert re.search(r"\d+ group-scans on places static for longer", result.output)
    config = tmp_path / "paper.toml"
    config.write_text(
        "[group_tracker]\nstatic_groups = true\n[auto_background]\nprelearn = false\n"
    )
    result = CliRunner().invoke(
        app, ["track", str(rec), "-o", str(out), "--tracker", "group-mht", "--config", str(config)]
    )
    assert result.exit_code == 0, result.output
    assert "group-scans on places static" not in result.output
    assert "static world model for people: none (group_tracker.static_groups = true)" in (
        result.output
    )
