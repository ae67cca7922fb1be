"""GIFs written frame by frame, captions, the legend and the overview's labels."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("matplotlib")
from PIL import Image

from laserpeople.errors import LaserPeopleError
from laserpeople.viz import Scene, render
from laserpeople.viz.figure import AXES_BOX, caption, counted
from laserpeople.viz.gif import GifWriter, image_block
from laserpeople.viz.raster import OverviewLabel, gif_palette, place_labels, write_gif
from test_viz_support import write_scene

PALETTE = np.array(gif_palette(), dtype=np.uint8).reshape(-1, 3)


def _frames(n: int, h: int = 40, w: int = 60) -> list[np.ndarray]:
    """Index images with a block that moves and changes colour, one still repeat at the end."""
    rng = np.random.default_rng(1)
    out = []
    for i in range(n):
        f = np.zeros((h, w), dtype=np.uint8)
        f[5 + i : 12 + i, 3 * i : 3 * i + 9] = rng.integers(1, 255, size=(7, 9))
        out.append(f)
    out.append(out[-1].copy())
    return out


def test_gif_writer_frames_decode_to_what_was_written(tmp_path: Path) -> None:
    frames = _frames(8)
    with GifWriter(tmp_path / "a.gif", (60, 40), gif_palette()) as w:
        for f in frames:
            w.add(f, 0.1)
    with Image.open(tmp_path / "a.gif") as im:
        assert im.n_frames == len(frames) and im.size == (60, 40)
        assert im.info["loop"] == 0
        for k, f in enumerate(frames):
            im.seek(k)
            assert im.info["duration"] == 100
            np.testing.assert_array_equal(np.asarray(im.convert("RGB")), PALETTE[f])


def test_gif_writer_codes_only_the_changed_rectangle(tmp_path: Path) -> None:
    a = np.zeros((40, 60), dtype=np.uint8)
    b = a.copy()
    b[10:13, 20:25] = 7
    with GifWriter(tmp_path / "b.gif", (60, 40), gif_palette()) as w:
        w.add(a, 0.05)
        w.add(b, 0.05)
        w.add(b, 0.05)
    data = (tmp_path / "b.gif").read_bytes()
    # image descriptors: separator 0x2C after a graphic control block (…, 0x00 terminator)
    descriptors = [
        np.frombuffer(data[i + 1 : i + 9], dtype="<u2").tolist()
        for i in range(len(data) - 9)
        if data[i] == 0x2C and data[i - 8 : i - 5] == b"\x21\xf9\x04"
    ]
    assert descriptors == [[0, 0, 60, 40], [20, 10, 5, 3], [0, 0, 1, 1]]


def test_gif_is_written_while_the_frames_are_still_coming(tmp_path: Path) -> None:
    out = tmp_path / "s.gif"
    sizes: list[int] = []

    def images() -> Iterator[np.ndarray]:
        for k in range(6):
            if k >= 2:
                sizes.append(out.stat().st_size)
            img = np.full((30, 40, 3), 255, dtype=np.uint8)
            img[k : k + 5, 2 * k : 2 * k + 5] = (31, 119, 180)
            yield img

    assert write_gif(images(), out, 0.1) == 6
    assert sizes == sorted(sizes) and sizes[-1] > sizes[0]  # the file grew frame by frame


def test_empty_or_failed_animation_leaves_no_file(tmp_path: Path) -> None:
    out = tmp_path / "e.gif"
    with pytest.raises(LaserPeopleError, match="no frames"):
        write_gif(iter(()), out, 0.1)
    assert not out.exists()

    def broken() -> Iterator[np.ndarray]:
        yield np.full((30, 40, 3), 255, dtype=np.uint8)
        raise RuntimeError("drawing failed")

    with pytest.raises(RuntimeError):
        write_gif(broken(), out, 0.1)
    assert not out.exists()


def test_gif_writer_refuses_a_frame_of_another_size(tmp_path: Path) -> None:
    with GifWriter(tmp_path / "c.gif", (60, 40), gif_palette()) as w:
        w.add(np.zeros((40, 60), dtype=np.uint8), 0.1)
        with pytest.raises(LaserPeopleError, match="30x20"):
            w.add(np.zeros((20, 30), dtype=np.uint8), 0.1)


def test_image_block_rejects_what_is_not_a_gif() -> None:
    with pytest.raises(LaserPeopleError):
        image_block(b"\x89PNG....")


def test_captions_count_in_words_and_seconds_since_the_start() -> None:
    assert counted(1, "person", "people") == "1 person"
    assert counted(2, "person", "people") == "2 people"
    text = caption("demo", 12, 1.234, 1, 2, 0, 1)
    assert text == "demo\nscan 12  t = 1.23 s\n1 person, 2 legs, truth: 1 person"
    assert caption("", 0, 0.0, 0, 1, 1, None) == "scan 0  t = 0.00 s\n1 leg, 1 group"


def test_legend_lists_the_kinds_of_track_drawn(tmp_path: Path) -> None:
    from laserpeople.viz.figure import FrameRenderer

    def entries(kinds: frozenset[str] | None, truth: bool = False) -> list[str]:
        r = FrameRenderer((0.0, 10.0, 0.0, 8.0), size=(800, 600), truth=truth, kinds=kinds)
        try:
            return [] if r._legend is None else [t.get_text() for t in r._legend.get_texts()]
        finally:
            r.close()

    groups = entries(frozenset({"group"}))
    assert len(groups) == 1 and groups[0].startswith("group track")
    both = entries(None)  # legs and people
    assert [e.split()[0] for e in both] == ["person", "leg"]
    assert entries(frozenset()) == []  # no tracks, no truth: no legend
    assert [e.split()[0] for e in entries(frozenset(), truth=True)] == ["true", "true"]
    rec, csv = write_scene(tmp_path, n=3)
    assert Scene(rec, csv, None).track_kinds() == {"group", "person"}  # what write_scene writes
    assert Scene(rec, None, None).track_kinds() == frozenset()


def test_animation_captions_start_at_zero_seconds(tmp_path: Path) -> None:
    from laserpeople.io import open_recording
    from laserpeople.viz.raster import iter_images

    rec, csv = write_scene(tmp_path, n=4)
    source = open_recording(rec)
    first = next(iter(source.scans())).stamp
    source.close()
    scene = Scene(rec, csv, "auto", start=2)
    assert scene.first_stamp() == first  # the recording's first scan, not the window's
    assert scene.draws_truth()
    assert not Scene(rec, csv, None).draws_truth()
    assert len(list(iter_images(scene, size=(480, 360)))) == 2


def test_overview_labels_longest_first_and_never_overlapping() -> None:
    extent, size = (0.0, 10.0, 0.0, 10.0), (800, 600)
    px_per_m = AXES_BOX[2] * size[0] / 10.0  # 70.4 px per metre along x
    assert px_per_m == pytest.approx(70.4)
    a = OverviewLabel(50, 1.0, 1.0, "P1", (0.0, 0.0, 0.0))
    b = OverviewLabel(10, 1.05, 1.0, "P2", (0.0, 0.0, 0.0))  # 3.5 px right of P1: overlaps
    c = OverviewLabel(12, 5.0, 5.0, "P3", (0.0, 0.0, 0.0))
    assert place_labels([b, a, c], extent, size) == [a, c]
    # with many tracks, those seen in fewer than 5 scans get no label
    many = [OverviewLabel(3 if i == 0 else 9, i * 0.45, 9.0, f"P{i}", (0, 0, 0)) for i in range(21)]
    placed = place_labels(many, extent, size)
    assert many[0] not in placed and len(placed) == 20


def test_overview_of_many_short_tracks_stays_readable(tmp_path: Path) -> None:
    rec, csv = write_scene(tmp_path, n=12)
    result = render(Scene(rec, csv), tmp_path / "o.png")
    assert result.frames == 1 and (tmp_path / "o.png").stat().st_size > 0
