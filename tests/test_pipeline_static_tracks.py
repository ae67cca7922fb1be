"""Person tracks on static places left out behind trackers without a static world of their
own (``pipeline/static_tracks.py``): the rule by hand on a scripted static model, the wiring
in ``build``, and the nn tracker on a chair and a walker who stops."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.pipeline import Pipeline, build
from laserpeople.pipeline.background import StaticWorldParams, load_static_world
from laserpeople.pipeline.recording import add_static_track_filter
from laserpeople.pipeline.static_people import PeopleStaticModel
from laserpeople.pipeline.static_tracks import StaticTrackFilter, StaticTrackParams
from laserpeople.tracking import registry
from laserpeople.tracks import Track, Tracks
from test_pipeline_static_people import _frames, _on_chair, _walker


class _Scripted:
    """A static world model whose static times are set by the test: ``places`` maps a
    point (x, y) to the time [s] since which it is static (None: not static)."""

    def __init__(self) -> None:
        self.now = 0.0
        self.places: dict[tuple[float, float], float] = {}

    def static_time(self, positions: np.ndarray) -> np.ndarray:
        out = []
        for x, y in np.asarray(positions).reshape(-1, 2):
            since = [s for (px, py), s in self.places.items() if np.hypot(x - px, y - py) < 0.3]
            out.append(self.now - min(since) if since else 0.0)
        return np.array(out)


def _person(track_id: int, x: float, y: float, vx: float = 0.0) -> Track:
    return Track(track_id, "person", np.array([x, y]), np.array([vx, 0.0]), np.eye(2) * 0.01)


def _step(stage: StaticTrackFilter, model: _Scripted, t: float, *tracks: Track) -> list[int]:
    model.now = t
    out = stage.update(Tracks(t, int(t * 10), tracks), None)  # type: ignore[arg-type]
    return [tr.track_id for tr in out.tracks if tr.kind == "person"]


def _stand(stage: StaticTrackFilter, model: _Scripted, t0: float, t1: float, track: Track) -> list:
    """Steps every 0.1 s from ``t0`` to ``t1`` (excluded) with ``track``: what was reported."""
    return [_step(stage, model, t0 + 0.1 * k, track) for k in range(round((t1 - t0) / 0.1))]


def test_a_track_that_never_walked_is_hidden_once_its_place_is_static() -> None:
    model = _Scripted()
    model.places[(2.0, 1.0)] = -5.0  # static since t = -5 s
    stage = StaticTrackFilter(model)  # type: ignore[arg-type]
    # static for 10 s or less (static_time), then tracks stand there for less than
    # stand_time (10 s, from t = 5.1 s): reported; from then on hidden
    shown = _stand(stage, model, 0.0, 20.0, _person(1, 2.0, 1.0))
    assert shown[:151] == [[1]] * 151 and shown[151:] == [[]] * 49
    assert stage.hidden == 49 and stage.hidden_ids == {1}
    # a new id on the same place within place_gap continues the place's time: hidden
    assert _step(stage, model, 21.0, _person(2, 2.0, 1.05)) == []
    # groups and legs are never touched
    group = Track(7, "group", np.array([2.0, 1.0]), np.zeros(2), np.eye(2))
    model.now = 21.1
    kept = stage.update(Tracks(21.1, 211, (group, _person(2, 2.0, 1.0))), None)  # type: ignore[arg-type]
    assert [(t.kind, t.track_id) for t in kept.tracks] == [("group", 7)]
    # after place_gap without anyone there, the place's time starts again
    assert _step(stage, model, 30.0, _person(3, 2.0, 1.0)) == [3]


def test_hopping_between_static_posts_is_not_walking() -> None:
    model = _Scripted()
    for x in (0.0, 0.4, 0.8, 1.2):
        model.places[(x, 0.0)] = 0.0
    stage = StaticTrackFilter(model)  # type: ignore[arg-type]
    shown = []
    for k in range(150):  # 1.2 m back and forth over four posts, all static for > 10 s
        x = [0.0, 0.4, 0.8, 1.2][k % 4]
        shown.append(_step(stage, model, 20.0 + 0.1 * k, _person(3, x, 0.0, vx=4.0)))
    # reported for its first stand_time (10 s), hidden from then on
    assert shown[:100] == [[3]] * 100 and shown[100:] == [[]] * 50


def test_a_walker_who_stops_keeps_the_track_unless_the_place_was_static_before() -> None:
    model = _Scripted()
    stage = StaticTrackFilter(model)  # type: ignore[arg-type]
    # walks 2 m over free places from t = 0 to 2 s, then stands at (2, 0) ...
    for k in range(21):
        assert _step(stage, model, 0.1 * k, _person(1, 0.1 * k, 0.0, vx=1.0)) == [1]
    model.places[(2.0, 0.0)] = 2.0  # ... whose cells are static from when it stopped
    assert _stand(stage, model, 2.1, 60.0, _person(1, 2.0, 0.0)) == [[1]] * 579
    # another walker stops at a place static since long before it came (slid onto a chair)
    model.places[(5.0, 0.0)] = -100.0
    for k in range(21):
        _step(stage, model, 60.0 + 0.1 * k, _person(2, 3.0 + 0.1 * k, 0.0, vx=1.0))
    # it is on the chair's place from t = 61.7 s (its cells reach 0.3 m): reported while
    # tracks have stood there for less than stand_time, then hidden (static 170 s > stood
    # 10 s + arrival_slack 2 s)
    shown = _stand(stage, model, 62.1, 75.0, _person(2, 5.0, 0.0))
    assert shown[:96] == [[2]] * 96 and shown[96:] == [[]] * 33
    # moving faster than min_speed it is not standing: reported
    assert _step(stage, model, 75.0, _person(2, 5.0, 0.0, vx=0.5)) == [2]


def test_ids_unseen_for_forget_after_are_forgotten() -> None:
    model = _Scripted()
    stage = StaticTrackFilter(model, StaticTrackParams(forget_after=5.0))  # type: ignore[arg-type]
    for k in range(100):
        _step(stage, model, 0.1 * k, _person(k, float(k), 0.0))
    assert len(stage._seen) <= 51  # ids of the last 5 s (and this scan's)


def test_params_are_checked() -> None:
    with pytest.raises(ValueError, match="not negative"):
        StaticTrackParams(static_time=-1.0)
    with pytest.raises(ValueError, match="forget_after"):
        StaticTrackParams(forget_after=0.0)


def test_build_adds_the_filter_only_behind_trackers_without_their_own_static_world(
    tmp_path: Path,
) -> None:
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "s.npz"
    run_scenario("crossing-3", seconds=1.0, seed=0).write(rec)
    for name, wanted in (("nn", True), ("csa", True), ("leg-mht", False), ("group-mht", False)):
        pipe = build(rec, tracker=name)
        filters = [i for i in pipe.identify if isinstance(i, StaticTrackFilter)]
        models = [s for s in pipe.stages if isinstance(s, PeopleStaticModel)]
        assert bool(filters) == wanted, name
        if wanted:
            assert filters[0].model is models[0] and not models[0].fill_foreground
        pipe.close()
    off = StaticWorldParams(static_tracks=StaticTrackParams(hide=False))
    assert add_static_track_filter(registry.get("nn").make(), [], "auto", None, off) is None
    assert add_static_track_filter(registry.get("nn").make(), [], "none") is None
    config = tmp_path / "paper.toml"
    config.write_text("[static_tracks]\nhide = false\n")
    assert load_static_world(config).static_tracks.hide is False


def test_nn_people_on_a_chair_are_hidden_and_a_walker_who_stops_is_not() -> None:
    frames = _frames(30.0)
    p = StaticTrackParams()
    # the chair is static after the grid's first-sight hold, then stands for stand_time
    late = [k for k, f in enumerate(frames) if f.stamp > p.static_time + p.stand_time + 1.0]

    def run(hide: bool) -> tuple[list[Tracks], StaticTrackFilter | None]:
        tracker = registry.get("nn").make()
        preprocess: list = []
        static = StaticWorldParams(static_tracks=StaticTrackParams(hide=hide))
        stage = add_static_track_filter(tracker, preprocess, "auto", None, static)
        pipe = Pipeline(
            frames,
            preprocess=preprocess,
            tracker=tracker,
            identify=[stage] if stage is not None else [],
            source_fields=frozenset({"scans", "legs"}),
        )
        return [step.tracks for step in pipe], stage  # type: ignore[misc]

    bare, _ = run(hide=False)
    hidden, stage = run(hide=True)
    # nn pairs the chair's posts into people for most of the run; none once static
    assert sum(bool(_on_chair(bare[k])) for k in late) > 0.8 * len(late)
    assert not any(_on_chair(hidden[k]) for k in late)
    assert stage is not None and stage.hidden > 0.8 * len(late)

    # the walker (walks 4 s, then stands for 26 s) is reported as often as without the rule
    def near(out: Tracks, t: float) -> bool:
        body = _walker(t).mean(axis=0)
        return any(np.hypot(*(p.position - body)) < 0.5 for p in out.of_kind("person"))

    walker = [near(o, f.stamp) for o, f in zip(hidden, frames, strict=True)]
    walker_bare = [near(o, f.stamp) for o, f in zip(bare, frames, strict=True)]
    assert walker == walker_bare and sum(walker) > 0.9 * len(frames)


def test_track_says_how_many_person_scans_it_did_not_report(
    shared_data: Path, tmp_path: Path
) -> None:
    """On the real demo bag the upper-body tracker has a track on a thing put down after
    the background was learned (about 80 s of it, docs/people-benchmarks.md)."""
    bag = shared_data / "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag"
    out = tmp_path / "p.csv"
    args = ["track", str(bag), "-o", str(out), "--tracker", "upper-body-pf"]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "static world model for people: occupancy grid" in result.output
    said = re.search(r"(\d+) person-scans of (\d+) tracks on places static", result.output)
    assert said and int(said.group(1)) > 300, result.output
    config = tmp_path / "paper.toml"
    config.write_text("[static_tracks]\nhide = false\n")
    result = CliRunner().invoke(app, [*args, "--config", str(config)])
    assert result.exit_code == 0, result.output
    assert "person-scans of" not in result.output
