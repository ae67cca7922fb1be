"""Commands that changed what they worked on without a word: what they used is said."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app


@pytest.fixture(scope="module")
def poses_stop(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, int, int]:
    """A simulated walk whose last 20 scans have no sensor pose: (path, scans, posed)."""
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path_factory.mktemp("bench") / "walk.npz"
    run_scenario("figure-eight", seconds=2.0, seed=1).write(rec)
    with np.load(rec) as z:
        arrays = {k: z[k] for k in z.files}
    n = len(arrays["scan_stamp"])
    arrays["scan_pose"][n - 20 :] = np.nan
    np.savez(rec, **arrays)  # type: ignore[arg-type]
    return rec, n, n - 20


def test_bench_says_the_frame_and_the_frames_it_timed(poses_stop: tuple[Path, int, int]) -> None:
    rec, n, posed = poses_stop
    run = CliRunner().invoke(app, ["bench", str(rec), "--tracker", "nn", "--repeat", "1"])
    assert run.exit_code == 0, run.output
    assert f"trackers timed on {posed} frames, working in the world frame" in run.output
    assert "20 frames skipped and 0 scans dropped for lack of a sensor pose" in run.output
    as_json = CliRunner().invoke(
        app, ["--quiet", "bench", str(rec), "--tracker", "nn", "--repeat", "1", "--json"]
    )
    doc = json.loads(as_json.stdout)
    assert (doc["scans"], doc["tracking_frame"], doc["tracked_frames"]) == (n, "world", posed)


@pytest.mark.parametrize(
    ("window", "said"),
    [
        (["--start", "5000"], "(scans from 5000): topic laser holds scans 0-{last}"),
        (["--start", "500", "--stop", "600"], "(scans 500-599): topic laser holds scans 0-{last}"),
    ],
)
@pytest.mark.parametrize("out", ["v.png", "v.gif"])
def test_view_of_a_window_beyond_the_recording_names_the_scans_it_holds(
    poses_stop: tuple[Path, int, int], tmp_path: Path, window: list[str], said: str, out: str
) -> None:
    rec, n, _ = poses_stop
    run = CliRunner().invoke(app, ["view", str(rec), "-o", str(tmp_path / out), *window])
    assert run.exit_code == 1
    assert f"no scans in the chosen window {said.format(last=n - 1)}" in str(run.exception)
    assert not (tmp_path / out).exists()


@pytest.mark.parametrize("writer", ["tracks", "detections"])
def test_a_csv_another_run_is_writing_is_refused_and_left_as_it_is(
    tmp_path: Path, writer: str
) -> None:
    """Two runs with one -o at once mixed their rows into a file neither wrote; the second
    is refused before it changes a byte, and the first writes on."""
    from laserpeople.errors import RecordingError
    from laserpeople.io.detections_csv import DetectionsCsvWriter
    from laserpeople.io.tracks_csv import TracksCsvWriter

    make = TracksCsvWriter if writer == "tracks" else DetectionsCsvWriter
    out = tmp_path / "run.csv"
    with make(out) as first:
        before = out.read_bytes()
        with pytest.raises(RecordingError) as info:
            make(out)
        assert str(info.value).startswith(f"{out}: another run is writing this {writer} CSV now")
        assert out.read_bytes() == before
        assert first.rows == 0
    with make(out):  # once the first has closed it, the file is free again
        pass
    assert out.read_bytes() == before


def test_an_older_file_is_emptied_when_taken(tmp_path: Path) -> None:
    from laserpeople.io.tracks_csv import TracksCsvWriter

    out = tmp_path / "run.csv"
    out.write_text("x" * 10_000)
    with TracksCsvWriter(out):
        pass
    assert (
        out.read_text() == "scan,stamp,track_id,kind,x,y,vx,vy,cov_xx,cov_xy,cov_yy,size,labels\n"
    )


def test_staging_names_differ_per_call_and_keep_the_extension(tmp_path: Path) -> None:
    """Two runs writing one output at once each write their own hidden file (one name would
    let their bytes mix before the rename); the extension stays for writers that need it."""
    import os

    from laserpeople.io.paths import staging_name

    out = tmp_path / "walk.npz"
    a, b = staging_name(out), staging_name(out)
    assert a != b and a.parent == b.parent == tmp_path
    assert a.name.startswith(".walk.") and a.suffix == ".npz"
    assert f".{os.getpid()}-" in a.name


def test_simulate_leaves_no_staging_file(tmp_path: Path) -> None:
    out = tmp_path / "walk.npz"
    run = CliRunner().invoke(app, ["simulate", "figure-eight", "-s", "1", "-o", str(out)])
    assert run.exit_code == 0, run.output
    assert [p.name for p in tmp_path.iterdir()] == ["walk.npz"]


@pytest.mark.parametrize(
    ("keyword", "given", "said"),
    [
        ("topics", "/scan", "topics takes a list, got the single str '/scan'"),
        ("outputs", "tracks.csv", "outputs takes a list, got the single str 'tracks.csv'"),
        ("outputs", Path("t.csv"), "outputs takes a list, got the single PosixPath 't.csv'"),
        ("mounts", "mir100", "mounts takes a list, got the single str 'mir100'"),
    ],
)
def test_build_refuses_one_name_where_a_list_is_asked(
    tmp_path: Path, keyword: str, given: object, said: str
) -> None:
    """``topics="/scan"`` was read letter by letter: "no topic '/'"; refused before the
    recording is opened (it need not exist)."""
    from laserpeople.errors import ConfigError
    from laserpeople.pipeline import build

    with pytest.raises(ConfigError) as info:
        build(tmp_path / "missing.bag", **{keyword: given})  # type: ignore[arg-type]
    assert str(info.value).startswith(said)
    assert f"write {keyword}=[" in str(info.value)


def test_build_takes_lists_as_before(poses_stop: tuple[Path, int, int], tmp_path: Path) -> None:
    from laserpeople.pipeline import build

    rec = poses_stop[0]
    out = tmp_path / "t.csv"
    stats = build(rec, topics=("laser",), outputs=[out], tracker="nn").run()
    assert stats.frames > 0 and out.is_file()


def test_run_batch_refuses_one_recording_given_as_a_string(tmp_path: Path) -> None:
    pytest.importorskip("dask.distributed")
    from laserpeople.batch import TrackOptions, run_batch
    from laserpeople.errors import ConfigError

    with pytest.raises(ConfigError, match=r"recordings takes a list, got the single str 'a\.npz'"):
        run_batch("a.npz", tmp_path / "out", TrackOptions())
    assert not (tmp_path / "out").exists()


def test_a_per_frame_table_on_a_full_disk_leaves_the_older_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """`evaluate --per-frame` on a full disk wrote over the older table with a torn one."""
    import errno

    from laserpeople.errors import EvaluationError
    from laserpeople.evaluation.detail import FrameTable

    real = Path.write_text

    def full(self: Path, text: str, *args: object, **kwargs: object) -> int:
        real(self, text[:20], encoding="utf-8")  # what fitted before the disk was full
        raise OSError(errno.ENOSPC, "No space left on device")

    out = tmp_path / "per-frame.csv"
    out.write_text("the older table\n")
    table = FrameTable(("scan", "stamp", "misses"), ((0, 0.0, 1), (1, 0.1, 0)))
    monkeypatch.setattr(Path, "write_text", full)
    with pytest.raises(EvaluationError) as info:
        table.to_csv(out)
    monkeypatch.undo()
    assert str(info.value) == (
        f"{out}: cannot write the per-frame table: No space left on device "
        "(give a writable file path)"
    )
    assert out.read_text() == "the older table\n"
    assert [p.name for p in tmp_path.iterdir()] == ["per-frame.csv"]
    table.to_csv(out)
    assert out.read_text() == "scan,stamp,misses\n0,0.000000,1\n1,0.100000,0\n"


def test_align_of_one_laser_names_the_file_and_the_laser(
    poses_stop: tuple[Path, int, int], tmp_path: Path
) -> None:
    rec = poses_stop[0]
    run = CliRunner().invoke(app, ["align", str(rec), "-o", str(tmp_path / "m.toml")])
    assert run.exit_code == 1
    assert str(run.exception).startswith(f"{rec}: need two lasers to align, found 1 (laser)")
    assert not (tmp_path / "m.toml").exists()


@pytest.mark.parametrize(
    ("offset_periods", "shift"),
    [
        (-100.0, 100),  # a label numbered i has the stamp of scan i - 100
        (-100.015, 100),  # within 0.02 of a period
        (-100.025, 0),  # beyond it: an unrelated clock
        (3.0, -3),
        (0.4, 0),  # under a period: another clock (the receive time)
        (-374.0, 374),  # fewer than the 375 scans the tracks span
        (-375.0, 0),  # not fewer: far beyond the recording
        (-37500.0, 0),
    ],
)
def test_a_stamp_offset_of_whole_scan_periods_is_a_shift_of_the_numbering(
    offset_periods: float, shift: int
) -> None:
    from laserpeople.evaluation.pairing import PairingCounts

    period = 10.0 / 375  # tracks of scans 0-375 over 10 s
    counts = PairingCounts(tracks_scans=(0, 375), tracks_stamps=(100.0, 110.0))
    assert counts.scan_shift(offset_periods * period) == shift


def test_evaluate_says_a_truth_numbered_from_another_scan(tmp_path: Path) -> None:
    """Labels numbered 100 scans late scored tracks of other scans, with only a note on
    another clock; now a warning naming the shift."""
    import csv

    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "walk.npz"
    run_scenario("figure-eight", seconds=6.0, seed=1).write(rec)
    tracks = tmp_path / "t.csv"
    assert CliRunner().invoke(app, ["track", str(rec), "-o", str(tracks)]).exit_code == 0
    with np.load(rec) as z:
        index, stamp, offset = z["truth_scan_index"], z["truth_stamp"], z["truth_offset"]
        ids, xy = z["truth_person_id"], z["truth_xy"]
    truth = tmp_path / "truth.csv"
    with truth.open("w", newline="") as fh:
        out = csv.writer(fh)
        out.writerow(["scan", "stamp", "person_id", "x", "y"])
        for k in range(len(index)):
            for j in range(offset[k], offset[k + 1]):
                out.writerow([index[k] + 100, stamp[k], ids[j], xy[j, 0], xy[j, 1]])
    run = CliRunner().invoke(app, ["evaluate", str(tracks), "--truth", str(truth)])
    assert "100 scan periods, so the truth's scan numbers may be +100 off" in run.output
    assert "warning: truth stamps are -" in run.output


@pytest.fixture(scope="module")
def tracked(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path, Path]:
    """A simulated walk and its tracks as a CSV and as the bag of ``track --bag``."""
    from laserpeople.sim.scenarios import run_scenario

    folder = tmp_path_factory.mktemp("tracked")
    rec = folder / "walk.npz"
    run_scenario("figure-eight", seconds=2.0, seed=2).write(rec)
    csv, bag = folder / "t.csv", folder / "t.mcap"
    run = CliRunner().invoke(app, ["track", str(rec), "-o", str(csv), "--bag", str(bag)])
    assert run.exit_code == 0, run.output
    return rec, csv, bag


def _parquet_of(csv: Path, out: Path) -> Path:
    """The tracks of ``csv`` as `batch --format parquet` writes them."""
    pytest.importorskip("pyarrow")
    from types import SimpleNamespace

    from laserpeople.batch.parquet import TracksParquetSink
    from laserpeople.io.tracks_csv import iter_tracks_csv

    sink = TracksParquetSink(out)
    for t in iter_tracks_csv(csv):
        sink.write(SimpleNamespace(topic="laser"), t)  # type: ignore[arg-type]
    sink.close()
    return out


def test_view_and_evaluate_read_every_tracks_file_the_package_writes(
    tracked: tuple[Path, Path, Path], tmp_path: Path
) -> None:
    """`view --tracks` read only CSVs ("not a text CSV: not UTF-8" for the bag of `track
    --bag` and the Parquet of `batch`), `evaluate` of one Parquet file likewise."""
    rec, csv, bag = tracked
    parquet = _parquet_of(csv, tmp_path / "t.parquet")
    for tracks in (csv, bag, parquet):
        out = tmp_path / f"{tracks.suffix[1:]}.png"
        run = CliRunner().invoke(app, ["view", str(rec), "--tracks", str(tracks), "-o", str(out)])
        assert run.exit_code == 0, (tracks, run.output)
        assert "may not belong" not in run.output and out.is_file()
    scores = {}
    for tracks in (csv, bag, parquet):
        run = CliRunner().invoke(
            app, ["--quiet", "evaluate", str(tracks), "--truth", str(rec), "--json"]
        )
        assert run.exit_code == 0, (tracks, run.output)
        scores[tracks.suffix] = json.loads(run.stdout)["mota"]
    assert scores[".csv"] == pytest.approx(scores[".parquet"], abs=1e-12)
    assert scores[".csv"] == pytest.approx(scores[".mcap"], abs=1e-3)  # (bag: float32 positions)


def test_a_truth_given_with_a_batch_folder_says_that_its_truth_is_found_by_name(
    tracked: tuple[Path, Path, Path], tmp_path: Path
) -> None:
    rec, csv, _ = tracked
    out = tmp_path / "out"
    out.mkdir()
    (out / "summary.csv").write_text(
        f"recording,name,topic,status,output\n{rec},walk,laser,done,{csv}\n"
    )
    run = CliRunner().invoke(app, ["evaluate", str(out), "--truth", str(rec)])
    assert run.exit_code == 1
    assert str(run.exception).startswith(
        "0 TRACKS files but 1 --truth (1 batch folder: its recordings' truth is found by name"
    )
