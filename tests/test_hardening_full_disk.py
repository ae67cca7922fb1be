"""A CSV the disk refuses mid-run (`detect -o`, `track -o`): the error names the scan it
failed at and counts the scans the file holds, those without rows included (a scan with no
leg or no track is in the file all the same), not only the scans that had rows."""

from __future__ import annotations

import os
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import RecordingError
from laserpeople.io.detections_csv import DetectionsCsvWriter, iter_detections_csv
from laserpeople.io.scan_lines import TornScanWarning
from laserpeople.io.tracks_csv import TracksCsvWriter, iter_tracks_csv
from laserpeople.tracks import Detections, Track, Tracks


def _full_after(monkeypatch: pytest.MonkeyPatch, writes: int) -> None:
    """The disk takes ``writes`` more pages, then is full."""
    real = os.pwrite
    left = [writes]

    def pwrite(fd: int, data: bytes, offset: int) -> int:
        if left[0] <= 0:
            raise OSError(28, "No space left on device")
        left[0] -= 1
        return real(fd, data, offset)

    monkeypatch.setattr("laserpeople.io.scan_lines.os.pwrite", pwrite)


def _legs(k: int, n: int) -> Detections:
    pos = np.arange(2.0 * n).reshape(n, 2)
    return Detections(0.1 * k, k, pos, np.tile(np.eye(2), (n, 1, 1)), np.ones(n))


def test_detections_count_the_scans_without_legs(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "legs.csv"
    out = DetectionsCsvWriter(path, topic="/scan")
    for k, n in enumerate([2, 0, 0, 1, 0]):
        out.write(_legs(k, n))
    _full_after(monkeypatch, 0)
    with pytest.raises(RecordingError) as err:
        out.write(_legs(5, 3))
    out.close()
    assert (
        "cannot write the detections CSV at scan 5 of /scan: No space left on device; it "
        "holds the rows of the 5 scans handled before (2 with rows, up to scan 4 of "
        "/scan), whole: scan 5 of /scan and the scans after it are missing"
    ) in str(err.value)
    with warnings.catch_warnings():
        warnings.simplefilter("error", TornScanWarning)
        assert [int(r["scan"]) for r in iter_detections_csv(path)] == [0, 0, 3]


def test_tracks_count_the_scans_without_tracks(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "t.csv"
    out = TracksCsvWriter(path)
    track = Track(7, "person", np.array([1.0, 2.0]), np.zeros(2), np.eye(2))
    for k in range(3):
        out.write(Tracks(0.1 * k, k, (track,) if k == 0 else (), "world"))
    _full_after(monkeypatch, 0)
    with pytest.raises(
        RecordingError, match=r"at scan 3: .* the 3 scans handled before \(1 with rows"
    ):
        out.write(Tracks(0.3, 3, (track,), "world"))
    out.close()
    assert [t.scan_index for t in iter_tracks_csv(path)] == [0]


def test_a_disk_full_before_any_scan_or_the_header_is_said_so(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    out = DetectionsCsvWriter(tmp_path / "a.csv")
    _full_after(monkeypatch, 0)
    with pytest.raises(
        RecordingError, match=r"at scan 0: No space left on device; it holds the header alone"
    ):
        out.write(_legs(0, 1))
    out.close()
    with pytest.raises(RecordingError, match=r"No space left on device \(not even its header\)"):
        TracksCsvWriter(tmp_path / "b.csv")
    assert (tmp_path / "b.csv").read_bytes() == b""


def test_detect_on_a_full_disk_says_what_the_csv_holds(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import dataclasses

    from laserpeople.io import write_recording
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "walk.npz"
    scans = run_scenario("figure-eight", seconds=3.0, seed=3).scans
    # every third scan without a return (a driver writing NaN): no leg, no row
    blank = [
        dataclasses.replace(s, ranges=np.full_like(s.ranges, np.nan)) if k % 3 == 1 else s
        for k, s in enumerate(scans)
    ]
    write_recording(rec, blank)
    out = tmp_path / "legs.csv"
    _full_after(monkeypatch, 12)  # the header and some scans' pages
    run = CliRunner().invoke(app, ["detect", str(rec), "-o", str(out)])
    assert isinstance(run.exception, RecordingError)
    text = str(run.exception)
    said = re.search(
        r"at scan (\d+) of (\S+): No space left on device; it holds the rows of the (\d+) scans "
        r"handled before \((\d+) with rows, up to scan (\d+) of \2\)",
        text,
    )
    assert said, text
    failed, handled, with_rows, last = (int(said.group(i)) for i in (1, 3, 4, 5))
    scans = [int(r["scan"]) for r in iter_detections_csv(out)]
    assert len(set(scans)) == with_rows and max(scans) <= last == failed - 1
    assert handled == failed  # one laser: scans 0 .. failed - 1
    assert with_rows <= handled - handled // 3  # the blank scans are counted too
