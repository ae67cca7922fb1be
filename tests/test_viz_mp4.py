"""MP4 animations: encoded for real with ffmpeg (the one on the PATH, else the binary that
imageio-ffmpeg bundles), then decoded and compared with what was drawn."""

from __future__ import annotations

import os
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import LaserPeopleError
from laserpeople.viz import Scene, render, track_color
from laserpeople.viz.raster import VideoEncoderMissingError, find_ffmpeg, iter_images
from test_viz_support import near_colour, people_at, pixel_of, write_scene

pytest.importorskip("matplotlib")
imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")

runner = CliRunner()
EXTENT = (-4.0, 6.0, -3.0, 5.0)  # the test room [m]
SIZE = (321, 241)  # odd on purpose: yuv420p needs even sides, so ffmpeg pads to 322x242


def decode(path: Path) -> tuple[dict[str, object], list[np.ndarray]]:
    """The stream metadata and every frame (H, W, 3) of a video."""
    gen = imageio_ffmpeg.read_frames(str(path))
    meta = next(gen)
    w, h = meta["size"]
    return meta, [np.frombuffer(f, np.uint8).reshape(h, w, 3) for f in gen]


def test_view_writes_an_mp4_that_decodes_to_the_drawn_frames(tmp_path: Path) -> None:
    n = 10
    rec, csv = write_scene(tmp_path, n=n)
    out = tmp_path / "view.mp4"
    res = runner.invoke(
        app,
        [
            *["view", str(rec), "--tracks", str(csv), "-o", str(out), "--size", "321x241"],
            *["--extent", ",".join(str(v) for v in EXTENT)],
        ],
    )
    assert res.exit_code == 0, res.output
    assert f"({n} frames" in " ".join(res.output.split())  # rich wraps long paths
    assert imageio_ffmpeg.count_frames_and_secs(str(out)) == (n, pytest.approx(n * 0.1))
    meta, frames = decode(out)
    assert meta["codec"] == "h264"
    assert str(meta["pix_fmt"]).startswith("yuv420p")
    assert meta["size"] == (322, 242)
    assert meta["fps"] == pytest.approx(10.0)  # real time: scans are 0.1 s apart
    assert len(frames) == n
    # the padding column and row are background white
    assert np.all(frames[4][:, -1] >= 250) and np.all(frames[4][-1, :] >= 250)

    pink = track_color(8, "person")  # track 3's colour is a grey, like the scan points
    assert max(abs(a - b) for a, b in zip(pink, (127, 127, 127), strict=True)) > 50
    first, last = pixel_of(people_at(0)[1], EXTENT, SIZE), pixel_of(people_at(9)[1], EXTENT, SIZE)
    assert near_colour(frames[0], *first, pink, r=2, tol=12)
    assert near_colour(frames[9], *last, pink, r=2, tol=12)
    assert not near_colour(frames[9], *first, pink, r=1, tol=12)  # it has walked on
    far = pixel_of(np.array([5.5, 4.5]), EXTENT, SIZE)
    assert not near_colour(frames[9], *far, pink, r=4, tol=30)

    # every decoded frame is, within H.264 loss, the image drawn for its own scan
    drawn = list(iter_images(Scene(rec, csv), size=SIZE, extent=EXTENT))
    for k, frame in enumerate(frames):
        errors = [np.abs(frame[: SIZE[1], : SIZE[0]].astype(int) - d).mean() for d in drawn]
        assert errors[k] < 3.0, (k, errors[k])
        assert int(np.argmin(errors)) == k


def test_track_animate_writes_a_playable_mp4(tmp_path: Path) -> None:
    n = 8
    rec, _csv = write_scene(tmp_path, n=n)
    out = tmp_path / "track.mp4"
    res = runner.invoke(
        app, ["track", str(rec), "-o", str(tmp_path / "t.csv"), "--animate", str(out)]
    )
    assert res.exit_code == 0, res.output
    assert imageio_ffmpeg.count_frames_and_secs(str(out)) == (n, pytest.approx(n * 0.1))
    meta, frames = decode(out)
    assert meta["size"] == (640, 480)  # the default size, already even
    assert len(frames) == n and frames[0].std() > 5  # not a blank picture


def test_bundled_ffmpeg_is_used_when_none_is_on_the_path(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr("shutil.which", lambda name, *a, **k: None)
    bundled = imageio_ffmpeg.get_ffmpeg_exe()
    assert find_ffmpeg() == bundled
    rec, csv = write_scene(tmp_path, n=3)
    out = tmp_path / "bundled.mp4"
    assert render(Scene(rec, csv), out, size=(160, 120), fps=4).frames == 3
    assert imageio_ffmpeg.count_frames_and_secs(str(out)) == (3, pytest.approx(0.75))


def _raise_runtime_error() -> str:
    raise RuntimeError("no ffmpeg binary for this platform")


@pytest.mark.parametrize(
    "bundle",
    [None, SimpleNamespace(get_ffmpeg_exe=_raise_runtime_error)],
    ids=["imageio-ffmpeg-not-installed", "imageio-ffmpeg-without-binary"],
)
def test_mp4_without_any_ffmpeg_is_a_clear_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, bundle: object
) -> None:
    monkeypatch.setattr("shutil.which", lambda name, *a, **k: None)
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", bundle)  # None: import fails
    assert find_ffmpeg() is None
    rec, csv = write_scene(tmp_path, n=4)
    out = tmp_path / "a.mp4"
    with pytest.raises(VideoEncoderMissingError) as info:
        render(Scene(rec, csv), out)
    text = str(info.value)
    assert "ffmpeg" in text and "laserpeople[all]" in text and "apt install ffmpeg" in text
    assert str(out) in text
    assert not out.exists()
    res = runner.invoke(app, ["view", str(rec), "--tracks", str(csv), "-o", str(out)])
    assert isinstance(res.exception, VideoEncoderMissingError)  # printed as one line by main()


def _stand_in(tmp_path: Path, body: str) -> Path:
    """A fake ``ffmpeg`` program first on the PATH, running the Python ``body``."""
    fake = tmp_path / "bin" / "ffmpeg"
    fake.parent.mkdir()
    fake.write_text(f"#!{sys.executable}\nimport sys\n{body}")
    fake.chmod(0o755)
    return fake


def test_ffmpeg_on_the_path_comes_first_and_gets_every_frame_whole(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    fake = _stand_in(
        tmp_path,
        "args = sys.argv[1:]\n"
        "w, h = map(int, args[args.index('-s') + 1].split('x'))\n"
        "data = sys.stdin.buffer.read()\n"
        "assert len(data) % (w * h * 3) == 0\n"
        "rate = args[args.index('-r') + 1]\n"
        "codec = args[args.index('-c:v') + 1] + ' ' + args[args.index('-pix_fmt', 8) + 1]\n"
        "open(args[-1], 'w').write(f'{len(data) // (w * h * 3)} {w} {h} {rate} {codec}')\n",
    )
    monkeypatch.setenv("PATH", f"{fake.parent}{os.pathsep}{os.environ.get('PATH', '')}")
    assert find_ffmpeg() == str(fake)
    rec, csv = write_scene(tmp_path, n=7)
    out = tmp_path / "a.mp4"
    result = render(Scene(rec, csv, every=2), out, size=(320, 240))
    assert result.frames == 4
    # scans 0, 2, 4, 6 at 0.2 s each: 5 frames/s
    assert out.read_text() == "4 320 240 5 libx264 yuv420p"


def test_ffmpeg_failure_is_reported_and_leaves_no_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    fake = _stand_in(
        tmp_path,
        "sys.stdin.buffer.read()\n"
        "open(sys.argv[-1], 'w').write('half')\n"
        "sys.stderr.write('Unknown encoder libx264\\n')\n"
        "sys.exit(1)\n",
    )
    monkeypatch.setenv("PATH", f"{fake.parent}{os.pathsep}{os.environ.get('PATH', '')}")
    rec, csv = write_scene(tmp_path, n=3)
    out = tmp_path / "a.mp4"
    with pytest.raises(LaserPeopleError, match="Unknown encoder libx264") as info:
        render(Scene(rec, csv), out, size=(160, 120))
    assert "laserpeople[all]" in str(info.value)
    assert not out.exists()
