"""`live --record` whose file fails mid-run (a full disk, the file removed, a folder that
cannot take it): what was recorded stays a readable recording, ended after its last whole
frame, and the error says how many frames and scans it holds."""

from __future__ import annotations

import dataclasses
import errno
import io
import os
import re
from pathlib import Path

import pytest

from laserpeople.errors import RecordingError
from laserpeople.io import open_recording
from laserpeople.io.mcap_record import mcap_ending
from laserpeople.io.tracks_bag import iter_tracks_bag
from laserpeople.live.messages import TrackEncoder, ros2_typestore
from laserpeople.live.runner import tracker_pipelines
from laserpeople.live.sinks import RecordSink
from laserpeople.pipeline.sources import laser_frames
from laserpeople.scan import Pose2D, Scan
from laserpeople.tracks import Tracks

FRAMES = 30


def _scans() -> list[Scan]:
    """The first ``FRAMES`` scans of the simulated ``demo`` scene (10 Hz), posed."""
    from laserpeople.sim import run_scenario

    result = run_scenario("demo", seconds=FRAMES / 10 + 1, seed=0, rate=10.0)
    first = result.scans[0].sensor
    scans = [s for s in result.scans if s.sensor == first][:FRAMES]
    return [dataclasses.replace(s, sensor="/scan", pose=Pose2D(1.0, 2.0, 0.3)) for s in scans]


class FullDisk(io.RawIOBase):
    """A file that takes bytes up to ``limit`` and then refuses them as a full disk does:
    the part that fits is written, the rest raises ``ENOSPC``."""

    def __init__(self, fd: int, limit: int) -> None:
        self.fd = fd
        self.limit = limit

    def writable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return True

    def fileno(self) -> int:
        return self.fd

    def seek(self, offset: int, whence: int = 0) -> int:
        return os.lseek(self.fd, offset, whence)

    def tell(self) -> int:
        return os.lseek(self.fd, 0, os.SEEK_CUR)

    def write(self, b: bytes | bytearray | memoryview) -> int:  # type: ignore[override]
        room = self.limit - self.tell()
        if room <= 0:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return os.write(self.fd, bytes(b)[:room])

    def close(self) -> None:
        if not self.closed:
            os.close(self.fd)
        super().close()


def _fill_disk_at(sink: RecordSink, limit: int) -> None:
    """Make the recording's file refuse bytes beyond ``limit``."""
    storage = sink._recorder._writer.storage
    storage.bio.flush()
    raw = FullDisk(os.dup(storage.bio.fileno()), limit)
    storage.bio.close()
    storage.bio = io.BufferedWriter(raw)


def _record(out: Path, sink_hook: object = None) -> tuple[RecordSink, RecordingError | None]:
    encoder = TrackEncoder(ros2_typestore())
    sink = RecordSink(out, encoder)
    if callable(sink_hook):
        sink_hook(sink)
    frames = (f.with_fields(frame="world") for f in laser_frames(_scans()))
    try:
        tracker_pipelines("leg-mht")(frames, [sink]).run()
    except RecordingError as exc:
        return sink, exc
    return sink, None


def _whole(tmp_path: Path) -> tuple[int, list[tuple[int, int]]]:
    """Size of a whole recording of the scans, and its tracks (scan index, track count per
    frame with tracks); it is left in a folder of its own."""
    folder = tmp_path / "whole"
    sink, err = _record(folder / "whole.mcap")
    assert err is None and sink.frames == FRAMES
    return (folder / "whole.mcap").stat().st_size, _tracks(folder / "whole.mcap")


def _tracks(path: Path) -> list[tuple[int, int]]:
    return [(t.scan_index, len(t.tracks)) for t in iter_tracks_bag(path)]


def _hidden(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith("."))


def test_a_full_disk_mid_run_leaves_the_whole_frames_readable(tmp_path: Path) -> None:
    whole, tracks = _whole(tmp_path)
    out = tmp_path / "run.mcap"
    sink, err = _record(out, lambda s: _fill_disk_at(s, whole // 2))
    assert err is not None
    text = str(err)
    assert "No space left on device" in text and "run.mcap" in text
    said = re.search(r"holds the (\d+) whole frames before \((\d+) scans", text)
    assert said, text
    frames, scans = int(said.group(1)), int(said.group(2))
    assert 5 < frames < FRAMES - 5 and scans == frames == sink.frames
    assert f"stopped at frame {frames + 1}:" in text
    # the file is in place, ends with the MCAP end records, and reads: every frame it says
    data = out.read_bytes()
    assert data.endswith(mcap_ending()) and len(data) < whole // 2 + 100
    assert _tracks(out) == [t for t in tracks if t[0] < frames]
    with open_recording(out) as rec:
        stamps = [s.stamp for s in rec.scans()]
    assert len(stamps) == scans
    assert f"up to the scan stamped {stamps[-1]:.3f} s" in text
    assert _hidden(tmp_path) == []  # nothing left beside it


def test_a_disk_full_before_the_first_frame_leaves_an_empty_recording(tmp_path: Path) -> None:
    out = tmp_path / "run.mcap"
    _, err = _record(out, lambda s: _fill_disk_at(s, s._recorder.kept_bytes + 10))
    assert err is not None and "holds the 0 whole frames before (0 scans)" in str(err)
    assert "stamped" not in str(err)
    with open_recording(out) as rec:
        assert rec.topics() == []


def test_a_disk_full_while_ending_the_file_keeps_every_frame(tmp_path: Path) -> None:
    whole, tracks = _whole(tmp_path)
    out = tmp_path / "run.mcap"
    # room for the frames, not for the summary (the chunk indexes and statistics)
    _, err = _record(out, lambda s: _fill_disk_at(s, whole - 200))
    assert err is not None and "stopped at its end" in str(err)
    assert f"holds the {FRAMES} whole frames before ({FRAMES} scans" in str(err)
    assert _tracks(out) == tracks
    assert _hidden(tmp_path) == []


def test_a_recording_removed_while_written_is_written_again_whole(tmp_path: Path) -> None:
    import shutil

    out = tmp_path / "run.mcap"

    def remove(sink: RecordSink) -> None:
        (hidden,) = [p for p in tmp_path.iterdir() if p.name.startswith(".run.mcap.")]
        shutil.rmtree(hidden)

    sink, err = _record(out, remove)
    assert err is None and sink.frames == FRAMES
    assert _tracks(out) == _whole(tmp_path)[1]
    assert _hidden(tmp_path) == []


def test_a_recording_that_cannot_be_moved_into_place_names_where_it_is(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    out = tmp_path / "run.mcap"
    real = os.replace

    def refuse(src: object, dst: object) -> None:
        if Path(str(dst)) == out:
            raise PermissionError(errno.EACCES, os.strerror(errno.EACCES))
        real(src, dst)  # type: ignore[arg-type]

    monkeypatch.setattr(os, "replace", refuse)
    _, err = _record(out)
    assert err is not None and "Permission denied" in str(err)
    kept = Path(re.search(r"it is (\S+\.mcap)", str(err)).group(1))  # type: ignore[union-attr]
    assert kept.is_file() and not out.exists()
    monkeypatch.setattr(os, "replace", real)
    assert _tracks(kept) == _whole(tmp_path)[1]


@pytest.mark.slow
def test_live_on_a_full_disk_keeps_the_recording_and_says_what_it_holds(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The whole command: `live --record` whose disk fills up mid-run prints its summary,
    ends with an error saying how many frames and scans the recording holds, and the
    recording reads with exactly those."""
    pytest.importorskip("zenoh")
    from typer.testing import CliRunner

    from laserpeople.cli import app
    from laserpeople.live import sinks
    from laserpeople.sim.scenarios import run_scenario
    from live_harness import free_port, play_when_subscribed

    bag = tmp_path / "walk.bag"
    run_scenario("figure-eight", seconds=2.0, seed=3).write(bag)
    with open_recording(bag) as rec:
        topic, n = rec.topics()[0].name, rec.topics()[0].count
    made = sinks.RecordSink.__init__

    def on_a_small_disk(self: RecordSink, *args: object, **kwargs: object) -> None:
        made(self, *args, **kwargs)  # type: ignore[arg-type]
        _fill_disk_at(self, 60_000)

    monkeypatch.setattr(sinks.RecordSink, "__init__", on_a_small_disk)
    out = tmp_path / "live.mcap"
    port = free_port()
    player = play_when_subscribed(bag, topic, port)
    args = ["live", "--topic", topic, "--listen", f"tcp/127.0.0.1:{port}", "--frame", "sensor"]
    args += ["--queue", "100000", "--max-scans", str(n), "--duration", "120"]
    args += ["--record", str(out)]
    result = CliRunner().invoke(app, args)
    player.join(30)
    assert isinstance(result.exception, RecordingError), result.output
    said = re.search(r"holds the (\d+) whole frames before \((\d+) scans", str(result.exception))
    assert said, str(result.exception)
    frames, scans = int(said.group(1)), int(said.group(2))
    assert 0 < frames < n and scans == frames
    # the summary came first; the frame whose recording failed had been published
    assert f"{frames} frames tracked, {frames + 1} published" in result.output
    with open_recording(out) as rec:
        assert rec.topics()[0].count == scans


def test_a_recording_onto_a_folder_is_refused_before_the_run(tmp_path: Path) -> None:
    (tmp_path / "run.mcap").mkdir()
    with pytest.raises(RecordingError, match="is a folder, not a file"):
        RecordSink(tmp_path / "run.mcap", TrackEncoder(ros2_typestore()))
    assert _hidden(tmp_path) == []


def test_a_recording_killed_mid_run_reads_up_to_the_cut_with_on_error_skip(
    tmp_path: Path,
) -> None:
    """`kill -9` leaves the hidden file with whole frames and no MCAP end records (and a cut
    copy may stop inside a frame): `--on-error skip` reads the frames before the cut and
    says what it left out; `stop` says what is wrong and what to do."""
    from typer.testing import CliRunner

    from laserpeople.cli import app

    out = tmp_path / "run.mcap"
    sink = RecordSink(out, TrackEncoder(ros2_typestore()))
    ends = []  # the byte after each whole frame
    for frame in list(laser_frames(_scans()))[:12]:
        sink.write(frame, Tracks(frame.stamp, frame.scans[0].index, (), "world"))
        ends.append(sink._recorder.kept_bytes)
    staged = sink._recorder._staged
    data = staged.read_bytes()  # what a kill -9 leaves: 12 whole frames, no end records
    sink.close()
    killed = tmp_path / "killed.mcap"
    cut = tmp_path / "cut.mcap"
    killed.write_bytes(data)
    cut.write_bytes(data[: len(data) - 1000])  # inside the last frame's chunk (about 5 kB)
    said = {
        killed: f"read its {len(data):,} bytes, whole records up to the cut",
        cut: f"read its whole records, {ends[10]:,} of its {len(data) - 1000:,} bytes; the "
        f"{len(data) - 1000 - ends[10]:,} bytes after the cut are left out",
    }
    for path, scans in ((killed, 12), (cut, 11)):
        with pytest.raises(RecordingError, match="ends without its end records") as err:
            open_recording(path)
        assert "--on-error skip reads its whole records" in str(err.value)
        with open_recording(path, on_error="skip") as rec:
            assert len(list(rec.scans())) == scans
            assert said[path] in rec.damaged.summary()
        assert path.read_bytes() == data[: path.stat().st_size]  # the input is not changed
    run = CliRunner().invoke(
        app, ["track", str(cut), "-o", str(tmp_path / "t.csv"), "--on-error", "skip"]
    )
    assert run.exit_code == 0, run.output
    text = " ".join(run.output.split())
    assert f"{cut}: the MCAP ends without its end records" in text and "11 scans tracked" in text
    (tmp_path / "empty.mcap").write_bytes(data[:60])
    with pytest.raises(RecordingError, match="no record before the cut is whole"):
        open_recording(tmp_path / "empty.mcap", on_error="skip")


def test_whole_records_end_at_the_cut_or_before_it(tmp_path: Path) -> None:
    import struct

    from laserpeople.io.mcap_record import MCAP_MAGIC
    from laserpeople.io.mcap_tail import missing_end, whole_records

    def record(op: int, body: bytes) -> bytes:
        return bytes([op]) + struct.pack("<Q", len(body)) + body

    header = MCAP_MAGIC + record(0x01, b"\x04\x00\x00\x00ros2\x00\x00\x00\x00")
    path = tmp_path / "a.mcap"
    two = header + record(0x03, b"x" * 20) + record(0x05, b"y" * 7)
    path.write_bytes(two)  # the last record ends at the last byte: whole
    assert missing_end(path) and whole_records(path) == (len(two), 2)
    path.write_bytes(two[:-1])
    assert whole_records(path) == (len(two) - 9 - 7, 1)
    path.write_bytes(two + b"\x0f" + struct.pack("<QI", 4, 0) + b"junk")  # DataEnd: stop
    assert whole_records(path) == (len(two), 2)
    path.write_bytes(header + b"\x00" * 30)  # a hole of NUL bytes is no record
    assert whole_records(path) == (len(header), 0)
    path.write_bytes(two + MCAP_MAGIC)
    assert not missing_end(path)
    assert not missing_end(tmp_path / "none.mcap")
