"""`laserpeople batch` and laserpeople.batch on a real Dask LocalCluster (processes and
threads), on a handful of small simulated recordings and some bad ones."""

from __future__ import annotations

import json
import os
import shutil
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("dask.distributed")
pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")

from typer.testing import CliRunner  # noqa: E402

from laserpeople.batch import ClusterSpec, TrackOptions, open_client, resolve, run_batch  # noqa: E402
from laserpeople.batch.manifest import Manifest  # noqa: E402
from laserpeople.batch.parquet import iter_tracks_parquet, tracks_schema  # noqa: E402
from laserpeople.batch.summary import summary_schema  # noqa: E402
from laserpeople.batch.task import attempt_marker, count_attempts, track_recording  # noqa: E402
from laserpeople.cli import app  # noqa: E402
from laserpeople.errors import ConfigError  # noqa: E402
from laserpeople.io.tracks_csv import iter_tracks_csv  # noqa: E402

runner = CliRunner()
GOOD = ("demo", "crossing-3", "speed-normal")


@pytest.fixture(scope="module")
def recordings(tmp_path_factory) -> dict[str, Path]:
    """Three short simulated recordings with truth, a garbage file, a truncated recording
    and a path that does not exist."""
    from laserpeople.sim import run_scenario

    folder = tmp_path_factory.mktemp("recordings")
    paths = {}
    for k, name in enumerate(GOOD):
        paths[name] = run_scenario(name, seconds=2.0, seed=k + 1).write(folder / f"{name}.npz")
    (folder / "garbage.npz").write_bytes(b"not a recording")
    data = paths["demo"].read_bytes()
    (folder / "truncated.npz").write_bytes(data[: len(data) // 2])
    paths["garbage"] = folder / "garbage.npz"
    paths["truncated"] = folder / "truncated.npz"
    paths["missing"] = folder / "missing.bag"
    return paths


@pytest.fixture(scope="module")
def client():
    """A LocalCluster of two worker processes (a worker may die twice per task)."""
    with open_client(ClusterSpec(workers=2, retries=2)) as c:
        yield c


ONE_TOPIC = TrackOptions(topics=("all",))


def by_name(rows):
    return {r.name: r for r in rows}


@pytest.mark.slow
def test_processes_cluster_tracks_good_and_reports_bad(recordings, client, tmp_path):
    paths = list(recordings.values())
    result = run_batch(paths, tmp_path / "out", ONE_TOPIC, client=client)
    rows = by_name(result.rows)
    assert [r.name for r in result.rows] == list(recordings)  # input order
    for name in GOOD:
        r = rows[name]
        assert r.status == "done", r.error
        assert r.scans > 0 and r.duration_s > 1.5 and r.attempts == 1
        assert r.ids >= 1 and r.person_seconds > 0
        assert (tmp_path / "out" / r.output).is_file()
    for name, text in (
        ("garbage", "garbage.npz"),
        ("truncated", "truncated.npz"),
        ("missing", "missing.bag: file not found"),
    ):
        assert rows[name].status == "failed"
        assert text in rows[name].error
    assert result.failed == 3
    assert not list((tmp_path / "out" / "tracks").glob(".*.tmp"))  # no temp file left


@pytest.mark.slow
def test_csv_is_what_track_writes(recordings, client, tmp_path):
    result = run_batch([recordings["demo"]], tmp_path / "out", ONE_TOPIC, client=client)
    res = runner.invoke(
        app,
        ["track", str(recordings["demo"]), "--topics", "all", "-o", str(tmp_path / "t.csv")],
    )
    assert res.exit_code == 0, res.output
    written = (tmp_path / "out" / result.rows[0].output).read_text()
    assert written == (tmp_path / "t.csv").read_text()


@pytest.mark.slow
def test_rerun_skips_done_redoes_changed_and_force(recordings, client, tmp_path):
    folder = tmp_path / "recs"
    folder.mkdir()
    paths = [Path(shutil.copy(recordings[n], folder)) for n in ("demo", "crossing-3")]
    out = tmp_path / "out"
    first = run_batch(paths, out, ONE_TOPIC, client=client)
    stamp = {r.name: (out / r.output).stat().st_mtime_ns for r in first.rows}
    again = run_batch(paths, out, ONE_TOPIC, client=client)
    assert [r.status for r in again.rows] == ["skipped", "skipped"]
    assert again.submitted == 0
    assert {r.name: (out / r.output).stat().st_mtime_ns for r in again.rows} == stamp
    # a changed recording (other content, same name) is tracked again, the other is not
    shutil.copy(recordings["speed-normal"], paths[1])
    changed = by_name(run_batch(paths, out, ONE_TOPIC, client=client).rows)
    assert changed["demo"].status == "skipped"
    assert changed["crossing-3"].status == "done"
    # a changed configuration redoes all; so does force
    other = TrackOptions(topics=("all",), tracker="nn")
    assert {r.status for r in run_batch(paths, out, other, client=client).rows} == {"done"}
    forced = run_batch(paths, out, other, client=client, force=True)
    assert {r.status for r in forced.rows} == {"done"}


def test_digest_changes_with_any_parameter(tmp_path):
    base = resolve(ONE_TOPIC)
    assert resolve(ONE_TOPIC).digest == base.digest
    config = tmp_path / "c.toml"
    config.write_text("[leg_detector]\nscore_threshold = 0.5\n")
    assert resolve(replace(ONE_TOPIC, config=config)).digest != base.digest
    tuned = resolve(ONE_TOPIC, {"leg_detector": {"score_threshold": 0.5}})
    assert tuned.digest == resolve(replace(ONE_TOPIC, config=config)).digest
    assert resolve(replace(ONE_TOPIC, format="parquet")).digest != base.digest
    with pytest.raises(ConfigError, match="leg_detectr"):
        resolve(ONE_TOPIC, {"leg_detectr": {"score_threshold": 0.5}})


def fail_on_crossing(task):
    """A task that fails for crossing-3 (a run killed before it finished it). An ordinary
    exception: a KeyboardInterrupt raised in a Dask worker's task thread could leave its
    future unresolved on a loaded machine (the test once waited half an hour for it)."""
    if task.name == "crossing-3":
        raise RuntimeError("killed")
    return track_recording(task)


def die_once(task):
    """A task whose worker process dies the first time it starts demo."""
    if task.name == "demo" and count_attempts(task.out, task.key) == 0:
        marker = attempt_marker(task.out, task.key)
        marker.parent.mkdir(parents=True, exist_ok=True)
        marker.touch()
        os._exit(1)
    return track_recording(task)


@pytest.fixture
def by_value():
    """Send this module's task functions to the workers by value (they cannot import it)."""
    import cloudpickle

    module = sys.modules[__name__]
    cloudpickle.register_pickle_by_value(module)
    yield
    cloudpickle.unregister_pickle_by_value(module)


@pytest.mark.slow
def test_killed_run_resumes_with_only_unfinished_recordings(recordings, client, tmp_path, by_value):
    paths = [recordings[n] for n in GOOD]
    out = tmp_path / "out"
    killed = run_batch(paths, out, ONE_TOPIC, client=client, task_function=fail_on_crossing)
    assert by_name(killed.rows)["crossing-3"].status == "failed"
    # a temp file as a killed worker leaves it is never taken for done, nor is a manifest
    # line cut off by the kill
    (out / "tracks" / ".crossing-3.csv.999-abcdef.tmp").write_text("scan,stamp\n0,")
    with (out / "manifest.jsonl").open("a") as f:
        f.write('{"version": 1, "name": "crossing-3", "input_hash": "')
    assert Manifest(out).torn == 1
    resumed = run_batch(paths, out, ONE_TOPIC, client=client)
    assert {r.name: r.status for r in resumed.rows} == {
        "demo": "skipped",
        "crossing-3": "done",
        "speed-normal": "skipped",
    }
    assert resumed.submitted == 1
    assert Manifest(out).done_rows("crossing-3", resumed.rows[1].input_hash, resume_digest())


def resume_digest():
    return resolve(ONE_TOPIC).digest


@pytest.mark.slow
def test_dead_worker_task_is_redone_and_reported(recordings, client, tmp_path, by_value):
    paths = [recordings["demo"], recordings["crossing-3"]]
    result = run_batch(paths, tmp_path / "out", ONE_TOPIC, client=client, task_function=die_once)
    rows = by_name(result.rows)
    assert rows["demo"].status == "done", rows["demo"].error
    assert rows["crossing-3"].status == "done", rows["crossing-3"].error
    # at least the one death; on a loaded machine the scheduler may also lose the restarted
    # worker (missed heartbeats) and run a task once more, which is counted the same way
    assert 2 <= rows["demo"].attempts <= 3
    assert "demo" in [r.name for r in result.retried]


@pytest.mark.slow
def test_threads_cluster_and_parquet(recordings, tmp_path):
    paths = [recordings["demo"], recordings["garbage"]]
    spec = ClusterSpec(workers=1, threads=2, processes=False)
    options = TrackOptions(topics=("all",), format="parquet")
    result = run_batch(paths, tmp_path / "out", options, spec)
    done = by_name(result.rows)["demo"]
    assert done.output.endswith(".parquet")
    table = pq.read_table(tmp_path / "out" / done.output)
    assert table.schema.remove_metadata() == tracks_schema()
    assert table.schema.metadata[b"frame"] in (b"world", b"sensor")
    assert table.num_rows == done.rows
    summary = pq.read_table(tmp_path / "out" / "summary.parquet")
    assert summary.schema.remove_metadata() == summary_schema()
    assert summary.column("status").to_pylist() == ["done", "failed"]
    # the same tracks as the CSV, to its 4 decimals
    csv_result = run_batch([recordings["demo"]], tmp_path / "csv", ONE_TOPIC, spec)
    from_csv = list(iter_tracks_csv(tmp_path / "csv" / csv_result.rows[0].output))
    from_parquet = list(iter_tracks_parquet(tmp_path / "out" / done.output))
    assert [t.scan_index for t in from_csv] == [t.scan_index for t in from_parquet]
    for a, b in zip(from_csv, from_parquet, strict=True):
        assert a.frame == b.frame  # the file's own frame
        assert a.sensor_pose is not None and b.sensor_pose is not None  # the demo's poses
        np.testing.assert_allclose(a.sensor_pose.as_array(), b.sensor_pose.as_array(), atol=1e-6)
        assert [t.track_id for t in a.tracks] == [t.track_id for t in b.tracks]
        np.testing.assert_allclose(
            [t.position for t in a.tracks], [t.position for t in b.tracks], atol=1e-4
        )


@pytest.mark.slow
def test_each_topic_on_its_own_by_default(recordings, tmp_path):
    spec = ClusterSpec(workers=1, processes=False)
    result = run_batch([recordings["crossing-3"]], tmp_path / "out", TrackOptions(), spec)
    topics = [r.topic for r in result.rows]
    assert len(topics) >= 2 and "fused" not in topics  # the simulated robot's two lasers
    assert len({r.output for r in result.rows}) == len(topics)


@pytest.mark.slow
def test_cli_exit_code_table_and_evaluate_over_the_folder(recordings, tmp_path):
    out = tmp_path / "out"
    args = [
        "batch",
        str(recordings["demo"]),
        str(recordings["crossing-3"]),
        str(recordings["garbage"]),
    ]
    res = runner.invoke(app, [*args, "--out", str(out), "--topics", "all", "--no-processes"])
    assert res.exit_code == 1, res.output  # one failed recording
    assert "garbage" in res.output and "failed" in res.output
    assert (out / "summary.csv").is_file()
    lines = (out / "manifest.jsonl").read_text().splitlines()
    assert len(lines) == 3 and all(json.loads(line)["version"] == 1 for line in lines)
    res = runner.invoke(app, ["evaluate", str(out), "--json"])
    assert res.exit_code == 0, res.output
    rows = json.loads(res.stdout.strip().splitlines()[-1])
    assert [r["recording"] for r in rows] == ["demo laser", "crossing-3 fused", "pooled (2)"]
    assert all(0.0 < r["hota"] <= 1.0 for r in rows)
    res = runner.invoke(app, ["batch", str(tmp_path / "*.nothing"), "--out", str(out)])
    assert res.exit_code != 0 and "matches no file" in str(res.exception or res.output)


@pytest.mark.slow
def test_sweep_ranks_settings_and_scores_held_out(recordings, tmp_path):
    from laserpeople.batch.sweep import load_sweep, run_sweep

    sweep = tmp_path / "sweep.toml"
    sweep.write_text(
        'metric = "hota"\nheld_out = ["speed-*"]\nbest = 1\n'
        "[grid.leg_detector]\nscore_threshold = [0.0, 20.0]\n"
    )
    spec = load_sweep(sweep)
    assert len(spec.settings()) == 2
    paths = [recordings[n] for n in GOOD]
    # (the arras people ask no static world model: --background is said to have no effect)
    options = replace(ONE_TOPIC, people_policy="arras", background="histogram")
    result = run_sweep(
        paths, tmp_path / "out", options, spec, ClusterSpec(workers=1, processes=False)
    )
    (said,) = result.unused
    assert said.startswith("--background histogram had no effect on 3 of 3 recordings")
    best, worst = result.ranked
    # a margin threshold of 20 leaves almost no leg: the default ranks first
    assert best.setting == {"leg_detector": {"score_threshold": 0.0}}
    assert best.tune["hota"] > worst.tune["hota"]
    assert best.held_out and not worst.held_out
    assert result.held_out == [str(recordings["speed-normal"])]
    assert (tmp_path / "out" / "settings-000" / "config.toml").is_file()
    lines = (tmp_path / "out" / "sweep.csv").read_text().splitlines()
    assert len(lines) == 3 and lines[1].startswith("1,settings-000")
    bad = tmp_path / "bad.toml"
    bad.write_text('metric = "speed"\n[grid.leg_detector]\nscore_threshold = [0.0]\n')
    with pytest.raises(ConfigError, match="speed"):
        load_sweep(bad)


def test_parquet_keeps_the_frame_and_sensor_pose(tmp_path):
    from laserpeople.batch.parquet import COLUMNS, TracksParquetSink
    from laserpeople.frame import Frame
    from laserpeople.scan import Pose2D
    from laserpeople.tracks import Track, Tracks

    pose = Pose2D(3.0, -2.0, 0.75)
    leg = Track(4, "leg", np.array([1.0, 0.5]), np.zeros(2), np.eye(2) * 0.01)
    sink = TracksParquetSink(tmp_path / "t.parquet", frame="sensor")
    for k, p in ((0, pose), (1, None)):
        frame = Frame(k, 0.1 * k, (), "/scan", "sensor")
        sink.write(frame, Tracks(0.1 * k, k, (leg,), "sensor", p))
    sink.close()
    back = list(iter_tracks_parquet(tmp_path / "t.parquet", frame="world"))
    assert [(t.frame, t.sensor_pose) for t in back] == [("sensor", pose), ("sensor", None)]
    # a file written before the pose columns existed: read without poses
    table = pq.read_table(tmp_path / "t.parquet")
    old = table.drop_columns(["sensor_x", "sensor_y", "sensor_yaw"])
    pq.write_table(old, tmp_path / "old.parquet")
    assert [t.sensor_pose for t in iter_tracks_parquet(tmp_path / "old.parquet")] == [None, None]
    assert [name for name, _ in COLUMNS][-4:-1] == ["sensor_x", "sensor_y", "sensor_yaw"]


def test_summary_table_prints_brackets_of_names_and_errors_as_written():
    """rich would take ``[a]`` of a file name, or ``[leg_tracker]`` quoted in an error,
    for markup and drop it from the table."""
    from rich.console import Console

    from laserpeople.batch.task import TopicRow
    from laserpeople.cli.batch import render

    row = TopicRow(
        recording="/d/run[a].bag",
        name="run[a]",
        topic="/scan[b]",
        status="failed",
        error="bad value of [leg_tracker] people.gate_probability",
    )
    console = Console(record=True, width=400)
    console.print(render([row], "batch summary"))
    text = console.export_text()
    for written in ("run[a]", "/scan[b]", "of [leg_tracker] people"):
        assert written in text


def test_totals_count_one_worker_as_one(tmp_path, capsys):
    """The totals line says "on 1 worker" and "on 2 workers"."""
    from laserpeople.batch.run import BatchResult
    from laserpeople.batch.task import TopicRow
    from laserpeople.cli.batch import report

    row = TopicRow(recording="/d/a.bag", name="a", topic="/scan", status="done")
    for workers, said in ((1, "on 1 worker\n"), (2, "on 2 workers\n")):
        report(BatchResult(rows=[row], seconds=1.0, submitted=1, workers=workers), tmp_path)
        assert said in capsys.readouterr().err
