"""rerun ``.rrd`` export: written with the installed rerun SDK and read back chunk by chunk."""

from __future__ import annotations

import sys
from collections import defaultdict
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import LaserPeopleError
from laserpeople.viz import Scene, export_rerun, render
from laserpeople.viz.geometry import covariance_ellipses
from laserpeople.viz.rerun_export import RerunMissingError
from test_viz_support import make_scans, make_tracks, people_at, write_scene

runner = CliRunner()
ENTITIES = {
    "/world/scan",
    "/world/sensor",
    "/world/legs",
    "/world/people",
    "/world/groups",
    "/world/covariance",
    "/world/truth",
}


def read_rrd(path: Path) -> dict[str, list[dict[str, Any]]]:
    """Per entity path, one dict per logged row (timelines and components), in scan order."""
    pa = pytest.importorskip("pyarrow")
    chunk_api = pytest.importorskip("rerun.chunk")  # the reader API of rerun-sdk 0.41
    rows: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for chunk in chunk_api.RrdReader(path).stream():
        if chunk.is_static:
            continue
        batch = chunk.to_record_batch()
        for name in ("time", "log_time"):  # durations/timestamps as int64 nanoseconds
            if name in batch.schema.names:
                i = batch.schema.get_field_index(name)
                batch = batch.set_column(i, name, batch.column(i).cast(pa.int64()))
        rows[chunk.entity_path].extend(batch.to_pylist())
    for entity in rows.values():
        entity.sort(key=lambda r: r["scan"])
    return dict(rows)


def test_rrd_reads_back_with_every_entity_and_one_row_per_scan(tmp_path: Path) -> None:
    pytest.importorskip("rerun")
    n = 8
    rec, csv = write_scene(tmp_path, n=n)
    out = tmp_path / "scene.rrd"
    res = runner.invoke(app, ["view", str(rec), "--tracks", str(csv), "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert f"({n} frames" in " ".join(res.output.split())  # rich wraps long paths
    rows = read_rrd(out)
    assert set(rows) == ENTITIES
    for entity, logged in rows.items():
        assert [r["scan"] for r in logged] == list(range(n)), entity
        assert [r["time"] for r in logged] == [round((100.0 + 0.1 * k) * 1e9) for k in range(n)]

    scans, tracks = make_scans(n), make_tracks(n)
    for k in range(n):
        cloud = np.array(rows["/world/scan"][k]["Points2D:positions"])
        assert np.allclose(cloud, scans[k].valid_points("world")[0], atol=1e-5)
        sensor = rows["/world/sensor"][k]["Points2D:positions"]
        assert np.allclose(sensor, [[0.5, 1.0]])
        people = rows["/world/people"][k]
        assert people["Points2D:labels"] == ["P3", "P8"]
        assert np.allclose(people["Points2D:positions"], people_at(k), atol=1e-5)
        truth = rows["/world/truth"][k]
        assert truth["Points2D:labels"] == ["truth 0", "truth 1"]
        assert np.allclose(truth["Points2D:positions"], people_at(k), atol=1e-5)
        assert rows["/world/legs"][k]["Points2D:positions"] == []  # the CSV has no legs
        groups = rows["/world/groups"][k]
        if k < 2:
            assert groups["LineStrips2D:strips"] == []
        else:  # a tracks CSV has no contours: the group is outlined by its 95 % ellipse
            assert groups["LineStrips2D:labels"] == ["G1 x2"]
            (strip,) = groups["LineStrips2D:strips"]
            group = tracks[k].of_kind("group")[0]
            ellipse = covariance_ellipses(group.position[None], group.covariance[None])[0]
            assert np.allclose(strip, ellipse, atol=1e-5)
        # one ellipse per track: 2 people, plus the group from scan 2 on
        assert len(rows["/world/covariance"][k]["LineStrips2D:strips"]) == (2 if k < 2 else 3)


def test_rrd_of_a_window_logs_only_the_drawn_scans(tmp_path: Path) -> None:
    pytest.importorskip("rerun")
    rec, csv = write_scene(tmp_path, n=9)
    out = tmp_path / "sub" / "window.rrd"
    assert export_rerun(Scene(rec, csv, start=2, stop=8, every=2), out) == 3
    rows = read_rrd(out)
    assert set(rows) == ENTITIES
    for entity, logged in rows.items():
        assert [r["scan"] for r in logged] == [2, 4, 6], entity


def test_rrd_of_tracker_output_has_group_contours_and_empty_truth(tmp_path: Path) -> None:
    pytest.importorskip("rerun")
    out = tmp_path / "no-truth.rrd"
    tracks = make_tracks(4)
    assert render(Scene(make_scans(4), tracks), out).frames == 4
    rows = read_rrd(out)
    assert [r["Points2D:positions"] for r in rows["/world/truth"]] == [[]] * 4
    assert [len(r["Points2D:positions"]) for r in rows["/world/people"]] == [2] * 4
    groups = rows["/world/groups"]
    assert [len(r["LineStrips2D:strips"]) for r in groups] == [0, 0, 1, 1]
    for k in (2, 3):  # a closed contour: the three corners and the first again
        contour = tracks[k].of_kind("group")[0].contour
        assert np.allclose(groups[k]["LineStrips2D:strips"][0], np.vstack([contour, contour[:1]]))


def test_rrd_without_rerun_names_the_extra(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "rerun", None)  # import rerun now raises ImportError
    rec, csv = write_scene(tmp_path, n=4)
    out = tmp_path / "a.rrd"
    with pytest.raises(RerunMissingError, match=r"laserpeople\[rerun\]"):
        render(Scene(rec, csv), out)
    assert not out.exists()
    assert issubclass(RerunMissingError, LaserPeopleError)


def test_rrd_with_a_too_old_rerun_names_the_version(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    class OldStream:  # rerun < 0.23: set_time_sequence/set_time_seconds, no set_time
        def set_time_sequence(self, timeline: str, sequence: int) -> None: ...

    old = SimpleNamespace(__version__="0.18.2", RecordingStream=OldStream)
    monkeypatch.setitem(sys.modules, "rerun", old)
    rec, csv = write_scene(tmp_path, n=2)
    out = tmp_path / "old.rrd"
    with pytest.raises(RerunMissingError, match=r"0\.23 or newer, this is 0\.18\.2"):
        render(Scene(rec, csv), out)
    assert not out.exists()
