"""Crash safety of the CSV writers, outputs that never overwrite inputs, and requests that
cannot fit in memory refused up front."""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import textwrap
import time
import warnings
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import ConfigError, LaserPeopleError, RecordingError
from laserpeople.io import write_recording
from laserpeople.io.detections_csv import DetectionsCsvWriter, iter_detections_csv
from laserpeople.io.paths import check_outputs
from laserpeople.io.scan_lines import TornScanWarning
from laserpeople.io.tracks_csv import TracksCsvWriter, iter_tracks_csv
from laserpeople.scan import Scan
from laserpeople.tracks import Detections, Track, Tracks

ROWS = 150  # rows per scan: about 12 KiB, more than one 8 KiB buffer

WRITER = textwrap.dedent(
    """
    import sys
    import numpy as np
    from laserpeople.io.detections_csv import DetectionsCsvWriter
    from laserpeople.io.tracks_csv import TracksCsvWriter
    from laserpeople.tracks import Detections, Track, Tracks

    kind, path, rows = sys.argv[1], sys.argv[2], int(sys.argv[3])
    tracks = tuple(
        Track(j, "leg", np.array([j * 0.123456789, 1.0]), np.zeros(2), np.eye(2))
        for j in range(rows)
    )
    pos = np.arange(2.0 * rows).reshape(rows, 2) * 0.987654321
    out = TracksCsvWriter(path, "world") if kind == "tracks" else DetectionsCsvWriter(path)
    print("ready", flush=True)
    k = 0
    while True:
        if kind == "tracks":
            out.write(Tracks(0.1 * k, k, tracks, "world"))
        else:
            out.write(
                Detections(0.1 * k, k, pos, np.tile(np.eye(2), (rows, 1, 1)), np.ones(rows))
            )
        k += 1
    """
)


def _kill_while_writing(kind: str, path: Path, seed: int) -> None:
    env = dict(os.environ)
    src = str(Path(__file__).parents[1] / "src")
    env["PYTHONPATH"] = src + os.pathsep + env.get("PYTHONPATH", "")
    proc = subprocess.Popen(
        [sys.executable, "-c", WRITER, kind, str(path), str(ROWS)],
        stdout=subprocess.PIPE,
        env=env,
    )
    assert proc.stdout is not None
    assert proc.stdout.readline().strip() == b"ready"
    time.sleep(random.Random(seed).uniform(0.05, 0.6))
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    proc.stdout.close()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_tracks_csv_killed_mid_run_is_complete_to_the_last_scan(tmp_path: Path, seed: int) -> None:
    path = tmp_path / "tracks.csv"
    _kill_while_writing("tracks", path, seed)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", TornScanWarning)
        scans = list(iter_tracks_csv(path))
    assert scans, "the writer had time to write some scans"
    assert [t.scan_index for t in scans] == list(range(len(scans)))
    assert all(len(t) == ROWS for t in scans)
    _assert_torn_only_at_the_end(path, caught, len(scans))


def _assert_torn_only_at_the_end(
    path: Path, caught: list[warnings.WarningMessage], scans: int
) -> None:
    """A kill inside a scan's write leaves it torn (a hole of NULs or a cut row): said once."""
    torn = [w for w in caught if issubclass(w.category, TornScanWarning)]
    data = path.read_bytes()
    if data.endswith(b"\n") and b"\0" not in data:
        assert not torn
    else:
        assert len(torn) == 1
        assert f"scan {scans}" in str(torn[0].message) or "after the last complete" in str(
            torn[0].message
        )


@pytest.mark.parametrize("seed", [3, 4])
def test_detections_csv_killed_mid_run_is_complete_to_the_last_scan(
    tmp_path: Path, seed: int
) -> None:
    path = tmp_path / "detections.csv"
    _kill_while_writing("detections", path, seed)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", TornScanWarning)
        rows = list(iter_detections_csv(path))
    scans = np.bincount([int(r["scan"]) for r in rows])
    assert len(scans) and np.all(scans == ROWS)
    _assert_torn_only_at_the_end(path, caught, len(scans))


def _tracks(k: int, rows: int = 3) -> Tracks:
    return Tracks(
        0.1 * k,
        k,
        tuple(
            Track(j, "person", np.array([1.0, float(j)]), np.zeros(2), np.eye(2))
            for j in range(rows)
        ),
        "world",
    )


class _Killed(BaseException):
    """Stands for SIGKILL: nothing after it runs, not even ``except Exception``."""


@pytest.mark.parametrize("stop", [_Killed, KeyboardInterrupt])
@pytest.mark.parametrize("pages_written", [0, 1, 2, 3])
def test_a_scan_stopped_between_its_pages_is_dropped_not_short(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, pages_written: int, stop: type
) -> None:
    """A kill leaves the scan's start a hole the readers notice (a torn scan, said); a
    Ctrl-C (KeyboardInterrupt), which can clean up, cuts the scan back off: whole lines."""
    path = tmp_path / "t.csv"
    out = TracksCsvWriter(path)
    out.write(_tracks(0))
    out.write(_tracks(1))
    real = os.pwrite
    calls = []

    def stops(fd: int, data: bytes, offset: int) -> int:
        if len(calls) == pages_written:
            raise stop
        calls.append(offset)
        return real(fd, data, offset)

    monkeypatch.setattr("laserpeople.io.scan_lines.os.pwrite", stops)
    with pytest.raises(stop):
        out.write(_tracks(2, rows=200))  # about 4 pages
    assert calls == sorted(calls, reverse=True), "pages go from the scan's end backwards"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", TornScanWarning)
        scans = list(iter_tracks_csv(path))
    assert [(t.scan_index, len(t)) for t in scans] == [(0, 3), (1, 3)]
    torn = stop is _Killed and pages_written > 0
    assert len(caught) == (1 if torn else 0)
    assert ("\0" in path.read_text()) == torn  # the hole a kill leaves


def test_a_failed_write_leaves_the_complete_scans(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "t.csv"
    out = TracksCsvWriter(path)
    out.write(_tracks(0))
    real = os.pwrite
    calls = []

    def fills_up(fd: int, data: bytes, offset: int) -> int:
        if calls:
            raise OSError(28, "No space left on device")
        calls.append(offset)
        return real(fd, data, offset)

    monkeypatch.setattr("laserpeople.io.scan_lines.os.pwrite", fills_up)
    with pytest.raises(
        RecordingError, match=r"the 1 scan handled before \(1 with rows, up to scan 0\)"
    ):
        out.write(_tracks(1, rows=200))
    out.close()
    with warnings.catch_warnings():
        warnings.simplefilter("error", TornScanWarning)
        assert [t.scan_index for t in iter_tracks_csv(path)] == [0]


def test_reader_drops_a_torn_last_scan_and_says_so(tmp_path: Path) -> None:
    path = tmp_path / "t.csv"
    with TracksCsvWriter(path) as out:
        for k in range(4):
            out.write(_tracks(k))
    data = path.read_bytes()
    first = data.find(b"\n3,")
    cut = first + 20  # inside the first row of scan 3
    path.write_bytes(data[:cut])
    with pytest.warns(TornScanWarning, match="scan 3"):
        scans = list(iter_tracks_csv(path))
    assert [t.scan_index for t in scans] == [0, 1, 2]
    # cut inside the second row of scan 3: its complete first row is dropped too
    second = data.index(b"\n", first + 1) + 15
    path.write_bytes(data[:second])
    with pytest.warns(TornScanWarning):
        assert [t.scan_index for t in iter_tracks_csv(path)] == [0, 1, 2]


def test_detections_reader_drops_a_torn_last_scan(tmp_path: Path) -> None:
    path = tmp_path / "d.csv"
    with DetectionsCsvWriter(path) as out:
        for k in range(3):
            out.write(
                Detections(0.1 * k, k, np.ones((2, 2)), np.tile(np.eye(2), (2, 1, 1)), [1, 2])
            )
    data = path.read_bytes()
    path.write_bytes(data[:-5])
    with pytest.warns(TornScanWarning, match="scan 2"):
        rows = list(iter_detections_csv(path))
    assert sorted({r["scan"] for r in rows}) == [0, 1]


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_full_disk_is_a_clear_error() -> None:
    with pytest.raises(RecordingError, match="No space left on device"):
        TracksCsvWriter("/dev/full").write(_tracks(0))
    with pytest.raises(RecordingError, match="No space left"):
        DetectionsCsvWriter("/dev/full")


def test_unwritable_output_is_a_clear_error(tmp_path: Path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(RecordingError, match="cannot write the tracks CSV"):
        TracksCsvWriter(blocker / "sub" / "t.csv")


def test_track_ids_of_any_text_are_read(tmp_path: Path) -> None:
    path = tmp_path / "t.csv"
    path.write_text(
        "scan,stamp,track_id,kind,x,y,vx,vy,cov_xx,cov_xy,cov_yy,size,labels\n"
        "0,0.0,123456789012,person,1,2,0,0,1,0,1,1,\n"
        "0,0.0,p7,person,1,2,0,0,1,0,1,1,\n"
        "1,0.1,p7,person,1,2,0,0,1,0,1,1,\n"
        "1,0.1,99999999999999999999999,person,1,2,0,0,1,0,1,1,\n"
        "2,0.2,-3,person,1,2,0,0,1,0,1,1,\n"
    )
    scans = list(iter_tracks_csv(path))
    ids = [[t.track_id for t in s] for s in scans]
    assert ids[0][0] == 123456789012
    assert ids[0][1] == ids[1][0]  # the same text, the same id
    assert len({ids[0][1], ids[1][1], ids[2][0], ids[0][0]}) == 4


def test_evaluate_scores_text_track_ids(tmp_path: Path) -> None:
    from laserpeople.evaluation import evaluate
    from laserpeople.evaluation.params import EvaluationParams
    from laserpeople.io.truth_csv import read_truth_csv

    truth = tmp_path / "truth.csv"
    truth.write_text("scan,stamp,person_id,x,y\n0,0.0,7,1,1\n1,0.1,7,1.1,1\n")
    tracks = tmp_path / "t.csv"
    tracks.write_text(
        "scan,stamp,track_id,kind,x,y,vx,vy,cov_xx,cov_xy,cov_yy,size,labels\n"
        "0,0.0,a-1,person,1,1,0,0,1,0,1,1,\n"
        "1,0.1,a-1,person,1.1,1,0,0,1,0,1,1,\n"
    )
    run = evaluate(read_truth_csv(truth), iter_tracks_csv(tracks), EvaluationParams())
    report = run.result()
    assert report.summary()["mota"] == pytest.approx(1.0)


# -- outputs never overwrite inputs -------------------------------------------------------------


def test_check_outputs_refuses_an_input(tmp_path: Path) -> None:
    rec = tmp_path / "r.npz"
    rec.write_bytes(b"x")
    link = tmp_path / "link.npz"
    link.symlink_to(rec)
    hard = tmp_path / "hard.npz"
    os.link(rec, hard)
    folder = tmp_path / "bag"
    folder.mkdir()
    (folder / "metadata.yaml").write_text("rosbag2_bagfile_information: {}\n")
    for out in (rec, tmp_path / "." / "r.npz", link, hard, folder / "out.csv"):
        with pytest.raises(ConfigError, match=f"would write over the input .*{rec.name}|bag"):
            check_outputs({"-o": out}, [rec, folder])
    with pytest.raises(ConfigError, match="are the same file"):
        check_outputs({"-o": tmp_path / "a.csv", "--plot": tmp_path / "a.csv"}, [rec])
    check_outputs({"-o": tmp_path / "out.csv", "--plot": None}, [rec, None])


def test_track_refuses_to_overwrite_its_recording(tmp_path: Path) -> None:
    rec = tmp_path / "r.npz"
    write_recording(rec, [Scan(0.0, -1.0, 0.1, np.ones(21))])
    before = rec.read_bytes()
    result = CliRunner().invoke(app, ["track", str(rec), "-o", str(rec)])
    assert isinstance(result.exception, LaserPeopleError)
    assert "would write over the input" in str(result.exception)
    assert rec.read_bytes() == before


def test_on_error_option_skips_damaged_scans(tmp_path: Path) -> None:
    rec = tmp_path / "r.npz"
    scans = [Scan(0.1 * k, -1.0, 0.1, np.full(21, 2.0), index=k) for k in range(6)]
    write_recording(rec, scans)
    with np.load(rec) as z:
        arrays = {k: z[k] for k in z.files}
    arrays["scan_stamp"][3] = np.nan
    np.savez(rec, **arrays)  # type: ignore[arg-type]
    out = tmp_path / "d.csv"
    stop = CliRunner().invoke(app, ["detect", str(rec), "-o", str(out)])
    assert isinstance(stop.exception, RecordingError) and "scan 3" in str(stop.exception)
    skip = CliRunner().invoke(app, ["detect", str(rec), "-o", str(out), "--on-error", "skip"])
    assert skip.exit_code == 0, skip.output
    assert "skipped 1 damaged scan" in skip.output


# -- requests that cannot fit in memory -------------------------------------------------------


def test_simulate_refuses_what_cannot_fit_in_memory() -> None:
    from laserpeople.sim.scenarios import run_scenario

    t0 = time.monotonic()
    with pytest.raises(LaserPeopleError, match="longer than"):
        run_scenario("demo", seconds=1e9)
    with pytest.raises(LaserPeopleError, match="GiB of memory"):
        run_scenario("demo", seconds=9e4, rate=1000.0)
    assert time.monotonic() - t0 < 10.0


@pytest.mark.parametrize(
    "args",
    [["--extent=-inf,1,0,1"], ["--extent=0,1e300,0,1"], ["--fps", "nan"], ["--fps", "-1"]],
)
def test_view_refuses_non_finite_requests(tmp_path: Path, args: list[str]) -> None:
    rec = tmp_path / "r.npz"
    write_recording(rec, [Scan(0.0, -1.0, 0.1, np.ones(21))])
    result = CliRunner().invoke(app, ["view", str(rec), "-o", str(tmp_path / "v.gif"), *args])
    assert isinstance(result.exception, LaserPeopleError), result.output
