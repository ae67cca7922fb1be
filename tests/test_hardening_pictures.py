"""Pictures, animations and bags on a full disk or interrupted: an older file stays as it
was, no torn file is left, and the error names the output with what to do."""

from __future__ import annotations

import errno
import os
import sys
from pathlib import Path
from typing import Any

import pytest

from laserpeople.errors import LaserPeopleError
from laserpeople.viz import Scene, render
from test_viz_support import write_scene

pytest.importorskip("matplotlib")

FULL = OSError(errno.ENOSPC, "No space left on device")


def _fail_gif_after(monkeypatch: pytest.MonkeyPatch, frames: int, error: BaseException) -> None:
    """GifWriter.add raises ``error`` once ``frames`` frames are written."""
    from laserpeople.viz import gif

    add = gif.GifWriter.add

    def failing(self: gif.GifWriter, indices: Any, seconds: float) -> None:
        if self.frames >= frames:
            raise error
        add(self, indices, seconds)

    monkeypatch.setattr(gif.GifWriter, "add", failing)


@pytest.mark.parametrize("error", [FULL, KeyboardInterrupt()])
def test_a_gif_stopped_half_way_leaves_the_older_file_and_nothing_else(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, error: BaseException
) -> None:
    rec, csv = write_scene(tmp_path, n=6)
    out = tmp_path / "out" / "walk.gif"
    out.parent.mkdir()
    out.write_bytes(b"the older animation")
    _fail_gif_after(monkeypatch, 2, error)
    with pytest.raises(
        type(error) if isinstance(error, KeyboardInterrupt) else LaserPeopleError
    ) as info:
        render(Scene(rec, csv), out, size=(160, 120))
    if not isinstance(error, KeyboardInterrupt):
        assert str(info.value).startswith(f"{out}: cannot write the output: No space left")
    assert out.read_bytes() == b"the older animation"
    assert sorted(p.name for p in out.parent.iterdir()) == ["walk.gif"]


def test_a_complete_gif_replaces_the_older_file(tmp_path: Path) -> None:
    rec, csv = write_scene(tmp_path, n=4)
    out = tmp_path / "walk.gif"
    out.write_bytes(b"the older animation")
    result = render(Scene(rec, csv), out, size=(160, 120))
    assert result.path == out and result.frames == 4
    data = out.read_bytes()
    assert data[:6] == b"GIF89a" and data[-1:] == b"\x3b"
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


@pytest.mark.parametrize("of_output", [True, False])
def test_an_error_raised_for_the_staging_file_names_the_output(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, of_output: bool
) -> None:
    """An error naming the staging file names the output instead; one naming another file
    (the recording being read) keeps that name."""
    from laserpeople.viz import gif

    rec, csv = write_scene(tmp_path, n=3)

    def refuse(self: gif.GifWriter, indices: Any, seconds: float) -> None:
        raise LaserPeopleError("frame 0 is 1x1 px", path=self.path if of_output else rec)

    monkeypatch.setattr(gif.GifWriter, "add", refuse)
    out = tmp_path / "walk.gif"
    with pytest.raises(LaserPeopleError) as info:
        render(Scene(rec, csv), out, size=(160, 120))
    named = out if of_output else rec
    assert info.value.path == str(named)
    assert str(info.value) == f"{named}: frame 0 is 1x1 px"


def _fake_ffmpeg(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, stderr: str) -> None:
    fake = tmp_path / "bin" / "ffmpeg"
    fake.parent.mkdir()
    fake.write_text(
        f"#!{sys.executable}\nimport sys\nsys.stdin.buffer.read()\n"
        f"open(sys.argv[-1], 'w').write('half')\nsys.stderr.write({stderr!r})\nsys.exit(1)\n"
    )
    fake.chmod(0o755)
    monkeypatch.setenv("PATH", f"{fake.parent}{os.pathsep}{os.environ.get('PATH', '')}")


@pytest.mark.parametrize(
    ("stderr", "hint", "not_hint"),
    [
        (
            "Error closing file: No space left on device\n",
            "free disk space, or give -o a path in a writable directory",
            "libx264",
        ),
        ("Error opening output: Read-only file system\n", "free disk space", "libx264"),
        ("Unknown encoder 'libx264'\n", "laserpeople[all]", "free disk space"),
    ],
)
def test_an_mp4_that_ffmpeg_cannot_write_says_why(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, stderr: str, hint: str, not_hint: str
) -> None:
    _fake_ffmpeg(tmp_path, monkeypatch, stderr)
    rec, csv = write_scene(tmp_path, n=3)
    out = tmp_path / "walk.mp4"
    with pytest.raises(LaserPeopleError) as info:
        render(Scene(rec, csv), out, size=(160, 120))
    text = str(info.value)
    assert (
        text.startswith(f"{out}: ffmpeg") and hint in text and not_hint not in text.split("(")[-1]
    )
    assert sorted(p.name for p in tmp_path.iterdir() if p.suffix == ".mp4") == []


def test_a_rerun_writer_that_stops_is_an_error_naming_the_output(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pytest.importorskip("rerun")
    from laserpeople.viz import rerun_export

    closed: list[bool] = []

    class Stopped:
        def flush(self) -> None:
            raise RuntimeError("File-writer thread shut down prematurely")

        def disconnect(self) -> None:
            closed.append(True)

    with pytest.raises(LaserPeopleError) as info:
        rerun_export._close(Stopped(), tmp_path / "x.rrd")
    assert str(info.value).startswith(f"{tmp_path / 'x.rrd'}: cannot write the output")
    assert "free disk space" in str(info.value) and closed == [True]


def test_a_bag_that_cannot_be_moved_into_place_names_it_and_the_reason(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from laserpeople.errors import RecordingError
    from laserpeople.io import rosbag_writer

    def full(*_args: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device", str(tmp_path / ".x.mcap.tmp"))

    monkeypatch.setattr(rosbag_writer.os, "replace", full)
    out = tmp_path / "x.mcap"
    with pytest.raises(RecordingError) as info, rosbag_writer.open_bag(out):
        pass
    assert str(info.value) == (
        f"{out}: cannot write the bag: No space left on device "
        "(free disk space, or give a path in a writable directory)"
    )
    assert list(tmp_path.iterdir()) == []
